"""Fitting α, leak-test units, the virtual rig, the HTML report and bad data files (docs/theory.md § 4)."""

import json
import warnings
from dataclasses import replace
from html.parser import HTMLParser

import numpy as np
import pytest

from sealeak import FileFormatError
from sealeak.cases import example_path, fit_models, load_cases, predict, rig_prediction
from sealeak.cli import main
from sealeak.lab.data import read_leak_data
from sealeak.lab.rig import exponential_height


def test_fit_through_data_file_and_cli(case, sweep, tmp_path):
    p0, cj, em = sweep
    rng = np.random.default_rng(3)
    q = 0.35 * cj * np.exp(0.2 * rng.standard_normal(cj.size))
    data = tmp_path / "measured.csv"
    rows = "\n".join(f"{p / 1e3:.10g}, {x * 6e7:.10g}" for p, x in zip(p0, q))
    data.write_text("# synthetic\nsqueeze_pressure (kPa), leak_rate (ml/min)\n" + rows + "\n")
    d = read_leak_data(data)
    assert np.allclose(d.leak_rate, q, rtol=1e-9) and np.isnan(d.pressure_difference).all()
    fits = fit_models(case, d.squeeze_pressure, d.pressure_difference, d.leak_rate)
    assert abs(fits["critical_junction"].alpha - 0.35) < 3 * fits["critical_junction"].alpha_std
    out = tmp_path / "fit.json"
    figs = tmp_path / "figs"
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--json", str(out),
                 "--plots", str(figs), "-q"]) == 0
    doc = json.loads(out.read_text())
    for name in ("critical_junction", "effective_medium"):
        assert set(doc[name]) >= {"alpha", "alpha_std", "rms_log10_residual"}
    assert doc["critical_junction"]["alpha"] == pytest.approx(fits["critical_junction"].alpha, rel=1e-9)
    # the effective-medium factor: the data are 0.35 × CJ(α=1), so it is 0.35 × CJ/EM on average
    assert doc["effective_medium"]["alpha"] == pytest.approx(fits["effective_medium"].alpha, rel=1e-9)
    assert (figs / "fit.png").read_bytes()[:4] == b"\x89PNG"


def test_a_liquid_weighed_is_fitted_as_its_volume_flow(case, sweep, tmp_path, capsys):
    """Leak rates in g/h of a liquid: the fit takes ṁ/ρ, with fluid.density (1000 kg/m³ in the example), or the
    property library's density of the named liquid when the case gives none; a liquid without either is refused,
    naming the column and what to give."""
    p0, cj, _ = sweep
    q = 0.35 * cj  # m³/s
    for name, rows in (("ml.csv", "leak_rate (ml/min)\n" + "\n".join(f"{p / 1e3:.10g}, {x * 6e7:.10g}" for p, x in zip(p0, q))),
                       ("g.csv", "leak_rate (g/h)\n" + "\n".join(f"{p / 1e3:.10g}, {x * 1e3 * 3.6e6:.10g}" for p, x in zip(p0, q)))):
        (tmp_path / name).write_text("squeeze_pressure (kPa), " + rows + "\n")
    text = example_path("reference-experiment").read_text()
    (tmp_path / "given.toml").write_text(text)
    # (the rig's water column keeps its own density)
    no_density = text.replace('density = "1000 kg/m^3"\n', "").replace("[rig]\n", '[rig]\ndensity = "1000 kg/m^3"\n')
    (tmp_path / "library.toml").write_text(no_density)
    (tmp_path / "unnamed.toml").write_text(no_density.replace('name = "water"\n', ""))
    alpha = {}
    for case_file, data in (("given", "ml"), ("given", "g"), ("library", "g")):
        out = tmp_path / f"{case_file}-{data}.json"
        assert main(["fit", str(tmp_path / f"{case_file}.toml"), "--data", str(tmp_path / f"{data}.csv"),
                     "--json", str(out)]) == 0
        printed = capsys.readouterr().out
        assert ("are mass flows: fitted as the volume flows ṁ/ρ" in printed) == (data == "g")
        alpha[case_file, data] = json.loads(out.read_text())["critical_junction"]["alpha"]
    assert alpha["given", "g"] == pytest.approx(alpha["given", "ml"], rel=1e-9)
    # water at 20 °C: 998.2 kg/m³, so the same grams are 0.18 % more volume than at 1000 kg/m³
    assert alpha["library", "g"] == pytest.approx(alpha["given", "ml"] * 1000 / 998.2, rel=1e-4)
    assert main(["fit", str(tmp_path / "unnamed.toml"), "--data", str(tmp_path / "g.csv")]) == 2
    err = capsys.readouterr().err
    assert "column 'leak_rate (g/h)'" in err and "give fluid.density" in err and len(err.strip().splitlines()) == 1


