"""Nothing a user types crashes sealeak or is read as something else; outputs replace regular files only.

Every test drives the command line: exit status 2, one line naming the field or file, no traceback,
no output left behind or replaced.
"""

import os
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from sealeak.cases import example_path
from sealeak.cli import main
from sealeak.io.files import Output, OutputExistsError, OutputWriteError, atomic_write, check_outputs, check_replaceable, write_files
from tests.casefiles import edit
from tests.cli_errors import one_line_error

REFERENCE = str(example_path("reference-experiment"))
MEASURED = str(example_path("reference-experiment").with_name("reference-measured.csv"))
CLI = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"  # the command line in a subprocess


# ------------------------------------------------------------------------------------ quantities in case files
CASE_VALUES = [  # (old text, new text, field named)
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2,3 MPa"', "rubber.youngs_modulus"),
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "1/0 MPa"', "rubber.youngs_modulus"),
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "(2 MPa"', "rubber.youngs_modulus"),
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "1e999999 Pa"', "rubber.youngs_modulus"),
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "1e-200 Pa"', "rubber.youngs_modulus"),  # E*² would underflow
    ('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "0.5 Pa"', "rubber.youngs_modulus"),
    ('h_rms = "44 um"', 'h_rms = "2**1000**1000 um"', "surface.h_rms"),
    ('h_rms = "44 um"', 'h_rms = "44,5 um"', "surface.h_rms"),
    ('pressure_difference = "10 kPa"', 'pressure_difference = "3 kPa + 2 kPa"', "conditions.pressure_difference"),
    ('pressure_difference = "10 kPa"', 'pressure_difference = "1,000 Pa"', "conditions.pressure_difference"),
    ('"60 kPa"', '"6,0e1 kPa"', "conditions.squeeze_pressure[1]"),
    ('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s*"', "fluid.viscosity"),
    ('viscosity = "1 mPa*s"', 'viscosity = "nan mPa*s"', "fluid.viscosity"),
    ('rolloff_wavevector = "9.1e3 1/m"', 'rolloff_wavevector = "9,1e3 1/m"', "surface.rolloff_wavevector"),
    ("alpha = 0.2", 'alpha = "0,2"', "theory.alpha"),
    ("hurst = 0.8", 'hurst = "--0.8"', "surface.hurst"),
    # named as written, with the value it must exceed (it was "seal.outer_diameter = 0.02: ... diameter 0.03 m")
    ('outer_diameter = "4 cm"', 'outer_diameter = "2 cm"', "seal.outer_diameter = '2 cm': must exceed seal.inner_diameter = '3 cm'"),
]


@pytest.mark.parametrize("old, new, field", CASE_VALUES, ids=[c[1] for c in CASE_VALUES])
def test_bad_quantities_in_a_case_file(tmp_path, capsys, old, new, field):
    case = tmp_path / "case.toml"
    case.write_text(edit(old, new))
    kept = tmp_path / "kept.json"
    kept.write_text("earlier result\n")
    new_out = tmp_path / "new.csv"
    assert main(["predict", str(case), "--json", str(kept), "--csv", str(new_out), "--force", "-q"]) == 2
    err = one_line_error(capsys, field)
    assert kept.read_text() == "earlier result\n" and not new_out.exists()
    if "," in new:
        assert "use a decimal point" in err or "thousands" in err


