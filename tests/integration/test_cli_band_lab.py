"""sealeak fit / fit --linearity / rig / report with O-ring and pressure-profile seals, through the CLI.

Every refusal: exit status 2, one line ``sealeak: error: ...`` naming the field or the file (and the
column), no traceback, and no output file written or replaced.
"""

import json

import numpy as np
import pytest

from sealeak.cases import example_path
from sealeak.cli import main
from tests.unit.test_band_lab import RIG, SURFACE, profile_case, series_conductance

ORING_DATA = example_path("o-ring").parent / "o-ring-measured.csv"
EXAMPLES = {"uniform": ["--example", "reference-experiment"], "profile": ["--example", "lip-profile"],
            "o-ring": ["--example", "o-ring", "--variant", "water"]}


def _refused(capsys, argv, *names, keep=None):
    """Run ``sealeak argv``: exit 2, one line naming ``names``, no traceback; ``keep``: files left exactly as they were."""
    before = {p: p.read_bytes() if p.exists() else None for p in keep or ()}
    capsys.readouterr()
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sealeak: error: ") and "Traceback" not in err, err
    for name in names:
        assert name in lines[0], (name, lines[0])
    assert out == ""
    for p, content in before.items():
        assert (p.read_bytes() if p.exists() else None) == content
    return lines[0]


def test_fit_of_the_bundled_oring_measurements(tmp_path, capsys):
    """The example data: α = 0.3 times the band theory with 20 % scatter; the fit finds it within its error."""
    out, figs = tmp_path / "fit.json", tmp_path / "figs"
    assert main(["fit", *EXAMPLES["o-ring"], "--data", str(ORING_DATA), "--json", str(out), "--plots", str(figs)]) == 0
    text = capsys.readouterr().out
    assert "O-ring's leak rate at each row's compression" in text and "5 distinct compressions" in text
    doc = json.loads(out.read_text())
    cj = doc["critical_junction"]
    assert abs(cj["alpha"] - 0.3) < 3 * cj["alpha_std"] and cj["points_used"] == 5
    assert doc["load_column"] == "compression" and doc["effective_medium"]["points_used"] == 5
    assert (figs / "fit.png").read_bytes()[:4] == b"\x89PNG"


def test_fit_of_a_profile_seal_with_its_own_pressure_differences(tmp_path, capsys):
    profile_case(tmp_path)  # writes step.csv
    (tmp_path / "case.toml").write_text(_profile_text())
    scales, dps = [0.8, 1.0, 1.0, 1.3], [5.0, 10.0, 20.0, 10.0]  # kPa
    q = [0.25 * series_conductance(tmp_path, s, alpha=1.0) * dp * 1e3 for s, dp in zip(scales, dps)]
    data = tmp_path / "m.csv"
    data.write_text("profile_scale (1), pressure_difference (kPa), leak_rate (m^3/s)\n"
                    + "".join(f"{s}, {dp}, {v:.17g}\n" for s, dp, v in zip(scales, dps, q)))
    out = tmp_path / "fit.json"
    assert main(["fit", str(tmp_path / "case.toml"), "--data", str(data), "--json", str(out), "-q"]) == 0
    assert json.loads(out.read_text())["critical_junction"]["alpha"] == pytest.approx(0.25, rel=1e-9)


def _profile_text(scale="1", extra=""):
    """The step-profile case of tests/unit/test_band_lab.py as case-file text (step.csv beside it), fluid pressure
    ignored (Q = K ΔP, which these tests check)."""
    return SURFACE + f"""
[seal]
pressure_profile = "step.csv"
length = "100 mm"
[conditions]
profile_scale = {scale}
pressure_difference = "10 kPa"
[theory]
alpha = 0.5
fluid_pressure = "ignored"
""" + extra


# ---------------------------------------------------------------------- the data file does not fit the seal
@pytest.mark.parametrize("kind, header, column, seal", [
    ("uniform", "compression (%)", "compression (%)", "ring pressed by a uniform squeeze pressure"),
    ("uniform", "profile_scale", "profile_scale", "ring pressed by a uniform squeeze pressure"),
    ("o-ring", "squeeze_pressure (kPa)", "squeeze_pressure (kPa)", "an O-ring of 2.62 mm cross-section"),
    ("o-ring", "profile_scale (1)", "profile_scale (1)", "an O-ring"),
    ("profile", "compression (1)", "compression (1)", "a pressure-profile seal"),
    ("profile", "p0 (MPa)", "p0 (MPa)", "a pressure-profile seal"),
])
def test_a_load_column_that_does_not_fit_the_seal(tmp_path, capsys, kind, header, column, seal):
    data = tmp_path / "m.csv"
    data.write_text(f"{header}, leak_rate (ml/min)\n0.2, 1e-9\n0.3, 1e-10\n")
    out = tmp_path / "fit.json"
    line = _refused(capsys, ["fit", *EXAMPLES[kind], "--data", str(data), "--json", str(out)],
                    str(data), f"column '{column}' does not fit the case's seal", seal, keep=[out])
    assert "give a column" in line