def test_non_percolating_points_are_excluded_with_a_message(case, tmp_path, capsys):
    data = tmp_path / "m.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min), pressure_difference (kPa)\n"
                    "30, 200, 10\n60, 70, 10\n100, 20, 5\n1e6, 0.01, 10\n")
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data)]) == 0
    out = capsys.readouterr().out
    assert "line 5" in out and "excluded" in out and "does not percolate" in out  # data row 4, after the header
    fits = fit_models(case, [3e4, 6e4, 1e5, 1e9], [1e4, 1e4, 5e3, np.nan], [1, 1, 1, 1])
    assert fits["critical_junction"].n_used == 3
    assert [i for i, _ in fits["critical_junction"].excluded] == [3]


def test_linearity_cli(tmp_path, capsys):
    data = tmp_path / "dp.csv"
    dp = np.array([2, 4, 6, 8, 10.0])
    data.write_text("pressure_difference (kPa), leak_rate (ml/min)\n" + "\n".join(f"{a}, {7.2 * a + 0.01 * (-1) ** i}"
                                                                                   for i, a in enumerate(dp)) + "\n")
    out = tmp_path / "lin.json"
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--linearity",
                 "--json", str(out), "--plots", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "slope" in text and "intercept" in text and "[rig] load" in text
    doc = json.loads(out.read_text())["linearity"]
    assert doc["slope"] == pytest.approx(7.2e-6 / 60 / 1e3, rel=1e-3, abs=0)
    assert abs(doc["intercept"]) < 3 * doc["intercept_std"]
    assert doc["alpha_from_slope"] > 0 and (tmp_path / "linearity.png").exists()
    # the implied α is the critical junction's, on a line of its own (it stood under the effective medium's model line)
    (line,) = [ln for ln in text.splitlines() if "implied by the measured slope" in ln]
    assert line.startswith(f"alpha      {doc['alpha_from_slope']:.3g}: the critical junction's α"), line
    # in the linearity test ΔP is the abscissa: an empty cell is an error, not "the case's ΔP"
    gap = tmp_path / "gap.csv"
    gap.write_text("pressure_difference (kPa), leak_rate (ml/min)\n2, 14\n, 29\n6, 43\n")
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(gap), "--linearity"]) == 2
    assert "line 3, column 'pressure_difference': is empty" in capsys.readouterr().err


