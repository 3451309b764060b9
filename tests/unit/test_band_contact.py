"""The band contact solver (a smooth cylinder on a rough surface, free across the band): checks against
answers derived independently of it (Hertz line contact, the plane-strain strip load, a periodic FFT
Green's function on a much wider cell)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import fft as sfft

from sealeak.errors import InputError, ResourceError
from sealeak.numerics import (
    band_displacement,
    contact_edges,
    hertz_line_contact,
    solve_band_contact,
    synthesize,
)
from sealeak.physics.spectrum import PowerSpectrum

# an O-ring-like cylinder: d = 2.62 mm, soft rubber
R = 1.31e-3
E_STAR = 3.0e6


def _force_for_half_width(b: float) -> float:
    """Hertz: b = √(4fR/(πE*)) solved for f, written out here (Johnson 1985 eq. 4.43)."""
    return math.pi * E_STAR * b * b / (4.0 * R)


# ---------------------------------------------------------------- smooth cylinder against Hertz
@pytest.mark.parametrize("n, ny, half_width, domain", [
    (256, 1, 0.25e-3, 2.5),   # 51 cells across the half-width
    (256, 8, 0.25e-3, 2.5),   # the same problem on a 2D grid: y-uniform, must not change
    (384, 1, 0.6e-3, 3.0),    # a wider band in a wider domain
    (200, 1, 0.1e-3, 2.0),    # narrow domain: contact still well inside
])
def test_smooth_cylinder_is_hertz(n, ny, half_width, domain):
    f = _force_for_half_width(half_width)
    W = domain * 2.0 * half_width
    res = solve_band_contact(np.zeros((n, ny)), W, W, E_STAR, R, f)
    # Hertz written out by hand: b, p_max = 2f/(πb) and p(x) = p_max √(1 - (x-xc)²/b²)
    p_max = 2.0 * f / (math.pi * half_width)
    lo, hi = contact_edges(res.x, res.line_pressure)
    assert hi - lo == pytest.approx(2.0 * half_width, rel=0.01)
    assert 0.5 * (lo + hi) == pytest.approx(W / 2.0, abs=0.5 * res.dx)
    assert res.contact_width == pytest.approx(2.0 * half_width, abs=2.0 * res.dx)  # whole cells
    assert res.max_pressure == pytest.approx(p_max, rel=0.01)
    exact = p_max * np.sqrt(np.clip(1.0 - ((res.x - W / 2.0) / half_width) ** 2, 0.0, None))
    assert np.abs(res.line_pressure - exact).max() < 0.02 * p_max  # the whole profile, edges included
    assert (res.pressure == res.pressure[:, :1]).all()  # nothing varies along the seal line
    assert not res.touches_edge
    assert res.residual <= res.tol
    # the library's Hertz helper agrees with the formulas above
    b, pm = hertz_line_contact(f, R, E_STAR)
    assert (b, pm) == pytest.approx((half_width, p_max), rel=1e-12, abs=0)


def test_off_centre_cylinder_moves_the_band():
    b = 0.2e-3
    f = _force_for_half_width(b)
    W = 2.0e-3
    res = solve_band_contact(np.zeros((256, 1)), W, W, E_STAR, R, f, center=0.7e-3)
    lo, hi = contact_edges(res.x, res.line_pressure)
    assert 0.5 * (lo + hi) == pytest.approx(0.7e-3, abs=0.5 * res.dx)
    assert hi - lo == pytest.approx(2 * b, rel=0.01)


def test_a_domain_too_narrow_for_the_band_is_flagged():
    b = 0.3e-3
    res = solve_band_contact(np.zeros((64, 1)), 0.9 * 2 * b, 1e-3, E_STAR, R, _force_for_half_width(b))
    assert res.touches_edge
    ok = solve_band_contact(np.zeros((64, 1)), 2.5 * 2 * b, 1e-3, E_STAR, R, _force_for_half_width(b))
    assert not ok.touches_edge


# ---------------------------------------------------------------- the Green's function: free across, periodic along
def test_y_uniform_strip_load_is_the_plane_strain_solution_without_wrap_around():
    """u(x) = -(2p/(πE*)) [(x-a) ln|x-a| - (x-b) ln|x-b|] + C for pressure p on a < x < b (plane strain, Johnson 1985 ch. 2).

    Evaluated over the whole domain, up to its edges: a periodic (wrapped) kernel would bend it there.
    """
    nx, W, E = 96, 3.0, 2.0
    dx = W / nx
    x = (np.arange(nx) + 0.5) * dx
    for i0, i1 in ((2, 9), (40, 41), (80, 96)):
        p = np.zeros((nx, 3))
        p[i0:i1] = 1.5
        u = band_displacement(p, W, 1.0, E)
        a, b = i0 * dx, i1 * dx

        # signed: ∫_a^b -ln|x-s| ds = -( F(x-a) - F(x-b) ) with F(t) = t ln|t| - t, odd
        def F(t):
            return np.where(t != 0, t * np.log(np.abs(np.where(t != 0, t, 1.0))) - t, 0.0)

        exact = -(2 * 1.5 / (math.pi * E)) * (F(x - a) - F(x - b))
        for j in range(3):
            diff = (u[:, j] - u[0, j]) - (exact - exact[0])
            assert np.abs(diff).max() < 1e-12 * np.abs(exact - exact[0]).max()


@pytest.mark.parametrize("modes", [(2,), (1, 5)])
def test_y_varying_load_matches_a_periodic_green_function_on_a_wide_cell(modes):
    """Modes k ≠ 0 decay like K0(|k||x|) across the band, so a periodic cell 8x wider sees no image.

    Reference: 2/(E*|q|) on the wider periodic grid (independent FFT Green's function). The two
    discretisations differ by O(dx²): the error falls about fourfold when the grid is refined.
    """
    W, Ly, E = 2.0, 1.0, 3.0
    errors = []
    for nx in (64, 128):
        ny = nx // 2
        dx = W / nx
        x = (np.arange(nx) + 0.5) * dx
        y = np.arange(ny) * (Ly / ny)
        wave = sum(np.cos(2 * np.pi * k * y / Ly + k) for k in modes)
        p = np.exp(-((x[:, None] - 0.8) ** 2) / (2 * 0.1**2)) * wave[None, :]
        u = band_displacement(p, W, Ly, E)
        wide = np.zeros((8 * nx, ny))
        wide[:nx] = p
        kx = 2 * np.pi * sfft.fftfreq(8 * nx, d=dx)
        ky = 2 * np.pi * sfft.fftfreq(ny, d=Ly / ny)
        q = np.hypot(kx[:, None], ky[None, :])
        green = np.where(q > 0, 2.0 / (E * np.where(q > 0, q, 1.0)), 0.0)
        ref = np.real(sfft.ifft2(sfft.fft2(wide) * green))[:nx]
        errors.append(np.abs(u - ref).max() / np.abs(ref).max())
    assert errors[1] < 3e-3
    assert errors[0] / errors[1] > 3.0


def test_padding_a_wider_domain_changes_nothing_but_a_constant():
    """The same load in a domain with extra empty columns: identical displacement where both are defined
    (y-varying part exactly; the y-uniform part up to the line load's constant)."""
    rng = np.random.default_rng(4)
    nx, ny, dx, Ly, E = 40, 16, 0.01, 0.2, 5.0
    p = np.zeros((nx, ny))
    p[10:25] = rng.random((15, ny))
    u = band_displacement(p, nx * dx, Ly, E)
    wide = np.zeros((3 * nx, ny))
    wide[nx:2 * nx] = p
    uw = band_displacement(wide, 3 * nx * dx, Ly, E)[nx:2 * nx]
    d = uw - u
    assert np.allclose(d, d.mean(), rtol=0, atol=1e-12 * np.abs(u).max())


def test_the_seal_line_is_periodic():
    rng = np.random.default_rng(7)
    p = rng.random((32, 24))
    u = band_displacement(p, 1.0, 0.5, 2.0)
    shifted = band_displacement(np.roll(p, 9, axis=1), 1.0, 0.5, 2.0)
    assert np.allclose(shifted, np.roll(u, 9, axis=1), rtol=0, atol=1e-13 * np.abs(u).max())


def test_contact_edges_of_a_sampled_ellipse():
    """Sub-cell edges from p² linear near the edge. For a semi-ellipse of half-width b, p² = k s (2b - s) at a
    distance s inside the edge, and the straight line through s1, s1 + dx misses the edge by
    s1 (s1 + dx)/(2b - 2 s1 - dx) <= ~dx²/b (algebra in the test's docstring), far below a cell."""
    dx = 0.1
    x = (np.arange(50) + 0.5) * dx
    for lo, hi in ((1.03, 3.97), (0.55, 4.41), (0.6, 4.0)):
        c, b = (lo + hi) / 2, (hi - lo) / 2
        p = 7.0 * np.sqrt(np.clip(1 - ((x - c) / b) ** 2, 0, None))
        e = contact_edges(x, p)
        assert e == pytest.approx((lo, hi), abs=1.05 * dx**2 / b)
        assert abs(e[0] - lo) < 0.1 * dx and abs(e[1] - hi) < 0.1 * dx
    assert np.isnan(contact_edges(x, np.where(np.arange(50) == 3, 1.0, 0.0))).all()


# ---------------------------------------------------------------- rough band
@pytest.fixture(scope="module")
def rough():
    b = 0.3e-3
    W = 2.5 * 2 * b
    n = 128
    q = np.geomspace(2 * np.pi / (2 * b), 2 * np.pi * n / (4 * W), 20)
    spectrum = PowerSpectrum(q, 1e-30 * (q / q[0]) ** -3.6)
    h = synthesize(spectrum, n, W, seed=3)
    h *= 5e-6 / h.std()  # 5 µm rms roughness
    return h, W, _force_for_half_width(b)


def test_rough_band_balances_the_load_and_is_complementary(rough):
    h, W, f = rough
    res = solve_band_contact(h, W, W, E_STAR, R, f)
    n = h.shape[0]
    dx = dy = W / n
    assert res.pressure.sum() * dx * dy / W == pytest.approx(f, rel=1e-12)
    assert (res.pressure >= 0).all() and (res.gap >= 0).all()
    assert res.residual <= res.tol
    # recompute the gap from the pressure with the displacement operator: zero in contact, positive outside
    x = (np.arange(n) + 0.5) * dx
    H = h - ((x - W / 2) ** 2 / (2 * R))[:, None]
    g = band_displacement(res.pressure, W, W, E_STAR) - H
    c = -g[res.contact].mean()
    g += c
    h_rms = h.std()
    assert np.abs(g[res.contact]).max() < 1e-5 * h_rms
    assert g[~res.contact].min() > -1e-5 * h_rms
    assert np.allclose(res.gap[~res.contact], g[~res.contact], rtol=0, atol=1e-5 * h_rms)
    # roughness: partial contact inside the band, none far outside it
    band = np.abs(x - W / 2) < 0.3e-3
    assert 0.05 < res.contact[band].mean() < 0.95
    assert not res.contact[np.abs(x - W / 2) > 0.6e-3].any()
    assert not res.touches_edge


def test_warm_start_converges_to_the_same_contact(rough):
    h, W, f = rough
    cold = solve_band_contact(h, W, W, E_STAR, R, f)
    warm = solve_band_contact(h, W, W, E_STAR, R, f, initial=solve_band_contact(h, W, W, E_STAR, R, 0.8 * f))
    assert np.abs(warm.pressure - cold.pressure).max() < 1e-4 * cold.max_pressure
    plain = solve_band_contact(h, W, W, E_STAR, R, f, precondition=False)
    assert np.abs(plain.pressure - cold.pressure).max() < 1e-4 * cold.max_pressure


@pytest.mark.parametrize("kwargs, field", [
    ({"radius": 0.0}, "radius"),
    ({"radius": float("nan")}, "radius"),
    ({"force_per_length": -1.0}, "force_per_length"),
    ({"width": 0.0}, "width"),
    ({"e_star": float("inf")}, "e_star"),
    ({"heights": np.zeros(16)}, "heights"),
    ({"heights": np.full((16, 4), np.nan)}, "heights"),
    ({"center": 5.0}, "center"),
])
def test_bad_inputs_name_the_field(kwargs, field):
    args = {"heights": np.zeros((16, 4)), "width": 1e-3, "period": 1e-3, "e_star": E_STAR, "radius": R,
            "force_per_length": 100.0}
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        solve_band_contact(**args)
    assert err.value.field == field


def test_memory_is_checked_before_any_work():
    with pytest.raises(ResourceError):
        solve_band_contact(np.zeros((64, 64)), 1e-3, 1e-3, E_STAR, R, 100.0, memory_limit=1e3)
