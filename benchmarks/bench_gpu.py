"""GPU against CPU on the same machine: the contact solve, the flow solve and a whole ``simulate``, on ``"cuda"`` and ``"cpu"``.

Usage: python benchmarks/bench_gpu.py [--quick] [--cpu-max N] [--simulate-max N] [--simulate-cpu-max N]
       [--flow N,N,...] [--flow-fractions F,F,...] [--jacobi-max N] [--sections contact,flow,simulate] [N ...]

* contact: ``solve_contact`` on the surface of ``benchmarks/_common.py`` at about 10 % and 40 % contact (residual
  1e-8), at each grid N (default 2048 4096 8192), on the GPU (CuPy) and, up to ``--cpu-max`` (default 4096; a
  CPU solve at 8192² takes many minutes), on the CPU; the iterations and contact areas of both;
* flow: ``solve_flow`` on the gap fields of GPU contact solutions at about 10 % and 25 % contact (or
  ``--flow-fractions``), at each grid of
  ``--flow`` (default 2048,4096): the AMG back-end on the CPU (Gauss–Seidel V-cycles) against ``device="cuda"``
  (the same hierarchy, built on the CPU, cycled on the GPU with l1-Jacobi smoothing, one sweep) and, up
  to ``--jacobi-max`` (default 2048) two sweeps and CG on the GPU with the diagonal alone (at most 20 000 iterations); the
  seconds of each phase, the CG iterations and the flux of each against the CPU's, with the same check;
* simulate: the bundled reference-experiment case at 10 squeeze pressures, one realisation, no threshold search,
  in this process, ``--device cuda`` up to ``--simulate-max`` (default 2048) against ``--device cpu`` up to
  ``--simulate-cpu-max`` (default: the same), with the seconds of the flow solves;
* ``--sections``: which of the three to run (default all);
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
from sealeak.numerics import _amg  # noqa: E402

FRACTIONS = (0.1, 0.4)
ETA, DP = 1e-3, 1e5


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


def gap_field(n: int, fraction: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The gap field and contact mask (on the host) of the GPU's contact solution, and its contact area."""
    h, sp = surface(n)
    res = numerics.solve_contact(numerics.array_namespace_for("cuda").asarray(h), SIZE, E_STAR,
                                 pressure_for(sp, fraction)).on_host()
    return res.gap, res.contact, res.contact_area


def flow(gap: np.ndarray, contact: np.ndarray, device: str, preconditioner: str = "amg", sweeps: int = 1,
         max_iter: int = 2000) -> numerics.FlowResult | str:
    """One flow solve (its result), or why it failed (a line)."""
    _amg.DEVICE_PRECONDITIONER, _amg._CycleSolver.SWEEPS = preconditioner, sweeps
    try:
        return numerics.solve_flow(gap, SIZE, ETA, DP, contact=contact, method="amg", device=device, max_iter=max_iter)
    except Exception as err:  # a benchmark reports a failed solve and goes on
        return f"{type(err).__name__}: {err}"
    finally:
        _amg.DEVICE_PRECONDITIONER, _amg._CycleSolver.SWEEPS = "amg", 1
        free_gpu()


def flow_cell(r: numerics.FlowResult | str, ref: numerics.FlowResult) -> str:
    """A table cell: total seconds (set-up + CG iterations), iterations, flux against the CPU's."""
    if isinstance(r, str):
        return r[:90]
    ph = r.phase_seconds
    return (f"{r.seconds:.2f} s ({ph.get('setup', 0):.2f} + {ph.get('iterations', 0):.2f}), {r.iterations} its, "
            f"{r.flux / ref.flux - 1:+.1e}")


def whole_run(n: int, device: str) -> tuple[float, float]:
    """Seconds of ``simulate`` (reference-experiment, 10 pressures, one realisation) and of its flow solves."""
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=np.geomspace(2e4, 2.5e5, 10))
    solve, spent = numerics.solve_flow, [0.0]

    def timed_flow(*a, **k):
        out = solve(*a, **k)
        spent[0] += out.seconds
        return out

    numerics.solve_flow = timed_flow
    try:
        t = time.perf_counter()
        simulate(case, grid=n, realizations=1, seed=1, threshold=False, device=device)
        return time.perf_counter() - t, spent[0]
    finally:
        numerics.solve_flow = solve


