"""analyze() and the readers with degenerate data: flat measurements, no-data markers, a reliable range
that the instrument's own resolution closes. No warning may escape (warnings are errors here)."""

from __future__ import annotations

import numpy as np
import pytest

from sealeak.errors import FileFormatError, InputError
from sealeak.topography import LineScans, Topography, analyze, cli_option_names, read_topography

pytestmark = pytest.mark.filterwarnings("error")

L = 1e-3
_x, _y = np.meshgrid(np.linspace(0, 1, 40), np.linspace(0, 1, 30), indexing="ij")


@pytest.mark.parametrize("surface,detrend,said", [
    (Topography(heights=np.full((40, 30), 7e-6), size=(L, L)), "auto", "all 1200 heights are equal (7 µm)"),
    (Topography(heights=np.zeros((16, 16)), size=(L, L), periodic=True), "auto", "all 256 heights are equal"),
    (Topography(heights=2e-6 * _x - 5e-6 * _y + 1e-3, size=(L, L)), "plane", "the map is a plane"),
    (Topography(heights=1e-6 * (_x**2 + _x * _y - 3 * _y**2), size=(L, L)), "curvature",
                "the map is a quadratic surface"),
    (LineScans(heights=np.full(100, -2e-6), length=L), "auto", "all 100 heights are equal"),
    (LineScans(heights=np.outer(np.arange(1, 4), np.linspace(0, 1e-6, 50)), length=L), "auto",
               "each profile is a straight line"),
])
def test_flat_measurements_are_refused_naming_them(surface, detrend, said):
    surface = type(surface)(**{**surface.__dict__, "source": "/data/scan.txt"})
    with pytest.raises(FileFormatError) as err:
        analyze(surface, detrend=detrend)
    assert str(err.value).startswith("scan.txt: ") and said in str(err.value) and "no roughness" in str(err.value)


def test_a_plane_is_flat_only_after_removing_it():
    tilted = Topography(heights=2e-6 * _x - 5e-6 * _y, size=(L, L), source="tilt")
    with pytest.raises(FileFormatError, match="plane"):
        analyze(tilted)
    # asked to keep the tilt (mean removed only), the map has something to show: no refusal
    assert analyze(tilted, detrend="mean", fit=False).statistics.h_rms > 1e-6


def test_roughness_far_below_the_heights_is_not_round_off():
    # 1 nm of roughness on a 1 mm offset (a stage position in the heights): 1e-6 of the heights, kept
    rough = 1e-3 + 1e-9 * np.random.default_rng(0).standard_normal((64, 64))
    an = analyze(Topography(heights=rough, size=(L, L)), fit=False)
    assert an.statistics.h_rms == pytest.approx(1e-9, rel=0.05)
    assert 2.5 < an.statistics.kurtosis < 3.5  # Gaussian heights, not the kurtosis 1 of round-off


@pytest.mark.parametrize("marker", [1e300, -1e38, np.inf, -np.inf, 1e30])
def test_topography_objects_refuse_markers_and_say_what_to_do(marker):
    h = np.random.default_rng(1).standard_normal((8, 8)) * 1e-6
    h[2, 3] = marker
    with pytest.raises(InputError, match="no-data markers: set them to NaN"):
        Topography(heights=h, size=(L, L))
    with pytest.raises(InputError, match="1 value"):
        LineScans(heights=h[2], length=L)


def test_markers_on_reading_become_undefined_points(tmp_path):
    h = np.random.default_rng(2).standard_normal((20, 20))
    marked = h.copy()
    marked[[1, 5, 5], [2, 2, 9]] = [3.4028235e38, -1e38, 1e300]
    np.save(tmp_path / "m.npy", marked)
    t = read_topography(tmp_path / "m.npy", height_unit="um", size="1 mm")
    assert np.isnan(t.heights).sum() == 3 and np.isfinite(t.heights).sum() == 397
    np.testing.assert_array_equal(t.heights[np.isfinite(t.heights)], (h * 1e-6)[np.isfinite(t.heights)])
    (warning,) = t.warnings
    assert "3 of 400 points" in warning and "-1e+38" in warning and "no-data marker" in warning
    assert analyze(t, fit=False).warnings == (f"m.npy: {warning}",)


def test_the_files_own_resolution_is_named_when_it_closes_the_range():
    h = np.random.default_rng(3).standard_normal((64, 64)) * 1e-6
    stylus = Topography(heights=h, size=(L, L), resolution=0.8e-3,
                        source="stylus.csv")  # as an instrument file would state it
    an = analyze(stylus)
    assert not an.has_spectrum
    problem = an.sources[0].spectrum_problem
    assert "the lateral resolution the file states (800 µm)" in problem and "measure a larger area" in problem
    with cli_option_names():
        problem = analyze(stylus).sources[0].spectrum_problem
    assert "--resolution" in problem  # the way to override it, if the instrument resolves more
    # a given resolution replaces the file's: then it is the input at fault
    with pytest.raises(InputError, match=r"resolution = '2 mm': longer than the map"):
        analyze(stylus, resolution=2e-3)
