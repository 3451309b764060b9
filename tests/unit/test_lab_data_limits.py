"""Data and readings files are bounded before they are parsed, and a rig's readings are checked before its model runs.

A fuzzer found that a 24 MB file of 3 M leak-rate rows was parsed whole (26 s, 1 GB) before the 10 000-row limit
refused it, that rig readings had no limit at all (3 M readings ran past two minutes), that a readings column
without a unit was told to write 'time (kPa)', and that bad pressure-decay readings were refused only after the
model had run. Time is not asserted here: the tests assert that the table is never parsed, that peak memory stays
far below the file's, and that the model is never called.
"""

from __future__ import annotations

import tracemalloc

import pytest

import sealeak.cases
import sealeak.cases.leak_tests
import sealeak.lab.data
from sealeak.cli import main
from sealeak.errors import FileFormatError
from sealeak.lab import read_leak_data, read_rig_readings
from sealeak.lab.data import MAX_DATA_BYTES, MAX_DATA_ROWS, MAX_READINGS
from sealeak.lab.rig import read_decay_readings

LEAK_HEADER = "squeeze_pressure (kPa), leak_rate (ml/min)\n"


@pytest.fixture
def parses(monkeypatch):
    """The number of times a data or readings table was parsed (read_unit_table called)."""
    calls = []
    real = sealeak.lab.data.read_unit_table

    def spy(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(sealeak.lab.data, "read_unit_table", spy)
    monkeypatch.setattr("sealeak.lab.rig.read_unit_table", spy, raising=False)  # (where the old code read decay readings)
    return calls


def _peak(fn, *args):
    """``fn(*args)``'s FileFormatError message and the peak of memory allocated meanwhile (bytes)."""
    tracemalloc.start()
    try:
        with pytest.raises(FileFormatError) as exc:
            fn(*args)
        return str(exc.value), tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


# ------------------------------------------------------------------ defect 1: leak-rate data files
def test_a_data_file_far_over_the_row_limit_is_refused_without_being_parsed(tmp_path, parses):
    path = tmp_path / "many.csv"
    rows = 250_000  # 2 MB: under the byte limit, 25 times the row limit
    path.write_text(LEAK_HEADER + "20, 453\n" * rows)
    assert path.stat().st_size <= MAX_DATA_BYTES
    message, peak = _peak(read_leak_data, path)
    assert message == (f"{path}: has more than {MAX_DATA_ROWS} data rows: at most {MAX_DATA_ROWS} (as many as a "
                       "case's squeeze pressures; each row is a prediction); average repeated measurements first")
    assert parses == []  # counting stopped at the first row past the limit; the table was never built
    assert peak < 3 * path.stat().st_size  # the file's bytes and text, not a list of 250 000 rows


def test_a_data_file_over_the_byte_limit_is_refused_on_its_size_before_it_is_read(tmp_path, parses):
    path = tmp_path / "huge.csv"
    with path.open("w") as f:
        f.write(LEAK_HEADER + "20, 453\n")
        f.truncate(50_000_000)  # sparse: 50 MB that were never written
    message, peak = _peak(read_leak_data, path)
    assert message == (f"{path}: is 50000000 bytes: at most {MAX_DATA_BYTES} bytes (2 MiB, ample for {MAX_DATA_ROWS} "
                       "data rows); average or thin the rows out")
    assert parses == [] and peak < 1_000_000  # not a byte of it read


def test_the_cli_refuses_a_large_data_file_in_one_line(tmp_path, capsys):
    path = tmp_path / "h3m.csv"
    path.write_text(LEAK_HEADER + "20, 453\n" * 300_000)  # 2.4 MB
    assert main(["fit", "--example", "reference-experiment", "--data", str(path)]) == 2
    assert _one_error_line(capsys).endswith(f"h3m.csv: is {path.stat().st_size} bytes: at most {MAX_DATA_BYTES} bytes "
                                            f"(2 MiB, ample for {MAX_DATA_ROWS} data rows); average or thin the rows out")


def test_a_data_file_at_the_row_limit_is_read_and_one_past_it_counted_exactly(tmp_path):
    at = tmp_path / "at.csv"
    at.write_text("# measured\n" + LEAK_HEADER + "".join(f"{20 + i / 1000:.3f}, 400\n\n" for i in range(MAX_DATA_ROWS)))
    assert len(read_leak_data(at)) == MAX_DATA_ROWS  # comments and blank lines are no rows
    over = tmp_path / "over.csv"
    over.write_text(LEAK_HEADER + "20, 400\n" * (MAX_DATA_ROWS + 1))
    with pytest.raises(FileFormatError, match=rf"has {MAX_DATA_ROWS + 1} data rows: at most {MAX_DATA_ROWS} "):
        read_leak_data(over)


# ------------------------------------------------------------------ defect 2: rig readings
def _readings(path, n, column="height (cm)"):
    path.write_text(f"time (s), {column}\n" + "".join(f"{i}, {2000 - i * 1e-3:.3f}\n" for i in range(n)))
    return path


@pytest.mark.parametrize("read, column", [(read_rig_readings, "height (cm)"), (read_decay_readings, "pressure (mbar)")])
def test_readings_far_over_the_limit_are_refused_without_being_parsed(tmp_path, parses, read, column):
    path = _readings(tmp_path / "readings.csv", 100_000, column)  # 1.7 MB
    message, peak = _peak(read, path)
    assert message == (f"{path}: has more than {MAX_READINGS} readings: at most {MAX_READINGS} (one every 10 s for "
                       "more than a day); thin the readings out")
    assert parses == [] and peak < 3 * path.stat().st_size


@pytest.mark.parametrize("read, column", [(read_rig_readings, "height (cm)"), (read_decay_readings, "pressure (mbar)")])
def test_readings_at_the_limit_are_read_and_one_past_it_refused(tmp_path, read, column):
    t, _ = read(_readings(tmp_path / "at.csv", MAX_READINGS, column))
    assert t.size == MAX_READINGS
    with pytest.raises(FileFormatError, match=rf"has {MAX_READINGS + 1} readings: at most {MAX_READINGS} "):
        read(_readings(tmp_path / "over.csv", MAX_READINGS + 1, column))


@pytest.mark.parametrize("example, column", [("reference-experiment", "height (cm)"), ("pressure-decay", "pressure (mbar)")])
def test_the_rig_command_refuses_too_many_readings_in_one_line(tmp_path, capsys, example, column):
    path = _readings(tmp_path / "readings.csv", 50_000, column)
    assert main(["rig", "--example", example, "--readings", str(path)]) == 2
    assert _one_error_line(capsys).endswith(f"readings.csv: has more than {MAX_READINGS} readings: at most {MAX_READINGS} "
                                            "(one every 10 s for more than a day); thin the readings out")


def test_a_readings_file_over_the_byte_limit_is_refused_on_its_size(tmp_path, capsys):
    path = tmp_path / "big.csv"
    with path.open("w") as f:
        f.write("time (s), height (cm)\n0, 100\n")
        f.truncate(MAX_DATA_BYTES + 1)
    assert main(["rig", "--example", "reference-experiment", "--readings", str(path)]) == 2
    assert _one_error_line(capsys).endswith(f"big.csv: is {MAX_DATA_BYTES + 1} bytes: at most {MAX_DATA_BYTES} bytes "
                                            f"(2 MiB, ample for {MAX_READINGS} readings); average or thin the rows out")


# ------------------------------------------------------------------ defect 3: the example unit fits the column
@pytest.mark.parametrize("text, read, example", [
    ("time, height\n0, 10\n1, 9\n", read_rig_readings, "'time (min)'"),
    ("time (min), height\n0, 10\n1, 9\n", read_rig_readings, "'height (cm)'"),
    ("squeeze_pressure, leak_rate (ml/min)\n20, 1\n", read_leak_data, "'squeeze_pressure (kPa)'"),
    ("squeeze_pressure (kPa), leak_rate (ml/min), dp\n20, 1, 10\n", read_leak_data, "'dp (kPa)'"),
])
def test_a_column_without_a_unit_is_shown_a_unit_of_its_kind(tmp_path, text, read, example):
    path = tmp_path / "file.csv"
    path.write_text(text)
    with pytest.raises(FileFormatError) as exc:
        read(path)
    assert str(exc.value).endswith(f"has no unit: write it in parentheses, e.g. {example}")


# ------------------------------------------------------------------ defect 4: readings checked before the model
def _model_must_not_run(*args, **kwargs):
    raise AssertionError("the rig's model ran before its readings were checked")


@pytest.mark.parametrize("readings, why", [
    ("time (min), pressure (mbar)\n0, 500\n1, 499\n", "reading 1: pressure 50000 Pa is not above the outside pressure"),
    ("time (min), pressure (mbar)\n0, 1500\n0, 1499\n", "reading 2: time 0 s is not after the previous reading"),
    ("time (min), pressure (mbar)\n0, 1500\n", "needs at least two readings"),
    ("time (min), pressure\n0, 1500\n1, 1499\n", "e.g. 'pressure (mbar)'"),
])
def test_bad_decay_readings_are_refused_before_the_model_runs(tmp_path, capsys, monkeypatch, readings, why):
    monkeypatch.setattr(sealeak.cases.leak_tests, "decay_prediction", _model_must_not_run)
    path = tmp_path / "readings.csv"
    path.write_text(readings)
    assert main(["rig", "--example", "pressure-decay", "--readings", str(path)]) == 2
    assert why in _one_error_line(capsys)


@pytest.mark.parametrize("readings, why", [
    ("time (min), height (cm)\n0, 50\n0, 40\n", "reading 2: time 0 s is not after the previous reading"),
    ("time (min), height (cm)\n0, 50\n1, 60\n", "the water level does not fall over the readings"),
    ("time, height (cm)\n0, 50\n1, 40\n", "e.g. 'time (min)'"),
])
def test_bad_water_column_readings_are_refused_before_the_model_runs(tmp_path, capsys, monkeypatch, readings, why):
    monkeypatch.setattr(sealeak.cases, "rig_prediction", _model_must_not_run)
    path = tmp_path / "readings.csv"
    path.write_text(readings)
    assert main(["rig", "--example", "reference-experiment", "--readings", str(path)]) == 2
    assert why in _one_error_line(capsys)
