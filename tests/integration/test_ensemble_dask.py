"""``simulate`` on Dask: a local cluster gives the serial numbers; a killed run resumes from its store.

Tiny grids: these tests check bookkeeping and determinism, not physics (test_simulation does that).
"""

import gc
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path

import cloudpickle
import numpy as np
import pytest
from distributed import LocalCluster

from sealeak.cases import example_path, load_cases
from sealeak.cases.ensemble import make_runner
from sealeak.cases.simulation import run_task, simulate
from sealeak.cli import main

PRESSURES = '["20 kPa", "80 kPa", "300 kPa"]'


def case_file(tmp_path, name="reference-experiment"):
    text = example_path(name).read_text()
    old = '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }'
    assert old in text
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace(old, PRESSURES))
    return path


def test_local_cluster_gives_the_serial_numbers(tmp_path):
    """Two worker processes, tasks finishing in any order: every number, note and contact map as the serial loop."""
    (case,) = load_cases(case_file(tmp_path))
    serial = simulate(case, grid=64, realizations=4, seed=9)
    events, times = [], []

    def record(event):
        events.append(event)
        times.append(time.monotonic())

    parallel = simulate(case, grid=64, realizations=4, seed=9, runner=make_runner(workers=2, progress=record, heartbeat=0.2))
    assert serial.per_realization.keys() == parallel.per_realization.keys()
    for key in serial.per_realization:
        np.testing.assert_array_equal(serial.per_realization[key], parallel.per_realization[key], err_msg=key)
    for name in ("relative_contact_area", "relative_contact_area_std", "mean_gap", "leak_rate", "leak_rate_std",
                 "alpha", "alpha_std", "percolating_fraction"):
        np.testing.assert_array_equal(getattr(serial, name), getattr(parallel, name), err_msg=name)
    assert (serial.percolation_threshold, serial.percolation_threshold_std) == (
        parallel.percolation_threshold, parallel.percolation_threshold_std)
    assert serial.notes == parallel.notes
    for i in serial.contact_maps:
        np.testing.assert_array_equal(serial.contact_maps[i], parallel.contact_maps[i])
    finished = [e for e in events if e.task is not None]
    assert sorted(e.task for e in finished) == sorted(f"{k}-r{r}" for r in range(4) for k in ("sweep", "threshold"))
    assert [e.done for e in finished] == list(range(1, 9)) and finished[-1].left == 0
    assert all(e.left is not None and e.left >= 0 for e in finished)


def slow_task(task):
    """A task that takes at least 1.5 s (sent to the workers by value)."""
    time.sleep(1.5)
    return run_task(task)


def test_progress_never_silent_while_tasks_run(tmp_path):
    """Tasks of 1.5 s on 2 workers, heartbeat 0.2 s: an event at least every ~0.2 s, the finished ones with the time left."""
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    (case,) = load_cases(case_file(tmp_path))
    case = replace(case, squeeze_pressure=case.squeeze_pressure[:1])
    events, times = [], []

    def record(event):
        events.append(event)
        times.append(time.monotonic())

    simulate(case, grid=32, realizations=2, seed=1, threshold=False,
             runner=make_runner(workers=2, progress=record, heartbeat=0.2, task_function=slow_task))
    assert [e.task for e in events if e.task is not None] != [] and events[-1].done == 2
    assert sum(e.task is None for e in events) >= 3  # "working" while the 1.5 s tasks run
    assert max(np.diff(times)) < 0.2 + 0.8  # slack for a loaded machine, far below the 1.5 s of a task
    assert all(e.left is None for e in events if e.task is None)


def test_cli_workers_json_and_fields_identical(tmp_path):
    """Through the CLI, a gas case (liquid and gas columns): --workers 2 writes the JSON and field files of --workers 0."""
    path = example_path("helium-test")
    out = {}
    for w in ("0", "2"):
        args = ["simulate", str(path), "--grid", "32", "--realizations", "2", "--seed", "4", "--workers", w,
                "--json", str(tmp_path / f"w{w}.json"), "--fields", str(tmp_path / f"f{w}"), "-q"]
        assert main(args) == 0
        out[w] = json.loads((tmp_path / f"w{w}.json").read_text())
    assert out["0"] == out["2"]
    names = sorted(p.name for p in (tmp_path / "f0").iterdir())
    assert names and names == sorted(p.name for p in (tmp_path / "f2").iterdir())
    for name in names:
        a, b = np.load(tmp_path / "f0" / name), np.load(tmp_path / "f2" / name)
        for key in ("height", "gap", "pressure", "size"):
            np.testing.assert_array_equal(a[key], b[key])


def test_cli_running_scheduler(tmp_path):
    """--scheduler ADDRESS: the tasks run on a cluster started elsewhere (here in this test), same JSON as serial."""
    path = case_file(tmp_path)
    base = ["simulate", str(path), "--grid", "32", "--realizations", "2", "--seed", "6", "-q"]
    assert main([*base, "--workers", "0", "--json", str(tmp_path / "serial.json")]) == 0
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        assert main([*base, "--scheduler", cluster.scheduler_address, "--json", str(tmp_path / "remote.json")]) == 0
    assert json.loads((tmp_path / "serial.json").read_text()) == json.loads((tmp_path / "remote.json").read_text())