def test_a_decimal_comma_is_never_read_as_another_number(tmp_path, capsys):
    """The issue's case: youngs_modulus = "2,3 MPa" gave E = 23 MPa with exit 0."""
    case = tmp_path / "case.toml"
    case.write_text(edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2,3 MPa"'))
    assert main(["predict", str(case), "-q"]) == 2
    err = one_line_error(capsys, "rubber.youngs_modulus", "'2,3 MPa'")
    assert "write 2.3 MPa: use a decimal point; ',' is not allowed in numbers" in err


# ------------------------------------------------------------------------------------ quantities in options
OPTIONS = [
    ["fit", REFERENCE, "--data", MEASURED, "--at-pressure", "1/0 atm"],
    ["fit", REFERENCE, "--data", MEASURED, "--at-pressure", "1,5 bar"],
    ["fit", REFERENCE, "--data", MEASURED, "--at-pressure", "(1 atm"],
    ["fit", REFERENCE, "--data", "{tmp}/linearity.csv", "--linearity", "--squeeze-pressure", "2**1000**1000 kPa"],
    ["surface", "synthesize", REFERENCE, "--size", "1/0 mm", "-o", "{tmp}/map.npz"],
    ["surface", "synthesize", REFERENCE, "--size", "2,5 mm", "-o", "{tmp}/map.npz"],
    ["surface", "synthesize", REFERENCE, "--size", "1e999999 mm", "-o", "{tmp}/map.npz"],
    ["surface", "analyze", "{tmp}/none.txt", "--resolution", "(2 um"],
    ["surface", "analyze", "{tmp}/none.txt", "--resolution", "0,5 um"],
]


@pytest.mark.parametrize("argv", OPTIONS, ids=[" ".join(a[:1] + a[-2:]) for a in OPTIONS])
def test_bad_quantities_in_options(tmp_path, capsys, argv):
    (tmp_path / "linearity.csv").write_text("pressure_difference (kPa), leak_rate (ml/min)\n5, 1\n10, 2\n20, 4\n")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    option = next(a for a in argv if a.startswith("--") and a not in ("--data", "--linearity"))
    assert main(argv) == 2
    err = one_line_error(capsys, option)
    assert [p.name for p in tmp_path.iterdir()] == ["linearity.csv"]
    if "," in argv[-1] or "," in argv[argv.index(option) + 1]:
        assert "use a decimal point" in err


# ------------------------------------------------------------------------------------ data files
@pytest.mark.parametrize("content, line", [
    ("squeeze_pressure (kPa); leak_rate (ml/min)\n30; 1,5\n60; 2,5\n", 2),
    ("squeeze_pressure (kPa)\tleak_rate (ml/min)\n30\t1.5\n60,5\t2.5\n", 3),
    ("squeeze_pressure (kPa) leak_rate (ml/min)\n30,0 1,5\n", 2),
])
def test_decimal_commas_in_a_data_file_name_the_file_and_line(tmp_path, capsys, content, line):
    data = tmp_path / "measured.csv"
    data.write_text(content)
    assert main(["fit", REFERENCE, "--data", str(data), "--json", str(tmp_path / "fit.json")]) == 2
    one_line_error(capsys, f"{data}: line {line}: ", "use a decimal point; ',' is not allowed in numbers")
    assert not (tmp_path / "fit.json").exists()


def test_a_unit_expression_in_a_data_header_names_the_file(tmp_path, capsys):
    data = tmp_path / "measured.csv"
    data.write_text("squeeze_pressure (1/0 kPa), leak_rate (ml/min)\n30, 1\n60, 2\n")
    assert main(["fit", REFERENCE, "--data", str(data)]) == 2
    one_line_error(capsys, str(data), "squeeze_pressure")


# ------------------------------------------------------------------------------------ outputs
def _fifo(tmp_path):
    p = tmp_path / "pipe.json"
    os.mkfifo(p)
    return p, lambda: stat.S_ISFIFO(os.lstat(p).st_mode)


def _link_to_regular(tmp_path):
    target = tmp_path / "real.json"
    target.write_text("keep me\n")
    p = tmp_path / "link.json"
    p.symlink_to(target)
    return p, lambda: p.is_symlink() and target.read_text() == "keep me\n"


def _link_to_devnull(tmp_path):
    p = tmp_path / "null.json"
    p.symlink_to("/dev/null")
    return p, lambda: p.is_symlink() and stat.S_ISCHR(os.stat("/dev/null").st_mode)


def _dangling_link(tmp_path):
    p = tmp_path / "dangling.json"
    p.symlink_to(tmp_path / "nowhere.json")
    return p, lambda: p.is_symlink() and not (tmp_path / "nowhere.json").exists()


def _folder(tmp_path):
    p = tmp_path / "out.json"
    (p / "inside").mkdir(parents=True)
    return p, lambda: (p / "inside").is_dir()


def _devnull(tmp_path):
    return Path("/dev/null"), lambda: stat.S_ISCHR(os.lstat("/dev/null").st_mode)


NOT_REGULAR = {"fifo": _fifo, "link to a regular file": _link_to_regular, "link to /dev/null": _link_to_devnull,
               "dangling link": _dangling_link, "folder": _folder, "/dev/null": _devnull}
NOT_REGULAR_WORDS = {"fifo": "named pipe", "link to a regular file": "symbolic link", "link to /dev/null": "symbolic link",
                     "dangling link": "symbolic link", "folder": "folder", "/dev/null": "character device"}


@pytest.mark.parametrize("force", [False, True], ids=["", "--force"])
@pytest.mark.parametrize("kind", NOT_REGULAR)
def test_outputs_replace_regular_files_only(tmp_path, capsys, kind, force):
    path, unchanged = NOT_REGULAR[kind](tmp_path)
    other = tmp_path / "results.csv"
    argv = ["predict", "--example", "reference-experiment", "--csv", str(other), "--json", str(path), "-q"]
    assert main(argv + (["--force"] if force else [])) == 2
    err = one_line_error(capsys, path, NOT_REGULAR_WORDS[kind])
    assert unchanged() and not other.exists(), err
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]


