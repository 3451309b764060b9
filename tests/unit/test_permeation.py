"""Gas permeation through a squeezed O-ring's rubber (docs/theory.md §11.11)."""

import math

import numpy as np
import pytest

from sealeak.errors import InputError
from sealeak.physics.permeation import oring_permeation, permeation_path, time_lag

P = 3e-12  # m²/s, a pV permeability
D = 2e-10  # m²/s
LY = math.pi * 22.62e-3  # m, the seal line of a 20 x 2.62 mm O-ring


@pytest.mark.parametrize("eps", [0.05, 0.15, 0.3])
def test_closed_form(eps):
    d, dp = 2.62e-3, 1e5
    res = oring_permeation(P, D, d, eps, LY, dp)
    # the cord rectangularised at constant area π d²/4: height (1 - ε) d, width π d / (4 (1 - ε))
    h, t = (1 - eps) * d, math.pi * d / (4 * (1 - eps))
    path, height = permeation_path(d, eps)  # the code's slab keeps the cord's area
    assert float(path[0] * height[0]) == pytest.approx(math.pi * d**2 / 4, rel=1e-14, abs=0)
    assert (float(path[0]), float(height[0])) == pytest.approx((t, h), rel=1e-14, abs=0)
    assert float(res.throughput[0]) == pytest.approx(P * dp * LY * h / t, rel=1e-13, abs=0)
    assert float(res.throughput[0]) == pytest.approx(P * dp * LY * 4 / math.pi * (1 - eps) ** 2, rel=1e-13, abs=0)
    assert float(res.breakthrough_time[0]) == pytest.approx(t**2 / (6 * D), rel=1e-13)


def test_linear_in_pressure_difference_and_permeability():
    base = oring_permeation(P, D, 2.62e-3, [0.1, 0.2], LY, 1e5).throughput
    np.testing.assert_allclose(oring_permeation(P, D, 2.62e-3, [0.1, 0.2], LY, 3e5).throughput, 3 * base, rtol=1e-14)
    np.testing.assert_allclose(oring_permeation(2 * P, D, 2.62e-3, [0.1, 0.2], LY, 1e5).throughput, 2 * base, rtol=1e-14)


def test_flux_goes_as_height_over_path():
    """Fick's law through a slab: Q ∝ area/thickness. A thicker cord at the same squeeze has a longer path and a
    taller face in proportion, so Q stays; the same face over a longer path (more squeeze relief) passes less."""
    eps = np.array([0.1, 0.2, 0.3])
    thin, thick = (oring_permeation(P, D, d, eps, LY, 1e5) for d in (1.78e-3, 5.33e-3))
    np.testing.assert_allclose(thin.throughput, thick.throughput, rtol=1e-13)
    np.testing.assert_allclose(thick.path / thin.path, 5.33 / 1.78, rtol=1e-13)
    q_per_area = thin.throughput / (LY * thin.height)
    np.testing.assert_allclose(q_per_area * thin.path, P * 1e5, rtol=1e-13)  # ∝ 1/thickness at a given face
    # the breakthrough time goes as the path squared
    np.testing.assert_allclose(thick.breakthrough_time / thin.breakthrough_time, (5.33 / 1.78) ** 2, rtol=1e-13)


def test_time_lag_is_the_intercept_of_the_transient_outflow():
    """Diffusion into an empty layer of thickness l (c = 1 upstream, 0 downstream): solved by finite differences, the
    cumulative outflow becomes a straight line in t whose intercept with the time axis is l²/(6D) (Daynes-Barrer)."""
    l, diff, n = 1e-3, 1e-10, 60
    dx = l / n
    dt = 0.4 * dx**2 / diff
    c = np.zeros(n + 1)
    c[0] = 1.0
    out, times, flux_sum = [], [], 0.0
    t_end = 3 * l**2 / diff
    steps = int(t_end / dt)
    for k in range(steps):
        c[1:-1] += diff * dt / dx**2 * (c[2:] - 2 * c[1:-1] + c[:-2])
        flux_sum += diff * (c[-2] - c[-1]) / dx * dt
        if k % 50 == 0:
            out.append(flux_sum)
            times.append((k + 1) * dt)
    times_a, out_a = np.array(times), np.array(out)
    late = times_a > 1.5 * l**2 / diff
    slope, intercept = np.polyfit(times_a[late], out_a[late], 1)
    assert slope == pytest.approx(diff / l, rel=0.02)  # the steady flux D c/l
    assert -intercept / slope == pytest.approx(float(time_lag(l, diff)), rel=0.03)
    assert float(time_lag(l, diff)) == pytest.approx(l**2 / (6 * diff), rel=1e-14)


def test_without_diffusivity_no_breakthrough_time():
    res = oring_permeation(P, None, 2.62e-3, [0.1, 0.2], LY, 1e5)
    assert np.all(np.isnan(res.breakthrough_time)) and np.all(res.throughput > 0)


def test_path_and_height():
    t, h = permeation_path(2e-3, [0.0, 0.5])
    np.testing.assert_allclose(t, [math.pi * 2e-3 / 4, math.pi * 2e-3 / 2], rtol=1e-14)
    np.testing.assert_allclose(h, [2e-3, 1e-3], rtol=1e-14)


@pytest.mark.parametrize("perm, diff, field", [(0.0, D, "permeability"), (-1.0, D, "permeability"),
                                                (float("nan"), D, "permeability"), (P, 0.0, "diffusivity")])
def test_bad_values_are_refused_naming_them(perm, diff, field):
    with pytest.raises(InputError, match=field):
        oring_permeation(perm, diff, 2.62e-3, 0.1, LY, 1e5)
