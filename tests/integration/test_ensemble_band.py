"""The O-ring route as tasks (one per realisation): the same numbers from the plain loop, 2 Dask workers and a plain
reimplementation of the realisation loop; a store resumes without recomputing; fields kept in the store carry the load.
"""

import json
from dataclasses import fields as dataclass_fields

import numpy as np
import pytest
import zarr

from sealeak import numerics
from sealeak.cases import load_cases
from sealeak.cases.ensemble import make_runner
from sealeak.cases.simulation_band import run_band_task, simulate_band
from sealeak.cli import main
from sealeak.numerics.synthesis import synthesize
from tests.integration.test_cli_simulate_oring import ORING

GRID, REALIZATIONS, SEED = 32, 3, 3


@pytest.fixture(scope="module")
def case_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("oring") / "oring.toml"
    path.write_text(ORING)
    return path


@pytest.fixture(scope="module")
def case(case_path):
    (c,) = load_cases(case_path)
    return c


@pytest.fixture(scope="module")
def plain(case):
    return simulate_band(case, grid=GRID, realizations=REALIZATIONS, seed=SEED)


def assert_same(a, b):
    for f in dataclass_fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, dict):
            assert x.keys() == y.keys(), f.name
            for k in x:
                np.testing.assert_array_equal(x[k], y[k], err_msg=f"{f.name}[{k}]")
        elif isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y, err_msg=f.name)
        elif f.name != "gas":
            assert x == y, f.name


def test_two_workers_and_a_plain_loop_give_the_same_numbers(case, plain):
    """Every field of the result (per-realisation arrays, contact maps, p̄(x)) from 2 Dask workers equals the plain
    run's; and the per-realisation leak rates equal a plain loop written here from the solvers, with the tasks' spec."""
    specs = []

    def runner(tasks):
        specs.append(tasks[0].spec)
        return make_runner(workers=2, task_function=run_band_task)(tasks)

    assert_same(plain, simulate_band(case, grid=GRID, realizations=REALIZATIONS, seed=SEED, runner=runner))
    spec = specs[0]
    for r in range(REALIZATIONS):
        h = synthesize(spec.spectrum, GRID, spec.size, seed=np.random.default_rng([SEED, r]))
        prev = None
        for i, f in enumerate(spec.forces):
            prev = numerics.solve_band_contact(h, spec.size, spec.size, spec.e_star, spec.radius, float(f),
                                               tol=spec.contact_tol, initial=prev)
            flow = numerics.solve_flow(prev.gap, spec.size, spec.viscosity, spec.pressure_difference, contact=prev.contact)
            assert plain.per_realization["leak_rate"][r, i] == spec.scale * flow.flux
            assert plain.per_realization["percolates"][r, i] == flow.percolates
            if r == 0:
                np.testing.assert_array_equal(plain.contact_maps[i], prev.contact)
                np.testing.assert_array_equal(plain.line_pressure[i], prev.line_pressure)


class Counting:
    def __init__(self, fail_after=None):
        self.names, self.fail_after = [], fail_after

    def __call__(self, task):
        if self.fail_after is not None and len(self.names) == self.fail_after:
            raise KeyboardInterrupt
        self.names.append(task.name)
        return run_band_task(task)


def test_store_resumes_without_recomputing(case, plain, tmp_path):
    store = tmp_path / "store"
    first = Counting(fail_after=1)
    with pytest.raises(KeyboardInterrupt):
        simulate_band(case, grid=GRID, realizations=REALIZATIONS, seed=SEED,
                      runner=make_runner(workers=0, store=store, task_function=first))
    assert first.names == ["band-r0"] and [p.name for p in (store / "tasks").iterdir()] == ["band-r0.json"]
    again, notes = Counting(), []
    res = simulate_band(case, grid=GRID, realizations=REALIZATIONS, seed=SEED,
                        runner=make_runner(workers=0, store=store, task_function=again, note=notes.append))
    assert again.names == ["band-r1", "band-r2"]
    assert f"resumed: 1 of 3 tasks from {store}" in notes
    assert_same(plain, res)


def test_cli_oring_on_two_workers_keeps_fields_in_the_store(case_path, tmp_path):
    """--workers 2 --store DIR --store-fields on an O-ring: the JSON of the plain loop; each realisation's maps in
    DIR/fields.zarr, one per compression, the contact pressure carrying the force per length (Σ p dx dy = f Ly)."""
    base = ["simulate", str(case_path), "--grid", str(GRID), "--realizations", "2", "--seed", "1", "-q"]
    assert main([*base, "--workers", "0", "--json", str(tmp_path / "plain.json")]) == 0
    store = tmp_path / "store"
    assert main([*base, "--workers", "2", "--store", str(store), "--store-fields", "--json", str(tmp_path / "d.json")]) == 0
    assert json.loads((tmp_path / "plain.json").read_text()) == json.loads((tmp_path / "d.json").read_text())
    root = zarr.open_group(str(store / "fields.zarr"), mode="r")
    assert sorted(root.group_keys()) == ["r0", "r1"]
    g = root["r1"]
    forces, size = g.attrs["force_per_length"], g.attrs["size"]
    assert g["gap"].metadata.dimension_names == ("compression", "x", "y")
    np.testing.assert_allclose(g["compression"][...], [0.03, 0.05], rtol=1e-12)
    p = g["pressure"][...]
    for i, f in enumerate(forces):
        cell = (size / GRID) ** 2
        assert p[i].sum() * cell == pytest.approx(f * size, rel=1e-9)
    assert (g["gap"][...] >= 0).all() and g["height"].shape == (GRID, GRID)
