"""Validity verdicts, input warnings and inputs at fault, as `sealeak predict` shows them (docs/theory.md §9.11)."""

import csv
import io
import json

import pytest

from sealeak.cli import main
from tests.casefiles import BASE, edit


def _write(tmp_path, text, name="c.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_hrms_study_flags_the_rows_below_one_molecule_in_table_json_and_csv(tmp_path, capsys):
    js, cs = tmp_path / "o.json", tmp_path / "o.csv"
    assert main(["predict", "--example", "hrms-study", "--json", str(js), "--csv", str(cs)]) == 0
    out = capsys.readouterr().out
    assert any(line.rstrip().endswith(" valid") for line in out.splitlines())  # the table's verdict column
    assert "valid = NO" in out and "molecular size" in out
    doc = json.loads(js.read_text())
    d = doc["cases"][0]["fluid"]["molecular_size"]
    flagged = [r for r in doc["results"] if r["valid"] is False]
    assert flagged, "the study reaches sub-molecular gaps"
    for r in doc["results"]:  # the verdict follows from the row's own gap and width
        if r["critical_gap"] is None:
            assert r["valid"] is True and r["validity"] == ""
        else:
            inside = d <= r["critical_gap"] <= r["critical_wavelength"]
            assert r["valid"] is inside and (r["validity"] == "") is inside
    rows = list(csv.DictReader(io.StringIO(cs.read_text())))
    assert [row["valid (1)"] == "true" for row in rows] == [r["valid"] for r in doc["results"]]
    assert all((row["validity"] == "") == (row["valid (1)"] == "true") for row in rows)
    assert doc["warnings"], "P0 up to 10 MPa on E = 10 MPa rubber breaks linear elasticity"


def test_fluid_name_and_molecular_size_set_the_limit(tmp_path, capsys):
    water = _write(tmp_path, edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\nname = "water"'), "w.toml")
    js = tmp_path / "w.json"
    assert main(["predict", str(water), "-q", "--json", str(js)]) == 0
    fluid = json.loads(js.read_text())["cases"][0]["fluid"]
    assert fluid["molecular_size"] == pytest.approx(0.265e-9, rel=1e-6, abs=0) and fluid["molecular_size_note"] == "water"
    # near the percolation threshold u_c falls below any molecule: a larger molecule flags more rows
    sweep = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                 'squeeze_pressure = { start = "0.1 MPa", stop = "0.9 MPa", num = 40, spacing = "log" }')
    counts = []
    for size in ("0.1 nm", "0.9 um"):
        path = _write(tmp_path, edit('viscosity = "1 mPa*s"', f'viscosity = "1 mPa*s"\nmolecular_size = "{size}"', sweep), "s.toml")
        js.unlink()
        assert main(["predict", str(path), "-q", "--json", str(js)]) == 0
        counts.append(sum(r["valid"] is False for r in json.loads(js.read_text())["results"]))
    assert counts[0] < counts[1]


@pytest.mark.parametrize(("old", "new", "words"), [
    ('h_rms = "44 um"', 'h_rms = "1 km"', "larger than the seal width"),
    ('cutoff_wavelength = "20 um"', 'cutoff_wavelength = "1e-15 m"', "below atomic size"),
    ('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "3 MPa"]', "linear elasticity"),
    ('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["100 MPa"]', "full contact"),
])
def test_absurd_inputs_are_computed_and_warned_about(tmp_path, capsys, old, new, words):
    path = _write(tmp_path, edit(old, new))
    js = tmp_path / "o.json"
    assert main(["predict", str(path), "--json", str(js)]) == 0
    out = capsys.readouterr().out
    assert any(line.startswith("warning: ") and words in line for line in out.splitlines())
    assert any(words in w for w in json.loads(js.read_text())["warnings"])


def test_a_spectrum_band_out_of_order_names_the_keys_the_file_has(tmp_path, capsys):
    path = _write(tmp_path, edit('rolloff_wavevector = "9.1e3 1/m"', 'rolloff_wavevector = "1e9 1/m"'))
    assert main(["predict", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: surface.rolloff_wavevector") and "surface.cutoff_wavelength" in err
    assert "cutoff_wavevector" not in err  # the file does not have that key


@pytest.mark.parametrize(("old", "new", "field"), [
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "1e30 Pa"', "rubber.youngs_modulus"),
    ('outer_diameter = "4 cm"', 'outer_diameter = "3.0000001 cm"', "seal.outer_diameter"),
    ('pressure_difference = "10 kPa"', 'pressure_difference = "0 Pa"', "conditions.pressure_difference"),
    ('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\nmolecular_size = "-1 nm"', "fluid.molecular_size"),
    ('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\nmolecular_size = "1 m"', "fluid.molecular_size"),
    ('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\nname = 3', "fluid.name"),
    ('outer_diameter = "4 cm"', 'outer_diameter = "4 cm"\nheight = "tall"', "seal.height"),
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2.3 MPa"\nname = ["PDMS"]', "rubber.name"),
])
def test_the_input_at_fault_is_named(tmp_path, capsys, old, new, field):
    path = _write(tmp_path, edit(old, new))
    js = tmp_path / "o.json"
    assert main(["predict", str(path), "--json", str(js)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sealeak: error: {field}") and err.count("\n") == 1 and "Traceback" not in err
    assert not js.exists()


def test_no_channel_notes_are_grouped_into_one_line(tmp_path, capsys):
    path = _write(tmp_path, edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                                 'squeeze_pressure = { start = "20 kPa", stop = "100 MPa", num = 30, spacing = "log" }'))
    assert main(["predict", str(path)]) == 0
    notes = [line for line in capsys.readouterr().out.splitlines() if "never percolates" in line]
    assert len(notes) == 1 and " of 30 pressures)" in notes[0]


def test_base_case_is_valid_everywhere(tmp_path, capsys):
    assert main(["predict", str(_write(tmp_path, BASE))]) == 0
    out = capsys.readouterr().out
    assert "valid = NO" not in out and out.count(" yes") == 3


def test_pressure_difference_not_small_against_p0_is_outside_the_theory(tmp_path, capsys):
    text = edit('pressure_difference = "10 kPa"', 'pressure_difference = "45 kPa"')
    path = _write(tmp_path, edit("alpha = 0.2", 'alpha = 0.2\nfluid_pressure = "ignored"', text))
    js = tmp_path / "o.json"
    assert main(["predict", str(path), "-q", "--json", str(js)]) == 0
    rows = json.loads(js.read_text())["results"]
    # ΔP > P0/2 (docs/theory.md §3.6) at P0 = 20 and 60 kPa, not at 100 kPa
    assert [r["valid"] for r in rows] == [r["pressure_difference"] <= 0.5 * r["squeeze_pressure"] for r in rows]
    assert [r["valid"] for r in rows] == [False, False, True]
    assert rows[0]["validity"].startswith("ΔP = ")
    assert "lift_off_pressure_difference" not in rows[0]


def test_pressure_difference_beyond_lift_off_opens_the_seal(tmp_path):
    """Coupled (the default): only ΔP >= P0 is outside, the seal opens (docs/theory.md §13.4)."""
    path = _write(tmp_path, edit('pressure_difference = "10 kPa"', 'pressure_difference = "45 kPa"'))
    js = tmp_path / "o.json"
    assert main(["predict", str(path), "-q", "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    rows = doc["results"]
    assert doc["units"]["lift_off_pressure_difference"] == "Pa"
    assert [r["lift_off_pressure_difference"] for r in rows] == [r["squeeze_pressure"] for r in rows]
    assert [r["valid"] for r in rows] == [False, True, True]
    assert "opens the seal" in rows[0]["validity"]


def test_a_row_beyond_lift_off_is_explained_under_the_table(tmp_path, capsys):
    """The row the fluid pressure opens (valid = NO) gets its note under the table, one line naming its pressure, as
    every other invalid row does (with the fluid pressure ignored, the theory's own note says it)."""
    path = _write(tmp_path, edit('pressure_difference = "10 kPa"', 'pressure_difference = "45 kPa"'))
    assert main(["predict", str(path)]) == 0
    out = capsys.readouterr().out
    (line,) = [ln for ln in out.splitlines() if "lift-off" in ln]
    assert line.startswith("note: critical junction, P0 = 20 kPa: valid = NO") and "opens the seal" in line
