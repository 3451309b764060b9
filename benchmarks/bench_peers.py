"""Optional peer comparison of sealeak.numerics.solve_contact with tamaas and ContactMechanics.

Usage: python benchmarks/bench_peers.py [--timeout S] [N ...]   (default N = 256 512 1024, S = 400)

The same problem for every code: the rigid periodic rough surface h = _common.surface(N) (heights,
side SIZE) pressed on an elastic half-space of contact modulus E_STAR at the mean pressure
P0 = _common.pressure_for(sp, fraction), fractions 0.1 and 0.4, frictionless, non-adhesive,
periodic. Each (N, fraction, code) runs in a fresh subprocess limited to S seconds ("timeout").
Per row: seconds of the solve (set-up of the elastic kernel included; imports and surface
synthesis not), relative contact area A/A0 (fraction of cells with pressure > 0), mean gap over
the whole cell (contact cells included, interpenetration below the tolerance clipped to 0, as
sealeak reports it) and the peer's relative difference (peer - sealeak) / sealeak of both. A peer
that cannot be imported prints "<code> not installed: skipped"; one that raises or does not
converge "FAILED: ...".

Conventions, checked on 128², 256² and 512² (contact areas identical but for one cell of 512²
at 40 %, mean gaps within 5e-8 relative):

* tamaas 2.9: ModelFactory.createModel(basic_2d, [L, L], [N, N]) with E = E*, nu = 0 (tamaas'
  pressure unit is E/(1-nu²)); the surface is the rigid body's heights (summits positive), as in
  sealeak; PolonskyKeerRey(model, h, tol).solve(P0) prescribes the MEAN pressure; afterwards
  model.displacement is shifted so that gap = displacement - h is >= 0 and 0 in contact.
* ContactMechanics 1.8: PeriodicFFTElasticHalfSpace(young=E*, poisson left at 0, where ``young``
  is the contact modulus); heights as in sealeak (gap = u - (h + offset)); the constrained
  conjugate gradients (Polonsky-Keer) take external_force = TOTAL force P0 L² and return pixel
  forces (pressure = force / (L/N)²); its FFT comes from muGrid (older releases used muFFT).

Tolerances (all 1e-8, comparable): sealeak's default residual (rms gap on the contact set and
interpenetration / h_rms, and mean(p|g|) / (P0 h_rms)); tamaas' PolonskyKeerRey error (a relative
complementarity error: on these surfaces within a factor ~5 of sealeak's second measure);
ContactMechanics pentol = 1e-8 h_rms (rms and max penetration), forcetol = 1e-8 P0 (L/N)² (largest
tensile pixel force) and thermotol = 1e-8. The peers get at most 20000 iterations. Threads: each
code's default (sealeak's scipy.fft uses all cores; the tamaas and muGrid wheels run on one).

The peers are sealeak's optional `bench` extra (tamaas is AGPL-3.0 and ContactMechanics brings its
own dependencies, so they are never installed by default): `make bench-peers` installs the extra
into .venv and runs this script at 256², 512² and 1024²; by hand:

    .venv/bin/pip install -e '.[bench]'
    .venv/bin/python benchmarks/bench_peers.py 1024

Without them the peers are reported as skipped and only the sealeak rows are printed.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

FRACTIONS = (0.1, 0.4)
CODES = ("sealeak", "tamaas", "ContactMechanics")
PEERS = CODES[1:]
TOL = 1e-8
PEER_MAX_ITER = 20000


def probe(code: str) -> dict:
    """Whether ``code`` (with its FFT back-end) can be imported."""
    try:
        if code == "tamaas":
            import tamaas  # noqa: F401
        else:
            import ContactMechanics  # noqa: F401
            from ContactMechanics import PeriodicFFTElasticHalfSpace, make_system  # noqa: F401
            from SurfaceTopography import Topography  # noqa: F401
    except Exception as exc:  # ImportError, or a missing shared library (OSError)
        return dict(ok=False, error=f"{type(exc).__name__}: {exc}")
    return dict(ok=True)


def sealeak_solver():
    from sealeak.numerics import solve_contact

    def solve(h, size: float, e_star: float, p0: float) -> tuple[float, float]:
        res = solve_contact(h, size, e_star, p0, tol=TOL)
        return res.contact_area, res.mean_gap

    return solve


def tamaas_solver():
    import numpy as np
    import tamaas as tm

    tm.set_log_level(tm.LogLevel.warning)  # no per-iteration output

    def solve(h, size: float, e_star: float, p0: float) -> tuple[float, float]:
        n = h.shape[0]
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [size, size], [n, n])
        model.E, model.nu = e_star, 0.0  # then E* = E / (1 - nu²) = e_star
        solver = tm.PolonskyKeerRey(model, np.ascontiguousarray(h), TOL)
        solver.max_iter = PEER_MAX_ITER
        error = solver.solve(p0)  # mean pressure
        if not error <= TOL:
            raise RuntimeError(f"tamaas not converged: error {error:.3g} > {TOL:g} "
                               f"(max_iter {PEER_MAX_ITER})")
        p = np.asarray(model.traction).reshape(n, n)
        gap = np.asarray(model.displacement).reshape(n, n) - h  # the solver shifted u: gap >= 0
        if abs(float(p.mean()) / p0 - 1) > 1e-6:
            raise RuntimeError(f"tamaas mean pressure {float(p.mean()):.6g} Pa != {p0:.6g} Pa")
        return float(np.count_nonzero(p > 0)) / p.size, float(np.maximum(gap, 0.0).mean())

    return solve


def contactmechanics_solver():
    import numpy as np
    from ContactMechanics import PeriodicFFTElasticHalfSpace, make_system
    from SurfaceTopography import Topography

    def solve(h, size: float, e_star: float, p0: float) -> tuple[float, float]:
        n = h.shape[0]
        substrate = PeriodicFFTElasticHalfSpace((n, n), e_star, physical_sizes=(size, size))  # nu = 0: E*
        system = make_system(substrate=substrate,
                             surface=Topography(h, physical_sizes=(size, size), periodic=True))
        pixel = (size / n) ** 2
        h_rms = float(np.std(h))
        res = system.minimize_proxy(external_force=p0 * size * size,  # TOTAL force
                                    pentol=TOL * h_rms, forcetol=TOL * p0 * pixel, thermotol=TOL,
                                    maxiter=PEER_MAX_ITER)
        if not res.success:
            raise RuntimeError(f"ContactMechanics not converged: {res.message}")
        force = np.asarray(system.force)  # pixel forces, compressive > 0
        if abs(float(force.sum()) / (p0 * size * size) - 1) > 1e-6:
            raise RuntimeError(f"ContactMechanics total force {float(force.sum()):.6g} N "
                               f"!= {p0 * size * size:.6g} N")
        gap = system.compute_gap(res.x, res.offset)  # u - (h + offset)
        return float(system.compute_relative_contact_area()), float(np.maximum(gap, 0.0).mean())

    return solve


SOLVERS = {"sealeak": sealeak_solver, "tamaas": tamaas_solver, "ContactMechanics": contactmechanics_solver}


def one(code: str, n: int, fraction: float) -> dict:
    from _common import E_STAR, SIZE, pressure_for, surface

    h, sp = surface(n)
    p0 = pressure_for(sp, fraction)
    try:
        solve = SOLVERS[code]()  # imports outside the timing
        t = time.perf_counter()
        area, mean_gap = solve(h, SIZE, E_STAR, p0)
        sec = time.perf_counter() - t
    except Exception as exc:
        return dict(status="failed", error=f"{type(exc).__name__}: {exc}")
    return dict(status="ok", seconds=sec, area=area, mean_gap=mean_gap)


def run_case(code: str, n: int, fraction: float, timeout: float) -> dict:
    try:
        out = subprocess.run([sys.executable, __file__, "--case", code, str(n), str(fraction)],
                             capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return dict(status="timeout")
    lines = out.stdout.strip().splitlines()
    try:
        return json.loads(lines[-1])
    except (IndexError, json.JSONDecodeError):
        err = (out.stderr.strip().splitlines() or ["no output"])[-1]
        return dict(status="failed", error=f"exit code {out.returncode}: {err}")


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--case":
        print(json.dumps(one(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]))))
        return
    if len(sys.argv) == 3 and sys.argv[1] == "--probe":
        print(json.dumps(probe(sys.argv[2])))
        return
    ap = argparse.ArgumentParser(description="Compare sealeak's contact solver with tamaas and ContactMechanics.")
    ap.add_argument("sizes", nargs="*", type=int, default=[256, 512, 1024], metavar="N")
    ap.add_argument("--timeout", type=float, default=400.0, metavar="S", help="seconds per case (default 400)")
    args = ap.parse_args()

    codes = ["sealeak"]
    for peer in PEERS:
        out = subprocess.run([sys.executable, __file__, "--probe", peer], capture_output=True, text=True)
        try:
            r = json.loads(out.stdout.strip().splitlines()[-1])
        except (IndexError, json.JSONDecodeError):
            r = dict(ok=False, error=f"import check exited with code {out.returncode}")
        if r["ok"]:
            codes.append(peer)
        else:
            missing = f"No module named '{peer}'" in r["error"]
            print(f"{peer} not installed: skipped" + ("" if missing else f" ({r['error']})"), flush=True)

    print(f"{'N':>6} {'target':>6} {'code':<16} {'seconds':>8} {'A/A0':>8} {'mean gap m':>11} "
          f"{'dA rel':>9} {'dgap rel':>9}", flush=True)
    for n in args.sizes:
        for f in FRACTIONS:
            ref = None
            for code in codes:
                r = run_case(code, n, f, args.timeout)
                head = f"{n:>6} {f:>6.2f} {code:<16}"
                if r["status"] == "timeout":
                    print(f"{head} timeout (> {args.timeout:g} s)", flush=True)
                    continue
                if r["status"] != "ok":
                    print(f"{head} FAILED: {r['error']}", flush=True)
                    continue
                if code == "sealeak":
                    ref = r
                    diff = f"{'-':>9} {'-':>9}"
                elif ref is None:
                    diff = f"{'n/a':>9} {'n/a':>9}"
                else:
                    diff = (f"{(r['area'] - ref['area']) / ref['area']:>+9.1e} "
                            f"{(r['mean_gap'] - ref['mean_gap']) / ref['mean_gap']:>+9.1e}")
                print(f"{head} {r['seconds']:>8.2f} {r['area']:>8.5f} {r['mean_gap']:>11.5e} {diff}", flush=True)


if __name__ == "__main__":
    main()
