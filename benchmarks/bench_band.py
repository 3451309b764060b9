"""Leak rate of an O-ring over a 50-point compression sweep: the series-strip integral (docs/theory.md §10).

The bundled `o-ring` example (water), compression 10–30 % in 50 steps; the critical junction alone and
both theories, with the fluid pressure in the band ignored (the paper) and coupled (the default,
docs/theory.md §13). Prints the wall and CPU time of the process (each the best of ``--repeat``, each run cold: the
kept P(u) rows of physics/gaps.py are forgotten first), the theory evaluations and the quadrature nodes. Goal (issue 12):
50 loads, both theories, within 1 s.

Then the bundled `o-ring` example as it is (9 compressions, water and oil, both theories, coupled) and a web
update of it: the web app's prediction call (``PredictionCache.predict``, as ``POST /api/predict`` and the case
page run it) for the example, then for the example with one field changed — ΔP, the viscosity of both fluids,
or the compressions — each a case the web cache has not seen (goal, issue 24: 0.3 s).
Usage: python benchmarks/bench_band.py [--repeat N] [--skip-sweep | --skip-example]
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

import sealeak.cases.band as band_module
import sealeak.cases.band_tables as tables_module
from sealeak.cases import example_path, example_text, load_cases, run_case
from sealeak.cases.seals import with_loads
from sealeak.physics.gaps import clear_caches
from sealeak.web.casework import PredictionCache


def sweep_case(model: str, fluid_pressure: str = "ignored"):
    case = load_cases(example_path("o-ring"))[0]
    assert case.band is not None
    band = with_loads(case.band, np.linspace(0.10, 0.30, 50), case.youngs_modulus, case.poisson_ratio)
    return replace(case, band=band, model=model, fluid_pressure=fluid_pressure)


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def example_and_web_update() -> None:
    """The bundled o-ring example (cold, then again with its P(u) kept), and the web app's prediction call for it and
    for three edits of it."""
    cases = load_cases(example_path("o-ring"))
    clear_caches()
    print(f"o-ring example (2 fluids x 9 compressions, both theories, coupled): cold {timed(lambda: [run_case(c) for c in cases]):.2f} s, "
          f"again {timed(lambda: [run_case(c) for c in cases]):.2f} s")
    text = example_text("o-ring")
    edits = {"pressure difference 1 -> 2 bar": ('pressure_difference = "1 bar"', 'pressure_difference = "2 bar"'),
             "viscosities x 1.5": ('"1 mPa*s"', '"1.5 mPa*s"'),
             "compressions 10-30 % -> 12-32 %": ('start = "10 %", stop = "30 %"', 'start = "12 %", stop = "32 %"')}
    with tempfile.TemporaryDirectory() as folder:
        web = PredictionCache()
        clear_caches()
        first = timed(lambda: web.predict(text.encode(), "o-ring.toml", Path(folder)))
        print(f"web: the o-ring example, nothing kept: {first:.2f} s")
        for name, (old, new) in edits.items():
            assert old in text, old
            changed = text.replace(old, new).encode()
            print(f"web update, {name}: {timed(lambda: web.predict(changed, 'o-ring.toml', Path(folder))):.2f} s")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skip-sweep", action="store_true", help="only the bundled example and its web update")
    ap.add_argument("--skip-example", action="store_true", help="only the 50-compression sweeps")
    args = ap.parse_args()
    print(f"{platform.processor() or platform.machine()}, {time.strftime('%Y-%m-%d')}")
    if args.skip_sweep:
        example_and_web_update()
        return
    counts = {"cj": 0, "em": 0}
    cj, em = band_module.critical_junction, tables_module.effective_medium

    def count_cj(*a, **k):
        counts["cj"] += np.size(k["squeeze_pressure"])
        return cj(*a, **k)

    def count_em(*a, **k):
        counts["em"] += np.size(k["squeeze_pressure"])
        return em(*a, **k)

    band_module.critical_junction = tables_module.critical_junction = count_cj
    tables_module.effective_medium = count_em
    runs = (("critical-junction", "ignored"), ("both", "ignored"), ("critical-junction", "coupled"), ("both", "coupled"))
    for model, fluid_pressure in runs:
        case = sweep_case(model, fluid_pressure)
        best = cpu = float("inf")
        for _ in range(args.repeat):
            counts.update(cj=0, em=0)
            clear_caches()
            t, c = time.perf_counter(), time.process_time()
            res = band_module.run_band(case)
            best, cpu = min(best, time.perf_counter() - t), min(cpu, time.process_time() - c)
        nodes = res.critical_junction.evaluations
        print(f"{model:18s} fluid pressure {fluid_pressure:8s} 50 loads: {best:.2f} s (CPU {cpu:.2f} s)  "
              f"(critical-junction pressures {counts['cj']}, effective-medium pressures {counts['em']}; σ evaluations per load {nodes.min()}-{nodes.max()}; "
              f"largest estimated relative error {np.nanmax(res.critical_junction.change):.1e})")
    band_module.critical_junction = tables_module.critical_junction = cj
    tables_module.effective_medium = em
    if not args.skip_example:
        example_and_web_update()


if __name__ == "__main__":
    main()
