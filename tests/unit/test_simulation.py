"""The numerically exact pipeline: reproducibility, bookkeeping, spectrum cut, CLI output."""

import json
from dataclasses import replace

import numpy as np
import pytest

from sealeak import ResourceError
from sealeak.cases import example_path, load_cases, predict
from sealeak.cases.simulation import resolved_spectrum_cut, simulate
from sealeak.cli import main
from sealeak.render.notes import worded


@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([2e4, 8e4, 3e5]))


@pytest.fixture(scope="module")
def run(case):
    return simulate(case, grid=64, realizations=3, seed=7, threshold=True)


def test_shapes_and_bookkeeping(case, run):
    n = 3
    for key in ("relative_contact_area", "mean_gap", "percolating_fraction", "leak_rate", "leak_rate_std",
                "leak_rate_critical_junction", "alpha", "alpha_std"):
        assert getattr(run, key).shape == (n,)
    per = run.per_realization
    assert per["leak_rate"].shape == (3, n)
    # means are means of the realisations; α is the ratio to the α = 1 critical-junction prediction
    assert np.allclose(run.leak_rate, per["leak_rate"].mean(axis=0), rtol=1e-12)
    assert np.allclose(run.percolating_fraction, per["percolates"].mean(axis=0))
    ok = per["percolates"]
    for i in range(3):
        if ok[:, i].any():
            expected = np.mean(per["leak_rate"][ok[:, i], i]) / run.leak_rate_critical_junction[i]
            assert run.alpha[i] == pytest.approx(expected, rel=1e-12, abs=0)
        else:
            assert np.isnan(run.alpha[i])
    # physics: contact grows and the gap and leak rate fall with pressure
    assert np.all(np.diff(run.relative_contact_area) > 0)
    assert np.all(np.diff(run.mean_gap) < 0)
    assert np.all(np.diff(run.leak_rate) < 0)
    assert 0.2 < run.percolation_threshold < 0.8


def test_spectrum_cut_used_by_both_sides(case, run):
    q_cut = resolved_spectrum_cut(64, case.square_side)
    assert q_cut == pytest.approx(2 * np.pi * 64 / (4 * 5e-3))
    assert run.q_cut == pytest.approx(q_cut)
    assert any("cut" in n for n in worded(run.notes))
    cut = replace(case, spectrum=case.spectrum.truncated(None, q_cut), alpha=1.0)
    expected = predict(cut).leak_rate
    assert np.allclose(run.leak_rate_critical_junction, expected, rtol=1e-12, equal_nan=True)


def test_reproducible_by_seed(case, run):
    again = simulate(case, grid=64, realizations=3, seed=7, threshold=False)
    assert np.array_equal(again.per_realization["leak_rate"], run.per_realization["leak_rate"])
    other = simulate(case, grid=64, realizations=1, seed=8, threshold=False)
    assert not np.allclose(other.per_realization["leak_rate"][0], run.per_realization["leak_rate"][0])
    assert np.isnan(other.leak_rate_std).all()  # one realisation: no spread


def test_memory_refused_up_front(case):
    with pytest.raises(ResourceError, match="GiB|MiB|bytes"):
        simulate(case, grid=4096, realizations=1, seed=0, memory_limit=1e8)


def test_cli_simulate_outputs(tmp_path, case):
    text = example_path("reference-experiment").read_text().replace(
        '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }', '["30 kPa", "100 kPa"]')
    (tmp_path / "c.toml").write_text(text)
    js, figs, fields = tmp_path / "s.json", tmp_path / "figs", tmp_path / "fields"
    args = ["simulate", str(tmp_path / "c.toml"), "--grid", "32", "--realizations", "2", "--seed", "1",
            "--json", str(js), "--plots", str(figs), "--fields", str(fields), "-q"]
    assert main(args) == 0
    doc = json.loads(js.read_text())
    assert doc["units"]["leak_rate"] == "m^3/s" and doc["units"]["alpha"] == "1"
    row = doc["results"][0]
    for key in ("squeeze_pressure", "relative_contact_area", "mean_gap", "percolating_fraction", "leak_rate",
                "leak_rate_std", "leak_rate_critical_junction", "alpha", "alpha_std"):
        assert key in row
    assert "percolation_threshold" in doc and "percolation_threshold_std" in doc
    for name in ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png"):
        assert (figs / name).read_bytes()[:4] == b"\x89PNG"
    f = np.load(fields / "r1-p0.npz")
    assert f["height"].shape == f["gap"].shape == f["pressure"].shape == (32, 32)
    assert float(f["size"]) == pytest.approx(5e-3)
    assert np.all(f["gap"] >= 0) and np.all(f["pressure"] >= 0)
    assert np.mean(f["pressure"]) == pytest.approx(3e4, rel=1e-6)
    # the same command again refuses to overwrite
    assert main(args) == 2
