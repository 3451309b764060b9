"""``simulate`` of a liquid with a contact angle (a uniform seal and an O-ring): each realisation's critical
constriction and its entry pressure (docs/theory.md §12.4). The constriction is recomputed here from the gap fields the run writes, by a search of every
gap value with :func:`sealeak.numerics.spans`."""


import numpy as np
import pytest

from sealeak.cases import parse_cases
from sealeak.cases.simulation import simulate
from sealeak.cases.simulation_band import simulate_band
from sealeak.numerics import spans
from sealeak.render.simulation import band_simulation_json, band_simulation_table, simulation_json, simulation_table
from tests.casefiles import FINE_SURFACE
from tests.integration.test_cli_simulate_oring import ORING

CASE = """
title = "capillarity in the simulation"
""" + FINE_SURFACE + """[seal]
shape = "rectangle"
width = "0.5 mm"
length = "100 mm"
[fluid]
viscosity = "1 mPa*s"
{fluid}
[conditions]
squeeze_pressure = ["8 kPa", "20 kPa"]
pressure_difference = "5 kPa"
"""
GAMMA, THETA = 0.072, 90.1


def _case(fluid):
    (case,) = parse_cases(CASE.format(fluid=fluid))
    return case


def _widest_path_gap(gap, fluid):
    """The largest gap value h whose cells (gap >= h) still connect inlet and outlet, tried from the top down."""
    return next((h for h in np.unique(gap[fluid])[::-1] if spans(fluid & (gap >= h))), np.nan)


def test_simulate_reports_each_realisations_entry_pressure(tmp_path):
    case = _case(f'surface_tension = "{GAMMA} N/m"\ncontact_angle = {THETA}')
    res = simulate(case, grid=32, realizations=2, seed=3, threshold=False, fields_dir=tmp_path)
    c = res.capillarity
    assert c is not None
    entry = res.per_realization["capillary_entry_pressure"]
    factor = -GAMMA * 2.0 * np.cos(np.radians(THETA))  # p_e u (eq. 12.2)
    for r in range(2):
        for i in range(2):
            with np.load(tmp_path / f"r{r}-p{i}.npz") as f:
                u = _widest_path_gap(f["gap"], f["pressure"] <= 0)
            assert entry[r, i] == pytest.approx(factor / u, rel=1e-12) if np.isfinite(u) else np.isnan(entry[r, i])
    held = res.per_realization["held_by_capillarity"]
    np.testing.assert_array_equal(held, res.per_realization["percolates"] & (5e3 < np.nan_to_num(entry)))
    np.testing.assert_allclose(c.held_fraction, held.mean(axis=0))
    assert list(c.held_by_capillarity) == [False, True]  # p_e ≈ 2 kPa and 10 kPa about ΔP = 5 kPa
    # the theory's u_c of the same (grid-cut) spectrum, from its leak rate Q_cj = (Ly/Lx) u_c³ ΔP/(12η) at α = 1
    q_cj = res.leak_rate_critical_junction
    assert np.isfinite(q_cj).any()
    u_c = np.cbrt(12.0 * 1e-3 * q_cj / (case.seal.aspect_ratio * 5e3))
    ok = np.isfinite(u_c)
    np.testing.assert_allclose(c.capillary_entry_pressure_critical_junction[ok], factor / u_c[ok], rtol=1e-9)
    # the narrowest constriction grows tighter with the squeeze pressure: a higher entry pressure
    assert c.capillary_entry_pressure[1] > c.capillary_entry_pressure[0]
    assert "capillary_entry_pressure_critical_junction" in simulation_json(case, res)
    assert "p_e at u_c (kPa)" in simulation_table(case, res)


def test_simulate_with_a_contact_angle_of_90_degrees_changes_no_flow():
    plain = simulate(_case(""), grid=32, realizations=1, seed=3, threshold=False)
    right = simulate(_case(f'surface_tension = "{GAMMA} N/m"\ncontact_angle = 90'), grid=32, realizations=1, seed=3,
                     threshold=False)
    assert plain.capillarity is None and "capillary" not in simulation_json(_case(""), plain)
    np.testing.assert_array_equal(right.leak_rate, plain.leak_rate)
    np.testing.assert_array_equal(right.alpha, plain.alpha)
    assert right.capillarity is not None and not right.capillarity.held_fraction.any()
    assert np.all(np.nan_to_num(right.capillarity.capillary_entry_pressure) == 0.0)


def test_simulate_of_an_o_ring_reports_the_constriction_across_its_band(tmp_path):
    text = ORING.replace('viscosity = "1 mPa*s"', f'viscosity = "1 mPa*s"\nsurface_tension = "{GAMMA} N/m"\n'
                                                   f'contact_angle = {THETA}')
    (case,) = parse_cases(text)
    res = simulate_band(case, grid=32, realizations=1, seed=3, fields_dir=tmp_path)
    c = res.capillarity
    assert c is not None and res.per_realization["percolates"].any()
    factor = -GAMMA * 2.0 * np.cos(np.radians(THETA))
    for i in range(res.loads.size):
        with np.load(tmp_path / f"r0-p{i}.npz") as f:
            u = _widest_path_gap(f["gap"], f["pressure"] <= 0)
        entry = res.per_realization["capillary_entry_pressure"][0, i]
        assert entry == pytest.approx(factor / u, rel=1e-12) if np.isfinite(u) else np.isnan(entry)
    assert "p_e at u_c, peak (kPa)" in band_simulation_table(case, res)
    assert "held_by_capillarity" in band_simulation_json(case, res)
