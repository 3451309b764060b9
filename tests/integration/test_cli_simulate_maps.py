"""``sealeak simulate`` on a topography case: the measured maps are the surfaces (docs/cli.md, "Measured maps")."""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from sealeak.cli import main
from sealeak.numerics import synthesize
from sealeak.physics import PowerSpectrum

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"

CASE = """title = "rubber on a map"
[surface]
model = "topography"
{surface}
[rubber]
youngs_modulus = "2.3 MPa"
poisson_ratio = 0.5
[seal]
shape = "rectangle"
width = "2 cm"
length = "2 cm"
[fluid]
viscosity = "1 mPa*s"
[conditions]
squeeze_pressure = [{pressures}]
pressure_difference = "10 kPa"
"""


def _case(tmp_path, surface, pressures='"20 kPa", "40 kPa"', extra=""):
    path = tmp_path / "case.toml"
    path.write_text(CASE.format(surface=surface, pressures=pressures) + extra)
    return path


def _map(tmp_path, heights, name="map.npy"):
    np.save(tmp_path / name, heights)
    return f'file = "{name}"\npixel_size = "10 um"\nheight_unit = "m"'


def _rough(n=32, seed=0):
    """A rough periodic map (m) of side n × 10 µm, skewed by a square (not Gaussian)."""
    spectrum = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=2e4, q_cutoff=1.5e5, h_rms=2e-6)
    g = synthesize(spectrum, n, n * 1e-5, seed=seed)
    return g + 0.3 * g**2 / g.std()


def _refused(capsys, out, *words):
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    assert not out.exists()


def test_a_npy_map_is_the_surface_and_its_moments_are_reported(tmp_path, capsys):
    h = _rough()
    case = _case(tmp_path, _map(tmp_path, h))
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--no-threshold", "--json", str(out)]) == 0
    table = capsys.readouterr().out
    assert "map.npy" in table and "mirrored" in table and "α em" in table
    doc = json.loads(out.read_text())
    (m,) = doc["maps"]
    assert doc["route"] == "maps" and m["mirrored"] and m["points"] == 32
    x, y = np.meshgrid(np.arange(32.0), np.arange(32.0), indexing="ij")
    a = np.stack([np.ones(h.size), x.ravel(), y.ravel()], axis=1)
    levelled = h.ravel() - a @ np.linalg.lstsq(a, h.ravel(), rcond=None)[0]
    assert m["skewness"] == pytest.approx(stats.skew(levelled), rel=1e-9) and m["skewness"] > 0.3
    assert m["kurtosis"] == pytest.approx(stats.kurtosis(levelled, fisher=False), rel=1e-9)
    assert [r["squeeze_pressure"] for r in m["results"]] == [20e3, 40e3]
    assert any(row["percolates"] for row in m["results"])  # α below is checked on at least one row
    for row in m["results"]:  # α is the ratio to each theory of the map's own C(q)
        if row["percolates"]:
            assert row["alpha"] == pytest.approx(row["leak_rate"] / row["leak_rate_critical_junction"], rel=1e-12)
            assert row["alpha_effective_medium"] == pytest.approx(row["leak_rate"] / row["leak_rate_effective_medium"],
                                                                  rel=1e-12)


def test_windows_give_one_realisation_each(tmp_path, capsys):
    case = _case(tmp_path, _map(tmp_path, _rough(64)), pressures='"20 kPa"')
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--windows", "2", "--grid", "32", "--no-threshold", "-q", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert [m["label"].rsplit(" ", 1)[-1] for m in doc["maps"]] == ["1,1]", "1,2]", "2,1]", "2,2]"]
    assert doc["settings"] == {"grid": 32, "maps": 4}


@pytest.mark.parametrize(("heights", "options", "words"), [
    (_rough(14), [], ("map.npy",)),  # too small for a C(q): refused on reading the case
    (_rough(32), ["--windows", "4"], ("surface.file = 'map.npy [window 1,1]'", "8x8 points", "at least 16")),
    (np.where(np.eye(32, dtype=bool), np.nan, _rough()), [], ("surface.file = 'map.npy'", "32 undefined points")),
    (np.zeros((32, 32, 3)), [], ("map.npy", "shape (32, 32, 3)")),
])
def test_bad_maps_are_refused_in_one_line(tmp_path, capsys, heights, options, words):
    case = _case(tmp_path, _map(tmp_path, heights))
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), *options, "--json", str(out), "-q"]) == 2
    _refused(capsys, out, *words)


@pytest.mark.parametrize("pixel", ['"nan um"', '"inf um"', '"0 um"'])
def test_a_non_finite_pixel_size_is_refused(tmp_path, capsys, pixel):
    np.save(tmp_path / "map.npy", _rough())
    case = _case(tmp_path, f'file = "map.npy"\npixel_size = {pixel}\nheight_unit = "m"')
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--json", str(out), "-q"]) == 2
    _refused(capsys, out, "surface.pixel_size")


def test_the_map_options_are_refused_where_they_do_not_apply(tmp_path, capsys):
    out = tmp_path / "out.json"
    assert main(["simulate", "--example", "reference-experiment", "--surface", "maps", "--json", str(out), "-q"]) == 2
    _refused(capsys, out, "--surface", "topography")
    assert main(["simulate", "--example", "reference-experiment", "--windows", "2", "--json", str(out), "-q"]) == 2
    _refused(capsys, out, "--windows")
    case = _case(tmp_path, _map(tmp_path, _rough()))
    assert main(["simulate", str(case), "--windows", "9", "--json", str(out), "-q"]) == 2
    _refused(capsys, out, "--windows")


def test_random_surfaces_from_the_maps_spectrum_on_request(tmp_path, capsys):
    case = _case(tmp_path, _map(tmp_path, _rough()), pressures='"20 kPa"', extra='[theory]\nsquare_side = "320 um"\n')
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--surface", "random", "--grid", "32", "--realizations", "1",
                 "--no-threshold", "-q", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert "route" not in doc and doc["settings"]["realizations"] == 1


@pytest.mark.skipif(not (SAMPLES / "tmd-1.tmd").is_file(), reason="the topography samples are not there")
def test_a_real_measured_map(tmp_path, capsys):
    """A TrueMap file (300 × 300 points, 19 mm, not periodic) on a 32-point grid: levelled, mirrored, resampled."""
    case = _case(tmp_path, f'file = "{SAMPLES / "tmd-1.tmd"}"', pressures='"1 kPa", "3 kPa"')
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--grid", "32", "--no-threshold", "-q", "--json", str(out)]) == 0
    (m,) = json.loads(out.read_text())["maps"]
    assert m["mirrored"] and m["points"] == 300 and m["side"] == pytest.approx(18.96e-3, rel=1e-3)
    assert any("resampled from 600x600 to the 32x32" in n for n in m["notes"])
    assert np.isfinite(m["skewness"]) and m["kurtosis"] > 1.0
    area = [r["relative_contact_area"] for r in m["results"]]
    assert 0 < area[0] < area[1] <= 1


def test_a_line_scan_is_no_map(tmp_path, capsys):
    profile = _rough(64)[0]
    case = _case(tmp_path, _map(tmp_path, profile))
    out = tmp_path / "out.json"
    assert main(["simulate", str(case), "--json", str(out), "-q"]) == 2
    _refused(capsys, out, "surface.file = 'map.npy'", "line scan", "--surface random")
