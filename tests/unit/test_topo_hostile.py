"""Hostile topography inputs found by fuzzing: damaged instrument headers, sizes near the ends of the doubles,
arrays where one length belongs, huge plain-text tables, statistics of maps whose derivatives overflow when squared.

Each is refused with one line naming the file (and the entry), or read and analysed without a warning.
"""

import json
import subprocess
import sys
import textwrap
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sealeak.errors import FileFormatError, InputError
from sealeak.topography import LineScans, Topography, _external, _readers, _text, read_topography, surface_statistics

# ---------------------------------------------------------------------------- 1. damaged instrument headers


class _Broken:
    """A SurfaceTopography reader whose header parsing fails as it does on a damaged file."""

    def __init__(self, exc):
        self.exc = exc

    @property
    def channels(self):
        raise self.exc

    def topography(self, **_):
        raise AssertionError("the data were read")


def _read_external(path, reader, **options):
    kw = {"pixel_size": None, "size": None, "height_unit": None, "lateral_unit": None, "periodic": False,
          "channel": None, **options}
    return _external._read(path, reader, **kw)


@pytest.mark.parametrize("exc", [ValueError("could not convert string to float: '4.38e-07\\x00\\x7f'"),
                                 TypeError("int() argument must be a string, not 'NoneType'"),
                                 KeyError("x"), IndexError("list index out of range"),
                                 UnicodeDecodeError("utf-8", b"\xff", 0, 1, "invalid start byte")])
def test_an_instrument_file_whose_header_the_reader_cannot_parse_is_a_file_format_error(tmp_path, exc):
    with pytest.raises(FileFormatError) as info:
        _read_external(tmp_path / "scan.al3d", _Broken(exc))
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'scan.al3d'}: cannot be read")
    assert type(exc).__name__ in message and "\n" not in message and len(message) < 500


def test_a_channel_whose_declared_grid_cannot_be_read_is_a_file_format_error(tmp_path):
    """The channel list parses, but its grid (nb_grid_pts None: a zeroed header byte of a .nc) does not."""
    channel = SimpleNamespace(name="Height", unit="m", physical_sizes=(1e-3, 1e-3), nb_grid_pts=(None, 4))
    reader = SimpleNamespace(channels=[channel], default_channel=channel, topography=_Broken(None).topography)
    with pytest.raises(FileFormatError, match=r"scan\.nc: cannot be read.*TypeError"):
        _read_external(tmp_path / "scan.nc", reader)


@pytest.mark.parametrize(("grid", "sizes", "expected"), [((0, 4), (1e-3, 1e-3), "declares a grid of 0 × 4 points"),
                                                         ((2, 3, 4), (1.0, 1.0, 1.0), "declares a grid of 2 × 3 × 4"),
                                                         ((4, 4), (1e-3,), "states 1 physical size")])
def test_a_channel_declaring_an_impossible_grid_is_refused_before_its_data_are_read(tmp_path, grid, sizes, expected):
    channel = SimpleNamespace(name="Height", unit="m", physical_sizes=sizes, nb_grid_pts=grid)
    reader = SimpleNamespace(channels=[channel], default_channel=channel, topography=_Broken(None).topography)
    with pytest.raises(FileFormatError, match=expected):
        _read_external(tmp_path / "scan.sur", reader)


# ---------------------------------------------------------------------------- 2. sizes near the ends of the doubles


def _npz(path, **arrays):
    np.savez(path, heights=np.random.default_rng(0).random((8, 8)), height_unit=np.array("m"), **arrays)
    return path


@pytest.mark.parametrize(("key", "value", "why"), [("size", 5e-324, "below"), ("size", 1e-101, "below"),
                                                   ("size", 1e101, "beyond"), ("pixel_size", 5e-324, "below"),
                                                   ("size", [1e-3, 5e-324], "below")])
def test_an_npz_stating_a_size_outside_the_allowed_range_is_refused_naming_the_entry(tmp_path, key, value, why):
    path = _npz(tmp_path / "s.npz", **{key: np.array(value)})
    with pytest.raises(FileFormatError) as info:
        read_topography(path)
    message = str(info.value)
    assert message.startswith(f"{path}: array {key!r}") and "1e-100 m and 1e+100 m" in message and why in message


