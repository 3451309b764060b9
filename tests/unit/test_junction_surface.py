"""The critical junction's u_c(p; q0) surface that the loads of a long sweep share (cases/band_tables.py, docs/architecture.md)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy import special

import sealeak.cases.band as band_module
import sealeak.cases.band_tables as tables_module
from sealeak.cases import example_path, load_cases
from sealeak.cases.band import _junction_surface, run_band
from sealeak.cases.band_tables import (
    JUNCTION_RTOL,
    JUNCTION_TOP,
    JunctionSurface,
    chebyshev_lobatto_interpolate,
    lobatto_points,
    lobatto_weights,
    persson_contact,
)
from sealeak.cases.seals import with_loads
from sealeak.physics.critical_junction import critical_junction, percolation_limit


def _sweep(n: int, fluid_pressure: str = "ignored"):
    """The bundled o-ring example (water, critical junction) over ``n`` compressions from 10 % to 35 %: the highest
    peak pressures lie above the percolation limit (sealed loads), the lowest far below it."""
    case = load_cases(example_path("o-ring"))[0]
    band = with_loads(case.band, np.linspace(0.10, 0.35, n), case.youngs_modulus, case.poisson_ratio)
    return replace(case, band=band, model="critical-junction", fluid_pressure=fluid_pressure)


def _gap(case, q0, p):
    """u_c (m) of the exact critical junction (docs/theory.md eq. 3.4), NaN where it does not percolate."""
    return critical_junction(persson_contact(case, float(q0)), squeeze_pressure=p, pressure_difference=1.0,
                             viscosity=1.0, aspect_ratio=1.0,
                             percolation_threshold=case.percolation_threshold).critical_gap


@pytest.fixture(scope="module")
def sweep():
    case = _sweep(20, "coupled")
    surface = _junction_surface(case, case.band)
    assert surface is not None
    return case, surface


def test_the_percolation_limit_is_where_the_contact_area_at_the_cutoff_reaches_one_minus_p_c():
    """P0 = 2 erfinv(1 − p_c) √G(ζ1): A(ζ1)/A0 = erf(P0/(2√G(ζ1))) is 1 − p_c there (to rounding), and the junction
    percolates just below it and not just above."""
    case = _sweep(2)
    contact = persson_contact(case, float(case.band.q0[0]))
    for p_c in (0.6, 0.5):
        limit = percolation_limit(contact, p_c)
        area = float(special.erf(limit / (2.0 * math.sqrt(float(contact.G(contact.zeta_max))))))
        assert area == pytest.approx(1.0 - p_c, rel=1e-13, abs=0.0)
        res = critical_junction(contact, squeeze_pressure=[limit * (1 - 1e-6), limit * (1 + 1e-6)], pressure_difference=1.0,
                                viscosity=1.0, aspect_ratio=1.0, percolation_threshold=p_c)
        assert res.percolates.tolist() == [True, False]


def test_lobatto_weights_are_the_interpolant_of_unit_values():
    """The weights of the q0 points are chebyshev_lobatto_interpolate at each unit vector, bit for bit, and sum to 1."""
    nodes = lobatto_points(-1.3, 2.1, 9)
    for x in (-1.3, -0.2, 0.77, nodes[4], 2.1):
        w = lobatto_weights(nodes, float(x))
        one_by_one = [float(chebyshev_lobatto_interpolate(nodes, e, np.full(1, x))[0]) for e in np.eye(nodes.size)]
        assert w.tolist() == one_by_one
        assert float(w.sum()) == pytest.approx(1.0, rel=1e-14, abs=0.0)


def test_surface_matches_the_exact_junction_between_its_points(sweep):
    """Off every point of the surface (q0 between its q0 points, p between its points in ln p), σ ∝ u_c³ is the exact
    junction's to the stated tolerance."""
    case, surface = sweep
    assert surface.nodes.size >= 2 and surface.s.size >= 65
    q0 = np.exp(0.5 * (surface.nodes[:-1] + surface.nodes[1:]))[[0, -1]]
    p = np.exp(0.5 * (surface.s[:-1] + surface.s[1:]))[::5]
    for q in q0:
        contact = persson_contact(case, float(q))
        approx = surface.for_load(case, contact)(p)
        exact = case.alpha * _gap(case, q, p) ** 3 / (12.0 * case.fluid.viscosity)
        assert np.max(np.abs(approx / exact - 1.0)) < JUNCTION_RTOL


