"""Leak rate by effective-medium theory: 2D Bruggeman flow conductivity of the gap distribution P(u).

docs/theory.md §5.2–§5.5 (Bruggeman, Ann. Phys. (Leipzig) 416 (1935) 636; Lorenz & Persson, Eur. Phys. J. E 31
(2010) 159). Where the surfaces are apart by u the fluid flows as between parallel plates,
with local conductivity σ(u) = u³/(12η) (flow per unit width per unit pressure gradient); where they
touch, σ = 0. The isotropic 2D Bruggeman effective conductivity σ_eff of that random mixture solves::

    1/σ_eff = ∫ du P(u) 2/(σ_eff + σ(u))        (the δ(u) contact part contributes 2 A(ζ1)/(A0 σ_eff))

and the leak rate of the seal (Ly/Lx squares in parallel) is Q = (Ly/Lx) σ_eff ΔP. No fit factor
enters (α of the critical-junction theory has no counterpart here; :mod:`sealeak.lab.fitting` can still
fit a factor that multiplies this prediction).

Percolation. Multiplying by σ_eff, the equation reads g(σ_eff) = 1 with
g(σ) = ∫ P(u) 2σ/(σ + σ(u)) du, which rises monotonically from 2 A(ζ1)/A0 (σ → 0) to 2 (σ → ∞): a
positive root exists if and only if A(ζ1)/A0 < 1/2. So plain 2D Bruggeman puts the percolation
threshold of the non-contact area at A/A0 = 0.5, while numerically exact studies of self-affine
contacts find that the non-contact area stops percolating near A/A0 ≈ 0.42 (Wang & Müser, Tribol.
Lett. 2020: 0.415; Dapp et al., PRL 108 (2012) 244301); the critical-junction theory uses
A/A0 = 1 - p_c (0.4 by default). Between these thresholds the two theories disagree on whether
the seal leaks at all.

A single gap value u with contact fraction a gives σ_eff = σ(u)(1 - 2a) for a < 1/2 and 0 beyond.

How it is solved
----------------
The continuous part of P(u) (a mixture of folded Gaussians, :mod:`sealeak.physics.gaps`) is discretised on
Gauss–Legendre nodes in ln u (8 per panel), on panels no wider than 0.25 between the 1e-10 and 1 - 1e-13 quantiles,
each squeeze pressure its own (σ_eff within ~3e-8 of panels 8× narrower; 0.5 left σ_eff up to 3e-4 off at a few Pa,
where P(u) has features narrower than a panel, tests/unit/test_effective_medium.py); each panel's
weights are rescaled so the panel holds exactly its mass from the closed-form mixture CDF (so
the discrete distribution integrates to one to rounding), the mass below (above) the range sits
at its lower (upper) end. The upper cut point is where 1 - CDF, summed as Σ W P(|X| > u), reaches 1e-13 of
the continuous mass (computed as mass - CDF, that level is rounding noise, which moves the cut by up to a
few per cent and σ_eff by up to ~5e-11). The mixture's density and CDF are summed without visiting every
(component, u) pair (:class:`_Mixture`: closed forms only where they differ from 0, 1 and from a Taylor
series in u; the same values to ~1e-15), the lower cut point by Newton's method, the upper one by bisection
over the components' own quantile points and then regula falsi (docs/theory.md §5.5).
On that discrete distribution, with x = ln u and s = ln u_e where
σ(u_e) = σ_eff, g(s) = 2A(ζ1)/A0 + Σ_j W_j 2/(1 + e^(3(x_j - s))), monotone in s; a vectorised
Newton iteration with a bisection bracket (all pressures at once) solves g(s) = 1 until the
relative residual |1 - g| is below 1e-12 (σ_eff to ~1e-12 relative).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ..errors import ConvergenceError, InputError
from ..io.quantities import quantity
from ._kernels import gauss_legendre
from .contact import PerssonContact
from .critical_junction import _pressures
from .gaps import ArrayCache, GapDistribution, contact_key, folded_normal_cdf, gap_distribution
from .validity import no_channel_note

__all__ = ["EffectiveMediumResult", "effective_medium", "bruggeman_conductivity", "bruggeman_residual", "bruggeman_threshold",
           "discretise", "BRUGGEMAN_THRESHOLD"]

FloatArray = NDArray[np.float64]

#: Contact-area fraction at which plain 2D Bruggeman stops conducting.
BRUGGEMAN_THRESHOLD = 0.5

#: Bytes of discretised P(u) kept for reuse, by contact and the exact list of pressures discretised together.
DISCRETE_CACHE_BYTES = 32 * 2**20

_DISCRETE = ArrayCache(lambda: DISCRETE_CACHE_BYTES)


def bruggeman_threshold(contact: PerssonContact) -> float:
    """P0_B (Pa): the squeeze pressure at which A(ζ1)/A0 = erf(P0/(2√G(ζ1))) reaches :data:`BRUGGEMAN_THRESHOLD`,
    P0_B = 2 erfinv(1/2) √G(ζ1) (docs/theory.md §2.4, §5.4; σ_eff vanishes there as (1 − P0/P0_B)³, eq. 5.5)."""
    return 2.0 * float(special.erfinv(BRUGGEMAN_THRESHOLD)) * math.sqrt(float(contact.G(contact.zeta_max)))


def _g_and_slope(x: FloatArray, w: FloatArray, contact: FloatArray, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """g(s) = 2c + Σ w 2/(1+e^(3(x-s))) and dg/ds (rows: pressures)."""
    z = np.clip(3.0 * (x - s[:, None]), -700.0, 700.0)
    r = np.exp(z)
    g = 2.0 * contact + np.sum(w * 2.0 / (1.0 + r), axis=1)
    dg = np.sum(w * 6.0 * r / (1.0 + r) ** 2, axis=1)
    return g, dg


def bruggeman_conductivity(gaps: ArrayLike, weights: ArrayLike, contact_fraction: ArrayLike, viscosity: float,
                           *, rtol: float = 1e-12, max_iter: int = 200) -> tuple[FloatArray, FloatArray]:
    """2D Bruggeman σ_eff (m³/(Pa·s)) of discrete gap distributions, one per row.

    Solves 1/σ_eff = Σ_j W_j 2/(σ_eff + σ(u_j)) + 2c/σ_eff (docs/theory.md §5.3, §5.5; eqs. 5.3, 5.4).

    Parameters
    ----------
    gaps, weights:
        Shape (rows, n) (or (n,) for one distribution): gap values u_j > 0 in m and their weights.
    contact_fraction:
        Weight of u = 0 (σ = 0) per row; contact + Σ weights should be 1.
    viscosity:
        η in Pa·s; σ(u) = u³/(12η).

    Returns
    -------
    sigma_eff : ndarray
        σ_eff per row (m³/(Pa·s)); 0 where the contact fraction is >= 1/2 (no percolation in
        Bruggeman's theory).
    residual : ndarray
        Relative residual 1 - g(σ_eff) per row; NaN where σ_eff = 0.
    """
    u = np.atleast_2d(np.asarray(gaps, dtype=float))
    w = np.atleast_2d(np.asarray(weights, dtype=float))
    c = np.atleast_1d(np.asarray(contact_fraction, dtype=float)).astype(float)
    if u.shape != w.shape or c.size != u.shape[0]:
        raise InputError("gap distribution", (u.shape, w.shape, c.shape), "gaps, weights (rows × n) and one contact fraction per row")
    if not (np.isfinite(u).all() and (u > 0).all()):
        raise InputError("gaps", u[~(np.isfinite(u) & (u > 0))][0], "must be finite and > 0 (m); put contact in contact_fraction")
    if not (np.isfinite(w).all() and (w >= 0).all() and np.isfinite(c).all() and (c >= 0).all()):
        raise InputError("weights", w.tolist() if w.size < 10 else "...", "must be finite and >= 0")
    if not (np.isfinite(viscosity) and viscosity > 0):
        raise InputError("viscosity", viscosity, "must be finite and > 0")
    x = np.log(u)
    total = c + w.sum(axis=1)
    flows = (2.0 * c < total) & (w.sum(axis=1) > 0)
    rows = np.flatnonzero(flows)
    sigma = np.zeros(c.size)
    resid = np.full(c.size, np.nan)
    if rows.size:
        xr, wr, cr = x[rows], w[rows] / total[rows, None], c[rows] / total[rows]
        lo = xr.min(axis=1) - 30.0  # g(lo) ≈ 2c + 2·Σw·e^(-90·...) < 1
        hi = xr.max(axis=1) + 30.0  # g(hi) ≈ 2(1 - c) + 2c > 1
        s = np.log(np.sum(wr * np.exp(3.0 * xr), axis=1)) / 3.0  # start: u_e from <u³>
        s = np.clip(s, lo, hi)
        for _ in range(max_iter):
            g, dg = _g_and_slope(xr, wr, cr, s)
            f = g - 1.0
            lo = np.where(f < 0, s, lo)
            hi = np.where(f > 0, s, hi)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(dg > 0, f / dg, np.inf)
            new = s - step
            bad = ~np.isfinite(new) | (new <= lo) | (new >= hi)
            new = np.where(bad, 0.5 * (lo + hi), new)
            done = (np.abs(f) < rtol) | (hi - lo < 1e-14 * np.maximum(1.0, np.abs(s)))
            if done.all():
                break
            s = np.where(done, s, new)
        else:
            raise ConvergenceError(f"Bruggeman equation: no convergence in {max_iter} iterations "
                                   f"(largest residual {np.max(np.abs(f)):.3g})")
        g, _ = _g_and_slope(xr, wr, cr, s)
        sigma[rows] = np.exp(3.0 * s) / (12.0 * viscosity)
        resid[rows] = 1.0 - g
    return sigma, resid


def bruggeman_residual(gaps: ArrayLike, weights: ArrayLike, contact_fraction: ArrayLike, viscosity: float,
                       sigma: ArrayLike) -> FloatArray:
    """σ_eff [1/σ_eff - Σ_j W_j 2/(σ_eff + σ(u_j)) - 2c/σ_eff] per row (0 at the solution; dimensionless), written out directly.

    The Bruggeman equation of docs/theory.md §5.3 (eq. 5.3); gaps in m, η in Pa·s, σ_eff in m³/(Pa·s).
    """
    u = np.atleast_2d(np.asarray(gaps, dtype=float))
    w = np.atleast_2d(np.asarray(weights, dtype=float))
    c = np.atleast_1d(np.asarray(contact_fraction, dtype=float))
    s = np.atleast_1d(np.asarray(sigma, dtype=float))
    local = u**3 / (12.0 * viscosity)
    return s * (1.0 / s - np.sum(w * 2.0 / (s[:, None] + local), axis=1) - 2.0 * c / s)


_R = float(np.sqrt(80.0))  # terms with |u ∓ u1|/h beyond √80 (< e^-40 of their peak) are left out of the density
_R_TAIL = 12.0  # the upper tail 1 - CDF keeps components with u < u1 + 12 h (the rest add < 2e-33 of their weight)
_SERIES = 1.0  # the small-u series serves a component for u/h <= _SERIES/(u1/h + 3) ...
_SERIES_TERMS = 10  # ... with the terms s^0, s^2, ..., s^18 (the next one is below 2e-15 of the first there)
_SQRT2PI = float(np.sqrt(2.0 * np.pi))
_CHUNK = 8192  # (component, u) pairs evaluated together (arrays below 128 kB)
_STEPS = np.array([-8.0, -4.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 4.0, 8.0])  # u = c + t h: bisection points of the upper tail


class _Mixture:
    """The continuous part of P(u) (a mixture of folded Gaussians), prepared for fast evaluation.

    For one component (weight W, centre c = u1, width h; κ = c/h, s = u/h) the density is
    W [φ(s - κ) + φ(s + κ)]/h and the CDF Φ(s - κ) - Φ(-s - κ) (φ, Φ: standard normal density and CDF).
    Three regimes make the sums cheap without changing their value beyond rounding (docs/theory.md §5.5):

    * u >= c + √80 h: the CDF is 1 to double precision (Φ(√80) rounds to 1), the density term is left out
      (as in the plain sum, which drops terms below e^-40 of their peak); u <= c - √80 h: both are left out;
    * u/h <= 1/(κ + 3) (only for κ < √80): the even Taylor series in s, with the Hermite polynomials
      He_n (from their generating function e^(κs - s²/2) = Σ He_n(κ) sⁿ/n!, Abramowitz & Stegun ch. 22:
      e^(-s²/2) cosh(sκ) = Σ_(n even) He_n(κ) sⁿ/n!):
      density = 2W φ(κ)/h Σ_(n = 0, 2, ..., 18) He_n(κ) sⁿ/n!,  CDF = 2W φ(κ) Σ_(n = 0, 2, ..., 18) He_n(κ) s^(n+1)/((n+1) n!),
      truncated where the remainder is below 2e-15 of the sum (checked against the closed forms in the tests);
      the series' coefficients of all components add up into one polynomial in u, so they cost nothing per
      component;
    * in between: the closed forms, evaluated only on the (component, u) pairs that fall there, the mirror
      terms φ(s + κ) and Φ(-s - κ) only where s + κ < √80 (beyond, below e^-40 and 2e-19).
    """

    def __init__(self, dist: GapDistribution) -> None:
        w, c, h = dist.weights, dist.centres, dist.widths
        self.w = np.where(w > 0, w, 0.0)
        self.c = c
        self.h = h
        self.mass = w.sum(axis=1)
        self.smooth = (w > 0) & (h > 0)  # components with a density (h = 0: a step of the CDF at u = c)
        hs = np.where(self.smooth, h, 1.0)
        self.hs = hs
        kappa = c / hs
        self.amp = np.where(self.smooth, w / (_SQRT2PI * hs), 0.0)
        self.top = np.where(w > 0, c + _R * np.where(h > 0, h, 0.0), np.inf)  # CDF = 1 from here on
        self.bottom = c - _R * hs  # nothing below this
        # He_n(κ) by the recurrence He_(n+1) = κ He_n - n He_(n-1)
        he = [np.ones_like(kappa), kappa]
        for n in range(1, 2 * _SERIES_TERMS - 2):
            he.append(kappa * he[n] - n * he[n - 1])
        with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
            lead = 2.0 * self.amp * np.exp(-0.5 * kappa * kappa)
            dens = [lead * he[2 * k] / (math.factorial(2 * k) * hs ** (2 * k)) for k in range(_SERIES_TERMS)]
        ok = self.smooth & (kappa < _R) & np.all([np.isfinite(d) & (np.abs(d) < 1e290) for d in dens], axis=0)
        self.series_top = np.where(ok, _SERIES * hs / (kappa + 3.0), 0.0)
        self.dens_coef = np.stack([np.where(ok, d, 0.0) for d in dens])  # (term, row, component)
        self.cdf_coef = self.dens_coef / (2.0 * np.arange(_SERIES_TERMS) + 1.0)[:, None, None]
        self.window_lo = np.maximum(self.series_top, self.bottom)  # exact evaluation for window_lo < u < top
        self.tail_top = np.where(w > 0, np.where(h > 0, c + _R_TAIL * np.where(h > 0, h, 0.0), c), -np.inf)

    # ------------------------------------------------------------------ one u per row (root finding)
    def tail(self, u: FloatArray) -> FloatArray:
        """1 - CDF at one u per row, as Σ W [Φ((c - u)/h) + Φ((-u - c)/h)] (no cancellation) over the components
        with u < c + 12 h (h = 0: u < c); the others add less than 2e-33 of their weight."""
        r, k = np.nonzero(u[:, None] < self.tail_top)
        ur, c, h, hs = u[r], self.c[r, k], self.h[r, k], self.hs[r, k]
        sf = np.where(h > 0, special.ndtr((c - ur) / hs) + special.ndtr((-ur - c) / hs), 1.0)
        return _sum_by(r, self.w[r, k] * sf, u.size)

    def at(self, u: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(CDF, density) at one u per row."""
        uu = u[:, None]
        series = uu <= self.series_top
        us = uu * uu
        poly_d = _horner(self.dens_coef, us)
        poly_c = _horner(self.cdf_coef, us) * uu
        dens = np.sum(np.where(series, poly_d, 0.0), axis=1)
        cdf = np.sum(np.where(uu >= self.top, self.w, 0.0), axis=1) + np.sum(np.where(series, poly_c, 0.0), axis=1)
        r, k = np.nonzero(self.smooth & ~series & (uu > self.window_lo) & (uu < self.top))
        if r.size:
            ur, c, h = u[r], self.c[r, k], self.h[r, k]
            dens += _sum_by(r, self.amp[r, k] * _pair_density(ur, c, h), u.size)
            cdf += _sum_by(r, self.w[r, k] * folded_normal_cdf(ur, c, h), u.size)
        return cdf, dens

    def quantile(self, level: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
        """The u (per row) where the CDF reaches ``level``, to 1e-13 in ln u (rows without a continuous part: ``lo``).

        Newton's method on ln CDF against ln u, kept inside the bisection bracket [lo, hi]. It starts at ``lo``:
        there the CDF grows like u, so the first step all but lands.
        """
        a, b = np.log(lo), np.log(hi)
        live = (self.mass > 0) & (level > 0)
        log_level = np.log(np.where(live, level, 1.0))
        x = a.copy()
        done = ~live
        for it in range(200):
            u = np.exp(x)
            value, dens = self.at(u)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                f = np.log(value) - log_level
                step = f / (u * dens / value)
            small = np.abs(step) <= 1e-13 * np.maximum(1.0, np.abs(x))
            a = np.where((f < 0) & ~done, x, a)
            b = np.where((f >= 0) & ~done, x, b)
            new = x - step
            bisect = ~small & (~np.isfinite(new) | (new <= a) | (new >= b) | (it >= 100))
            new = np.where(bisect, 0.5 * (a + b), new)
            converged = small | (b - a <= 1e-13 * np.maximum(1.0, np.abs(x)))
            x = np.where(done, x, new)
            done = done | converged
            if done.all():
                return np.exp(x)
        raise ConvergenceError("gap distribution: its lower quantile was not found in 200 iterations")

    def upper_quantile(self, level: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
        """The u (per row) where 1 - CDF falls to ``level``, to 1e-12 in ln u (rows without a continuous part: ``lo``).

        Far out, P(u) is a comb of narrow components (ζ → 1: large u1, small h, tiny weights), so 1 - CDF is a
        staircase on which Newton's method stalls. The root is bracketed by the largest single-component quantiles
        (1 - CDF >= W_i Φ((c_i - u)/h_i) gives the lower end; W_i [Φ((c_i - u)/h_i) + Φ((-u - c_i)/h_i)] <= level/(2n)
        for the n components with W_i > level/(4n), the others adding at most level/4, the upper end), narrowed by
        bisection over the sorted points c_i + t h_i (t = 0, ±0.5, ±1, ±2, ±4, ±8) inside it, and then solved by regula
        falsi with the Illinois modification on ln(1 - CDF) against ln u between two neighbouring points, where it
        is smooth.
        """
        live = (self.mass > 0) & (level > 0)
        rows = np.arange(level.size)
        n = np.maximum(np.sum(self.w > 0, axis=1), 1)[:, None]
        lev = level[:, None]
        h = np.where(self.h > 0, self.h, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            low = np.max(np.where(self.w > lev, self.c - h * special.ndtri(np.minimum(lev / self.w, 1.0)), 0.0), axis=1)
            high = np.max(np.where(self.w > lev / (4 * n), self.c - h * special.ndtri(np.minimum(lev / (4 * n * self.w), 1.0)), 0.0),
                          axis=1)
        a = np.clip(np.log(np.maximum(low, lo)), np.log(lo), np.log(hi))
        b = np.maximum(np.clip(np.log(np.maximum(high, lo)), np.log(lo), np.log(hi)), a)
        log_level = np.log(np.where(live, level, 1.0))

        def f(x: FloatArray) -> FloatArray:
            with np.errstate(divide="ignore"):
                return np.log(self.tail(np.exp(x))) - log_level

        fa, fb = f(a), f(b)
        # bisection over the sorted points c + t h inside (a, b)
        with np.errstate(divide="ignore", invalid="ignore"):
            points = np.log((self.c[:, :, None] + h[:, :, None] * _STEPS).reshape(level.size, -1))
        points = np.where((self.w > 0).repeat(_STEPS.size, axis=1) & (points > a[:, None]) & (points < b[:, None]), points, b[:, None])
        points = np.sort(np.concatenate([a[:, None], points, b[:, None]], axis=1), axis=1)
        i_lo = np.zeros(level.size, dtype=np.intp)
        i_hi = np.argmax(points >= b[:, None], axis=1)
        while True:
            wide = i_hi - i_lo > 1
            if not wide.any():
                break
            mid = (i_lo + i_hi) // 2
            fm = f(np.where(wide, points[rows, mid], a))
            above = wide & (fm > 0)  # the root lies above
            below = wide & ~(fm > 0)
            i_lo, fa = np.where(above, mid, i_lo), np.where(above, fm, fa)
            i_hi, fb = np.where(below, mid, i_hi), np.where(below, fm, fb)
        a, b = points[rows, i_lo], points[rows, i_hi]
        done = ~live | (fa <= 0) | (fb >= 0) | (b - a <= 1e-12 * np.maximum(1.0, np.abs(a)))
        x = np.where(fa <= 0, a, b)  # (a bracket end that is the root already)
        side = np.zeros(a.size)
        for _ in range(200):
            if done.all():
                return np.exp(np.where(live, x, np.log(lo)))
            with np.errstate(invalid="ignore", divide="ignore"):
                secant = b - fb * (b - a) / (fb - fa)
            inside = np.isfinite(secant) & (secant > a) & (secant < b)
            x = np.where(done, x, np.where(inside, secant, 0.5 * (a + b)))
            fx = f(x)
            above = fx > 0  # the root lies above x
            # Illinois: halve the f of the end kept twice in a row
            fb = np.where(above & (side > 0), 0.5 * fb, fb)
            fa = np.where(~above & (side < 0), 0.5 * fa, fa)
            a, fa = np.where(above & ~done, x, a), np.where(above & ~done, fx, fa)
            b, fb = np.where(~above & ~done, x, b), np.where(~above & ~done, fx, fb)
            side = np.where(above, 1.0, -1.0)
            done = done | (fx == 0) | (b - a <= 1e-12 * np.maximum(1.0, np.abs(x)))
        raise ConvergenceError("gap distribution: its upper quantile was not found in 200 iterations")

    # ------------------------------------------------------------------ sorted grids (one row at a time)
    def density_on(self, i: int, u: FloatArray) -> FloatArray:
        """The density at the ascending separations ``u`` of row i (1/m)."""
        out = _horner(_series_sums(u, self.series_top[i], self.dens_coef[:, i]), u * u)
        for (node, c, h, amp), sign in zip(self._pairs(i, u), (-1.0, 1.0)):
            for lo in range(0, node.size, _CHUNK):
                part = slice(lo, lo + _CHUNK)
                z = u[node[part]] + sign * c[part]  # u - c, then u + c (the mirror term)
                z /= h[part]
                z *= z
                term = np.exp(-0.5 * z)
                term[z >= 80.0] = 0.0  # (the windows end at √80 h; rounding may let one more in)
                term *= amp[part]
                out += _sum_by(node[part], term, u.size)
        return out

    def cdf_on(self, i: int, u: FloatArray) -> FloatArray:
        """The CDF of the continuous part at the ascending separations ``u`` of row i."""
        order = np.argsort(self.top[i], kind="stable")
        full = np.concatenate([[0.0], np.cumsum(self.w[i, order])])[np.searchsorted(self.top[i, order], u, side="right")]
        out = full + _horner(_series_sums(u, self.series_top[i], self.cdf_coef[:, i]), u * u) * u
        # Φ((u - c)/h) - Φ((-u - c)/h): the second term only where (u + c)/h < √80 (elsewhere below 2e-19)
        for (node, c, h, amp), sign in zip(self._pairs(i, u), (-1.0, 1.0)):
            for lo in range(0, node.size, _CHUNK):
                part = slice(lo, lo + _CHUNK)
                z = u[node[part]] + sign * c[part]
                z /= (-sign) * h[part]
                term = special.ndtr(z)
                term *= (-sign * _SQRT2PI) * amp[part] * h[part]  # ± W
                out += _sum_by(node[part], term, u.size)
        return out

    def _pairs(self, i: int, u: FloatArray) -> tuple[tuple[NDArray[np.intp], FloatArray, FloatArray, FloatArray], ...]:
        """The (node, c, h, W/(√(2π) h)) quadruples of row i where the closed forms are evaluated: window_lo < u < top
        for the term in u - c, and in addition u < √80 h - c for the mirror term in u + c (nodes ascending)."""
        smooth = np.flatnonzero(self.smooth[i])
        c, h, amp = self.c[i, smooth], self.h[i, smooth], self.amp[i, smooth]
        j_lo = np.searchsorted(u, self.window_lo[i, smooth], side="right")
        j_hi = np.searchsorted(u, self.top[i, smooth], side="left")
        j_mirror = np.minimum(np.searchsorted(u, _R * h - c, side="left"), j_hi)
        out = []
        for top in (j_hi, j_mirror):
            count = np.maximum(top - j_lo, 0)
            node = np.repeat(j_lo - (np.cumsum(count) - count), count) + np.arange(count.sum())
            out.append((node, np.repeat(c, count), np.repeat(h, count), np.repeat(amp, count)))
        return tuple(out)


def _horner(coef: FloatArray | list[FloatArray], x: FloatArray) -> FloatArray:
    """Σ_k coef[k] x^k (``coef``: the terms along its first axis)."""
    out = coef[-1] * x
    for c in coef[-2:0:-1]:
        out += c
        out *= x
    return out + coef[0]


def _series_sums(u: FloatArray, series_top: FloatArray, coef: FloatArray) -> list[FloatArray]:
    """Per node j, the sum of every series coefficient (``coef``: term × component) over the components whose series
    serves u_j (u_j <= series_top): all terms in one bincount and one running sum (each term's sums in the same order,
    so the same bits, as one term at a time)."""
    n = u.size
    j = np.searchsorted(u, series_top, side="right")  # the series serves nodes 0 .. j-1
    terms = coef.shape[0]
    index = (np.arange(terms)[:, None] * (n + 1) + j[None, :]).ravel()
    acc = _sum_by(index, coef.ravel(), terms * (n + 1)).reshape(terms, n + 1)
    return list(np.cumsum(acc[:, ::-1], axis=1)[:, ::-1][:, 1:])


def _sum_by(index: NDArray[np.intp], values: FloatArray, n: int) -> FloatArray:
    """Σ of ``values`` per ``index`` (0 .. n-1), as floats."""
    return cast(FloatArray, np.bincount(index, weights=values, minlength=n))


def _pair_density(u: FloatArray, c: FloatArray, h: FloatArray) -> FloatArray:
    """e^(-(u-c)²/2h²) + e^(-(u+c)²/2h²), each term left out beyond √80 widths (as the plain sum does)."""
    z = ((u - c) / h) ** 2
    out = np.exp(-0.5 * z, where=z < 80.0, out=np.zeros_like(z))
    zm = ((u + c) / h) ** 2
    out += np.exp(-0.5 * zm, where=zm < 80.0, out=np.zeros_like(zm))
    return out


def discretise(dist: GapDistribution, *, panel_width: float = 0.25, order: int = 8) -> tuple[FloatArray, FloatArray]:
    """The continuous part of P(u) as discrete (gaps, weights), shape (pressures, n), see the module docstring.

    Gaps in m, weights dimensionless (docs/theory.md §5.5). Rows whose continuous part is empty get a
    single node of weight 0.
    """
    mix = _Mixture(dist)
    mass = mix.mass
    scale = np.maximum(dist.mean, 1e-200)  # (rows in complete contact have no continuous part)
    top = np.maximum(np.max(np.where(dist.weights > 0, dist.centres + 12.0 * dist.widths, 0.0), axis=1), scale)
    u_lo = mix.quantile(1e-10 * mass, scale * 1e-30, top)
    u_hi = mix.upper_quantile(1e-13 * mass, scale * 1e-30, top * 10.0)
    u_hi = np.maximum(u_hi, u_lo * 1.0001)
    span = np.log(u_hi / u_lo)
    # each row its own panels (the list of pressures does not change a row's rule); the rows with fewer end in
    # panels of zero width at u_hi, which get no weight
    per_row = np.clip(np.ceil(span / panel_width), 1, 2000).astype(np.intp)
    n_pan = int(per_row.max())
    k = np.minimum(np.arange(n_pan + 1)[None, :], per_row[:, None]) / per_row[:, None]
    edges = np.log(u_lo)[:, None] + span[:, None] * k
    xg, wg = gauss_legendre(order)
    left, right = edges[:, :-1], edges[:, 1:]
    half = 0.5 * (right - left)
    x = (0.5 * (left + right))[:, :, None] + half[:, :, None] * xg
    u = np.exp(x).reshape(len(dist), -1)
    u_edges = np.exp(edges)
    dens = np.empty_like(u)
    cdf_edges = np.empty_like(u_edges)
    for i in range(len(dist)):
        n = int(per_row[i])
        dens[i, :n * order] = mix.density_on(i, u[i, :n * order])
        dens[i, n * order:] = 0.0
        cdf_edges[i, :n + 1] = mix.cdf_on(i, u_edges[i, :n + 1])
        cdf_edges[i, n + 1:] = cdf_edges[i, n]
    w = (half[:, :, None] * wg).reshape(len(dist), -1) * u * dens
    # rescale each panel to its exact mass from the closed-form CDF
    exact = np.diff(cdf_edges, axis=1)
    approx = w.reshape(len(dist), n_pan, order).sum(axis=2)
    # a panel whose Gauss points badly miss its mass (a feature narrower than the panel) gets its
    # exact mass at the panel's middle node instead
    resolved = (approx > 0.5 * exact) & (approx < 2.0 * exact)
    ratio = np.where(resolved, exact / np.where(resolved, approx, 1.0), 0.0)
    w = w.reshape(len(dist), n_pan, order) * ratio[:, :, None]
    fallback = ~resolved & (exact > 0)
    if fallback.any():
        w[fallback, order // 2] = exact[fallback]
    w = w.reshape(len(dist), -1)
    below = cdf_edges[:, 0]
    above = mass - cdf_edges[:, -1]
    gaps = np.concatenate([u_lo[:, None], u, u_hi[:, None]], axis=1)
    weights = np.concatenate([below[:, None], w, np.maximum(above, 0.0)[:, None]], axis=1)
    return gaps, weights


@dataclass(frozen=True, kw_only=True)
class EffectiveMediumResult:
    """Effective-medium prediction over a sweep of squeeze pressures (arrays of equal length, SI units).

    Attributes
    ----------
    squeeze_pressure, pressure_difference
        P0 and ΔP (Pa).
    percolates
        σ_eff > 0 (A(ζ1)/A0 < 1/2, Bruggeman's threshold; docs/theory.md §5.4).
    effective_conductivity
        σ_eff in m³/(Pa·s) (0 where it does not percolate).
    effective_gap
        u_e = (12 η σ_eff)^(1/3), the gap with the local conductivity σ_eff (m).
    leak_rate
        Q = (Ly/Lx) σ_eff ΔP in m³/s (NaN where it does not percolate).
    contact_area_at_cutoff
        A(ζ1)/A0, the δ(u) weight.
    mean_gap
        ū(1) (m).
    gap_distribution_mean
        ∫ u P(u) du (m).
    residual
        Relative residual 1 - g(σ_eff) of the solved Bruggeman equation.
    viscosity
        η (Pa·s).
    aspect_ratio
        Ly/Lx (dimensionless).
    distribution
        The :class:`~sealeak.physics.gaps.GapDistribution` P(u) at the distinct squeeze pressures.
    messages
        Human-readable notes (one per non-percolating pressure).
    """

    squeeze_pressure: FloatArray
    pressure_difference: FloatArray
    percolates: NDArray[np.bool_] = quantity("1", "the effective medium conducts (σ_eff > 0)",
                                             key="percolates_effective_medium")
    effective_conductivity: FloatArray = quantity("m^3/(Pa*s)", "effective sheet conductivity σ_eff")
    effective_gap: FloatArray = quantity("m", "gap u_e = (12 η σ_eff)^(1/3)")
    leak_rate: FloatArray = quantity("m^3/s", "leak rate Q of the effective medium", key="leak_rate_effective_medium")
    contact_area_at_cutoff: FloatArray
    mean_gap: FloatArray = quantity("m", "mean gap ū(1)")
    gap_distribution_mean: FloatArray = quantity("m", "mean ∫ u P(u) du of the gap distribution")
    residual: FloatArray
    viscosity: float
    aspect_ratio: float
    distribution: GapDistribution = field(repr=False, compare=False)
    messages: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.squeeze_pressure.size)


#: Distinct squeeze pressures whose P(u) is discretised and whose Bruggeman equation is solved together.
ROWS_AT_ONCE = 256


def _rows(dist: GapDistribution, block: slice) -> GapDistribution:
    """The rows ``block`` of a gap distribution."""
    return GapDistribution(**{f.name: getattr(dist, f.name)[block] for f in fields(GapDistribution)})


def _joined(parts: list[GapDistribution]) -> GapDistribution:
    """Gap distributions of consecutive blocks of pressures as one (their rows in order)."""
    return GapDistribution(**{f.name: np.concatenate([getattr(d, f.name) for d in parts]) for f in fields(GapDistribution)})


def _solve(contact: PerssonContact, pressures: FloatArray, quadrature: dict[str, int], viscosity: float,
           distribution: GapDistribution | None) -> tuple[GapDistribution, FloatArray, FloatArray]:
    """(P(u), σ_eff, residual) at the distinct ``pressures`` (Pa), P(u) computed unless ``distribution`` is given."""
    if distribution is None:
        # the discretisation of a list of pressures (each row on its own panels, padded to the longest) depends on the
        # contact, the ζ-rule and the list alone, not on η: a second fluid, or the same σ table again, takes it from
        # the cache
        key = (contact_key(contact, *quadrature.values()), tuple(quadrature), pressures.tobytes())
        kept = _DISCRETE.get(key)
        distribution = gap_distribution(contact, pressures, **quadrature)
        gaps, weights = kept if kept is not None else _DISCRETE.put(key, discretise(distribution))
    else:
        gaps, weights = discretise(distribution)
    sigma, resid = bruggeman_conductivity(gaps, weights, distribution.contact_fraction, viscosity)
    return distribution, sigma, resid


def effective_medium(
    contact: PerssonContact,
    *,
    squeeze_pressure: ArrayLike,
    pressure_difference: ArrayLike,
    viscosity: float,
    aspect_ratio: float,
    distribution: GapDistribution | None = None,
    gap_quadrature: Mapping[str, int] | None = None,
) -> EffectiveMediumResult:
    """Bruggeman effective-medium leak rate Q = (Ly/Lx) σ_eff ΔP at every squeeze pressure (vectorised).

    Q in m³/s; σ_eff in m³/(Pa·s) solves 1/σ_eff = ∫ du P(u) 2/(σ_eff + σ(u)), σ(u) = u³/(12η)
    (Bruggeman (1935); docs/theory.md §5.3, eq. 5.3). No leak rate (NaN) where A(ζ1)/A0 >= 1/2 (§5.4).

    Parameters
    ----------
    contact
        Persson contact mechanics of the interface.
    squeeze_pressure
        Nominal squeeze pressures P0 in Pa (scalar or 1-D array).
    pressure_difference
        ΔP in Pa, scalar or broadcastable against ``squeeze_pressure``.
    viscosity
        η in Pa·s.
    aspect_ratio
        Ly/Lx (number of squares of side L across the seal).
    distribution
        A :class:`GapDistribution` already computed for these pressures (else it is computed).
    gap_quadrature
        Keywords of :func:`~sealeak.physics.gaps.gap_distribution` for the ζ-rule of P(u) when it is computed here
        (default: its own); :data:`~sealeak.physics.gaps.CONDUCTIVITY_QUADRATURE` is the lighter rule for σ tables.
    """
    quadrature = dict(gap_quadrature or {})
    p0, dp = _pressures(squeeze_pressure, pressure_difference)
    for name, v in (("viscosity", viscosity), ("aspect_ratio", aspect_ratio)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(name, v, "must be finite and > 0")
    # one distribution per distinct pressure
    uniq, inverse = np.unique(p0, return_inverse=True)
    given = distribution is not None and distribution.squeeze_pressure.shape == uniq.shape and \
        np.array_equal(distribution.squeeze_pressure, uniq)
    # in blocks of at most ROWS_AT_ONCE pressures (a list of them is discretised on one padded grid: 2 000 pressures took
    # 1 GB at once, the 5 000 of a fit 16 GB); up to one block, the list as before
    parts = []
    for start in range(0, uniq.size, ROWS_AT_ONCE):
        block = slice(start, start + ROWS_AT_ONCE)
        parts.append(_solve(contact, uniq[block], quadrature, viscosity,
                            _rows(distribution, block) if given and distribution is not None else None))
    dist = parts[0][0] if len(parts) == 1 else _joined([d for d, _, _ in parts])
    sigma = np.concatenate([sg for _, sg, _ in parts])
    resid = np.concatenate([r for _, _, r in parts])
    percolates = sigma > 0
    sigma, resid, percolates = sigma[inverse], resid[inverse], percolates[inverse]
    area = dist.contact_fraction[inverse]
    q = np.where(percolates, aspect_ratio * sigma * dp, np.nan)
    u_e = np.cbrt(12.0 * viscosity * sigma)
    note = no_channel_note(p0, percolates, area,
                           " >= 0.5, the 2D Bruggeman percolation threshold: the effective-medium theory predicts no flow "
                           "(no leak-rate number; numerically exact studies put the threshold near A/A0 = 0.42).")
    messages = [note] if note else []
    return EffectiveMediumResult(
        squeeze_pressure=p0, pressure_difference=dp, percolates=percolates, effective_conductivity=sigma,
        effective_gap=u_e, leak_rate=q, contact_area_at_cutoff=area, mean_gap=dist.mean_gap[inverse],
        gap_distribution_mean=dist.mean[inverse], residual=resid, viscosity=float(viscosity),
        aspect_ratio=float(aspect_ratio), distribution=dist, messages=tuple(messages),
    )