def test_the_issue_command_leaves_dev_null_a_device():
    before = os.lstat("/dev/null")
    run = subprocess.run([sys.executable, "-c", CLI, "predict", "--example", "reference-experiment", "--json",
                          "/dev/null", "--force"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.count("\n") == 1 and "/dev/null" in run.stderr and "Traceback" not in run.stderr
    after = os.lstat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev


EVERY_COMMAND = [  # every command's output options, each given a FIFO
    ["predict", REFERENCE, "--table", "{out}"],
    ["predict", REFERENCE, "--csv", "{out}"],
    ["predict", REFERENCE, "--plots", "{dir}"],
    ["fit", REFERENCE, "--data", MEASURED, "--json", "{out}"],
    ["fit", REFERENCE, "--data", MEASURED, "--plots", "{dir}"],
    ["rig", REFERENCE, "--json", "{out}"],
    ["rig", REFERENCE, "--plots", "{dir}"],
    ["report", REFERENCE, "-o", "{out}"],
    ["simulate", REFERENCE, "--grid", "16", "--json", "{out}"],
    ["simulate", REFERENCE, "--grid", "16", "--plots", "{dir}"],
    ["surface", "analyze", "{tmp}/none.txt", "--json", "{out}"],
    ["surface", "analyze", "{tmp}/none.txt", "--psd-out", "{out}"],
    ["surface", "analyze", "{tmp}/none.txt", "--plot", "{out}"],
    ["surface", "synthesize", REFERENCE, "--grid", "16", "-o", "{out}.npz"],
    ["surface", "synthesize", REFERENCE, "--grid", "16", "-o", "{out}.npy"],
]


@pytest.mark.parametrize("argv", EVERY_COMMAND, ids=[" ".join(a[:1] + a[-2:-1]) for a in EVERY_COMMAND])
def test_every_command_refuses_a_fifo_as_output_up_front(tmp_path, capsys, argv):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    os.mkfifo(tmp_path / "pipe.npz")
    os.mkfifo(tmp_path / "pipe.npy")
    argv = [a.replace("{out}", str(fifo)).replace("{dir}", str(fifo)).replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv + ["--force"]) == 2
    err = one_line_error(capsys, fifo)
    assert "named pipe" in err or "not a folder" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe", "pipe.npy", "pipe.npz"]
    assert all(stat.S_ISFIFO(os.lstat(p).st_mode) for p in tmp_path.iterdir())


def test_a_regular_file_is_replaced_with_force_only(tmp_path, capsys):
    out = tmp_path / "out.json"
    out.write_text("old\n")
    assert main(["predict", REFERENCE, "--json", str(out), "-q"]) == 2
    one_line_error(capsys, out, "--force")
    assert out.read_text() == "old\n"
    assert main(["predict", REFERENCE, "--json", str(out), "-q", "--force"]) == 0
    assert out.read_text().startswith("{") and stat.S_ISREG(os.lstat(out).st_mode)


def test_an_output_below_a_file_is_refused_naming_it(tmp_path, capsys):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("x")
    out = blocker / "sub" / "out.json"
    assert main(["predict", REFERENCE, "--json", str(out), "-q"]) == 2
    one_line_error(capsys, out, f"{blocker} is not a folder")


@pytest.mark.parametrize("option", ["--json", "--csv", "--table", "--plots", "--plots below a file"])
def test_an_output_of_the_wrong_kind_is_refused_naming_its_option(tmp_path, capsys, monkeypatch, option):
    monkeypatch.chdir(tmp_path)  # relative paths: a message cuts an option's value at 80 characters, a long tmp_path too
    folder, blocker = Path("results"), Path("notes.txt")
    folder.mkdir()
    blocker.write_text("x")
    given = {"--plots": blocker, "--plots below a file": blocker / "figures"}.get(option, folder)
    assert main(["predict", REFERENCE, option.split()[0], str(given), "-q"]) == 2
    err = one_line_error(capsys, given, "not a folder" if option.startswith("--plots") else "is a folder")
    named = f"{option.split()[0]} = '{given}': " if option.startswith("--plots") else f"{option} {given} is a folder"
    assert err.startswith(f"sealeak: error: {named}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt", "results"] and not any(folder.iterdir())


def test_the_python_api_refuses_the_same_paths(tmp_path):
    fifo = tmp_path / "pipe.txt"
    os.mkfifo(fifo)
    with pytest.raises(OutputExistsError, match="named pipe"):
        check_replaceable(fifo)
    with pytest.raises(OutputExistsError, match="named pipe"):
        with atomic_write(fifo) as tmp:
            tmp.write_text("x")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and list(tmp_path.iterdir()) == [fifo]
    with pytest.raises(OutputExistsError, match="same file"):
        check_outputs([tmp_path / "a.json", tmp_path / "." / "a.json"], force=True)
    assert check_replaceable(tmp_path / "absent.json") is False


@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "folder", "missing", "below a file"])
def test_data_inputs_that_are_not_regular_files_are_refused_not_read_forever(tmp_path, capsys, kind):
    path = {"fifo": tmp_path / "data.csv", "/dev/zero": Path("/dev/zero"), "folder": tmp_path,
            "missing": tmp_path / "none.csv", "below a file": tmp_path / "f.txt" / "data.csv"}[kind]
    if kind == "fifo":
        os.mkfifo(path)
    if kind == "below a file":
        (tmp_path / "f.txt").write_text("x")
    argv = ["fit", REFERENCE, "--data", str(path)]
    if kind in ("fifo", "/dev/zero"):  # in a process of its own: reading these would never end (a timeout fails)
        run = subprocess.run([sys.executable, "-c", CLI, *argv], capture_output=True, text=True, timeout=60)
        assert run.returncode == 2 and run.stderr.count("\n") == 1 and str(path) in run.stderr, run.stderr
        assert "not a regular file" in run.stderr
    else:
        assert main(argv) == 2
        one_line_error(capsys, path)


