"""`sealeak predict --sensitivity N`: Sobol' indices of log10 Q per uncertain input (issue 24 item 3).

A ring seal whose h_rms carries a wide spread and whose E a narrow one: Q depends on h_rms through u_c
and on E through P0/E*, so at every load the wide spread must explain most of the variance of log Q
and the narrow one little. The files must hold the fields the documentation names, the figures must be
written, the same seed must give the same bytes, and bad values must be one line with exit status 2.
"""

from __future__ import annotations

import csv
import io
import json

import pytest

from sealeak.cli import main
from tests.casefiles import BASE, edit

UNCERTAIN = edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2.3 MPa ± 0.5 %"',
                 edit('h_rms = "44 um"', 'h_rms = "44 um ± 15 %"'))
KEYS = ("surface.h_rms", "rubber.youngs_modulus")
FIELDS = ("sobol_first", "sobol_first_conf", "sobol_total", "sobol_total_conf")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sens")
    case = folder / "case.toml"
    case.write_text(UNCERTAIN)
    args = ["predict", str(case), "--samples", "16", "--seed", "3", "--sensitivity", "32", "-q"]
    assert main([*args, "--json", str(folder / "a.json"), "--csv", str(folder / "a.csv"), "--table", str(folder / "a.txt"),
                 "--plots", str(folder / "plots")]) == 0
    assert main([*args, "--json", str(folder / "b.json")]) == 0
    return folder


def test_the_wide_spread_explains_most_of_the_variance_at_every_load(run):
    doc = json.loads((run / "a.json").read_text())
    assert len(doc["results"]) == 3
    for rec in doc["results"]:
        for key in KEYS:
            for field in FIELDS:
                assert doc["units"][f"{field}[{key}]"] == "1"
                assert isinstance(rec[f"{field}[{key}]"], float)
        assert rec["sobol_total[surface.h_rms]"] > 0.8
        assert rec["sobol_total[rubber.youngs_modulus]"] < 0.2
    sens = doc["sensitivity"]
    assert sens["inputs"] == list(KEYS) and sens["base_samples"] == 32 and sens["predictions"] == 32 * 4
    assert sens["seed"] == 3 and sens["output"].startswith("log10")
    assert sens["summaries"][0].startswith("at P0 = 60 kPa: surface.h_rms explains")


def test_same_seed_same_bytes(run):
    assert (run / "a.json").read_bytes() == (run / "b.json").read_bytes()


def test_csv_and_table_carry_the_indices(run):
    rows = list(csv.reader(io.StringIO((run / "a.csv").read_text())))
    header = rows[0]
    for key in KEYS:
        assert f"sobol_total[{key}] (1)" in header and f"sobol_first_conf[{key}] (1)" in header
    doc = json.loads((run / "a.json").read_text())
    col = header.index("sobol_total[surface.h_rms] (1)")
    assert [float(r[col]) for r in rows[1:]] == pytest.approx([r["sobol_total[surface.h_rms]"] for r in doc["results"]], rel=1e-9)
    table = (run / "a.txt").read_text()
    assert "sensitivity: Sobol' indices of log10 Q, 32 base samples (128 predictions, seed 3)" in table
    assert "surface.h_rms ST (S1)" in table and "measure it better first" in table


def test_plots_hold_the_band_the_distribution_and_the_tornado(run):
    for name in ("leak_rate_band.png", "leak_rate_distribution.png", "sensitivity.png", "leak_rate_log.png"):
        assert (run / "plots" / name).read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("value, text", [
    ("12", "--sensitivity = 12: must be a power of two from 16"),
    ("65536", "--sensitivity = 65536: with 2 uncertain inputs runs N·(inputs + 2) = 262144 predictions; at most 16384 (N up to 4096)"),
])
def test_a_bad_sample_size_is_one_line_before_any_sample_runs(tmp_path, capsys, value, text):
    case = tmp_path / "case.toml"
    case.write_text(UNCERTAIN)
    assert main(["predict", str(case), "--sensitivity", value, "--json", str(tmp_path / "out.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and text in err and "sampling" not in err
    assert not (tmp_path / "out.json").exists()


def test_sensitivity_needs_uncertain_inputs(tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(BASE)
    assert main(["predict", str(case), "--sensitivity", "16"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: --sensitivity = 16: the case file has no uncertain inputs")


def test_report_has_the_uncertainty_section_with_its_figures(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(UNCERTAIN)
    out = tmp_path / "r.html"
    assert main(["report", str(case), "--samples", "16", "--sensitivity", "16", "-q", "-o", str(out)]) == 0
    html = out.read_text()
    assert '<h2 id="uncertainty">' in html and '<h3 id="sensitivity">' in html
    for name in ("leak_rate_band.png", "leak_rate_distribution.png", "sensitivity.png"):
        assert f'id="fig-{name}"' in html
    assert html.index('id="fig-leak_rate_band.png"') > html.index('<h2 id="uncertainty">')
