"""Benchmark of the ensemble on Dask: speed-up on 1 and 2 workers, and the overhead of Dask against the plain loop.

Usage: python benchmarks/bench_dask.py [N] [--realizations R] [--repeat K]   (default N = 512, R = 4, K = 2)

Case: the bundled reference-experiment case at 10 squeeze pressures 20–250 kPa (its own 40 would make each
task four times longer; the ratios are what is measured), grid N, seed 1, no threshold search (it would add
one task per realisation of about the same length, which changes nothing in the ratios). One task is one
realisation's contact sweep and flow solves (``sealeak.cases.simulation.ensemble_tasks``).

(a) R realisations through ``simulate`` with ``make_runner(workers=0)`` (the plain loop in this process),
    ``workers=1`` and ``workers=2`` (a local Dask cluster of one-thread worker processes, started and
    stopped by the runner: its start-up is inside these times): wall times and speed-ups against the
    plain loop.
(b) One realisation (one task): the plain loop, the plain loop with the one FFT thread per task that the Dask
    workers use ("plain, 1 FFT thread": the same computation as on a worker), the default runner (``workers=2``,
    which computes a single task in this process, ``CLUSTER_FROM_TASKS``), and ``workers=1`` with the cluster
    forced (``cluster_from=1``). The cluster
    start-up and shut-down are measured apart, by the same runner on the same task list with a task that
    returns at once; the overhead is (t_dask1 - t_plain)/t_plain with the start-up included, and with it
    subtracted.
Every configuration runs K times; the minimum is reported (the machine is shared: the load average is
printed before and after). The results of all runs are asserted identical (bit for bit) to the plain loop's.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from _common import take_option  # noqa: E402
from sealeak.cases import example_path, load_cases, simulate  # noqa: E402
from sealeak.cases.ensemble import make_runner  # noqa: E402
from sealeak.cases.simulation import EnsembleTask, run_task  # noqa: E402


def _instant(task: EnsembleTask) -> dict[str, Any]:
    """A task that does nothing: the runner's own cost (cluster start-up, submission, shut-down)."""
    return {}


def _one_fft_thread(tasks: list[EnsembleTask]) -> list[dict[str, Any]]:
    """The plain loop with the tasks' FFTs on one thread, as on a Dask worker."""
    return [run_task(replace(t, spec=replace(t.spec, fft_workers=1))) for t in tasks]


def main() -> None:
    realizations = int(take_option("--realizations", "4"))
    repeat = int(take_option("--repeat", "2"))
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 512
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=np.geomspace(2e4, 2.5e5, 10))
    print(f"reference-experiment, grid {n}², 10 squeeze pressures, seed 1, no threshold search; "
          f"{os.cpu_count()} CPUs; load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)

    reference: dict[int, Any] = {}

    def timed(label: str, r: int, runner: Any) -> float:
        best = float("inf")
        for _ in range(repeat):
            t = time.perf_counter()
            res = simulate(case, grid=n, realizations=r, seed=1, threshold=False, runner=runner)
            dt = time.perf_counter() - t
            best = min(best, dt)
            per = {k: np.asarray(v) for k, v in res.per_realization.items()}
            if r not in reference:
                reference[r] = per
            for k, v in per.items():  # identical numbers whatever runs the tasks
                assert np.array_equal(v, reference[r][k], equal_nan=True), f"{label}: {k} differs from the plain loop"
        print(f"  {label:<34} {best:8.2f} s   (runs of {repeat}, minimum)", flush=True)
        return best

    print(f"(a) {realizations} realisations")
    t0 = timed("plain loop (workers=0)", realizations, make_runner(workers=0))
    t1 = timed("Dask, 1 worker", realizations, make_runner(workers=1))
    t2 = timed("Dask, 2 workers", realizations, make_runner(workers=2))
    print(f"  speed-up against the plain loop: 1 worker {t0 / t1:.2f}x, 2 workers {t0 / t2:.2f}x; "
          f"2 workers against 1: {t1 / t2:.2f}x")

    print("(b) 1 realisation")
    plain = make_runner(workers=0)
    captured: list[EnsembleTask] = []

    def capturing(tasks: list[EnsembleTask]) -> list[dict[str, Any]]:
        captured[:] = tasks
        return plain(tasks)

    p = timed("plain loop", 1, capturing)
    p1 = timed("plain loop, 1 FFT thread", 1, _one_fft_thread)
    auto = timed("default runner (workers=2: 1 task)", 1, make_runner(workers=2))
    d = timed("Dask, 1 worker (cluster forced)", 1, make_runner(workers=1, cluster_from=1))
    tasks_runner = make_runner(workers=1, task_function=_instant, cluster_from=1)
    startup = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        tasks_runner(captured)  # the same task list, each task returning at once
        startup = min(startup, time.perf_counter() - t)
    print(f"  {'cluster start-up + shut-down':<34} {startup:8.2f} s")
    print(f"  overhead of the default runner, which computes a single task in this process: {100 * (auto - p) / p:+.1f} %")
    print(f"  overhead of a forced one-worker cluster (t_dask1 - t_plain)/t_plain: {100 * (d - p) / p:+.1f} % with the start-up, "
          f"{100 * (d - startup - p) / p:+.1f} % without; against the plain loop with 1 FFT thread: "
          f"{100 * (d - p1) / p1:+.1f} % / {100 * (d - startup - p1) / p1:+.1f} %")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
