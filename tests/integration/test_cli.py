import csv
import json

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, predict
from sealeak.cli import main
from sealeak.render import PREDICTION_FIGURE_NAMES


@pytest.fixture
def case_file(tmp_path):
    text = (example_path("reference-experiment").read_text()
            .replace('{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }',
                     '["30 kPa", "60 kPa", "1 GPa"]'))
    p = tmp_path / "ring.toml"
    p.write_text(text)
    return p


def test_predict_table(case_file, capsys):
    assert main(["predict", str(case_file)]) == 0
    out = capsys.readouterr().out
    assert "P0 (kPa)" in out and "u_c (µm)" in out and "Q (m³/s)" in out
    assert "never percolates" in out  # the 1 GPa row
    assert len([ln for ln in out.splitlines() if ln.strip().startswith(("30 ", "60 ", "1e+06"))]) == 3


def test_predict_json_schema(case_file, tmp_path):
    out = tmp_path / "r.json"
    assert main(["predict", str(case_file), "--json", str(out), "-q"]) == 0
    doc = json.loads(out.read_text())
    assert doc["units"]["leak_rate"] == "m^3/s" and doc["units"]["critical_gap"] == "m"
    rows = doc["results"]
    assert len(rows) == 3
    for key in ("squeeze_pressure", "pressure_difference", "percolates", "critical_magnification",
                "critical_gap", "critical_wavelength", "leak_rate", "contact_area_at_cutoff"):
        assert key in rows[0]
    assert rows[0]["squeeze_pressure"] == pytest.approx(3e4)
    assert rows[2]["percolates"] is False and rows[2]["leak_rate"] is None
    # JSON numbers equal the library's
    (case,) = load_cases(case_file)
    r = predict(case)
    assert rows[1]["leak_rate"] == pytest.approx(r.leak_rate[1], rel=1e-15, abs=0)


def test_predict_csv(case_file, tmp_path):
    out = tmp_path / "r.csv"
    assert main(["predict", str(case_file), "--csv", str(out), "-q"]) == 0
    rows = list(csv.reader(out.open()))
    assert rows[0][0] == "squeeze_pressure (Pa)" and "leak_rate (m^3/s)" in rows[0]
    assert len(rows) == 4
    assert rows[3][rows[0].index("leak_rate (m^3/s)")] == ""


