"""docs/outputs.md lists every output field with the unit and description its result class declares."""

import importlib.util
from pathlib import Path

import pytest

from sealeak.cases.gas import GAS_UNITS, HELIUM_UNITS
from sealeak.cases.run import BAND_EFFECTIVE_MEDIUM_UNITS, BAND_UNITS, EFFECTIVE_MEDIUM_UNITS, RESULT_UNITS
from sealeak.render.convergence import CONVERGENCE_UNITS
from sealeak.render.lab import DECAY_UNITS, FIT_UNITS, LINEARITY_UNITS, RIG_UNITS
from sealeak.render.simulation import BAND_SIMULATION_GAS_UNITS, BAND_SIMULATION_UNITS, SIMULATION_GAS_UNITS
from sealeak.render.surface import SURFACE_UNITS

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "outputs.md"


def _tool():
    spec = importlib.util.spec_from_file_location("output_fields", ROOT / "tools" / "output_fields.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_output_fields_page_is_what_the_fields_metadata_gives():
    text = DOC.read_text(encoding="utf-8")
    assert _tool().rewritten(text) == text, "docs/outputs.md is out of date: run tools/output_fields.py"


@pytest.mark.parametrize("units", [RESULT_UNITS, EFFECTIVE_MEDIUM_UNITS, BAND_UNITS, BAND_EFFECTIVE_MEDIUM_UNITS,
                                   GAS_UNITS, HELIUM_UNITS, SIMULATION_GAS_UNITS, BAND_SIMULATION_UNITS,
                                   BAND_SIMULATION_GAS_UNITS, CONVERGENCE_UNITS, FIT_UNITS, LINEARITY_UNITS, RIG_UNITS,
                                   DECAY_UNITS, SURFACE_UNITS])
def test_every_key_an_output_gives_a_unit_is_listed_with_that_unit(units):
    listed = {(cells[1].strip(), cells[2].strip()) for cells in (line.split("|") for line in DOC.read_text(
        encoding="utf-8").splitlines() if line.startswith("| `"))}  # (key, unit) of every table row
    shown = {"": "text", "1": "1 (dimensionless)"}
    renamed = {"leak_rate_pv_series_resistance": "leak_rate_pv_critical_junction"}  # an O-ring's name for the same field
    for key, unit in units.items():
        assert (f"`{renamed.get(key, key)}`", shown.get(unit, f"`{unit}`")) in listed, key
