"""Checks of the FFT boundary-element contact solver against answers derived independently."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize

from sealeak.errors import ConvergenceError, InputError, ResourceError
from sealeak.numerics import check_memory, contact_memory_bytes, solve_contact, solve_contact_sweep
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.spectrum import PowerSpectrum


def test_hertz_sphere_on_flat() -> None:
    """Paraboloid h = -r²/(2R): a = (3FR/4E*)^(1/3), p_max = 3F/(2πa²) (Johnson 1985, §4.2)."""
    n, L, R, e_star = 512, 1.0, 1.0, 1.0
    a_target = 0.08 * L  # small against the cell: periodic images shift a by << 1 %
    F = 4.0 * e_star * a_target**3 / (3.0 * R)
    x = (np.arange(n) - n / 2) * (L / n)
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    h = -r2 / (2.0 * R)
    res = solve_contact(h, L, e_star, F / L**2)
    a_hertz = (3.0 * F * R / (4.0 * e_star)) ** (1.0 / 3.0)
    a_num = math.sqrt(res.contact_area * L**2 / math.pi)
    assert a_num == pytest.approx(a_hertz, rel=0.02)
    p_max = 3.0 * F / (2.0 * math.pi * a_hertz**2)
    assert res.pressure.max() == pytest.approx(p_max, rel=0.02)
    assert res.residual <= res.tol


def test_westergaard_sinusoid_sweep() -> None:
    """h = h0 cos(2πx/λ): p̄/p* = sin²(πa/λ), p* = π E* h0/λ (Westergaard 1939; Johnson 1985 §13.2)."""
    n, L, e_star, h0 = 512, 1.0, 1.0, 1e-3
    lam = L
    x = np.arange(n) * (L / n)
    h = np.repeat((h0 * np.cos(2 * np.pi * x / lam))[:, None], n, axis=1)
    p_star = math.pi * e_star * h0 / lam
    ratios = [0.2, 0.5, 0.8]
    results = solve_contact_sweep(h, L, e_star, [r * p_star for r in ratios])
    for ratio, res in zip(ratios, results):
        a_exact = lam / math.pi * math.asin(math.sqrt(ratio))
        in_contact = res.contact[:, 0]
        assert (res.contact == in_contact[:, None]).all()  # constant along y
        a_num = 0.5 * np.count_nonzero(in_contact) * (L / n)
        assert a_num == pytest.approx(a_exact, rel=0.01), ratio
    full = solve_contact(h, L, e_star, 1.1 * p_star)
    assert full.contact_area == 1.0
    # full contact: p = p̄ + p* cos(2πx/λ) exactly (u = h up to a constant)
    assert np.allclose(full.pressure[:, 0], 1.1 * p_star + p_star * np.cos(2 * np.pi * x / lam),
                       rtol=0, atol=1e-6 * p_star)


def _dense_reference(h: np.ndarray, L: float, e_star: float, p0: float) -> np.ndarray:
    """Independent solve: explicit influence matrix + NNLS for each rigid-body offset c, root on c.

    Influence matrix: column k is the displacement caused by a unit pressure in cell k, built by
    evaluating the periodic Green's function 2/(E*|q|) (q ≠ 0) as an explicit sum of cosines over
    the wavevector grid (no FFT). Adding the rank-one term J = 11ᵀ makes it
    positive definite; since mean(p) is fixed this only shifts the offset c. For fixed c,
    min ½pᵀKp - (h - c)ᵀp, p >= 0 is an NNLS problem with K = RᵀR.
    """
    n = h.shape[0]
    k1 = 2 * np.pi * np.fft.fftfreq(n, d=L / n)
    qx, qy = np.meshgrid(k1, k1, indexing="ij")
    q = np.hypot(qx, qy).ravel()
    green_q = np.where(q > 0, 2.0 / (e_star * np.where(q > 0, q, 1.0)), 0.0)
    # displacement at lattice offset (i, j) of a unit pressure cell: G(d) = (1/N²) Σ_q G(q) cos(q·d)
    d = np.arange(n) * (L / n)
    phase = qx.ravel()[:, None, None] * d[None, :, None] + qy.ravel()[:, None, None] * d[None, None, :]
    G = np.tensordot(green_q, np.cos(phase), axes=1) / (n * n)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    I, J = i.ravel(), j.ravel()
    K = G[(I[:, None] - I[None, :]) % n, (J[:, None] - J[None, :]) % n]
    s = float(np.abs(K).max())
    Kt = K + s * np.ones_like(K)
    R = np.linalg.cholesky(Kt).T
    hv = h.ravel()

    def p_of(c: float) -> np.ndarray:
        rhs = np.linalg.solve(R.T, hv - c)
        p, _ = optimize.nnls(R, rhs, maxiter=50 * n * n)
        return p

    hi = hv.max()
    lo = hi - 10 * (hv.max() - hv.min()) - 10 * p0 * n * n * s
    c = optimize.brentq(lambda c: p_of(c).mean() - p0, lo, hi, xtol=1e-15 * abs(hi - lo), rtol=1e-14)
    return p_of(c).reshape(n, n)


def test_random_surface_matches_dense_nnls() -> None:
    n, L, e_star = 32, 1e-3, 1e6
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=2 * 2 * np.pi / L, q_cutoff=8 * 2 * np.pi / L,
                                   q_lowest=2 * np.pi / L, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=7)
    p0 = 0.05 * e_star * sp.slope_rms
    res = solve_contact(h, L, e_star, p0, tol=1e-12)
    ref = _dense_reference(h, L, e_star, p0)
    assert 0.05 < res.contact_area < 0.9
    assert np.abs(res.pressure - ref).max() <= 1e-6 * p0
    assert ((res.pressure > 0) == (ref > 1e-9 * p0)).all()


def test_warm_start_gives_same_answer_in_fewer_iterations() -> None:
    n, L, e_star = 128, 1e-3, 1e6
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * 2 * np.pi / L, q_cutoff=16 * 2 * np.pi / L,
                                   q_lowest=2 * np.pi / L, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=3)
    p1, p2 = 0.05 * e_star * sp.slope_rms, 0.055 * e_star * sp.slope_rms
    first = solve_contact(h, L, e_star, p1)
    cold = solve_contact(h, L, e_star, p2)
    warm = solve_contact(h, L, e_star, p2, initial=first)
    assert warm.iterations < cold.iterations
    assert np.abs(warm.pressure - cold.pressure).max() <= 1e-5 * p2
    assert warm.mean_pressure == p2 and np.mean(warm.pressure) == pytest.approx(p2, rel=1e-12)
    assert warm.mean_gap == pytest.approx(float(warm.gap.mean()), rel=1e-6, abs=0)


def test_warm_start_from_a_one_cell_contact_reaches_the_cold_answer() -> None:
    """At a tiny pressure the contact is a single cell; warm-starting a much larger load from it must still work."""
    n, L, e_star = 32, 1e-3, 1e6
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * 2 * np.pi / L, q_cutoff=8 * 2 * np.pi / L,
                                   q_lowest=2 * np.pi / L, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=0)
    first = solve_contact(h, L, e_star, 1e-6 * e_star * sp.slope_rms)
    assert first.contact_area <= 2 / n**2
    p2 = 1e-2 * e_star * sp.slope_rms
    cold = solve_contact(h, L, e_star, p2)
    warm = solve_contact(h, L, e_star, p2, initial=first)
    assert np.abs(warm.pressure - cold.pressure).max() <= 1e-5 * p2


def test_not_converging_raises_with_residual_and_tolerance() -> None:
    n, L = 64, 1e-3
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * 2 * np.pi / L, q_cutoff=16 * 2 * np.pi / L, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=1)
    with pytest.raises(ConvergenceError, match=r"residual .* tolerance 1e-12"):
        solve_contact(h, L, 1e6, 0.05 * 1e6 * sp.slope_rms, tol=1e-12, max_iter=3)


def test_inputs_and_memory_are_checked() -> None:
    h = np.zeros((8, 8))
    with pytest.raises(InputError, match="mean_pressure"):
        solve_contact(h, 1.0, 1.0, -1.0)
    with pytest.raises(InputError, match="heights"):
        solve_contact(np.zeros((8, 4)), 1.0, 1.0, 1.0)
    with pytest.raises(ResourceError, match="GiB"):
        solve_contact(np.ones((64, 64)) + np.eye(64), 1.0, 1.0, 1.0, memory_limit=1e5)
    n_huge = 1 << 17  # 2^34 cells: ~2 TB for the contact arrays
    with pytest.raises(ResourceError, match=r"needs about \d"):
        check_memory(n_huge, "contact")
    assert contact_memory_bytes(1024) < contact_memory_bytes(2048)
