"""Inputs of the surface commands and odd case-file numbers: one line naming the input, exit 2, nothing hangs."""

import os
import subprocess
import sys

import numpy as np
import pytest

from sealeak.cli import main
from tests.casefiles import edit


@pytest.fixture
def height_map(tmp_path):
    path = tmp_path / "map.txt"
    np.savetxt(path, np.random.default_rng(0).normal(size=(32, 32)))
    return path


@pytest.mark.parametrize(("option", "value", "words"), [
    ("--height-unit", "2**1000**1000 um", "arithmetic is not evaluated"),
    ("--height-unit", "2,5 um", "use a decimal point"),
    ("--height-unit", "kPa", "length"),
    ("--size", "2,5 mm", "use a decimal point"),
    ("--size", "1 mm, 2 mm, 3 mm", "up to 2"),
])
def test_surface_options_are_read_by_the_one_parser(height_map, capsys, option, value, words):
    args = ["surface", "analyze", str(height_map), "--height-unit", "um", "--size", "1 mm"]
    args[args.index(option) + 1] = value
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sealeak: error: {option} = ") and words in err and err.count("\n") == 1


def test_a_fifo_as_topography_file_is_refused_not_read_forever(tmp_path):
    fifo = tmp_path / "map.txt"
    os.mkfifo(fifo)
    code = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"
    run = subprocess.run([sys.executable, "-c", code, "surface", "analyze", str(fifo)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "named pipe" in run.stderr and "Traceback" not in run.stderr


def test_an_integer_too_large_for_a_float_names_the_key(tmp_path, capsys):
    path = tmp_path / "c.toml"
    path.write_text(edit("alpha = 0.2", "alpha = 1" + "0" * 400))
    assert main(["predict", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: theory.alpha = ") and err.count("\n") == 1


@pytest.mark.parametrize(("option", "value"), [("--grid", "15"), ("--realizations", "0"), ("--seed", "-5")])
def test_simulate_names_the_option_at_fault(capsys, option, value):
    assert main(["simulate", "--example", "reference-experiment", option, value, "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sealeak: error: {option} = {value}") and err.count("\n") == 1
