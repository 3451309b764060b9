"""Outputs that collide: with each other, with an input, or empty; refused up front through the CLI.

Every refusal: exit status 2, one line ``sealeak: error: ...`` naming the path(s), no traceback, and
nothing written or replaced (the folder holds exactly what it held before, byte for byte).
"""

import os
import shutil

import pytest

from sealeak.cases import example_path
from sealeak.cli import main

DATA = example_path("reference-experiment").parent / "reference-measured.csv"


@pytest.fixture
def work(tmp_path, monkeypatch):
    """A folder with a case file, a data file, a height map and a C(q) table; the working directory."""
    shutil.copy(example_path("reference-experiment"), tmp_path / "case.toml")
    shutil.copy(DATA, tmp_path / "good.csv")
    (tmp_path / "h.txt").write_text("0 1 2 1\n1 0 2 1\n2 1 0 1\n1 2 1 0\n")
    (tmp_path / "psd.csv").write_text("q (1/m), C (m^4)\n1e4, 1e-20\n1e5, 1e-23\n1e6, 1e-26\n")
    (tmp_path / "r.csv").write_text("time (min), height (cm)\n0, 20\n10, 19\n20, 18\n")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _snapshot(folder):
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None) for p in sorted(folder.rglob("*"))}


def _refused(capsys, work, argv, *names):
    """Run ``sealeak argv`` and check the refusal; return the message."""
    before = _snapshot(work)
    capsys.readouterr()
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sealeak: error: "), err
    assert "Traceback" not in err and out == ""
    for name in names:
        assert name in lines[0], (name, lines[0])
    assert _snapshot(work) == before, "something was written or replaced"
    return lines[0]


FIT = ["fit", "case.toml", "--data", "good.csv"]

NESTED = {
    "predict --json X --plots X": (["predict", "case.toml", "--json", "y.json", "--plots", "y.json"], "--json y.json", "--plots y.json"),
    "predict --table X --plots X": (["predict", "case.toml", "--table", "t.txt", "--plots", "t.txt"], "--table t.txt", "--plots t.txt"),
    "predict --csv below --json": (["predict", "case.toml", "--json", "a", "--csv", os.path.join("a", "b.csv")], "--json a", "--csv a"),
    "fit --json X --plots X": (FIT + ["--json", "y", "--plots", "y"], "--json y", "--plots y"),
    "fit --linearity --json X --plots X": (FIT + ["--linearity", "--json", "y", "--plots", "y"], "--json y", "--plots y"),
    "rig --json X --plots X": (["rig", "case.toml", "--json", "y", "--plots", "y"], "--json y", "--plots y"),
    "simulate --fields X --json X": (["simulate", "case.toml", "--fields", "X", "--json", "X"], "--json X", "--fields X"),
    "simulate --fields below --json": (["simulate", "case.toml", "--fields", os.path.join("X", "f"), "--json", "X"], "--json X", "--fields X"),
    "simulate --json X --plots X": (["simulate", "case.toml", "--json", "X", "--plots", "X"], "--json X", "--plots X"),
    "analyze --plot below --json": (["surface", "analyze", "h.txt", "--size", "1 mm", "--height-unit", "um", "--json", "j",
                                     "--plot", os.path.join("j", "p.png")], "--json j", "--plot j"),
}


@pytest.mark.parametrize("force", [False, True], ids=["", "force"])
@pytest.mark.parametrize("key", list(NESTED))
def test_output_inside_another_output_is_refused_up_front(capsys, work, key, force):
    argv, *names = NESTED[key]
    _refused(capsys, work, argv + (["--force"] if force else []), *names)


def _hard_link(work):
    os.link(work / "case.toml", work / "same.toml")
    return "same.toml"


INPUTS = {
    "analyze --psd-out = height map": ["surface", "analyze", "h.txt", "--size", "1 mm", "--height-unit", "um", "--psd-out", "h.txt"],
    "analyze --json = height map": ["surface", "analyze", "h.txt", "--size", "1 mm", "--height-unit", "um", "--json", "h.txt"],
    "predict --table = case": ["predict", "case.toml", "--table", "case.toml"],
    "predict --csv = case, other spelling": ["predict", "case.toml", "--csv", os.path.join("sub", "..", "case.toml")],
    "predict --json = case, absolute": ["predict", "case.toml", "--json", "ABS/case.toml"],
    "fit --json = data": FIT + ["--json", "good.csv"],
    "fit --json = case": FIT + ["--json", "case.toml"],
    "rig --json = readings": ["rig", "case.toml", "--readings", "r.csv", "--json", "r.csv"],
    "report -o = case": ["report", "case.toml", "-o", "case.toml"],
    "simulate --json = case": ["simulate", "case.toml", "--json", "case.toml"],
    "synthesize -o = --psd table": ["surface", "synthesize", "--psd", "psd.csv", "--size", "1 mm", "--grid", "8", "-o", "psd.csv"],
}


@pytest.mark.parametrize("force", [False, True], ids=["", "force"])
@pytest.mark.parametrize("key", list(INPUTS))
def test_output_that_is_an_input_is_refused_even_with_force(capsys, work, key, force):
    argv = [a.replace("ABS", str(work)) for a in INPUTS[key]]
    msg = _refused(capsys, work, argv + (["--force"] if force else []))
    assert "is the input" in msg and "already exist" not in msg


def test_output_hard_linked_to_an_input_is_refused(capsys, work):
    name = _hard_link(work)
    msg = _refused(capsys, work, ["predict", "case.toml", "--json", name, "--force"], name, "case.toml")
    assert "is the input" in msg


EMPTY = {
    "predict --json": ["predict", "case.toml", "--json", ""],
    "predict --plots": ["predict", "case.toml", "--plots", ""],
    "predict --table": ["predict", "case.toml", "--table", ""],
    "predict --csv": ["predict", "case.toml", "--csv", ""],
    "fit --json": FIT + ["--json", ""],
    "fit --plots": FIT + ["--plots", ""],
    "rig --plots": ["rig", "case.toml", "--plots", ""],
    "simulate --fields": ["simulate", "case.toml", "--fields", ""],
    "simulate --json": ["simulate", "case.toml", "--json", ""],
    "report --output": ["report", "case.toml", "--output", ""],
    "analyze --psd-out": ["surface", "analyze", "h.txt", "--size", "1 mm", "--height-unit", "um", "--psd-out", ""],
}


@pytest.mark.parametrize("key", list(EMPTY))
def test_empty_output_path_is_refused_naming_the_option(capsys, work, key):
    option = key.split()[-1]
    msg = _refused(capsys, work, EMPTY[key], option)
    assert "empty" in msg


def test_file_output_inside_the_plots_folder_is_allowed(capsys, work):
    """Not a collision: a --json file in the --plots folder, next to the figures."""
    assert main(["predict", "case.toml", "-q", "--json", os.path.join("out", "a.json"), "--plots", "out"]) == 0
    assert (work / "out" / "a.json").is_file() and any((work / "out").glob("*.png"))
