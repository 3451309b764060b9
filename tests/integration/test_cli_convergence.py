"""``sealeak simulate --grid N1,N2,...``: the convergence study from the command line (table, JSON, figures, refusals)."""

import contextlib
import io
import json

import pytest
from matplotlib.image import imread

from sealeak.cases import example_path
from sealeak.cli import main

from .test_cli_simulate_oring import ORING

CASE = example_path("reference-experiment").read_text().replace(
    '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }', '["25 kPa", "40 kPa"]')


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One study at grids 32 and 64 (R = 2), its table, JSON and figures; and the single-grid JSON at 64."""
    d = tmp_path_factory.mktemp("conv")
    (d / "c.toml").write_text(CASE)
    out = {}
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["simulate", str(d / "c.toml"), "--grid", "32,64", "--realizations", "2", "--seed", "3",
                     "--json", str(d / "s.json"), "--plots", str(d / "p")]) == 0
        assert main(["simulate", str(d / "c.toml"), "--grid", "64", "--realizations", "2", "--seed", "3",
                     "--json", str(d / "one.json"), "-q"]) == 0
    out["table"] = buf.getvalue()
    out["dir"] = d
    return out


def test_table_json_and_figures_are_written(run):
    d, table = run["dir"], run["table"]
    assert "convergence study" in table and "percolation threshold against published values" in table
    assert "Dapp et al., PRL 108 (2012) 244301: 0.42" in table and "Wang & Müser" in table
    assert "only 2 realisations per grid" in table and "rests on 2 grids" in table
    doc = json.loads((d / "s.json").read_text())
    assert [g["grid"] for g in doc["grids"]] == [32, 64]
    assert {"extrapolation", "threshold", "flags"} <= set(doc)
    assert [c["published"] for c in doc["threshold"]["comparison"][:2]] == [0.42, 0.415]
    # the study's records at N = 64 are those of the single-grid run at 64, plus the standard errors
    one = json.loads((d / "one.json").read_text())
    for row, single in zip(doc["grids"][1]["results"], one["results"], strict=True):
        assert {k: row[k] for k in single} == single
        assert {"alpha_stderr", "alpha_count", "relative_contact_area_stderr"} <= set(row)
    assert doc["grids"][1]["percolation_threshold"] == one["percolation_threshold"]
    for name in ("convergence_alpha.png", "convergence_threshold.png"):
        img = imread(d / "p" / name)
        assert img.shape[0] > 500 and img.shape[1] > 500


@pytest.mark.parametrize("bad", ["32,63", "32,,64", "abc", "32,32", "16,8"])
def test_bad_grid_lists_are_refused(tmp_path, capsys, bad):
    (tmp_path / "c.toml").write_text(CASE)
    capsys.readouterr()
    assert main(["simulate", str(tmp_path / "c.toml"), "--grid", bad, "--json", str(tmp_path / "s.json"),
                 "--plots", str(tmp_path / "p")]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sealeak: error: --grid") and "Traceback" not in err, err
    assert out == "" and not (tmp_path / "s.json").exists() and not (tmp_path / "p").exists()


def test_case_file_grid_list_runs_the_study(tmp_path, capsys):
    (tmp_path / "c.toml").write_text(CASE + "\n[simulation]\ngrid = [32, 48]\nrealizations = 1\n")
    capsys.readouterr()
    assert main(["simulate", str(tmp_path / "c.toml"), "--no-threshold", "--json", str(tmp_path / "s.json")]) == 0
    out, _ = capsys.readouterr()
    assert "grids 32, 48" in out and "only 1 realisation per grid" in out
    assert [g["grid"] for g in json.loads((tmp_path / "s.json").read_text())["grids"]] == [32, 48]
    for bad in ("grid = [32, 33]", "grid = [32, 32]", 'grid = ["32"]'):
        (tmp_path / "bad.toml").write_text(CASE + f"\n[simulation]\n{bad}\n")
        assert main(["simulate", str(tmp_path / "bad.toml"), "-q"]) == 2
        assert "simulation.grid" in capsys.readouterr().err


def test_store_keeps_one_folder_per_grid(tmp_path, capsys):
    (tmp_path / "c.toml").write_text(CASE)
    argv = ["simulate", str(tmp_path / "c.toml"), "--grid", "32,48", "--realizations", "1", "--no-threshold",
            "--store", str(tmp_path / "st"), "--json"]
    assert main(argv + [str(tmp_path / "a.json"), "-q"]) == 0
    assert sorted(p.name for p in (tmp_path / "st").iterdir()) == ["grid-32", "grid-48"]
    for n in (32, 48):
        assert json.loads((tmp_path / "st" / f"grid-{n}" / "manifest.json").read_text())["grid"] == n
    capsys.readouterr()
    assert main(argv + [str(tmp_path / "b.json")]) == 0
    assert "resumed: 1 of 1 tasks" in capsys.readouterr().err
    assert json.loads((tmp_path / "a.json").read_text())["grids"] == json.loads((tmp_path / "b.json").read_text())["grids"]


def test_o_ring_with_a_grid_list_is_refused(tmp_path, capsys):
    (tmp_path / "o.toml").write_text(ORING)
    capsys.readouterr()
    assert main(["simulate", str(tmp_path / "o.toml"), "--grid", "32,64"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: --grid") and "O-ring takes one grid" in err and len(err.splitlines()) == 1


def test_a_list_of_one_grid_is_the_ordinary_run(tmp_path):
    """`[simulation] grid = [32]` and `--grid 32` write byte for byte the JSON of the plain single-grid run."""
    (tmp_path / "one.toml").write_text(CASE + "\n[simulation]\ngrid = [32]\nrealizations = 2\n")
    (tmp_path / "plain.toml").write_text(CASE + "\n[simulation]\ngrid = 32\nrealizations = 2\n")
    assert main(["simulate", str(tmp_path / "one.toml"), "--json", str(tmp_path / "a.json"), "-q"]) == 0
    assert main(["simulate", str(tmp_path / "plain.toml"), "--grid", "32", "--json", str(tmp_path / "b.json"), "-q"]) == 0
    a, b = (tmp_path / "a.json").read_bytes(), (tmp_path / "b.json").read_bytes()
    assert a.replace(b"one.toml", b"plain.toml") == b and b'"grids"' not in b
