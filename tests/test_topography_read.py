"""Reading real instrument files (../shared/topography-samples) and plain formats; clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sealeak.errors import FileFormatError, InputError, SealeakError, UnitError
from sealeak.topography import LineScans, Topography, length_unit_factor, read_topography

SAMPLES = Path(__file__).parents[2] / "shared" / "topography-samples"
needs_samples = pytest.mark.skipif(not SAMPLES.is_dir(), reason="shared topography samples not present")
UM, NM, MM = 1e-6, 1e-9, 1e-3

# README table: file, grid, size, unit factor, rms (raw heights, no detrending, in that unit)
INSTRUMENT = [
    ("al3d-1.al3d", (200, 296), (8.76e-05, 1.297e-04), 1.0, 7.688e-06),
    ("di-1.di", (512, 512), (500, 500), NM, 9.946),
    ("frt-2.frt", (150, 300), (0.03, 0.06), 1.0, 8.827e-06),
    ("metropro-1.dat", (640, 480), (7.03e-04, 5.27e-04), 1.0, 7.529e-08),
    ("mi-1.mi", (256, 256), (20, 20), UM, 0.03322),
    ("nc-1.nc", (5, 10), (5, 10), NM, 5.745),
    ("opd-1.opd", (640, 480), (0.1259, 0.0944), MM, 8.356e-06),
    ("plu-1.plu", (768, 576), (1274.9, 956.2), UM, 2.834),
    ("sur-2.sur", (563, 484), (1.961, 1.686), MM, 1.752e-05),
    ("tmd-1.tmd", (300, 300), (18.96, 18.96), MM, 0.07434),
    ("x3p-2.x3p", (650, 650), (8.30e-05, 2.04e-04), 1.0, 7.728e-08),
]


def _rms(h):
    h = h[np.isfinite(h)]
    return np.sqrt(np.mean((h - h.mean()) ** 2))


@needs_samples
@pytest.mark.parametrize("name,grid,size,unit,rms", INSTRUMENT, ids=[r[0] for r in INSTRUMENT])
def test_instrument_files(name, grid, size, unit, rms):
    pytest.importorskip("SurfaceTopography")
    t = read_topography(SAMPLES / name)
    assert isinstance(t, Topography)
    assert t.nb_grid_pts == grid
    # the README gives 3-5 significant digits (2.04e-04 stands for anything within ±0.25 %)
    np.testing.assert_allclose(t.size, np.asarray(size) * unit, rtol=3e-3)
    assert _rms(t.heights) == pytest.approx(rms * unit, rel=3e-3)
    assert any("from the file" in n for n in t.notes)


@needs_samples
def test_dektak_nonuniform_line_scan_via_extra():
    pytest.importorskip("SurfaceTopography")
    s = read_topography(SAMPLES / "dektak-1.csv")
    assert isinstance(s, LineScans) and s.nb_points == 9600
    # length = n · Δx of the uniform grid spanning the 1499.8 µm of the file
    assert s.length * (s.nb_points - 1) / s.nb_points == pytest.approx(1499.8 * UM, rel=1e-6)
    assert any("interpolated" in n for n in s.notes)
    assert _rms(s.heights) == pytest.approx(4.764 * UM, rel=0.01)  # interpolation changes rms slightly


@needs_samples
def test_di_channels():
    pytest.importorskip("SurfaceTopography")
    t = read_topography(SAMPLES / "di-1.di", channel=1)
    assert "channel 1" in t.source
    with pytest.raises(UnitError, match="does not hold heights"):
        read_topography(SAMPLES / "di-1.di", channel="Phase")
    with pytest.raises(InputError, match="has channels"):
        read_topography(SAMPLES / "di-1.di", channel=7)


@needs_samples
def test_matrix_text_needs_units_from_user():
    with pytest.raises(UnitError, match=r"matrix-5\.txt.*height_unit"):
        read_topography(SAMPLES / "matrix-5.txt")
    with pytest.raises(UnitError, match=r"matrix-5\.txt.*(size|pixel_size)"):
        read_topography(SAMPLES / "matrix-5.txt", height_unit="um")
    t = read_topography(SAMPLES / "matrix-5.txt", height_unit="µm", pixel_size="0.5 um")
    assert t.nb_grid_pts == (10, 10)
    assert t.size == pytest.approx((5 * UM, 5 * UM))
    assert _rms(t.heights) == pytest.approx(1 * UM)
    # file rows are y: the first five rows (y = 0..4) hold 2, the rest 0
    assert np.all(t.heights[:, :5] == 2 * UM) and np.all(t.heights[:, 5:] == 0)


@needs_samples
def test_xyz_columns():
    with pytest.raises(UnitError, match="lateral_unit"):
        read_topography(SAMPLES / "xyz-1.txt", height_unit="nm")
    t = read_topography(SAMPLES / "xyz-1.txt", height_unit="nm", lateral_unit="um")
    assert t.nb_grid_pts == (4, 4)
    assert t.size == pytest.approx((4 * UM, 4 * UM))
    assert _rms(t.heights) == pytest.approx(0.3307 * NM, rel=1e-3)
    assert t.heights[1, 1] == pytest.approx(2 * NM) and t.heights[1, 3] == pytest.approx(1 * NM)


@needs_samples
def test_xy_nonuniform_line_scan():
    s = read_topography(SAMPLES / "xy-1.txt", height_unit="um", lateral_unit="um")
    assert isinstance(s, LineScans) and s.nb_points == 132
    assert s.length * 131 / 132 == pytest.approx(187.19 * UM, rel=1e-4)
    assert any("non-uniform x" in n and "interpolated" in n for n in s.notes)
    assert _rms(s.heights) == pytest.approx(3.059 * UM, rel=0.02)


def test_npy_and_units(tmp_path):
    h = np.random.default_rng(0).standard_normal((8, 6))
    np.save(tmp_path / "map.npy", h)
    t = read_topography(tmp_path / "map.npy", height_unit="nm", size=("8 um", "6 um"))
    np.testing.assert_allclose(t.heights, h * NM)
    assert t.pixel_size == pytest.approx((1 * UM, 1 * UM))
    np.save(tmp_path / "prof.npy", h[0])
    s = read_topography(tmp_path / "prof.npy", height_unit="mm", pixel_size=2e-6)
    assert isinstance(s, LineScans) and s.length == pytest.approx(12e-6)
    assert length_unit_factor("μm") == length_unit_factor("µm") == length_unit_factor("um") == 1e-6


# ---------------------------------------------------------------------------- errors
@pytest.mark.parametrize("content,problem", [
    (b"", "empty"),
    (b"# only a comment\n\n", "no numeric data"),
    (b"1 2 3 4\n5 6 7 8\n9 10\n", "line 3 has 2 values"),  # truncated
    (b"1 2 3 4\n5 six 7 8\n", "'six' is not a number"),
    (b"1 2 3 4\n1 2 inf 4\n", "infinite"),
    (b"0 0 1\n0 1 2\n1 0 3\n", "do not fill"),
])
def test_malformed_text_files(tmp_path, content, problem):
    p = tmp_path / "bad.txt"
    p.write_bytes(content)
    with pytest.raises(FileFormatError) as err:
        read_topography(p, height_unit="um", pixel_size="1 um", lateral_unit="um")
    assert "bad.txt" in str(err.value) and problem in str(err.value)


def test_truncated_npy(tmp_path):
    p = tmp_path / "cut.npy"
    np.save(p, np.zeros((50, 50)))
    p.write_bytes(p.read_bytes()[:300])
    with pytest.raises(FileFormatError, match="cut.npy"):
        read_topography(p, height_unit="um", pixel_size="1 um")


def test_wrong_units(tmp_path):
    p = tmp_path / "m.txt"
    p.write_text("1 2 3 4\n5 6 7 8\n")
    with pytest.raises(UnitError, match="height_unit = 'kg'.*not a length"):
        read_topography(p, height_unit="kg", pixel_size="1 um")
    with pytest.raises(UnitError, match="unknown unit"):
        read_topography(p, height_unit="furlongz", pixel_size="1 um")
    with pytest.raises(UnitError, match="pixel_size"):
        read_topography(p, height_unit="um", pixel_size="-1 um")
    with pytest.raises(InputError, match="not both"):
        read_topography(p, height_unit="um", pixel_size="1 um", size="4 um")


def test_missing_and_unknown_files(tmp_path):
    with pytest.raises(FileFormatError, match="no such file"):
        read_topography(tmp_path / "nope.txt")
    p = tmp_path / "junk.sur"
    p.write_bytes(b"\x00\x01garbage" * 51)
    with pytest.raises(FileFormatError, match="junk.sur"):
        read_topography(p)
    # 450 bytes = 2·15² pass as an SRTM .hgt height file, which has no unit: still a clear error
    p.write_bytes(b"\x00\x01garbage" * 50)
    with pytest.raises(SealeakError, match="junk.sur.*hgt.*height_unit"):
        read_topography(p)


def test_instrument_file_without_extra(tmp_path, monkeypatch):
    import sealeak.topography._readers as readers

    monkeypatch.setattr(readers, "_have_surfacetopography", lambda: False)
    p = tmp_path / "scan.plu"
    p.write_bytes(b"\x00\x01" * 100)
    with pytest.raises(FileFormatError, match=r"pip install 'sealeak\[formats\]'"):
        read_topography(p)
    q = tmp_path / "export.csv"
    q.write_text("Scan Parameters\nLength,1500 um\n0.0,1.0\n")
    with pytest.raises(FileFormatError, match=r"export.csv.*pip install 'sealeak\[formats\]'"):
        read_topography(q)


_tokens = st.sampled_from(["1", "-2.5", "3e-3", "nan", "inf", "x", "1e999", "", " ", "\t", ",", ";", "\n",
                           "#", "%", "0", "7", "1_0", "é", "\x00", "-", ".", "e5"])


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(body=st.one_of(st.lists(_tokens, max_size=60).map("".join), st.binary(max_size=200)))
def test_fuzz_text_reader_raises_only_sealeak_errors(tmp_path, body):
    from unittest import mock

    import sealeak.topography._readers as readers

    p = tmp_path / "fuzz.txt"
    p.write_bytes(body.encode("utf-8") if isinstance(body, str) else body)
    try:  # the native reader only (no SurfaceTopography fallback)
        with mock.patch.object(readers, "_have_surfacetopography", lambda: False):
            out = read_topography(p, height_unit="um", pixel_size="1 um", lateral_unit="um")
    except SealeakError:
        return
    assert isinstance(out, (Topography, LineScans))
    assert np.all(np.isfinite(out.heights) | np.isnan(out.heights))
