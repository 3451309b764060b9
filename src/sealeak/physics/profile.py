"""Seals with a non-uniform nominal contact pressure p(x): the pressure profile and its flow resistance.

The fluid crosses the sealing band along x, 0 <= x <= w, and the seal line has length Ly. A strip
dx at nominal pressure p(x) conducts like a uniform seal at that pressure, with the sheet
conductance σ(p) in m³/(Pa·s) (the flow per unit length of seal line per unit pressure gradient).
The strips are in series, so (docs/theory.md §10.1)

    Q = Ly ΔP / R,      R = ∫₀^w dx / σ(p(x))      [R in Pa·s/m²]

A strip that does not percolate (σ = 0 at p > 0) seals the band (R = ∞, Q = 0); a strip at zero
pressure adds no resistance. For a constant profile R = w/σ(P0) and Q = (Ly/w) σ(P0) ΔP is the
uniform seal of width w.

The integral is computed by adaptive Gauss–Kronrod quadrature after the substitution
x = a + (b - a)(1 - cos θ)/2 on each linear piece (nodes gather at the ends, where p may fall to
zero), until the estimated relative error is below ``rtol`` (1e-8 by default); a constant piece is
integrated exactly, Δx/σ(p). The semi-elliptic (Hertz) profile p = p_max sqrt(1 - (2x/w - 1)²)
becomes p = p_max sin θ, x = (w/2)(1 - cos θ), smooth in θ.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, positive_number
from ._kernels import weighted_sum

__all__ = ["PressureProfile", "BandIntegral", "series_resistance", "resistance_band", "SIGMA_FLOOR"]

FloatArray = NDArray[np.float64]

#: Relative change of R between two refinements below which the quadrature counts as converged.
RTOL = 1e-8
#: Fraction of the flow resistance the reported resistance band holds (docs/theory.md §10.1).
RESISTANCE_FRACTION = 0.9
#: A sheet conductance σ (m³/(Pa·s)) at or below this counts as no leak channel: the smallest normal double,
#: 2.2·10⁻³⁰⁸ (a critical gap u_c of ~10⁻¹⁰³ m in water), where 1/σ overflows. A band whose peak sits within a hair of
#: the percolation limit has such a σ: it seals for any purpose, and R = ∫dx/σ is infinite, not a number.
SIGMA_FLOOR = float(np.finfo(float).tiny)


@dataclass(frozen=True)
class PressureProfile:
    """Nominal contact pressure p(x) (Pa) across a sealing band 0 <= x <= width (m).

    ``shape`` "table": piecewise linear through the nodes (``x`` non-decreasing from 0 to the
    width; two equal neighbouring x make a step). ``shape`` "semi-elliptic": the Hertz profile
    p = p_max sqrt(1 - (2x/w - 1)²) (Johnson, Contact Mechanics (1985) §4.2; docs/theory.md §10.2),
    stored by its two ends (x = [0, w]) and ``peak``.
    """

    x: FloatArray
    pressure: FloatArray
    shape: str = "table"
    peak: float = 0.0

    @classmethod
    def semi_elliptic(cls, width: float, max_pressure: float) -> PressureProfile:
        """Hertz profile of width w (m) and peak p_max (Pa); it carries f = π w p_max/4 (N/m) (eq. 10.2)."""
        w = _positive("contact_width", width)
        p = _positive("max_pressure", max_pressure)
        return cls(np.array([0.0, w]), np.array([0.0, 0.0]), "semi-elliptic", p)

    @classmethod
    def table(cls, x: ArrayLike, pressure: ArrayLike, *, x_name: str = "x", pressure_name: str = "pressure") -> PressureProfile:
        """Piecewise-linear profile through (x, p) nodes (m, Pa); x is shifted to start at 0."""
        xs = np.asarray(x, dtype=float).ravel()
        ps = np.asarray(pressure, dtype=float).ravel()
        if xs.size != ps.size:
            raise InputError(x_name, f"{xs.size} values", f"needs as many values as {pressure_name} ({ps.size})")
        if xs.size < 2:
            raise InputError(x_name, xs.tolist(), "needs at least two points across the band")
        if not (np.all(np.isfinite(xs)) and np.all(np.isfinite(ps))):
            raise InputError(x_name if not np.all(np.isfinite(xs)) else pressure_name, "a non-finite value",
                             "every value must be a finite number")
        if np.any(np.diff(xs) < 0):
            i = int(np.argmax(np.diff(xs) < 0)) + 1
            raise InputError(f"{x_name}[{i}]", float(xs[i]), f"must not be below the previous value {xs[i - 1]:.6g}: "
                             "x must be non-decreasing across the band")
        if np.any(ps < 0):
            i = int(np.argmax(ps < 0))
            raise InputError(f"{pressure_name}[{i}]", float(ps[i]), "must be >= 0 (a contact pressure)")
        if not xs[-1] > xs[0]:
            raise InputError(x_name, xs.tolist(), "must span a band of non-zero width")
        if not ps.max() > 0:
            raise InputError(pressure_name, ps.tolist(), "must be > 0 somewhere: nothing presses the seal")
        return cls(xs - xs[0], ps)

    @property
    def width(self) -> float:
        """Contact width w in m."""
        return float(self.x[-1])

    @property
    def max_pressure(self) -> float:
        """Largest nominal pressure p_max in Pa."""
        return self.peak if self.shape == "semi-elliptic" else float(self.pressure.max())

    @property
    def force_per_length(self) -> float:
        """f = ∫ p dx in N/m (exact for both shapes)."""
        if self.shape == "semi-elliptic":
            return np.pi * self.width * self.peak / 4.0
        return float(np.sum(np.diff(self.x) * (self.pressure[1:] + self.pressure[:-1]) / 2.0))

    @property
    def mean_pressure(self) -> float:
        """f / w in Pa: the uniform pressure that carries the same load on the same width."""
        return self.force_per_length / self.width

    def at(self, x: ArrayLike) -> FloatArray:
        """p(x) in Pa (0 outside the band; at a step, the value after it)."""
        xs = np.asarray(x, dtype=float)
        if self.shape == "semi-elliptic":
            s = 2.0 * xs / self.width - 1.0
            return self.peak * np.sqrt(np.clip(1.0 - s * s, 0.0, None))
        inside = (xs >= 0) & (xs <= self.width)
        return np.where(inside, np.interp(xs, self.x, self.pressure), 0.0)

    def scaled(self, factor: float) -> PressureProfile:
        """The same shape with every pressure multiplied by ``factor`` (> 0)."""
        f = _positive("profile_scale", factor)
        return PressureProfile(self.x, self.pressure * f, self.shape, self.peak * f)


def _positive(name: str, value: float) -> float:
    return positive_number(name, value, allowed="must be a finite number > 0")


@dataclass(frozen=True, kw_only=True)
class BandIntegral:
    """R = ∫ dx/σ(p(x)) of one profile, with the nodes it was computed on (SI units).

    Attributes
    ----------
    resistance
        R in Pa·s/m² (inf where a strip does not percolate; 0 for a band without pressure).
    sealed
        True where σ(p_max) = 0: the band holds no leak channel.
    converged, change, evaluations
        Whether the estimated relative error fell below ``rtol``, that estimate (Σ|K15 - G7| / R),
        and the number of σ evaluations.
    x, dx, pressure, conductance
        The quadrature points (m), their weights as widths (m; Σ dx = w), p (Pa) and σ
        (m³/(Pa·s)), sorted along x; constant pieces are one point of width Δx.
    """

    resistance: float
    sealed: bool
    converged: bool
    change: float
    evaluations: int
    x: FloatArray
    dx: FloatArray
    pressure: FloatArray
    conductance: FloatArray


# Gauss–Kronrod 7/15 (QUADPACK's qk15): Kronrod nodes on [-1, 1] (the odd ones, 1, 3, 5, 7, are
# the 7-point Gauss–Legendre nodes), Kronrod weights, and the Gauss weights of those nodes.
_XK = np.array([0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                0.207784955007898467600689403773245, 0.0])
_WK = np.array([0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                0.204432940075298892414161999234649, 0.209482141084727828012999174891714])
_WG = np.array([0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                0.381830050505118944950369775488975, 0.417959183673469387755102040816327])
KRONROD_NODES = np.concatenate([-_XK[:-1], _XK[::-1]])  # 15 nodes, ascending
KRONROD_WEIGHTS = np.concatenate([_WK[:-1], _WK[::-1]])
GAUSS_WEIGHTS = np.zeros(15)
GAUSS_WEIGHTS[[1, 3, 5, 7, 9, 11, 13]] = np.concatenate([_WG[:-1], _WG[::-1]])
#: Sub-intervals each varying piece starts with, and the most the adaptive quadrature may use.
FIRST_INTERVALS = 4
MAX_INTERVALS = 4096


def _evaluate(profile: PressureProfile, piece: NDArray[np.int_], theta: FloatArray,
              a: FloatArray, b: FloatArray, pa: FloatArray, pb: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """x (m), dx/dθ (m) and p (Pa) at angles θ of the given pieces."""
    if profile.shape == "semi-elliptic":
        w = profile.width
        return w * (1.0 - np.cos(theta)) / 2.0, w * np.sin(theta) / 2.0, profile.peak * np.sin(theta)
    u = (1.0 - np.cos(theta)) / 2.0
    ak, bk = a[piece], b[piece]
    return ak + (bk - ak) * u, (bk - ak) * np.sin(theta) / 2.0, pa[piece] + (pb[piece] - pa[piece]) * u


def series_resistance(profile: PressureProfile, sheet_conductance: Callable[[FloatArray], FloatArray], *,
                      rtol: float = RTOL, max_intervals: int = MAX_INTERVALS) -> BandIntegral:
    """R = ∫₀^w dx/σ(p(x)) in Pa·s/m² of a band with sheet conductance σ(p) in m³/(Pa·s) (docs/theory.md §10.1, eq. 10.1).

    ``sheet_conductance`` maps an array of pressures (Pa, all > 0) to σ (0 where the contact does
    not percolate; at or below :data:`SIGMA_FLOOR` counts as 0); σ is assumed to fall as p rises, so the band is
    sealed exactly when σ(p_max) = 0. Strips at zero pressure add no resistance; constant pieces are exact, Δx/σ(p).
    The varying pieces are integrated in θ (x = a + (b - a)(1 - cos θ)/2) by adaptive
    Gauss–Kronrod 7/15 quadrature (Piessens et al., QUADPACK (1983)): every sub-interval whose
    error estimate |K15 - G7| is among the largest is halved, all in one call of σ per round,
    until the summed estimate is below ``rtol`` × R (converged) or ``max_intervals`` is reached.
    σ may fall by tens of orders of magnitude near the peak when the band is close to sealing:
    the sub-intervals gather there.
    """
    p_max = profile.max_pressure
    if float(np.asarray(sheet_conductance(np.array([p_max])))[0]) <= SIGMA_FLOOR:
        return BandIntegral(resistance=float("inf"), sealed=True, converged=True, change=0.0, evaluations=1,
                            x=np.array([0.0]), dx=np.array([profile.width]),
                            pressure=np.array([p_max]), conductance=np.zeros(1))
    # constant pieces: exact
    if profile.shape == "semi-elliptic":
        a = b = pa = pb = np.zeros(1)
        varying = np.array([0])
        cx = cdx = cp = np.zeros(0)
    else:
        xa, xb = profile.x[:-1], profile.x[1:]
        qa, qb = profile.pressure[:-1], profile.pressure[1:]
        real = xb > xa
        const = real & (qa == qb)
        vary = real & (qa != qb)
        a, b, pa, pb = xa[vary], xb[vary], qa[vary], qb[vary]
        varying = np.arange(a.size)
        cx, cdx, cp = (xa[const] + xb[const]) / 2.0, xb[const] - xa[const], qa[const]
    csig = np.zeros_like(cp)
    if cp.size:
        pressed = cp > 0
        csig[pressed] = sheet_conductance(cp[pressed])
        if np.any(csig[pressed] <= SIGMA_FLOOR):
            return BandIntegral(resistance=float("inf"), sealed=True, converged=True, change=0.0,
                                evaluations=cp.size, x=cx, dx=cdx, pressure=cp, conductance=csig)
    r_const = float(np.sum(np.where(cp > 0, cdx / np.where(csig > 0, csig, 1.0), 0.0)))
    # adaptive Gauss–Kronrod on the varying pieces, in θ
    lo = np.repeat(np.arange(FIRST_INTERVALS) * np.pi / FIRST_INTERVALS, varying.size)
    hi = lo + np.pi / FIRST_INTERVALS
    piece = np.tile(varying, FIRST_INTERVALS)
    done_k = np.zeros(0)
    done_e = np.zeros(0)
    keep: list[tuple[FloatArray, FloatArray, FloatArray, FloatArray]] = []
    evaluations = cp.size + 1
    converged = False
    error = 0.0
    total = r_const
    while lo.size:
        half = (hi - lo) / 2.0
        theta = ((lo + hi) / 2.0)[:, None] + half[:, None] * KRONROD_NODES[None, :]
        x, dxdt, p = _evaluate(profile, piece[:, None], theta, a, b, pa, pb)
        sigma = np.zeros_like(p)
        pressed = p > 0
        sigma[pressed] = sheet_conductance(p[pressed])
        evaluations += int(pressed.sum())
        if np.any(sigma[pressed] <= SIGMA_FLOOR):  # a strip below p_max that does not percolate: σ is not monotone
            return BandIntegral(resistance=float("inf"), sealed=True, converged=True, change=0.0,
                                evaluations=evaluations, x=x.ravel(), dx=(dxdt * half[:, None]).ravel(),
                                pressure=p.ravel(), conductance=sigma.ravel())
        f = np.where(pressed, dxdt / np.where(sigma > 0, sigma, 1.0), 0.0)
        k = half * weighted_sum(f, KRONROD_WEIGHTS)  # fixed order of addition: the same bits on every call
        g = half * weighted_sum(f, GAUSS_WEIGHTS)
        e = np.abs(k - g)
        total = r_const + float(done_k.sum() + k.sum())
        error = float(done_e.sum() + e.sum())
        budget = rtol * total
        if error <= budget or done_k.size + 2 * lo.size > max_intervals:
            converged = error <= budget
            keep.append((x.ravel(), (dxdt * half[:, None] * KRONROD_WEIGHTS[None, :]).ravel(), p.ravel(), sigma.ravel()))
            break
        # accept the intervals whose error is a small share of the budget; halve the others
        split = e > budget / (4.0 * (done_k.size + lo.size))
        if not split.any():
            split = e >= e.max()
        ok = ~split
        done_k = np.concatenate([done_k, k[ok]])
        done_e = np.concatenate([done_e, e[ok]])
        keep.append((x[ok].ravel(), (dxdt[ok] * half[ok, None] * KRONROD_WEIGHTS[None, :]).ravel(), p[ok].ravel(),
                     sigma[ok].ravel()))
        mid = (lo[split] + hi[split]) / 2.0
        lo, hi, piece = (np.concatenate([lo[split], mid]), np.concatenate([mid, hi[split]]),
                         np.concatenate([piece[split], piece[split]]))
    xs = np.concatenate([cx] + [k_[0] for k_ in keep])
    dxs = np.concatenate([cdx] + [k_[1] for k_ in keep])
    ps = np.concatenate([cp] + [k_[2] for k_ in keep])
    ss = np.concatenate([csig] + [k_[3] for k_ in keep])
    order = np.argsort(xs, kind="stable")
    change = error / total if total > 0 else 0.0
    return BandIntegral(resistance=total, sealed=False, converged=converged or varying.size == 0, change=change,
                        evaluations=evaluations, x=xs[order], dx=dxs[order],
                        pressure=ps[order], conductance=ss[order])


def resistance_band(integral: BandIntegral, fraction: float = RESISTANCE_FRACTION) -> tuple[float, float]:
    """Where the resistance sits: the width (m) of the narrowest part of the band that holds ``fraction`` of R, and the x (m) of its densest point.

    The strips are taken in decreasing order of resistance per unit width 1/σ until they hold
    ``fraction`` of R (the last one in part); NaN for a sealed band or one without resistance.
    """
    if integral.sealed or not integral.resistance > 0:
        return float("nan"), float("nan")
    with np.errstate(divide="ignore"):
        density = np.where(integral.conductance > 0, 1.0 / integral.conductance, 0.0)
    order = np.argsort(-density, kind="stable")
    r = integral.dx[order] * density[order]
    cum = np.cumsum(r)
    target = fraction * integral.resistance
    k = int(np.searchsorted(cum, target))
    k = min(k, r.size - 1)
    before = cum[k - 1] if k > 0 else 0.0
    part = (target - before) / r[k] if r[k] > 0 else 0.0
    width = float(np.sum(integral.dx[order][:k]) + part * integral.dx[order][k])
    return width, float(integral.x[order][0])
