"""Running a simulation's tasks on Dask, keeping each finished one in a store, and reporting progress.

The ensemble of :func:`sealeak.cases.simulation.simulate` is a set of independent tasks
(:func:`sealeak.cases.simulation.ensemble_tasks`: realisation r's pressure sweep and its threshold
search, each drawing its surface from the seed sequence (seed, r)). :func:`make_runner` returns the
runner ``simulate`` calls with them:

- ``workers = 0`` and no scheduler: the plain loop in this process, one task after the other;
- ``workers = N >= 1``: a ``distributed.LocalCluster`` of N worker processes with one thread each
  (the FFTs of a task run on one thread, and OMP/OpenBLAS/MKL are held to one thread, so N tasks share
  N cores without oversubscription);
- ``scheduler = ADDRESS``: a running Dask cluster (SSH, Kubernetes, SLURM through dask-jobqueue).

A task returns its scalars only; the runner hands the results back in the order of the tasks, so the
numbers are those of the serial loop whatever the number of workers or the order in which tasks finish
(docs/theory.md §6.7, the ensemble as independent tasks; the time left of a progress line is the mean
wall time per computed task times the tasks still to do).

With a store (:class:`TaskStore`), every finished task's result is written at once, atomically, as
``DIR/tasks/<task>.json`` with its SHA-256; ``DIR/manifest.json`` names the case, spectrum, grid and seed
the results belong to. Running the same command again reuses what is there and computes the rest.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from importlib.util import find_spec
from pathlib import Path
from typing import Any

import dask
from distributed import Client, LocalCluster, as_completed

from ..errors import InputError
from ..io.files import OutputWriteError
from .simulation import EnsembleTask, run_task

__all__ = ["TaskStore", "TaskEvent", "make_runner", "STORE_FORMAT", "THREAD_ENV", "default_workers", "DASK_FROM_GRID"]

#: The format tag of a store's manifest.
STORE_FORMAT = "sealeak-ensemble-store/1"
#: Environment of every worker process: one thread for the numerical libraries.
THREAD_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: Dask configuration of the local cluster's worker processes. Dask sets MALLOC_TRIM_THRESHOLD_=65536 in them
#: by default (to return freed memory to the system sooner); glibc then maps and unmaps every large temporary
#: array afresh, which made the contact solves 2-3 times slower on this machine: sealeak's workers keep glibc's
#: own, adaptive threshold.
_WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
#: Seconds without a finished task after which the runner reports that it is still working.
HEARTBEAT = 5.0


#: Smallest grid N for which ``simulate`` starts a local Dask cluster unless told (``--workers``): one task
#: then takes some ten seconds or more, and the cluster's start-up (2-3 s) is a small part of the run; below
#: it, the plain loop is faster.
DASK_FROM_GRID = 512


def default_workers(grid: int | None = None) -> int:
    """All cores of this machine (the CPUs this process may run on); 0 (the plain loop) below ``DASK_FROM_GRID``."""
    if grid is not None and grid < DASK_FROM_GRID:
        return 0
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@dataclass(frozen=True)
class TaskEvent:
    """What the runner reports: a task finished (``task`` its name) or, with ``task = None``, still working.

    ``done`` of ``total`` tasks are finished (those taken from a store included), ``elapsed`` and ``left``
    in seconds (``left`` is None until a task has been computed in this run). ``dashboard`` is the address of
    the Dask dashboard, reported once when the cluster is up (if it serves one).
    """

    done: int
    total: int
    task: str | None
    elapsed: float
    left: float | None
    dashboard: str | None = None


def _digest(value: Any) -> str:
    """SHA-256 of a JSON value written canonically (sorted keys, floats by ``repr``: exact)."""
    return hashlib.sha256(json.dumps(value, sort_keys=True, allow_nan=True).encode()).hexdigest()


def _write_atomic(path: Path, text: str) -> None:
    """``text`` into ``path`` through a temporary file in the same folder and ``os.replace``."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class TaskStore:
    """A folder of finished task results for one case, spectrum, grid and seed.

    ``DIR/manifest.json`` holds the format tag, the grid, the seed, and SHA-256 hashes of the spectrum's
    nodes and of the other inputs the tasks depend on (:meth:`EnsembleSpec.identity`); a store whose
    manifest differs is refused (:class:`sealeak.errors.InputError` naming ``--store`` and what differs),
    never mixed. Each result is ``DIR/tasks/<name>.json``: ``{"sha256": ..., "result": ...}``, the hash
    over the result; one that does not parse or whose hash does not match is reported and computed again.
    The number of realisations is not part of the manifest: a run with more realisations reuses the first.
    """

    def __init__(self, folder: str | Path, identity: dict[str, Any], note: Callable[[str], None] | None = None) -> None:
        self.folder = Path(folder)
        self.note = note or (lambda _msg: None)
        self.manifest = {"format": STORE_FORMAT, "grid": identity["grid"], "seed": identity["seed"],
                         "spectrum": _digest(identity["spectrum"]), "case": _digest(identity["case"])}
        if self.folder.exists() and not self.folder.is_dir():
            raise InputError("--store", str(self.folder), "is a file, not a folder: give a folder for the task results")
        path = self.folder / "manifest.json"
        if path.exists():
            self._check(path)
        elif self.folder.exists() and any(self.folder.iterdir()):
            raise InputError("--store", str(self.folder), "is a folder that holds other files and no sealeak store "
                                                          "(no manifest.json): give an empty or new folder")
        try:
            (self.folder / "tasks").mkdir(parents=True, exist_ok=True)
            if not path.exists():
                _write_atomic(path, json.dumps(self.manifest, indent=1) + "\n")
        except OSError as exc:
            raise OutputWriteError(self.folder, exc) from None

    def _check(self, path: Path) -> None:
        try:
            stored = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            raise InputError("--store", str(self.folder), "has an unreadable manifest.json: not a sealeak store, or "
                                                          "damaged (give another folder)") from None
        if not isinstance(stored, dict) or stored.get("format") != STORE_FORMAT:
            raise InputError("--store", str(self.folder), f"is not a store of this sealeak ({STORE_FORMAT})")
        for key, what in (("seed", "seed"), ("grid", "grid"), ("spectrum", "spectrum"), ("case", "case")):
            if stored.get(key) != self.manifest[key]:
                if key in ("seed", "grid"):
                    diff = f"{what} {stored.get(key)}, not {self.manifest[key]} as this run"
                else:
                    diff = f"another {what} (its inputs differ from this run's)"
                raise InputError("--store", str(self.folder), f"holds results for {diff}: results are never mixed; "
                                                              "give another folder (or the same inputs)")

    def _path(self, name: str) -> Path:
        return self.folder / "tasks" / f"{name}.json"

    def load(self, name: str) -> dict[str, Any] | None:
        """The stored result of task ``name``; None if missing or damaged (with a note)."""
        path = self._path(name)
        if not path.exists():
            return None
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
            result = record["result"]
            ok = record["sha256"] == _digest(result)
        except (OSError, ValueError, KeyError, TypeError):
            ok = False
        if not ok:
            self.note(f"{path} is damaged (checksum does not match): computing {name} again")
            return None
        return result  # type: ignore[no-any-return]

    def save(self, name: str, result: dict[str, Any]) -> None:
        """Write task ``name``'s result atomically."""
        try:
            _write_atomic(self._path(name), json.dumps({"sha256": _digest(result), "result": result}) + "\n")
        except OSError as exc:
            raise OutputWriteError(self._path(name), exc) from None


