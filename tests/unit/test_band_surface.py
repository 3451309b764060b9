"""The effective medium's σ_eff surface that the loads of a sweep share (cases/band.py, docs/architecture.md)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy import special
from scipy.interpolate import BarycentricInterpolator

import sealeak.cases.band as band_module
import sealeak.cases.band_tables as tables_module
from sealeak.cases import example_path, load_cases
from sealeak.cases.band import _surface, run_band
from sealeak.cases.band_tables import SURFACE_RTOL, TABLE_RTOL, SweepSurface, effective_medium_exact, persson_contact
from sealeak.cases.seals import with_loads
from sealeak.physics.gaps import clear_caches


def _threshold(case, q0):
    """Bruggeman's threshold pressure of the case's contact at q0 (Pa): A(ζ1)/A0 = erf(P0/(2√G(ζ1))) = 1/2."""
    contact = persson_contact(case, float(q0))
    return 2.0 * float(special.erfinv(0.5)) * math.sqrt(float(contact.G(contact.zeta_max)))


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
    low = tables_module.TABLE_FLOOR * min(p.max_pressure for p in profiles)
    surface = SweepSurface.build(case, np.asarray(case.band.q0), low, max(p.max_pressure for p in profiles))
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
        exact = effective_medium_exact(case, persson_contact(case, q))(p)
        assert np.all(exact > 0)
        np.testing.assert_allclose(surface.sigma(q, p), exact, rtol=SURFACE_RTOL, atol=0)


def test_surface_reaches_close_to_the_threshold_on_few_points(sweep):
    """The surface tabulates σ_eff/(1 − p/p_c)³ (docs/theory.md eq. 5.5), so it reaches SURFACE_TOP = 0.95 of the lowest
    threshold of the loads (their peaks lie beyond it) on a 65-point middle table; ln σ_eff itself over the same range
    needs 129 (its logarithmic singularity at p_c)."""
    case, surface = sweep
    top = min(_threshold(case, q) for q in case.band.q0)
    assert max(p.max_pressure for p in case.band.profiles) > top
    assert surface.high == pytest.approx(0.95 * top, rel=1e-12, abs=0)
    assert surface.base is not None and surface.base.s.size <= 65
    q_mid = math.exp(float(surface.nodes[surface.nodes.size // 2]))
    exact = effective_medium_exact(case, persson_contact(case, q_mid))
    plain = tables_module.SigmaTable(exact, surface.high, 65, surface.low / surface.high)
    assert not plain.checked(exact, 0.5 * SURFACE_RTOL, grow=False)[1]  # ln σ itself: 65 points are not enough


def test_a_table_with_the_threshold_follows_sigma_up_to_it():
    """σ = e^(−p/p0) (1 − p/p_c)³ over [1e-3 p_max, p_max], p_max = 0.99 p_c: with ``threshold`` the table interpolates
    ln σ − 3 ln(1 − p/p_c), a smooth function, and 17 points hold σ to 1e-9 up to p_max; ln σ itself, with its
    logarithmic singularity just beyond p_max, is 16 % off at 33 points and 0.8 % at 65."""
    p_c = 2e6

    def sigma(p):
        p = np.asarray(p, dtype=float)
        return 1e-12 * np.exp(-p / 3e5) * (1.0 - p / p_c) ** 3

    p = np.geomspace(0.99 * p_c * 1e-3, 0.99 * p_c, 2001)
    with_threshold = tables_module.SigmaTable(sigma, 0.99 * p_c, 17, threshold=p_c)
    np.testing.assert_allclose(with_threshold(p), sigma(p), rtol=1e-9, atol=0)
    plain = tables_module.SigmaTable(sigma, 0.99 * p_c, 65)
    assert np.max(np.abs(plain(p) / sigma(p) - 1.0)) > 1e-3
    refined = with_threshold.refine(sigma)  # (the factor follows the table through a doubling)
    np.testing.assert_allclose(refined(p), sigma(p), rtol=1e-12, atol=0)
    assert tables_module.SigmaTable(sigma, 0.99 * p_c, 9, threshold=0.5 * p_c).threshold is None  # (only above p_max)


def test_the_o_ring_examples_effective_medium_integrals_converge(monkeypatch):
    """Every load of the bundled `o-ring` example meets the band integral's tolerance. Its σ tables interpolate
    σ/(1 − p/p_c)³, so the loads whose peak nears the threshold converge on few points: capped at 33, tables of ln σ
    stopped 3.5e-5 to 6e-3 from converged at 22.5–27.5 % compression, these stop within 3e-5."""
    case = load_cases(example_path("o-ring"))[0]
    em = run_band(case).effective_medium
    assert em is not None
    assert np.nanmax(em.change) <= TABLE_RTOL
    assert not [m for m in em.messages if getattr(m, "code", "") == "band_not_converged"]
    for module in (tables_module, band_module):
        monkeypatch.setattr(module, "TABLE_POINTS", (9, 33))
    clear_caches()
    capped = run_band(case).effective_medium
    assert capped is not None and np.nanmax(capped.change) < 1e-4


def test_surface_stays_below_the_bruggeman_threshold_and_takes_exact_values_above(sweep):
    """Above its top (a factor below the pressure where A(ζ1)/A0 = 1/2) a load's σ is the exact one, bit for bit, and 0
    beyond the threshold."""
    case, surface = sweep
    contact = persson_contact(case, float(case.band.q0[-1]))
    threshold = _threshold(case, contact.q0)
    assert surface.high < threshold
    p = np.array([surface.high * 1.01, 1.2 * threshold])
    exact = effective_medium_exact(case, contact)(p)
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
    monkeypatch.setattr(tables_module, "SURFACE_P_POINTS", (5, 9))
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

    table = tables_module.SigmaTable(sigma, 1e6, 9, 1e-6)
    sizes = []
    while True:
        calls.clear()
        nxt, good = table.checked(sigma, 1e-6)
        added = np.exp(tables_module.lobatto_points(table.lo, table.hi, 2 * table.s.size - 1)[1::2])
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
    small = tables_module.SigmaTable(sigma, 1e6, 9, 1e-6)
    calls.clear()
    assert small.checked(sigma, 1e-6, grow=False) == (small, False) and sum(calls) == 8  # nothing beyond the check


def _points_needed(f, lo, hi, sizes, rtol):
    """The first of ``sizes`` whose Chebyshev–Lobatto interpolant of ``f`` on [lo, hi] (scipy's barycentric
    interpolation, independent of the code's) is within ``rtol`` of ``f`` at every middle of its intervals; None if none."""
    for n in sizes:
        s = (lo + hi) / 2 - (hi - lo) / 2 * np.cos(np.pi * np.arange(2 * n - 1) / (2 * n - 2))
        nodes, middles = s[::2], s[1::2]
        if np.max(np.abs(BarycentricInterpolator(nodes, f(nodes))(middles) - f(middles))) < rtol:
            return n
    return None


def _vanishing_at_the_threshold(monkeypatch, case, log_regular):
    """The effective medium's σ replaced by exp(``log_regular``(p, q0)) (1 − p/p_c)³, p_c the contact's Bruggeman
    threshold: the surface tabulates exp(``log_regular``) (σ less the factor with which it vanishes at p_c)."""
    def exact(case_, contact):
        top = _threshold(case, contact.q0)
        return lambda p: np.exp(log_regular(p, contact.q0)) * (1.0 - p / top) ** 3
    monkeypatch.setattr(tables_module, "effective_medium_exact", exact)


@pytest.mark.parametrize("k", [2.0, 4.0, 8.0, 40.0])
def test_a_surface_table_takes_as_many_points_as_its_tolerance_needs(monkeypatch, k):
    """A table of the surface is accepted at the first of 33, 65 and 129 points that meets :data:`SURFACE_RTOL` (ln r
    = sin(k ln p) over 1 Pa .. 1 MPa, σ = r (1 − p/p_c)³, needs more points the larger k: as many as an interpolant of ln r
    checked at all its middles needs), and there is none where 129 do not."""
    case = load_cases(example_path("o-ring"))[0]
    _vanishing_at_the_threshold(monkeypatch, case, lambda p, q0: np.sin(k * np.log(p)))
    table = SweepSurface._table(case, 3000.0, 1.0, 1e6, SURFACE_RTOL)
    points = _points_needed(lambda s: np.sin(k * s), 0.0, math.log(1e6), (33, 65, 129), SURFACE_RTOL)
    assert (table is None) if points is None else (table is not None and table.s.size == points)
    if table is not None:
        p = np.geomspace(1.0, 1e6, 1001)
        sigma = np.exp(np.sin(k * np.log(p))) * (1.0 - p / _threshold(case, 3000.0)) ** 3
        np.testing.assert_allclose(table(p), sigma, rtol=SURFACE_RTOL, atol=0)


@pytest.mark.parametrize(("k", "m"), [(2.0, 0.0), (4.0, 1.5), (2.0, 7.0)])
def test_the_other_q0_points_tabulate_their_difference_from_the_middle_one(monkeypatch, k, m):
    """ln σ(p; q0) = sin(k ln p) + c(q0)(ln p + sin(m ln p)), c = 0.01 (ln q0 − 8): the middle q0's table takes the
    points it needs at SURFACE_RTOL/2, and each other q0 point tabulates its difference from it on as many of those
    points as the difference needs at SURFACE_RTOL/2 (9 where it is linear in ln p); a difference that would need the
    middle table's own points (sin(7 ln p) against a 33-point middle table) makes every q0 point take a full table of
    its own at SURFACE_RTOL. Either way the surface agrees with σ between its q0 points to :data:`SURFACE_RTOL`."""
    def log_sigma(p, q0):
        s = np.log(p)
        return np.sin(k * s) + 0.01 * (math.log(q0) - 8.0) * (s + np.sin(m * s))

    case = load_cases(example_path("o-ring"))[0]
    _vanishing_at_the_threshold(monkeypatch, case, log_sigma)
    q0 = np.geomspace(3000.0, 5500.0, 7)
    surface = SweepSurface.build(case, q0, 1.0, 1e6)
    assert surface is not None
    # the q0 points: Chebyshev–Lobatto in ln q0, ends at the loads' own q0 (σ is linear in ln q0: five are exact)
    lo, hi, ends = 0.0, math.log(1e6), np.log(q0[[0, -1]])
    nodes = np.exp((ends[0] + ends[1]) / 2 - (ends[1] - ends[0]) / 2 * np.cos(np.pi * np.arange(5) / 4))
    nodes[[0, -1]] = q0[[0, -1]]
    middle = _points_needed(lambda s: log_sigma(np.exp(s), nodes[2]), lo, hi, (33, 65, 129), SURFACE_RTOL / 2)
    differences = [_points_needed(lambda s, q=q: log_sigma(np.exp(s), q) - log_sigma(np.exp(s), nodes[2]), lo, hi,
                                  (9, 17, 33, 65)[:{33: 2, 65: 3, 129: 4}[middle]], SURFACE_RTOL / 2)
                   for q in nodes[[0, 1, 3, 4]]]
    sizes = {part[0].size for part in surface.parts if part is not None}
    if None not in differences:
        assert surface.base is not None and surface.base.s.size == middle and sizes == set(differences)
    else:
        full = {_points_needed(lambda s, q=q: log_sigma(np.exp(s), q), lo, hi, (33, 65, 129), SURFACE_RTOL)
                for q in nodes}
        assert surface.base is None and sizes == full
    assert (surface.base is None) == (m == 7.0)  # (the fallback is exercised, and only where the reasoning says)
    p = np.geomspace(1.0, 1e6, 301)
    for q in np.sqrt(q0[:-1] * q0[1:]).tolist():
        np.testing.assert_allclose(surface.sigma(q, p), np.exp(log_sigma(p, q)) * (1.0 - p / _threshold(case, q)) ** 3,
                                   rtol=SURFACE_RTOL, atol=0)


def test_a_tables_top_point_is_its_top_pressure_itself():
    """A σ table over [floor·p_max, p_max] asks for σ at p_max itself, not at exp(ln p_max) (an ulp off for some
    pressures), so the effective medium's σ(p_max), asked first by the band integral, is read from what is kept instead
    of computed again."""
    asked = []

    def sigma(p):
        asked.append(np.array(p, copy=True))
        return 1e-12 * np.exp(-np.asarray(p) / 1e6)

    tops = [p for p in np.geomspace(1.0, 1e7, 400) if math.exp(math.log(p)) != p]
    assert tops  # (pressures whose logarithm does not come back to them exist)
    for p_max in tops[:5]:
        asked.clear()
        tables_module.SigmaTable(sigma, p_max, 9)
        assert asked[0][-1] == p_max and asked[0][0] == pytest.approx(1e-3 * p_max, rel=1e-12, abs=0)
