"""Hostile case files and options (issue 21 §4) are refused before any work: exit status 2, one line naming
the file or the key, no traceback, no output written or replaced, in bounded time and memory.

Each command runs in a subprocess limited to 1.5 GB of address space (a valid run needs less than half);
the inputs that used to take the machine down (3.5 GB, RecursionError, MemoryError) must now be refused
within that, in seconds.
"""

import resource
import subprocess
import sys
import time

import pytest

from sealeak.cases import example_text, parse_case_bytes, parse_case_file
from sealeak.cases.limits import MAX_CASE_FILE_BYTES, MAX_REALIZATIONS
from sealeak.errors import FileFormatError, InputError
from tests.casefiles import BASE, edit

CLI = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"  # as in test_cli_inputs.py
MEMORY = 1_500_000_000  # bytes of address space for the child


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def refused(tmp_path, argv, *names):
    """Run ``sealeak argv`` with a kept output and ``--force``: exit 2, one line naming ``names``, nothing written."""
    kept = tmp_path / "kept.json"
    kept.write_text("earlier result\n")
    start = time.monotonic()
    run = subprocess.run([sys.executable, "-c", CLI, *argv, "--json", str(kept), "--force"], capture_output=True,
                         text=True, timeout=120, preexec_fn=_limit_memory, cwd=tmp_path)
    elapsed = time.monotonic() - start
    assert run.returncode == 2, run.stderr[-2000:]
    assert run.stderr.startswith("sealeak: error: ") and run.stderr.count("\n") == 1, run.stderr[-2000:]
    assert "Traceback" not in run.stderr and len(run.stderr) < 400, run.stderr
    for name in names:
        assert name in run.stderr, (name, run.stderr)
    assert kept.read_text() == "earlier result\n"
    inputs = (a for a in argv if a.endswith((".toml", ".npy", ".npz")))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["kept.json", *inputs])
    assert elapsed < 60, elapsed  # start-up and the refusal: seconds, never the minutes of the work
    return run.stderr


def _line(text, snippet):
    """The line number of ``snippet`` in ``text``."""
    return text[:text.index(snippet)].count("\n") + 1


END = BASE.count("\n") + 1  # the first line after BASE
THEORY = _line(BASE, "[theory]") + 1  # the key _with_theory_key adds


def _with_theory_key(line):
    return edit("[theory]\n", f"[theory]\n{line}\n")


CASES = {  # name: (case text, what the error names)
    "dotted key of 20000 parts": (BASE + "x" + ".x" * 20_000 + " = 1\n", [f"case.toml: line {END}", "dotted key", "32"]),
    "inline tables 5000 deep": (_with_theory_key("x = " + "{a = " * 5_000 + "1" + "}" * 5_000),
                                [f"case.toml: line {THEORY}", "nested", "32"]),
    "arrays 100000 deep": (_with_theory_key("x = " + "[" * 100_000 + "]" * 100_000), [f"case.toml: line {THEORY}", "nested"]),
    "integer of 5000 digits": (edit("alpha = 0.2", "alpha = " + "2" * 5_000), [f"case.toml: line {_line(BASE, 'alpha')}", "5000 characters", "at most 1000"]),
    "range of 100000 points": (edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                                    'squeeze_pressure = {start = "20 kPa", stop = "1 MPa", num = 100000}'),
                               ["conditions.squeeze_pressure.num = 100000", "10000"]),
    "150000 pressures": (edit('["20 kPa", "60 kPa", "0.1 MPa"]', "[" + "2e4, " * 150_000 + "]"),
                         ["conditions.squeeze_pressure = [", "150000 pressures", "at most 10000"]),
    "10^6 pressures": (edit('["20 kPa", "60 kPa", "0.1 MPa"]', "[" + '"20 kPa", ' * 10**6 + "]"),
                       ["case.toml: is 10000", f"at most {MAX_CASE_FILE_BYTES} bytes"]),
    "1000 study values": (BASE + '[study]\nvary = "surface.hurst"\nvalues = [' + "0.8, " * 1_000 + "]\n",
                          ["study.values", "1000 values", "at most 100"]),
    "O-ring compression range of 100000 points": (
        example_text("o-ring").replace('compression = { start = "10 %", stop = "30 %", num = 9 }',
                                       'compression = { start = "10 %", stop = "30 %", num = 100000 }'),
        ["conditions.compression.num", "= 100000: must be a whole number from 1 to 1000\n"]),
}