def test_an_npz_size_at_the_ends_of_the_range_is_read(tmp_path):
    small = read_topography(_npz(tmp_path / "small.npz", size=np.array(1e-100)))
    large = read_topography(_npz(tmp_path / "large.npz", size=np.array(1e100)))
    assert small.size == (1e-100, 1e-100) and large.size == (1e100, 1e100)


def test_a_sidecar_stating_a_subnormal_size_is_refused(tmp_path):
    np.save(tmp_path / "map.npy", np.random.default_rng(1).random((8, 8)))
    (tmp_path / "map.npy.json").write_text(json.dumps({"size": [5e-324, 5e-324], "height_unit": "m"}))
    with pytest.raises(FileFormatError, match=r"map\.npy\.json: sidecar: size = .*1e-100 m and 1e\+100 m"):
        read_topography(tmp_path / "map.npy")


def test_a_pixel_size_times_the_points_beyond_the_range_is_refused(tmp_path):
    np.save(tmp_path / "map.npy", np.random.default_rng(1).random((8, 8)))
    with pytest.raises(FileFormatError, match=r"map\.npy: size \(pixel size × points\) \(x\) = 1\.6e\+100 m"):
        read_topography(tmp_path / "map.npy", pixel_size=2e99, height_unit="m")


def test_xyz_columns_spanning_a_subnormal_size_are_refused(tmp_path):
    rows = [f"{i * 5e-324!r} {j * 5e-324!r} {(i * j) % 3}" for i in range(4) for j in range(4)]
    (tmp_path / "grid.xyz").write_text("\n".join(rows) + "\n")
    with pytest.raises(FileFormatError, match=r"grid\.xyz: map size .* m: a length between 1e-100 m"):
        read_topography(tmp_path / "grid.xyz", lateral_unit="m", height_unit="um")


def test_x_h_columns_spanning_a_subnormal_length_are_refused(tmp_path):
    (tmp_path / "line.txt").write_text("".join(f"{i * 5e-324!r} {i % 3}\n" for i in range(8)))
    with pytest.raises(FileFormatError, match=r"line\.txt: profile length .* m: a length between 1e-100 m"):
        read_topography(tmp_path / "line.txt", lateral_unit="m", height_unit="um")


def test_an_instrument_file_stating_a_subnormal_physical_size_is_refused(tmp_path):
    channel = SimpleNamespace(name="Height", unit="m", physical_sizes=(5e-324, 1e-3), nb_grid_pts=(8, 8))
    topo = SimpleNamespace(heights=lambda: np.random.default_rng(2).random((8, 8)), is_uniform=True, info={},
                           short_reliability_cutoff=lambda: None)
    reader = SimpleNamespace(channels=[channel], default_channel=channel, topography=lambda **_: topo)
    with pytest.raises(FileFormatError, match=r"scan\.sur: physical size \(x\) = 4\.94066e-324 m"):
        _read_external(tmp_path / "scan.sur", reader)


def test_a_number_given_as_a_length_must_lie_in_the_range_as_a_length_with_a_unit_does(tmp_path):
    np.save(tmp_path / "map.npy", np.ones((4, 4)))
    with pytest.raises(InputError, match="1e-100 m and 1e\\+100 m"):
        read_topography(tmp_path / "map.npy", size=5e-324, height_unit="m")


# ---------------------------------------------------------------------------- 3. an array where a length belongs


def test_an_npz_size_of_many_values_is_described_by_its_shape_in_one_line(tmp_path):
    path = _npz(tmp_path / "big.npz", size=np.ones((1000, 1000)))
    with pytest.raises(FileFormatError) as info:
        read_topography(path)
    message = str(info.value)
    assert "\n" not in message and len(message) < 300, message
    assert "array 'size'" in message and "shape (1000, 1000)" in message and "one length or two" in message


def test_an_npz_unit_holding_an_array_is_described_in_one_line(tmp_path):
    np.savez(tmp_path / "u.npz", heights=np.ones((4, 4)), height_unit=np.array([["m"] * 50] * 50))
    with pytest.raises(FileFormatError) as info:
        read_topography(tmp_path / "u.npz", size="1 mm")
    assert "\n" not in str(info.value) and "shape (50, 50)" in str(info.value)


