"""The documentation matches the tool: every option, every case-file key, the README's example."""

import argparse
import contextlib
import importlib.util
import io
import re
import shlex
import tomllib
from pathlib import Path

import pytest

from sealeak.cases import parse_cases
from sealeak.cases.loader import example_data_names, example_names, example_text
from sealeak.cases.schema import SECTIONS, TOP_LEVEL
from sealeak.cli import build_parser, main
from tests.textmatch import same_text

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"


def _sub_parsers(parser: argparse.ArgumentParser, prefix: str = ""):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield f"{prefix}{name}", sub
                yield from _sub_parsers(sub, f"{prefix}{name} ")


COMMANDS = dict(_sub_parsers(build_parser()))


def test_every_command_is_documented():
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    missing = [name for name in COMMANDS if f"sealeak {name}" not in text]
    assert not missing


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_option_is_documented(command):
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    options = [o for a in COMMANDS[command]._actions for o in a.option_strings if o.startswith("--")]
    missing = [o for o in options if not re.search(r"`" + re.escape(o) + r"(?![\w-])", text)]
    assert not missing, f"sealeak {command}: {missing} not in docs/cli.md"


def test_every_case_file_key_is_documented():
    text = (ROOT / "docs" / "case-files.md").read_text(encoding="utf-8")
    keys = [f"{section}.{key}" for section, keys in SECTIONS.items() for key in keys] + sorted(TOP_LEVEL)
    missing = [k for k in keys if f"`{k}`" not in text]
    assert not missing, f"not in docs/case-files.md: {missing}"


def test_readme_is_short_and_opens_with_the_two_commands():
    text = README.read_text(encoding="utf-8")
    assert len(text.encode("utf-8")) <= 12 * 1024
    first_block = text.split("```")[1]
    assert "make demo" in first_block and "make test" in first_block


# ---------------------------------------------------------------- every shown command runs and prints what is shown
#
# In README.md and the docs pages below, every line of a code block that starts with "$ " is a command
# a reader can type; the lines after it (up to the next "$ " line or the end of the block) are what it
# prints on stdout. A line "..." stands for any number of lines, so a block can show an excerpt.
# Commands: `sealeak ARGS [> FILE]` (run in-process) and `cat FILE`. The files the commands read are
# the ones the pages show (a ```toml block introduced by `NAME.toml`), run in one folder per page.

DOCS = ROOT / "docs"
PAGES = [README, DOCS / "index.md", DOCS / "user-guide.md", DOCS / "cli.md", DOCS / "case-files.md"]
ELLIPSIS = {"...", "…"}


def _shown_files(text):
    """The case files a page shows: {"ring.toml": text} for a ```toml block introduced by `ring.toml`."""
    return dict(re.findall(r"`([\w.-]+\.toml)`[^\n]*\n\n```toml\n(.*?)```", text, re.S))


def _sessions(text):
    """(command, shown output lines) for every "$ " line of every code block, in page order."""
    out = []
    for block in re.findall(r"^```[a-z]*\n(.*?)^```", text, re.S | re.M):
        lines = block.splitlines()
        if not any(ln.startswith("$ ") for ln in lines):
            continue
        assert lines[0].startswith("$ "), f"a block with commands starts with one: {lines[0]!r}"
        for ln in lines:
            if ln.startswith("$ "):
                out.append((ln[2:], []))
            else:
                out[-1][1].append(ln)
    return out


def _run(command, folder):
    """Run one shown command in ``folder``; return (exit status, stdout)."""
    argv = shlex.split(command, comments=True)
    target = None
    if len(argv) > 2 and argv[-2] == ">":
        argv, target = argv[:-2], argv[-1]
    if argv[0] == "cat":
        return 0, (folder / argv[1]).read_text(encoding="utf-8")
    assert argv[0] in ("sealeak", ".venv/bin/sealeak"), f"not a command the docs test can run: {command}"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(folder), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv[1:])
    if target is not None:
        (folder / target).write_text(out.getvalue(), encoding="utf-8")
        return status, ""
    return status, out.getvalue()


def _same_lines(shown, actual):
    """Line by line, the text exactly and the numbers within the cross-machine tolerance of tests/textmatch.py."""
    return len(shown) == len(actual) and all(map(same_text, shown, actual))