@pytest.mark.parametrize("text, names", CASES.values(), ids=list(CASES))
def test_a_hostile_case_file_is_refused_in_one_line_in_bounded_memory(tmp_path, text, names):
    (tmp_path / "case.toml").write_text(text)
    refused(tmp_path, ["predict", "case.toml"], *names)


def test_the_o_ring_example_still_has_the_range_the_hostile_one_replaces():
    assert 'compression = { start = "10 %", stop = "30 %", num = 9 }' in example_text("o-ring")


@pytest.mark.parametrize("argv, names", [
    (["--realizations", "1000000000000"], ["--realizations = 1000000000000", f"from 1 to {MAX_REALIZATIONS}"]),
    (["--realizations", "1e12"], ["--realizations = '1e12'"]),
    (["--workers", "100000"], ["--workers = 100000", "1024"]),
    (["--grid", ",".join(str(n) for n in range(16, 1000, 2))], ["--grid = '16,18,20", "grids: at most 16"]),
], ids=["realizations", "realizations 1e12", "workers", "grids"])
def test_simulate_options_are_bounded(tmp_path, argv, names):
    refused(tmp_path, ["simulate", "--example", "reference-experiment", "--grid", "16", *argv], *names)


def test_simulate_realizations_of_the_case_file_are_bounded(tmp_path):
    (tmp_path / "case.toml").write_text(BASE + "[simulation]\ngrid = 16\nrealizations = 1000000000000\n")
    refused(tmp_path, ["simulate", "case.toml"], "simulation.realizations = 1000000000000", "10000")


def test_a_huge_case_file_is_refused_before_it_is_read(tmp_path):
    case = tmp_path / "case.toml"
    with case.open("wb") as f:  # sparse: 3 GB on the file system's books, nothing on the disk
        f.truncate(3 * 10**9)
    refused(tmp_path, ["predict", "case.toml"], "case.toml: is 3000000000 bytes", "at most 1000000 bytes")


# ------------------------------------------------------------------ the library the web app shares
def test_the_shared_parser_refuses_too_many_bytes_naming_the_source():
    data = BASE.encode() + b"#" * MAX_CASE_FILE_BYTES
    with pytest.raises(FileFormatError, match=r"^upload\.toml: is \d+ bytes: a case file may have at most"):
        parse_case_bytes(data, ".", "upload.toml")
    assert parse_case_bytes(BASE.encode() + b"#" * (MAX_CASE_FILE_BYTES - len(BASE) - 1), ".", "ok.toml").cases
    with pytest.raises(FileFormatError, match=r"^text\.toml: is \d+ bytes"):  # the text parser too
        parse_case_file(data.decode(), ".", "text.toml")


def test_the_shared_parser_refuses_deep_nesting_naming_the_source():
    with pytest.raises(FileFormatError, match=rf"^upload\.toml: line {THEORY}: tables and arrays nested"):
        parse_case_bytes(_with_theory_key("x = " + "[" * 200 + "]" * 200).encode(), ".", "upload.toml")


@pytest.mark.parametrize("value", [
    "x" * 100_000,
    list(range(10**6)),
    {"a": {"b": {"c": {"d": {"e": list(range(100))}}}}},
], ids=["long text", "long list", "deep table"])
def test_an_error_shows_a_long_or_deep_value_in_one_short_line(value):
    message = str(InputError("study.values", value, "allowed: something else"))
    assert "\n" not in message and len(message) < 250, message
    assert message.startswith("study.values = ") and "..." in message


