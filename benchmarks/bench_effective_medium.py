"""Benchmark of the effective-medium theory per squeeze pressure (plain script; prints a table).

sealeak.physics.effective_medium.effective_medium at 1, 9 and 33 squeeze pressures (one call each; 33 is
the largest σ_eff(p) table a band seal builds per load), for four contacts: the reference-experiment
ring, a self-affine surface with γ = 0.42, a 30-node tabulated spectrum and the bundled O-ring on steel.
CPU time (best of 5, each run cold: the P(u) kept for reuse forgotten first) per pressure; with ``--against REV``
the same in the source tree of git revision REV (exported to a temporary folder), and the largest relative
difference of σ_eff between the two.

Run: .venv/bin/python benchmarks/bench_effective_medium.py [--against REV]   (single-threaded NumPy)

Results (CPU ms per pressure, best of 5; AMD EPYC, 2 CPUs (KVM), Python 3.11.7, NumPy 2.4.6; 2026-11-23 22:35,
load average 2.5-3.3 from other jobs, so ±20 %):

    contact                  pressures   after   before (f07a4c4)   speed-up   max |Δσ|/σ
    reference experiment          1      15.8         52.8            3.3x       0
    reference experiment         33       9.1         38.4            4.2x       4.6e-11
    self-affine, γ = 0.42        33      10.7         52.8            4.9x       1.4e-12
    tabulated, 30 nodes          33      16.8         67.6            4.0x       3.2e-13
    o-ring on steel              33       9.9         40.0            4.1x       1.2e-11

(Δσ above 1e-12 comes from the upper cut point of P(u), which the old code set from rounding noise; see
sealeak.physics.effective_medium.) Where the time goes now, per pressure (reference experiment): the
separation integrals u1(ζ) at ~900 ζ-nodes × ~85 quadrature points, ~5 ms (about 50 ns per point: five
exponential-type evaluations, NumPy-bound); the mixture's density at ~700 nodes (~70 000 Gaussian terms
left after the series), its CDF and cut points, ~2.5 ms; the rest ~1 ms.

The cost before was PerssonContact.u1 (scipy.special.exp1 per point, the generic inverse moment),
the plain mixture sums of P(u) and the 80-step bisections of its cut points; see the module
docstrings of sealeak.physics.contact and sealeak.physics.effective_medium for what replaced them.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
SIZES = (1, 9, 33)


def measure() -> dict:
    """Run in a fresh interpreter whose sealeak is the tree under test: CPU seconds and σ_eff per case."""
    import numpy as np

    from sealeak import PowerSpectrum
    from sealeak.cases import example_path, load_cases
    from sealeak.physics.contact import PerssonContact, contact_modulus
    from sealeak.physics.effective_medium import effective_medium

    try:  # P(u) kept for reuse (since 2026-11-26): every timed run starts cold
        from sealeak.physics.gaps import clear_caches
    except ImportError:  # an older tree (--against) keeps nothing
        def clear_caches() -> None:
            pass

    case = load_cases(example_path("reference-experiment"))[0]
    e_star = contact_modulus(2.3e6, 0.5)
    q0 = 2 * np.pi / 5e-3
    rough = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=2 * np.pi / 20e-6, q_lowest=q0, h_rms=44e-6)
    q = np.geomspace(1e3, 3e5, 30)
    table = PowerSpectrum.from_arrays(q, 1e-17 / (1 + (q / 1e4) ** 2) ** 1.6 * np.exp(-((np.log(q / 3e4)) ** 2) / 8))
    # the contact of the bundled o-ring example at one compression (ground steel, NBR 70, q0 = 2π/contact width),
    # over the pressures of its σ(p) table (p_max·1e-3 .. p_max)
    steel = PowerSpectrum.self_affine(hurst=0.8, rolloff_wavelength=100e-6, cutoff_wavelength=10e-9, q_lowest=2398.16, h_rms=1.5e-6)
    contacts = {"reference experiment": (case.contact(), (1e4, 3e5)),
                "self-affine, γ = 0.42": (PerssonContact(rough, e_star, q0, 0.42), (1e4, 3e5)),
                "tabulated, 30 nodes": (PerssonContact(table, e_star, 2 * np.pi / 4e-3), (1e4, 3e5)),
                "o-ring on steel": (PerssonContact(steel, 7.36e6, 5487.5), (626.0, 6.26e5))}
    out: dict = {}
    for name, (contact, (lo, hi)) in contacts.items():
        for n in SIZES:
            p0 = np.geomspace(lo, hi, n) if n > 1 else np.array([np.sqrt(lo * hi)])

            def run():
                return effective_medium(contact, squeeze_pressure=p0, pressure_difference=1e3, viscosity=1e-3, aspect_ratio=1.0)

            run()
            best = float("inf")
            for _ in range(5):
                clear_caches()
                t = time.process_time()
                res = run()
                best = min(best, time.process_time() - t)
            out[f"{name}|{n}"] = {"seconds": best, "sigma": res.effective_conductivity.tolist()}
    return out


def run_tree(src: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src))
    done = subprocess.run([sys.executable, __file__, "--measure"], env=env, capture_output=True, text=True, check=True,
                          cwd=tempfile.gettempdir())
    return json.loads(done.stdout.strip().splitlines()[-1])


def export(rev: str, into: Path) -> Path:
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", rev, "src"], capture_output=True, check=True).stdout
    path = into / "tree.tar"
    path.write_bytes(archive)
    with tarfile.open(path) as tar:
        tar.extractall(into, filter="data")
    return into / "src"


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (f"{cpu}, {os.cpu_count()} CPUs, Python {platform.python_version()}, {platform.system()}; "
            f"load average {load:.1f}; {datetime.datetime.now().isoformat(timespec='minutes')}")


def main() -> None:
    if sys.argv[1:] == ["--measure"]:
        print(json.dumps(measure()))
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", metavar="REV", help="also time git revision REV (f07a4c4: the code before the speed-up)")
    args = parser.parse_args()
    print(machine())
    now = run_tree(ROOT / "src")
    before = None
    if args.against:
        with tempfile.TemporaryDirectory() as tmp:
            before = run_tree(export(args.against, Path(tmp)))
    head = f"{'contact':24s} {'pressures':>9s} {'ms/pressure':>12s}"
    if before:
        head += f" {args.against + ' ms/p':>14s} {'speed-up':>9s} {'max |Δσ|/σ':>11s}"
    print(head)
    for key, row in now.items():
        name, n = key.split("|")
        line = f"{name:24s} {n:>9s} {1e3 * row['seconds'] / int(n):12.2f}"
        if before:
            old = before[key]
            sigma, ref = row["sigma"], old["sigma"]
            rel = max((abs(a - b) / abs(b) for a, b in zip(sigma, ref) if b), default=0.0)
            line += f" {1e3 * old['seconds'] / int(n):14.2f} {old['seconds'] / row['seconds']:8.1f}x {rel:11.1e}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
