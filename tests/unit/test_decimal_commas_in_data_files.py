"""Decimal commas in data files are refused, not read as separators (topography text matrices, C(q)
tables, measured data), through the CLI: exit 2, one line naming the file and line, no output."""

import numpy as np
import pytest

from sealeak.cli import main
from tests.casefiles import edit


def _matrix(rows=8, cols=8, seed=1):
    return np.random.default_rng(seed).normal(size=(rows, cols))


def _write_matrix(path, sep, decimal_comma):
    lines = []
    for row in _matrix():
        line = sep.join(f"{v:.4f}" for v in row)
        lines.append(line.replace(".", ",") if decimal_comma else line)
    path.write_text("\n".join(lines) + "\n")


def _refused_in_one_line(capsys, path, line):
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert str(path) in lines[0] and f"line {line}" in lines[0]
    assert "',' is not allowed in numbers" in lines[0]
    return lines[0]


@pytest.mark.parametrize("sep", [";", " ", "\t", "; ", " ; "])
def test_topography_matrix_with_decimal_commas_is_refused(tmp_path, capsys, sep):
    path = tmp_path / "comma.txt"
    _write_matrix(path, sep, decimal_comma=True)
    json_out = tmp_path / "out.json"
    assert main(["surface", "analyze", str(path), "--size", "1 mm", "--height-unit", "um", "--json", str(json_out)]) == 2
    message = _refused_in_one_line(capsys, path, 1)
    first = f"{_matrix()[0, 0]:.4f}"
    assert f"write {first}" in message  # says how to write the first offending value
    assert not json_out.exists()


@pytest.mark.parametrize("text, line", [
    ("1,5 2,3 0,5 1,0\n1,0 2,0 3,0 4,0\n", 1),  # ambiguous: a space-separated line of numbers with commas
    ("# comment\n0.5 0.3 0.1 0.2\n0.4 1,5 0.2 0.1\n", 3),  # one decimal comma in an otherwise good matrix
    ("1;2;3;4\n5;6;7;1,000\n", 2),  # thousands separator
    ("0,3456 -1,3032e-1 0,8216 1\n1 2 3 4\n", 1),
])
def test_topography_lines_with_a_comma_inside_a_value_are_refused(tmp_path, capsys, text, line):
    path = tmp_path / "heights.txt"
    path.write_text(text)
    assert main(["surface", "analyze", str(path), "--size", "1 mm", "--height-unit", "um"]) == 2
    _refused_in_one_line(capsys, path, line)


@pytest.mark.parametrize("sep", [",", ", "])
def test_comma_separated_matrix_still_reads(tmp_path, capsys, sep):
    path = tmp_path / "good.csv"
    _write_matrix(path, sep, decimal_comma=False)
    json_out = tmp_path / "out.json"
    assert main(["surface", "analyze", str(path), "--size", "1 mm", "--height-unit", "um", "--json", str(json_out)]) == 0
    assert json_out.exists()
    out, _ = capsys.readouterr()
    assert main(["surface", "analyze", str(path), "--size", "1 mm", "--height-unit", "um"]) == 0
    out, _ = capsys.readouterr()
    assert "8x8 points" in out  # every value one pixel: the commas are separators


PSD_BAD = [
    ("1e3 1,5e-20\n1e4 1e-23\n1e5 1e-26\n", 1),  # first row: not to be taken for a header
    ("1e3 1e-20\n1e4 1,5e-23\n1e5 1e-26\n", 2),
    ("1,0e3 1e-20\n1e4 1e-23\n1e5 1e-26\n", 1),
    ("q (1/m) C (m^4)\n1e3 1e-20\n1e4 1e-23\n1e5 1,5e-26\n", 4),
    ("1e3\t1,5e-20\n1e4\t1e-23\n1e5\t1e-26\n", 1),
]


@pytest.mark.parametrize("text, line", PSD_BAD)
def test_psd_table_with_decimal_comma_is_refused_by_synthesize(tmp_path, capsys, text, line):
    table = tmp_path / "psd.txt"
    table.write_text(text)
    out = tmp_path / "map.npz"
    assert main(["surface", "synthesize", "--psd", str(table), "--size", "1 mm", "--grid", "32", "-o", str(out)]) == 2
    _refused_in_one_line(capsys, table, line)
    assert not out.exists()


@pytest.mark.parametrize("text, line", PSD_BAD[:2])
def test_psd_table_with_decimal_comma_is_refused_in_a_case_file(tmp_path, capsys, text, line):
    table = tmp_path / "psd.txt"
    table.write_text(text)
    case = tmp_path / "case.toml"
    case.write_text(edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                         'cutoff_wavelength = "20 um"', 'model = "table"\nfile = "psd.txt"'))
    json_out = tmp_path / "out.json"
    assert main(["predict", str(case), "--json", str(json_out)]) == 2
    _refused_in_one_line(capsys, table, line)
    assert not json_out.exists()


def test_headerless_space_separated_psd_table_reads_all_rows(tmp_path, capsys):
    table = tmp_path / "psd.txt"
    table.write_text("1e3 1e-20\n1e4 1e-23\n1e5 1e-26\n")
    out = tmp_path / "map.npz"
    assert main(["surface", "synthesize", "--psd", str(table), "--size", "1 mm", "--grid", "32", "-o", str(out), "-q"]) == 0
    assert out.exists()


@pytest.mark.parametrize("row", ["30 17,2", "30,5 17", "30 1,000"])
def test_fit_data_with_a_decimal_comma_names_it(tmp_path, capsys, row):
    data = tmp_path / "measured.txt"
    data.write_text(f"squeeze_pressure (kPa) leak_rate (ml/min)\n20 380\n{row}\n40 5\n")
    json_out = tmp_path / "fit.json"
    assert main(["fit", "--example", "reference-experiment", "--data", str(data), "--json", str(json_out)]) == 2
    message = _refused_in_one_line(capsys, data, 3)
    assert "is not a number" not in message
    assert not json_out.exists()
