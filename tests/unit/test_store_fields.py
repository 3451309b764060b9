"""Fields in the task store (Zarr): what a task writes, checked against physics and an independent recomputation;
a record never without its fields; damaged or missing fields computed again; the memory estimate of a task."""

import json
import shutil
import tracemalloc
from dataclasses import replace

import numpy as np
import pytest
import zarr

from sealeak.cases import example_path, load_cases
from sealeak.cases.ensemble import make_runner
from sealeak.cases.simulation import TASK_BASE_BYTES, resolved_spectrum_cut, run_task, simulate
from sealeak.io import fieldstore
from sealeak.numerics.synthesis import synthesize

GRID, REALIZATIONS, SEED = 64, 2, 5
PRESSURES = np.array([2e4, 8e4, 3e5])


@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=PRESSURES)


@pytest.fixture(scope="module")
def plain(case):
    return simulate(case, grid=GRID, realizations=REALIZATIONS, seed=SEED)


class Counting:
    def __init__(self):
        self.names = []

    def __call__(self, task):
        self.names.append(task.name)
        return run_task(task)


def run(case, store, *, fields=True, task_function=run_task, notes=None, realizations=REALIZATIONS):
    runner = make_runner(workers=0, store=store, fields=fields, task_function=task_function,
                         note=(notes if notes is not None else []).append)
    return simulate(case, grid=GRID, realizations=realizations, seed=SEED, runner=runner)


@pytest.fixture(scope="module")
def stored(case, tmp_path_factory):
    store = tmp_path_factory.mktemp("fields") / "store"
    return store, run(case, store)


def same_numbers(a, b):
    for key in a.per_realization:
        np.testing.assert_array_equal(a.per_realization[key], b.per_realization[key], err_msg=key)


def test_fields_are_the_physics_of_the_task(case, plain, stored):
    """Each realisation's maps, opened with zarr: the surface is the one the seed draws; the pressure carries the
    squeeze pressure; the gap is the elastic displacement of that pressure (an independent FFT of 2/(E*|q|)) minus the
    heights, plus the rigid approach, clipped at 0; the scalars of the run are those of these maps."""
    store, res = stored
    same_numbers(res, plain)  # keeping fields changes no number
    spectrum = case.spectrum
    q_cut = resolved_spectrum_cut(GRID, case.square_side)
    if spectrum.q_max > q_cut:
        spectrum = spectrum.truncated(None, q_cut)
    root = zarr.open_group(str(store / "fields.zarr"), mode="r")
    assert sorted(root.group_keys()) == [f"r{r}" for r in range(REALIZATIONS)]
    for r in range(REALIZATIONS):
        g = root[f"r{r}"]
        assert (g.attrs["realization"], g.attrs["seed"], g.attrs["grid"]) == (r, SEED, GRID)
        size, e_star = g.attrs["size"], g.attrs["e_star"]
        assert size == case.square_side and e_star == case.e_star
        h, gap, p = g["height"][...], g["gap"][...], g["pressure"][...]
        assert gap.shape == p.shape == (PRESSURES.size, GRID, GRID)
        assert g["gap"].attrs["units"] == "m" and g["pressure"].attrs["units"] == "Pa"
        np.testing.assert_array_equal(g["squeeze_pressure"][...], PRESSURES)
        np.testing.assert_allclose(g["x"][...], (np.arange(GRID) + 0.5) * size / GRID, rtol=1e-15)
        np.testing.assert_array_equal(h, synthesize(spectrum, GRID, size, seed=np.random.default_rng([SEED, r])))
        k = 2 * np.pi * np.fft.fftfreq(GRID, d=size / GRID)
        q = np.hypot(k[:, None], k[None, :])
        compliance = np.where(q > 0, 2.0 / (e_star * np.where(q > 0, q, 1.0)), 0.0)
        for i, p0 in enumerate(PRESSURES):
            assert (p[i] >= 0).all() and (gap[i] >= 0).all()
            assert p[i].mean() == pytest.approx(p0, rel=1e-12)  # Σ p dA = P0 L²
            u = np.real(np.fft.ifft2(compliance * np.fft.fft2(p[i])))
            free = p[i] == 0
            c = np.median((gap[i] - u + h)[free])
            np.testing.assert_allclose(np.maximum(u - h + c, 0.0), gap[i], rtol=0, atol=1e-9 * h.std())
            assert gap[i][~free].max() < 1e-6 * h.std()  # contact: the surfaces touch
            assert res.per_realization["relative_contact_area"][r, i] == np.count_nonzero(p[i] > 0) / GRID**2
            assert res.per_realization["mean_gap"][r, i] == float(gap[i].mean())


