"""Independent reference implementations for the tests (adaptive quadrature, no shared code paths).

Nothing here uses sealeak's closed forms, its K(y) table or its panel quadrature: integrals are
computed with scipy.integrate.quad directly from the definitions in docs/theory.md.
"""

from __future__ import annotations

import numpy as np
from scipy import special
from scipy.integrate import quad

QUAD = dict(epsabs=0.0, epsrel=1e-12, limit=500)


def self_affine(q, C0, q_l, q_r, q_1, H):
    """C(q) of the self-affine model, written out directly."""
    q = np.asarray(q, dtype=float)
    return np.where((q >= q_l) & (q < q_r), C0,
                    np.where((q >= q_r) & (q <= q_1), C0 * (q / q_r) ** (-2 * (1 + H)), 0.0))


def band_integral(f, a, b, kinks=()):
    """∫_a^b f(q) dq by quad in ln q, split at the kinks."""
    if b <= a:
        return 0.0
    edges = [a] + sorted(k for k in kinks if a < k < b) + [b]
    total = 0.0
    for lo, hi in zip(edges[:-1], edges[1:]):
        total += quad(lambda t: np.exp(t) * f(np.exp(t)), np.log(lo), np.log(hi), **QUAD)[0]
    return total


def inner_pressure_integral(s, p, gamma):
    """∫_p^∞ dp'/p' [γ + 3(1-γ) erf²(s p')] exp(-(s p')²), by quad in x = s p'."""
    return quad(lambda x: (gamma + 3 * (1 - gamma) * special.erf(x) ** 2) * np.exp(-x * x) / x,
                s * p, np.inf, **QUAD)[0]


class PerssonReference:
    """ū(ζ) and u1(ζ) by nested adaptive quadrature, straight from docs/theory.md § 2."""

    def __init__(self, C, q_min, q_max, kinks, e_star, q0, gamma):
        self.C, self.q_min, self.q_max, self.kinks = C, q_min, q_max, tuple(kinks)
        self.e_star, self.q0, self.gamma = e_star, q0, gamma

    def moment3(self, a, b):
        return band_integral(lambda q: q**3 * self.C(q), max(a, self.q_min), min(b, self.q_max), self.kinks)

    def G(self, zeta):
        return np.pi / 4 * self.e_star**2 * self.moment3(self.q0, zeta * self.q0)

    def area(self, zeta, p0):
        g = self.G(zeta)
        return 1.0 if g == 0 else special.erf(p0 / (2 * np.sqrt(g)))

    def ubar(self, zeta, p0):
        p = p0 / self.area(zeta, p0)
        lo = max(zeta * self.q0, self.q_min)
        # cumulative moment from lo, accumulated piecewise for accuracy near the lower limit
        def integrand(q):
            t = self.moment3(lo, q)
            if t <= 0:
                return 0.0
            w = (np.pi * t) ** -0.5
            return q**2 * self.C(q) * w * inner_pressure_integral(w / self.e_star, p, self.gamma)
        return np.sqrt(np.pi) * band_integral(integrand, lo, self.q_max, self.kinks)

    def u1(self, zeta, p0, h=2e-3):
        """u1 = ū + ū' A/A' with ū' and A' by Richardson-extrapolated central differences."""
        def deriv(f):
            d1 = (f(zeta * (1 + h)) - f(zeta * (1 - h))) / (2 * zeta * h)
            d2 = (f(zeta * (1 + h / 2)) - f(zeta * (1 - h / 2))) / (zeta * h)
            return (4 * d2 - d1) / 3
        du = deriv(lambda z: self.ubar(z, p0))
        da = deriv(lambda z: self.area(z, p0))
        return self.ubar(zeta, p0) + du * self.area(zeta, p0) / da


def loglog_table(q_nodes, c_nodes):
    """C(q) of a table, interpolated linearly in log C against log q (zero outside), written out directly."""
    lq = np.log(np.asarray(q_nodes, dtype=float))
    lc = np.log(np.asarray(c_nodes, dtype=float))

    def C(q):
        x = np.log(q)
        if x < lq[0] or x > lq[-1]:
            return 0.0
        return float(np.exp(np.interp(x, lq, lc)))

    return C