def test_predict_plots(case_file, tmp_path):
    d = tmp_path / "figs"
    assert main(["predict", str(case_file), "--plots", str(d), "-q"]) == 0
    for name in PREDICTION_FIGURE_NAMES:
        data = (d / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_no_overwrite_without_force(case_file, tmp_path, capsys):
    out = tmp_path / "r.json"
    out.write_text("precious")
    assert main(["predict", str(case_file), "--json", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert out.read_text() == "precious"
    assert main(["predict", str(case_file), "--json", str(out), "--force", "-q"]) == 0
    assert json.loads(out.read_text())["results"]


def test_output_files_get_the_usual_permissions(case_file, tmp_path):
    import os
    import stat

    old = os.umask(0o022)
    try:
        assert main(["predict", str(case_file), "--json", str(tmp_path / "r.json"), "-q"]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "r.json").stat().st_mode) == 0o644  # not mkstemp's 0600


def test_interrupted_write_leaves_no_file(case_file, tmp_path, monkeypatch):
    import sealeak.render as render

    def boom(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(render, "prediction_csv", boom)
    out = tmp_path / "r.csv"
    assert main(["predict", str(case_file), "--csv", str(out), "-q"]) == 130
    assert list(tmp_path.glob("r.csv*")) == [] and list(tmp_path.glob(".r.csv*")) == []


@pytest.mark.parametrize("message", ["Unable to allocate 8.00 GiB for an array with shape (32768, 32768) and data type "
                                     "float64", "Out of memory allocating 1,073,741,824 bytes (allocated so far: 0 bytes).", ""])
def test_out_of_memory_is_one_line_and_leaves_no_file(case_file, tmp_path, monkeypatch, capsys, message):
    import sealeak.render as render

    def boom(*a, **k):
        raise MemoryError(message)

    monkeypatch.setattr(render, "prediction_csv", boom)
    out = tmp_path / "r.csv"
    assert main(["predict", str(case_file), "--csv", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: out of memory (") and len(err.strip().splitlines()) == 1
    assert "Traceback" not in err and (message.split(" for ")[0] if message else "an allocation failed") in err
    assert list(tmp_path.glob("r.csv*")) == [] and list(tmp_path.glob(".r.csv*")) == []


def test_examples_command(capsys):
    assert main(["examples"]) == 0
    out = capsys.readouterr().out
    assert "reference-experiment" in out and "hrms-study" in out
    assert main(["examples", "reference-experiment"]) == 0
    assert "[surface]" in capsys.readouterr().out
    assert main(["examples", "nope"]) == 2
    assert "example = 'nope'" in capsys.readouterr().err


def test_study_case_runs_every_variant(tmp_path):
    out = tmp_path / "s.json"
    assert main(["predict", "--example", "hrms-study", "--json", str(out), "-q"]) == 0
    doc = json.loads(out.read_text())
    variants = {r["variant"] for r in doc["results"]}
    assert len(variants) == 4
    # rougher surfaces leak more at the same pressure
    by = {v: [r for r in doc["results"] if r["variant"] == v][0]["leak_rate"] for v in variants}
    assert by["h_rms = 6 µm"] > by["h_rms = 1 µm"]


def test_usage_errors_exit_nonzero(capsys):
    assert main(["predict"]) == 2
    capsys.readouterr()
    with pytest.raises(SystemExit) as e:
        main(["predict", "--bogus"])
    assert e.value.code == 2
    assert capsys.readouterr().err == "sealeak: error: unrecognized arguments: --bogus (options: sealeak predict --help)\n"
    assert main(["predict", "/no/such/case.toml"]) == 2
    assert "case file not found" in capsys.readouterr().err


def test_output_that_is_a_folder_is_refused_even_with_force(case_file, tmp_path, capsys):
    folder = tmp_path / "adir"
    folder.mkdir()
    assert main(["predict", str(case_file), "--json", str(folder), "--force", "-q"]) == 2
    err = capsys.readouterr().err
    assert "is a folder" in err and str(folder) in err and "Traceback" not in err
    assert folder.is_dir() and not any(folder.iterdir())


def test_two_outputs_with_one_name_are_refused(case_file, tmp_path, capsys):
    out = tmp_path / "x.json"
    assert main(["predict", str(case_file), "--json", str(out), "--csv", str(out), "-q"]) == 2
    assert "same file" in capsys.readouterr().err
    assert not out.exists()


def test_unwritable_output_is_a_one_line_error(case_file, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    # a folder that cannot be created: its parent is a file
    assert main(["predict", str(case_file), "--json", str(blocker / "sub" / "r.json"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error:") and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_write_failure_names_the_file(tmp_path, monkeypatch):
    import os

    from sealeak.io.files import OutputWriteError, write_text

    def refuse(src, dst):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(OutputWriteError, match="cannot write .*r.txt: Permission denied"):
        write_text(tmp_path / "r.txt", "data")
    assert list(tmp_path.iterdir()) == []  # the temporary file is gone too


def test_predict_writes_the_table_it_prints(case_file, tmp_path, capsys):
    out = tmp_path / "table.txt"
    assert main(["predict", str(case_file), "--table", str(out)]) == 0
    printed = capsys.readouterr().out
    assert out.read_text() == printed and "Q (m³/s)" in printed


def test_vanishing_squeeze_pressure_is_refused(case_file, tmp_path, capsys):
    text = case_file.read_text().replace('["30 kPa", "60 kPa", "1 GPa"]', '["1e-9 Pa", "60 kPa"]')
    tiny = tmp_path / "tiny.toml"
    tiny.write_text(text)
    assert main(["predict", str(tiny)]) == 2
    err = capsys.readouterr().err
    assert "conditions.squeeze_pressure[0] = '1e-9 Pa': must be at least 1 mPa" in err


def test_study_table_shows_each_variants_own_settings(case_file, tmp_path, capsys):
    text = case_file.read_text() + '\n[study]\nvary = "rubber.youngs_modulus"\nvalues = ["2.3 MPa", "5 MPa"]\n'
    study = tmp_path / "study.toml"
    study.write_text(text)
    assert main(["predict", str(study)]) == 0
    out = capsys.readouterr().out
    assert "rubber    E = 2.3 MPa" in out and "rubber    E = 5 MPa" in out
    assert out.count("seal      ring") == 1  # the same seal is described once


def test_table_length_units_follow_the_values(capsys):
    assert main(["predict", "--example", "hrms-study"]) == 0
    out = capsys.readouterr().out
    assert "u_c (nm)" in out  # gaps of a few nm to a few tens of nm
    assert main(["predict", "--example", "reference-experiment"]) == 0
    assert "u_c (µm)" in capsys.readouterr().out


def test_length_unit_choice():
    from sealeak.io.units import length_unit

    assert length_unit([3e-9, 4e-7]) == (1e-9, "nm")  # all below 1 µm
    assert length_unit([2e-2, 0.5]) == (1e-3, "mm")  # all at least 1 cm
    assert length_unit([3e-9, 2e-6, np.nan, 0.0]) == (1e-6, "µm")  # mixed: µm; NaN and zero ignored
    assert length_unit([np.nan]) == (1e-6, "µm")


@pytest.mark.parametrize("argv, line", [
    (["simulate", "--example", "o-ring", "--seed", "x"], "--seed = 'x': must be an integer (options: sealeak simulate --help)"),
    (["simulate", "--example", "o-ring", "--seed"], "--seed: needs a value (options: sealeak simulate --help)"),
    (["surface", "analyze", "m.npy", "--bogus"], "unrecognized arguments: --bogus (options: sealeak surface analyze --help)"),
    (["surface", "analyze"], "the following arguments are required: FILE (options: sealeak surface analyze --help)"),
])
def test_argument_errors_are_one_line_naming_the_option_and_where_to_read(capsys, argv, line):
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    assert capsys.readouterr().err == f"sealeak: error: {line}\n"
