"""``sealeak predict`` and ``report`` with uncertain inputs: the band under the table, the files, the refusals."""

import json
import warnings

import pytest

from sealeak.cli import main
from tests.casefiles import BASE, edit

SPREAD = edit('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"',
              edit('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "1 m^3/s"'))


def test_predict_prints_and_writes_the_band(tmp_path, capsys):
    case = tmp_path / "c.toml"
    case.write_text(SPREAD)
    out = tmp_path / "r.json"
    assert main(["predict", str(case), "--samples", "8", "--seed", "2", "--json", str(out), "--csv", str(tmp_path / "r.csv")]) == 0
    printed = capsys.readouterr()
    assert "uncertainty: 8 samples" in printed.out and "surface.h_rms: 44 um ± 10 %" in printed.out
    assert "P(Q > max)" in printed.out and "sampling 1 uncertain input" in printed.err
    doc = json.loads(out.read_text())
    assert all(r["exceed_probability"] == 0.0 for r in doc["results"])  # 1 m³/s: far above any row
    assert doc["uncertainty"]["seed"] == 2 and doc["uncertainty"]["compared_with"] == "leak_rate"
    header = (tmp_path / "r.csv").read_text().splitlines()[0]
    assert "leak_rate_p95 (m^3/s)" in header and "sealed_fraction (1)" in header


def test_report_shows_the_band(tmp_path):
    case = tmp_path / "c.toml"
    case.write_text(SPREAD)
    assert main(["report", str(case), "--samples", "4", "-o", str(tmp_path / "r.html"), "-q"]) == 0
    html = (tmp_path / "r.html").read_text()
    assert 'id="uncertainty"' in html and "Q p95" in html


def test_samples_without_uncertain_inputs_is_one_line(tmp_path, capsys):
    case = tmp_path / "c.toml"
    case.write_text(BASE)
    assert main(["predict", str(case), "--samples", "64", "--json", str(tmp_path / "r.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--samples = 64" in err and "no uncertain inputs" in err
    assert not (tmp_path / "r.json").exists()


def test_bad_samples_leave_no_file(tmp_path, capsys):
    case = tmp_path / "c.toml"
    case.write_text(SPREAD)
    assert main(["predict", str(case), "--samples", "100", "--json", str(tmp_path / "r.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "powers of two" in err and "Traceback" not in err
    assert not (tmp_path / "r.json").exists()


def test_web_predict_gives_the_band_as_the_command_line_does(tmp_path):
    """POST /api/predict answers what `sealeak predict --json` writes: with uncertain inputs, the band (α and η only:
    the samples share the nominal contact, so this runs in a moment)."""
    pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from fastapi.testclient import TestClient
    from sealeak.web import create_app

    text = edit("alpha = 0.2", 'alpha = "0.2 ± 0.05"', edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s ± 10 %"'))
    (tmp_path / "c.toml").write_text(text)
    assert main(["predict", str(tmp_path / "c.toml"), "--json", str(tmp_path / "r.json"), "-q"]) == 0
    with TestClient(create_app(), base_url="http://127.0.0.1:8765") as client:
        answer = client.post("/api/predict", content=text.encode(), headers={"Content-Type": "application/toml"})
    assert answer.status_code == 200
    web, cli = answer.json(), json.loads((tmp_path / "r.json").read_text())
    assert web["uncertainty"] == cli["uncertainty"]
    assert [r["leak_rate_p95"] for r in web["results"]] == [r["leak_rate_p95"] for r in cli["results"]]
