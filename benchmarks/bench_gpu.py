"""GPU against CPU on the same machine: the contact solve and a whole ``simulate``, ``device = "cuda"`` and ``"cpu"``.

Usage: python benchmarks/bench_gpu.py [--quick] [--cpu-max N] [--simulate-max N] [N ...]

* contact: ``solve_contact`` on the surface of ``benchmarks/_common.py`` at about 10 % and 40 % contact (residual
  1e-8), at each grid N (default 2048 4096 8192), on the GPU (CuPy) and, up to ``--cpu-max`` (default 4096; a
  CPU solve at 8192² takes many minutes), on the CPU; the iterations and contact areas of both;
* simulate: the bundled reference-experiment case at 10 squeeze pressures, one realisation, no threshold search,
  in this process, ``--device cuda`` against ``--device cpu`` up to ``--simulate-max`` (default 2048), with the
  seconds of the flow solves (on the CPU either way);
* ``--quick``: 512² only (seconds), to check a GPU machine before the long run.

Prints Markdown tables for docs/performance.md headed by the date, the card (CuPy's name of it) and the CPU.
Without CuPy or without a GPU it prints one line saying so and exits 0. Runs from the repository root with the
project's virtual environment: ``python benchmarks/bench_gpu.py``.
"""

from __future__ import annotations

import datetime
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from _common import E_STAR, SIZE, pressure_for, surface, take_option  # noqa: E402
from sealeak import __version__, numerics  # noqa: E402
from sealeak.cases import example_path, load_cases, simulate  # noqa: E402
from sealeak.errors import InputError  # noqa: E402

FRACTIONS = (0.1, 0.4)


def cpu_name() -> str:
    """The CPU's model name and the cores this process may use."""
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            model = next((ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name")), model)
    except OSError:
        pass
    return f"{model}, {len(os.sched_getaffinity(0))} cores"


def contact(n: int, fraction: float, device: str) -> tuple[float, int, float]:
    """Seconds, iterations and contact area of one contact solve on ``device`` (heights moved there first)."""
    h, sp = surface(n)
    heights = numerics.array_namespace_for(device).asarray(h)
    t = time.perf_counter()
    res = numerics.solve_contact(heights, SIZE, E_STAR, pressure_for(sp, fraction))  # its scalars synchronise
    return time.perf_counter() - t, res.iterations, res.contact_area


def whole_run(n: int, device: str) -> tuple[float, float]:
    """Seconds of ``simulate`` (reference-experiment, 10 pressures, one realisation) and of its flow solves."""
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=np.geomspace(2e4, 2.5e5, 10))
    flow, spent = numerics.solve_flow, [0.0]

    def timed_flow(*a, **k):
        out = flow(*a, **k)
        spent[0] += out.seconds
        return out

    numerics.solve_flow = timed_flow
    try:
        t = time.perf_counter()
        simulate(case, grid=n, realizations=1, seed=1, threshold=False, device=device)
        return time.perf_counter() - t, spent[0]
    finally:
        numerics.solve_flow = flow


def free_gpu() -> None:
    """Hand CuPy's cached blocks back, so that the next run's memory check sees the card's memory."""
    numerics.array_namespace_for("cuda")  # CuPy is imported by now
    sys.modules["cupy"].get_default_memory_pool().free_all_blocks()


def main() -> None:
    quick = "--quick" in sys.argv
    cpu_max = int(take_option("--cpu-max", "4096"))
    sim_max = int(take_option("--simulate-max", "2048"))
    sizes = [512] if quick else [int(a) for a in sys.argv[1:] if not a.startswith("--")] or [2048, 4096, 8192]
    try:
        card = numerics.device_name("cuda", "--device")
    except InputError as err:
        print(f"bench_gpu: no GPU run on this machine: {err}")
        return
    print(f"GPU benchmark, {datetime.date.today().isoformat()}: {card} against {cpu_name()}; sealeak {__version__}\n")
    contact(256, 0.1, "cuda")  # CuPy's start-up and first FFT plans, outside the measurements
    print("| grid | contact | GPU | CPU (same machine) | speed-up | iterations GPU / CPU | contact area GPU / CPU |")
    print("|---|---|---|---|---|---|---|")
    for n in sizes:
        for f in FRACTIONS:
            g = contact(n, f, "cuda")
            free_gpu()
            c = contact(n, f, "cpu") if n <= cpu_max else None
            cpu = f"{c[0]:.2f} s" if c else "—"
            speed = f"{c[0] / g[0]:.0f}×" if c else "—"
            its = f"{g[1]} / {c[1]}" if c else f"{g[1]} / —"
            area = f"{g[2]:.4%} / {c[2]:.4%}" if c else f"{g[2]:.4%} / —"
            print(f"| {n}² | {f:.0%} | {g[0]:.2f} s | {cpu} | {speed} | {its} | {area} |", flush=True)
    runs = [n for n in sizes if n <= sim_max]
    if runs:
        print("\n| grid | simulate, 10 pressures, 1 realisation | GPU (of which flow) | CPU (of which flow) | speed-up |")
        print("|---|---|---|---|---|")
        for n in runs:
            g = whole_run(n, "cuda")
            free_gpu()
            c = whole_run(n, "cpu")
            print(f"| {n}² | reference-experiment | {g[0]:.1f} s ({g[1]:.1f} s) | {c[0]:.1f} s ({c[1]:.1f} s) | "
                  f"{c[0] / g[0]:.1f}× |", flush=True)


if __name__ == "__main__":
    main()