def test_a_study_value_that_fails_is_shown_short():
    text = BASE + '[study]\nvary = "surface.h_rms"\nvalues = ["' + "4" * 3_000 + ' um"]\n'
    with pytest.raises(InputError) as err:
        parse_case_bytes(text.encode(), ".", "s.toml")
    assert "\n" not in str(err.value) and len(str(err.value)) < 400, str(err.value)


@pytest.mark.parametrize("key", ['"' + "k" * 100_000 + '"', '"a\\nb"'], ids=["long key", "key with a newline"])
def test_an_unknown_key_is_named_in_one_short_line(key):
    with pytest.raises(InputError) as err:
        parse_case_bytes(edit("[rubber]\n", f"[rubber]\n{key} = 1\n").encode(), ".", "k.toml")
    message = str(err.value)
    assert message.startswith("rubber.") and "unknown key in [rubber]" in message, message
    assert "\n" not in message and len(message) < 400, message


def test_a_topography_of_thousands_of_files_is_refused_before_any_is_read(tmp_path):
    (tmp_path / "h.txt").write_text("0 1\n1 0\n")  # a file that exists: without the limit it would be read 5000 times
    surface = '[surface]\nmodel = "topography"\npixel_size = "1 um"\nfiles = [' + '"h.txt", ' * 5_000 + "]\n"
    text = BASE.replace(BASE[BASE.index("[surface]"):BASE.index("[rubber]")], surface)
    with pytest.raises(InputError, match=r"^surface\.files = \['h\.txt', .*: 5000 files: at most 100 "):
        parse_case_bytes(text.encode(), tmp_path, "t.toml")


# ------------------------------------------------------------------ topography files that expand
def _huge_header(shape=(100_000, 100_000)):
    import io

    import numpy as np

    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": "<f8", "fortran_order": False, "shape": shape})
    return buf.getvalue()


@pytest.mark.parametrize("name", ["bomb.npz", "big.npy"])
def test_a_small_map_file_declaring_billions_of_heights_is_refused_before_it_expands(tmp_path, name):
    import zipfile

    if name == "bomb.npz":
        with zipfile.ZipFile(tmp_path / name, "w", compression=zipfile.ZIP_DEFLATED) as z:
            with z.open("heights.npy", "w", force_zip64=True) as f:  # 200 MB of zeros in about 200 kB
                f.write(_huge_header())
                for _ in range(200):
                    f.write(bytes(1 << 20))
    else:
        (tmp_path / name).write_bytes(_huge_header() + bytes(64))
    assert (tmp_path / name).stat().st_size < 1_000_000
    refused(tmp_path, ["surface", "analyze", name, "--pixel-size", "1 um", "--height-unit", "m"],
            f"{name}: declares 100000 × 100000 = 10,000,000,000 heights", "at most 67,108,864")


def test_an_npz_of_many_arrays_is_refused_before_any_is_read(tmp_path):
    import numpy as np

    np.savez(tmp_path / "many.npz", heights=np.zeros((4, 4)), **{f"a{i}": np.zeros(1) for i in range(40)})
    refused(tmp_path, ["surface", "analyze", "many.npz", "--pixel-size", "1 um", "--height-unit", "m"],
            "many.npz: .npz holds 41 arrays")


def test_an_instrument_file_declaring_too_many_points_is_refused_before_its_data_are_read(tmp_path):
    from types import SimpleNamespace

    from sealeak.topography import _external

    def never(**_):
        raise AssertionError("the data were read")

    channel = SimpleNamespace(name="Height", unit="m", physical_sizes=(1e-3, 1e-3), nb_grid_pts=(10_000, 10_000))
    reader = SimpleNamespace(channels=[channel], default_channel=channel, topography=never)
    with pytest.raises(FileFormatError, match="declares 10000 × 10000 = 100,000,000 heights"):
        _external._read(tmp_path / "map.datx", reader, pixel_size=None, size=None, height_unit=None,
                        lateral_unit=None, periodic=False, channel=None)
