"""The task store of ``simulate``: resuming an interrupted run, refusing another run's store, damaged task files."""

import json
from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases
from sealeak.cases.ensemble import default_workers, make_runner
from sealeak.cases.simulation import run_task, simulate
from sealeak.errors import InputError

GRID, REALIZATIONS, SEED = 64, 3, 11


@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([2e4, 8e4, 3e5]))


@pytest.fixture(scope="module")
def plain(case):
    """The uninterrupted run without a runner: the reference every stored run must equal."""
    return simulate(case, grid=GRID, realizations=REALIZATIONS, seed=SEED)


class Counting:
    """A task function that counts the tasks it computes (by name) and can fail after ``fail_after`` of them."""

    def __init__(self, fail_after: int | None = None) -> None:
        self.names: list[str] = []
        self.fail_after = fail_after

    def __call__(self, task):
        if self.fail_after is not None and len(self.names) == self.fail_after:
            raise KeyboardInterrupt  # as Ctrl-C in the middle of the run
        self.names.append(task.name)
        return run_task(task)


def assert_same(a, b):
    assert a.per_realization.keys() == b.per_realization.keys()
    for key in a.per_realization:
        np.testing.assert_array_equal(a.per_realization[key], b.per_realization[key], err_msg=key)
    for name in ("relative_contact_area", "leak_rate", "alpha", "alpha_std", "mean_gap"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.percolation_threshold == b.percolation_threshold
    assert a.notes == b.notes
    assert a.contact_maps.keys() == b.contact_maps.keys()
    for i in a.contact_maps:
        np.testing.assert_array_equal(a.contact_maps[i], b.contact_maps[i])


def stored_run(case, store, task_function, notes, seed=SEED, grid=GRID, realizations=REALIZATIONS):
    runner = make_runner(workers=0, store=store, task_function=task_function, note=notes.append)
    return simulate(case, grid=grid, realizations=realizations, seed=seed, runner=runner)


@pytest.mark.parametrize("k", [1, 4])
def test_interrupted_run_resumes_without_recomputing(case, plain, tmp_path, k):
    store = tmp_path / "store"
    first = Counting(fail_after=k)
    with pytest.raises(KeyboardInterrupt):
        stored_run(case, store, first, [])
    assert len(list((store / "tasks").glob("*.json"))) == k  # each finished task was written at once

    again, notes = Counting(), []
    res = stored_run(case, store, again, notes)
    n = 2 * REALIZATIONS  # a sweep and a threshold search per realisation
    assert sorted(again.names) == sorted(set(t for t in again.names))  # none twice
    assert not set(again.names) & set(first.names)  # no finished task computed again
    assert len(again.names) == n - k
    assert f"resumed: {k} of {n} tasks from {store}" in notes
    assert_same(res, plain)

    third = Counting()
    assert_same(stored_run(case, store, third, []), plain)
    assert third.names == []  # everything from the store


def test_more_realisations_reuse_the_first(case, tmp_path):
    store = tmp_path / "store"
    stored_run(case, store, Counting(), [], realizations=1)
    more = Counting()
    res = stored_run(case, store, more, [], realizations=2)
    assert sorted(more.names) == ["sweep-r1", "threshold-r1"]
    assert_same(res, simulate(case, grid=GRID, realizations=2, seed=SEED))


@pytest.mark.parametrize("change, named", [
    ({"seed": SEED + 1}, "seed"),
    ({"grid": 2 * GRID}, "grid"),
    ({"case": "e_star"}, "case"),
    ({"case": "spectrum"}, "spectrum"),
])
def test_store_of_another_run_is_refused(case, tmp_path, change, named):
    store = tmp_path / "store"
    stored_run(case, store, Counting(), [], realizations=1)
    before = {p.name: p.read_bytes() for p in (store / "tasks").iterdir()}
    other, kwargs = case, {"realizations": 1}
    if change.get("case") == "e_star":
        other = replace(case, e_star=case.e_star * 1.01)
    elif change.get("case") == "spectrum":
        other = replace(case, spectrum=replace(case.spectrum, C=case.spectrum.C * 1.1))
    else:
        kwargs |= change
    counting = Counting()
    with pytest.raises(InputError) as err:
        stored_run(other, store, counting, [], **kwargs)
    assert err.value.field == "--store"
    assert named in str(err.value) and "\n" not in str(err.value)
    assert counting.names == []
    assert {p.name: p.read_bytes() for p in (store / "tasks").iterdir()} == before  # nothing mixed in


@pytest.mark.parametrize("damage", ["truncate", "flip-digit", "not-json", "empty"])
def test_damaged_task_file_is_computed_again_with_a_note(case, plain, tmp_path, damage):
    store = tmp_path / "store"
    stored_run(case, store, Counting(), [])
    path = store / "tasks" / "sweep-r1.json"
    text = path.read_text()
    if damage == "truncate":
        path.write_text(text[: len(text) // 2])
    elif damage == "flip-digit":  # still valid JSON, one number changed: only the checksum tells
        record = json.loads(text)
        record["result"]["leak_rate"][0] *= 1.0000001
        path.write_text(json.dumps(record))
    elif damage == "not-json":
        path.write_bytes(b"\x00\xff garbage")
    else:
        path.write_text("")
    again, notes = Counting(), []
    res = stored_run(case, store, again, notes)
    assert again.names == ["sweep-r1"]
    assert any(str(path) in n and "damaged" in n for n in notes)
    assert_same(res, plain)
    rest = Counting()
    stored_run(case, store, rest, [])  # the recomputed result was stored again, intact
    assert rest.names == []


@pytest.mark.parametrize("setup, words", [
    ("other-files", "no manifest.json"),
    ("bad-manifest", "manifest.json"),
    ("foreign-manifest", "not a store"),
    ("is-a-file", "is a file"),
])
def test_folder_that_is_no_store_is_refused(case, tmp_path, setup, words):
    store = tmp_path / "store"
    if setup == "is-a-file":
        store.write_text("x")
    else:
        store.mkdir()
        name, text = {"other-files": ("notes.txt", "mine"), "bad-manifest": ("manifest.json", "{oops"),
                      "foreign-manifest": ("manifest.json", '{"format": "something else"}')}[setup]
        (store / name).write_text(text)
    with pytest.raises(InputError) as err:
        stored_run(case, store, Counting(), [], realizations=1)
    assert err.value.field == "--store" and words in str(err.value)


@pytest.mark.parametrize("workers", [-1, 1.5, True])
def test_workers_must_be_a_whole_number(workers):
    with pytest.raises(InputError) as err:
        make_runner(workers=workers)
    assert err.value.field == "--workers"


def test_default_workers_plain_loop_below_512():
    assert default_workers(256) == 0 and default_workers(510) == 0
    assert default_workers(512) >= 1 and default_workers() == default_workers(4096) >= 1