# ---------------------------------------------------------------------------- 4. plain text in bounded memory


def _line_by_line(monkeypatch):
    """Make the text reader take every piece line by line (the reference the numpy path must agree with)."""
    monkeypatch.setattr(_text._Scan, "_fast", lambda self, piece, lineno: None)


def _outcome(path, text):
    try:
        raw = _text.parse_text(path, text.encode())
    except FileFormatError as exc:
        return type(exc).__name__, str(exc)
    return raw.kind, raw.heights.tolist(), None if raw.x is None else raw.x.tolist(), raw.meta


_TOKENS = st.sampled_from(["1", "-2.5", "3e-3", "+.5", "nan", "inf", "1e500", "0,5", "1,000", "x", "1_0", "7."])
_SEPARATORS = st.sampled_from([" ", "\t", ",", ";", ", ", " ; ", "  "])
_LINES = st.one_of(
    st.tuples(st.lists(_TOKENS, min_size=1, max_size=5), _SEPARATORS).map(lambda t: t[1].join(t[0])),
    st.sampled_from(["", "   ", "# a comment", "  % another", "// third", "# size: 1 mm", "# height_unit: µm",
                     "# periodic = true", "1 2 # trailing", "µ 1 2", "1\u00a02", "1\x0c2", "1\r2"]))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines=st.lists(_LINES, min_size=1, max_size=40), ending=st.sampled_from(["\n", "\r\n", ""]),
       piece=st.sampled_from([1, 7, 64, 2**18]))
def test_the_numpy_text_reader_agrees_with_reading_line_by_line(tmp_path, monkeypatch, lines, ending, piece):
    """Same tables, headers and errors (type, line and message), whatever the pieces the text is cut into."""
    path = tmp_path / "t.txt"
    text = ending.join(lines) + ending if ending else "\n".join(lines)
    with monkeypatch.context() as m:
        m.setattr(_text, "_PIECE_CHARS", piece)
        fast = _outcome(path, text)
        _line_by_line(m)
        slow = _outcome(path, text)
    assert repr(fast) == repr(slow)


def test_a_table_of_more_heights_than_a_map_may_hold_is_refused_while_it_is_read(tmp_path, monkeypatch):
    monkeypatch.setattr(_text, "MAX_POINTS", 1000)
    monkeypatch.setattr(_text, "_PIECE_CHARS", 64)
    (tmp_path / "c.txt").write_text("1\n2\n" * 5000)
    with pytest.raises(FileFormatError, match=r"c\.txt: more than 1,000 heights by line 10\d\d; at most 1,000"):
        read_topography(tmp_path / "c.txt", height_unit="um", size="1 mm")


_PEAK = textwrap.dedent("""
    import resource, sys, time
    from sealeak.topography import read_topography
    read_topography(sys.argv[2], height_unit="um", size="1 mm")  # imports and unit tables loaded
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    start = time.perf_counter()
    s = read_topography(sys.argv[1], height_unit="um", size="1 mm")
    seconds = time.perf_counter() - start
    print(s.heights.size, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - before, seconds)
""")


