"""Seals with a non-uniform nominal contact pressure p(x): the pressure profile and its flow resistance.

The fluid crosses the sealing band along x, 0 <= x <= w, and the seal line has length Ly. A strip
dx at nominal pressure p(x) conducts like a uniform seal at that pressure, with the sheet
conductance σ(p) in m³/(Pa·s) (the flow per unit length of seal line per unit pressure gradient).
The strips are in series, so (docs/theory.md §10.1)

    Q = Ly ΔP / R,      R = ∫₀^w dx / σ(p(x))      [R in Pa·s/m²]

A strip that does not percolate (σ = 0 at p > 0) seals the band (R = ∞, Q = 0); a strip at zero
pressure adds no resistance. For a constant profile R = w/σ(P0) and Q = (Ly/w) σ(P0) ΔP is the
uniform seal of width w.

The integral is computed by Gauss–Legendre quadrature after the substitution
x = a + (b - a)(1 - cos θ)/2 on each linear piece (nodes gather at the ends, where p may fall to zero),
doubling the number of nodes until the relative change is below ``rtol`` (1e-8 by default); a
constant piece is integrated exactly, Δx/σ(p). The semi-elliptic (Hertz) profile
p = p_max sqrt(1 - (2x/w - 1)²) becomes p = p_max sin θ, x = (w/2)(1 - cos θ), smooth in θ.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = ["PressureProfile", "BandIntegral", "series_resistance", "resistance_band"]

FloatArray = NDArray[np.float64]

#: Relative change of R between two refinements below which the quadrature counts as converged.
RTOL = 1e-8
#: Gauss–Legendre nodes per piece: the first level, and the most before giving up (then reported).
FIRST_NODES = 8
MAX_NODES = 1024
#: Fraction of the flow resistance the reported resistance band holds (docs/theory.md §10.1).
RESISTANCE_FRACTION = 0.9


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
        """Hertz profile of width w (m) and peak p_max (Pa); it carries f = π w p_max/4 (N/m)."""
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
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise InputError(name, value, "must be a finite number > 0")
    return v


@dataclass(frozen=True)
class BandIntegral:
    """R = ∫ dx/σ(p(x)) of one profile, with the nodes it was computed on (SI units).

    Attributes
    ----------
    resistance
        R in Pa·s/m² (inf where a strip does not percolate; 0 for a band without pressure).
    sealed
        True where σ(p_max) = 0: the band holds no leak channel.
    converged, change, nodes
        Whether the relative change between the last two refinements fell below ``rtol``, that
        change, and the Gauss–Legendre nodes per piece of the last one.
    x, dx, pressure, conductance
        The last refinement's points (m), their quadrature widths (m; Σ dx = w), p (Pa) and σ
        (m³/(Pa·s)), sorted along x; constant pieces are one point of width Δx.
    """

    resistance: float
    sealed: bool
    converged: bool
    change: float
    nodes: int
    x: FloatArray
    dx: FloatArray
    pressure: FloatArray
    conductance: FloatArray


def _pieces(profile: PressureProfile, n: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Quadrature points, widths and pressures of ``profile`` with n Gauss–Legendre nodes per piece."""
    t, wt = np.polynomial.legendre.leggauss(n)
    if profile.shape == "semi-elliptic":
        # x = (w/2)(1 - cos θ), θ in (0, π): dx = (w/2) sin θ dθ, p = p_max sin θ
        theta = (t + 1.0) * np.pi / 2.0
        w = profile.width
        return w * (1.0 - np.cos(theta)) / 2.0, wt * np.pi / 2.0 * w / 2.0 * np.sin(theta), profile.peak * np.sin(theta)
    xs, dxs, ps = [], [], []
    theta = (t + 1.0) * np.pi / 2.0
    for a, b, pa, pb in zip(profile.x[:-1], profile.x[1:], profile.pressure[:-1], profile.pressure[1:]):
        if b <= a:
            continue
        if pa == pb:  # a constant piece: integrated exactly
            xs.append(np.array([(a + b) / 2.0]))
            dxs.append(np.array([b - a]))
            ps.append(np.array([pa]))
            continue
        u = (1.0 - np.cos(theta)) / 2.0  # 0..1, gathered at both ends
        xs.append(a + (b - a) * u)
        dxs.append(wt * np.pi / 2.0 * (b - a) * np.sin(theta) / 2.0)
        ps.append(pa + (pb - pa) * u)
    return np.concatenate(xs), np.concatenate(dxs), np.concatenate(ps)


def series_resistance(profile: PressureProfile, sheet_conductance: Callable[[FloatArray], FloatArray], *,
                      rtol: float = RTOL, max_nodes: int = MAX_NODES) -> BandIntegral:
    """R = ∫₀^w dx/σ(p(x)) in Pa·s/m² of a band with sheet conductance σ(p) in m³/(Pa·s) (docs/theory.md §10.1).

    ``sheet_conductance`` maps an array of pressures (Pa, all > 0) to σ (0 where the contact does
    not percolate); σ is assumed to fall as p rises, so the band is sealed exactly when
    σ(p_max) = 0. Strips at zero pressure add no resistance. Nodes are doubled from
    :data:`FIRST_NODES` until R changes by less than ``rtol`` (relative) or ``max_nodes`` is reached.
    """
    p_max = profile.max_pressure
    if float(np.asarray(sheet_conductance(np.array([p_max])))[0]) <= 0:
        x, dx, p = _pieces(profile, FIRST_NODES)
        return BandIntegral(float("inf"), True, True, 0.0, FIRST_NODES, x, dx, p, np.zeros_like(p))
    previous = None
    n = FIRST_NODES
    while True:
        x, dx, p = _pieces(profile, n)
        sigma = np.zeros_like(p)
        pressed = p > 0
        sigma[pressed] = sheet_conductance(p[pressed])
        if np.any(sigma[pressed] <= 0):  # a strip below p_max that does not percolate: σ is not monotone
            return BandIntegral(float("inf"), True, True, 0.0, n, x, dx, p, sigma)
        r = float(np.sum(dx[pressed] / sigma[pressed]))
        change = abs(r - previous) / r if previous is not None and r > 0 else (0.0 if r == 0 else float("inf"))
        if change <= rtol or n >= max_nodes or _constant(profile):
            order = np.argsort(x, kind="stable")
            return BandIntegral(r, False, change <= rtol or _constant(profile), change if previous is not None else 0.0, n,
                                x[order], dx[order], p[order], sigma[order])
        previous = r
        n *= 2


def _constant(profile: PressureProfile) -> bool:
    """Whether every piece is constant (then one level of quadrature is exact)."""
    return profile.shape == "table" and bool(np.all(np.diff(profile.pressure)[np.diff(profile.x) > 0] == 0))


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
