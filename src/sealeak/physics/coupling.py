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
The seal opens (lifts off) where the fluid pressure reaches the contact pressure; it can first do
so at the peak p_max (P0 for a uniform seal), so ΔP ≥ p_max opens the seal: the functions then
return the limit ΔP → p_max and say so (``lifted``). Effective pressures below
:data:`LIFT_OFF_FLOOR` × the peak (an open or barely pressed strip) take σ there: σ grows only
logarithmically as the pressure falls, and Persson's contact theory cannot resolve contact at
vanishing pressure.
"""

from __future__ import annotations

import bisect
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import ode, solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from .profile import PressureProfile, series_resistance

__all__ = ["LIFT_OFF_FLOOR", "CoupledIntegral", "CoupledBand", "effective_pressure_integral", "coupled_band_flow"]

FloatArray = NDArray[np.float64]

#: Lowest effective pressure, relative to the peak contact pressure, at which σ is evaluated (docs/theory.md §13.3).
LIFT_OFF_FLOOR = 1e-6
#: Gauss–Legendre orders tried in turn by :func:`effective_pressure_integral` until two agree to ``rtol``.
ORDERS = (16, 32, 64, 128)
#: Points of the σ(s) table a band solve interpolates (a cubic spline of ln σ in ln s over [floor, p_max]).
TABLE_POINTS = 241


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
    for order in ORDERS:
        v, w = np.polynomial.legendre.leggauss(order)
        v, w = (v + 1.0) / 2.0, w / 2.0
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


class _GaveUp(Exception):
    """The Fortran DOP853 gave up on a piece of the band."""


def _across(slope: Callable[[float, float], float], y: float, dp: float, fortran: bool) -> float:
    """p_f at θ = π of dp_f/dθ = ``slope``(θ, p_f) from p_f(0) = ``y`` (Pa), relative tolerance 1e-10, absolute 1e-12 ΔP.

    Hairer's DOP853 itself (Fortran, through scipy.integrate.ode): the method of solve_ivp's DOP853 without its
    per-step array work (3× faster here). With ``fortran`` False (a lifted band, or a band where the Fortran code gave
    up on some shot: its step fell below rounding, as it can near lift-off, ΔP → p_max) solve_ivp's DOP853, as before;
    raises :class:`_GaveUp` where the Fortran code gives up, so the whole band is shot again with solve_ivp.
    """
    if fortran:
        solver = ode(lambda t, u: slope(t, u[0])).set_integrator("dop853", rtol=1e-10, atol=1e-12 * dp, nsteps=10**6)
        with warnings.catch_warnings():  # (its failure is handled below)
            warnings.filterwarnings("ignore", message="dop853: ", category=UserWarning)
            end = float(solver.set_initial_value(y, 0.0).integrate(math.pi)[0])
        if not solver.successful():
            raise _GaveUp
        return end
    # the step-size control divides 0 by 0 where a step's error vanishes (a flat stretch): not an error
    with np.errstate(invalid="ignore", divide="ignore"):
        sol = solve_ivp(lambda t, u: [slope(t, u[0])], (0.0, np.pi), [y], method="DOP853", rtol=1e-10, atol=1e-12 * dp)
    return float(sol.y[0, -1])


def coupled_band_flow(profile: PressureProfile, sheet_conductance: Callable[[FloatArray], FloatArray],
                      pressure_difference: float, *, rtol: float = 1e-9) -> CoupledBand:
    """The flow per unit length q (m²/s) of a band with the fluid pressure p_f(x) acting on it (docs/theory.md eq. 13.3).

    dp_f/dx = −q / σ(p(x) − p_f(x)) from p_f(0) = ΔP is integrated across the band (DOP853 in θ on
    each piece, relative tolerance 1e-10), and q is found by Brent's method such that p_f(w) = 0; q lies
    between ΔP/R (the band without fluid pressure, R = ∫dx/σ(p)) and a bound found by doubling.
    σ(s) is tabulated (a cubic spline of ln σ in ln s through :data:`TABLE_POINTS` values over
    [:data:`LIFT_OFF_FLOOR` p_max, p_max]); effective pressures outside are clipped to it. ΔP ≥ p_max lifts
    the seal: q is then that of ΔP = p_max. A band whose σ(p_max) = 0 is sealed (q = 0).
    """
    p_max = profile.max_pressure
    floor = LIFT_OFF_FLOOR * p_max
    lifted = pressure_difference >= p_max
    dp = min(float(pressure_difference), p_max)
    s_grid = np.geomspace(floor, p_max, TABLE_POINTS)
    sigma_grid = np.asarray(sheet_conductance(s_grid), dtype=float)
    if not np.all(sigma_grid > 0):
        return CoupledBand(0.0, lifted, True, 0)
    spline = CubicSpline(np.log(s_grid), np.log(sigma_grid))
    lo, hi = float(np.log(floor)), float(np.log(p_max))

    knots = spline.x.tolist()
    pieces_c = [tuple(spline.c[:, i].tolist()) for i in range(len(knots) - 1)]

    def sigma(s: float) -> float:  # the spline at one point, in plain floats (the ODE calls it ~10⁵ times)
        t = min(max(math.log(s) if s > 0 else lo, lo), hi)
        i = min(max(bisect.bisect_right(knots, t) - 1, 0), len(pieces_c) - 1)
        a, b, c, d = pieces_c[i]
        h = t - knots[i]
        return math.exp(((a * h + b) * h + c) * h + d)

    if dp <= 0:
        return CoupledBand(0.0, lifted, True, 0)
    r0 = series_resistance(profile, lambda p: np.exp(spline(np.clip(np.log(p), lo, hi)))).resistance
    pieces = _pieces(profile)
    if not lifted:
        try:
            return _shoot(pieces, sigma, dp, r0, lifted, rtol, fortran=True)
        except _GaveUp:
            pass
    return _shoot(pieces, sigma, dp, r0, lifted, rtol, fortran=False)


def _shoot(pieces: list[tuple[Callable[..., float], Callable[..., float]]], sigma: Callable[[float], float], dp: float,
           r0: float, lifted: bool, rtol: float, fortran: bool) -> CoupledBand:
    """q (m²/s) with p_f(w) = 0 (Pa): a lower bound ΔP/R, an upper one by doubling, then Brent's method; every shot
    integrates across the band by :func:`_across`."""
    shots = 0

    def outlet(q: float) -> float:
        nonlocal shots
        shots += 1
        y = dp
        for dxdt, p in pieces:
            y = _across(lambda t, u: -q * dxdt(t) / sigma(p(t) - u), y, dp, fortran)
        return y / dp

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
