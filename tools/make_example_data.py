"""Make the bundled example data files ``src/sealeak/examples/*-measured.csv``.

No published data set comes with the leak rates these examples need, so the data files that
``sealeak fit`` is shown with are synthetic, each made from a bundled case's own prediction:

- ``reference-measured.csv``: the critical-junction prediction of the ``reference-experiment`` case
  (α = 0.2, ΔP = 10 kPa) at eight squeeze pressures, times log-normal scatter (standard deviation 0.15
  in ln Q, about 15 %, seed 2009). Fitting it gives α close to 0.2, not exactly.
- ``o-ring-measured.csv``: the ``o-ring`` example's ``water`` variant (O-ring 20 x 2.62 mm, NBR 70
  Shore A, on ground steel, water at ΔP = 1 bar): the band's critical-junction leak rate (strips in
  series, docs/theory.md §10.1) with α = 0.3 at five compressions, times log-normal scatter (0.2 in
  ln Q, about 20 %, seed 2019). Fitting it gives α close to 0.3, not exactly.

Every value is rounded to three significant digits, so each file is the same on every machine.

Usage (from the repository root)::

    .venv/bin/python tools/make_example_data.py           # write the files
    .venv/bin/python tools/make_example_data.py --check   # exit 1 if a bundled file differs

tests/integration/test_docs.py checks that the bundled files are what this script makes.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from sealeak.cases import example_path, load_case, load_cases, predict
from sealeak.cases.band import run_band
from sealeak.cases.seals import with_loads

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "sealeak" / "examples"
ML_MIN_PER_M3_S = 6e7


def _scatter(q: np.ndarray, sd: float, seed: int) -> np.ndarray:
    """``q`` (m³/s) in ml/min times log-normal scatter of standard deviation ``sd`` in ln Q."""
    return q * np.exp(np.random.default_rng(seed).normal(0.0, sd, q.size)) * ML_MIN_PER_M3_S


def _csv(header: Sequence[str], column: str, rows: Sequence[str]) -> str:
    return "\n".join([*(f"# {line}" for line in header), column, *rows]) + "\n"


def reference_measured_csv() -> str:
    """``reference-measured.csv``: the reference case at α = 0.2 with 15 % scatter (seed 2009)."""
    kpa, sd, seed = (20, 30, 45, 65, 95, 140, 200, 250), 0.15, 2009
    case = load_case(example_path("reference-experiment"))
    ml_min = _scatter(predict(case, squeeze_pressure=np.array(kpa, dtype=float) * 1e3).leak_rate, sd, seed)
    return _csv(["Synthetic leak-rate measurements for the bundled reference-experiment case (PDMS ring on sandpaper).",
                 "Made by tools/make_example_data.py: the critical-junction prediction with alpha = 0.2 at",
                 f"delta P = {case.pressure_difference / 1e3:g} kPa, times log-normal scatter (sd {sd} in ln Q, seed {seed}), "
                 "3 significant digits.",
                 "Try: sealeak fit --example reference-experiment --data reference-measured.csv"],
                "squeeze_pressure (kPa), leak_rate (ml/min)",
                [f"{p:g}, {float(f'{v:.3g}'):g}" for p, v in zip(kpa, ml_min, strict=True)])


def oring_measured_csv() -> str:
    """``o-ring-measured.csv``: the o-ring example's water variant at α = 0.3 with 20 % scatter (seed 2019)."""
    percent, alpha, sd, seed = (10.0, 12.5, 15.0, 17.5, 20.0), 0.3, 0.2, 2019
    case = next(c for c in load_cases(example_path("o-ring")) if c.label == "water")
    assert case.band is not None
    band = with_loads(case.band, np.array(percent) / 100.0, case.youngs_modulus, case.poisson_ratio)  # q0 = 2π/w each
    q = run_band(replace(case, band=band, alpha=alpha), effective=False).critical_junction.leak_rate  # m³/s
    if not np.isfinite(q).all():
        raise SystemExit("a compression of the example has no leak channel: choose smaller ones")
    ml_min = _scatter(q, sd, seed)
    return _csv(["Synthetic leak-rate measurements for the bundled o-ring example (water variant; O-ring 20 x 2.62 mm on steel).",
                 f"Made by tools/make_example_data.py: the band's critical-junction leak rate with alpha = {alpha:g} at",
                 f"delta P = {case.pressure_difference / 1e5:g} bar, times log-normal scatter (sd {sd} in ln Q, seed {seed}), "
                 "3 significant digits.",
                 "Try: sealeak fit --example o-ring --variant water --data o-ring-measured.csv"],
                "compression (%), leak_rate (ml/min)",
                [f"{e:g}, {float(f'{v:.3g}'):.3g}" for e, v in zip(percent, ml_min, strict=True)])


#: Each bundled data file and the function that makes its text.
FILES: dict[str, Callable[[], str]] = {"reference-measured.csv": reference_measured_csv, "o-ring-measured.csv": oring_measured_csv}


def main(argv: list[str]) -> int:
    """Write the data files, or with ``--check`` compare them with the bundled ones (exit status 1 if one differs)."""
    status = 0
    for name, make in FILES.items():
        target, text = EXAMPLES / name, make()
        if "--check" in argv:
            same = target.exists() and target.read_text(encoding="utf-8") == text
            print(f"{target}: {'up to date' if same else 'differs from what this script makes'}")
            status |= 0 if same else 1
        else:
            target.write_text(text, encoding="utf-8")
            print(f"wrote {target}")
    return status


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