def test_linearity_of_a_liquid_weighed_reads_its_volume_flow(tmp_path, capsys):
    """A linearity file of mass flows (g/h) was refused as 'NaN or inf' though every cell was finite; as fit does, the
    leak is read as ṁ/ρ with the case's density (the reference case: 1000 kg/m³)."""
    data = tmp_path / "lin.csv"
    data.write_text("pressure_difference (kPa), leak_rate (g/h)\n2, 10\n5, 25\n10, 50\n")
    out = tmp_path / "lin.json"
    assert main(["fit", "--example", "reference-experiment", "--linearity", "--data", str(data), "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["linearity"]["slope"] == pytest.approx(10e-3 / 3600 / 1000 / 2e3, rel=1e-9, abs=0)  # (kg/s)/(kg/m³)/Pa
    assert any("mass flows" in m for m in doc["messages"])
    capsys.readouterr()


@pytest.mark.parametrize("option, problem", [
    ("100 kPa", "differs from the data file's squeeze_pressure column (60000 Pa)"),  # it replaced 60 kPa without a word
    ("0.0001 Pa", "must be at least 1 mPa"),  # the case file's floor
])
def test_linearity_squeeze_pressure_option_is_checked(tmp_path, capsys, option, problem):
    data = tmp_path / "lin.csv"
    data.write_text("squeeze_pressure (kPa), pressure_difference (kPa), leak_rate (ml/min)\n60, 2, 1\n60, 5, 2.5\n60, 10, 5\n")
    args = ["fit", "--example", "reference-experiment", "--linearity", "--data", str(data), "--squeeze-pressure"]
    assert main([*args, option]) == 2
    assert problem in capsys.readouterr().err
    assert main([*args, "60 kPa"]) == 0  # the same value as the file's
    assert "P0         60 kPa (from --squeeze-pressure)" in capsys.readouterr().out


def test_at_pressure_option(tmp_path, case):
    data = tmp_path / "m.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (mbar*l/s)\n30, 0.5\n60, 0.1\n")
    a = read_leak_data(data)
    b = read_leak_data(data, reference_pressure=2 * 101325)
    assert a.leak_rate[0] == pytest.approx(0.5 * 0.1 / 101325, rel=1e-14, abs=0)
    assert np.allclose(b.leak_rate, a.leak_rate / 2, rtol=1e-14)
    out1, out2 = tmp_path / "a.json", tmp_path / "b.json"
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--json", str(out1), "-q"]) == 0
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--json", str(out2), "-q",
                 "--at-pressure", "2 atm"]) == 0
    a1 = json.loads(out1.read_text())["critical_junction"]["alpha"]
    a2 = json.loads(out2.read_text())["critical_junction"]["alpha"]
    assert a2 == pytest.approx(a1 / 2, rel=1e-12, abs=0)
    assert a.throughput and not read_leak_data_volume(tmp_path).throughput


def read_leak_data_volume(tmp_path):
    data = tmp_path / "v.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 0.5\n")
    return read_leak_data(data)


def test_fit_output_states_the_conversion_pressure_and_large_pressure_differences(tmp_path, capsys):
    data = tmp_path / "m.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (mbar*l/s), pressure_difference (kPa)\n30, 0.5, 10\n"
                    "60, 0.1, 40\n")
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--at-pressure", "2 atm"]) == 0
    out = capsys.readouterr().out
    assert "converted to volume flows at 202.65 kPa" in out
    assert "line 3: ΔP = 40000 Pa is not small against P0 = 60000 Pa" in out


def test_rig_cli(tmp_path, capsys):
    readings = tmp_path / "readings.csv"
    case = load_cases(example_path("reference-experiment"))[0]
    pred = rig_prediction(case)
    k = next(iter(pred.conductance.values()))
    t = np.linspace(0, 10, 11)  # minutes
    h = exponential_height(case.rig, 1.3 * k, t * 60) * 100  # cm
    readings.write_text("time (min), height (cm)\n" + "\n".join(f"{a:.6g}, {b:.10g}" for a, b in zip(t, h)) + "\n")
    out = tmp_path / "rig.json"
    assert main(["rig", "--example", "reference-experiment", "--readings", str(readings), "--json", str(out),
                 "--plots", str(tmp_path / "f")]) == 0
    text = capsys.readouterr().out
    assert "P0 = 60.65 kPa" in text and "α implied by the readings: 0.26" in text
    doc = json.loads(out.read_text())
    assert doc["readings"]["conductance"] == pytest.approx(1.3 * k, rel=1e-6, abs=0)
    assert (tmp_path / "f" / "rig.png").exists() and (tmp_path / "f" / "readings.png").exists()


# ---------------------------------------------------------------------- report
class _Checker(HTMLParser):
    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.imgs, self.ids, self.links = [], [], [], [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.imgs.append(a.get("src", ""))
        if tag in ("link", "script") and (a.get("href") or a.get("src")):
            self.links.append(a.get("href") or a.get("src"))
        if "id" in a:
            self.ids.append(a["id"])
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"unbalanced </{tag}> (open: {self.stack[-3:]})")
        else:
            self.stack.pop()


