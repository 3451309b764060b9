"""Make the bundled example data file ``src/sealeak/examples/o-ring-measured.csv``.

Synthetic leak-rate measurements of the bundled ``o-ring`` example (its ``water`` variant: an
O-ring 20 x 2.62 mm, NBR 70 Shore A, on ground steel, water at ΔP = 1 bar): the critical-junction
leak rate of the band (strips in series, docs/theory.md §10.1) with α = 0.3 at five compressions,
multiplied by log-normal scatter (standard deviation 0.2 in ln Q, about 20 %, seed 2019), rounded to
three significant digits. Fitting it gives α close to 0.3, not exactly.

Usage (from the repository root)::

    .venv/bin/python tools/make_oring_measured_example.py           # write the file
    .venv/bin/python tools/make_oring_measured_example.py --check   # exit 1 if the bundled file differs

tests/integration/test_cli_band_lab.py checks that the bundled file is what this script makes.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from sealeak.cases import example_path, load_cases
from sealeak.cases.band import run_band
from sealeak.cases.seals import with_loads

TARGET = Path(__file__).resolve().parents[1] / "src" / "sealeak" / "examples" / "o-ring-measured.csv"
VARIANT = "water"
COMPRESSIONS_PERCENT = (10.0, 12.5, 15.0, 17.5, 20.0)
ALPHA = 0.3
SCATTER = 0.2  # standard deviation of ln Q
SEED = 2019


def measured_csv_text() -> str:
    """The text of the data file (deterministic: fixed seed, prediction rounded to 3 digits)."""
    case = next(c for c in load_cases(example_path("o-ring")) if c.label == VARIANT)
    assert case.band is not None
    eps = np.array(COMPRESSIONS_PERCENT) / 100.0
    band = with_loads(case.band, eps, case.youngs_modulus, case.poisson_ratio)  # q0 = 2π/w per compression
    q = run_band(replace(case, band=band, alpha=ALPHA), effective=False).critical_junction.leak_rate  # m³/s
    if not np.isfinite(q).all():
        raise SystemExit("a compression of the example has no leak channel: choose smaller ones")
    noise = np.exp(np.random.default_rng(SEED).normal(0.0, SCATTER, eps.size))
    ml_min = q * noise * 6e7
    lines = [
        "# Synthetic leak-rate measurements for the bundled o-ring example (water variant; O-ring 20 x 2.62 mm on steel).",
        "# Made by tools/make_oring_measured_example.py: the band's critical-junction leak rate with alpha = "
        f"{ALPHA:g} at",
        f"# delta P = {case.pressure_difference / 1e5:g} bar, times log-normal scatter (sd {SCATTER} in ln Q, seed {SEED}), "
        "3 significant digits.",
        "# Try: sealeak fit --example o-ring --variant water --data o-ring-measured.csv",
        "compression (%), leak_rate (ml/min)",
    ]
    lines += [f"{e:g}, {float(f'{v:.3g}'):.3g}" for e, v in zip(COMPRESSIONS_PERCENT, ml_min)]
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> int:
    """Write the data file, or with ``--check`` compare it with the bundled one (exit status 1 if it differs)."""
    text = measured_csv_text()
    if "--check" in argv:
        same = TARGET.exists() and TARGET.read_text(encoding="utf-8") == text
        print(f"{TARGET}: {'up to date' if same else 'differs from what this script makes'}")
        return 0 if same else 1
    TARGET.write_text(text, encoding="utf-8")
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
