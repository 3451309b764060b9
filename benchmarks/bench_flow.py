"""Benchmark of sealeak.numerics.solve_flow on contact gap fields: seconds, iterations, peak memory.

Usage: python benchmarks/bench_flow.py [N ...]   (default 256 512 1024 2048)
Columns: "bound" is the rigorous flux-error bound ||r||_1/Q of the solution check, "conserv" the
|inflow - outflow|/Q.
The contact solution is computed first (not timed); each case runs in a fresh subprocess.
Memory: ru_maxrss of the case (contact solve included) and "rss0", the peak before the flow
solve; the flow solve's own peak is about maxrss - rss0 when that is positive. (tracemalloc is not
used here: it slows pyamg's many small allocations several-fold.)
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

FRACTIONS = (0.1, 0.25, 0.3, 0.4)  # 0.3: near the percolation threshold, the hardest case


def one(n: int, fraction: float, method: str) -> dict:
    from _common import E_STAR, SIZE, pressure_for, surface
    from sealeak.numerics import flow_memory_bytes, solve_contact, solve_flow

    h, sp = surface(n)
    c = solve_contact(h, SIZE, E_STAR, pressure_for(sp, fraction))
    gap, contact = c.gap, c.contact
    del h, c
    rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t = time.perf_counter()
    res = solve_flow(gap, SIZE, 1e-3, 1e4, contact=contact, method=method)
    sec = time.perf_counter() - t
    return dict(n=n, target=fraction, area=float(contact.mean()), method=res.method, seconds=sec,
                iterations=res.iterations, unknowns=res.unknowns, flux=res.flux, residual=res.residual,
                cons=res.conservation_error, rss_before_mb=rss_before,
                estimate_mb=flow_memory_bytes(n, res.method if res.method != "none" else "auto") / 2**20,
                maxrss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--case":
        print(json.dumps(one(int(sys.argv[2]), float(sys.argv[3]), sys.argv[4])))
        return
    sizes = [int(a) for a in sys.argv[1:]] or [256, 512, 1024, 2048]
    print(f"{'N':>6} {'A/A0':>7} {'method':>7} {'unknowns':>9} {'seconds':>8} {'iter':>5} {'flux m3/s':>10} "
          f"{'bound':>8} {'conserv':>8} {'rss0 MB':>8} {'est MB':>7} {'maxrss MB':>9}")
    for n in sizes:
        for f in FRACTIONS:
            methods = ["direct", "amg"] if n <= 1024 else ["amg"]
            for m in methods:
                out = subprocess.run([sys.executable, __file__, "--case", str(n), str(f), m],
                                     capture_output=True, text=True)
                if out.returncode:
                    print(f"{n:>6} {f:>7.2f} {m:>7} FAILED: {out.stderr.strip().splitlines()[-1]}", flush=True)
                    continue
                r = json.loads(out.stdout.strip().splitlines()[-1])
                print(f"{r['n']:>6} {r['area']:>7.4f} {r['method']:>7} {r['unknowns']:>9d} {r['seconds']:>8.2f} "
                      f"{r['iterations']:>5d} {r['flux']:>10.3e} {r['residual']:>8.1e} {r['cons']:>8.1e} "
                      f"{r['rss_before_mb']:>8.0f} {r['estimate_mb']:>7.0f} {r['maxrss_mb']:>9.0f}", flush=True)


if __name__ == "__main__":
    main()
