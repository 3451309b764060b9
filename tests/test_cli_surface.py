"""`sealeak surface ...` and `[surface] model = "topography"` case files."""

import json
from pathlib import Path

import numpy as np
import pytest

from sealeak.casefile import example_path, load_cases
from sealeak.cli import main

SAMPLES = Path(__file__).resolve().parents[2] / "shared" / "topography-samples"


def test_synthesize_then_analyze_recovers_h_rms(tmp_path, capsys):
    out = tmp_path / "s.npy"
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--grid", "256", "--seed", "4",
                 "--amplitudes", "phases", "-o", str(out)]) == 0
    h = np.load(out)
    assert h.shape == (256, 256)
    (case,) = load_cases(example_path("reference-experiment"))
    # exact amplitudes: the map's rms equals the rms of C(q) over the modes the grid resolves
    resolved = case.spectrum.truncated(None, np.pi * 256 / case.seal.width)
    assert h.std() == pytest.approx(resolved.h_rms, rel=0.03)
    js = tmp_path / "a.json"
    assert main(["surface", "analyze", str(out), "--size", "5 mm", "--height-unit", "m", "--periodic",
                 "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert doc["units"]["h_rms"] == "m" and doc["units"]["C"] == "m^4"
    assert doc["statistics"]["h_rms"] == pytest.approx(h.std(), rel=1e-9)
    assert len(doc["psd"]["q"]) == len(doc["psd"]["C"]) > 5
    # the same seed gives the same surface
    out2 = tmp_path / "s2.npy"
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--grid", "256", "--seed", "4",
                 "--amplitudes", "phases", "-o", str(out2)]) == 0
    assert np.array_equal(np.load(out2), h)


def test_synthesize_text_output_and_no_overwrite(tmp_path, capsys):
    out = tmp_path / "s.txt"
    args = ["surface", "synthesize", "--example", "hrms-study", "--grid", "64", "-o", str(out)]
    assert main(args) == 0
    assert np.loadtxt(out).shape == (64, 64)
    before = out.read_text()
    assert main(args) == 2
    assert "--force" in capsys.readouterr().err
    assert out.read_text() == before


def test_analyze_needs_units_for_plain_matrix(tmp_path, capsys):
    f = tmp_path / "m.txt"
    np.savetxt(f, np.random.default_rng(0).normal(size=(32, 32)))
    assert main(["surface", "analyze", str(f)]) == 2
    err = capsys.readouterr().err
    assert "sealeak: error:" in err and "Traceback" not in err and "m.txt" in err
    assert main(["surface", "analyze", str(f), "--size", "1 mm", "--height-unit", "um"]) == 0
    assert main(["surface", "analyze", str(f), "--size", "1 kg", "--height-unit", "um"]) == 2
    assert "--size = '1 kg'" in capsys.readouterr().err


def test_case_with_measured_topography(tmp_path):
    h = np.random.default_rng(1).normal(scale=2e-6, size=(128, 128))
    np.save(tmp_path / "map.npy", h)
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")
    text = text[:start] + ('[surface]\nmodel = "topography"\nfile = "map.npy"\nsize = "5 mm"\n'
                           'height_unit = "m"\nperiodic = true\n\n') + text[end:]
    (tmp_path / "case.toml").write_text(text)
    (case,) = load_cases(tmp_path / "case.toml")
    assert "measured topography" in case.spectrum_note
    # white noise: C(q) is flat; h_rms of the measured band is close to the map's (band edges cut some)
    assert 0.2 * 2e-6 < case.spectrum.h_rms < 1.01 * 2e-6
    assert main(["predict", str(tmp_path / "case.toml"), "-q"]) == 0


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
def test_analyze_instrument_files_with_plot(tmp_path):
    pytest.importorskip("SurfaceTopography")
    png = tmp_path / "c.png"
    csv = tmp_path / "c.csv"
    assert main(["surface", "analyze", str(SAMPLES / "di-1.di"), str(SAMPLES / "plu-1.plu"),
                 "--plot", str(png), "--psd-out", str(csv)]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.shape[1] == 2 and np.all(np.diff(data[:, 0]) > 0) and np.all(data[:, 1] > 0)
