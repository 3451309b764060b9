"""The fluid's own pressure in the sealing band: the coupled flow (docs/theory.md §13).

The fluid pressure p_f(x) inside the band pushes the rubber away from the counterface, so a strip
at nominal contact pressure p(x) is pressed by the effective pressure p(x) − p_f(x) only
(Persson, "Fluid leakage in static rubber seals", Tribol. Lett. 70 (2022), issue 2; Lorenz & Persson (2009) neglect it,
P0 ≫ ΔP). The flux through the band (gauge pressures: p_f = ΔP at the inlet x = 0, 0 at the
outlet x = w) is the same at every x (docs/theory.md eq. 13.1):

    Q = −Ly σ(p(x) − p_f(x)) dp_f/dx

with σ(p) the sheet conductance of either theory (m³/(Pa·s)). For a uniform seal (p = P0) the
substitution s = P0 − p_f separates it (eq. 13.2):

    Q = (Ly/w) ∫_{P0−ΔP}^{P0} σ(s) ds           (:func:`effective_pressure_integral`)

and for a band seal it is an ODE in x solved by shooting on Q (:func:`coupled_band_flow`, eq. 13.3).
A gas conserves its pV throughput instead, Q_pV = −Ly σ(p(x) − (P − P_b)) f(Kn) P dP/dx with the
rarefaction factor f at the local gas pressure P and the local gap (eq. 13.5; :class:`GasSheet`,
:func:`coupled_gas_integral`, :func:`coupled_gas_band_flow`).
The seal opens (lifts off) where the fluid pressure reaches the contact pressure; it can first do
so at the peak p_max (P0 for a uniform seal), so ΔP ≥ p_max opens the seal: the functions then
return the limit ΔP → p_max and say so (``lifted``). Effective pressures below
:data:`LIFT_OFF_FLOOR` × the peak (an open or barely pressed strip) take σ there: σ grows only
logarithmically as the pressure falls, and Persson's contact theory cannot resolve contact at
vanishing pressure.
"""

from __future__ import annotations

import bisect
import hashlib
import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import ode, quad, solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from ._kinetic_slit import capped_rarefactions, poiseuille_flow_rate_at
from .gaps import ArrayCache
from .gas import Gas, bk_pressure_integrand, check_rarefaction_model
from .profile import SIGMA_FLOOR, PressureProfile, series_resistance

__all__ = ["LIFT_OFF_FLOOR", "FLOW_RTOL", "SHOT_RTOL", "CoupledIntegral", "CoupledBand", "effective_pressure_integral", "coupled_band_flow",
           "GasSheet", "gas_sheet", "coupled_gas_integral", "coupled_gas_band_flow"]

FloatArray = NDArray[np.float64]

#: Lowest effective pressure, relative to the peak contact pressure, at which σ is evaluated (docs/theory.md §13.3).
LIFT_OFF_FLOOR = 1e-6
#: Gauss–Legendre orders tried in turn by :func:`effective_pressure_integral` until two agree to ``rtol``.
ORDERS = (16, 32, 64, 128)
#: The Gauss–Legendre nodes and weights of :data:`ORDERS` on [0, 1], computed once.
_LEGENDRE = tuple(((v + 1.0) / 2.0, w / 2.0) for v, w in (np.polynomial.legendre.leggauss(n) for n in ORDERS))
#: Points of the σ(s) table a band solve interpolates (a cubic spline of ln σ in ln s over [floor, p_max]).
TABLE_POINTS = 241
#: Nodes and weights on [−1, 1] of the Gauss–Legendre sum of the Kirchhoff transform in Newton's shooting (:func:`_newton_shoot`).
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(32)
#: Ratio of the bounds ΔP/R(p − ΔP) and ΔP/R(p) on a band's flow above which σ falls by ten decades or more between
#: p − ΔP and p: where Newton's shooting gives up on such a band, no bracketing is tried (docs/theory.md §13.3).
NEAR_SEALED = 1e10
#: Steps of the Fortran DOP853 within which a shot of Newton's method must cross the band (a shot takes ~10²).
NEWTON_STEPS = 2_000
#: FLOW_RTOL: the ``rtol`` of :func:`coupled_band_flow`, the tolerance of its root-finders on q (Newton's method stops at
#: a step in ln q below 10 rtol, :func:`_settled`; Brent's method at rtol). SHOT_RTOL: the relative tolerance of the ODE
#: in each of Newton's shots (DOP853, absolute SHOT_RTOL·10⁻² ΔP). The shots' own error sets q's accuracy, ~10⁻⁶ (on the
#: 50-compression O-ring sweep q moved by at most 6.6·10⁻⁷ from shots at 10⁻¹⁰). Both lie far below the error of the σ
#: the band reads (its spline of ln σ, ~10⁻⁵; the effective medium's tables, 10⁻⁵ in R): until 2026-11-27 they were
#: 10⁻⁹ and 10⁻¹⁰, which cost a quarter more slope evaluations for digits no input holds.
FLOW_RTOL = 1e-7
SHOT_RTOL = 1e-8
#: The tolerance a shot that failed at SHOT_RTOL or LOOSE_RTOL is shot again at (DOP853's step may shrink to nothing
#: in a steep stretch it would follow at a tighter tolerance; a failure is otherwise taken as a flow too large), and of
#: every shot on a near-sealed band (:data:`NEAR_SEALED`), where failures are what brackets the root.
STRICT_RTOL = 1e-10
#: Newton's shots far from the root — the first, and those after a step in ln q above LOOSE_STEP — integrate at this
#: relative tolerance (absolute LOOSE_RTOL·10⁻² ΔP) instead of SHOT_RTOL: their error only moves the next trial flow, by far
#: less than the step; the root is taken from shots at SHOT_RTOL alone.
LOOSE_RTOL = 1e-6
LOOSE_STEP = 1e-2
#: The least curvature C taken for Newton's error C δ² after a step δ in ln q (:func:`_settled`): where the estimate
#: |δ|/δ_prev² of the last two steps is smaller (it ranges from ~1 to ~10³ on the bundled O-rings, inflated where the
#: step before was a loose shot's), this floor keeps the error estimate from trusting a lucky small step.
NEWTON_CURVATURE = 10.0
#: Bytes of solved bands :func:`coupled_band_flow` keeps (by profile, ΔP, tolerance and σ table; ~250 bytes each).
KEPT_BANDS_BYTES = 4 * 2**20

