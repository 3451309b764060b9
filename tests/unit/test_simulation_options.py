"""The one check of a simulation's options (cases/options.py) and the ensemble pipeline's strategy contract."""

from dataclasses import dataclass, replace

import numpy as np
import pytest

from sealeak.cases import SimulationOptions, load_cases, parse_case_bytes, simulation_options
from sealeak.cases.loader import example_path, example_text
from sealeak.cases.pipeline import Records, TaskRecord, run_ensemble
from sealeak.cases.simulation import SweepRecord, simulate
from sealeak.errors import InputError


def test_given_options_override_the_case_which_overrides_the_defaults():
    opts = simulation_options(realizations=2, defaults={"grid": 64, "seed": 5, "realizations": 8})
    assert opts == SimulationOptions(grids=(64,), realizations=2, seed=5, workers=None, grid_field="simulation.grid")
    built_in = simulation_options()
    assert (built_in.grid, built_in.realizations, built_in.seed, built_in.grid_field) == (256, 4, 0, "--grid")


def test_a_grid_list_is_a_convergence_study_sorted():
    assert simulation_options(grid="128,64").grids == (64, 128)
    assert simulation_options(defaults={"grid": (32, 64)}).grids == (32, 64)


@pytest.mark.parametrize("given, field", [
    ({"grid": 15}, "--grid = 15"), ({"grid": 8}, "--grid = 8"), ({"grid": True}, "--grid = true"),
    ({"grid": "32,33"}, "--grid = '32,33'"), ({"seed": -1}, "--seed = -1"), ({"seed": True}, "--seed = true"),
    ({"realizations": 0}, "--realizations = 0"), ({"workers": -1}, "--workers = -1"),
    ({"workers": 10**6}, "--workers = 1000000"),
])
def test_each_refusal_names_the_option_and_its_value(given, field):
    with pytest.raises(InputError) as err:
        simulation_options(**given)
    assert str(err.value).startswith(field + ": must be")


def test_a_case_value_is_named_by_its_key_and_a_server_may_lower_the_limits():
    with pytest.raises(InputError, match=r"^simulation\.realizations = 20: .* 1 to 16 \(this server's limit\)$"):
        simulation_options(defaults={"realizations": 20}, max_realizations=16, limit_note=" (this server's limit)")
    with pytest.raises(InputError, match=r"^web\.workers = 9: .* 0 to 8"):
        simulation_options(workers=9, max_workers=8, prefix="web.")


def test_the_case_files_and_the_library_apply_the_same_grid_and_seed_rules():
    text = example_text("reference-experiment")
    for bad, field in (("grid = 18", None), ("grid = 15", "simulation.grid = 15"), ("grid = [32, 31]", "simulation.grid"),
                       ("seed = true", "simulation.seed = true")):
        doc = (text + f"\n[simulation]\n{bad}\n").encode()
        if field is None:
            assert parse_case_bytes(doc, "c.toml").cases[0].simulation["grid"] == 18
            continue
        with pytest.raises(InputError, match="^" + field.replace("[", r"\[")):
            parse_case_bytes(doc, "c.toml")
    (case,) = load_cases(example_path("reference-experiment"))
    for kw, field in (({"grid": 17}, "grid = 17"), ({"seed": True}, "seed = true"), ({"grid": 64.0}, "grid = 64.0")):
        with pytest.raises(InputError, match="^" + field):
            simulate(case, **({"grid": 32, "realizations": 1, "seed": 0} | kw))


@dataclass(frozen=True, kw_only=True)
class _ARecord(TaskRecord):
    KIND = "toy-a"

    value: float


@dataclass(frozen=True, kw_only=True)
class _BRecord(TaskRecord):
    KIND = "toy-b"

    value: float


@dataclass
class _Task:
    kind: str
    realization: int

    def run(self, progress=None):
        record = _BRecord if self.kind == "b" else _ARecord
        return record(realization=self.realization, value=10.0 * self.realization + (self.kind == "b"))


@dataclass
class _Toy:
    """A geometry with trivial tasks: checks the order of the pipeline's steps and of the records."""

    calls: list

    def check_memory(self, grid, memory_limit):
        self.calls.append("memory")

    def prepare(self, case, grid, grid_field, notes, progress):
        self.calls.append("prepare")
        notes.append(f"{grid_field} {grid}")
        return grid

    def tasks(self, plan, common, realizations):
        self.calls.append("tasks")
        assert common.grid == plan and not hasattr(common, "spectrum")
        return [_Task(k, r) for r in range(realizations) for k in ("a", "b")]

    def aggregate(self, plan, records: Records, notes):
        self.calls.append("aggregate")
        return (records.stack(_ARecord, lambda rec: [rec.value], 1)[:, 0],
                records.stack(_BRecord, lambda rec: [rec.value], 1)[:, 0], tuple(notes))


def test_a_geometry_strategy_runs_through_the_pipeline_in_realisation_order():
    (case,) = load_cases(example_path("reference-experiment"))
    toy = _Toy([])
    in_order = lambda tasks: [t.run() for t in tasks]  # noqa: E731  # a runner: the results in the order given
    a, b, notes = run_ensemble(toy, case, grid=32, realizations=3, seed=1, grid_field="--grid", runner=in_order)
    assert toy.calls == ["memory", "prepare", "tasks", "aggregate"]
    assert np.array_equal(a, [0.0, 10.0, 20.0]) and np.array_equal(b, [1.0, 11.0, 21.0])
    assert notes == ("--grid 32",)
    checked = _Toy([])
    checked_runner = lambda tasks: [t.run() for t in tasks]  # noqa: E731
    checked_runner.checks_memory = True  # a runner of make_runner checks the memory where the tasks run
    run_ensemble(checked, replace(case), grid=32, realizations=1, seed=1, runner=checked_runner)
    assert "memory" not in checked.calls


def test_a_task_record_round_trips_through_its_mapping_and_anything_else_is_refused():
    rec = _ARecord(realization=2, value=3.5)
    assert rec.to_mapping() == {"kind": "toy-a", "realization": 2, "value": 3.5}
    assert TaskRecord.from_mapping(rec.to_mapping()) == rec
    for bad in ({"kind": "toy-a", "realization": 2}, {"kind": "toy-c", "realization": 0, "value": 1.0}, [1.0]):
        with pytest.raises(ValueError):
            TaskRecord.from_mapping(bad)


def test_a_liquid_sweep_record_keeps_no_gas_columns_and_no_fields_in_its_mapping():
    rec = SweepRecord(realization=0, relative_contact_area=[0.1], percolates=[True], leak_rate=[1e-9], mean_gap=[1e-6])
    assert set(rec.to_mapping()) == {"kind", "realization", "relative_contact_area", "percolates", "leak_rate",
                                     "contact_maps", "mean_gap"}
    assert TaskRecord.from_mapping(rec.to_mapping()) == rec
