"""Running a simulation's tasks on Dask, keeping each finished one in a store, and reporting progress.

The ensemble of every simulated geometry (:func:`sealeak.cases.pipeline.run_ensemble`) is a set of
independent tasks (for a uniform seal :func:`sealeak.cases.simulation.ensemble_tasks`: realisation r's
pressure sweep and its threshold search; for an O-ring one task per realisation), each drawing its surface
from the seed sequence (seed, r) and computing itself (``task.run()``). :func:`make_runner` returns the
runner the pipeline calls with them:

- ``workers = 0`` and no scheduler: the plain loop in this process, one task after the other;
- ``workers = N >= 1``: a ``distributed.LocalCluster`` of N worker processes with one thread each
  (the FFTs of a task run on one thread, and OMP/OpenBLAS/MKL are held to one thread, so N tasks share
  N cores without oversubscription);
- ``scheduler = ADDRESS``: a running Dask cluster (SSH, Kubernetes, SLURM through dask-jobqueue).

A task returns its scalars only (its :class:`~sealeak.cases.pipeline.TaskRecord`); the runner hands the
results back in the order of the tasks, so the numbers are those of the serial loop whatever the number of
workers or the order in which tasks finish
(docs/theory.md §6.7, the ensemble as independent tasks; the time left of a progress line is the mean
wall time per computed task times the tasks still to do).

With a store (:class:`TaskStore`), every finished task's result is written at once, atomically, as
``DIR/tasks/<task>.json`` with its SHA-256; ``DIR/manifest.json`` names the case, spectrum, grid and seed
the results belong to. Running the same command again reuses what is there and computes the rest. A store
that keeps fields (``fields=True``) has every sweep task write its height, gap and pressure maps into
``DIR/fields.zarr`` itself, from the worker (:mod:`sealeak.io.fieldstore`); the task's record, written by
the client after the task has returned, holds their checksums, so a record never exists without its fields.

Memory (docs/theory.md §6.7): before a task is submitted its peak memory is estimated
(:meth:`sealeak.cases.simulation.EnsembleTask.memory_bytes`); a worker is given only tasks it can hold, its
``memory_limit`` shared by its threads (each thread may run a task at once). A local cluster runs fewer
worker processes than asked when a task does not fit the machine's memory divided among them. The plain
loop and a local cluster refuse a task larger than the memory this machine has free; with a scheduler, only
the workers' memory counts (``simulate`` leaves its own up-front check to the runner: ``checks_memory``).
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import logging
import os
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, replace
from importlib.util import find_spec
from pathlib import Path
from typing import Any

import dask
from distributed import Client, LocalCluster, Security, as_completed, system
from distributed.comm import connect

from .. import numerics
from ..errors import InputError, SealeakError
from ..io.fieldstore import FIELDS_FOLDER, clear_partial, create_field_store, fields_intact
from ..io.files import OutputWriteError
from .limits import MAX_WORKERS, whole_number
from .pipeline import TaskRecord, compute_task

__all__ = ["TaskStore", "TaskEvent", "make_runner", "STORE_FORMAT", "THREAD_ENV", "default_workers", "run_workers",
           "gpu_of_worker", "DASK_FROM_GRID",
           "machine_memory", "CLUSTER_FROM_TASKS"]

#: The format tag of a store's manifest.
STORE_FORMAT = "sealeak-ensemble-store/1"
#: Environment of every worker process: one thread for the numerical libraries.
THREAD_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: Dask configuration of the local cluster's worker processes. Dask sets MALLOC_TRIM_THRESHOLD_=65536 in them
#: by default (to return freed memory to the system sooner); glibc then maps and unmaps every large temporary
#: array afresh, which made the contact solves 2-3 times slower on this machine: sealeak's workers keep glibc's
#: own, adaptive threshold.
_WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
#: Fewest tasks left to compute for which a runner with ``workers >= 1`` starts a local Dask cluster: a single task
#: gains no parallelism, only the cluster's start-up and the cost of a worker process (benchmarks/bench_dask.py).
CLUSTER_FROM_TASKS = 2
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


def run_workers(workers: int | None, grid: int | None, device: str = "cpu", gpus: int = 0) -> int:
    """Worker processes of a run: ``workers`` (``--workers``) if given, else :func:`default_workers` of the grid.

    On ``device = "cuda"`` one worker process per GPU (``gpus``, as many as CuPy sees; ``workers`` may lower it,
    more would share a GPU), each given its own card (:func:`gpu_of_worker`); with one GPU, 0: this process
    alone runs the tasks one after the other, which a cluster of one worker could only slow down.
    """
    if device != "cuda":
        return default_workers(grid) if workers is None else workers
    n = gpus if workers is None else min(workers, gpus)
    return n if n > 1 else 0


def gpu_of_worker(index: int, gpus: int, visible: str | None) -> str:
    """``CUDA_VISIBLE_DEVICES`` of worker ``index`` of a local cluster with one worker per GPU: one card of those
    this process sees (``visible``, the variable's value here, None: cards 0 .. gpus-1), round the cards."""
    cards = [c.strip() for c in visible.split(",") if c.strip()] if visible else [str(i) for i in range(gpus)]
    return cards[index % len(cards)]


def _pin_gpu(card: str) -> None:
    """In a worker process before any task: see only GPU ``card`` (CUDA reads the variable when it starts there)."""
    os.environ["CUDA_VISIBLE_DEVICES"] = card


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
    nodes and of the other inputs the tasks depend on (:meth:`sealeak.cases.pipeline.TaskSpec.identity`); a store whose
    manifest differs is refused (:class:`sealeak.errors.InputError` naming ``--store`` and what differs),
    never mixed. Each result is ``DIR/tasks/<name>.json``: ``{"sha256": ..., "result": ...}``, the hash
    over the result; one that does not parse or whose hash does not match is reported and computed again.
    The number of realisations is not part of the manifest: a run with more realisations reuses the first.

    Fields: the manifest's ``"fields"`` says whether the store keeps every sweep task's fields in
    ``DIR/fields.zarr``. It is set by the first run that asks for them (``fields=True``) and stays set: every
    later run on the store writes the fields of the tasks it computes, asked or not (:attr:`fields`). With
    fields kept, a record whose fields are missing or damaged (their SHA-256 in the record does not match) is
    computed again with a note, and so is a record stored before fields were kept (listed in :attr:`lacking`).
    """

    def __init__(self, folder: str | Path, identity: dict[str, Any], note: Callable[[str], None] | None = None, *,
                 fields: bool = False) -> None:
        self.folder = Path(folder)
        self.note = note or (lambda _msg: None)
        self.manifest = {"format": STORE_FORMAT, "grid": identity["grid"], "seed": identity["seed"],
                         "spectrum": _digest(identity["spectrum"]), "case": _digest(identity["case"]),
                         "fields": bool(fields)}
        #: Names of the records found without fields while fields are kept (:meth:`load`).
        self.lacking: list[str] = []
        if self.folder.exists() and not self.folder.is_dir():
            raise InputError("--store", str(self.folder), "is a file, not a folder: give a folder for the task results")
        path = self.folder / "manifest.json"
        had_fields = False
        if path.exists():
            had_fields = self._check(path)
        elif self.folder.exists() and any(self.folder.iterdir()):
            raise InputError("--store", str(self.folder), "is a folder that holds other files and no sealeak store "
                                                          "(no manifest.json): give an empty or new folder")
        self.manifest["fields"] = bool(fields) or had_fields
        try:
            (self.folder / "tasks").mkdir(parents=True, exist_ok=True)
            if self.fields:
                create_field_store(self.folder)
                clear_partial(self.folder)
            if not path.exists() or (self.fields and not had_fields):
                _write_atomic(path, json.dumps(self.manifest, indent=1) + "\n")
        except OSError as exc:
            raise InputError("--store", str(self.folder), f"cannot be written ({exc.strerror or exc}): give a folder "
                                                          "you may create and write into") from None

    @property
    def fields(self) -> bool:
        """Whether the store keeps the sweep tasks' fields (``DIR/fields.zarr``)."""
        return bool(self.manifest["fields"])

    def _check(self, path: Path) -> bool:
        """Refuse a manifest of another run; return whether it keeps fields."""
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
        return stored.get("fields") is True

    def _path(self, name: str) -> Path:
        return self.folder / "tasks" / f"{name}.json"

    def load(self, name: str, fields: bool = False) -> TaskRecord | None:
        """The stored result of task ``name``; None if missing or damaged (with a note).

        ``fields``: the task writes fields, which must be in the store, intact; a record without them is None
        (and listed in :attr:`lacking`), one whose fields are missing or damaged None with a note.
        """
        path = self._path(name)
        if not path.exists():
            return None
        try:
            stored = json.loads(path.read_text(encoding="utf-8"))
            ok = stored["sha256"] == _digest(stored["result"])
            result = TaskRecord.from_mapping(stored["result"])
        except (OSError, ValueError, KeyError, TypeError):
            ok = False
        if not ok:
            self.note(f"{path} is damaged (checksum does not match): computing {name} again")
            return None
        if fields:
            kept = getattr(result, "fields", None)
            if kept is None:
                self.lacking.append(name)
                return None
            if not fields_intact(self.folder, kept):
                self.note(f"the fields of {name} in {self.folder / FIELDS_FOLDER} are missing or damaged (checksum "
                          f"does not match): computing {name} again")
                return None
        return result

    def save(self, name: str, record: TaskRecord) -> None:
        """Write task ``name``'s record atomically (:meth:`sealeak.cases.pipeline.TaskRecord.to_mapping`)."""
        result = record.to_mapping()
        try:
            _write_atomic(self._path(name), json.dumps({"sha256": _digest(result), "result": result}) + "\n")
        except OSError as exc:
            raise OutputWriteError(self._path(name), exc) from None


def machine_memory() -> int:
    """Memory of this machine in bytes as Dask counts it (``distributed.system.MEMORY_LIMIT``: the physical
    memory, or a smaller cgroup or rlimit): what a worker without ``memory_limit`` may use."""
    return int(system.MEMORY_LIMIT)


def _gib(n: float) -> str:
    return f"{n / 2**30:.2f} GiB"


def _task_memory(task: Any) -> int:
    """A task's peak memory estimate in bytes (0 for a task that has none)."""
    estimate = getattr(task, "memory_bytes", None)
    return int(estimate()) if callable(estimate) else 0


def _grid_of(task: Any) -> Any:
    spec = getattr(task, "spec", None)
    return getattr(spec, "grid", None)


def _local_workers(workers: int, need: int, grid: Any, say: Callable[[str], None]) -> int:
    """How many one-thread worker processes of a local cluster can each hold a task of ``need`` bytes.

    Each gets the machine's memory divided by their number (Dask's default ``memory_limit``): fewer workers
    than asked when a task does not fit that share (with a note); an error when it does not fit the machine.
    """
    machine = machine_memory()
    if need > machine:
        raise InputError("grid", grid, f"a task needs about {_gib(need)} (estimate, docs/theory.md §6.7), more than "
                                       f"this machine's {_gib(machine)}: use a smaller grid, or a cluster with bigger "
                                       "workers (--scheduler)")
    fit = max(1, int(machine // max(need, 1)))
    if fit < workers:
        say(f"a task of the {grid}x{grid} grid needs about {_gib(need)} (estimate): the local cluster runs {fit} "
            f"worker process{'es' if fit > 1 else ''} of {_gib(machine / fit)} each instead of {workers} of "
            f"{_gib(machine / workers)}")
        return fit
    return workers


def _placement(client: Any, tasks: list[Any], todo: list[int], need: dict[int, int]) -> dict[int, list[str] | None]:
    """The workers each task may run on: those whose memory per thread holds its estimate (None: any worker).

    A worker's ``memory_limit`` (0 or None: the memory of its machine) is shared by its threads, each of which
    may run a task at the same time, so a task fits a worker when its estimate is at most memory_limit/nthreads.
    Raises :class:`InputError` (nothing submitted) when a task fits no worker.
    """
    try:
        info = client.scheduler_info(n_workers=-1)
    except TypeError:  # Dask before 2025: all workers by default
        info = client.scheduler_info()
    workers = info.get("workers", {})
    if not workers:
        return {i: None for i in todo}
    unlimited = [a for a, w in workers.items() if not w.get("memory_limit")]
    machines = client.run(machine_memory, workers=unlimited) if unlimited else {}
    caps = {a: float(w.get("memory_limit") or machines.get(a, 0)) / max(1, int(w.get("nthreads") or 1))
            for a, w in workers.items()}
    largest = max(caps, key=lambda a: caps[a])
    where: dict[int, list[str] | None] = {}
    for i in todo:
        ok = [a for a, cap in caps.items() if cap >= need[i]]
        if not ok:
            w = workers[largest]
            raise InputError("grid", _grid_of(tasks[i]),
                             f"a task ({tasks[i].name}) needs about {_gib(need[i])} (estimate, docs/theory.md §6.7), "
                             f"more than the largest Dask worker holds ({largest}: memory_limit "
                             f"{_gib(caps[largest] * max(1, int(w.get('nthreads') or 1)))} for "
                             f"{int(w.get('nthreads') or 1)} thread(s)): use a smaller grid or workers with more memory")
        where[i] = None if len(ok) == len(caps) else sorted(ok)
    return where


#: Seconds to wait for a Dask scheduler to answer (``--scheduler``).
SCHEDULER_TIMEOUT = 20.0


def _check_scheduler(address: str) -> None:
    """Refuse ``address`` unless a Dask scheduler answers there within :data:`SCHEDULER_TIMEOUT`, before any ``Client``
    is made.

    A ``Client`` that fails to connect leaves its event-loop thread running, and its finaliser, run later by the
    garbage collector in whichever thread allocates at that moment, takes the lock that every new cluster holds
    while its own event loop starts: a ``LocalCluster`` started afterwards in the same process could wait on itself
    and fail after 10 s. So the scheduler is probed with one ``distributed.comm.connect`` (which refuses a malformed
    address or scheme at once with ValueError) on an event loop of its own, in a thread of its own (this thread may be
    running a loop already, as in a notebook), both ended when the probe ends.
    """
    async def probe() -> None:
        comm = await connect(address, timeout=SCHEDULER_TIMEOUT, **Security().get_connection_args("client"))
        await comm.close()

    try:
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="sealeak-scheduler-probe") as pool:
            pool.submit(asyncio.run, probe()).result()
    except ValueError as err:
        raise InputError("--scheduler", address, f"is not a scheduler address (tcp://HOST:PORT): {err}") from None
    except (OSError, TimeoutError):
        raise InputError("--scheduler", address,
                         f"no Dask scheduler answers there (waited {SCHEDULER_TIMEOUT:g} s)") from None


@contextmanager
def _client(workers: int, scheduler: str | None, memory_limit: int | None = None, gpus: int = 0) -> Iterator[Any]:
    """A ``distributed.Client`` of the running cluster at ``scheduler``, or of a new local cluster (with ``gpus``,
    worker i sees only GPU i: :func:`gpu_of_worker`)."""
    if scheduler is not None:
        _check_scheduler(scheduler)
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except (OSError, TimeoutError):  # it answered the probe a moment ago
            raise InputError("--scheduler", scheduler, "the Dask scheduler there stopped answering") from None
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
                                   silence_logs=logging.CRITICAL, env=dict(THREAD_ENV),
                                   memory_limit=memory_limit if memory_limit is not None else "auto")
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    with cluster, Client(cluster) as client, _quiet_when_interrupted():
        visible = os.environ.get("CUDA_VISIBLE_DEVICES")
        for i, address in enumerate(sorted(client.scheduler_info()["workers"]) if gpus else ()):
            client.run(_pin_gpu, gpu_of_worker(i, gpus, visible), workers=[address])
        yield client


#: The loggers that report, with tracebacks, the callbacks and connections a cluster drops when it is stopped by Ctrl-C.
_SHUTDOWN_LOGGERS = ("distributed", "tornado", "tornado.application", "asyncio")


@contextmanager
def _quiet_when_interrupted() -> Iterator[None]:
    """On Ctrl-C, silence the shutdown of the cluster: the interruption is said in one line by the command line, not by
    the event loop's tracebacks of the work it drops. The loggers stay silent for the rest of the process: the loop
    runs in a thread of its own and may still report a dropped callback after the cluster is down (restoring them
    then let such a traceback through, now and then, before the command line's one line)."""
    try:
        yield
    except KeyboardInterrupt:
        for name in _SHUTDOWN_LOGGERS:
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)
        raise