@pytest.mark.parametrize("kind, column", [("uniform", "squeeze_pressure"), ("profile", "profile_scale"),
                                          ("o-ring", "compression")])
def test_a_data_file_without_a_load_column_names_the_one_the_case_takes(tmp_path, capsys, kind, column):
    data = tmp_path / "m.csv"
    data.write_text("leak_rate (ml/min), pressure_difference (kPa)\n1e-9, 10\n")
    _refused(capsys, ["fit", *EXAMPLES[kind], "--data", str(data)], str(data),
             f"missing column {column} (the load of the case's seal)")


def test_an_existing_output_is_not_replaced_when_the_data_do_not_fit(tmp_path, capsys):
    data = tmp_path / "m.csv"
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min)\n30, 1e-9\n")
    out = tmp_path / "fit.json"
    out.write_text("{}\n")
    _refused(capsys, ["fit", *EXAMPLES["profile"], "--data", str(data), "--json", str(out), "--force"],
             "column 'squeeze_pressure (kPa)'", keep=[out])


@pytest.mark.parametrize("kind, text, names", [
    ("o-ring", "compression (%), leak_rate (ml/min)\n15, 1e-9\n55, 1e-10\n",
     ["line 3, column 'compression (%)': compression 55 %", "must be below"]),
    ("o-ring", "compression (1), leak_rate (ml/min)\n15, 1e-9\n",
     ["line 2, column 'compression'", "for per cent write 'compression (%)'"]),
    ("o-ring", "compression, leak_rate (ml/min)\n15, 1e-9\n", ["column 'compression' has no unit"]),
    ("profile", "profile_scale, leak_rate (ml/min)\n0, 1e-9\n", ["line 2, column 'profile_scale': 0 must be > 0"]),
])
def test_bad_loads_in_a_data_file_name_the_line(tmp_path, capsys, kind, text, names):
    data = tmp_path / "m.csv"
    data.write_text(text)
    _refused(capsys, ["fit", *EXAMPLES[kind], "--data", str(data)], str(data), *names)


# ---------------------------------------------------------------------- variants of a study
def test_variant_picks_one_case_of_a_study(tmp_path, capsys):
    line = _refused(capsys, ["fit", "--example", "o-ring", "--data", str(ORING_DATA)], "study of 2", "--variant")
    assert "'water'" in line and "'oil (ISO VG 32 at 40 °C)'" in line
    _refused(capsys, ["fit", "--example", "o-ring", "--variant", "air", "--data", str(ORING_DATA)],
             "--variant = 'air'", "is not a variant", "'water'")
    _refused(capsys, ["rig", "--example", "reference-experiment", "--variant", "water"], "--variant", "no [study]")


# ---------------------------------------------------------------------- rig
def test_rig_of_a_profile_seal_against_the_closed_form_drain(tmp_path, capsys):
    profile_case(tmp_path)  # writes step.csv
    case_file = tmp_path / "case.toml"
    case_file.write_text(_profile_text("1.2", RIG))
    k = series_conductance(tmp_path, 1.2, alpha=0.5)
    out = tmp_path / "rig.json"
    assert main(["rig", str(case_file), "--json", str(out), "--plots", str(tmp_path / "f")]) == 0
    text = capsys.readouterr().out
    assert "pressure profile at profile scale 1.2: contact width 0.5 mm" in text and "kPa on the" not in text
    doc = json.loads(out.read_text())
    model = doc["models"]["critical junction (α = 0.5)"]
    assert model["conductance"] == pytest.approx(k, rel=1e-9, abs=0)
    area, rho_g = np.pi * 0.5e-3**2 / 4, 1000.0 * 9.80665
    tau = area / (k * rho_g)  # H = H0 exp(-t/τ): from 1 m to 0.25 m in τ ln 4
    assert model["time_constant"] == pytest.approx(tau, rel=1e-9)
    assert model["time_to_final_height"] == pytest.approx(tau * np.log(4.0), rel=1e-9)
    assert model["time_to_final_height_ode"] == pytest.approx(tau * np.log(4.0), rel=1e-6)
    t, h = np.array(model["time"]), np.array(model["height"])
    assert np.allclose(h, np.exp(-t / tau), rtol=1e-6, atol=1e-9)
    assert doc["profile_scale"] == 1.2 and doc["band"]["contact_width"] == pytest.approx(0.5e-3, rel=1e-12, abs=0)
    assert doc["band"]["max_contact_pressure"] == pytest.approx(1.2 * 0.2e6, rel=1e-12)
    assert (tmp_path / "f" / "rig.png").exists()