def _is_excerpt(shown, actual):
    """Whether ``shown`` lines are ``actual`` lines, with "..." lines standing for any number of lines
    (numbers compared with a relative tolerance: the last bit of a result differs between CPUs)."""
    actual = [ln.rstrip() for ln in actual]
    pieces, piece = [], []
    for ln in shown:
        if ln.strip() in ELLIPSIS:
            pieces.append(piece)
            piece = []
        else:
            piece.append(ln.rstrip())
    pieces.append(piece)
    pos = 0
    for k, piece in enumerate(pieces):
        if not piece:
            continue
        if k == 0:  # no "..." before it: the output starts with it
            if not _same_lines(piece, actual[:len(piece)]):
                return False
            pos = len(piece)
            continue
        found = next((i for i in range(pos, len(actual) - len(piece) + 1) if _same_lines(piece, actual[i:i + len(piece)])), None)
        if found is None:
            return False
        pos = found + len(piece)
    return not pieces[-1] or pos == len(actual)  # no "..." after the last piece: the output ends with it


def test_excerpt_rule():
    actual = ["a", "b", "c", "d"]
    assert _is_excerpt(actual, actual)
    assert _is_excerpt(["a", "...", "d"], actual) and _is_excerpt(["...", "b", "c", "..."], actual)
    assert not _is_excerpt(["a", "b"], actual)            # the output goes on: "..." needed
    assert not _is_excerpt(["...", "c", "b", "..."], actual)  # order matters
    assert not _is_excerpt(["a", "x", "..."], actual)
    # the last bit of a result may differ on another CPU; another value may not
    printed = ['"leak_rate": 6.376955986710464e-06,', "Q = 6.38e-06"]
    assert _is_excerpt(['"leak_rate": 6.376955986710466e-06,', "Q = 6.37e-06"], printed)
    assert not _is_excerpt(['"leak_rate": 6.3769559e-06,', "Q = 6.38e-06"], printed)


README_FILES = _shown_files(README.read_text(encoding="utf-8"))


def test_readme_shows_the_case_file_its_commands_use():
    assert "ring.toml" in README_FILES
    parse_cases(README_FILES["ring.toml"], ROOT, "ring.toml")  # a valid case


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_shown_command_prints_what_the_page_shows(page, tmp_path):
    text = page.read_text(encoding="utf-8")
    files = dict(README_FILES)
    for name, body in _shown_files(text).items():
        assert files.get(name, body) == body, f"{page.name} shows a {name} that differs from the README's"
        files[name] = body
    for name, body in files.items():
        (tmp_path / name).write_text(body, encoding="utf-8")
    # the user guide's effective-medium example: ring.toml with model = "both" under [theory]
    (tmp_path / "both.toml").write_text(files["ring.toml"].replace("[theory]\n", '[theory]\nmodel = "both"\n'),
                                        encoding="utf-8")
    sessions = _sessions(text)
    if page in (README, DOCS / "user-guide.md", DOCS / "cli.md"):
        assert sessions, f"{page.name} shows no command"
    for command, shown in sessions:
        status, out = _run(command, tmp_path)
        assert status == 0, f"{page.name}: `{command}` exited with {status}"
        if shown:
            assert _is_excerpt(shown, out.splitlines()), (
                f"{page.name}: `{command}` prints\n{out}\nnot what the page shows:\n" + "\n".join(shown))


def test_bundled_case_shown_in_full_is_the_bundled_file():
    """docs/case-files.md shows reference-experiment.toml: the same text as the file (after its comments)."""
    text = (DOCS / "case-files.md").read_text(encoding="utf-8")
    shown = re.search(r"`reference-experiment` uses most sections:\n\n```toml\n(.*?)```", text, re.S).group(1)
    bundled = example_text("reference-experiment")
    assert shown == bundled[bundled.index("title"):]


def test_every_key_of_a_bundled_case_is_documented():
    text = (DOCS / "case-files.md").read_text(encoding="utf-8")
    used = set()
    for name in example_names():
        doc = tomllib.loads(example_text(name))
        for key, value in doc.items():
            if isinstance(value, dict):
                used |= {f"{key}.{k}" for k in value}
            else:
                used.add(key)
    missing = sorted(k for k in used if f"`{k}`" not in text)
    assert not missing, f"keys of bundled cases not in docs/case-files.md: {missing}"


def test_bundled_data_files_are_what_their_generator_makes():
    spec = importlib.util.spec_from_file_location("make_example_data", ROOT / "tools" / "make_example_data.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert set(module.FILES) == {n for n in example_data_names() if n.endswith("-measured.csv")} == {
        "reference-measured.csv", "o-ring-measured.csv"}
    for name, make in module.FILES.items():  # three rounded digits: a value on a rounding boundary may round either way
        bundled, made = example_text(name).splitlines(), make().splitlines()
        assert len(bundled) == len(made) and all(map(same_text, bundled, made)), name