#: Solved bands by a digest of everything the solution depends on (:func:`coupled_band_flow`); cleared with the P(u)
#: rows by :func:`sealeak.physics.gaps.clear_caches`.
_BANDS = ArrayCache(lambda: KEPT_BANDS_BYTES)


@dataclass(frozen=True)
class CoupledIntegral:
    """∫_{P0−ΔP}^{P0} σ(s) ds per row (m³/s per unit of Ly/w), and whether the fluid lifts the seal (ΔP ≥ P0).

    ``change`` is the relative difference of the last two Gauss–Legendre orders (the estimated error).
    """

    value: FloatArray
    lifted: NDArray[np.bool_]
    change: float


def effective_pressure_integral(sheet_conductance: Callable[[FloatArray], FloatArray], squeeze_pressure: ArrayLike,
                                pressure_difference: ArrayLike, *, rtol: float = 1e-9) -> CoupledIntegral:
    """I = ∫_{P0−ΔP}^{P0} σ(s) ds (m³/s) of a uniform seal, per row: Q = (Ly/w) I (docs/theory.md eq. 13.2).

    ``sheet_conductance`` maps pressures (Pa, > 0) to σ (m³/(Pa·s)); P0 and ΔP (Pa) broadcast. Rows
    with ΔP ≥ P0 are lifted: their integral runs from the floor (:data:`LIFT_OFF_FLOOR` P0) to P0, the
    limit ΔP → P0. Gauss–Legendre quadrature in v with s = s_lo + (P0 − s_lo) v² (smooth where the
    lower end approaches zero pressure), the order doubled until the relative change is below ``rtol``.
    """
    p0, dp = np.broadcast_arrays(np.atleast_1d(np.asarray(squeeze_pressure, dtype=float)),
                                 np.atleast_1d(np.asarray(pressure_difference, dtype=float)))
    lifted = dp >= p0
    lo = np.maximum(p0 - dp, LIFT_OFF_FLOOR * p0)
    span = np.maximum(p0 - lo, 0.0)
    value = np.full(p0.shape, np.nan)
    change = float("inf")
    for v, w in _LEGENDRE:
        s = lo[:, None] + span[:, None] * v[None, :] ** 2
        sigma = np.asarray(sheet_conductance(s.ravel()), dtype=float).reshape(s.shape)
        new = np.sum(2.0 * span[:, None] * v[None, :] * sigma * w[None, :], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            rel = np.where(new != 0, np.abs(new - value) / np.abs(new), 0.0)
        change = float(np.nanmax(rel)) if np.isfinite(rel).any() else float("inf")
        value = new
        if change <= rtol:
            break
    return CoupledIntegral(value, lifted, change)


@dataclass(frozen=True)
class CoupledBand:
    """The coupled flow through one band (SI units; docs/theory.md §13.3).

    Attributes
    ----------
    flow
        q = Q/(faces · Ly), the flow per unit length of seal line (m²/s); 0 for a sealed band.
    lifted
        ΔP ≥ p_max: the fluid opens the seal; ``flow`` is then the limit ΔP → p_max.
    converged
        Whether the shooting on q met its tolerance.
    shots
        ODE solves used.
    """

    flow: float
    lifted: bool
    converged: bool
    shots: int


class _Splines:
    """Cubic splines sharing their knots ``t``, with their pieces' coefficients as plain floats for the functions an
    ODE calls ~10⁵ times (:func:`_liquid_slopes`, :attr:`GasSheet.pointwise`; clipped to the knots there)."""

    def __init__(self, t: FloatArray, values: Sequence[FloatArray]) -> None:
        self.splines = [CubicSpline(t, v) for v in values]
        self.knots = t.tolist()
        self.lo, self.hi = float(self.knots[0]), float(self.knots[-1])
        # per piece, per spline, its four coefficients (highest power first) as plain floats, in one conversion
        self.pieces: list[list[list[float]]] = np.stack([sp.c for sp in self.splines]).transpose(2, 0, 1).tolist()


def _pieces(profile: PressureProfile) -> list[tuple[Callable[..., float], Callable[..., float]]]:
    """(dx/dθ (m), p (Pa)) as functions of θ ∈ [0, π] for each piece of the band, inlet to outlet.

    A linear piece [a, b] is x = a + (b − a)(1 − cos θ)/2; the Hertz profile x = (w/2)(1 − cos θ), p = p_max sin θ.
    Plain floats: the ODE calls them ~10⁵ times.
    """
    if profile.shape == "semi-elliptic":
        w, peak = float(profile.width), float(profile.peak)
        return [(lambda t: w * math.sin(t) / 2.0, lambda t: peak * math.sin(t))]
    out: list[tuple[Callable[..., float], Callable[..., float]]] = []
    for a, b, pa, pb in zip(profile.x[:-1].tolist(), profile.x[1:].tolist(), profile.pressure[:-1].tolist(),
                            profile.pressure[1:].tolist(), strict=True):
        if b > a:
            out.append((lambda t, a=a, b=b: (b - a) * math.sin(t) / 2.0,
                        lambda t, pa=pa, pb=pb: pa + (pb - pa) * (1.0 - math.cos(t)) / 2.0))
    return out


def _liquid_slopes(profile: PressureProfile, table: _Splines, *, sensitivity: bool = False,
                   ) -> list[Callable[[float], Callable[[float, FloatArray], Any]]]:
    """For each piece of the band (as :func:`_pieces`) a maker of dp_f/dθ = −q (dx/dθ) / σ(p(θ) − p_f) for a trial q:
    σ the exp of ``table``'s first spline of ln σ in ln s (clipped to its knots; s <= 0 takes the lowest knot).

    The same arithmetic as ``-q * dxdt(t) / sigma(p(t) - u)`` with :func:`_pieces` and the spline of :class:`_Splines`,
    written out in one function of (θ, [p_f]) that the Fortran DOP853 calls directly: the ODE calls it ~10⁵ times, and
    the nested calls cost half of it.

    With ``sensitivity`` the state is [p_f, G], G = ∂p_f/∂ln q (Pa, of the order of p_f), and the slope gains the
    variational equation dG/dθ = f + f (d ln σ/ds) G (f the slope of p_f, ∝ q; ∂f/∂p_f = f σ'(s)/σ(s), s = p − p_f;
    d ln σ/ds = 0 where σ is clipped to the table), for Newton's method in ln q (:func:`_newton_shoot`).
    """
    knots, last = table.knots, len(table.pieces) - 1
    coef = [piece[0] for piece in table.pieces]
    lo, hi = table.lo, table.hi
    exp, log, sin, cos, right = math.exp, math.log, math.sin, math.cos, bisect.bisect_right

    def ln_sigma(s: float) -> float:
        x = min(max(log(s) if s > 0 else lo, lo), hi)
        i = min(max(right(knots, x) - 1, 0), last)
        h = x - knots[i]
        a, b, c, d = coef[i]
        return ((a * h + b) * h + c) * h + d

    def ln_sigma_slope(s: float) -> tuple[float, float]:
        """(ln σ(s), d ln σ/ds) of the clipped spline."""
        x = log(s) if s > 0 else lo
        if lo < x < hi:
            i = min(right(knots, x) - 1, last)
            h = x - knots[i]
            a, b, c, d = coef[i]
            return ((a * h + b) * h + c) * h + d, ((3.0 * a * h + 2.0 * b) * h + c) / s
        return ln_sigma(s), 0.0

    if profile.shape == "semi-elliptic":
        w, peak = float(profile.width), float(profile.peak)
        if sensitivity:
            def hertz_pair(q: float) -> Callable[[float, FloatArray], list[float]]:
                def slope(t: float, u: FloatArray) -> list[float]:
                    pf, g = u.tolist()  # (Python floats: the same arithmetic, faster than NumPy scalars)
                    st = sin(t)
                    ln_s, d_ln_s = ln_sigma_slope(peak * st - pf)
                    f = -q * (w * st / 2.0) / exp(ln_s)
                    return [f, f + f * d_ln_s * g]
                return slope
            return [hertz_pair]

        def hertz(q: float) -> Callable[[float, FloatArray], float]:
            def slope(t: float, u: FloatArray) -> float:
                st = sin(t)
                return -q * (w * st / 2.0) / exp(ln_sigma(peak * st - u[0]))
            return slope
        return [hertz]
    out: list[Callable[[float], Callable[[float, FloatArray], Any]]] = []
    for a, b, pa, pb in zip(profile.x[:-1].tolist(), profile.x[1:].tolist(), profile.pressure[:-1].tolist(),
                            profile.pressure[1:].tolist(), strict=True):
        if b > a:
            if sensitivity:
                def linear_pair(q: float, width: float = b - a, pa: float = pa, rise: float = pb - pa,
                                ) -> Callable[[float, FloatArray], list[float]]:
                    def slope(t: float, u: FloatArray) -> list[float]:
                        pf, g = u.tolist()
                        ln_s, d_ln_s = ln_sigma_slope(pa + rise * (1.0 - cos(t)) / 2.0 - pf)
                        f = -q * (width * sin(t) / 2.0) / exp(ln_s)
                        return [f, f + f * d_ln_s * g]
                    return slope
                out.append(linear_pair)
                continue

            def linear(q: float, width: float = b - a, pa: float = pa, rise: float = pb - pa) -> Callable[[float, FloatArray], float]:
                def slope(t: float, u: FloatArray) -> float:
                    return -q * (width * sin(t) / 2.0) / exp(ln_sigma(pa + rise * (1.0 - cos(t)) / 2.0 - u[0]))
                return slope
            out.append(linear)
    return out


class _GaveUp(Exception):
    """The Fortran DOP853 gave up on a piece of the band."""


def _across(slope: Callable[[float, FloatArray], float], y: float, dp: float, fortran: bool) -> float:
    """p_f at θ = π of dp_f/dθ = ``slope``(θ, [p_f]) from p_f(0) = ``y`` (Pa), relative tolerance 1e-10, absolute 1e-12 ΔP
    (tighter than Newton's shots, :data:`SHOT_RTOL`: Brent's method on the outlet pressure turns its error into an error
    of q some 10⁴ times larger on a band where p_f(w) varies slowly with q; 10⁻⁵ at SHOT_RTOL on a test band).

    Hairer's DOP853 itself (Fortran, through scipy.integrate.ode): the method of solve_ivp's DOP853 without its
    per-step array work (3× faster here). With ``fortran`` False (a lifted band, or a band where the Fortran code gave
    up on some shot: its step fell below rounding, as it can near lift-off, ΔP → p_max) solve_ivp's DOP853, as before;
    raises :class:`_GaveUp` where the Fortran code gives up, so the whole band is shot again with solve_ivp.
    """
    if fortran:
        solver = ode(slope).set_integrator("dop853", rtol=1e-10, atol=1e-12 * dp, nsteps=10**6)
        with warnings.catch_warnings():  # (its failure is handled below)
            warnings.filterwarnings("ignore", message="dop853: ", category=UserWarning)
            end = float(solver.set_initial_value(y, 0.0).integrate(math.pi)[0])
        if not solver.successful():
            raise _GaveUp
        return end
    # the step-size control divides 0 by 0 where a step's error vanishes (a flat stretch), and overflows where a trial
    # flow is far off: not an error
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        sol = solve_ivp(lambda t, u: [slope(t, u)], (0.0, np.pi), [y], method="DOP853", rtol=1e-10, atol=1e-12 * dp)
    return float(sol.y[0, -1])


def coupled_band_flow(profile: PressureProfile, sheet_conductance: Callable[[FloatArray], FloatArray],
                      pressure_difference: float, *, rtol: float = FLOW_RTOL) -> CoupledBand:
    """The flow per unit length q (m²/s) of a band with the fluid pressure p_f(x) acting on it (docs/theory.md eq. 13.3).

    dp_f/dx = −q / σ(p(x) − p_f(x)) from p_f(0) = ΔP is integrated across the band (DOP853 in θ on
    each piece, relative tolerance :data:`SHOT_RTOL`), and q such that p_f(w) = 0 is found by Newton's method on the Kirchhoff
    transform of p_f(w) (:func:`_newton_shoot`), within the bounds ΔP/R[p] ... ΔP/R[p − ΔP] that 0 <= p_f <= ΔP give
    (R = ∫dx/σ). Where the Fortran integrator gives up (as near lift-off) q is bracketed (from ΔP/R[p], doubling) and
    found by Brent's method. A band this shooting cannot follow (no convergence, or a flow outside the bounds: σ
    falling by tens of decades, p_f dropping over a sliver of the width) is solved the other way round, x(p_f)
    (:func:`_solve_inverse`, docs/theory.md §13.3). Where that fails too, ``converged`` is False and q is the upper
    bound ΔP/R[p − ΔP] (the full ΔP acting against the contact everywhere: the flow cannot be larger).
    σ(s) is tabulated (a cubic spline of ln σ in ln s through :data:`TABLE_POINTS` values over
    [:data:`LIFT_OFF_FLOOR` p_max, p_max]); effective pressures outside are clipped to it. ΔP ≥ p_max lifts
    the seal: q is then that of ΔP = p_max. A band whose σ(p_max) = 0 is sealed (q = 0).

    The solution is a function of the profile, ΔP, ``rtol`` and the σ table alone: a band solved once in this process is
    not solved again (kept up to :data:`KEPT_BANDS_BYTES`). Since q ∝ σ at fixed ΔP (p_f(x) does not change when σ is
    multiplied by a constant, docs/theory.md §13.3), a caller that passes σ at a viscosity of 1 Pa·s and divides q by η
    reuses one solution for every viscosity of a liquid.
    """
    p_max = profile.max_pressure
    floor = LIFT_OFF_FLOOR * p_max
    lifted = pressure_difference >= p_max
    dp = min(float(pressure_difference), p_max)
    s_grid = np.geomspace(floor, p_max, TABLE_POINTS)
    sigma_grid = np.asarray(sheet_conductance(s_grid), dtype=float)
    if not np.all(sigma_grid > SIGMA_FLOOR):  # (σ(p_max) = 0, or below the smallest normal double: sealed)
        return CoupledBand(0.0, lifted, True, 0)
    if dp <= 0:
        return CoupledBand(0.0, lifted, True, 0)
    digest = hashlib.blake2b(digest_size=16)
    for part in (np.array([profile.width, p_max, profile.peak, dp, float(lifted), rtol]), profile.x, profile.pressure,
                 sigma_grid):
        digest.update(np.ascontiguousarray(part, dtype=float).tobytes())
    digest.update(profile.shape.encode())
    key = digest.digest()
    kept = _BANDS.get(key)
    if kept is None:
        band = _solve_band(profile, s_grid, sigma_grid, dp, lifted, rtol)
        kept = _BANDS.put(key, (np.array([band.flow, band.converged, band.shots], dtype=float),))
    flow, converged, shots = kept[0].tolist()
    return CoupledBand(flow, lifted, bool(converged), int(shots))


def _solve_band(profile: PressureProfile, s_grid: FloatArray, sigma_grid: FloatArray, dp: float, lifted: bool,
                rtol: float) -> CoupledBand:
    """:func:`coupled_band_flow` of a band with σ ``sigma_grid`` (m³/(Pa·s), all > 0) at ``s_grid`` (Pa) and
    0 < ΔP = ``dp`` <= p_max (Pa), solved."""
    table = _Splines(np.log(s_grid), (np.log(sigma_grid),))
    spline = table.splines[0]
    lo, hi = table.lo, table.hi
    def sigma(p: FloatArray) -> FloatArray:
        """σ(p) of the table (Pa → m³/(Pa·s)), clipped to its knots (p <= 0 takes the lowest)."""
        return np.exp(spline(np.clip(np.log(np.maximum(p, 0.0) + 1e-300), lo, hi)))

    r0 = series_resistance(profile, sigma).resistance
    # 0 <= p_f <= ΔP bounds the effective pressure between p − ΔP and p, so (σ falling with s) q between ΔP/R(p) and
    # ΔP/R(p − ΔP): a shot outside failed to follow the band (σ falling by ten decades or more across it) and is no answer
    r_open = series_resistance(profile, lambda p: sigma(p - dp)).resistance
    bounds = ((1.0 - 1e-6) * dp / r0, (1.0 + 1e-6) * dp / r_open)
    band = None
    if not lifted:
        try:
            band = _newton_shoot(_liquid_slopes(profile, table, sensitivity=True), sigma, float(s_grid[-1]), dp,
                                 dp / r0, bounds, rtol)
        except _GaveUp:
            if bounds[1] > NEAR_SEALED * bounds[0]:  # (p_f drops over less of the band than θ resolves)
                band = CoupledBand(bounds[1], lifted, False, 0)
            else:  # (as near lift-off)
                try:
                    band = _shoot(_liquid_slopes(profile, table), dp, r0, lifted, rtol, fortran=True)
                except _GaveUp:
                    pass
    if band is None:
        band = _shoot(_liquid_slopes(profile, table), dp, r0, lifted, rtol, fortran=False)
    if band.converged and bounds[0] <= band.flow <= bounds[1]:
        return band
    inverse = _solve_inverse(profile, lambda p: math.exp(float(spline(min(max(math.log(p) if p > 0 else lo, lo), hi)))),
                             dp, bounds, rtol)
    shots = band.shots + inverse.shots
    if inverse.converged and bounds[0] <= inverse.flow <= bounds[1]:
        return replace(inverse, lifted=lifted, shots=shots)
    return CoupledBand(bounds[1], lifted, False, shots)


def _solve_inverse(profile: PressureProfile, sigma: Callable[[float], float], dp: float, bounds: tuple[float, float],
                   rtol: float) -> CoupledBand:
    """Eq. 13.3 the other way round, for a band the shooting in x cannot follow (σ falling by tens of decades: p_f
    drops over a sliver of the width): x(τ), τ = ΔP − p_f from 0 to ΔP, from dx/dτ = σ(p(x) − ΔP + τ)/q (smooth where
    σ is tiny), and q within ``bounds`` (m²/s) such that x(ΔP) = w, by Brent's method in ln q. The mismatch is
    (x(ΔP) − w)/w where the flow crosses the band, and the share of ΔP left, p_f/ΔP, where x reaches w first."""
    w = float(profile.width)
    shots = 0

    def mismatch(ln_q: float) -> float:
        nonlocal shots
        shots += 1
        q = math.exp(ln_q)

        def rhs(tau: float, x: FloatArray) -> list[float]:
            return [sigma(float(profile.at(min(float(x[0]), w))) - dp + tau) / q]

        def across(tau: float, x: FloatArray) -> float:
            return float(x[0]) - w
        across.terminal, across.direction = True, 1.0  # type: ignore[attr-defined]
        # a trial flow far too small makes dx/dτ overflow: the step-size control then overflows, divides 0 by 0 and
        # rejects the step, which is its answer, not an error
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            sol = solve_ivp(rhs, (0.0, dp), [0.0], method="DOP853", rtol=1e-10, atol=1e-14 * w, events=across)
        if sol.status == 1:  # reached the outlet with fluid pressure left: q is too small
            return float(dp - sol.t_events[0][0]) / dp
        return float(sol.y[0, -1] - w) / w

    lo, hi = math.log(bounds[0]), math.log(bounds[1])
    if mismatch(lo) <= 0:  # no root between the bounds: not followed either (σ falling by hundreds of decades)
        return CoupledBand(bounds[0], False, False, shots)
    if mismatch(hi) >= 0:
        return CoupledBand(bounds[1], False, False, shots)
    ln_q, info = brentq(mismatch, lo, hi, xtol=rtol, full_output=True)
    return CoupledBand(math.exp(ln_q), False, bool(info.converged), shots)


def _newton_shoot(pairs: list[Callable[[float], Callable[[float, FloatArray], Any]]], sigma: Callable[[FloatArray], FloatArray],
                  p_max: float, dp: float, q0: float, bounds: tuple[float, float], rtol: float) -> CoupledBand:
    """q (m²/s) with p_f(w) = 0 by Newton's method on the Kirchhoff transform of the outlet pressure,
    ψ(p_f(w)) = ∫ σ(s) ds over [p_max − p_f(w), p_max] (docs/theory.md eq. 13.8: exactly linear in q where σ is
    exponential in s, close to linear where ln σ is smooth; zero where p_f(w) is), each shot carrying G = ∂p_f/∂ln q across
    the band (eq. 13.9; ``pairs``, :func:`_liquid_slopes` with ``sensitivity``; DOP853 in Fortran at :data:`SHOT_RTOL`,
    or :data:`LOOSE_RTOL` far from the root), dψ/dq = σ(p_max − p_f(w)) G/q. ``sigma`` is the band's σ(s) (its clipped spline; above p_max
    σ(p_max), so ψ = σ(p_max) p_f(w) where p_f(w) < 0); ψ is a 32-point Gauss–Legendre sum (its accuracy sets the
    speed of convergence, not the root).

    The first shot is the root of (13.8) for an exponential σ, q = ψ(ΔP)/(σ(p_max) R) with R = ΔP/``q0`` the band's
    resistance without fluid pressure (exact for an exponential σ), kept inside ``bounds`` (ΔP/R(p) ... ΔP/R(p − ΔP));
    a step that leaves the bracket of the shots so far takes its false position in q on ψ instead (kept 5 % of the
    bracket in ln q from its ends; bisection in ln q until both ends are shot). Converged when a Newton step from a
    shot at :data:`SHOT_RTOL` is below 10 ``rtol`` relative (the error after it is of the order of its square, and the
    ODE's own error on p_f(w), ~100 SHOT_RTOL ΔP, holds q to ~10⁻⁶ whatever the root-finder), or, without a shot to
    confirm it, when its error C δ² is below rtol/10; either only where the steps left, were Newton converging linearly
    at the rate of the last two, sum to less than rtol (:func:`_settled`).
    Shots far from the root — the first, and those after a step above :data:`LOOSE_STEP` — integrate at
    :data:`LOOSE_RTOL` (about half the slope evaluations; not on a near-sealed band, where the integrator gives up
    just above the root): their error moves the next trial flow by far less than the step.
    2–4 shots where bracketing and Brent's method take 8–15. A near-sealed band shoots at :data:`STRICT_RTOL`
    throughout, and a shot at SHOT_RTOL or LOOSE_RTOL the Fortran code gives up on is shot again at STRICT_RTOL (its step
    may shrink to nothing in a steep stretch it follows at the tighter tolerance). A shot it gives up on at STRICT_RTOL is
    taken as a flow too large (it does so where p_f(w) falls far below zero, σ falling by tens of decades across the band) once a
    smaller flow has crossed it (before, the next shot is ΔP/R); it is a bound, not an answer, so an answer is still a
    shot with a Newton step below the tolerance. Raises :class:`_GaveUp` at the fourth such shot, or where the shot at
    ΔP/R fails (the caller then brackets, with solve_ivp where the Fortran code gives up again, as near lift-off); not
    ``converged`` after 40 shots."""
    lo, hi = math.log(bounds[0]), math.log(bounds[1])
    top = float(sigma(np.array([p_max]))[0])

    def kirchhoff(pf: float) -> float:
        """ψ(p_f)/σ(p_max) (Pa) for p_f > 0."""
        return 0.5 * pf * float(_GAUSS_WEIGHTS @ sigma(p_max - 0.5 * pf * (1.0 + _GAUSS_NODES))) / top

    x = min(max(math.log(q0 * kirchhoff(dp) / dp), lo), hi)
    failed, crossed = 0, False
    psi_lo: float | None = None  # ψ at the ends of the bracket, once shot
    psi_hi: float | None = None
    # far from the root (the first shot, or after a Newton step above LOOSE_STEP) a coarser integration; not on a
    # near-sealed band, whose shots the integrator gives up on just above the root
    steep = hi - lo > math.log(NEAR_SEALED)
    loose = not steep
    previous: float | None = None  # |δ| of the Newton step that gave this trial flow
    again = False  # the same flow once more at STRICT_RTOL: a shot at a looser tolerance failed
    for shots in range(1, 41):
        q = math.exp(x)
        y = [dp, 0.0]
        shot_loose = loose and not again  # (never loose on a near-sealed band: ``loose`` is False there)
        tolerance = STRICT_RTOL if steep or again else LOOSE_RTOL if shot_loose else SHOT_RTOL
        again = False
        rtol_ode, atol_ode = tolerance, tolerance * 1e-2 * dp
        for pair in pairs:
            solver = ode(pair(q)).set_integrator("dop853", rtol=rtol_ode, atol=atol_ode, nsteps=NEWTON_STEPS)
            with warnings.catch_warnings():  # (its failure is handled below)
                warnings.filterwarnings("ignore", message="dop853: ", category=UserWarning)
                y = solver.set_initial_value(y, 0.0).integrate(math.pi).tolist()
            if not solver.successful():
                break
        if not solver.successful() and tolerance > STRICT_RTOL:  # (on a steep test band at 1e-8, below the root)
            again = True
            continue
        if not solver.successful():  # (as where p_f falls by hundreds of decades: taken as a flow too large)
            failed += 1
            start = min(max(math.log(q0), lo), hi)
            if failed > 3 or x <= start:
                raise _GaveUp
            hi, psi_hi = x, None
            x = 0.5 * (lo + x) if crossed else start  # (the bisection needs a shot that has crossed the band)
            previous = None
            continue
        crossed = True
        outlet, g = y  # p_f(w) (Pa) and ∂p_f(w)/∂ln q (Pa)
        if outlet == 0.0:
            return CoupledBand(q, False, True, shots)
        # a loose shot's outlet pressure may have the wrong sign near the root (on a test band at 0.75 p_max one at 1e-6
        # gave −0.025 ΔP where the tight one gives +0.004 ΔP): it moves the trial flow, but only tight shots narrow the
        # bracket, which a wrong end would close on the wrong side of the root
        if outlet > 0:
            psi, d_psi = kirchhoff(outlet), float(sigma(np.array([p_max - outlet]))[0]) / top
        else:
            psi, d_psi = outlet, 1.0
        if not shot_loose and outlet > 0:
            lo, psi_lo = x, psi
        elif not shot_loose:
            hi, psi_hi = x, psi
        ratio = 1.0 - psi / (d_psi * g) if g < 0 else -1.0  # q_new/q of Newton's step in q
        step = math.log(ratio) if ratio > 0 else math.inf
        if not shot_loose and _settled(step, previous, rtol):
            return CoupledBand(math.exp(min(max(x + step, lo), hi)), False, True, shots)
        loose = abs(step) > LOOSE_STEP and not steep
        previous = None
        if shot_loose and not lo < x + step < hi:  # the loose shot's step leaves the bracket: shoot this flow tight
            loose = False  # (rather than bisect a bracket the loose shots have not narrowed)
            continue
        if lo < x + step < hi:
            x += step
            previous = abs(step)
        elif psi_lo is not None and psi_hi is not None:  # false position in q on ψ (nearly linear), off the ends
            q_lo, q_hi = math.exp(lo), math.exp(hi)
            guess = math.log(q_lo + psi_lo * (q_hi - q_lo) / (psi_lo - psi_hi))
            x = min(max(guess, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))
        else:
            x = 0.5 * (lo + hi)
        if hi - lo <= rtol:
            return CoupledBand(math.exp(x), False, True, shots)
    return CoupledBand(math.exp(x), False, False, shots)


def _settled(step: float, previous: float | None, rtol: float) -> bool:
    """Whether Newton's step δ = ``step`` (in ln q) from a shot at :data:`SHOT_RTOL` is the answer, with δ_prev = ``previous`` the
    Newton step that gave this trial flow (None: the trial flow came from elsewhere) and, where the steps shrink, the
    rate ρ = |δ|/δ_prev < 1. Where Newton converges only linearly (as near sealing) the steps left sum to |δ| ρ/(1 − ρ),
    which must be below ``rtol``; then the answer is |δ| <= 10 ``rtol`` (noise: the shots hold q to ~10⁻⁶), or, without
    a shot to confirm it, a step whose error if Newton converges quadratically, C δ² (C the larger of
    :data:`NEWTON_CURVATURE` and |δ|/δ_prev²), is below rtol/10."""
    d = abs(step)
    shrinking = previous is not None and d < previous
    rho = d / previous if previous is not None and shrinking else 0.0
    if shrinking and d * rho / (1.0 - rho) > rtol:
        return False
    if d <= 10.0 * rtol:
        return True
    return shrinking and previous is not None and max(NEWTON_CURVATURE, d / previous**2) * d * d <= 0.1 * rtol


def _shoot(slopes: list[Callable[[float], Callable[[float, FloatArray], float]]], dp: float, r0: float, lifted: bool,
           rtol: float, fortran: bool) -> CoupledBand:
    """q (m²/s) with p_f(w) = 0 (Pa): a lower bound ΔP/R, an upper one by doubling, then Brent's method; every shot
    integrates across the band's pieces (``slopes``, :func:`_liquid_slopes`) by :func:`_across`. A flow shot once is
    not shot again (Brent's method starts from the two ends of the bracket, both shot already)."""
    shots = 0
    known: dict[float, float] = {}

    def outlet(q: float) -> float:
        nonlocal shots
        if q not in known:
            shots += 1
            y = dp
            for slope in slopes:
                y = _across(slope(q), y, dp, fortran)
            known[q] = y / dp
        return known[q]

    q_lo = dp / r0
    if outlet(q_lo) <= 0:
        return CoupledBand(q_lo, lifted, True, shots)
    q_hi = 2.0 * q_lo
    while outlet(q_hi) > 0:
        q_lo, q_hi = q_hi, 2.0 * q_hi
        if shots > 80:
            return CoupledBand(q_hi, lifted, False, shots)
    q, info = brentq(outlet, q_lo, q_hi, xtol=1e-12 * q_lo, rtol=rtol, full_output=True)
    return CoupledBand(float(q), lifted, bool(info.converged), shots)


# ---------------------------------------------------------------------- gases (docs/theory.md §13.5)
#: The sheet of one theory at effective pressures s (Pa, an array): its σ(s) (m³/(Pa·s), with the gas's viscosity),
#: the gap h(s) of its narrowest constriction (m) and that constriction's length L(s) along the flow (m; NaN: an infinite slit).
Sheet = Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray]]