def test_surface_stops_below_the_percolation_limit_and_takes_the_exact_junction_above(sweep):
    """Its top is JUNCTION_TOP of the lowest limit; above it σ is the exact junction's, bit for bit, 0 beyond the limit."""
    case, surface = sweep
    limit = min(percolation_limit(persson_contact(case, float(q)), case.percolation_threshold) for q in case.band.q0)
    assert surface.high == pytest.approx(JUNCTION_TOP * limit, rel=1e-12, abs=0.0)
    q = float(case.band.q0[7])
    p = np.array([surface.high * 1.01, 0.5 * (surface.high + limit), limit * 1.01])
    sigma = surface.for_load(case, persson_contact(case, q))(p)
    exact = case.alpha * _gap(case, q, p) ** 3 / (12.0 * case.fluid.viscosity)
    assert sigma[:2].tolist() == exact[:2].tolist() and sigma[2] == 0.0 and np.isnan(exact[2])


def test_beyond_its_percolation_limit_a_load_is_closed_without_a_call_of_the_junction(sweep, monkeypatch):
    """σ = 0 beyond the load's own limit (closed form), as the exact junction says, and without calling it: a sealed
    load's band integral stops at its peak."""
    case, surface = sweep
    contact = persson_contact(case, float(case.band.q0[7]))
    limit = percolation_limit(contact, case.percolation_threshold)
    p = limit * np.array([1.0 + 1e-6, 1.01, 2.0])
    assert not critical_junction(contact, squeeze_pressure=p, pressure_difference=1.0, viscosity=1.0, aspect_ratio=1.0,
                                 percolation_threshold=case.percolation_threshold).percolates.any()
    calls = []
    monkeypatch.setattr(tables_module, "critical_junction", lambda *a, **k: calls.append(k))
    assert surface.for_load(case, contact)(p).tolist() == [0.0, 0.0, 0.0] and not calls


@pytest.mark.parametrize("fluid_pressure", ["ignored", "coupled"])
def test_a_long_sweep_with_the_surface_gives_the_exact_leak_rates(fluid_pressure, monkeypatch):
    """20 loads, some sealed: the leak rates and peak junctions through the surface are those of the exact junction at
    every load (within the surface's tolerance, far below the quadrature's own), the sealed loads the same; the reported
    error includes the surface's."""
    case = _sweep(20, fluid_pressure)
    assert _junction_surface(case, case.band) is not None
    with_surface = run_band(case)
    monkeypatch.setattr(band_module, "JUNCTION_SURFACE_MIN_LOADS", 10**6)
    assert _junction_surface(case, case.band) is None
    exact = run_band(case)
    a, b = with_surface.critical_junction, exact.critical_junction
    assert (~a.percolates).any() and a.percolates.any()
    assert a.percolates.tolist() == b.percolates.tolist()
    leaks = a.percolates
    assert np.max(np.abs(a.leak_rate[leaks] / b.leak_rate[leaks] - 1.0)) < 3 * JUNCTION_RTOL
    assert np.max(np.abs(with_surface.critical_gap_at_max_pressure[leaks] / exact.critical_gap_at_max_pressure[leaks] - 1.0)) \
        < JUNCTION_RTOL
    assert np.array_equal(with_surface.critical_wavelength_at_max_pressure, exact.critical_wavelength_at_max_pressure,
                          equal_nan=True)
    assert np.all(a.change[leaks] >= JUNCTION_RTOL)


def test_a_short_sweep_and_an_uncertainty_sample_take_the_exact_junction():
    """Below JUNCTION_SURFACE_MIN_LOADS loads (the bundled example's 9), and where scaled junction tables serve the loads
    (an uncertainty sample), there is no surface."""
    case = _sweep(band_module.JUNCTION_SURFACE_MIN_LOADS - 1)
    assert _junction_surface(case, case.band) is None
    case = _sweep(band_module.JUNCTION_SURFACE_MIN_LOADS)
    assert _junction_surface(case, case.band) is not None
    with band_module.scaled_junctions(band_module.ScaledJunctions({}, 1.0, 1.0)):
        assert _junction_surface(case, case.band) is None


def test_a_surface_is_built_once_for_the_same_loads(sweep, monkeypatch):
    """The same loads and range give the kept surface, without one exact value."""
    case, surface = sweep
    calls = []
    monkeypatch.setattr(JunctionSurface, "_build", classmethod(lambda cls, *a: calls.append(a)))
    again = _junction_surface(case, case.band)
    assert not calls and again is not None
    assert again.values.tolist() == surface.values.tolist() and again.s.tolist() == surface.s.tolist()
