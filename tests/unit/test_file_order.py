"""The test files' order switch of tests/conftest.py (SEALEAK_TEST_FILE_ORDER, docs/development.md)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parents[1]
FILES = ["unit/test_approx_guard.py", "unit/test_file_order.py"]


def _collected(order: str | None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "SEALEAK_TEST_FILE_ORDER"}
    if order is not None:
        env["SEALEAK_TEST_FILE_ORDER"] = order
    return subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                           *(str(TESTS / f) for f in FILES)], cwd=TESTS.parent, env=env, capture_output=True,
                          text=True, timeout=120)


def _files(out: str) -> list[str]:
    seen: list[str] = []
    for line in out.splitlines():
        if "::" in line and line.split("::")[0] not in seen:
            seen.append(line.split("::")[0])
    return seen


@pytest.fixture(scope="module")
def plain():
    res = _collected(None)
    assert res.returncode == 0, res.stdout + res.stderr
    return [line for line in res.stdout.splitlines() if "::" in line]


@pytest.mark.parametrize("order", [None, "reverse", "3"])
def test_files_run_in_the_order_asked_each_whole(order, plain):
    res = _collected(order)
    assert res.returncode == 0, res.stdout + res.stderr
    files = _files(res.stdout)
    assert sorted(files) == sorted(f"tests/{f}" for f in FILES)
    lines = [line for line in res.stdout.splitlines() if "::" in line]
    # each file's tests together and in their own order
    assert lines == sorted(plain, key=lambda line: files.index(line.split("::")[0]))
    if order is None:
        assert files == [f"tests/{f}" for f in FILES]
    elif order == "reverse":
        assert files == [f"tests/{f}" for f in reversed(FILES)]


def test_an_order_that_is_neither_reverse_nor_a_seed_is_refused():
    res = _collected("sideways")
    assert res.returncode != 0 and "SEALEAK_TEST_FILE_ORDER = 'sideways'" in res.stdout + res.stderr