def make_runner(*, workers: int, scheduler: str | None = None, store: str | Path | None = None,
                progress: Callable[[TaskEvent], None] | None = None,
                note: Callable[[str], None] | None = None,
                task_function: Callable[[Any], TaskRecord] = compute_task,
                heartbeat: float = HEARTBEAT, fields: bool = False,
                cluster_from: int = CLUSTER_FROM_TASKS) -> Callable[[list[Any]], list[TaskRecord]]:
    """A runner for :func:`sealeak.cases.simulation.simulate`'s ``runner`` argument.

    Parameters
    ----------
    workers:
        0: the plain loop in this process; N >= 1: a local Dask cluster of N one-thread worker processes,
        when at least ``cluster_from`` tasks are left to compute (fewer run in this process: one task gains
        nothing from a cluster but its start-up). Ignored with ``scheduler``.
    scheduler:
        Address of a running Dask scheduler (``tcp://host:8786``): the tasks run there; field files, and a
        store that keeps fields, must then be in a folder the workers share with this machine.
    store:
        Folder of a :class:`TaskStore`: finished results are kept there and reused by the next run.
    progress:
        Called with a :class:`TaskEvent` for every finished task, and at least every ``heartbeat`` seconds
        while tasks run.
    note:
        Called with one-line notes (a resumed run, a damaged task file, fewer local workers for memory).
    task_function:
        Computes one task (default :func:`sealeak.cases.pipeline.compute_task`: the task's own ``run``, for
        every geometry).
    fields:
        Every task that has fields writes them into the store (``DIR/fields.zarr``, :class:`TaskStore`);
        needs ``store``. A store that keeps fields has them written whether asked or not.
    """
    whole_number("--workers", workers, 0, MAX_WORKERS, " (0: no Dask, this process alone)")
    if fields and store is None:
        raise InputError("--store-fields", None, "needs --store DIR: the fields are kept in the store")
    say = note or (lambda _msg: None)
    cores = default_workers()
    if scheduler is None and workers > cores:
        say(f"--workers {workers} is more than the {cores} core{'s' if cores > 1 else ''} this process may use: a local "
            f"cluster runs {cores} worker process{'es' if cores > 1 else ''} (more would only share the cores and "
            "multiply the memory)")
        workers = cores

    def run(tasks: list[Any]) -> list[TaskRecord]:
        if not tasks:
            return []
        fresh = store is not None and not Path(store).exists()
        kept = TaskStore(store, tasks[0].spec.identity(), say, fields=fields) if store is not None else None
        if kept is not None and kept.fields:
            tasks = _with_spec(tasks, fields_store=str(kept.folder.resolve()))
        results = {} if kept is None else _resume(kept, tasks, say)
        todo = [i for i in range(len(tasks)) if i not in results]
        if kept is not None and kept.fields and not fields and any(getattr(tasks[i], "writes_fields", False) for i in todo):
            say(f"{kept.folder} keeps the fields of its tasks: this run writes them too")
        parallel = scheduler is not None or (workers >= 1 and len(todo) >= cluster_from)
        if workers >= 1 and scheduler is None and todo and not parallel:
            say(f"{len(todo)} task{'s' if len(todo) > 1 else ''} to compute: running in this process (a local Dask "
                "cluster would add its start-up and no parallelism)")
        if parallel:  # worker processes share the cores: one FFT thread per task
            tasks = _with_spec(tasks, fft_workers=1)
        need = {i: _task_memory(tasks[i]) for i in todo}

        def refuse(err: SealeakError) -> SealeakError:
            """Refused before any task ran: a store this run created is removed again."""
            if fresh and kept is not None and not any((kept.folder / "tasks").iterdir()):
                shutil.rmtree(kept.folder, ignore_errors=True)
            return err

        if scheduler is None and todo:  # this machine runs them: a task must fit what it has free now
            grid = _grid_of(tasks[0])
            try:
                numerics.require_memory(max(need.values()), f"a task of the {grid}x{grid} grid",
                                        getattr(tasks[0].spec, "memory_limit", None))
            except SealeakError as err:
                raise refuse(err) from None
        start = time.monotonic()
        clock = [start]  # when computing began (after a local cluster has started): the time left is rated from it
        computed = 0

        def finished(i: int, out: TaskRecord) -> None:
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
            try:
                n_local, limit = workers, None
                if scheduler is None:
                    n_local = _local_workers(workers, max(need.values()), _grid_of(tasks[0]), say)
                    limit = machine_memory() // n_local
                if progress is not None:
                    say(f"connecting to the Dask scheduler at {scheduler}" if scheduler is not None else
                        f"starting a local Dask cluster: {n_local} worker process{'es' if n_local > 1 else ''}, "
                        "one thread each")
                _run_dask(tasks, todo, finished, n_local, scheduler, task_function, progress, heartbeat, results,
                          start, clock, need, limit)
            except InputError as err:
                raise refuse(err) from None
        return [results[i] for i in range(len(tasks))]

    run.checks_memory = True  # type: ignore[attr-defined]  # simulate leaves the memory checks to the runner
    return run


