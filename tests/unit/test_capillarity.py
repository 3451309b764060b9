"""Capillarity of liquids (issue 23): the Laplace pressure of the narrowest gap holds a non-wetting liquid."""

import json
import math

import numpy as np
import pytest

from sealeak.cases.curves import prediction_curves
from sealeak.cases.loader import parse_cases
from sealeak.cases.run import run_case
from sealeak.cli import main
from sealeak.physics.capillarity import Wetting, capillary_pressure
from sealeak.physics.properties import surface_tension
from sealeak.render.notes import worded
from sealeak.render.text import capillary_tables, prediction_table
from tests.casefiles import BASE, ORING, edit

#: Water at 20 °C: 72.74 mN/m (IAPWS, Revised release on the surface tension of ordinary water substance, 2014).
WATER_20C = 72.74e-3


def _case(fluid_lines: str, text: str = BASE):
    return parse_cases(edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\n' + fluid_lines, text))[0]


def test_capillary_pressure_is_the_laplace_pressure_of_a_slit():
    # cos 60° = 1/2, cos 180° = -1: p = γ (1/2 - 1)/u = -γ/(2u)
    assert capillary_pressure(1e-6, 0.05, 60.0, 180.0) == pytest.approx(-0.05 / 2e-6, rel=1e-12)
    # both walls at 0°: 2γ/u, the textbook rise in a slit of fully wetting walls
    assert capillary_pressure([2e-6, 4e-6], 0.07, 0.0, 0.0) == pytest.approx([0.07 / 1e-6, 0.07 / 2e-6], rel=1e-12)
    wetting = Wetting(0.05, 60.0, 180.0)
    assert wetting.entry_pressure(1e-6) == pytest.approx(0.05 / 2e-6, rel=1e-12)
    assert wetting.held(1e-6, 0.9 * 0.05 / 2e-6) and not wetting.held(1e-6, 1.1 * 0.05 / 2e-6)


def test_water_surface_tension_at_20_degC_from_the_library():
    gamma, source = surface_tension("water", 293.15)
    assert gamma == pytest.approx(WATER_20C, rel=0.01)
    assert "CoolProp" in source
    assert surface_tension("water", 353.15)[0] < gamma  # γ falls with temperature


def test_the_issues_example_water_in_an_8_nm_gap_holds_far_above_a_bar():
    gamma, _ = surface_tension("water", 293.15)
    wetting = Wetting(gamma, 110.0, 110.0)
    entry = float(wetting.entry_pressure(8e-9))
    assert entry == pytest.approx(2 * WATER_20C * math.cos(math.radians(70.0)) / 8e-9, rel=0.01)
    assert 5e6 < entry < 7e6  # ≈ 6 MPa ≫ 0.1 MPa
    assert wetting.held(8e-9, 0.1e6)


def test_right_angles_give_no_capillary_pressure_and_the_usual_leak_rate():
    plain = run_case(parse_cases(BASE)[0])
    wet = run_case(_case("contact_angle = 90\nsurface_tension = \"72 mN/m\""))
    rows = wet.capillary["critical_junction"]
    assert (rows.entry_pressure == 0.0).all() and not rows.held.any()
    assert wet.critical_junction.leak_rate == pytest.approx(plain.critical_junction.leak_rate, rel=1e-12, abs=0)
    assert "capillary_entry_pressure" not in plain.units and "capillary_entry_pressure" in wet.units
    assert all(r["held_by_capillarity"] is False for r in wet.records())
    assert "no capillary pressure" in prediction_table([wet])


def test_below_the_entry_pressure_the_liquid_is_held_above_it_leaks_as_usual():
    angle, gamma = 110.0, 0.072
    plain = run_case(parse_cases(BASE)[0]).critical_junction
    entry = -2 * gamma * math.cos(math.radians(angle)) / plain.critical_gap
    i = 2  # the highest squeeze pressure: the narrowest u_c, the highest entry pressure
    assert entry[i] == entry.max()
    for factor, held in ((0.5, True), (2.0, False)):
        dp = factor * entry[i]
        text = edit('pressure_difference = "10 kPa"', f'pressure_difference = "{dp} Pa"')
        uncoupled = run_case(parse_cases(text)[0]).critical_junction.leak_rate
        r = run_case(_case(f'contact_angle = {angle}\nsurface_tension = "{gamma * 1e3} mN/m"', text))
        rows = r.capillary["critical_junction"]
        assert rows.entry_pressure == pytest.approx(entry, rel=1e-9)
        assert bool(rows.held[i]) is held
        expect = 0.0 if held else uncoupled[i]
        assert r.critical_junction.leak_rate[i] == pytest.approx(expect, rel=1e-12, abs=0)
        assert r.records()[i]["held_by_capillarity"] is held and r.records()[i]["leak_rate"] == pytest.approx(expect, rel=1e-6, abs=0)
        assert any("held by capillarity" in m for m in worded(r.messages)) is bool(rows.held.any())


def test_a_wetting_liquid_is_drawn_in_never_held():
    r = run_case(_case('name = "water"\ncontact_angle = 30'))
    rows = r.capillary["critical_junction"]
    assert (rows.entry_pressure < 0).all() and not rows.held.any()
    assert r.case.capillarity.surface_tension == pytest.approx(WATER_20C, rel=0.01)  # looked up for named water
    table = prediction_table([r])
    assert "capillarity, critical junction" in table and "draws it in" in table


def test_both_theories_get_their_own_columns_and_the_table_shows_them():
    text = edit("alpha = 0.2", 'alpha = 0.2\nmodel = "both"')
    r = run_case(_case('contact_angle_rubber = 120\ncontact_angle_surface = 100\nsurface_tension = "50 mN/m"', text))
    em = r.effective_medium
    expect = -0.05 * (math.cos(math.radians(120)) + math.cos(math.radians(100))) / em.effective_gap
    assert r.capillary["effective_medium"].entry_pressure == pytest.approx(np.where(em.percolates, expect, np.nan),
                                                                          rel=1e-9, nan_ok=True)
    assert {"capillary_entry_pressure_effective_medium", "held_by_capillarity_effective_medium"} <= set(r.units)
    table = prediction_table([r])
    assert "capillarity, effective medium" in table and "θ_rubber = 120°" in table
    assert all([k for k in rec] == list(r.units) for rec in r.records())


#: Two compressions of the shared O-ring case: a wider and a narrower critical gap.
TWO_LOADS = edit('compression = ["10 %", "15 %", "30 %"]', 'compression = ["10 %", "20 %"]', ORING)


def test_an_o_ring_holds_water_at_its_critical_gap_where_the_pressure_is_highest():
    plain = run_case(parse_cases(TWO_LOADS)[0]).band
    gamma = surface_tension("water", 293.15)[0]
    entry = -2 * gamma * math.cos(math.radians(110)) / plain.critical_gap_at_max_pressure
    assert np.isfinite(entry).all() and entry[1] > entry[0]  # the narrower gap at the higher compression
    dp = math.sqrt(entry[0] * entry[1])  # between the two: the first load leaks, the second is held
    text = edit('pressure_difference = "1 bar"', f'pressure_difference = "{dp} Pa"', TWO_LOADS)
    uncoupled = run_case(parse_cases(text)[0]).band.critical_junction.leak_rate
    r = run_case(parse_cases(edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\ncontact_angle = 110', text))[0])
    rows = r.capillary["critical_junction"]
    assert rows.entry_pressure == pytest.approx(entry, rel=1e-9)
    assert rows.held.tolist() == [False, True]
    assert r.band.critical_junction.leak_rate == pytest.approx([uncoupled[0], 0.0], rel=1e-12, abs=0)
    assert [rec["held_by_capillarity"] for rec in r.records()] == [False, True]
    assert any("held by capillarity at compression 20 %" in m for m in worded(r.messages))
    assert all([k for k in rec] == list(r.units) for rec in r.records())
    table = prediction_table([r])
    assert "capillarity, critical junction (gap: u_c at the peak contact pressure)" in table
    # the uniform seal's comparison Q_u(p_mean) takes no capillarity: the held row shows it all the same, so says
    assert r.band.critical_junction.uniform_mean_pressure[1] > 0 and "it takes no capillarity" in table
    assert "it takes no capillarity" not in prediction_table([run_case(parse_cases(text)[0])])


@pytest.mark.parametrize("fluid, field", [
    ("contact_angle = 200", "fluid.contact_angle"),
    ("contact_angle = -1", "fluid.contact_angle"),
    ('contact_angle = "wet"', "fluid.contact_angle"),
    ('contact_angle = 100\nsurface_tension = "-1 mN/m"', "fluid.surface_tension"),
    ('contact_angle = 100\nsurface_tension = "72 mN"', "fluid.surface_tension"),
    ("contact_angle_rubber = 100", "fluid.contact_angle_surface"),
    ("contact_angle = 100\ncontact_angle_rubber = 100", "fluid.contact_angle_rubber"),
    ('name = "my coolant"\ncontact_angle = 100', "fluid.surface_tension"),
])
def test_bad_capillarity_inputs_are_one_line_exit_2(tmp_path, capsys, fluid, field):
    _refused(tmp_path, capsys, edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\n' + fluid), field)


def test_a_contact_angle_with_a_gas_is_refused(tmp_path, capsys):
    gas = edit('viscosity = "1 mPa*s"', 'name = "helium"\ncontact_angle = 100',
               edit('pressure_difference = "10 kPa"', 'upstream_pressure = "2 bar"\ndownstream_pressure = "1 bar"'))
    err = _refused(tmp_path, capsys, gas, "fluid.contact_angle")
    assert "liquids" in err


def _refused(tmp_path, capsys, text, field):
    case = tmp_path / "case.toml"
    case.write_text(text)
    out = tmp_path / "out.json"
    assert main(["predict", str(case), "--json", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and field in err and "Traceback" not in err
    assert not out.exists()
    return err


def test_a_surface_tension_without_an_angle_is_checked_and_warned_about():
    case = _case('surface_tension = "72 mN/m"')
    assert case.capillarity is None and any("surface_tension" in w for w in case.input_warnings)


def test_json_has_the_columns_only_with_an_angle(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\ncontact_angle = 120\nsurface_tension = "0.06 N/m"'))
    out = tmp_path / "out.json"
    assert main(["predict", str(case), "--json", str(out), "-q"]) == 0
    doc = json.loads(out.read_text())
    assert doc["units"]["capillary_entry_pressure"] == "Pa" and doc["units"]["held_by_capillarity"] == "1"
    assert all(isinstance(r["held_by_capillarity"], bool) for r in doc["results"])


def test_the_pressure_difference_sweep_steps_up_at_the_entry_pressure():
    ignored = edit("[theory]", '[theory]\nfluid_pressure = "ignored"')  # Q = K ΔP above the step
    r = run_case(_case('contact_angle = 120\nsurface_tension = "72 mN/m"', ignored))
    sweep = prediction_curves([r]).pressure_difference[0]
    i = int(np.flatnonzero(r.critical_junction.squeeze_pressure == sweep.squeeze_pressure)[0])
    entry = r.capillary["critical_junction"].entry_pressure[i]
    assert 0 < entry < sweep.pressure_difference[-1]  # the step lies inside the sweep, and on its grid
    dp, q = sweep.pressure_difference, sweep.critical_junction
    k = r.critical_junction.leak_rate[i] / r.case.pressure_difference  # Q = K ΔP above the step
    assert np.all(q[dp < entry] == 0.0) and entry in dp
    assert q[dp >= entry] == pytest.approx(k * dp[dp >= entry], rel=1e-9, abs=0)


def test_the_capillarity_table_shows_the_records_values():
    r = run_case(_case('contact_angle = 150\nsurface_tension = "72 mN/m"'))
    records = r.records()
    [(title, cols)] = capillary_tables(r)
    assert title.startswith("capillarity, critical junction")
    head, _, cells, key = cols[2]
    scale = {"p_e (kPa)": 1e3, "p_e (MPa)": 1e6}[head]
    assert key == "capillary_entry_pressure"
    assert [float(c) * scale for c in cells] == pytest.approx([rec[key] for rec in records], rel=1e-3)
    head, _, cells, key = cols[3]
    assert key == "held_by_capillarity"
    assert cells == ["yes" if rec[key] else "no" for rec in records]


def test_a_uniform_seal_held_by_capillarity_prints_and_reports_its_note(tmp_path, capsys):
    """The critical junction's held-by-capillarity note of a uniform seal reaches the printed table and the report in
    words (it was a note object the table added to a string: predict and report stopped with a TypeError)."""
    case = tmp_path / "held.toml"
    held = edit('pressure_difference = "10 kPa"', 'pressure_difference = "2 kPa"')  # below p_e at 60 and 100 kPa
    case.write_text(edit("[fluid]\n", "[fluid]\ncontact_angle = 180\nsurface_tension = \"72 mN/m\"\n", held))
    assert main(["predict", str(case)]) == 0
    printed = capsys.readouterr().out
    assert "note: critical junction: held by capillarity at P0 = " in printed
    assert main(["report", str(case), "-o", str(tmp_path / "held.html")]) == 0
    assert "held by capillarity at P0 = " in (tmp_path / "held.html").read_text()


def test_the_effective_mediums_held_note_names_its_theory_among_the_cases_notes(tmp_path, capsys):
    """With both theories, the effective medium's held-by-capillarity note joins the case's notes (the JSON's
    ``messages``) naming its theory, as its sentences do ("effective medium: ..."): it was a note object added to a
    string, and predict stopped with a TypeError."""
    held = edit('pressure_difference = "10 kPa"', 'pressure_difference = "2 kPa"', edit("alpha = 0.2", 'alpha = 0.2\nmodel = "both"'))
    r = run_case(_case('contact_angle = 180\nsurface_tension = "72 mN/m"', held))
    assert r.capillary["effective_medium"].held.any()
    notes = worded(r.messages)
    assert any(n.startswith("critical junction: held by capillarity at P0 = ") for n in notes)
    assert any(n.startswith("effective medium: held by capillarity at P0 = ") for n in notes)
    case = tmp_path / "held.toml"
    case.write_text(edit("[fluid]\n", "[fluid]\ncontact_angle = 180\nsurface_tension = \"72 mN/m\"\n", held))
    assert main(["predict", str(case), "--json", str(tmp_path / "held.json")]) == 0
    messages = json.loads((tmp_path / "held.json").read_text())["messages"]
    assert any(m.startswith("effective medium: held by capillarity") for m in messages)
    printed = capsys.readouterr().out  # under its own heading the effective medium's note needs no prefix
    assert "\nnote: held by capillarity at P0 = " in printed