@dataclass(frozen=True)
class GasSheet:
    """The pV sheet conductance of a gas in one theory's contact, g(s, P) = σ(s) P f(Kn) (m³/s; docs/theory.md eq. 13.5).

    σ(s), the gap h(s) and the kinetic cap δ_ℓ(s) of the slit length ℓ = L(s)/h(s) are cubic splines in ln s
    through :data:`TABLE_POINTS` values over [``low``, ``high``] (effective pressures outside are clipped to it);
    Kn = λ(P)/h(s) is the gas's at the absolute pressure P. ``scale`` multiplies σ (another viscosity:
    σ ∝ 1/μ). Build the contact's tables with :func:`gas_sheet` (no-slip, no gas); :meth:`for_gas` names the gas.
    """

    tables: _Splines
    finite: bool
    gas: Gas | None = None
    model: str = "no-slip"
    scale: float = 1.0

    def for_gas(self, gas: Gas, model: str, scale: float) -> GasSheet:
        """The same contact and gaps with ``gas``, rarefaction ``model`` and σ multiplied by ``scale`` (μ_old/μ_new)."""
        check_rarefaction_model(model)
        return replace(self, gas=gas, model=model, scale=scale)

    def __call__(self, s: float, p: float) -> float:
        """g(s, P) in m³/s at the effective contact pressure s (Pa) and the absolute gas pressure P (Pa, >= 0)."""
        return self.pointwise(s, p)

    @cached_property
    def pointwise(self) -> Callable[[float, float], float]:
        """g(s, P) (m³/s) as one function of plain floats, its constants taken once (an ODE calls it ~10⁵ times):
        the three splines of :attr:`tables` share their knots, so the piece is found once for all three."""
        knots, pieces, last = self.tables.knots, self.tables.pieces, len(self.tables.pieces) - 1
        lo, hi = self.tables.lo, self.tables.hi
        scale, model, finite = self.scale, self.model, self.finite
        exp, log, right, sqrt_pi = math.exp, math.log, bisect.bisect_right, math.sqrt(math.pi)
        if model != "no-slip":
            assert self.gas is not None, "a rarefied sheet needs its gas (for_gas)"
            lambda_p = self.gas.rarefaction_pressure_scale  # λ P (Pa·m): Kn = c/P with c = λ P/h

        def g(s: float, p: float) -> float:
            x = min(max(log(s) if s > 0 else lo, lo), hi)
            i = min(max(right(knots, x) - 1, 0), last)
            h = x - knots[i]
            (a1, b1, c1, d1), (a2, b2, c2, d2), (a3, b3, c3, d3) = pieces[i]
            sigma = scale * exp(((a1 * h + b1) * h + c1) * h + d1)
            if model == "no-slip":
                return sigma * p
            c = lambda_p / exp(((a2 * h + b2) * h + c2) * h + d2)  # Kn = c/P
            if model == "beskok-karniadakis":
                return sigma * bk_pressure_integrand(p, c)
            # kinetic: P f = (12 c/√π) G_P(max(δ, δ_ℓ)), δ = (√π/2) P/c (docs/theory.md §11.5); an infinite slit's
            # G_P diverges (integrably) at P = 0: δ is kept above 1e-12
            delta = max(0.5 * sqrt_pi * p / c, exp(((a3 * h + b3) * h + c3) * h + d3) if finite else 1e-12)
            return sigma * 12.0 * c / sqrt_pi * poiseuille_flow_rate_at(delta)
        return g


