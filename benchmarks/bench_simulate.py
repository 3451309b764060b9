"""Benchmark of the whole numerically exact pipeline (``sealeak simulate``): seconds, iterations, memory.

Usage: python benchmarks/bench_simulate.py [N] [--threshold]   (default N = 1024)

The bundled reference-experiment case (PDMS ring on the sandpaper stand-in; L = Lx = 5 mm, whose
roughness cut-off λ1 = 20 µm a 1024² grid just resolves at 4 points per wavelength) at 10 squeeze
pressures 20–250 kPa, one realisation, seed 1: synthesis, the warm-started contact sweep and the
flow solves, with the percolation-threshold bisection only with ``--threshold``. The contact and
flow solvers are wrapped to time every call; "iter" is CG iterations (contact) and CG iterations
(flow, AMG) or refinement steps (flow, direct). Peak memory is the process's ru_maxrss.
"""

from __future__ import annotations

import resource
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from sealeak import numerics  # noqa: E402
from sealeak.cases import (  # noqa: E402
    example_path,
    load_cases,
    simulate,  # noqa: E402
)


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    n = int(args[0]) if args else 1024
    threshold = "--threshold" in sys.argv
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=np.geomspace(2e4, 2.5e5, 10))
    calls: list[tuple[str, float, int, str]] = []
    sweep, flow = numerics.solve_contact_sweep, numerics.solve_flow

    def timed_sweep(*a, **k):
        t = time.perf_counter()
        out = sweep(*a, **k)
        dt = time.perf_counter() - t
        calls.append(("contact sweep", dt, sum(r.iterations for r in out), f"{len(out)} pressures"))
        return out

    def timed_flow(*a, **k):
        out = flow(*a, **k)
        calls.append(("flow", out.seconds, out.iterations, f"{out.method}, {out.unknowns} unknowns"))
        return out

    numerics.solve_contact_sweep, numerics.solve_flow = timed_sweep, timed_flow
    t = time.perf_counter()
    res = simulate(case, grid=n, realizations=1, seed=1, threshold=threshold)
    total = time.perf_counter() - t
    numerics.solve_contact_sweep, numerics.solve_flow = sweep, flow

    print(f"pipeline: reference-experiment, grid {n}², 1 realisation, {res.squeeze_pressure.size} pressures, "
          f"threshold search {'on' if threshold else 'off'}")
    print(f"{'step':<14} {'seconds':>8} {'iter':>6}  detail")
    for name, dt, it, detail in calls:
        print(f"{name:<14} {dt:>8.2f} {it:>6d}  {detail}")
    contact_s = sum(c[1] for c in calls if c[0] == "contact sweep")
    flow_s = sum(c[1] for c in calls if c[0] == "flow")
    print(f"{'total':<14} {total:>8.2f}         contact {contact_s:.1f} s, flow {flow_s:.1f} s, "
          f"rest (synthesis, theory, threshold) {total - contact_s - flow_s:.1f} s")
    print(f"peak memory (ru_maxrss): {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")
    print(f"{'P0 (kPa)':>9} {'A/A0':>7} {'Q (m³/s)':>10} {'alpha':>7}")
    for p, a, q, al in zip(res.squeeze_pressure, res.relative_contact_area, res.leak_rate, res.alpha):
        print(f"{p / 1e3:>9.1f} {a:>7.3f} {q:>10.3e} {al:>7.3f}")


if __name__ == "__main__":
    main()