@contextmanager
def _client(workers: int, scheduler: str | None) -> Iterator[Any]:
    """A ``distributed.Client`` of the running cluster at ``scheduler``, or of a new local cluster."""
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="20s")
        except ValueError:
            raise InputError("--scheduler", scheduler, "is not a scheduler address (tcp://HOST:PORT)") from None
        except (OSError, TimeoutError):
            raise InputError("--scheduler", scheduler, "no Dask scheduler answers there (waited 20 s)") from None
        with client:
            yield client
        return
    # The worker processes are started with SIGINT ignored (they inherit it, and Python then installs no
    # KeyboardInterrupt handler in them): a Ctrl-C reaches this process alone, which stops the cluster, instead
    # of every worker printing its own traceback.
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        with dask.config.set(_WORKER_CONFIG):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                                   silence_logs=logging.ERROR, env=dict(THREAD_ENV))
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    with cluster, Client(cluster) as client:
        yield client


def make_runner(*, workers: int, scheduler: str | None = None, store: str | Path | None = None,
                progress: Callable[[TaskEvent], None] | None = None,
                note: Callable[[str], None] | None = None,
                task_function: Callable[[EnsembleTask], dict[str, Any]] = run_task,
                heartbeat: float = HEARTBEAT) -> Callable[[list[EnsembleTask]], list[dict[str, Any]]]:
    """A runner for :func:`sealeak.cases.simulation.simulate`'s ``runner`` argument.

    Parameters
    ----------
    workers:
        0: the plain loop in this process; N >= 1: a local Dask cluster of N one-thread worker processes.
        Ignored with ``scheduler``.
    scheduler:
        Address of a running Dask scheduler (``tcp://host:8786``): the tasks run there; field files, if
        asked, must then be written to a folder the workers share with this machine.
    store:
        Folder of a :class:`TaskStore`: finished results are kept there and reused by the next run.
    progress:
        Called with a :class:`TaskEvent` for every finished task, and at least every ``heartbeat`` seconds
        while tasks run.
    note:
        Called with one-line notes (a resumed run, a damaged task file).
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise InputError("--workers", workers, "must be a whole number >= 0 (0: no Dask, this process alone)")
    say = note or (lambda _msg: None)

    def run(tasks: list[EnsembleTask]) -> list[dict[str, Any]]:
        if not tasks:
            return []
        parallel = scheduler is not None or workers >= 1
        if parallel:  # worker processes share the cores: one FFT thread per task
            tasks = [replace(t, spec=replace(t.spec, fft_workers=1)) for t in tasks]
        kept = TaskStore(store, tasks[0].spec.identity(), say) if store is not None else None
        results: dict[int, dict[str, Any]] = {}
        if kept is not None:
            for i, t in enumerate(tasks):
                found = kept.load(t.name)
                if found is not None:
                    results[i] = found
            if results:
                say(f"resumed: {len(results)} of {len(tasks)} tasks from {kept.folder}")
        todo = [i for i in range(len(tasks)) if i not in results]
        start = time.monotonic()
        clock = [start]  # when computing began (after a local cluster has started): the time left is rated from it
        computed = 0

        def finished(i: int, out: dict[str, Any]) -> None:
            nonlocal computed
            results[i] = out
            computed += 1
            if kept is not None:
                kept.save(tasks[i].name, out)
            if progress is not None:
                now = time.monotonic()
                remaining = len(tasks) - len(results)
                progress(TaskEvent(len(results), len(tasks), tasks[i].name, now - start,
                                   (now - clock[0]) / computed * remaining))

        if not parallel:
            for i in todo:
                finished(i, task_function(tasks[i]))
        elif todo:
            if progress is not None:
                say(f"connecting to the Dask scheduler at {scheduler}" if scheduler is not None else
                    f"starting a local Dask cluster: {workers} worker process{'es' if workers > 1 else ''}, one thread each")
            _run_dask(tasks, todo, finished, workers, scheduler, task_function, progress, heartbeat, results, start, clock)
        return [results[i] for i in range(len(tasks))]

    return run


def _run_dask(tasks: list[EnsembleTask], todo: Iterable[int], finished: Callable[[int, dict[str, Any]], None],
              workers: int, scheduler: str | None, task_function: Callable[[EnsembleTask], dict[str, Any]],
              progress: Callable[[TaskEvent], None] | None, heartbeat: float, results: dict[int, Any],
              start: float, clock: list[float]) -> None:
    """Submit the tasks ``todo`` and hand each result to ``finished`` as soon as it arrives (in any order)."""
    with _client(workers, scheduler) as client:
        clock[0] = time.monotonic()
        link = getattr(client, "dashboard_link", None) if progress is not None else None
        if link and find_spec("bokeh") is not None:
            progress(TaskEvent(len(results), len(tasks), None, clock[0] - start, None, dashboard=link))
        index = {client.submit(task_function, tasks[i], pure=False): i for i in todo}
        pending = as_completed(list(index))
        last = time.monotonic()
        try:
            while not pending.is_empty():
                batch = pending.next_batch(block=False)
                if not batch:
                    time.sleep(0.05)
                    now = time.monotonic()
                    if progress is not None and now - last >= heartbeat:
                        last = now
                        progress(TaskEvent(len(results), len(tasks), None, now - start, None))
                    continue
                for fut in batch:
                    finished(index[fut], fut.result())
                last = time.monotonic()
        except BaseException:
            client.cancel(list(index))
            raise