def test_fields_open_in_xarray(stored):
    xr = pytest.importorskip("xarray")
    store, _ = stored
    ds = xr.open_zarr(store / "fields.zarr", group="r1", consolidated=False)
    assert ds["gap"].dims == ("squeeze_pressure", "x", "y") and ds["height"].dims == ("x", "y")
    np.testing.assert_array_equal(ds["squeeze_pressure"].values, PRESSURES)
    assert ds["pressure"].attrs["units"] == "Pa" and ds.attrs["realization"] == 1
    root = zarr.open_group(str(store / "fields.zarr"), mode="r")
    np.testing.assert_array_equal(ds["pressure"].sel(squeeze_pressure=8e4).values, root["r1/pressure"][1])


def test_record_holds_the_checksums_of_its_fields(stored):
    store, _ = stored
    assert json.loads((store / "manifest.json").read_text())["fields"] is True
    record = json.loads((store / "tasks" / "sweep-r0.json").read_text())["result"]["fields"]
    assert record["group"] == "r0" and set(record["sha256"]) == {"height", "gap", "pressure"}
    assert fieldstore.fields_intact(store, record)
    assert "fields" not in json.loads((store / "tasks" / "threshold-r0.json").read_text())["result"]
    assert not list((store / ".partial").iterdir())


@pytest.mark.parametrize("damage", ["chunk-deleted", "chunk-changed", "group-deleted"])
def test_damaged_fields_are_computed_again_with_a_note(case, plain, stored, tmp_path, damage):
    store = tmp_path / "store"
    shutil.copytree(stored[0], store)
    group = store / "fields.zarr" / "r1"
    chunk = group / "pressure" / "c" / "2" / "0" / "0"
    if damage == "chunk-deleted":
        chunk.unlink()
    elif damage == "chunk-changed":  # the same values but one: still a valid chunk, only the checksum tells
        a = zarr.open_array(str(group / "pressure"), mode="r+")
        a[2, 0, 0] = a[2, 0, 0] + 1.0
    else:
        shutil.rmtree(group)
    counting, notes = Counting(), []
    res = run(case, store, task_function=counting, notes=notes)
    assert counting.names == ["sweep-r1"]
    assert any("fields of sweep-r1" in n and "computing sweep-r1 again" in n for n in notes), notes
    same_numbers(res, plain)
    record = json.loads((store / "tasks" / "sweep-r1.json").read_text())["result"]["fields"]
    assert fieldstore.fields_intact(store, record)
    again = Counting()
    run(case, store, task_function=again)
    assert again.names == []


def test_fields_without_a_record_are_replaced(case, plain, stored, tmp_path):
    """A task killed after renaming its group in but before its record was written: the group is there, the
    record not; the task is computed again and its new group replaces the old one (intact, nothing left aside)."""
    store = tmp_path / "store"
    shutil.copytree(stored[0], store)
    (store / "tasks" / "sweep-r0.json").unlink()
    a = zarr.open_array(str(store / "fields.zarr" / "r0" / "gap"), mode="r+")
    a[0, 0, 0] = -1.0  # so that the replacement shows
    counting = Counting()
    same_numbers(run(case, store, task_function=counting), plain)
    assert counting.names == ["sweep-r0"]
    record = json.loads((store / "tasks" / "sweep-r0.json").read_text())["result"]["fields"]
    assert fieldstore.fields_intact(store, record)
    assert zarr.open_array(str(store / "fields.zarr" / "r0" / "gap"), mode="r")[0, 0, 0] >= 0
    assert not list((store / ".partial").iterdir())


