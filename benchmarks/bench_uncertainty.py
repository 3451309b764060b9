"""Benchmark of the uncertainty propagation (``predict --samples``): wall time of one band of percentiles.

Cases (the issue's goals in brackets):

* a uniform seal: the ``hrms-study`` example's first case with h_rms = "… ± 10 %" and α uniform on
  [0.5, 1.5], 512 Sobol' samples [≤ 2 s]: the samples take the nominal contact at scaled pressures
  (docs/theory.md §14.5, eqs. 14.6–14.7);
* the same seal with α and the viscosity uncertain only: the samples share the nominal contact (Q ∝ α/η);
* the O-ring of the ``o-ring`` example (water, critical junction), h_rms ± 10 %, 256 samples [≤ 30 s]: one band
  prediction per sample, its σ from the nominal contact's tables at the scaled pressures (docs/theory.md eq. 14.8);
* the same O-ring with α ± 20 % only (shared contact);
* the O-ring of the ``helium-test`` example (helium against vacuum, kinetic slit, the gas pressure coupled: every
  sample solves eq. 13.7 of docs/theory.md per load), h_rms ± 10 %, 256 samples (no goal set).

Run: .venv/bin/python benchmarks/bench_uncertainty.py [--quick] [--only=TEXT]   (single-threaded NumPy; --only: the
cases whose name contains TEXT)
"""

from __future__ import annotations

import os
import platform
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from sealeak.cases import example_text  # noqa: E402
from sealeak.cases.uncertainty import parse_uncertain_case, propagate  # noqa: E402


def cases() -> dict[str, tuple[str, int]]:
    hrms = example_text("hrms-study").split("[study]")[0]
    helium = example_text("helium-test")
    oring = example_text("o-ring").split("[study]")[0].replace('model = "both"', 'model = "critical-junction"')
    return {
        "uniform seal, h_rms ± 10 % and α, 512": (_hrms(hrms, spread=True), 512),
        "uniform seal, α and η only (shared contact), 512": (_hrms(hrms, spread=False), 512),
        "O-ring, h_rms ± 10 %, 256": (oring.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"'), 256),
        "O-ring, α ± 20 % only (shared contact), 256": (oring.replace("alpha = 1.0", 'alpha = "1.0 ± 0.2"'), 256),
        "helium test O-ring, h_rms ± 10 %, 256": (helium.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"'), 256),
    }


def _hrms(text: str, spread: bool) -> str:
    line = next(ln for ln in text.splitlines() if ln.startswith("h_rms"))
    value = line.split("=", 1)[1].strip().strip('"')
    out = text.replace(line, f'h_rms = "{value} ± 10 %"') if spread else text
    viscosity = next(ln for ln in out.splitlines() if ln.startswith("viscosity"))
    eta = viscosity.split("=", 1)[1].strip().strip('"')
    out = out.replace(viscosity, f'viscosity = "{eta} ± 10 %"') if not spread else out
    return out + '\n[uncertainty]\n"theory.alpha" = { distribution = "uniform", low = 0.5, high = 1.5 }\n'


def main(argv: list[str]) -> int:
    quick = "--quick" in argv
    only = next((a.split("=", 1)[1] for a in argv if a.startswith("--only=")), "")
    print(f"sealeak uncertainty benchmark: {platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d')}")
    for name, (text, n) in cases().items():
        if only not in name:
            continue
        n = min(n, 32) if quick else n
        study = parse_uncertain_case(text)
        t, cpu = time.perf_counter(), time.process_time()
        propagate(study, n, seed=0)
        dt, dcpu = time.perf_counter() - t, time.process_time() - cpu
        print(f"  {name:52s} {n:4d} samples  wall {dt:7.2f} s  CPU {dcpu:7.2f} s  ({1e3 * dcpu / n:.1f} ms CPU per sample)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