def test_report_is_valid_self_contained_html(tmp_path):
    from sealeak.render import PREDICTION_FIGURE_NAMES

    text = example_path("reference-experiment").read_text().replace("[theory]", '[theory]\nmodel = "both"')
    cf = tmp_path / "both.toml"
    cf.write_text(text)
    out = tmp_path / "r.html"
    assert main(["report", str(cf), "-o", str(out), "-q"]) == 0
    html = out.read_text()
    p = _Checker()
    p.feed(html)
    p.close()
    assert not p.errors and p.stack == []
    assert html.startswith("<!DOCTYPE html>")
    for name in PREDICTION_FIGURE_NAMES + ("rig.png",):
        assert f"fig-{name}" in p.ids
    assert all(src.startswith("data:image/png;base64,") for src in p.imgs)
    assert len(p.imgs) == len(PREDICTION_FIGURE_NAMES) + 1
    assert not p.links and "http://" not in html and "https://" not in html
    # the input table with units as written, and the assumptions
    for s in ("[surface] h_rms", "44 um", "[rubber] youngs_modulus", "2.3 MPa", "[rig] load", "3.4 kg"):
        assert s in html
    for s in ("p_c = 0.6", "γ = 1", "α = 0.2", "model (not a measurement)", "Q effective medium"):
        assert s in html
    assert main(["report", str(cf), "-o", str(out), "-q"]) == 2  # no overwrite without --force


# ---------------------------------------------------------------------- bad data files
@pytest.mark.parametrize("content, problem", [
    ("squeeze_pressure (kPa), pressure_difference (kPa)\n30, 10\n60, 10\n", "missing column leak_rate"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60, abc\n", "'abc' is not a number"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60, -2\n", "negative"),
    ("squeeze_pressure (kPa), leak_rate (furlong/fortnight)\n30, 1.0\n60, 2\n", "leak_rate"),
    ("squeeze_pressure (kPa), leak_rate (bogusunit)\n30, 1.0\n60, 2\n", "unknown unit"),
    ("squeeze_pressure, leak_rate (ml/min)\n30, 1.0\n60, 2\n", "has no unit"),
    ("30, 1.0\n60, 2\n", "first row must name every column"),
    ("squeeze_pressure (kg), leak_rate (ml/min)\n30, 1.0\n60, 2\n", "not a pressure"),
    ("temperature (K), leak_rate (ml/min)\n30, 1.0\n", "'temperature' is not one of the columns"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, nan\n", "not a finite number"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60,\n", "line 3, column 'leak_rate': is empty"),
    ("squeeze_pressure (kPa), leak_rate (ml/min), pressure_difference (kPa)\n30, 1.0, 10\n60, 2.0, 0\n",
     "line 3: a leak rate of 2 ml/min at zero pressure difference"),
    ("", "no numeric rows"),
    ("squeeze_pressure (kPa); leak_rate (ml/min)\n30; 1,5\n60; 2,5\n", "use a decimal point"),
    # found by fuzzing: a traceback, and an overflow warning before a line naming a case-file key
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n1e-320, 2\n", "line 3: squeeze_pressure = "),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n1e308, 2\n",
     "line 3: squeeze_pressure = 1e+308 kPa: beyond 1e+100 Pa in SI units"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n1e-9, 2\n", "line 3: squeeze pressure 1e-09 kPa: at least 0.001 Pa"),
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60, 1e308\n", "line 3: leak_rate = 1e+308 ml/min: beyond"),
    # a cell of 100 000 digits was repeated whole in a 100 kB error line
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60, " + "1" * 100_000 + "\n",
     "line 3: the number 111111111111111111...111111111111111111 is too large"),
    # a cell whose SI value underflows to 0 was read as a zero leak (excluded without a word)
    ("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1.0\n60, 1e-320\n", "line 3: leak_rate = 9.99989e-321 ml/min: below 1e-100"),
])
def test_bad_data_files_through_the_cli(tmp_path, capsys, content, problem):
    data = tmp_path / "bad.csv"
    data.write_text(content)
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: ") and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert str(data) in err and problem in err


