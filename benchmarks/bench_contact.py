"""Benchmark of sealeak.numerics.solve_contact: seconds, iterations, peak memory.

Usage: python benchmarks/bench_contact.py [N ...]   (default 256 512 1024 2048)
Each case runs in a fresh subprocess so that ru_maxrss is the peak of that case alone.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

FRACTIONS = (0.1, 0.4)


def one(n: int, fraction: float) -> dict:
    from _common import E_STAR, SIZE, pressure_for, surface
    from sealeak.numerics import contact_memory_bytes, solve_contact

    h, sp = surface(n)
    p0 = pressure_for(sp, fraction)
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    t = time.perf_counter()
    res = solve_contact(h, SIZE, E_STAR, p0)
    sec = time.perf_counter() - t
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return dict(n=n, target=fraction, area=res.contact_area, seconds=sec, iterations=res.iterations,
                residual=res.residual, peak_mb=peak / 2**20, estimate_mb=contact_memory_bytes(n) / 2**20,
                maxrss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def main() -> None:
    if len(sys.argv) == 4 and sys.argv[1] == "--case":
        print(json.dumps(one(int(sys.argv[2]), float(sys.argv[3]))))
        return
    sizes = [int(a) for a in sys.argv[1:]] or [256, 512, 1024, 2048]
    print(f"{'N':>6} {'target':>6} {'A/A0':>7} {'seconds':>8} {'iter':>5} {'residual':>9} "
          f"{'peak MB':>8} {'est MB':>7} {'maxrss MB':>9}")
    for n in sizes:
        for f in FRACTIONS:
            out = subprocess.run([sys.executable, __file__, "--case", str(n), str(f)], capture_output=True,
                                 text=True, check=True)
            r = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"{r['n']:>6} {r['target']:>6.2f} {r['area']:>7.4f} {r['seconds']:>8.2f} {r['iterations']:>5d} "
                  f"{r['residual']:>9.2e} {r['peak_mb']:>8.0f} {r['estimate_mb']:>7.0f} {r['maxrss_mb']:>9.0f}",
                  flush=True)


if __name__ == "__main__":
    main()