@pytest.mark.parametrize("command", [["predict"], ["report", "-o", "{tmp}/r.html"], ["rig"], ["simulate", "--grid", "16"]])
def test_a_case_that_is_a_fifo_is_refused_not_read_forever(tmp_path, command):
    fifo = tmp_path / "case.toml"
    os.mkfifo(fifo)
    argv = [command[0], str(fifo), *(a.replace("{tmp}", str(tmp_path)) for a in command[1:])]
    run = subprocess.run([sys.executable, "-c", CLI, *argv], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stderr.count("\n") == 1 and str(fifo) in run.stderr, run.stderr
    assert "named pipe" in run.stderr and "Traceback" not in run.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["case.toml"]


# ------------------------------------------------------------------------------------ outputs all or none
def _full_disk(monkeypatch, fails):
    """tempfile.mkstemp failing with ENOSPC for the temporary files whose prefix ``fails`` takes; the real one."""
    real = tempfile.mkstemp

    def full_disk(*args, **kwargs):
        if fails(kwargs.get("prefix", "")):
            raise OSError(28, "No space left on device")
        return real(*args, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", full_disk)
    return real


def test_outputs_are_written_all_or_none(tmp_path, monkeypatch):
    """write_files: a failure on the third file (a full disk, say) leaves the first two as they were, no temporary file
    and none of the folders it made."""
    (tmp_path / "a.json").write_text("earlier\n")
    real = _full_disk(monkeypatch, lambda prefix: prefix.startswith(".c.png"))
    contents = {str(tmp_path / "a.json"): "new\n", str(tmp_path / "b.csv"): "x\n", str(tmp_path / "new" / "deep" / "c.png"): b"png"}
    with pytest.raises(OutputWriteError, match="c.png: No space left on device"):
        write_files(contents)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"] and (tmp_path / "a.json").read_text() == "earlier\n"
    nested = {str(tmp_path / "out" / "r.json"): "x\n", str(tmp_path / "out" / "figs" / "c.png"): b"png"}  # folders it made,
    with pytest.raises(OutputWriteError):  # one inside the other: both removed, the deeper first
        write_files(nested)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]
    monkeypatch.setattr(tempfile, "mkstemp", real)
    assert write_files(contents) == list(contents)
    assert (tmp_path / "a.json").read_text() == "new\n" and (tmp_path / "new" / "deep" / "c.png").read_bytes() == b"png"


def test_a_figure_folder_that_fails_late_leaves_the_other_outputs_as_they_were(tmp_path, capsys, monkeypatch):
    """--plots in a folder that passes the up-front check but refuses the figures when they are written (a disk that
    fills during the run): one line, exit 2, the --json it was to replace as it was and no --csv."""
    _full_disk(monkeypatch, lambda prefix: prefix.endswith(".png."))  # (the figures' temporary files)
    old = tmp_path / "old.json"
    old.write_text("earlier\n")
    csv = tmp_path / "new.csv"
    rc = main(["predict", REFERENCE, "--json", str(old), "--csv", str(csv), "--plots", str(tmp_path / "figs"), "--force", "-q"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "No space left on device" in err, err
    assert old.read_text() == "earlier\n" and not csv.exists() and not (tmp_path / "figs").exists()


def test_a_file_output_ending_in_a_slash_is_refused_not_written_as_a_file(tmp_path, capsys, monkeypatch):
    """``report -o out/new/`` wrote a regular file named ``out/new``."""
    monkeypatch.chdir(tmp_path)
    assert main(["report", str(example_path("reference-experiment")), "-o", "new/"]) == 2
    assert "names a folder (it ends in '/'): give a file name" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()
    check_outputs([Path("plots")], force=False)  # (a path object never ends in '/': a file name)


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_a_folder_where_no_file_can_be_made_is_refused_before_the_run(tmp_path, capsys):
    """/proc takes no new file, yet the superuser's os.access says it may write there: the run computed the whole case
    and failed on its last step. A file made and removed in the folder up front is the answer; a writable folder keeps
    no trace of it."""
    with pytest.raises(OutputExistsError, match=r"cannot write --json /proc/sealeak-x\.json: "):
        check_outputs([Output("/proc/sealeak-x.json", option="--json")], force=False)
    assert main(["predict", "--example", "reference-experiment", "--json", "/proc/sealeak-x.json"]) == 2
    one_line_error(capsys, "/proc")
    check_outputs([Output(tmp_path / "out.json", option="--json"), Output(tmp_path / "new" / "plots", folder=True)], force=False)
    assert list(tmp_path.iterdir()) == []