def _resume(kept: TaskStore, tasks: list[Any], say: Callable[[str], None]) -> dict[int, TaskRecord]:
    """The results ``kept`` holds of ``tasks`` (by index), with a note on what was resumed or lacks its fields."""
    results: dict[int, TaskRecord] = {}
    for i, t in enumerate(tasks):
        found = kept.load(t.name, fields=bool(getattr(t, "writes_fields", False)))
        if found is not None:
            results[i] = found
    if results:
        say(f"resumed: {len(results)} of {len(tasks)} tasks from {kept.folder}")
    if kept.lacking:
        n = len(kept.lacking)
        say(f"{n} task{'s' if n > 1 else ''} in {kept.folder} {'were' if n > 1 else 'was'} stored without "
            f"fields (before the store kept them): computing {'them' if n > 1 else 'it'} again to write "
            f"{'their' if n > 1 else 'its'} fields")
    return results


def _with_spec(tasks: list[Any], **changes: Any) -> list[Any]:
    """The tasks with ``changes`` made to their spec (one new spec per spec shared by several tasks)."""
    specs: dict[int, Any] = {}
    return [replace(t, spec=specs.setdefault(id(t.spec), replace(t.spec, **changes))) for t in tasks]


def _run_dask(tasks: list[Any], todo: list[int], finished: Callable[[int, TaskRecord], None],
              workers: int, scheduler: str | None, task_function: Callable[[Any], TaskRecord],
              progress: Callable[[TaskEvent], None] | None, heartbeat: float, results: dict[int, Any],
              start: float, clock: list[float], need: dict[int, int], memory_limit: int | None = None) -> None:
    """Submit the tasks ``todo``, each to the workers that can hold it, and hand each result to ``finished`` as
    soon as it arrives (in any order)."""
    gpus = workers if getattr(tasks[0].spec, "device", "cpu") == "cuda" else 0  # one worker per GPU (run_workers)
    with _client(workers, scheduler, memory_limit, gpus) as client:
        where = _placement(client, tasks, todo, need)  # raises before anything is submitted
        clock[0] = time.monotonic()
        link = getattr(client, "dashboard_link", None) if progress is not None else None
        if link and progress is not None and find_spec("bokeh") is not None:
            progress(TaskEvent(len(results), len(tasks), None, clock[0] - start, None, dashboard=link))
        index = {client.submit(task_function, tasks[i], pure=False, workers=where[i],
                               allow_other_workers=False if where[i] is not None else None): i for i in todo}
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
