"""An output given as ``-`` goes to standard output, alone, and no file named ``-`` is written."""

import csv
import io
import json

import pytest

from sealeak.cli import main


def _run(args, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc = main(args)
    out, err = capsys.readouterr()
    return rc, out, err


def test_json_to_stdout_is_the_json_file_alone(capsys, tmp_path, monkeypatch):
    rc, out, err = _run(["predict", "--example", "reference-experiment", "--json", "-"], capsys, tmp_path, monkeypatch)
    assert rc == 0
    doc = json.loads(out)  # nothing but the document: the table is not printed
    assert doc["units"]["leak_rate"] == "m^3/s" and len(doc["results"]) > 1
    assert "wrote" not in err and not (tmp_path / "-").exists()
    assert main(["predict", "--example", "reference-experiment", "--json", str(tmp_path / "q.json"), "-q"]) == 0
    assert json.loads((tmp_path / "q.json").read_text()) == doc  # the same document as the file


def test_csv_to_stdout_beside_a_json_file(capsys, tmp_path, monkeypatch):
    rc, out, err = _run(["predict", "--example", "o-ring", "--csv", "-", "--json", "r.json"], capsys, tmp_path,
                        monkeypatch)
    assert rc == 0
    rows = list(csv.reader(io.StringIO(out)))
    assert "compression (1)" in rows[0] and "leak_rate (m^3/s)" in rows[0] and len(rows) > 2
    assert json.loads((tmp_path / "r.json").read_text())["units"]["compression"] == "1"
    assert "wrote r.json" in err and not (tmp_path / "-").exists()


@pytest.mark.parametrize("args, words", [
    (["--json", "-", "--csv", "-"], "only one output may go to standard output"),
    (["--plots", "-"], "is for a file output"),
])
def test_stdout_refused_where_it_cannot_work(args, words, capsys, tmp_path, monkeypatch):
    rc, out, err = _run(["predict", "--example", "o-ring", *args], capsys, tmp_path, monkeypatch)
    assert rc == 2 and out == "" and err.count("\n") == 1 and words in err
    assert not any(tmp_path.iterdir())


def test_surface_json_to_stdout(capsys, tmp_path, monkeypatch):
    import numpy as np

    rng = np.random.default_rng(1)
    np.save(tmp_path / "h.npy", rng.normal(size=(32, 32)))
    rc, out, err = _run(["surface", "analyze", "h.npy", "--pixel-size", "1 um", "--height-unit", "um", "--json", "-"], capsys, tmp_path,
                        monkeypatch)
    assert rc == 0, err
    assert "h_rms" in json.dumps(json.loads(out)) and not (tmp_path / "-").exists()