def test_rig_of_a_band_seal_refusals(tmp_path, capsys):
    profile_case(tmp_path)  # writes step.csv
    several = tmp_path / "several.toml"
    several.write_text(_profile_text("[1, 1.5]", RIG))
    out = tmp_path / "rig.json"
    _refused(capsys, ["rig", str(several), "--json", str(out)], "conditions.profile_scale", "one profile_scale",
             "(1, 1.5)", keep=[out])
    loaded = tmp_path / "loaded.toml"
    loaded.write_text(_profile_text("1", RIG + 'load = "3 kg"\n'))
    _refused(capsys, ["rig", str(loaded), "--json", str(out)], "rig.load = '3 kg'", "remove load", keep=[out])


def test_report_of_band_seals_with_a_rig(tmp_path, capsys):
    profile_case(tmp_path)  # writes step.csv
    one, several = tmp_path / "one.toml", tmp_path / "several.toml"
    one.write_text(_profile_text("1.2", RIG))
    several.write_text(_profile_text("[1, 1.5]", RIG))
    for case_file, has_rig in ((one, True), (several, False)):
        out = tmp_path / f"{case_file.stem}.html"
        assert main(["report", str(case_file), "-o", str(out), "-q"]) == 0
        assert ('id="rig"' in out.read_text()) == has_rig


# ---------------------------------------------------------------------- linearity
def test_linearity_of_a_profile_seal(tmp_path, capsys):
    profile_case(tmp_path)  # writes step.csv
    case_file = tmp_path / "case.toml"
    case_file.write_text(_profile_text("[1, 1.5]"))
    k = series_conductance(tmp_path, 1.5, alpha=0.5)
    dp = np.array([2.0, 4.0, 6.0, 8.0])  # kPa
    data = tmp_path / "lin.csv"
    data.write_text("profile_scale, pressure_difference (kPa), leak_rate (m^3/s)\n"
                    + "".join(f"1.5, {x}, {2 * k * x * 1e3:.17g}\n" for x in dp))
    out = tmp_path / "lin.json"
    assert main(["fit", str(case_file), "--data", str(data), "--linearity", "--json", str(out)]) == 0
    assert "load       profile scale 1.5 (from the data file)" in capsys.readouterr().out
    doc = json.loads(out.read_text())["linearity"]
    assert doc["model_slopes"]["critical_junction"] == pytest.approx(k, rel=1e-9, abs=0)
    assert doc["alpha_from_slope"] == pytest.approx(2 * 0.5, rel=1e-9) and doc["profile_scale"] == 1.5
    out.unlink()
    _refused(capsys, ["fit", str(case_file), "--data", str(data), "--linearity", "--squeeze-pressure", "1 MPa",
                      "--json", str(out)], "--squeeze-pressure = '1 MPa'", "a pressure-profile seal", keep=[out])
    mixed = tmp_path / "mixed.csv"
    mixed.write_text("profile_scale, pressure_difference (kPa), leak_rate (m^3/s)\n1, 2, 1e-20\n1.5, 4, 1e-20\n1.5, 6, 1e-20\n")
    _refused(capsys, ["fit", str(case_file), "--data", str(mixed), "--linearity"], str(mixed), "one profile scale")
    wrong = tmp_path / "wrong.csv"
    wrong.write_text("compression (%), pressure_difference (kPa), leak_rate (m^3/s)\n15, 2, 1e-20\n15, 4, 2e-20\n15, 6, 3e-20\n")
    _refused(capsys, ["fit", str(case_file), "--data", str(wrong), "--linearity"], str(wrong), "column 'compression (%)'")


def test_help_states_the_cost_of_the_effective_medium(capsys):
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    assert "1-2 s per distinct value" in " ".join(capsys.readouterr().out.split())
