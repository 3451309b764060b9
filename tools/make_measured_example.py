"""Make the bundled example data file ``src/sealeak/examples/reference-measured.csv``.

The reference paper (Lorenz & Persson, EPL 86 (2009) 44006) does not publish its measured leak
rates, so the data file that ``sealeak fit`` is shown with is synthetic: the critical-junction
prediction of the bundled ``reference-experiment`` case (α = 0.2, ΔP = 10 kPa) at eight squeeze
pressures, multiplied by log-normal scatter (standard deviation 0.15 in ln Q, i.e. about 15 %,
seed 2009), rounded to three significant digits. Fitting it gives α close to 0.2, not exactly.

Usage (from the repository root)::

    .venv/bin/python tools/make_measured_example.py           # write the file
    .venv/bin/python tools/make_measured_example.py --check   # exit 1 if the bundled file differs

The test suite (tests/integration/test_docs.py) checks that the bundled file is what this script makes.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from sealeak.cases import example_path, load_case, predict

TARGET = Path(__file__).resolve().parents[1] / "src" / "sealeak" / "examples" / "reference-measured.csv"
SQUEEZE_PRESSURES_KPA = (20, 30, 45, 65, 95, 140, 200, 250)
SCATTER = 0.15  # standard deviation of ln Q
SEED = 2009


def measured_csv_text() -> str:
    """The text of the data file (deterministic: fixed seed, prediction rounded to 3 digits)."""
    case = load_case(example_path("reference-experiment"))
    p0 = np.array(SQUEEZE_PRESSURES_KPA, dtype=float) * 1e3
    q = predict(case, squeeze_pressure=p0).leak_rate  # m³/s
    noise = np.exp(np.random.default_rng(SEED).normal(0.0, SCATTER, p0.size))
    ml_min = q * noise * 6e7
    lines = [
        "# Synthetic leak-rate measurements for the bundled reference-experiment case (PDMS ring on sandpaper).",
        "# Made by tools/make_measured_example.py: the critical-junction prediction with alpha = 0.2 at",
        f"# delta P = {case.pressure_difference / 1e3:g} kPa, times log-normal scatter (sd {SCATTER} in ln Q, "
        f"seed {SEED}), 3 significant digits.",
        "# Try: sealeak fit --example reference-experiment --data reference-measured.csv",
        "squeeze_pressure (kPa), leak_rate (ml/min)",
    ]
    lines += [f"{p:g}, {float(f'{v:.3g}'):g}" for p, v in zip(SQUEEZE_PRESSURES_KPA, ml_min)]
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
