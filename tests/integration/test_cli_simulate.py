"""The numerically exact pipeline: reproducibility, bookkeeping, spectrum cut, CLI output."""

import json
from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases
from sealeak.cli import main


@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([2e4, 8e4, 3e5]))




def test_simulation_section_gives_defaults_options_override(tmp_path):
    text = example_path("reference-experiment").read_text().replace(
        '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }', '["100 kPa"]')
    (tmp_path / "c.toml").write_text(text + '\n[simulation]\ngrid = 16\nrealizations = 1\nseed = 3\n')
    (case,) = load_cases(tmp_path / "c.toml")
    assert case.simulation == {"grid": 16, "realizations": 1, "seed": 3}
    assert main(["simulate", str(tmp_path / "c.toml"), "--no-threshold", "--json", str(tmp_path / "a.json"), "-q"]) == 0
    a = json.loads((tmp_path / "a.json").read_text())
    assert (a["settings"]["grid"], a["settings"]["realizations"], a["settings"]["seed"]) == (16, 1, 3)
    assert main(["simulate", str(tmp_path / "c.toml"), "--no-threshold", "--grid", "32", "--json",
                 str(tmp_path / "b.json"), "-q"]) == 0
    assert json.loads((tmp_path / "b.json").read_text())["settings"]["grid"] == 32
    for bad in ("grid = 15", "grid = 2", "realizations = 0", 'seed = "x"'):
        (tmp_path / "bad.toml").write_text(text + f"\n[simulation]\n{bad}\n")
        assert main(["simulate", str(tmp_path / "bad.toml"), "-q"]) == 2