class Counting:
    """Task function counting what it computes (serial runner: runs in this process)."""

    def __init__(self):
        self.names = []

    def __call__(self, task):
        self.names.append(task.name)
        return run_task(task)


def test_interrupted_dask_run_resumes_without_recomputing(tmp_path):
    """The client interrupted after 3 finished tasks on a 2-worker cluster; the rerun computes only the rest."""
    (case,) = load_cases(case_file(tmp_path))
    case = replace(case, squeeze_pressure=case.squeeze_pressure[:2])
    store = tmp_path / "store"

    def stop_after_three(event):
        if event.task is not None and event.done == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        simulate(case, grid=64, realizations=3, seed=2, runner=make_runner(workers=2, store=store,
                                                                            progress=stop_after_three))
    kept = {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json")}
    assert len(kept) == 3
    counting, notes = Counting(), []
    res = simulate(case, grid=64, realizations=3, seed=2,
                   runner=make_runner(workers=0, store=store, task_function=counting, note=notes.append))
    assert len(counting.names) == 3 and not {f"{n}.json" for n in counting.names} & set(kept)
    assert f"resumed: 3 of 6 tasks from {store}" in notes
    assert {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json") if p.name in kept} == kept
    plain = simulate(case, grid=64, realizations=3, seed=2)
    for key in plain.per_realization:
        np.testing.assert_array_equal(plain.per_realization[key], res.per_realization[key], err_msg=key)


def test_killed_process_resumes_from_its_store(tmp_path):
    """``sealeak simulate --store`` killed (SIGKILL, client and workers) after its first finished task; the same
    command again takes the finished tasks from the store, untouched, and gives the uninterrupted run's JSON."""
    path = case_file(tmp_path)
    store = tmp_path / "store"
    args = ["simulate", str(path), "--grid", "96", "--realizations", "4", "--seed", "1", "--workers", "1",
            "--store", str(store), "--json", str(tmp_path / "killed.json")]
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                             *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        for line in proc.stderr:
            if "finished (" in line or time.monotonic() > deadline:
                break
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        proc.stderr.close()
    assert proc.returncode == -signal.SIGKILL
    assert not (tmp_path / "killed.json").exists()
    kept = {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json")}
    assert 1 <= len(kept) < 8  # killed part-way
    assert not list((store / "tasks").glob(".*"))  # no half-written record left (temp files are hidden .part files)

    resumed = [*args[:-1], str(tmp_path / "resumed.json"), "--workers", "0"]
    proc2 = subprocess.run([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                            *resumed], capture_output=True, text=True, timeout=120)
    assert proc2.returncode == 0, proc2.stderr
    assert f"note: resumed: {len(kept)} of 8 tasks from {store}" in proc2.stderr
    assert proc2.stderr.count(" finished (") == 8 - len(kept)
    assert {p.name: p.stat().st_mtime_ns for p in (store / "tasks").glob("*.json") if p.name in kept} == kept
    assert main([*args[:-4], "--workers", "0", "--json", str(tmp_path / "plain.json"), "-q"]) == 0
    assert json.loads((tmp_path / "resumed.json").read_text()) == json.loads((tmp_path / "plain.json").read_text())


@pytest.mark.parametrize("rerun, named", [
    (["--seed", "3"], "seed"),
    (["--grid", "32"], "grid"),
    (["--realizations", "1", "--no-threshold", "--seed", "8"], "seed"),
])
def test_cli_refuses_another_runs_store(tmp_path, capsys, monkeypatch, rerun, named):
    path = case_file(tmp_path)
    monkeypatch.chdir(tmp_path)  # the store named as given, short (a long path is shown cut in the middle)
    store = Path("store")
    base = ["simulate", str(path), "--grid", "64", "--realizations", "1", "--seed", "2", "--workers", "0",
            "--store", str(store), "-q"]
    assert main(base) == 0
    before = {p.name: p.read_bytes() for p in (store / "tasks").iterdir()}
    capsys.readouterr()
    out = tmp_path / "out.json"
    out.write_text("old")
    assert main([*base, *rerun, "--json", str(out), "--force"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "--store = 'store': holds results for" in err and named in err
    assert out.read_text() == "old"
    assert {p.name: p.read_bytes() for p in (store / "tasks").iterdir()} == before


def test_cli_damaged_record_computed_again_with_a_note(tmp_path, capsys):
    path = case_file(tmp_path)
    store = tmp_path / "store"
    base = ["simulate", str(path), "--grid", "64", "--realizations", "2", "--seed", "2", "--workers", "0",
            "--store", str(store)]
    assert main([*base, "--json", str(tmp_path / "a.json")]) == 0
    record = store / "tasks" / "threshold-r1.json"
    record.write_text(record.read_text().replace('"threshold": 0.', '"threshold": 1.'))
    capsys.readouterr()
    assert main([*base, "--json", str(tmp_path / "b.json")]) == 0
    err = capsys.readouterr().err
    assert f"note: {record} is damaged" in err and "resumed: 3 of 4 tasks" in err
    assert [line.split()[1] for line in err.splitlines() if " finished (" in line] == ["threshold-r1"]
    assert json.loads((tmp_path / "a.json").read_text()) == json.loads((tmp_path / "b.json").read_text())


@pytest.mark.parametrize("extra, named", [
    (["--workers", "-1"], "--workers"),
    (["--store", "STORE", "--fields", "FIELDS"], "--fields"),
    (["--store-fields"], "--store-fields"),
    (["--store", "FILE"], "--store"),
    (["--scheduler", "not an address"], "--scheduler"),
])
def test_cli_bad_ensemble_options(tmp_path, capsys, extra, named):
    path = case_file(tmp_path)
    (tmp_path / "file").write_text("x")
    extra = [{"STORE": str(tmp_path / "s"), "FIELDS": str(tmp_path / "f"), "FILE": str(tmp_path / "file")}.get(a, a)
             for a in extra]
    assert main(["simulate", str(path), "--grid", "32", "--realizations", "1", "--json", str(tmp_path / "o.json"), "-q",
                 *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and named in err and "Traceback" not in err
    assert not (tmp_path / "o.json").exists() and not (tmp_path / "s").exists() and not (tmp_path / "f").exists()
    assert Path(tmp_path / "file").read_text() == "x"


def test_ctrl_c_stops_client_and_workers_with_one_line(tmp_path):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it) on a 2-worker run: one line, exit 130,
    no worker traceback, no worker left running, the finished tasks kept in the store."""
    path = case_file(tmp_path)
    store = tmp_path / "store"
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                             "simulate", str(path), "--grid", "128", "--realizations", "6", "--workers", "2",
                             "--store", str(store), "--json", str(tmp_path / "out.json")],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        seen = []
        for line in proc.stderr:
            seen.append(line)
            if " finished (" in line:
                os.killpg(proc.pid, signal.SIGINT)
                break
        rest = proc.stderr.read()
        proc.wait(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        proc.stderr.close()
    assert proc.returncode == 130, rest
    assert "Traceback" not in rest and "KeyboardInterrupt" not in rest
    assert rest.strip().splitlines()[-1].startswith("sealeak: interrupted")
    assert not (tmp_path / "out.json").exists()
    assert len(list((store / "tasks").glob("*.json"))) >= 1
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline:  # the whole group is gone: no worker process left behind
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.2)
    else:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail("worker processes still running 15 s after the client exited")


def test_a_single_task_runs_in_this_process_with_the_serial_numbers(tmp_path, monkeypatch):
    """One task to compute (1 realisation, no threshold search): no cluster is started (it would add its start-up and
    no parallelism), the numbers are the plain loop's, and a note says so; two tasks do start one."""
    import sealeak.cases.ensemble as ensemble

    started = []
    real_client = ensemble._client

    def spy(*args, **kwargs):
        started.append(args)
        return real_client(*args, **kwargs)

    monkeypatch.setattr(ensemble, "_client", spy)
    (case,) = load_cases(case_file(tmp_path))
    serial = simulate(case, grid=32, realizations=1, seed=4, threshold=False)
    notes = []
    one = simulate(case, grid=32, realizations=1, seed=4, threshold=False, runner=make_runner(workers=2, note=notes.append))
    assert started == [] and any("running in this process" in n for n in notes)
    for key in serial.per_realization:
        np.testing.assert_array_equal(serial.per_realization[key], one.per_realization[key], err_msg=key)
    simulate(case, grid=32, realizations=2, seed=4, threshold=False, runner=make_runner(workers=2))
    assert len(started) == 1


@pytest.mark.parametrize("address, says", [("not an address", "is not a scheduler address"),
                                           ("foo://127.0.0.1:8786", "is not a scheduler address"),
                                           ("CLOSED", "no Dask scheduler answers there (waited 1 s)")])
def test_a_refused_scheduler_leaves_no_thread_behind(tmp_path, capsys, monkeypatch, address, says):
    """A ``Client`` that fails to connect leaves its event-loop thread running, and its finaliser, run whenever the
    garbage collector next runs, takes the lock a new cluster holds while it starts (a LocalCluster started later in
    the process then failed after 10 s). The address is checked and the scheduler probed before any Client exists:
    the refusal is one line, no Client is made, and no thread is left."""
    import sealeak.cases.ensemble as ensemble

    if address == "CLOSED":
        with socket.socket() as s:  # a port nothing listens on: connections are refused until the timeout
            s.bind(("127.0.0.1", 0))
            address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    monkeypatch.setattr(ensemble, "SCHEDULER_TIMEOUT", 1.0)
    made = []
    monkeypatch.setattr(ensemble, "Client", lambda *a, **k: made.append(a))
    before = set(threading.enumerate())
    assert main(["simulate", str(case_file(tmp_path)), "--grid", "32", "--realizations", "2", "-q",
                 "--scheduler", address]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--scheduler" in err and says in err, err
    assert made == []
    gc.collect()
    assert set(threading.enumerate()) - before == set()