def test_bad_readings_and_missing_files(tmp_path, capsys):
    bad = tmp_path / "r.csv"
    bad.write_text("time (min), height (cm)\n0, 100\n0, 90\n")
    assert main(["rig", "--example", "reference-experiment", "--readings", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "times must increase" in err
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(tmp_path / "none.csv")]) == 2
    assert "file not found" in capsys.readouterr().err
    assert main(["rig", "--example", "hrms-study"]) == 2
    assert "study" in capsys.readouterr().err
    with pytest.raises(FileFormatError):
        read_leak_data(tmp_path / "none.csv")


@pytest.mark.parametrize("example, header, rows", [
    ("reference-experiment", "time (min), height (cm)", "0, 100\n1e-300, 82\n2e-300, 67\n"),
    ("pressure-decay", "time (min), pressure (mbar)", "0, 2000\n1e-300, 1999\n2e-300, 1998\n"),
])
def test_readings_of_times_below_the_si_range_are_refused_naming_the_cell(tmp_path, capsys, example, header, rows):
    """Times of 1e-300 min left no time between readings: a ZeroDivisionError traceback (pressure decay), or warnings
    on stderr and K = inf ± nan with exit 0 (water column). A reading holds the case file's SI range."""
    readings = tmp_path / "r.csv"
    readings.write_text(header + "\n" + rows)
    assert main(["rig", "--example", example, "--readings", str(readings)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 3: time = 1e-300 min: below 1e-100 s in SI units" in err


def test_a_rig_whose_column_would_empty_in_no_time_is_refused(tmp_path, capsys):
    """A cylinder of 1e-90 m: the Radau solver overflowed into a traceback, warnings first."""
    case = tmp_path / "c.toml"
    case.write_text(example_path("reference-experiment").read_text().replace('cylinder_diameter = "3 cm"',
                                                                             'cylinder_diameter = "1e-90 m"'))
    assert main(["rig", str(case)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the column would empty within 1e-06 s" in err and "rig.cylinder_diameter" in err


def test_rows_with_an_empty_pressure_difference_use_the_case_value_through_the_cli(case, tmp_path):
    data = tmp_path / "m.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min), pressure_difference (kPa)\n"
                    "30, 100, 20\n60, 30,\n")
    d = read_leak_data(data)
    assert d.pressure_difference[0] == pytest.approx(2e4) and np.isnan(d.pressure_difference[1])
    out = tmp_path / "fit.json"
    assert main(["fit", str(example_path("reference-experiment")), "--data", str(data), "--json", str(out), "-q"]) == 0
    # closed form: α = geometric mean of Q_measured / Q_model(α = 1), ΔP = 20 kPa and the case's 10 kPa
    q_model = [predict(replace(case, alpha=1.0), squeeze_pressure=np.array([p]), pressure_difference=dp).leak_rate[0]
               for p, dp in ((3e4, 2e4), (6e4, case.pressure_difference))]
    q_meas = np.array([100, 30]) * 1e-6 / 60
    expected = float(np.exp(np.mean(np.log(q_meas / np.array(q_model)))))
    assert json.loads(out.read_text())["critical_junction"]["alpha"] == pytest.approx(expected, rel=1e-12, abs=0)


def test_readings_of_a_rising_level_are_refused(case, tmp_path, capsys):
    bad = tmp_path / "r.csv"
    bad.write_text("time (min), height (cm)\n0, 90\n5, 95\n10, 100\n")
    assert main(["rig", "--example", "reference-experiment", "--readings", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "does not fall" in err


def test_the_rig_says_the_ode_agrees_only_where_it_does(tmp_path, capsys):
    """"the ODE solution agrees" was printed whatever the numbers: at H0 = 1e20 m the ODE's time to the final height
    was 28 058 s against the closed form's 24 498 s."""
    assert main(["rig", "--example", "reference-experiment"]) == 0
    assert "the ODE solution agrees" in capsys.readouterr().out
    case = tmp_path / "h.toml"
    text = example_path("reference-experiment").read_text()
    case.write_text(text.replace('initial_height = "1 m"', 'initial_height = "1e20 m"'))
    assert 'initial_height = "1e20 m"' in case.read_text()
    assert main(["rig", str(case)]) == 0
    out = capsys.readouterr().out
    assert "the ODE solution agrees" not in out and "the ODE solution's time differs from it by" in out


def test_a_fitted_alpha_no_case_file_would_take_is_flagged(tmp_path, capsys):
    """Leak rates of 1e-99 m³/s fitted α = 5e-95 without a word: computed, and flagged."""
    data = tmp_path / "far.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (m^3/s)\n20, 1e-99\n40, 1e-99\n")
    assert main(["fit", "--example", "reference-experiment", "--data", str(data)]) == 0
    out = capsys.readouterr().out
    for theory in ("critical junction", "effective medium"):
        assert f"note: {theory}: the fitted α = " in out and "lies outside 0.01 to 100" in out
    assert main(["fit", "--example", "reference-experiment", "--data", str(example_path("reference-experiment").parent / "reference-measured.csv")]) == 0
    assert "fit_alpha_far" not in capsys.readouterr().out  # the paper's data: α of order one
    # leak rates ~10⁴ times the paper's: α ~ 10³, which a case file takes but predict warns about; fit said nothing
    measured = [line for line in (example_path("reference-experiment").parent / "reference-measured.csv").read_text()
                .splitlines() if line.strip() and not line.startswith("#")]
    header, rows = measured[0], [line.split(",") for line in measured[1:]]
    data.write_text(header + "\n" + "\n".join(f"{p}, {float(q) * 1e4:.6g}" for p, q, *_ in rows) + "\n")
    assert main(["fit", "--example", "reference-experiment", "--data", str(data)]) == 0
    out = capsys.readouterr().out
    assert "lies outside 0.01 to 100" in out and "(fit_alpha_far)" in out


def test_a_rig_load_too_small_to_press_the_seal_is_named(tmp_path, capsys):
    """rig.load = "1e-90 kg" was reported as conditions.squeeze_pressure = 1.78374e-86, a key the user never wrote."""
    case = tmp_path / "l.toml"
    case.write_text(example_path("reference-experiment").read_text().replace('load = "3.4 kg"', 'load = "1e-90 kg"'))
    assert main(["rig", str(case)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: rig.load = '1e-90 kg': gives a squeeze pressure of 1.78e-86 Pa")


def test_a_figure_whose_labels_cannot_fit_warns_nobody(tmp_path, capsys):
    """initial_height = "1e90 m" gives 100-digit tick labels: matplotlib's "constrained_layout not applied" warning
    reached the user's stderr beside the command's own lines."""
    case = tmp_path / "h.toml"
    case.write_text(example_path("reference-experiment").read_text().replace('initial_height = "1 m"', 'initial_height = "1e90 m"'))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["rig", str(case), "--plots", str(tmp_path / "plots")]) == 0
    assert not [w for w in caught if "constrained_layout" in str(w.message)]
    assert "Warning" not in capsys.readouterr().err and (tmp_path / "plots" / "rig.png").is_file()


def test_linearity_notes_a_pressure_difference_not_small_against_p0(tmp_path, capsys):
    """``fit`` says where ΔP is not small against P0; ``fit --linearity`` said nothing (ΔP up to 10 kPa at P0 = 1 kPa)."""
    data = tmp_path / "lin.csv"
    data.write_text("pressure_difference (kPa), leak_rate (ml/min)\n2, 1\n5, 2.5\n10, 5\n")
    args = ["fit", "--example", "reference-experiment", "--linearity", "--data", str(data), "--squeeze-pressure"]
    assert main([*args, "1 kPa"]) == 0
    assert "note: line 2: ΔP = 2000 Pa is not small against P0 = 1000 Pa (3 row(s) like it)" in capsys.readouterr().out
    assert main([*args, "100 kPa"]) == 0
    assert "not small against P0" not in capsys.readouterr().out


def test_a_gas_fit_notes_a_pressure_difference_that_opens_the_seal(tmp_path, capsys):
    """A liquid's fit says where ΔP reaches P0; a gas's (ΔP = 1000 bar against P0 = 200 kPa) said nothing."""
    data = tmp_path / "g.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (mbar*l/s), pressure_difference (bar)\n200, 1e-3, 1000\n200, 1e-4, 1\n")
    assert main(["fit", "--example", "pressure-decay", "--data", str(data)]) == 0
    out = capsys.readouterr().out
    assert "note: line 2: ΔP = 1e+08 Pa reaches the lift-off pressure difference, P0 = 200000 Pa (1 row(s) like it)" in out


def test_a_data_files_load_the_theory_cannot_use_is_named_by_its_line(tmp_path, capsys):
    """An O-ring row at 0.0001 % compression was reported as conditions.compression[0], a key the user never wrote."""
    data = tmp_path / "oc.csv"
    data.write_text("compression (%), leak_rate (ml/min)\n0.0001, 1\n20, 2\n")
    assert main(["fit", "--example", "o-ring", "--variant", "water", "--data", str(data)]) == 2
    err = capsys.readouterr().err
    assert f"{data}: line 2, column 'compression (%)': compression 0.0001 %: gives a mean contact pressure" in err
    assert "conditions.compression" not in err


def test_rig_values_are_named_as_written(tmp_path, capsys):
    """A final height above the initial one was named in metres without a unit ("rig.final_height = 2.0"), and a
    sealed rig's note gave P0 as "6.06473e+10 Pa"."""
    text = example_path("reference-experiment").read_text()
    case = tmp_path / "r.toml"
    case.write_text(text.replace('final_height = "0.5 m"', 'final_height = "2 m"'))
    assert main(["rig", str(case)]) == 2
    assert capsys.readouterr().err.strip() == "sealeak: error: rig.final_height = '2 m': must be below rig.initial_height = '1 m'"
    case.write_text(text.replace('load = "3.4 kg"', 'load = "3400 t"'))
    assert main(["rig", str(case)]) == 0
    seal = load_cases(case)[0].seal
    p0 = 3.4e6 * 9.80665 / (seal.width * seal.length)  # the load's weight on the ring's area (about 60 GPa)
    assert f"no leak at P0 = {p0 / 1e9:.4g} GPa, the level stays at 1 m" in capsys.readouterr().out


@pytest.mark.parametrize("mass, opens", [("0.2 kg", True), ("0.8 kg", False)])
def test_a_coupled_rig_notes_where_the_water_column_opens_the_seal(tmp_path, capsys, mass, opens):
    """With the fluid pressure coupled the models take ΔP off the contact: a note says where ΔP = ρgH0 reaches P0 (the
    seal opens; it said 'the theory assumes P0 >> ΔP', the uncoupled wording, and also where P0/2 < ΔP < P0, which the
    coupling handles). Readings implying an α far from order one are flagged as fit flags a fitted one."""
    text = example_path("reference-experiment").read_text().replace('fluid_pressure = "ignored"', 'fluid_pressure = "coupled"')
    case = tmp_path / "r.toml"
    case.write_text(text.replace('load = "3.4 kg"', f'load = "{mass}"'))  # P0 = 3.6 / 14 kPa against ΔP = 9.8 kPa
    readings = tmp_path / "rd.csv"
    readings.write_text("time (min), height (cm)\n0, 100\n10, 90\n20, 81\n30, 73\n")
    assert main(["rig", str(case), "--readings", str(readings)]) == 0
    out = capsys.readouterr().out
    assert ("reaches the lift-off pressure difference" in out and "opens the seal" in out) == opens
    assert "the theory assumes P0 >> ΔP" not in out
    (line,) = [ln for ln in out.splitlines() if ln.startswith("α implied by the readings")]
    alpha = float(line.split(":")[1].split()[0])
    assert ("outside 0.01 to 100" in line) == (not 0.01 <= alpha <= 100), line


def test_a_file_of_measured_leak_rates_is_bounded(tmp_path, capsys):
    """10 000 rows took a minute and a GB; 200 000 ran on: at most as many rows as a case has squeeze pressures."""
    data = tmp_path / "big.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min)\n" + "".join(f"{20 + i / 100:.2f}, 400\n" for i in range(10_001)))
    assert main(["fit", "--example", "reference-experiment", "--data", str(data)]) == 2
    assert capsys.readouterr().err.strip().endswith("big.csv: has 10001 data rows: at most 10000 (as many as a case's "
                                                    "squeeze pressures; each row is a prediction); average repeated "
                                                    "measurements first")
