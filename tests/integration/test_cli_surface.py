"""`sealeak surface ...` and `[surface] model = "topography"` case files."""

import json
from pathlib import Path

import numpy as np
import pytest

import sealeak.numerics._memory as memory_module
from sealeak.cases import example_path, load_cases
from sealeak.cli import main

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"


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
    assert doc["statistics"]["h_rms"] == pytest.approx(h.std(), rel=1e-9, abs=0)
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


@pytest.mark.parametrize("name, magic", [("c.pdf", b"%PDF"), ("c.svg", b"<?xml"), ("c.PNG", b"\x89PNG")])
def test_analyze_plot_format_follows_the_file_name(tmp_path, name, magic):
    h = np.random.default_rng(3).normal(scale=1e-6, size=(64, 64))
    np.save(tmp_path / "map.npy", h)
    out = tmp_path / name
    assert main(["surface", "analyze", str(tmp_path / "map.npy"), "--size", "1 mm", "--height-unit", "m", "--plot", str(out)]) == 0
    assert out.read_bytes()[:len(magic)] == magic


def test_analyze_plot_of_another_format_is_refused_before_anything_is_written(tmp_path, capsys, monkeypatch):
    np.save(tmp_path / "map.npy", np.random.default_rng(3).normal(size=(64, 64)))
    monkeypatch.chdir(tmp_path)  # the output named as given, short (a long path is shown cut in the middle)
    out, js = Path("c.jpg"), Path("c.json")
    assert main(["surface", "analyze", str(tmp_path / "map.npy"), "--size", "1 mm", "--height-unit", "um", "--plot", str(out),
                 "--json", str(js)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"sealeak: error: --plot = '{out}': must end in .png, .pdf or .svg (the file's format follows its name)"]
    assert not out.exists() and not js.exists()


# ---------------------------------------------------------------------------- synthesize: errors, formats, size
def _no_traceback(err: str) -> None:
    assert "sealeak: error:" in err and "Traceback" not in err


@pytest.mark.parametrize("args,flag", [
    (["--grid", "200000"], "--grid"),  # about 480 GiB: refused before any allocation
    (["--grid", "63"], "--grid"),
    (["--grid", "-8"], "--grid"),
    (["--seed", "-1"], "--seed"),
])
def test_synthesize_user_mistakes_are_clean_errors(tmp_path, capsys, monkeypatch, args, flag):
    monkeypatch.setattr(memory_module, "available_memory_bytes", lambda: 16 * 2**30)  # whatever this machine has
    out = tmp_path / "s.npy"
    assert main(["surface", "synthesize", "--example", "hrms-study", *args, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    _no_traceback(err)
    assert flag in err
    assert not out.exists() and not (tmp_path / "s.npy.json").exists()


def test_synthesize_memory_message_names_the_grid(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(memory_module, "available_memory_bytes", lambda: 16 * 2**30)  # whatever this machine has
    assert main(["surface", "synthesize", "--example", "hrms-study", "--grid", "200000",
                 "-o", str(tmp_path / "s.npz")]) == 2
    err = capsys.readouterr().err
    assert "GiB" in err and "available" in err


def test_synthesize_formats_round_trip_with_their_size(tmp_path, capsys):
    from sealeak.topography import read_topography

    base = ["surface", "synthesize", "--example", "hrms-study", "--grid", "64", "--seed", "7", "--size", "0.3 mm"]
    maps = {}
    for suffix in (".npy", ".npz", ".txt", ".csv"):
        out = tmp_path / f"s{suffix}"
        assert main([*base, "-o", str(out)]) == 0
        t = read_topography(out)  # no unit options: the files state size, unit and periodicity
        assert t.size == pytest.approx((3e-4, 3e-4), rel=1e-15, abs=0) and t.periodic
        maps[suffix] = t.heights
    assert (tmp_path / "s.npy.json").is_file()
    # the same seed gives the same map in every format, in the same orientation (text: one row per y)
    for suffix in (".npz", ".txt", ".csv"):
        np.testing.assert_array_equal(maps[suffix], maps[".npy"])
    raw = np.load(tmp_path / "s.npy")
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "s.txt"), raw.T)
    # analyze reads them without unit options, as periodic maps (no window)
    js = tmp_path / "a.json"
    assert main(["surface", "analyze", str(tmp_path / "s.txt"), "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert doc["sources"][0]["size"] == pytest.approx([3e-4, 3e-4]) and doc["sources"][0]["periodic"]
    assert doc["statistics"]["h_rms"] == pytest.approx(np.std(raw), rel=1e-12, abs=0)
    # overwriting needs --force, for the sidecar too
    assert main([*base, "-o", str(tmp_path / "s.npy")]) == 2
    assert "--force" in capsys.readouterr().err


# ---------------------------------------------------------------------------- analyze: units and ranges
def _matrix(tmp_path, nx=40, ny=20):
    p = tmp_path / "m.txt"
    h = np.random.default_rng(2).normal(size=(nx, ny))
    np.savetxt(p, h.T)  # one row per y
    return p


def _json_source(tmp_path, args):
    js = tmp_path / "o.json"
    assert main(["surface", "analyze", *args, "--json", str(js), "--force"]) == 0
    return json.loads(js.read_text())["sources"][0]


def test_analyze_size_pair_and_pixel_size(tmp_path):
    p = str(_matrix(tmp_path))
    src = _json_source(tmp_path, [p, "--size", "1 mm, 0.5 mm", "--height-unit", "um"])
    assert src["grid"] == [40, 20] and src["size"] == pytest.approx([1e-3, 5e-4])
    # reliable range: from 3·2π/(shorter side) to wavelengths of 4 pixels (the larger pixel)
    assert src["reliable_range"] == pytest.approx([3 * 2 * np.pi / 5e-4, 2 * np.pi / (4 * 25e-6)])
    src = _json_source(tmp_path, [p, "--pixel-size", "2 um", "--height-unit", "um"])
    assert src["size"] == pytest.approx([80e-6, 40e-6])
    src = _json_source(tmp_path, [p, "--pixel-size", "2 um, 1 um", "--height-unit", "nm"])
    assert src["size"] == pytest.approx([80e-6, 20e-6])
    assert src["statistics"]["h_rms"] < 1e-8  # nm heights
    src = _json_source(tmp_path, [str(_matrix(tmp_path, 200, 100)), "--pixel-size", "1 um", "--height-unit", "um",
                                  "--low-cut", "2", "--resolution", "10 um"])
    assert src["reliable_range"] == pytest.approx([2 * 2 * np.pi / 100e-6, 2 * np.pi / 10e-6])


def test_analyze_asks_for_all_missing_units_with_cli_flags(tmp_path, capsys):
    p = str(_matrix(tmp_path))
    assert main(["surface", "analyze", p]) == 2
    err = capsys.readouterr().err
    _no_traceback(err)
    assert "m.txt" in err and "--height-unit" in err and "--size" in err and "--pixel-size" in err
    assert "height_unit" not in err and "pixel_size" not in err
    q = tmp_path / "xh.txt"
    q.write_text("0 1\n1 2\n2.5 1\n3 0\n4 1\n")
    assert main(["surface", "analyze", str(q)]) == 2
    err = capsys.readouterr().err
    assert "--height-unit" in err and "--lateral-unit" in err and "lateral_unit" not in err
    assert main(["surface", "analyze", p, "--size", "1 mm", "--height-unit", "um", "--resolution", "3 kg"]) == 2
    assert "--resolution" in capsys.readouterr().err
    assert main(["surface", "analyze", p, "--size", "1 mm", "--height-unit", "um", "--low-cut", "0.5"]) == 2
    assert "--low-cut" in capsys.readouterr().err


def test_analyze_two_files_json_statistics_are_filled(tmp_path):
    from sealeak.numerics.synthesis import synthesize
    from sealeak.physics.spectrum import PowerSpectrum

    model = PowerSpectrum.self_affine(hurst=0.7, q_rolloff=10**4.5, q_cutoff=10**6.5, q_lowest=10**3.5, h_rms=1e-6)
    np.save(tmp_path / "coarse.npy", synthesize(model, 256, 5e-3, seed=1))
    np.save(tmp_path / "fine.npy", synthesize(model, 256, 5e-3 / 8, seed=2))
    js = tmp_path / "a.json"
    # one --size for both would be wrong: give each file its size through .npz instead
    for name, size in (("coarse", 5e-3), ("fine", 5e-3 / 8)):
        np.savez(tmp_path / f"{name}.npz", heights=np.load(tmp_path / f"{name}.npy"), size=np.array([size, size]),
                 height_unit=np.array("m"), periodic=np.array(True))
    assert main(["surface", "analyze", str(tmp_path / "coarse.npz"), str(tmp_path / "fine.npz"),
                 "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    st = doc["statistics"]
    for key in ("h_rms", "slope_rms", "curvature_rms", "area_ratio", "skewness", "kurtosis"):
        assert isinstance(st[key], float), key
    # h_rms of the combined C(q), integrated independently from the "psd" table (log-log interpolation)
    q, C = np.array(doc["psd"]["q"]), np.array(doc["psd"]["C"])
    qs = np.geomspace(q[0], q[-1], 20001)
    Cs = np.exp(np.interp(np.log(qs), np.log(q), np.log(C)))
    assert st["h_rms"] == pytest.approx(np.sqrt(2 * np.pi * np.trapezoid(qs * Cs, qs)), rel=1e-3)
    assert st["slope_rms"] == pytest.approx(np.sqrt(2 * np.pi * np.trapezoid(qs**3 * Cs, qs)), rel=1e-3)
    assert st["slope_rms"] == pytest.approx(model.truncated(q[0], q[-1]).slope_rms, rel=0.1)
    assert [s["size"][0] for s in doc["sources"]] == pytest.approx([5e-3, 5e-3 / 8])
    assert all(s["statistics"]["h_rms"] > 0 for s in doc["sources"])


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
def test_analyze_sample_that_is_a_plane_is_refused(tmp_path, capsys):
    pytest.importorskip("SurfaceTopography")
    js = tmp_path / "s.json"
    assert main(["surface", "analyze", str(SAMPLES / "nc-1.nc"), "--json", str(js)]) == 2  # 5×10 points on a plane
    out, err = capsys.readouterr()
    _no_traceback(err)
    assert "nc-1.nc" in err and "plane" in err and out == "" and not js.exists()


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
@pytest.mark.parametrize("name,extra", [("matrix-5.txt", ["--size", "10 um", "--height-unit", "um"])])
def test_analyze_small_maps_give_statistics_and_the_reason(tmp_path, capsys, name, extra):
    js = tmp_path / "s.json"
    assert main(["surface", "analyze", str(SAMPLES / name), *extra, "--json", str(js)]) == 0
    out = capsys.readouterr().out
    assert "h_rms" in out and "too small for a reliable C(q)" in out and name in out
    doc = json.loads(js.read_text())
    assert doc["psd"] is None and "too small" in doc["psd_problem"]
    assert isinstance(doc["statistics"]["h_rms"], float)
    assert main(["surface", "analyze", str(SAMPLES / name), *extra, "--plot", str(tmp_path / "p.png")]) == 2
    err = capsys.readouterr().err
    _no_traceback(err)
    assert "--plot" in err and name in err


def test_case_with_several_measured_files_and_a_resolution(tmp_path):
    """Two maps of one surface at different scales are stitched; surface.resolution ends the reliable range."""
    from sealeak import PowerSpectrum
    from sealeak.numerics.synthesis import synthesize
    from sealeak.topography import write_height_map

    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=2e3, q_cutoff=2e6, q_lowest=5e2, h_rms=5e-6)
    write_height_map(tmp_path / "wide.npz", synthesize(sp, 256, 8e-3, seed=1), (8e-3, 8e-3), periodic=True)
    write_height_map(tmp_path / "fine.npz", synthesize(sp, 256, 1e-3, seed=2), (1e-3, 1e-3), periodic=True)
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")
    surface = '[surface]\nmodel = "topography"\nfiles = ["wide.npz", "fine.npz"]\n'

    def case(extra):
        path = tmp_path / "case.toml"
        path.write_text(text[:start] + surface + extra + "\n" + text[end:])
        return path

    (a,) = load_cases(case(""))
    (b,) = load_cases(case('resolution = "50 um"\n'))
    # the fine map reaches 4-pixel wavelengths of 1 mm / 64; the resolution cuts at 50 µm
    assert a.spectrum.q_max > 2 * np.pi / 20e-6
    assert 2 * np.pi / 50e-6 / 1.3 < b.spectrum.q_max <= 2 * np.pi / 50e-6 * (1 + 1e-12)  # bin centres in range
    assert b.spectrum.q_min == pytest.approx(a.spectrum.q_min)
    assert main(["predict", str(case('resolution = "5 kg"\n'))]) == 2


def test_case_file_topography_messages_name_case_keys(tmp_path, capsys):
    h = np.random.default_rng(1).normal(scale=2e-6, size=(64, 64))
    np.save(tmp_path / "map.npy", h)
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")

    def run(surface):
        (tmp_path / "case.toml").write_text(text[:start] + surface + "\n" + text[end:])
        code = main(["predict", str(tmp_path / "case.toml"), "-q"])
        return code, capsys.readouterr().err

    code, err = run('[surface]\nmodel = "topography"\nfile = "map.npy"\n')
    assert code == 2 and "surface.height_unit" in err and "surface.size" in err and "--" not in err
    code, err = run('[surface]\nmodel = "topography"\nfile = "map.npy"\nsize = "5 mm"\nheight_unit = "m"\n'
                    'low_cut = 0.5\n')
    assert code == 2 and "surface.low_cut = 0.5" in err
    code, err = run('[surface]\nmodel = "topography"\nfile = "map.npy"\nsize = "5 mm"\nheight_unit = "m"\n'
                    'periodic = true\nlabel = "lapped steel"\n')
    assert code == 0
    (case,) = load_cases(tmp_path / "case.toml")
    assert case.spectrum.label == "lapped steel"
