"""Benchmark of the critical-junction prediction (plain script; prints a table).

Cases: the reference-experiment ring (self-affine sandpaper stand-in), 200 squeeze pressures from
10 kPa to 300 kPa, for γ = 1 and γ = 0.42; the full u1(ζ) curve on 200 magnifications; the same
sweep on a 200-point tabulated spectrum; and, for scale, a scalar implementation with scipy's
adaptive `quad` per pressure (the nested integral of THEORY.md, E1/K closed forms not used),
timed on a few pressures and extrapolated to 200.

Run: .venv/bin/python benchmarks/bench_predict.py   (single-threaded NumPy: set OMP_NUM_THREADS=1)
"""

from __future__ import annotations

import os
import platform
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy import special  # noqa: E402
from scipy.integrate import quad  # noqa: E402

from sealeak import PowerSpectrum  # noqa: E402
from sealeak.cases import (  # noqa: E402
    example_path,
    load_case,
    predict,  # noqa: E402
)
from sealeak.physics import PerssonContact  # noqa: E402


def best_of(fn, repeat=7):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def scalar_quad_u1(contact: PerssonContact, p0: float, pc: float = 0.6) -> float:
    """u_c by adaptive quad per pressure (as a straightforward implementation would)."""
    zc = float(contact.zeta_at_area(1 - pc, p0)[0])
    s, e, g = contact.spectrum, contact.e_star, contact.gamma

    def ubar(z):
        p = p0 / float(contact.area(z, p0))
        lo = z * contact.q0
        m_lo = float(s.cumulative_moment(3, lo))

        def f(q):
            t = float(s.cumulative_moment(3, q)) - m_lo
            if t <= 0:
                return 0.0
            w = (np.pi * t) ** -0.5
            inner = quad(lambda x: (g + 3 * (1 - g) * special.erf(x) ** 2) * np.exp(-x * x) / x,
                         w * p / e, np.inf, epsrel=1e-8)[0]
            return q**2 * float(s(q)) * w * inner
        return np.sqrt(np.pi) * quad(f, lo, s.q_max, epsrel=1e-8, limit=200, points=list(s.q[1:-1]))[0]

    h = 1e-4 * zc
    du = (ubar(zc + h) - ubar(zc - h)) / (2 * h)
    a = float(contact.area(zc, p0))
    da = float(contact.area_derivative(zc, p0))
    return ubar(zc) + du * a / da


def main() -> None:
    case = load_case(example_path("reference-experiment"))
    p0 = np.geomspace(1e4, 3e5, 200)
    rows = []
    for gamma in (1.0, 0.42):
        c = case.__class__(**{**case.__dict__, "gamma": gamma})
        t = best_of(lambda: predict(c, squeeze_pressure=p0))
        rows.append((f"200-pressure sweep, γ = {gamma:g}", t))
        contact = c.contact()
        z = np.geomspace(1.0, contact.zeta_max, 202)[1:-1]
        t = best_of(lambda: contact.u1(z, 6e4))
        rows.append((f"u1(ζ) on 200 ζ, γ = {gamma:g}", t))
    q = np.geomspace(case.spectrum.q_min, case.spectrum.q_max, 200)
    table = PowerSpectrum.from_arrays(q, case.spectrum(q))
    ct = case.__class__(**{**case.__dict__, "spectrum": table, "gamma": 0.42})
    rows.append(("200-pressure sweep, 200-point table, γ = 0.42", best_of(lambda: predict(ct, squeeze_pressure=p0))))
    for gamma in (1.0, 0.42):
        contact = PerssonContact(case.spectrum, case.e_star, case.q0, gamma)
        few = p0[::50]
        t = time.perf_counter()
        for p in few:
            scalar_quad_u1(contact, float(p))
        per = (time.perf_counter() - t) / few.size
        rows.append((f"scalar quad per pressure (x200, extrapolated), γ = {gamma:g}", per * 200))

    print(f"sealeak critical-junction benchmark — {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}, NumPy {np.__version__}, "
          f"{time.strftime('%Y-%m-%d')}")
    print(f"{'case':62s} {'time':>10s}")
    for name, t in rows:
        print(f"{name:62s} {t * 1e3:8.1f} ms")


if __name__ == "__main__":
    main()
