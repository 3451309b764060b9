"""Result fields that carry their unit: one declaration gives a record's keys, its units and its values.

Every bundled example's records hold exactly the keys whose units the result declares, in the same
order, so a field added to a result class reaches the JSON ``units``, the CSV header and the rows at once.
"""

import dataclasses
import math
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from sealeak.cases import SimulationResult, run_case
from sealeak.cases.band import BandColumns, BandEffectiveMediumColumns
from sealeak.cases.capillarity import CapillaryColumns
from sealeak.cases.gas import GasColumns, HeliumColumns
from sealeak.cases.loader import example_names, load_cases
from sealeak.cases.pipeline import GasSimulation
from sealeak.cases.simulation_band import BandSimulationResult
from sealeak.io.quantities import descriptions_of, expand_keys, quantity, record_fields, units_for, units_of
from sealeak.physics.critical_junction import CriticalJunctionResult
from sealeak.physics.effective_medium import EffectiveMediumResult
from sealeak.render.records import json_rows


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Result:
    note: str = ""
    leak_rate: list[float] = quantity("m^3/s", "leak rate through the seal")
    percolates: list[bool] = quantity("1", "a leak channel exists", key="percolates_em")
    regime: tuple[str, ...] = quantity("", "flow regime", default=())


def test_units_keys_and_values_come_from_the_one_declaration():
    r = _Result(leak_rate=[1e-9, 2e-9], percolates=[True, False], regime=("slip", ""))
    assert units_of(_Result) == {"leak_rate": "m^3/s", "percolates_em": "1", "regime": ""}
    assert units_of(r) == units_of(_Result)
    assert record_fields(r) == {"leak_rate": [1e-9, 2e-9], "percolates_em": [True, False], "regime": ("slip", "")}
    assert descriptions_of(_Result)["percolates_em"] == "a leak channel exists"
    assert "note" not in units_of(_Result)  # a field without a unit is no record field


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Fit:
    leak_rate: float = quantity("Pa*m^3/s", "a gas's leak rate")
    fitted: float = quantity("Pa*m^3/s", "a model's fit", key="fitted_<model>")
    fitted_mbar: float = quantity("mbar*l/s", "the same in mbar·l/s", key="fitted_<model>_mbar")


def test_a_document_takes_the_units_of_its_keys_in_its_order_from_the_first_class_declaring_them():
    assert units_for(("regime", "leak_rate"), _Result, _Fit) == {"regime": "", "leak_rate": "m^3/s"}
    assert units_for(("leak_rate",), _Fit, _Result) == {"leak_rate": "Pa*m^3/s"}
    with pytest.raises(KeyError, match="note"):
        units_for(("leak_rate", "note"), _Result)  # a key without a declared unit is an error, never a guess


def test_template_keys_are_written_per_value_each_value_s_keys_together():
    assert list(expand_keys(units_of(_Fit), model=["a", "b"])) == ["leak_rate", "fitted_a", "fitted_a_mbar", "fitted_b",
                                                                    "fitted_b_mbar"]
    assert expand_keys(units_of(_Fit)) == {"leak_rate": "Pa*m^3/s"}


def test_json_rows_repeats_scalars_and_writes_missing_values_as_null():
    rows = json_rows({"q": np.array([1.0, math.nan]), "dp": 2e5, "cells": np.empty(0), "regime": ("slip", "")},
                     ("dp", "q", "cells", "regime"), 2)
    assert rows == [{"dp": 2e5, "q": 1.0, "cells": None, "regime": "slip"},
                    {"dp": 2e5, "q": None, "cells": None, "regime": None}]
    assert list(rows[0]) == ["dp", "q", "cells", "regime"]


@pytest.mark.parametrize("name", example_names())
def test_every_record_key_of_a_bundled_example_has_its_declared_unit(name):
    for case in load_cases(Path(str(resources.files("sealeak") / "examples" / f"{name}.toml")))[:2]:
        result = run_case(case)
        records = result.records()
        assert records
        for rec in records:
            assert [k for k in rec if k != "variant"] == list(result.units)


def test_every_declared_quantity_has_a_description():
    for cls in (CriticalJunctionResult, EffectiveMediumResult, BandColumns, BandEffectiveMediumColumns, GasColumns,
                HeliumColumns, GasSimulation, SimulationResult, BandSimulationResult, CapillaryColumns):
        described = descriptions_of(cls)
        assert described and all(d.strip() for d in described.values()), cls.__name__
        assert set(described) == set(units_of(cls))
