"""``[seal] force_factor`` and ``[seal] force_table`` of an O-ring through `sealeak predict` (docs/case-files.md)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from sealeak.cli import main
from tests.integration.test_cli_band import ORING

E = 5.5e6  # Pa, the case's modulus (ν = 0.5)
D = 2.62e-3  # m
LINE = 'inner_diameter = "20 mm"'


def _run(tmp_path, capsys, text, csv=None, name="o.json"):
    if csv is not None:
        (tmp_path / "f.csv").write_text(csv, encoding="utf-8")
    case = tmp_path / "c.toml"
    case.write_text(text, encoding="utf-8")
    out = tmp_path / name
    rc = main(["predict", str(case), "--json", str(out), "--force", "-q"])
    return rc, out, capsys.readouterr().err


def _rows(tmp_path, capsys, text, csv=None):
    rc, out, err = _run(tmp_path, capsys, text, csv)
    assert rc == 0, err
    return json.loads(out.read_text())["results"]


def test_factor_one_changes_nothing(tmp_path, capsys):
    _, plain, _ = _run(tmp_path, capsys, ORING, name="plain.json")
    _, one, _ = _run(tmp_path, capsys, ORING.replace(LINE, LINE + "\nforce_factor = 1"), name="one.json")
    a, b = json.loads(plain.read_text()), json.loads(one.read_text())
    assert a["results"] == b["results"]  # same machine, same numbers: bit for bit


def test_factor_two_doubles_the_force_and_the_mean_pressure(tmp_path, capsys):
    plain = _rows(tmp_path, capsys, ORING)
    doubled = _rows(tmp_path, capsys, ORING.replace(LINE, LINE + "\nforce_factor = 2"))
    for p, d in zip(plain, doubled, strict=True):
        assert d["force_per_length"] == pytest.approx(2 * p["force_per_length"], rel=1e-12)
        assert d["mean_contact_pressure"] == pytest.approx(2 * p["mean_contact_pressure"], rel=1e-12)
        assert d["contact_width"] == p["contact_width"]
        assert (d["leak_rate"] or 0.0) <= (p["leak_rate"] or 0.0)  # more force, less leak
    both = [(p["leak_rate"], d["leak_rate"]) for p, d in zip(plain, doubled, strict=True) if p["leak_rate"] and d["leak_rate"]]
    assert both and all(q2 < q1 for q1, q2 in both)  # a load that leaks either way leaks strictly less


def test_a_table_of_lindleys_values_reproduces_lindley(tmp_path, capsys):
    grid = np.linspace(10, 35, 11)  # %
    f = E * D * (1.25 * (grid / 100) ** 1.5 + 50 * (grid / 100) ** 6) / 1e3  # N/mm
    csv = "# Lindley (1967) by hand\ncompression (%), line_load (N/mm)\n" + "".join(
        f"{e:.6g}, {v:.9g}\n" for e, v in zip(grid, f, strict=True))
    plain = _rows(tmp_path, capsys, ORING)
    tabled = _rows(tmp_path, capsys, ORING.replace(LINE, LINE + '\nforce_table = "f.csv"'), csv)
    for p, t in zip(plain, tabled, strict=True):
        assert t["force_per_length"] == pytest.approx(p["force_per_length"], rel=2e-3)
        assert t["contact_width"] == p["contact_width"]


@pytest.mark.parametrize("csv, words", [
    ("compression (%), line_load (N/mm)\n10, 1\n", "two"),
    ("compression (%), line_load (N/mm)\n5, 1\n20, 3\n15, 4\n40, 9\n", "increase"),
    ("compression (%), line_load (N/mm)\n5, 1\n20, 3\n30, 2\n40, 9\n", "increase"),
    ("compression (%), line_load (N/mm)\n5, -1\n40, 9\n", "negative"),
    ("compression (%), line_load (MPa)\n5, 1\n40, 9\n", "force per length"),
    ("compression (%), line_load\n5, 1\n40, 9\n", "no unit"),
    ("x (mm), pressure (MPa)\n5, 1\n40, 9\n", "compression and line_load"),
    ("\x00\x01 not a table", "f.csv"),
    ("compression (%), line_load (N/mm)\n12, 1\n40, 9\n", "conditions.compression"),  # 10 % is below the table
])
def test_bad_table_is_one_line_and_no_output(tmp_path, capsys, csv, words):
    rc, out, err = _run(tmp_path, capsys, ORING.replace(LINE, LINE + '\nforce_table = "f.csv"'), csv)
    assert rc == 2
    assert err.count("\n") == 1 and "Traceback" not in err and words in err, err
    assert not out.exists()


def test_missing_table_and_bad_factor_name_the_key(tmp_path, capsys):
    rc, out, err = _run(tmp_path, capsys, ORING.replace(LINE, LINE + '\nforce_table = "none.csv"'))
    assert rc == 2 and "none.csv" in err and not out.exists()
    rc, out, err = _run(tmp_path, capsys, ORING.replace(LINE, LINE + "\nforce_factor = 0"))
    assert rc == 2 and "seal.force_factor" in err and err.count("\n") == 1 and not out.exists()


def test_force_never_replaces_the_table(tmp_path, capsys):
    csv = "compression (%), line_load (N/mm)\n5, 1\n40, 9\n"
    (tmp_path / "f.csv").write_text(csv, encoding="utf-8")
    case = tmp_path / "c.toml"
    case.write_text(ORING.replace(LINE, LINE + '\nforce_table = "f.csv"'), encoding="utf-8")
    assert main(["predict", str(case), "--json", str(tmp_path / "f.csv"), "--force", "-q"]) == 2
    err = capsys.readouterr().err
    assert "even with --force" in err and err.count("\n") == 1
    assert (tmp_path / "f.csv").read_text(encoding="utf-8") == csv

