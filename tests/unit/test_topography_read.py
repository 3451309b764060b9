"""Reading real instrument files (../shared/topography-samples) and plain formats; clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sealeak.errors import FileFormatError, InputError, SealeakError, UnitError
from sealeak.topography import (
    LineScans,
    MissingUnitsError,
    Topography,
    cli_option_names,
    length_unit_factor,
    read_topography,
    spectrum_1d,
    spectrum_2d,
    write_height_map,
)

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"
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
    assert _rms(t.heights) == pytest.approx(0.3307 * NM, rel=1e-3, abs=0)
    assert t.heights[1, 1] == pytest.approx(2 * NM, rel=1e-6, abs=0) and t.heights[1, 3] == pytest.approx(1 * NM, rel=1e-6, abs=0)


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
    (b"0 1\ninf 2\n2 3\n3 4\n4 5\n", "positions must be finite"),  # inf heights are no-data markers, not x
    (b"inf 1e300 -inf 1e999\n-1e38 3.4e38 1e300 inf\n", "all 8 heights are no-data markers"),
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
    # 450 bytes = 2·15² would pass as an SRTM .hgt elevation tile, which is recognised by its size
    # alone: accepted only for files named .hgt; a .sur gets the SUR reader's own reason
    pytest.importorskip("SurfaceTopography")
    p.write_bytes(b"\x00\x01garbage" * 50)
    with pytest.raises(FileFormatError, match=r"junk\.sur: cannot be read as Digital Surf SUR") as err:
        read_topography(p)
    assert "hgt" not in str(err.value).lower()
    hgt = tmp_path / "tile.hgt"
    hgt.write_bytes(p.read_bytes())
    with pytest.raises(MissingUnitsError, match=r"tile\.hgt.*hgt.*height_unit.*size"):
        read_topography(hgt)


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


# ---------------------------------------------------------------------------- truncated instrument files
# Cuts: a few header bytes, half the file, and a size of 2n² bytes (what SRTM .hgt tiles have).
_TRUNCATED = [(name, cut) for name in ("opd-1.opd", "plu-1.plu", "x3p-2.x3p", "sur-2.sur", "di-1.di",
                                       "al3d-1.al3d", "metropro-1.dat", "mi-1.mi", "frt-2.frt", "tmd-1.tmd")
              for cut in ("header", "half", "2n2")]


def _cut(size: int, how: str) -> int:
    if how == "header":
        return 2000
    if how == "half":
        return size // 2
    n = int(np.sqrt(size / 4))  # 2n² bytes, about half the file
    return 2 * n * n


@needs_samples
@pytest.mark.parametrize("name,how", _TRUNCATED, ids=[f"{n}-{c}" for n, c in _TRUNCATED])
def test_truncated_instrument_files_give_one_clear_error(tmp_path, capfd, name, how):
    pytest.importorskip("SurfaceTopography")
    data = (SAMPLES / name).read_bytes()
    p = tmp_path / f"cut-{name}"
    p.write_bytes(data[:_cut(len(data), how)])
    capfd.readouterr()
    try:
        t = read_topography(p, height_unit="um", size="1 mm")
    except SealeakError as exc:
        assert f"cut-{name}" in str(exc)
        assert not isinstance(exc, MissingUnitsError)  # never mistaken for a unit-less format (e.g. .hgt)
    else:
        # a cut after the height block can be complete: then it must be the same data as the original
        full = read_topography(SAMPLES / name)
        assert t.heights.shape == full.heights.shape
        np.testing.assert_array_equal(t.heights, full.heights)
    out, err = capfd.readouterr()  # file-descriptor level: catches foreign libraries' logging too
    assert out == "" and err == ""


@needs_samples
def test_dektak_tip_radius_sets_the_end_of_the_reliable_range():
    ST = pytest.importorskip("SurfaceTopography")
    s = read_topography(SAMPLES / "dektak-1.csv")
    # independent: SurfaceTopography's own cutoff (file unit µm) from the tip radius in the file
    cutoff = ST.open_topography(str(SAMPLES / "dektak-1.csv")).topography().short_reliability_cutoff() * UM
    assert s.resolution == pytest.approx(cutoff, rel=1e-12, abs=0)
    assert 4 * s.pixel_size < cutoff  # the tip, not the pixels, limits this scan
    b = spectrum_1d(s)
    assert b.q_reliable == pytest.approx((3 * 2 * np.pi / s.length, 2 * np.pi / cutoff))
    assert np.all(b.q[b.reliable] <= 2 * np.pi / cutoff) and np.any(b.q[~b.reliable] > 2 * np.pi / cutoff)
    # a resolution given explicitly wins; finer than 4 pixels, the pixel limit applies
    assert spectrum_1d(s, resolution=10 * UM).q_reliable[1] == pytest.approx(2 * np.pi / (10 * UM))
    assert spectrum_1d(s, resolution=0.1 * UM).q_reliable[1] == pytest.approx(2 * np.pi / (4 * s.pixel_size))


def test_reliable_range_start_and_end_on_a_map():
    rng = np.random.default_rng(5)
    t = Topography(heights=rng.standard_normal((200, 100)) * 1e-7, size=(200 * UM, 100 * UM))  # 1 µm pixels
    for kwargs, (lo, hi) in [
        ({}, (3 * 2 * np.pi / (100 * UM), 2 * np.pi / (4 * UM))),  # default: 3·2π/(shorter side), 4 pixels
        ({"low_cut": 2, "resolution": 10 * UM}, (2 * 2 * np.pi / (100 * UM), 2 * np.pi / (10 * UM))),
        ({"resolution_pixels": 2, "resolution": 0.5 * UM}, (3 * 2 * np.pi / (100 * UM), np.pi / UM)),
    ]:
        b = spectrum_2d(t, **kwargs)
        assert b.q_reliable == pytest.approx((lo, hi))
        inside = (b.q >= lo) & (b.q <= hi)
        np.testing.assert_array_equal(b.reliable, inside)
        assert inside.any() and not inside.all()


# ---------------------------------------------------------------------------- units stated by native files
def test_text_header_states_size_and_units(tmp_path):
    p = tmp_path / "m.txt"
    p.write_text("# size: 1 mm, 0.5 mm\n# height_unit: nm\n1 2 3 4\n5 6 7 8\n9 10 11 12\n")
    t = read_topography(p)
    assert t.size == pytest.approx((1e-3, 0.5e-3))
    assert t.nb_grid_pts == (4, 3)  # rows are y
    assert t.heights[2, 1] == pytest.approx(7 * NM, rel=1e-6, abs=0)
    # what the file states wins over the options, and the notes say so
    t2 = read_topography(p, size="3 mm", height_unit="um")
    assert t2.size == t.size and any("ignored" in n for n in t2.notes)
    p.write_text("# size: 1 kg\n1 2 3 4\n5 6 7 8\n")
    with pytest.raises(FileFormatError, match=r"m\.txt: line 1: size"):
        read_topography(p, height_unit="um")


def test_npz_and_npy_sidecar(tmp_path):
    h = np.random.default_rng(0).standard_normal((6, 4)) * 1e-6
    np.savez(tmp_path / "a.npz", heights=h, size=np.array([6e-6, 4e-6]), height_unit=np.array("m"))
    t = read_topography(tmp_path / "a.npz")
    np.testing.assert_array_equal(t.heights, h)
    assert t.size == pytest.approx((6e-6, 4e-6)) and not t.periodic
    write_height_map(tmp_path / "b.npy", h, (3e-6, 2e-6), periodic=True)
    t = read_topography(tmp_path / "b.npy")
    np.testing.assert_array_equal(t.heights, h)
    assert t.size == pytest.approx((3e-6, 2e-6)) and t.periodic
    np.save(tmp_path / "b.npy", h.T)  # the map replaced, the sidecar left behind
    with pytest.raises(FileFormatError, match=r"b\.npy\.json.*another file"):
        read_topography(tmp_path / "b.npy")
    np.save(tmp_path / "b.npy", h)
    (tmp_path / "b.npy.json").write_text('{"shape": 8, "size": [1e-6, 1e-6]}')
    with pytest.raises(FileFormatError, match=r"b\.npy\.json: shape = 8: a list of whole numbers"):
        read_topography(tmp_path / "b.npy")
    (tmp_path / "b.npy.json").write_text('{"size": "a lot"}')
    with pytest.raises(FileFormatError) as err:
        read_topography(tmp_path / "b.npy")
    assert str(err.value).count("b.npy.json") == 1 and "sidecar: size = 'a lot'" in str(err.value)


def test_missing_units_named_once_for_api_and_cli(tmp_path):
    p = tmp_path / "m.txt"
    p.write_text("1 2 3 4\n5 6 7 8\n")
    with pytest.raises(MissingUnitsError) as err:
        read_topography(p)
    msg = str(err.value)
    assert "m.txt" in msg and "height_unit='um'" in msg and "size=" in msg and "pixel_size=" in msg
    assert "--" not in msg
    with cli_option_names(), pytest.raises(MissingUnitsError) as err:
        read_topography(p)
    msg = str(err.value)
    assert "--height-unit um" in msg and "--size" in msg and "--pixel-size" in msg
    assert "height_unit" not in msg and "pixel_size" not in msg