def gas_sheet(sheet: Sheet, low: float, high: float) -> GasSheet | None:
    """The :class:`GasSheet` of ``sheet`` (σ, h, L at effective pressures, Pa) over [``low``, ``high``] (Pa), or None
    where σ vanishes somewhere in that range (the contact seals); no-slip until :meth:`GasSheet.for_gas`."""
    s = np.geomspace(min(low, 0.5 * high), high, TABLE_POINTS)
    sigma, gap, length = (np.asarray(v, dtype=float) for v in sheet(s))
    if not (np.all(sigma > SIGMA_FLOOR) and np.all(np.isfinite(gap) & (gap > 0))):
        return None
    finite = bool(np.all(np.isfinite(length) & (length > 0)))
    cap = np.log(capped_rarefactions(length / gap)) if finite else np.zeros(s.size)
    return GasSheet(_Splines(np.log(s), (np.log(sigma), np.log(gap), cap)), finite)


def coupled_gas_integral(sheet: GasSheet, squeeze_pressure: ArrayLike, downstream_pressure: float,
                         pressure_difference: float, *, rtol: float = 1e-10) -> CoupledIntegral:
    """I = ∫_{P_b}^{P_a} g(P0 − (P − P_b), P) dP (Pa·m³/s per unit of Ly/w) of a uniform seal, per row P0 (Pa):
    Q_pV = (Ly/w) I (docs/theory.md eq. 13.6).

    ``downstream_pressure`` P_b and ``pressure_difference`` ΔP = P_a − P_b (Pa). Rows with ΔP ≥ P0 are lifted and
    integrated to the limit ΔP → P0 (effective pressures down to :data:`LIFT_OFF_FLOOR` P0). Adaptive quadrature
    (scipy.integrate.quad, relative tolerance ``rtol``) in v with s = s_lo + (P0 − s_lo) v², as
    :func:`effective_pressure_integral`; ``change`` is the largest estimated relative error.
    """
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    lifted = pressure_difference >= p0
    value = np.empty(p0.size)
    change = 0.0
    for i, top in enumerate(p0.tolist()):
        lo = max(top - pressure_difference, LIFT_OFF_FLOOR * top)
        span = top - lo

        def integrand(v: float, lo: float = lo, span: float = span, top: float = top) -> float:
            s = lo + span * v * v
            return 2.0 * span * v * sheet(s, downstream_pressure + top - s)

        if span > 0:  # full_output: quad's roundoff message stays here (``change`` reports the error)
            value[i], err, *_ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=rtol, limit=200, full_output=1)
        else:
            value[i], err = 0.0, 0.0
        change = max(change, err / value[i] if value[i] > 0 else 0.0)
    return CoupledIntegral(value, lifted, change)


