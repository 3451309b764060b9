"""`sealeak surface analyze|synthesize` and `[surface] model = "topography"` with degenerate or odd input.

Flat maps are refused (one line naming the file, nothing written), no-data markers are found and
said, the input at fault is named, fit warnings appear in the text and the JSON alike.
Warnings are errors here (in-process: ``filterwarnings("error")``; a subprocess run uses ``-W error``),
so no NumPy RuntimeWarning can escape unseen.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from sealeak.cases import example_path
from sealeak.cli import main
from sealeak.topography import write_height_map
from tests.cli_errors import one_line_error

pytestmark = pytest.mark.filterwarnings("error")

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"
UNITS = ["--size", "1 mm", "--height-unit", "um"]


def _rough(n=32, seed=0):
    return np.random.default_rng(seed).normal(size=(n, n))


# ---------------------------------------------------------------------------- flat maps
def _write(path: Path, h: np.ndarray) -> Path:
    """h[x, y] (or a profile) in µm as a plain text file (one row per y), or .npy."""
    if path.suffix == ".npy":
        np.save(path, h)
    else:
        np.savetxt(path, h.T if h.ndim == 2 else h[:, None])
    return path


_i, _j = np.meshgrid(np.arange(32.0), np.arange(24.0), indexing="ij")
_holes = np.full((32, 32), 5.0)
_holes[3:6, 7:9] = np.nan
FLAT = {
    "equal.txt": (np.full((32, 32), 5.0), "all 1024 heights are equal"),
    "zeros.npy": (np.zeros((16, 16)), "all 256 heights are equal"),
    "holes.txt": (_holes, "heights are equal"),
    "tilted.txt": (3.0 + 0.1 * _i - 0.25 * _j, "plane"),
    "tilted-far.npy": (1e4 + 1e-3 * _i + 2e-3 * _j, "plane"),  # a plane far from zero: round-off is larger
    "profile.txt": (np.full(64, 3.0), "all 64 heights are equal"),
    "sloped-profile.npy": (np.linspace(-2.0, 7.0, 50), "straight line"),
}


@pytest.mark.parametrize("name", sorted(FLAT))
def test_flat_measurements_are_refused_and_nothing_is_written(tmp_path, capsys, name):
    h, said = FLAT[name]
    f = _write(tmp_path / name, h)
    psd, js, png = tmp_path / "c.csv", tmp_path / "a.json", tmp_path / "c.png"
    psd.write_text("keep me\n")  # an existing output is not replaced, even with --force
    code = main(["surface", "analyze", str(f), *UNITS, "--psd-out", str(psd), "--json", str(js), "--plot", str(png),
                 "--force"])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    one_line_error(err, name, said, "no roughness")
    assert psd.read_text() == "keep me\n" and not js.exists() and not png.exists()


def test_a_flat_file_among_rough_ones_is_named(tmp_path, capsys):
    rough = _write(tmp_path / "rough.txt", _rough())
    flat = _write(tmp_path / "flat.txt", np.full((32, 32), 1.5))
    assert main(["surface", "analyze", str(rough), str(flat), *UNITS]) == 2
    one_line_error(capsys.readouterr().err, "flat.txt", "equal")


def test_flat_map_in_a_case_file_is_refused(tmp_path, capsys):
    np.save(tmp_path / "flat.npy", np.full((64, 64), 2e-6))
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")
    (tmp_path / "case.toml").write_text(text[:start] + '[surface]\nmodel = "topography"\nfile = "flat.npy"\n'
                                        'size = "5 mm"\nheight_unit = "m"\n\n' + text[end:])
    js = tmp_path / "p.json"
    assert main(["predict", str(tmp_path / "case.toml"), "--json", str(js)]) == 2
    one_line_error(capsys.readouterr().err, "flat.npy", "equal")
    assert not js.exists()


def test_flat_map_refused_with_python_warnings_as_errors(tmp_path):
    """The same through a fresh interpreter with -W error (nothing but the one line on stderr)."""
    f = _write(tmp_path / "equal.txt", np.full((32, 32), 5.0))
    psd = tmp_path / "c.csv"
    run = subprocess.run([sys.executable, "-W", "error", "-c",
                          "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                          "surface", "analyze", str(f), *UNITS, "--psd-out", str(psd)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and run.stdout == ""
    one_line_error(run.stderr, "equal.txt", "equal")
    assert not psd.exists()


# ---------------------------------------------------------------------------- no-data markers
MARKERS = {  # marker values as instruments write them, and how they get into the file
    "1e300": (1e300, ".txt"),
    "-1e38": (-1e38, ".txt"),
    "float32 max": (float(np.finfo(np.float32).max), ".npy32"),
    "-inf": (-np.inf, ".npy"),
    "inf": (np.inf, ".txt"),
    "overflowing text": ("1e999", ".txt"),
}


def _with_markers(tmp_path: Path, marker, kind: str, where) -> tuple[Path, Path]:
    """A rough map with markers at ``where`` and the same map with NaN there (the reference)."""
    h = _rough(48, seed=5)
    ref = h.copy()
    ref[where] = np.nan
    np.savetxt(tmp_path / "ref.txt", ref.T)
    if kind == ".npy32":
        a = h.astype(np.float32)
        a[where] = marker
        np.save(tmp_path / "marked.npy", a)
        return tmp_path / "marked.npy", tmp_path / "ref.txt"
    if kind == ".npy":
        a = h.copy()
        a[where] = marker
        np.save(tmp_path / "marked.npy", a)
        return tmp_path / "marked.npy", tmp_path / "ref.txt"
    rows = [[f"{v!r}" for v in row] for row in h.T.tolist()]
    for x, y in zip(*where):
        rows[y][x] = marker if isinstance(marker, str) else repr(float(marker))
    (tmp_path / "marked.txt").write_text("\n".join(" ".join(r) for r in rows) + "\n")
    return tmp_path / "marked.txt", tmp_path / "ref.txt"


@pytest.mark.parametrize("label", sorted(MARKERS))
def test_no_data_markers_are_found_counted_and_treated_as_undefined(tmp_path, capsys, label):
    marker, kind = MARKERS[label]
    where = (np.array([3, 3, 40]), np.array([4, 30, 12]))
    marked, ref = _with_markers(tmp_path, marker, kind, where)
    js_m, js_r = tmp_path / "m.json", tmp_path / "r.json"
    assert main(["surface", "analyze", str(marked), *UNITS, "--json", str(js_m)]) == 0
    out = capsys.readouterr().out
    warning = [ln for ln in out.splitlines() if "warning:" in ln]
    assert len(warning) == 1 and "3 of 2304 points" in warning[0] and "no-data marker" in warning[0]
    assert "NaN" in warning[0]  # what to do about it
    assert main(["surface", "analyze", str(ref), *UNITS, "--json", str(js_r)]) == 0
    capsys.readouterr()
    m, r = json.loads(js_m.read_text()), json.loads(js_r.read_text())
    assert m["warnings"] == [f"{marked.name}: {m['sources'][0]['warnings'][0]}"]
    # a marker is an undefined point: the same statistics and C(q) as the map with NaN there
    for key in ("h_rms", "slope_rms", "skewness", "kurtosis"):
        assert m["statistics"][key] == pytest.approx(r["statistics"][key], rel=1e-5), key
    assert np.allclose(m["psd"]["C"], r["psd"]["C"], rtol=1e-5)


def test_a_file_of_markers_only_is_refused(tmp_path, capsys):
    f = tmp_path / "dead.txt"
    f.write_text("1e300 1e300 1e300 1e300\n1e300 1e300 1e300 1e300\n")
    assert main(["surface", "analyze", str(f), *UNITS]) == 2
    one_line_error(capsys.readouterr().err, "dead.txt", "no-data markers", "8")


def test_markers_with_python_warnings_as_errors(tmp_path):
    marked, _ = _with_markers(tmp_path, 1e300, ".txt", (np.array([1]), np.array([2])))
    run = subprocess.run([sys.executable, "-W", "error", "-c",
                          "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                          "surface", "analyze", str(marked), *UNITS], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and "Warning" not in run.stderr and "Traceback" not in run.stderr
    assert "1 of 2304 points" in run.stdout


def test_markers_in_a_case_file_map_are_undefined_points(tmp_path, capsys):
    h = _rough(64, seed=2) * 1e-6
    h[5, 7] = -1e38
    np.save(tmp_path / "map.npy", h)
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")
    (tmp_path / "case.toml").write_text(text[:start] + '[surface]\nmodel = "topography"\nfile = "map.npy"\n'
                                        'size = "5 mm"\nheight_unit = "m"\n\n' + text[end:])
    assert main(["predict", str(tmp_path / "case.toml"), "-q"]) == 0
    assert "Traceback" not in capsys.readouterr().err
    from sealeak.cases import load_cases

    (case,) = load_cases(tmp_path / "case.toml")
    # the marker is an undefined point: the spectrum is that of the 1 µm-rms map (band edges cut some)
    assert 0.2e-6 < case.spectrum.h_rms < 1.01e-6


# ---------------------------------------------------------------------------- the input at fault is named
@pytest.mark.parametrize("resolution,said", [("1 km", "longer than the map"), ("3 mm", "longer than the map"),
                                             ("1.9 mm", "too close to the map")])
def test_a_resolution_coarser_than_the_map_names_the_resolution(tmp_path, capsys, resolution, said):
    f = _write(tmp_path / "m.txt", _rough(64))
    js = tmp_path / "a.json"
    assert main(["surface", "analyze", str(f), "--size", "2 mm", "--height-unit", "um", "--resolution", resolution,
                 "--json", str(js)]) == 2
    err = capsys.readouterr().err
    one_line_error(err, "--resolution", said, "2 mm", "give a resolution below")
    assert "larger area" not in err and "more points" not in err and not js.exists()
    # the limit it states is right: just below it the analysis works
    limit = 2e-3 / 3  # L / --low-cut
    assert main(["surface", "analyze", str(f), "--size", "2 mm", "--height-unit", "um",
                 "--resolution", f"{limit * 0.5} m"]) == 0


def test_a_resolution_coarser_than_the_map_in_a_case_file(tmp_path, capsys):
    np.save(tmp_path / "map.npy", _rough(64) * 1e-6)
    text = example_path("reference-experiment").read_text()
    start, end = text.index("[surface]"), text.index("[rubber]")
    (tmp_path / "case.toml").write_text(text[:start] + '[surface]\nmodel = "topography"\nfile = "map.npy"\n'
                                        'size = "2 mm"\nheight_unit = "m"\nresolution = "1 km"\n\n' + text[end:])
    assert main(["predict", str(tmp_path / "case.toml")]) == 2
    err = capsys.readouterr().err
    one_line_error(err, "surface.resolution", "1 km", "longer than the map", "surface.low_cut")
    assert "--" not in err and "larger area" not in err


@pytest.mark.parametrize("n,extra,said", [
    (10, [], "only 10 pixels across"),  # too few points: more points, not a larger area at this pixel count
    (12, ["--low-cut", "4"], "only 12 pixels across"),
    (40, ["--resolution-pixels", "20"], "only 40 pixels across"),
    (64, ["--bins-per-decade", "1"], "more --bins-per-decade (now 1"),  # bins wider than the range
])
def test_a_map_with_too_few_points_names_the_points(tmp_path, capsys, n, extra, said):
    f = _write(tmp_path / "m.txt", _rough(n))
    assert main(["surface", "analyze", str(f), *UNITS, *extra, "--plot", str(tmp_path / "c.png")]) == 2
    err = capsys.readouterr().err
    one_line_error(err, "m.txt", said, "more points", "--low-cut", "--resolution-pixels")
    assert "--resolution " not in err and not (tmp_path / "c.png").exists()


# ---------------------------------------------------------------------------- fit warnings: text and JSON agree
def _fit_outputs(capsys, args, tmp_path):
    js = tmp_path / "fit.json"
    assert main(["surface", "analyze", *args, "--json", str(js), "--force"]) == 0
    out = capsys.readouterr().out
    text = [ln.split("warning: ", 1)[1] for ln in out.splitlines() if ln.startswith("  warning: ")]
    return json.loads(js.read_text()), text


def _check_fit_warnings(doc, text):
    fit = doc["fit"]
    at_bound = fit["hurst"] in (0.0, 1.0) or min(fit["hurst"], 1 - fit["hurst"]) < 1e-3
    poor = fit["chi2_red"] > 100
    assert text == fit["warnings"]
    assert doc["warnings"] == [f"self-affine fit: {w}" for w in fit["warnings"]]
    assert (fit["warning"] is None) == (not fit["warnings"])
    assert any("bound" in w or "outside" in w for w in fit["warnings"]) == at_bound, fit
    assert any("χ²" in w for w in fit["warnings"]) == poor, fit
    return at_bound, poor


def _synthetic(tmp_path, name, q, C, seed=3):
    from sealeak.numerics.synthesis import synthesize
    from sealeak.physics.spectrum import PowerSpectrum

    L = 1e-3
    h = synthesize(PowerSpectrum.from_arrays(q, C), 512, L, seed=seed, amplitudes="phases")
    write_height_map(tmp_path / name, h, (L, L), periodic=True)
    return str(tmp_path / name)


def test_fit_warnings_for_a_bump_and_a_bound_in_text_and_json(tmp_path, capsys):
    q = np.geomspace(2e4, 2e6, 41)
    plain = 1e-30 * (q / q[0]) ** -3.2
    bump = plain * np.exp(2.5 * np.exp(-(np.log(q / 2e5) / 0.2) ** 2))  # a factor-12 bump: not one power law
    steep = 1e-30 * (q / q[0]) ** -5.0  # wants H = 1.5
    results = {}
    for name, C in (("plain.npz", plain), ("bump.npz", bump), ("steep.npz", steep)):
        doc, text = _fit_outputs(capsys, [_synthetic(tmp_path, name, q, C)], tmp_path)
        results[name] = _check_fit_warnings(doc, text)
    # (H at a bound, reduced χ² > 100): the bump keeps H inside but misses the bins; q^-5 wants H = 1.5
    assert results == {"plain.npz": (False, False), "bump.npz": (False, True), "steep.npz": (True, True)}


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
@pytest.mark.parametrize("name", ["di-1.di", "plu-1.plu", "sur-2.sur", "x3p-2.x3p", "al3d-1.al3d", "frt-2.frt",
                                  "mi-1.mi", "opd-1.opd", "tmd-1.tmd", "metropro-1.dat"])
def test_fit_warnings_of_instrument_files_follow_one_rule(tmp_path, capsys, name):
    """Every fit at a bound of H or with reduced χ² > 100 carries a warning, in the text and the JSON; no other."""
    pytest.importorskip("SurfaceTopography")
    doc, text = _fit_outputs(capsys, [str(SAMPLES / name)], tmp_path)
    _check_fit_warnings(doc, text)


# ---------------------------------------------------------------------------- synthesize: a size with no content
# reference-experiment: C(q) spans wavelengths 20 µm (cut-off) .. 5 mm
@pytest.mark.parametrize("args,said", [
    (["--size", "1 um"], "smaller than the shortest wavelength"),
    (["--size", "15 um", "--grid", "256"], "smaller than the shortest wavelength"),
    (["--size", "10 m", "--grid", "8"], "too coarse"),
    (["--size", "10 cm", "--grid", "16"], "too coarse"),
])
@pytest.mark.parametrize("suffix", [".npy", ".txt"])
def test_synthesize_refuses_a_map_that_would_be_flat(tmp_path, capsys, args, said, suffix):
    out = tmp_path / f"s{suffix}"
    out.write_text("keep me\n")
    code = main(["surface", "synthesize", "--example", "reference-experiment", *args, "-o", str(out), "--force"])
    one_line_error(capsys.readouterr().err, "--size", said, "20 µm .. 5 mm")
    assert code == 2 and out.read_text() == "keep me\n" and not (tmp_path / "s.npy.json").exists()


def test_synthesize_from_a_table_refuses_a_map_that_would_be_flat(tmp_path, capsys):
    psd = tmp_path / "c.csv"
    psd.write_text("q (1/m), C (m^4)\n1e5, 1e-28\n1e6, 1e-31\n")  # wavelengths 6.3 µm .. 63 µm
    assert main(["surface", "synthesize", "--psd", str(psd), "--size", "1 um", "--grid", "32",
                 "-o", str(tmp_path / "s.npz")]) == 2
    one_line_error(capsys.readouterr().err, "--size", "6.283 µm .. 62.83 µm")
    assert not (tmp_path / "s.npz").exists()


def test_synthesize_warns_when_the_map_holds_little_of_the_roughness(tmp_path, capsys):
    from sealeak.topography import read_topography

    out = tmp_path / "patch.npz"
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--size", "100 um", "--grid", "64",
                 "--amplitudes", "phases", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    warning = [ln for ln in err.splitlines() if ln.startswith("warning:")]
    assert len(warning) == 1 and "longer than the map's side" in warning[0] and "--size" in warning[0]
    # the share it states is the map's: h_rms² of the map over h_rms² of the spectrum (44 µm)
    share = float(warning[0].split("only ")[1].split(" %")[0]) / 100
    h = read_topography(out).heights
    assert np.mean(h**2) / 44e-6**2 == pytest.approx(share, rel=0.05) and share < 0.1
    # a map of the seal's width holds nearly all: no warning
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--grid", "64",
                 "-o", str(tmp_path / "full.npz")]) == 0
    assert "warning" not in capsys.readouterr().err


@pytest.mark.parametrize("size", [None, "100 um"])  # a plain run and one with a warning
def test_synthesize_quiet_prints_nothing(tmp_path, capsys, size):
    out = tmp_path / "s.npz"
    extra = ["--size", size] if size else []
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--grid", "32", *extra, "-q",
                 "-o", str(out)]) == 0
    assert capsys.readouterr() == ("", "") and out.is_file()
    # errors still speak
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--size", "1 um", "-q",
                 "-o", str(tmp_path / "t.npz")]) == 2
    one_line_error(capsys.readouterr().err, "--size")
