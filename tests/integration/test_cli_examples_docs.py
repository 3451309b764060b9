"""The bundled example data file: printed by `sealeak examples`, refused as a case, usable by `sealeak fit`."""

import json

import pytest

from sealeak.cases import example_path, fit_models, load_case
from sealeak.cases.loader import example_data_names, example_description, example_names, example_text
from sealeak.cli import main
from sealeak.lab import read_leak_data

DATA = "reference-measured.csv"


def test_data_file_is_bundled_apart_from_the_cases():
    assert DATA in example_data_names()
    assert DATA not in example_names()  # cases stay cases: everything iterating example_names() loads a case
    assert "reference-experiment" in example_description(DATA)
    assert example_description("reference-experiment").startswith("PDMS ring")


def test_examples_prints_the_data_file(capsys, tmp_path):
    assert main(["examples", DATA]) == 0
    text = capsys.readouterr().out
    assert text == example_text(DATA)
    (tmp_path / "measured.csv").write_text(text)
    data = read_leak_data(tmp_path / "measured.csv")
    assert len(data.squeeze_pressure) == 8 and (data.leak_rate > 0).all()


@pytest.mark.parametrize("command", [["predict"], ["simulate"], ["rig"], ["report", "-o", "r.html"]])
def test_data_file_is_not_a_case(command, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main([*command, "--example", DATA]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert DATA in err and "data file" in err
    assert not any(tmp_path.iterdir())


def test_fit_to_the_data_file_finds_the_alpha_it_was_made_with(tmp_path):
    """The file is the reference case's prediction (α = 0.2) with 15 % log-normal scatter on 8 points:
    the fitted α lies within a few standard errors of 0.2, and the standard error is about 0.15/√8 in ln α."""
    (tmp_path / "m.csv").write_text(example_text(DATA))
    case = load_case(example_path("reference-experiment"))
    data = read_leak_data(tmp_path / "m.csv")
    fit = fit_models(case, data.squeeze_pressure, data.pressure_difference, data.leak_rate)["critical_junction"]
    assert abs(fit.alpha - 0.2) < 3 * fit.alpha_std
    assert 0.02 < fit.alpha_std / fit.alpha < 0.15
    out = tmp_path / "fit.json"
    assert main(["fit", "--example", "reference-experiment", "--data", str(tmp_path / "m.csv"), "--json", str(out),
                 "-q"]) == 0
    assert json.loads(out.read_text())["critical_junction"]["alpha"] == pytest.approx(fit.alpha, rel=1e-12, abs=0)


def test_fit_of_rows_repeating_one_measurement_says_alpha_has_no_standard_error(tmp_path, capsys):
    """Four copies of one row of the bundled data printed "± se 0" and no note."""
    header, row = [line for line in example_text(DATA).splitlines() if not line.startswith("#")][:2]
    (tmp_path / "same.csv").write_text("\n".join([header] + [row] * 4) + "\n")
    assert main(["fit", "--example", "reference-experiment", "--data", str(tmp_path / "same.csv")]) == 0
    out = capsys.readouterr().out
    assert "4 usable rows repeat one measurement" in out and "α has no standard error" in out