def coupled_gas_band_flow(profile: PressureProfile, sheet: GasSheet | None, downstream_pressure: float,
                          pressure_difference: float, *, rtol: float = FLOW_RTOL) -> CoupledBand:
    """The pV flow per unit length q (Pa·m²/s) of a band with the gas pressure acting on it (docs/theory.md eq. 13.7).

    In y = P² (regular at a vacuum outlet), dy/dx = −2 q P/g(p(x) − (P − P_b), P) is integrated across the band
    from y = P_a² (DOP853 in θ on each piece, as :func:`coupled_band_flow`, relative tolerance 1e-10, absolute
    1e-12 P_a²; y below 0 continues with P = √|y|; Hairer's Fortran code, or solve_ivp's DOP853 for a shot it gives
    up on, :func:`_across`), and q is found by Brent's method to ``rtol`` such that P(w) = P_b (P = ±√|y|),
    bracketed by doubling or halving from the uniform seal at the mean pressure. ``sheet`` None (σ(p_max) = 0):
    sealed, q = 0. ΔP ≥ p_max lifts the seal: q is then that of ΔP = p_max.

    ``rtol`` is :data:`FLOW_RTOL` (10⁻⁷), the shots' own noise: near a vacuum outlet P = √y turns y's absolute
    tolerance into an error of ~10⁻⁷ ΔP on P(w), and Brent's steps below it follow that noise (until 2026-11-28
    ``rtol`` was 10⁻⁹: 15–21 shots a band where 7–10 reach the same q within 10⁻⁷).
    """
    p_max, w = profile.max_pressure, profile.width
    lifted = pressure_difference >= p_max
    dp = min(float(pressure_difference), p_max)
    if sheet is None or dp <= 0:
        return CoupledBand(0.0, lifted, True, 0)
    g = sheet.pointwise
    pb, pa = float(downstream_pressure), float(downstream_pressure) + dp
    pieces = _pieces(profile)
    shots = 0

    def slope(q: float, dxdt: Callable[..., float], p: Callable[..., float]) -> Callable[[float, FloatArray], float]:
        def rhs(t: float, u: FloatArray) -> float:
            gas = math.sqrt(abs(u[0]))
            return -2.0 * q * dxdt(t) * gas / g(p(t) - (gas - pb), gas) if gas > 0 else 0.0
        return rhs

    def mismatch(q: float) -> float:
        nonlocal shots
        shots += 1
        for fortran in (True, False):  # (solve_ivp for a shot the Fortran code gives up on)
            y = pa * pa
            try:
                for dxdt, p in pieces:
                    y = _across(slope(q, dxdt, p), y, pa * pa, fortran)
                break
            except _GaveUp:
                continue
        return (math.copysign(math.sqrt(abs(y)), y) - pb) / dp  # in P, not y: linear in q on both sides of the root

    q0 = float(coupled_gas_integral(sheet, profile.mean_pressure, pb, dp).value[0]) / w
    m0 = mismatch(q0)
    step = 2.0 if m0 > 0 else 0.5
    while m0 != 0:
        q1 = q0 * step
        m1 = mismatch(q1)
        if (m1 > 0) != (m0 > 0):
            q, info = brentq(mismatch, min(q0, q1), max(q0, q1), xtol=1e-12 * q0, rtol=rtol, full_output=True)
            return CoupledBand(float(q), lifted, bool(info.converged), shots)
        if shots > 60:
            return CoupledBand(q1, lifted, False, shots)
        q0, m0 = q1, m1
    return CoupledBand(q0, lifted, True, shots)
