"""The documentation matches the tool: every option, every case-file key, the README's example."""

import argparse
import re
from pathlib import Path

import pytest

from sealeak.cases import parse_cases, run_case
from sealeak.cases.schema import SECTIONS, TOP_LEVEL
from sealeak.cli import build_parser
from sealeak.render import prediction_table

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


def test_readme_example_prints_what_the_readme_shows():
    """The README's case, run through the library, prints exactly the table the README shows."""
    text = README.read_text(encoding="utf-8")
    case_text = re.search(r"```toml\n(.*?)```", text, re.S).group(1)
    shown = re.search(r"prints:\n\n```\n(.*?)```", text, re.S).group(1)
    table = prediction_table([run_case(c) for c in parse_cases(case_text, ROOT, "ring.toml")])
    assert table == shown