def test_a_long_column_of_heights_is_read_in_memory_proportional_to_its_values(tmp_path):
    """2 M values (4 MB of text): a few float64 per value (the old reader: ~175 bytes per value, 5 s)."""
    n = 2_000_000
    (tmp_path / "c.txt").write_text("1\n2\n" * (n // 2))
    (tmp_path / "small.txt").write_text("1\n2\n3\n4\n")
    run = subprocess.run([sys.executable, "-c", _PEAK, str(tmp_path / "c.txt"), str(tmp_path / "small.txt")],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    points, grown, seconds = run.stdout.split()
    assert int(points) == n
    assert int(grown) < 64 * n, f"{int(grown) / n:.0f} bytes per value"
    assert float(seconds) < 30, seconds  # about 1 s; generous for a loaded machine


def test_a_text_file_beyond_the_size_limit_is_refused_before_it_is_read(tmp_path, monkeypatch):
    monkeypatch.setattr(_readers, "MAX_TEXT_BYTES", 2**20)
    with open(tmp_path / "huge.txt", "wb") as fh:  # 1 MiB and 1 byte; sparse past its first lines
        fh.write(b"1.5\n" * 2048)
        fh.truncate(2**20 + 1)

    def never(self):
        raise AssertionError("the whole file was read")

    monkeypatch.setattr(Path, "read_bytes", never)
    with pytest.raises(FileFormatError, match=r"huge\.txt: text file of 1 MiB is larger than the 1 MiB"):
        read_topography(tmp_path / "huge.txt", height_unit="um", size="1 mm")


def test_a_single_very_long_row_is_read_in_pieces(tmp_path, monkeypatch):
    monkeypatch.setattr(_text, "_PIECE_CHARS", 100)
    values = np.random.default_rng(3).random(5000)
    (tmp_path / "row.txt").write_text(" ".join(repr(float(v)) for v in values) + "\n")
    s = read_topography(tmp_path / "row.txt", height_unit="m", size="1 mm")
    assert isinstance(s, LineScans) and np.array_equal(s.heights[0], values)


def test_a_bad_value_far_into_a_long_file_is_named_by_its_line(tmp_path):
    lines = ["0.5 1.5 2.5 3.5"] * 100_000
    lines[76_543] = "0.5 1.5 oops 3.5"
    text = "# header\n" + "\n".join(lines) + "\n"
    with pytest.raises(_text.NotPlainText, match=r"m\.txt: line 76545: 'oops' is not a number"):
        _text.parse_text(tmp_path / "m.txt", text.encode())


def test_a_ragged_row_far_into_a_long_file_is_named_by_its_line(tmp_path):
    lines = ["0.5;1.5;2.5;3.5"] * 100_000
    lines[99_998] = "0.5;1.5;2.5"
    with pytest.raises(FileFormatError, match=r"m\.csv: line 99999 has 3 values but line 1 has 4"):
        _text.parse_text(tmp_path / "m.csv", "\n".join(lines).encode())


# ---------------------------------------------------------------------------- 5. statistics that overflow when squared


def _map(size):
    rng = np.random.default_rng(5)
    return Topography(heights=1e-6 * rng.standard_normal((16, 16)), size=(size, size))


def test_the_curvature_of_a_map_of_tiny_pixels_is_computed_without_overflow():
    """Curvature ~1e196 1/m: its square overflows, the rms does not (and no RuntimeWarning, an error here)."""
    tiny, mm = surface_statistics(_map(1e-100)), surface_statistics(_map(1e-3))
    assert tiny.curvature_rms == pytest.approx(mm.curvature_rms * 1e194, rel=1e-9)
    assert tiny.slope_rms == pytest.approx(mm.slope_rms * 1e97, rel=1e-9)
    assert 0.5 * tiny.slope_rms < tiny.area_ratio < tiny.slope_rms  # <√(1 + |∇h|²)> ≈ <|∇h|> for huge slopes
    assert tiny.h_rms == pytest.approx(mm.h_rms, rel=1e-12, abs=0)


def test_the_statistics_of_profiles_of_tiny_pixels_are_computed_without_overflow():
    h = 1e-6 * np.random.default_rng(6).standard_normal((2, 64))
    tiny = surface_statistics(LineScans(heights=h, length=1e-100))
    mm = surface_statistics(LineScans(heights=h, length=1e-3))
    assert tiny.curvature_rms == pytest.approx(mm.curvature_rms * 1e194, rel=1e-9)


def test_the_moments_of_tiny_heights_are_computed_without_underflow():
    """Heights of 1e-170 m: their squares underflow to 0; h_rms, skewness and kurtosis do not."""
    h = np.random.default_rng(7).standard_normal((16, 16))
    tiny = surface_statistics(Topography(heights=1e-170 * h, size=(1e-3, 1e-3)))
    unit = surface_statistics(Topography(heights=h, size=(1e-3, 1e-3)))
    assert tiny.h_rms == pytest.approx(unit.h_rms * 1e-170, rel=1e-12, abs=0)
    assert tiny.kurtosis == pytest.approx(unit.kurtosis, rel=1e-9)
    assert tiny.skewness == pytest.approx(unit.skewness, rel=1e-6, abs=1e-12)
