"""The FFT solvers' one code path on a strict array-API namespace (array_api_strict), as CuPy would run it.

CI has no GPU: these tests run synthesis, the periodic and the band contact solver on array_api_strict
arrays, which allow only what the array API standard allows (no scipy.fft, no ``out=``, no mixing of
bool and float), and check them against closed forms and against the NumPy path within a stated
relative tolerance (the FFTs of the two paths are different calls, so round-off may differ).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from array_api_compat import array_namespace

from sealeak.numerics import solve_band_contact, solve_contact, synthesize
from sealeak.numerics._xp import to_numpy
from sealeak.physics.spectrum import PowerSpectrum

xs = pytest.importorskip("array_api_strict")

#: Relative tolerance between the NumPy and the array-API path (FFT round-off, ~1e-15 per transform, over tens of
#: conjugate-gradient iterations).
REL = 1e-12
MODEL = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e5, q_cutoff=1e7, q_lowest=1e4, h_rms=1e-6)
L = 2 * np.pi / 1e4


def _strict(a):
    return array_namespace(a) is xs


def _close(a, b, rel=REL):
    a, b = to_numpy(a), np.asarray(b)
    return np.abs(a - b).max() <= rel * np.abs(b).max()


@pytest.mark.parametrize("amplitudes", ["gaussian", "phases"])
def test_synthesis_gives_the_numpy_surface_in_another_namespace(amplitudes):
    ref = synthesize(MODEL, 64, L, seed=5, amplitudes=amplitudes)
    h = synthesize(MODEL, 64, L, seed=5, amplitudes=amplitudes, xp=xs)
    assert _strict(h) and h.dtype == xs.float64 and h.shape == (64, 64)
    assert _close(h, ref)
    assert float(xs.mean(h)) == pytest.approx(0.0, abs=1e-12 * ref.std())


def test_full_contact_of_a_sinusoid_is_westergaard_in_another_namespace():
    """h = h0 cos(2πx/λ) above p* = π E* h0/λ: full contact, p = p̄ + p* cos(2πx/λ) (Johnson 1985 §13.2)."""
    n, e_star, h0 = 32, 1.0, 1e-3
    x = np.arange(n) * (L / n)
    h = np.repeat((h0 * np.cos(2 * np.pi * x / L))[:, None], n, axis=1)
    p_star = math.pi * e_star * h0 / L
    res = solve_contact(xs.asarray(h), L, e_star, 1.5 * p_star)
    assert _strict(res.pressure)
    assert res.contact_area == 1.0
    exact = 1.5 * p_star + p_star * np.cos(2 * np.pi * x / L)
    assert np.allclose(to_numpy(res.pressure), exact[:, None], rtol=0, atol=1e-6 * p_star)


@pytest.mark.parametrize("fraction", [0.02, 0.1])
def test_rough_contact_is_the_numpy_solution_in_another_namespace(fraction):
    h = synthesize(MODEL, 64, L, seed=2)
    e_star = 1e7
    p0 = fraction * e_star * MODEL.slope_rms / 2.0  # about 10 % and 40 % contact: the map holds only part of the slope
    ref = solve_contact(h, L, e_star, p0)
    res = solve_contact(xs.asarray(h), L, e_star, p0)
    assert 0.0 < ref.contact_area < 1.0
    assert res.contact_area == ref.contact_area
    assert _close(res.pressure, ref.pressure) and _close(res.gap, ref.gap)
    assert res.mean_gap == pytest.approx(ref.mean_gap, rel=REL, abs=0) and res.residual <= res.tol
    warm = solve_contact(xs.asarray(h), L, e_star, 1.2 * p0, initial=res)  # a warm start stays in the namespace
    assert _strict(warm.pressure) and warm.contact_area >= res.contact_area


def test_band_contact_is_the_numpy_solution_in_another_namespace():
    h = 50.0 * synthesize(MODEL, 64, L, seed=4)[:, :32]
    args = (L, L / 2, 3e6, 1.31e-3, 50.0)
    ref = solve_band_contact(h, *args)
    res = solve_band_contact(xs.asarray(h), *args)
    assert _strict(res.pressure)
    assert 0.0 < ref.contact_area < 1.0 and res.contact_area == ref.contact_area
    assert _close(res.pressure, ref.pressure)
    # the load balances in either namespace: Σ p dx dy / Ly = f
    assert float(xs.sum(res.pressure)) * (L / 64) * (L / 2 / 32) / (L / 2) == pytest.approx(50.0, rel=1e-12)
