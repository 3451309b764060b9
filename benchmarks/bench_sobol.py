"""Sobol' indices by SALib against SciPy's ``scipy.stats.sobol_indices`` on an additive test function (docs/architecture.md).

y = Σ a_i u_i on the unit cube (u_i uniform): S1_i = ST_i = a_i²/Σ a_j² in closed form. For each base
sample size N both libraries estimate S1 and ST from the same kind of design (Saltelli's, N·(d + 2)
runs, scrambled Sobol' points, Saltelli 2010 for S1 and Jansen 1999 for ST) and their 95 % bootstrap
intervals; printed: the largest error against the closed form over seeds 1–5, the mean half-width of the
intervals, and the wall time (best of 3) of sampling plus analysis with the bootstrap. Usage:
python benchmarks/bench_sobol.py
"""

from __future__ import annotations

import platform
import time

import numpy as np
from scipy import stats

from sealeak.cases.sensitivity import sobol_indices

A = np.array([1.0, 2.0, 0.5, 0.0, 3.0])
EXACT = A**2 / (A**2).sum()


def salib(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    s = sobol_indices(lambda u: 10.0 ** (u @ A), [f"x{i}" for i in range(A.size)], n, seed)
    return s.first[0], s.total[0], float(np.mean(np.r_[s.first_conf[0], s.total_conf[0]]))


def scipy_sobol(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    rng = np.random.default_rng(seed)
    res = stats.sobol_indices(func=lambda x: A @ x, n=n, dists=[stats.uniform()] * A.size, method="saltelli_2010",
                              rng=rng)
    boot = res.bootstrap(confidence_level=0.95, n_resamples=200)
    half = np.r_[np.diff(np.c_[boot.first_order.confidence_interval]).ravel(),
                 np.diff(np.c_[boot.total_order.confidence_interval]).ravel()] / 2
    return res.first_order, res.total_order, float(np.mean(half))


def main() -> None:
    print(f"additive function, d = {A.size}, exact S1 = ST = {np.round(EXACT, 4).tolist()}; {platform.processor() or platform.machine()}")
    print(f"{'N':>6} {'library':>8} {'max |S1 err|':>13} {'max |ST err|':>13} {'mean CI half':>13} {'time (s)':>9}")
    for n in (256, 1024, 4096):
        for name, run in (("SALib", salib), ("SciPy", scipy_sobol)):
            errors = [run(n, seed) for seed in range(1, 6)]
            e1 = max(float(np.max(np.abs(s1 - EXACT))) for s1, _, _ in errors)
            et = max(float(np.max(np.abs(st - EXACT))) for _, st, _ in errors)
            half = float(np.mean([h for _, _, h in errors]))
            best = min(_timed(run, n) for _ in range(3))
            print(f"{n:>6} {name:>8} {e1:>13.2e} {et:>13.2e} {half:>13.3f} {best:>9.3f}")


def _timed(run, n: int) -> float:
    t = time.perf_counter()
    run(n, 1)
    return time.perf_counter() - t


if __name__ == "__main__":
    main()
