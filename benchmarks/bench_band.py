"""Leak rate of an O-ring over a 50-point compression sweep: the series-strip integral (docs/theory.md §10).

The bundled `o-ring` example (water), compression 10–30 % in 50 steps; the critical junction alone and
both theories, with the fluid pressure in the band ignored (the paper) and coupled (the default,
docs/theory.md §13). Prints the wall time (best of ``--repeat``), the theory evaluations and the quadrature
nodes. Goal (issue 12): 50 loads, both theories, within 1 s. Usage: python benchmarks/bench_band.py [--repeat N]
"""

from __future__ import annotations

import argparse
import platform
import time
from dataclasses import replace

import numpy as np

import sealeak.cases.band as band_module
from sealeak.cases import example_path, load_cases
from sealeak.cases.seals import with_loads


def sweep_case(model: str, fluid_pressure: str = "ignored"):
    case = load_cases(example_path("o-ring"))[0]
    assert case.band is not None
    band = with_loads(case.band, np.linspace(0.10, 0.30, 50), case.youngs_modulus, case.poisson_ratio)
    return replace(case, band=band, model=model, fluid_pressure=fluid_pressure)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"{platform.processor() or platform.machine()}, {time.strftime('%Y-%m-%d')}")
    counts = {"cj": 0, "em": 0}
    cj, em = band_module.critical_junction, band_module.effective_medium

    def count_cj(*a, **k):
        counts["cj"] += np.size(k["squeeze_pressure"])
        return cj(*a, **k)

    def count_em(*a, **k):
        counts["em"] += np.size(k["squeeze_pressure"])
        return em(*a, **k)

    band_module.critical_junction, band_module.effective_medium = count_cj, count_em
    runs = (("critical-junction", "ignored", args.repeat), ("both", "ignored", 1),
            ("critical-junction", "coupled", args.repeat), ("both", "coupled", 1))
    for model, fluid_pressure, repeat in runs:
        case = sweep_case(model, fluid_pressure)
        best = float("inf")
        for _ in range(repeat):
            counts.update(cj=0, em=0)
            t = time.perf_counter()
            res = band_module.run_band(case)
            best = min(best, time.perf_counter() - t)
        nodes = res.critical_junction.evaluations
        print(f"{model:18s} fluid pressure {fluid_pressure:8s} 50 loads: {best:.2f} s  (critical-junction pressures {counts['cj']}, effective-medium "
              f"pressures {counts['em']}; σ evaluations per load {nodes.min()}-{nodes.max()}; "
              f"largest estimated relative error {np.nanmax(res.critical_junction.change):.1e})")


if __name__ == "__main__":
    main()
