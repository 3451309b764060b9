"""The effective medium's σ_eff surface that the loads of a sweep share (cases/band.py, docs/architecture.md)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import sealeak.cases.band as band_module
from sealeak.cases import example_path, load_cases
from sealeak.cases.band import SURFACE_RTOL, TABLE_RTOL, _contact, _em_exact, _surface, _SweepSurface, run_band
from sealeak.cases.seals import with_loads


def _sweep(n: int, fluid_pressure: str = "ignored"):
    """The bundled o-ring example (water, effective medium) over ``n`` compressions from 10 % to 30 %."""
    case = load_cases(example_path("o-ring"))[0]
    band = with_loads(case.band, np.linspace(0.10, 0.30, n), case.youngs_modulus, case.poisson_ratio)
    return replace(case, band=band, model="effective-medium", fluid_pressure=fluid_pressure)


pytestmark = pytest.mark.slow  # a surface costs ~650 exact effective-medium values (~10 s)


@pytest.fixture(scope="module")
def sweep():
    case = _sweep(4)
    assert case.band is not None
    profiles = case.band.profiles
    low = band_module.TABLE_FLOOR * min(p.max_pressure for p in profiles)
    surface = _SweepSurface.build(case, np.asarray(case.band.q0), low, max(p.max_pressure for p in profiles))
    assert surface is not None
    return case, surface


def test_surface_matches_the_exact_effective_medium_between_its_points(sweep):
    """Off every point of the surface (q0 between its q0 points, p between its table's points) σ_eff is the exact one
    to the stated tolerance."""
    case, surface = sweep
    nodes = surface.nodes
    assert nodes.size >= 2  # the loads' q0 differ: the surface interpolates in q0
    between = 0.5 * (nodes[:-1] + nodes[1:])
    q0 = np.exp(between[[0, -1]])  # the surface's q0 points lie in ln q0
    assert surface.base is not None  # the middle q0's table, the others as differences from it
    s = surface.base.s
    p = np.exp(0.5 * (s[:-1] + s[1:]))[::6]
    p = p[(p >= surface.low) & (p <= surface.high)]
    assert p.size > 10
    for q in q0.tolist():
        exact = _em_exact(case, _contact(case, q))(p)
        assert np.all(exact > 0)
        np.testing.assert_allclose(surface.sigma(q, p), exact, rtol=SURFACE_RTOL, atol=0)


def test_surface_stays_below_the_bruggeman_threshold_and_takes_exact_values_above(sweep):
    """Above its top (a factor below the pressure where A(ζ1)/A0 = 1/2) a load's σ is the exact one, bit for bit, and 0
    beyond the threshold."""
    case, surface = sweep
    contact = _contact(case, float(case.band.q0[-1]))
    threshold = 2.0 * 0.4769362762044699 * np.sqrt(contact.G(contact.zeta_max))  # erfinv(1/2) = 0.47693...
    assert surface.high < threshold
    p = np.array([surface.high * 1.01, 1.2 * threshold])
    exact = _em_exact(case, contact)(p)
    np.testing.assert_array_equal(surface.for_load(contact)(p), exact)
    assert exact[0] > 0 and exact[1] == 0


def test_a_sweep_with_the_surface_gives_the_exact_leak_rates(monkeypatch):
    """The band's effective-medium leak rates through the shared surface equal those of the exact σ_eff per load."""
    case = _sweep(4)
    monkeypatch.setattr(band_module, "SURFACE_MIN_LOADS", 2)
    assert case.band is not None and _surface(case, case.band) is not None
    shared = run_band(case).effective_medium
    monkeypatch.setattr(band_module, "SURFACE_MIN_LOADS", 10**6)
    exact = run_band(case).effective_medium
    assert shared is not None and exact is not None
    np.testing.assert_array_equal(shared.percolates, exact.percolates)
    assert shared.percolates.any() and not shared.percolates.all()  # a load seals: the exact top is exercised
    for name in ("leak_rate", "uniform_mean_pressure", "resistance"):
        np.testing.assert_allclose(getattr(shared, name), getattr(exact, name), rtol=TABLE_RTOL, atol=0)


def test_no_surface_where_it_cannot_reach_its_tolerance(monkeypatch):
    """Too few points allowed: no surface (the loads take the exact σ_eff)."""
    case = _sweep(4)
    monkeypatch.setattr(band_module, "SURFACE_P_POINTS", (5, 9))
    assert case.band is not None
    monkeypatch.setattr(band_module, "SURFACE_MIN_LOADS", 2)
    assert _surface(case, case.band) is None


def test_a_table_is_checked_at_a_quarter_of_the_points_the_next_adds():
    """:meth:`_Table.checked` evaluates σ at a quarter of the points the next table adds (every fourth and the last):
    a table it accepts agrees with σ at all of them within the tolerance; one it rejects becomes that next table,
    bit for bit the refined one, with no point evaluated twice."""
    calls: list[int] = []

    def sigma(p):
        calls.append(p.size)
        return p**-1.5 * np.exp(-p / 3e5) / (1.0 + (p / 2e3) ** 2)

    table = band_module._Table(sigma, 1e6, 9, 1e-6)
    sizes = []
    while True:
        calls.clear()
        nxt, good = table.checked(sigma, 1e-6)
        added = np.exp(band_module._lobatto(table.lo, table.hi, 2 * table.s.size - 1)[1::2])
        if good:
            n = added.size
            assert nxt is table and sum(calls) == len(set(range(0, n, min(4, max(1, n // 8)))) | {n - 1})
            np.testing.assert_allclose(table(added), sigma(added), rtol=1e-6, atol=0)
            break
        assert sum(calls) == added.size  # the points checked are reused
        refined = table.refine(sigma)
        np.testing.assert_array_equal(nxt.values, refined.values)
        assert np.max(np.abs(table(added) / sigma(added) - 1.0)) > 1e-6  # rejected for a reason
        sizes.append(table.s.size)
        table = nxt
    assert sizes and table.s.size >= 33  # it took a few doublings
    calls.clear()
    small = band_module._Table(sigma, 1e6, 9, 1e-6)
    calls.clear()
    assert small.checked(sigma, 1e-6, grow=False) == (small, False) and sum(calls) == 8  # nothing beyond the check


@pytest.mark.parametrize(("k", "points"), [(2.0, 33), (4.0, 65), (8.0, 129), (40.0, None)])
def test_a_surface_table_takes_as_many_points_as_its_tolerance_needs(monkeypatch, k, points):
    """A table of the surface is accepted at the first of 33, 65 and 129 points that meets :data:`SURFACE_RTOL` (ln σ
    = sin(k ln p) over 1 Pa .. 1 MPa needs more points the larger k), and there is none where 129 do not."""
    monkeypatch.setattr(band_module, "_em_exact", lambda case, contact: lambda p: np.exp(np.sin(k * np.log(p))))
    case = load_cases(example_path("o-ring"))[0]
    table = _SweepSurface._table(case, 3000.0, 1.0, 1e6, SURFACE_RTOL)
    assert (table is None) if points is None else (table is not None and table.s.size == points)
    if table is not None:
        p = np.geomspace(1.0, 1e6, 1001)
        np.testing.assert_allclose(table(p), np.exp(np.sin(k * np.log(p))), rtol=SURFACE_RTOL, atol=0)


@pytest.mark.parametrize(("k", "m", "base", "parts"), [(2.0, 0.0, 33, 9), (4.0, 1.5, 65, 33), (2.0, 7.0, None, 65)])
def test_the_other_q0_points_tabulate_their_difference_from_the_middle_one(monkeypatch, k, m, base, parts):
    """ln σ(p; q0) = sin(k ln p) + c(q0)(ln p + sin(m ln p)), c = 0.01 (ln q0 − 8): the difference from the middle q0
    is tabulated on a fraction of the middle table's points, as many as it needs (9 where it is linear in ln p, 33 for
    sin(1.5 ln p)); a difference that needs as many as the middle table (sin(7 ln p) against a 33-point middle table)
    takes full tables at every q0 point. Either way the surface agrees with σ between its q0 points to
    :data:`SURFACE_RTOL`."""
    def log_sigma(p, q0):
        s = np.log(p)
        return np.sin(k * s) + 0.01 * (math.log(q0) - 8.0) * (s + np.sin(m * s))

    monkeypatch.setattr(band_module, "_em_exact", lambda case, contact: lambda p: np.exp(log_sigma(p, contact.q0)))
    case = load_cases(example_path("o-ring"))[0]
    q0 = np.geomspace(3000.0, 5500.0, 7)
    surface = _SweepSurface.build(case, q0, 1.0, 1e6)
    assert surface is not None
    assert (None if surface.base is None else surface.base.s.size) == base
    assert {part[0].size for part in surface.parts if part is not None} == {parts}
    p = np.geomspace(1.0, 1e6, 301)
    for q in np.sqrt(q0[:-1] * q0[1:]).tolist():
        np.testing.assert_allclose(surface.sigma(q, p), np.exp(log_sigma(p, q)), rtol=SURFACE_RTOL, atol=0)
