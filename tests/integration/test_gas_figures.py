"""Figures and fit output of gas cases (issue 13): they show the gas leak rate the user tests against.

For a gas case ``leak_rate.png`` / ``leak_rate_log.png`` (uniform seal) and the band ``leak_rate.png``
draw the pV throughput in mbar·l/s with a second axis in Pa·m³/s, each theory solid and its helium
equivalent dashed; the drawn curves are the records' ``leak_rate_mbar_l_s`` (and
``leak_rate_helium_mbar_l_s``), read here from the Line2D data. ``leak_rate_vs_pressure_difference.png``
draws Q_pV against ΔP at fixed P_b (no slip: K (P_a² − P_b²)/2). ``sealeak fit`` on a gas case names Pa·m³/s (text, JSON, figure
labels) and gives mbar·l/s beside it. Liquid figures keep m³/s and ml/min.
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from sealeak.cases import example_path, prediction_curves, read_case_file, run_case, run_fit
from sealeak.cases.gas import gas_throughput
from sealeak.cli import main
from sealeak.lab.data import read_leak_data
from sealeak.render.band import figure_band_leak_rate
from sealeak.render.figures import figure_leak_rate, figure_pressure_difference
from sealeak.render.lab_figures import figure_fit
from sealeak.render.plotstyle import color
from tests.casefiles import BASE
from tests.integration.test_cli_gas import gas_case

#: 1 mbar·l/s in Pa·m³/s, by hand: 100 Pa × 10⁻³ m³/s.
PA_M3_PER_MBAR_L = 100.0 * 1e-3


def _uniform_text(model="both"):
    text = gas_case("nitrogen", "3 bar", "1 bar")
    text = text.replace('squeeze_pressure = ["0.3 MPa", "0.5 MPa"]',
                        'squeeze_pressure = ["0.4 MPa", "0.5 MPa", "0.6 MPa"]\nhelium_equivalent = true')
    return text.replace("alpha = 0.2", f'alpha = 0.2\nmodel = "{model}"')


def _band_text():
    text = Path(example_path("helium-test")).read_text()
    text = re.sub(r"(?m)^compression = .*$", 'compression = ["10 %", "15 %"]\nhelium_equivalent = true', text)
    return re.sub(r'(?m)^name = "helium" ', 'name = "nitrogen" ', text)


def _run(tmp_path, text, name="case.toml"):
    path = tmp_path / name
    path.write_text(text)
    return [run_case(c) for c in read_case_file(path).cases]


@pytest.fixture(scope="module")
def uniform(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("gas"), _uniform_text())


@pytest.fixture(scope="module")
def band(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("gasband"), _band_text())


def _data_lines(ax):
    """The curves drawn in data coordinates (not the legend's empty handles or the hollow markers)."""
    return [ln for ln in ax.get_lines() if len(ln.get_xdata()) and ln.get_linestyle() in ("-", "--")]


def _curve(ax, colour, style):
    found = [ln for ln in _data_lines(ax) if ln.get_color() == colour and ln.get_linestyle() == style]
    assert len(found) == 1, f"one {style} curve in {colour}"
    return np.asarray(found[0].get_ydata(), dtype=float)


def _same_where_drawn(drawn, expected, valid):
    expected = np.asarray(expected, dtype=float)
    assert np.isfinite(drawn[valid]).all()
    np.testing.assert_allclose(drawn[valid], expected[valid], rtol=1e-12)
    assert not np.isfinite(drawn[~valid]).any()


def _secondary(ax):
    secs = [c for c in ax.child_axes if c.get_ylabel()]
    assert len(secs) == 1
    return secs[0]


def _records(result, key):
    return np.array([np.nan if r[key] is None else r[key] for r in result.records()], dtype=float)


# ------------------------------------------------------------------------------------ uniform seal
def test_the_gas_case_has_what_the_figure_must_show(uniform):
    (r,) = uniform
    assert r.case.gas is not None and r.effective_medium is not None
    assert r.valid.sum() >= 2 and np.isfinite(_records(r, "leak_rate_helium_mbar_l_s")).sum() >= 2
    # the helium equivalent is a different number from the nitrogen leak: a dashed curve of its own
    assert not np.allclose(_records(r, "leak_rate_mbar_l_s"), _records(r, "leak_rate_helium_mbar_l_s"), equal_nan=True)


def test_gas_leak_rate_figure_draws_the_records_mbar_l_s_of_both_theories_and_helium_dashed(uniform):
    (r,) = uniform
    ax = figure_leak_rate(uniform, log=True).axes[0]
    assert "mbar·l/s" in ax.get_ylabel() and "m³/s" not in ax.get_ylabel().replace("Pa·m³/s", "")
    assert ax.get_yscale() == "log"
    valid_cj = np.asarray(r.valid, dtype=bool) & np.isfinite(_records(r, "leak_rate_mbar_l_s"))
    valid_em = np.asarray(r.valid_effective_medium, dtype=bool) & np.isfinite(_records(r, "leak_rate_mbar_l_s_effective_medium"))
    _same_where_drawn(_curve(ax, color(0), "-"), _records(r, "leak_rate_mbar_l_s"), valid_cj)
    _same_where_drawn(_curve(ax, color(0), "--"), _records(r, "leak_rate_helium_mbar_l_s"), valid_cj)
    _same_where_drawn(_curve(ax, color(1), "-"), _records(r, "leak_rate_mbar_l_s_effective_medium"), valid_em)
    _same_where_drawn(_curve(ax, color(1), "--"), _records(r, "leak_rate_helium_mbar_l_s_effective_medium"), valid_em)
    # not the incompressible K ΔP in m³/s
    k_dp = np.asarray(r.critical_junction.leak_rate, dtype=float)
    assert not np.allclose(_curve(ax, color(0), "-")[valid_cj], k_dp[valid_cj])


@pytest.mark.parametrize("log", [True, False])
def test_gas_leak_rate_axes_read_mbar_l_s_and_pa_m3_s_and_the_title_names_the_conditions(uniform, log):
    ax = figure_leak_rate(uniform, log=log).axes[0]
    title = ax.get_title()
    for text in ("nitrogen", "T = 20 °C", "P_a = 3 bar", "P_b = 1 bar", "helium equivalent", "Kn"):
        assert text in title
    sec = _secondary(ax)
    assert "Pa·m³/s" in sec.get_ylabel()
    assert re.search(r"mbar·l/s\)$", ax.get_ylabel())
    # the second axis converts the left axis's unit (with the power of ten of a linear axis) by 1 mbar·l/s = 0.1 Pa·m³/s
    power = re.search(r"\(10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+) mbar", ax.get_ylabel())
    left = 10.0 ** int(power.group(1).translate(str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789"))) if power else 1.0
    right = re.search(r"\(10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+) Pa", sec.get_ylabel())
    right_scale = 10.0 ** int(right.group(1).translate(str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789"))) if right else 1.0
    y = 0.5 * sum(ax.get_ylim())
    forward = sec._functions[0]
    assert forward(y) * right_scale == pytest.approx(y * left * PA_M3_PER_MBAR_L, rel=1e-12)


def _dp_curves(results):
    curves = prediction_curves(results)
    (sw,) = curves.pressure_difference
    ax = figure_pressure_difference(curves).axes[0]
    return sw, ax


def test_pressure_difference_figure_of_a_gas_draws_q_pv_through_the_records_point(uniform):
    (r,) = uniform
    sw, ax = _dp_curves(uniform)
    assert sw.gas and "mbar·l/s" in ax.get_ylabel() and "Pa·m³/s" in _secondary(ax).get_ylabel()
    assert "nitrogen" in ax.get_title() and "not linear in ΔP" in ax.get_title()
    row = int(np.flatnonzero(r.critical_junction.squeeze_pressure == sw.squeeze_pressure)[0])
    dp_case = 2e5  # P_a - P_b = 3 bar - 1 bar
    at = int(np.flatnonzero(np.isclose(sw.pressure_difference, dp_case))[0])
    # the sweep at the case's own ΔP is the record's leak rate (Pa·m³/s; 1 mbar·l/s = 0.1 Pa·m³/s by hand)
    assert sw.critical_junction[at] == pytest.approx(_records(r, "leak_rate_pv")[row], rel=1e-9)
    assert sw.effective_medium[at] == pytest.approx(_records(r, "leak_rate_pv_effective_medium")[row], rel=1e-9)
    assert sw.critical_junction[0] == 0.0
    drawn = _curve(ax, color(0), "-")  # in mbar·l/s; the point at ΔP = 0 is not drawn on log axes
    np.testing.assert_allclose(drawn[1:] * PA_M3_PER_MBAR_L, sw.critical_junction[1:], rtol=1e-12)
    # rarefaction: Kn falls as P_a rises, so Q_pV / Q_pV(no slip) = mean f along the drop falls along the sweep
    no_slip = ((1e5 + sw.pressure_difference[1:]) ** 2 - 1e5 ** 2) / 2
    ratio = sw.critical_junction[1:] / no_slip
    assert np.all(np.diff(ratio) < 0)


@pytest.mark.parametrize("fluid_pressure", ["coupled", "ignored"])
def test_gas_sweep_passes_through_the_records_leak_with_the_fluid_pressure_coupled_or_not(tmp_path, fluid_pressure):
    text = _uniform_text().replace('fluid_pressure = "ignored"', f'fluid_pressure = "{fluid_pressure}"')
    results = _run(tmp_path, text)
    (r,) = results
    sw, ax = _dp_curves(results)
    assert ("§13.5" in ax.get_title()) == (fluid_pressure == "coupled") != ("K ∫ p f(Kn) dp" in ax.get_title())
    row = int(np.flatnonzero(r.critical_junction.squeeze_pressure == sw.squeeze_pressure)[0])
    at = int(np.flatnonzero(np.isclose(sw.pressure_difference, 2e5))[0])  # the case's ΔP: 3 bar - 1 bar
    # the curve at the case's pressures is predict's leak of that row, each theory (exact coupling or not, §13.5)
    assert sw.critical_junction[at] == pytest.approx(_records(r, "leak_rate_pv")[row], rel=1e-9)
    assert sw.effective_medium[at] == pytest.approx(_records(r, "leak_rate_pv_effective_medium")[row], rel=1e-9)
    assert sw.critical_junction[0] == 0.0 and np.all(np.diff(sw.critical_junction) > 0)
    # K ∫ p f dp at each P_a (K and h of the row) only without the coupling; coupled, the gas pressure opens the contact
    # further as P_a rises, so the sweep grows faster than that
    rows = r.gas["critical_junction"]
    approx = gas_throughput(r.case, np.full(sw.pressure_difference.size, rows.conductance[row]),
                            np.full(sw.pressure_difference.size, rows.gap[row]), sw.pressure_difference,
                            np.full(sw.pressure_difference.size, rows.length[row]))
    if fluid_pressure == "ignored":
        np.testing.assert_allclose(sw.critical_junction, approx, rtol=1e-12)
    else:
        assert np.all(np.diff(sw.critical_junction[1:] / approx[1:]) > 0)


def test_pressure_difference_figure_no_slip_is_k_times_half_the_difference_of_squares(tmp_path):
    text = _uniform_text().replace("alpha = 0.2", 'alpha = 0.2\nrarefaction = "no-slip"')
    results = _run(tmp_path, text)
    (r,) = results
    sw, _ax = _dp_curves(results)
    row = int(np.flatnonzero(r.critical_junction.squeeze_pressure == sw.squeeze_pressure)[0])
    pb = 1e5
    for curve, rows in ((sw.critical_junction, r.gas["critical_junction"]), (sw.effective_medium, r.gas["effective_medium"])):
        k = rows.conductance[row]  # K = Q/ΔP of the liquid-like conductance, m³/(Pa·s)
        np.testing.assert_allclose(curve, k * ((pb + sw.pressure_difference) ** 2 - pb ** 2) / 2, rtol=1e-9, atol=0)


# ------------------------------------------------------------------------------------ band seal
def test_band_gas_figure_draws_the_records_mbar_l_s_and_the_helium_equivalent(band):
    (r,) = band
    assert r.band is not None and r.case.gas is not None
    ax = figure_band_leak_rate(band).axes[0]
    assert ax.get_ylabel().endswith("(mbar·l/s)") and "Pa·m³/s" in _secondary(ax).get_ylabel()
    for text in ("nitrogen", "P_a = 1 bar", "P_b = 0 (vacuum)", "helium equivalent"):
        assert text in ax.get_title()
    q = _records(r, "leak_rate_mbar_l_s")
    valid = np.asarray(r.valid, dtype=bool) & np.isfinite(q)
    assert valid.any()
    _same_where_drawn(_curve(ax, color(0), "-"), q, valid)
    _same_where_drawn(_curve(ax, color(0), "--"), _records(r, "leak_rate_helium_mbar_l_s"), valid)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert not any("uniform seal" in t for t in labels)  # the liquid figure's K ΔP twins are not drawn for a gas
    # the Knudsen numbers and their regime on one line, not "..., mean pressure: 46 to 2.1e+03" read as a pressure
    (kn,) = [line for line in ax.get_title().splitlines() if "Kn" in line]
    assert re.match(r"Kn = λ/h = [0-9.e+-]+( to [0-9.e+-]+)? \(", kn), kn
    assert "h = u_c at the peak contact pressure" in ax.get_title().replace("\n", " ")


# ------------------------------------------------------------------------------------ liquids unchanged
def test_liquid_leak_rate_figure_keeps_m3_s_and_ml_min(tmp_path):
    results = _run(tmp_path, BASE)
    assert results[0].case.gas is None
    ax = figure_leak_rate(results, log=True).axes[0]
    assert ax.get_ylabel() == "leak rate Q (m³/s)"
    assert _secondary(ax).get_ylabel() == "leak rate Q (ml/min)"
    assert "Leak rate against squeeze pressure" in ax.get_title()
    r = results[0]
    q = np.asarray(r.critical_junction.leak_rate, dtype=float)
    valid = np.asarray(r.valid, dtype=bool) & np.isfinite(q) & (q > 0)
    _same_where_drawn(_curve(ax, color(0), "-"), q, valid)


# ------------------------------------------------------------------------------------ fit of a gas case
def test_fit_of_a_gas_case_names_pa_m3_s_in_text_json_and_figure(tmp_path, capsys):
    text = _uniform_text("critical-junction")
    case = tmp_path / "case.toml"
    case.write_text(text)
    (r,) = _run(tmp_path, text, "run.toml")
    rows = [rec for rec in r.records() if rec["percolates"]]
    data = tmp_path / "measured.csv"
    # measured in mbar·l/s at α = 0.1, i.e. half of the case's α = 0.2
    data.write_text("squeeze_pressure (kPa), leak_rate (mbar*l/s)\n"
                    + "".join(f"{float(rec['squeeze_pressure']) / 1e3!r}, {float(rec['leak_rate_mbar_l_s']) * 0.5!r}\n" for rec in rows))
    out = tmp_path / "fit.json"
    plots = tmp_path / "plots"
    assert main(["fit", str(case), "--data", str(data), "--json", str(out), "--plots", str(plots), "--force"]) == 0
    printed = capsys.readouterr().out
    assert "Pa·m³/s" in printed and "mbar·l/s" in printed
    assert "m³/s" not in printed.replace("Pa·m³/s", "") and "ml/min" not in printed
    assert "converted to volume flows" not in printed
    doc = json.loads(out.read_text())
    assert doc["leak_rate_unit"] == "Pa*m^3/s"
    assert doc["critical_junction"]["alpha"] == pytest.approx(0.1, rel=1e-9)
    for rec, row in zip(rows, doc["rows"]):
        assert row["measured_mbar_l_s"] == pytest.approx(rec["leak_rate_mbar_l_s"] * 0.5, rel=1e-12, abs=0)
        assert row["measured"] == pytest.approx(row["measured_mbar_l_s"] * PA_M3_PER_MBAR_L, rel=1e-12, abs=0)
        assert row["fitted_critical_junction"] == pytest.approx(row["measured"], rel=1e-9, abs=0)
    assert all(doc["units"][k] for k in doc["rows"][0] if k != "squeeze_pressure")
    assert (plots / "fit.png").read_bytes().startswith(b"\x89PNG")


def test_fit_figure_of_a_gas_case_reads_pa_m3_s_and_mbar_l_s(tmp_path):

    text = _uniform_text("critical-junction")
    (r,) = _run(tmp_path, text)
    rows = [rec for rec in r.records() if rec["percolates"]]
    data = tmp_path / "measured.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (Pa*m^3/s)\n"
                    + "".join(f"{float(rec['squeeze_pressure']) / 1e3!r}, {float(rec['leak_rate_pv'])!r}\n" for rec in rows))
    fit = run_fit(r.case, read_leak_data(data))
    ax = figure_fit(fit).axes[0]
    assert ax.get_ylabel() == "pV throughput Q_pV (Pa·m³/s)"
    sec = _secondary(ax)
    assert "mbar·l/s" in sec.get_ylabel()
    assert sec._functions[0](1.0) == pytest.approx(1.0 / PA_M3_PER_MBAR_L, rel=1e-12)
    measured = [ln for ln in ax.get_lines() if ln.get_marker() == "s"][0]
    np.testing.assert_allclose(measured.get_ydata(), [rec["leak_rate_pv"] for rec in rows], rtol=1e-12)
    assert "nitrogen" in ax.get_title()


def test_band_gas_figure_draws_the_specification_in_mbar_l_s(band):
    """volume_limit gives a gas's limit as a pV throughput in Pa·m³/s; the figure's axis is mbar·l/s (1 mbar·l/s =
    0.1 Pa·m³/s), so 1e-7 Pa·m³/s is drawn at 1e-6."""
    (r,) = band
    q = _records(r, "leak_rate_mbar_l_s")
    at = float(np.nanmedian(q[np.isfinite(q) & (q > 0)]))  # within the axis
    ax = figure_band_leak_rate(band, limit=(at * 0.1, f"{at:g} mbar*l/s")).axes[0]  # (1 mbar·l/s = 0.1 Pa·m³/s)
    (line,) = [ln for ln in ax.get_lines() if ln.get_label().startswith("max_leak_rate = ")]
    assert line.get_ydata()[0] == pytest.approx(at, rel=1e-12, abs=0)