def free_gpu() -> None:
    """Hand CuPy's cached blocks back, so that the next run's memory check sees the card's memory."""
    numerics.array_namespace_for("cuda")  # CuPy is imported by now
    sys.modules["cupy"].get_default_memory_pool().free_all_blocks()


def main() -> None:
    quick = "--quick" in sys.argv
    cpu_max = int(take_option("--cpu-max", "4096"))
    sim_max = int(take_option("--simulate-max", "2048"))
    sim_cpu_max = int(take_option("--simulate-cpu-max", str(sim_max)))
    flow_sizes = [int(v) for v in take_option("--flow", "512" if quick else "2048,4096").split(",") if v]
    jacobi_max = int(take_option("--jacobi-max", "2048"))
    flow_fractions = [float(v) for v in take_option("--flow-fractions", "0.1,0.25").split(",") if v]
    sections = take_option("--sections", "contact,flow,simulate").split(",")
    sizes = [512] if quick else [int(a) for a in sys.argv[1:] if not a.startswith("--")] or [2048, 4096, 8192]
    try:
        card = numerics.device_name("cuda", "--device")
    except InputError as err:
        print(f"bench_gpu: no GPU run on this machine: {err}")
        return
    print(f"GPU benchmark, {datetime.date.today().isoformat()}: {card} against {cpu_name()}; sealeak {__version__}\n")
    contact(256, 0.1, "cuda")  # CuPy's start-up and first FFT plans, outside the measurements
    if "contact" in sections:
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
    if "flow" in sections and flow_sizes:
        print("\nFlow, seconds (set-up + CG iterations), CG iterations, flux against the CPU's; every check passed "
              "unless a line says otherwise:\n")
        print("| grid | contact | unknowns | CPU: AMG, Gauss–Seidel | GPU: AMG, l1-Jacobi ×1 | GPU: AMG, l1-Jacobi ×2 "
              "| GPU: CG, diagonal only |")
        print("|---|---|---|---|---|---|---|")
        for n in flow_sizes:
            for f in flow_fractions:
                gap, mask, area = gap_field(n, f)
                free_gpu()
                ref = flow(gap, mask, "cpu")
                if isinstance(ref, str):
                    print(f"| {n}² | {area:.1%} | | {ref[:90]} | | | |", flush=True)
                    continue
                one = flow(gap, mask, "cuda")
                two = flow(gap, mask, "cuda", sweeps=2) if n <= jacobi_max else "—"
                jac = flow(gap, mask, "cuda", "jacobi", max_iter=20000) if n <= jacobi_max else "—"
                print(f"| {n}² | {area:.1%} | {ref.unknowns} | {ref.seconds:.2f} s ({ref.phase_seconds['setup']:.2f} + "
                      f"{ref.phase_seconds['iterations']:.2f}), {ref.iterations} its | {flow_cell(one, ref)} | "
                      f"{two if isinstance(two, str) else flow_cell(two, ref)} | {jac if isinstance(jac, str) else flow_cell(jac, ref)} |", flush=True)
    runs = [n for n in sizes if n <= sim_max] if "simulate" in sections else []
    if runs:
        print("\n| grid | simulate, 10 pressures, 1 realisation | GPU (of which flow) | CPU (of which flow) | speed-up |")
        print("|---|---|---|---|---|")
        for n in runs:
            g = whole_run(n, "cuda")
            free_gpu()
            c = whole_run(n, "cpu") if n <= sim_cpu_max else None
            cpu = f"{c[0]:.1f} s ({c[1]:.1f} s)" if c else "—"
            speed = f"{c[0] / g[0]:.1f}×" if c else "—"
            print(f"| {n}² | reference-experiment | {g[0]:.1f} s ({g[1]:.1f} s) | {cpu} | {speed} |", flush=True)

if __name__ == "__main__":
    main()
