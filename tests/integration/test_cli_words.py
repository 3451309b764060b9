"""The command line names the right cause and does not accept nonsense silently (issue 21 §6).

Errors: exit status 2, one line, the key at fault named (and what is allowed). Warnings: the number is
still computed, and a warning names the key and why.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from sealeak.cases import example_path, parse_case_file, read_case_file, run_case
from sealeak.cases.ensemble import default_workers, make_runner
from sealeak.cli import main
from tests.casefiles import BASE, edit
from tests.cli_errors import one_line_error

CLI = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"  # the command line in a subprocess

ORING = edit('shape = "ring"\ninner_diameter = "3 cm"\nouter_diameter = "4 cm"',
             'shape = "o-ring"\ncross_section_diameter = "2.62 mm"\ninner_diameter = "20 mm"',
             edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'compression = ["15 %", "25 %"]'))
PROFILE_CSV = "x (mm), pressure (MPa)\n0, 0\n0.05, 0.4\n0.1, 0.8\n0.2, 0.3\n0.25, 0\n"
GAS = edit('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "helium"\ntemperature = "20 degC"',
           edit('pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"', ORING))


def predict(tmp_path, capsys, text, *names):
    case = tmp_path / "case.toml"
    case.write_text(text, encoding="utf-8")
    assert main(["predict", str(case), "-q"]) == 2
    return one_line_error(capsys, *names)


def subprocess_error(tmp_path, text, *names, files=None):
    """The command line in its own process (warnings printed as Python would): one line, naming ``names``."""
    for name, content in (files or {}).items():
        (tmp_path / name).write_text(content, encoding="utf-8")
    case = tmp_path / "case.toml"
    case.write_text(text, encoding="utf-8")
    run = subprocess.run([sys.executable, "-c", CLI, "predict", str(case)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    assert run.stderr.startswith("sealeak: error: ") and run.stderr.count("\n") == 1, run.stderr  # no RuntimeWarning
    for name in names:
        assert name in run.stderr, (name, run.stderr)
    return run.stderr


def case_of(tmp_path, text, files=None):
    for name, content in (files or {}).items():
        (tmp_path / name).write_text(content, encoding="utf-8")
    return parse_case_file(text, tmp_path).cases[0]


# ------------------------------------------------------------------------------------ seal.shape
@pytest.mark.parametrize("shape, near", [('"O-ring"', True), ('"oring"', True), ('"o_ring"', True), ('"o-ring "', True),
                                         ('""', False), ("5", False), ("{ kind = 1 }", False)])
def test_an_unknown_seal_shape_is_named_with_the_allowed_shapes(tmp_path, capsys, shape, near):
    err = predict(tmp_path, capsys, ORING.replace('shape = "o-ring"', f"shape = {shape}"), "seal.shape",
                  "'ring', 'rectangle', 'o-ring'")
    assert "cross_section_diameter" not in err
    assert ("did you mean 'o-ring'?" in err) == near, err


# ------------------------------------------------------------------------------------ values read as something else
def test_percent_squared_is_refused(tmp_path, capsys):
    predict(tmp_path, capsys, ORING.replace('compression = ["15 %", "25 %"]', 'compression = "10 % %"'),
            "conditions.compression", "'10 % %'", "'%' stands alone")


@pytest.mark.parametrize("unit", ["delta_degC", "delta_degF", "K*K/K"])
def test_a_temperature_difference_is_no_temperature(tmp_path, capsys, unit):
    err = predict(tmp_path, capsys, edit('viscosity = "1 mPa*s"', f'viscosity = "1 mPa*s"\ntemperature = "20 {unit}"'),
                  "fluid.temperature", "degC", "K (kelvin")
    assert "absolute temperature" in err


def test_a_misspelt_gas_is_refused_with_the_right_name(tmp_path, capsys):
    text = GAS.replace('name = "helium"', 'name = "helum"\nviscosity = "20 uPa*s"')
    predict(tmp_path, capsys, text, "fluid.name", "'helum'", "did you mean 'helium'?")
    # without a viscosity the library's message says the same
    predict(tmp_path, capsys, GAS.replace('name = "helium"', 'name = "helum"'), "fluid.name", "did you mean 'helium'?")


def test_an_unknown_liquid_with_absolute_pressures_is_a_liquid_and_says_so(tmp_path):
    text = edit('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "coolant X"\nviscosity = "2 mPa*s"',
                edit('pressure_difference = "10 kPa"', 'upstream_pressure = "2 bar"\ndownstream_pressure = "1 bar"'))
    res = run_case(case_of(tmp_path, text))
    assert res.case.gas is None and np.all(res.critical_junction.leak_rate[res.critical_junction.percolates] > 0)
    assert any("fluid.name = 'coolant X'" in w and "incompressible liquid" in w for w in res.warnings), res.warnings


# ------------------------------------------------------------------------------------ warnings: computed, and said
def _warned(res, *words):
    hits = [w for w in res.warnings if all(x in w for x in words)]
    assert hits, (words, res.warnings)
    return hits[0]


def _leaks(res):
    q = res.band.critical_junction.leak_rate if res.band is not None else res.critical_junction.leak_rate
    return np.isfinite(q).all() and (q > 0).any()


def test_a_gas_with_a_liquids_viscosity_and_density(tmp_path):
    res = run_case(case_of(tmp_path, GAS.replace('temperature = "20 degC"',
                                                 'temperature = "20 degC"\nviscosity = "1 mPa*s"\ndensity = "998 kg/m^3"')))
    assert res.gas is not None and _leaks(res)
    w = _warned(res, "fluid.viscosity", "times the property library's", "helium (gas)")
    assert "a liquid's?" in w
    _warned(res, "fluid.density", "times the property library's")


def test_a_gas_viscosity_near_the_librarys_is_not_warned_about(tmp_path):
    res = run_case(case_of(tmp_path, GAS.replace('temperature = "20 degC"', 'temperature = "20 degC"\nviscosity = "19.6 uPa*s"')))
    assert not [w for w in res.warnings if "fluid.viscosity" in w]


def test_hot_water_with_the_viscosity_of_cold_water(tmp_path):
    text = edit('viscosity = "1 mPa*s"', 'name = "water"\nviscosity = "1 mPa*s"\ntemperature = "200 degC"')
    res = run_case(case_of(tmp_path, text))
    assert _leaks(res)
    _warned(res, "fluid.temperature", "water is a gas at 200 °C")
    # with absolute pressures that keep it liquid, the viscosity is compared with the library's (0.13 mPa·s)
    text = edit('pressure_difference = "10 kPa"', 'upstream_pressure = "30 bar"\ndownstream_pressure = "20 bar"', text)
    res = run_case(case_of(tmp_path, text))
    assert _leaks(res)
    _warned(res, "fluid.viscosity = '1 mPa*s'", "water (liquid) at 200 °C")


def test_an_oring_of_steel_and_a_square_side_on_an_oring(tmp_path):
    text = edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "200 GPa"', ORING) + 'square_side = "1 mm"\n'
    res = run_case(case_of(tmp_path, text))
    assert np.isfinite(res.band.critical_junction.leak_rate).all()
    _warned(res, "E = 200 GPa", "no rubber's Young's modulus", "rubber.youngs_modulus")
    _warned(res, "theory.square_side", "has no square side", "2π/w")


def test_a_profile_250_m_wide_and_a_seal_line_shorter_than_its_band(tmp_path):
    text = ('title = "lip"\n' + BASE.split("[seal]")[0].split('title = "test case"')[1]
            + '[seal]\npressure_profile = "p.csv"\nlength = "0.1 mm"\n[fluid]\nviscosity = "1 mPa*s"\n'
            '[conditions]\nprofile_scale = 1\npressure_difference = "10 kPa"\n')
    res = run_case(case_of(tmp_path, text, {"p.csv": PROFILE_CSV}))
    assert _leaks(res)
    _warned(res, "seal.length = '0.1 mm'", "shorter than the band's width")
    res = run_case(case_of(tmp_path, text.replace('length = "0.1 mm"', 'length = "1 km"'),
                           {"p.csv": PROFILE_CSV.replace("x (mm)", "x (km)")}))
    _warned(res, "p.csv spans x over 250 m", "check the unit of its x column")


def test_a_rig_load_far_beyond_the_rubbers_modulus(tmp_path, capsys):
    text = BASE + '[rig]\ncylinder_diameter = "3 cm"\ninitial_height = "1 m"\nload = "1e5 kg"\ndensity = "1000 kg/m^3"\n'
    case = tmp_path / "case.toml"
    case.write_text(text)
    assert main(["rig", str(case)]) == 0
    out = capsys.readouterr().out
    assert "P0 = 1.784e+06 kPa" in out or "1.78 GPa" in out
    assert "the pressure of the rig's load exceeds 0.5 E" in out and "check [rig] load" in out


def test_more_workers_than_cores_are_capped_with_a_note():
    notes = []
    make_runner(workers=1000, note=notes.append)
    assert len(notes) == 1 and "--workers 1000" in notes[0] and f"{default_workers()} core" in notes[0]
    notes.clear()
    make_runner(workers=1, note=notes.append)
    assert notes == []


# ------------------------------------------------------------------------------------ overflow, underflow, the key named
@pytest.mark.parametrize("scale, why", [("1e308", "peak contact pressure"), ("1e-12", "a larger profile_scale")])
def test_a_profile_scale_out_of_reach_names_profile_scale(tmp_path, scale, why):
    text = ('title = "lip"\n' + BASE.split("[seal]")[0].split('title = "test case"')[1]
            + '[seal]\npressure_profile = "p.csv"\nlength = "100 mm"\n[fluid]\nviscosity = "1 mPa*s"\n'
            f'[conditions]\nprofile_scale = {scale}\npressure_difference = "10 kPa"\n')
    err = subprocess_error(tmp_path, text, "conditions.profile_scale", why, files={"p.csv": PROFILE_CSV})
    assert "squeeze_pressure" not in err


def test_a_vanishing_compression_names_compression(tmp_path):
    err = subprocess_error(tmp_path, ORING.replace('compression = ["15 %", "25 %"]', 'compression = "1e-300 %"'),
                           "conditions.compression", "'1e-300 %'", "0.0001 %")
    assert "max_pressure" not in err


def test_a_linearity_file_at_60_percent_names_the_file_and_line(tmp_path, capsys):
    data = tmp_path / "lin.csv"
    data.write_text("compression (%), pressure_difference (bar), leak_rate (ml/min)\n60, 1, 1e-6\n60, 2, 2e-6\n60, 3, 3e-6\n")
    assert main(["fit", "--example", "o-ring", "--variant", "water", "--linearity", "--data", str(data)]) == 2
    one_line_error(capsys, str(data), "line 2", "compression (%)", "60 %")


def test_a_store_that_cannot_be_created_names_store(tmp_path, capsys):
    argv = ["simulate", str(example_path("reference-experiment")), "--grid", "16", "--realizations", "1",
            "--store", "/proc/self/newdir", "-q"]
    assert main(argv) == 2
    one_line_error(capsys, "--store", "/proc/self/newdir")


def test_fit_linearity_of_a_gas_is_refused_with_the_reason(tmp_path, capsys):
    data = tmp_path / "he.csv"
    data.write_text("compression (%), pressure_difference (mbar), leak_rate (mbar*l/s)\n"
                    "20, 500, 1e-6\n20, 1000, 2e-6\n20, 1500, 3e-6\n")
    out = tmp_path / "lin.json"
    assert main(["fit", "--example", "helium-test", "--linearity", "--data", str(data), "--json", str(out)]) == 2
    one_line_error(capsys, "--linearity", "a gas", "(P_a² − P_b²)", "fit α without --linearity")
    assert not out.exists()


# ------------------------------------------------------------------------------------ what a newcomer reads
def test_examples_lists_every_description_whole(capsys):
    assert main(["examples"]) == 0
    out = " ".join(capsys.readouterr().out.split())  # the descriptions are wrapped: join the lines
    assert "steep on the oil side (x = 0) and gentle on the air side" in out
    assert "pressure-decay EPDM ring on ground steel, pressure-decay test with air" in out


def test_the_pressure_decay_example_says_the_roughness_it_sets():
    text = example_path("pressure-decay").read_text()
    header = " ".join(line for line in text.splitlines() if line.startswith("#"))
    h_rms = read_case_file(example_path("pressure-decay")).cases[0].spectrum.h_rms
    assert f"h_rms = {h_rms * 1e6:.0f} um" in header


def test_the_report_of_an_example_names_it_not_its_install_path(tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["report", "--example", "lip-profile", "-o", str(out), "-q"]) == 0
    html = out.read_text()
    install = str(example_path("lip-profile").parent)
    assert install not in html
    assert "<code>--example lip-profile</code>" in html and "lip-profile.csv (bundled example data)" in html


def test_json_of_a_warned_case_still_has_its_numbers(tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "5 GPa"'))
    out = tmp_path / "r.json"
    assert main(["predict", str(case), "--json", str(out), "-q"]) == 0
    doc = json.loads(out.read_text())
    text = json.dumps(doc)
    assert "no rubber's Young's modulus" in text
