"""The task store on Dask: fields written by the workers bit for bit as by the plain loop; tasks placed on the workers
that can hold them; a worker killed and the client interrupted part-way, then resumed without recomputing.

Tiny grids: these tests check bookkeeping, placement and determinism; test_store_fields checks the physics of the maps.
"""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path

import dask
import numpy as np
import pytest
from distributed import Scheduler, SpecCluster, Worker, get_worker

from sealeak.cases import ensemble as ensemble_module
from sealeak.cases import example_path, load_cases
from sealeak.cases.ensemble import make_runner
from sealeak.cases.simulation import ensemble_tasks, run_task, simulate
from sealeak.cli import main
from sealeak.errors import InputError, ResourceError
from sealeak.io.fieldstore import fields_intact

PRESSURES = np.array([2e4, 8e4, 3e5])


def small_case(pressures=PRESSURES):
    (case,) = load_cases(example_path("reference-experiment"))
    return replace(case, squeeze_pressure=np.asarray(pressures))


def tree(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_cli_store_fields_identical_on_two_workers(tmp_path):
    """--store DIR --store-fields: the plain loop and 2 worker processes write the same JSON and byte-identical
    Zarr stores (every chunk and metadata file), and the records hold the same checksums."""
    path = tmp_path / "case.toml"
    text = example_path("reference-experiment").read_text()
    old = '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }'
    path.write_text(text.replace(old, '["20 kPa", "80 kPa", "300 kPa"]'))
    for w in ("0", "2"):
        assert main(["simulate", str(path), "--grid", "32", "--realizations", "3", "--seed", "4", "--workers", w,
                     "--store", str(tmp_path / f"s{w}"), "--store-fields", "--json", str(tmp_path / f"w{w}.json"),
                     "-q"]) == 0
    assert json.loads((tmp_path / "w0.json").read_text()) == json.loads((tmp_path / "w2.json").read_text())
    a, b = tree(tmp_path / "s0" / "fields.zarr"), tree(tmp_path / "s2" / "fields.zarr")
    assert sorted({k.split("/")[0] for k in a if "/" in k}) == ["r0", "r1", "r2"]
    assert a == b
    for name in ("sweep-r0", "sweep-r1", "sweep-r2"):
        rec = [json.loads((tmp_path / s / "tasks" / f"{name}.json").read_text())["result"]["fields"] for s in ("s0", "s2")]
        assert rec[0] == rec[1] and fields_intact(tmp_path / "s2", rec[1])


# ---------------------------------------------------------------------------------------------------------------
# memory-aware placement: an in-process cluster with a small and a big worker

WHERE: dict[str, str] = {}
LOCK = threading.Lock()


def located(task):
    """run_task, noting which worker ran it (in-process workers: the same process as the test)."""
    with LOCK:
        WHERE[task.name] = get_worker().name
    return run_task(task)


@pytest.fixture
def two_workers():
    """A scheduler with two one-thread workers whose memory limits the test sets (Dask's own memory monitor off:
    in-process workers would measure this whole test process)."""
    clusters = []

    def start(small: int, big: int):
        spec = {name: {"cls": Worker, "options": {"nthreads": 1, "memory_limit": limit}}
                for name, limit in (("small", small), ("big", big))}
        cluster = SpecCluster(workers=spec, scheduler={"cls": Scheduler, "options": {"dashboard_address": ":0"}})
        clusters.append(cluster)
        return cluster

    off = {f"distributed.worker.memory.{k}": False for k in ("target", "spill", "pause", "terminate")}
    with dask.config.set(off):
        WHERE.clear()
        yield start
    for cluster in clusters:
        cluster.close()


def estimates(case, grid, realizations):
    """Every task's memory estimate, from the tasks simulate builds."""
    tasks = []

    def capture(ts):
        tasks.extend(ts)
        return [run_task(t) for t in ts]

    simulate(case, grid=grid, realizations=realizations, seed=0, runner=capture)
    return {t.name: t.memory_bytes() for t in ensemble_tasks(tasks[0].spec, realizations, True)}


def test_tasks_run_only_on_the_worker_that_holds_them(two_workers):
    case = small_case()
    need = estimates(case, 64, 1)
    cluster = two_workers(small=min(need.values()) // 2, big=2 * max(need.values()))
    serial = simulate(case, grid=64, realizations=3, seed=7)
    res = simulate(case, grid=64, realizations=3, seed=7,
                   runner=make_runner(workers=0, scheduler=cluster.scheduler_address, task_function=located))
    assert sorted(WHERE) == sorted(f"{k}-r{r}" for r in range(3) for k in ("sweep", "threshold"))
    assert set(WHERE.values()) == {"big"}
    for key in serial.per_realization:
        np.testing.assert_array_equal(serial.per_realization[key], res.per_realization[key], err_msg=key)


def test_tasks_spread_over_workers_that_all_hold_them(two_workers):
    """Both workers big enough: no restriction, both get tasks (the runner does not funnel work needlessly)."""
    case = small_case(PRESSURES[:1])
    need = estimates(case, 32, 1)
    cluster = two_workers(small=4 * max(need.values()), big=8 * max(need.values()))

    def slow(task):
        time.sleep(0.3)
        return located(task)

    simulate(case, grid=32, realizations=4, seed=1, threshold=False,
             runner=make_runner(workers=0, scheduler=cluster.scheduler_address, task_function=slow))
    assert set(WHERE.values()) == {"small", "big"}


def test_no_worker_holds_the_task_one_line_nothing_submitted(two_workers, tmp_path):
    case = small_case()
    need = estimates(case, 64, 1)
    cluster = two_workers(small=min(need.values()) // 4, big=min(need.values()) // 2)
    store = tmp_path / "store"
    with pytest.raises(InputError) as err:
        simulate(case, grid=64, realizations=2, seed=7, runner=make_runner(
            workers=0, scheduler=cluster.scheduler_address, store=store, task_function=located))
    text = str(err.value)
    assert err.value.field == "grid" and "\n" not in text
    assert "64" in text and f"{need['sweep-r0'] / 2**30:.2f} GiB" in text
    big = next(a for a, w in cluster.scheduler_info["workers"].items() if w["name"] == "big")
    assert big in text
    assert WHERE == {} and not any("sweep" in str(t[0]) for t in cluster.scheduler.transition_log)
    assert not store.exists()  # refused before any task ran: no store left


def test_local_cluster_uses_fewer_workers_when_a_task_needs_more(monkeypatch):
    notes = []
    monkeypatch.setattr(ensemble_module, "machine_memory", lambda: 10 * 2**30)
    assert ensemble_module._local_workers(4, 3 * 2**30, 512, notes.append) == 3
    assert notes == ["a task of the 512x512 grid needs about 3.00 GiB (estimate): the local cluster runs 3 worker "
                     "processes of 3.33 GiB each instead of 4 of 2.50 GiB"]
    assert ensemble_module._local_workers(2, 3 * 2**30, 512, notes.append) == 2 and len(notes) == 1
    with pytest.raises(InputError) as err:
        ensemble_module._local_workers(2, 11 * 2**30, 4096, notes.append)
    assert err.value.field == "grid" and "11.00 GiB" in str(err.value) and "10.00 GiB" in str(err.value)


# ---------------------------------------------------------------------------------------------------------------
# a worker killed, then the client interrupted; resumed

RUN = """
import os, sys, time
from dataclasses import replace
import numpy as np
from sealeak.cases import example_path, load_cases
from sealeak.cases.ensemble import make_runner
from sealeak.cases.simulation import run_task, simulate

store, log, gate = sys.argv[1:4]

def logged(task):
    with open(log, "a") as fh:
        fh.write(f"start {task.name} {os.getpid()}\\n")
    if task.name == "threshold-r3":  # waits for the test (one worker at most): the run cannot end before it is interrupted
        while not os.path.exists(gate):
            time.sleep(0.05)
    time.sleep(0.25)
    out = run_task(task)
    with open(log, "a") as fh:
        fh.write(f"end {task.name} {os.getpid()}\\n")
    return out

(case,) = load_cases(example_path("reference-experiment"))
case = replace(case, squeeze_pressure=np.array([2e4, 3e5]))
try:
    simulate(case, grid=64, realizations=4, seed=3,
             runner=make_runner(workers=2, store=store, fields=True, task_function=logged))
except KeyboardInterrupt:
    sys.exit(130)
"""


def wait_for(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        found = condition()
        if found:
            return found
        time.sleep(0.05)
    pytest.fail(f"waited {timeout} s for {what}")


def read_log(log: Path):
    lines = [line.split() for line in log.read_text().splitlines()] if log.exists() else []
    return [(kind, name, int(pid)) for kind, name, pid in lines]


def test_worker_killed_then_client_interrupted_resumes_without_recomputing(tmp_path):
    store, log, gate = tmp_path / "store", tmp_path / "log", tmp_path / "gate"
    proc = subprocess.Popen([sys.executable, "-c", RUN, str(store), str(log), str(gate)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    records = lambda: {p.stem for p in (store / "tasks").glob("*.json")} if (store / "tasks").exists() else set()  # noqa: E731
    try:
        wait_for(lambda: records(), 60, "a first stored task")

        def running():
            entries = read_log(log)
            ended = {(n, pid) for k, n, pid in entries if k == "end"}
            busy = [(n, pid) for k, n, pid in entries if k == "start" and (n, pid) not in ended
                    and n != "threshold-r3" and n not in records()]
            return busy[0] if busy else None

        victim, pid = wait_for(running, 30, "a task running on a worker")
        os.kill(pid, signal.SIGKILL)  # the worker process dies in the middle of its task
        wait_for(lambda: victim in records(), 60, f"Dask to run {victim} again on another worker")
        proc.send_signal(signal.SIGINT)  # then Ctrl-C to the client, the last task still waiting
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 130, err
    entries = read_log(log)
    assert [n for k, n, p in entries if k == "start"].count(victim) >= 2  # killed while running it, then run again
    kept = {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json")}
    assert 1 <= len(kept) <= 7 and "threshold-r3.json" not in kept

    names, notes = [], []

    def counting(task):
        names.append(task.name)
        return run_task(task)

    case = small_case(PRESSURES[::2])
    res = simulate(case, grid=64, realizations=4, seed=3,
                   runner=make_runner(workers=0, store=store, fields=True, task_function=counting, note=notes.append))
    every = {f"{k}-r{r}" for r in range(4) for k in ("sweep", "threshold")}
    assert sorted(names) == sorted(every - {Path(n).stem for n in kept})  # each missing task once, no other
    assert f"resumed: {len(kept)} of 8 tasks from {store}" in notes
    assert {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json") if p.name in kept} == kept
    plain = simulate(case, grid=64, realizations=4, seed=3)
    for key in plain.per_realization:
        np.testing.assert_array_equal(plain.per_realization[key], res.per_realization[key], err_msg=key)
    for r in range(4):
        record = json.loads((store / "tasks" / f"sweep-r{r}.json").read_text())["result"]["fields"]
        assert fields_intact(store, record)
    assert not list((store / ".partial").iterdir())


def test_only_the_workers_memory_counts_on_a_cluster(two_workers):
    """With a scheduler, the client's own memory (here declared 100 kB) does not limit the grid: the workers hold it."""
    case = small_case(PRESSURES[:1])
    need = estimates(case, 32, 1)
    cluster = two_workers(small=2 * max(need.values()), big=4 * max(need.values()))
    with pytest.raises(ResourceError):
        simulate(case, grid=32, realizations=1, seed=2, threshold=False, memory_limit=1e5)
    res = simulate(case, grid=32, realizations=1, seed=2, threshold=False, memory_limit=1e5,
                   runner=make_runner(workers=0, scheduler=cluster.scheduler_address, task_function=located))
    assert WHERE.keys() == {"sweep-r0"}
    np.testing.assert_array_equal(res.leak_rate, simulate(case, grid=32, realizations=1, seed=2, threshold=False).leak_rate)
