"""Benchmark of sealeak.numerics.solve_flow on contact gap fields: time per phase, iterations, check, peak memory.

Usage: python benchmarks/bench_flow.py [N ...] [--fractions 0.1,0.25] [--methods amg] [--repeat K]
(default N: 256 512 1024 2048; fractions 0.1, 0.25, 0.3, 0.4; "direct" and "amg" up to 1024², "amg" above)

Gap fields: the FFT contact solution (tolerance 1e-8) of the self-affine surface of ``_common.surface(N)``
at the load of ``_common.pressure_for(fraction)``, computed once and cached in out/bench-cache (a 4096²
contact solve takes several minutes; it is not part of the flow time).

Every (N, fraction, method) runs K times (default 1), each in a fresh subprocess; the table shows the
fastest run. Columns: "A/A0" the contact fraction, "unknowns" the cells of the spanning cluster, then the
flow solve's phases in seconds ("clusters": conductances and the spanning cluster; "assembly": faces and
the matrix; "setup": LU factorisation or AMG hierarchy; "iterations": the back-end's solves; "check": the
extended-precision residuals), the total, CG iterations (amg), the flux-error bound ||r||_1/Q of the
solution check, |inflow - outflow|/Q, and memory: "rss0" the process's peak resident set before the flow
solve (gap field loaded), "peak" the peak resident set of the whole process (ru_maxrss, which includes the
interpreter and the gap field) and "est" the up-front estimate ``flow_memory_bytes``.
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

from _common import take_option  # noqa: E402

FRACTIONS = (0.1, 0.25, 0.3, 0.4)  # 0.3: near the percolation threshold, the hardest case
PHASES = ("clusters", "assembly", "setup", "iterations", "check")


def one(n: int, fraction: float, method: str) -> dict:
    """One flow solve in this process; the gap field comes from the cache (or is computed first)."""
    from _common import SIZE, contact_gap
    from sealeak.numerics import flow_memory_bytes, solve_flow

    gap, contact, _info = contact_gap(n, fraction)
    rss_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t = time.perf_counter()
    res = solve_flow(gap, SIZE, 1e-3, 1e4, contact=contact, method=method)
    sec = time.perf_counter() - t
    return dict(n=n, target=fraction, area=float(contact.mean()), method=res.method, seconds=sec,
                phases=res.phase_seconds, iterations=res.iterations, unknowns=res.unknowns, flux=res.flux,
                residual=res.residual, cons=res.conservation_error, rss_before_mb=rss_before,
                estimate_mb=flow_memory_bytes(n, res.method if res.method != "none" else "auto") / 2**20,
                maxrss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--case":
        print(json.dumps(one(int(sys.argv[2]), float(sys.argv[3]), sys.argv[4])))
        return
    fractions = [float(f) for f in take_option("--fractions", ",".join(map(str, FRACTIONS))).split(",")]
    methods_opt = take_option("--methods", "")
    repeat = int(take_option("--repeat", "1"))
    sizes = [int(a) for a in sys.argv[1:]] or [256, 512, 1024, 2048]
    print(f"{'N':>5} {'A/A0':>6} {'method':>6} {'unknowns':>9} " + " ".join(f"{p[:6]:>6}" for p in PHASES)
          + f" {'total':>6} {'iter':>4} {'flux m3/s':>9} {'bound':>7} {'conserv':>7} {'rss0 MB':>7} {'peak MB':>7}"
          f" {'est MB':>7}  runs")
    for n in sizes:
        for f in fractions:
            methods = methods_opt.split(",") if methods_opt else (["direct", "amg"] if n <= 1024 else ["amg"])
            for m in methods:
                runs = []
                for _ in range(repeat):
                    out = subprocess.run([sys.executable, __file__, "--case", str(n), str(f), m],
                                         capture_output=True, text=True)
                    if out.returncode:
                        print(f"{n:>5} {f:>6.2f} {m:>6} FAILED: {out.stderr.strip().splitlines()[-1]}", flush=True)
                        break
                    runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
                if not runs:
                    continue
                r = min(runs, key=lambda x: x["seconds"])
                ph = " ".join(f"{r['phases'].get(p, 0.0):>6.2f}" for p in PHASES)
                print(f"{r['n']:>5} {r['area']:>6.4f} {r['method']:>6} {r['unknowns']:>9d} {ph} {r['seconds']:>6.2f} "
                      f"{r['iterations']:>4d} {r['flux']:>9.3e} {r['residual']:>7.1e} {r['cons']:>7.1e} "
                      f"{r['rss_before_mb']:>7.0f} {r['maxrss_mb']:>7.0f} {r['estimate_mb']:>7.0f}  "
                      + ", ".join(f"{x['seconds']:.1f}" for x in runs), flush=True)


if __name__ == "__main__":
    main()