def test_interrupted_task_leaves_neither_fields_nor_record(case, plain, tmp_path, monkeypatch):
    """Ctrl-C while a task writes its second map: no group in fields.zarr, no record, nothing in .partial."""
    store = tmp_path / "store"
    put = fieldstore.TaskFields.put

    def interrupted(self, i, gap, pressure):
        if i == 1:
            raise KeyboardInterrupt
        put(self, i, gap, pressure)

    monkeypatch.setattr(fieldstore.TaskFields, "put", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run(case, store)
    assert not list((store / "tasks").iterdir())
    assert not any(p.is_dir() for p in (store / "fields.zarr").iterdir())
    assert not list((store / ".partial").iterdir())
    monkeypatch.setattr(fieldstore.TaskFields, "put", put)
    same_numbers(run(case, store), plain)


def test_store_made_without_fields_computes_the_sweeps_again(case, plain, tmp_path):
    """A store without fields, then a run asking for them: the sweeps (not the threshold searches) are computed
    again to write their fields, with one note; from then on the store keeps fields, asked or not."""
    store = tmp_path / "store"
    run(case, store, fields=False)
    assert json.loads((store / "manifest.json").read_text())["fields"] is False
    assert not (store / "fields.zarr").exists()
    counting, notes = Counting(), []
    same_numbers(run(case, store, task_function=counting, notes=notes), plain)
    assert sorted(counting.names) == ["sweep-r0", "sweep-r1"]
    assert any("2 tasks" in n and "without fields" in n for n in notes), notes
    assert json.loads((store / "manifest.json").read_text())["fields"] is True
    more, notes = Counting(), []
    run(case, store, fields=False, task_function=more, notes=notes, realizations=3)  # not asked: written all the same
    assert sorted(more.names) == ["sweep-r2", "threshold-r2"]
    assert any("keeps the fields" in n for n in notes)
    assert sorted(zarr.open_group(str(store / "fields.zarr"), mode="r").group_keys()) == ["r0", "r1", "r2"]


def test_fields_need_a_store():
    from sealeak.errors import InputError

    with pytest.raises(InputError) as err:
        make_runner(workers=0, fields=True)
    assert err.value.field == "--store-fields"


def test_memory_estimate_bounds_what_a_task_allocates(case, tmp_path):
    """Each task's estimate minus the worker's base is at least the peak of the arrays it allocates (tracemalloc
    sees NumPy's allocations), and within a factor 10 of it (the flow's estimate is a bound for any contact)."""
    captured = []

    def capture(tasks):
        captured.extend(tasks)
        return [run_task(t) for t in tasks]

    simulate(replace(case, squeeze_pressure=np.geomspace(2e4, 3e5, 5)), grid=128, realizations=1, seed=1, runner=capture)
    fieldstore.create_field_store(tmp_path)
    for task in captured:
        task = replace(task, spec=replace(task.spec, fields_store=str(tmp_path), fft_workers=1))
        tracemalloc.start()
        try:
            run_task(task)
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        estimate = task.memory_bytes() - TASK_BASE_BYTES
        assert peak <= estimate <= 10 * peak, (task.name, peak, estimate)


def test_runner_checks_each_task_against_this_machines_memory(case, tmp_path):
    """simulate leaves its up-front memory check to a make_runner runner, which refuses a task larger than the memory
    free here (before computing anything, leaving no new store)."""
    from sealeak.errors import ResourceError

    counting = Counting()
    with pytest.raises(ResourceError, match="a task of the 4096x4096 grid needs about .* GiB"):
        simulate(case, grid=4096, realizations=1, seed=0, memory_limit=1e8,
                 runner=make_runner(workers=0, store=tmp_path / "store", task_function=counting))
    assert counting.names == [] and not (tmp_path / "store").exists()
