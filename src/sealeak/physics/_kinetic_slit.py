"""Kinetic-theory flow rate of a rarefied gas through a slit (plane channel), docs/theory.md §11.4.

Two dimensionless functions, both tabulated here and interpolated by monotone cubics (PCHIP; G_P in δ,
so that its integral, which the flow along a pressure drop needs, is exact; G_fm in ln ℓ), with the
published asymptotes outside the tables:

* G_P(δ), the Poiseuille flow rate of an infinite plane channel of height h from the linearized BGK
  kinetic equation with diffuse walls (Cercignani & Daneri 1963, *J. Appl. Phys.* 34, 3509; reviewed by
  Sharipov & Seleznev 1998, *J. Phys. Chem. Ref. Data* 27, 657, plane channel). δ = p h/(μ v0),
  v0 = √(2 R_s T) (Sharipov's rarefaction parameter); the mass flow per unit width is
  ṁ = (h²/v0) G_P (−dp/dx), which is h³ p/(12 μ R_s T) (−dp/dx) · 6 G_P/δ.
* G_fm(ℓ), the free-molecular value of the same quantity for a slit of finite length L = ℓ h between
  two reservoirs: G_fm = ℓ W(ℓ)/√π with W the Clausing transmission probability of the two-dimensional
  slot with diffuse walls (Clausing 1932, *Ann. Phys.* 404, 961; the slot's integral equation as in Berman
  1965, *J. Appl. Phys.* 36, 3365).

Sources of the numbers. The tables were computed for sealeak by ``tools/kinetic_slit_tables.py``: G_P
from Cercignani's integral equation of the BGK Poiseuille problem (Cercignani 1975, *Theory and
Application of the Boltzmann Equation*, ch. V; Sharipov & Seleznev 1998, eq. for the plane channel),
W from the slot's Clausing equation, both by product integration (exact cell integrals of the
kernels) with Richardson extrapolation (estimated error below 1e-4 relative for G_P, below 1e-3 for
G_fm). Checks against published values: G_P(1) = 1.5389 (Cercignani & Daneri 1963; here 1.53868),
the slip asymptote G_P → δ/6 + σ_P with σ_P = 1.0162 (the BGK viscous slip coefficient, Sharipov &
Seleznev 1998; the table minus δ/6 + σ_P at δ = 50 is 0.0204, as the interpolation formula of Fukui &
Kaneko 1990, *J. Tribol.* 112, 78, gives; that formula and the table agree within 1 % for δ >= 0.15), and the free-molecular
asymptote G_P → −ln(δ)/√π + 3(1 − γ)/(2√π) (Cercignani 1975; γ Euler's constant), which the
solution approaches to 6e-5 at δ = 1e-6. Numerically exact BGK results of this kind: Loyalka,
Petrellis & Storvick 1975, *ZAMP*.
"""

from __future__ import annotations

import bisect
import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PchipInterpolator
from scipy.optimize import minimize_scalar

__all__ = ["SIGMA_P", "FREE_MOLECULAR_CONSTANT", "poiseuille_flow_rate", "finite_slit_free_molecular",
           "knudsen_minimum", "capped_rarefaction", "capped_rarefactions",
           "finite_slit_free_molecular_many", "flow_rate_integral", "pressure_integral", "poiseuille_flow_rate_at"]

FloatArray = NDArray[np.float64]

#: σ_P: the BGK viscous slip coefficient with diffuse walls in the units of Sharipov's free path μ v0/p
#: (Sharipov & Seleznev 1998): G_P = δ/6 + σ_P + O(1/δ) for δ → ∞.
SIGMA_P = 1.0162

#: The constant of Cercignani's free-molecular asymptote G_P = −ln(δ)/√π + C + O(δ ln²δ), δ → 0:
#: C = 3(1 − γ)/(2√π) ≈ 0.3578 (γ = 0.5772... Euler's constant).
FREE_MOLECULAR_CONSTANT = 1.5 * (1.0 - float(np.euler_gamma)) / math.sqrt(math.pi)

#: log10 δ of the G_P table: −4.0, −3.9, ..., 1.7 (δ from 1e-4 to 50).
_LOG10_DELTA = np.round(np.arange(-40, 18) / 10.0, 1)
#: G_P(δ) of the plane channel, linearized BGK, diffuse walls (module docstring).
_G_P = np.array([
    5.557295, 5.428015, 5.298856, 5.169842, 5.040998, 4.912355, 4.783948, 4.655819,
    4.528015, 4.400591, 4.273609, 4.147143, 4.021272, 3.89609, 3.771703, 3.648226,
    3.525793, 3.404549, 3.284656, 3.166291, 3.04965, 2.934943, 2.822399, 2.712263,
    2.604796, 2.500276, 2.398998, 2.301269, 2.207415, 2.117778, 2.032714, 1.952604,
    1.877852, 1.808892, 1.746204, 1.690319, 1.641849, 1.601503, 1.570131, 1.548764,
    1.538679, 1.541476, 1.559184, 1.594393, 1.650423, 1.731542, 1.843233, 1.992527,
    2.188406, 2.442293, 2.768649, 3.185711, 3.716432, 4.389665, 5.241698, 6.318209,
    7.676725, 9.389719,
])
#: ℓ = L/h of the G_fm table.
_LENGTH_RATIO = np.array([1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 50.0, 70.0, 100.0, 150.0, 200.0,
                          300.0, 500.0])
#: G_fm(ℓ) = ℓ W(ℓ)/√π of the finite slot, free-molecular, diffuse walls (module docstring).
_G_FM = np.array([
    0.3861207, 0.5098681, 0.6116473, 0.7737603, 1.005416, 1.171719, 1.357224, 1.576713,
    1.736459, 1.965403, 2.257615, 2.451242, 2.656865, 2.890633, 3.056338, 3.289533,
    3.582639,
])

_LN_DELTA = _LOG10_DELTA * math.log(10.0)
_SQRT_PI = math.sqrt(math.pi)
_GP_SPLINE = PchipInterpolator(np.exp(_LN_DELTA), _G_P, extrapolate=False)
_H_SPLINE = _GP_SPLINE.antiderivative()
_FM_SPLINE = PchipInterpolator(np.log(_LENGTH_RATIO), _G_FM, extrapolate=False)
_D_LO, _D_HI = math.exp(_LN_DELTA[0]), math.exp(_LN_DELTA[-1])
#: Matching of the asymptotes to the ends of the table (continuous G_P): the O(1/δ) term of the slip
#: side, a/δ, and the O(δ ln²δ) term of the free-molecular side, b δ ln²δ.
_A_HI = (_G_P[-1] - _D_HI / 6.0 - SIGMA_P) * _D_HI
_B_LO = (_G_P[0] + _LN_DELTA[0] / math.sqrt(math.pi) - FREE_MOLECULAR_CONSTANT) / (_D_LO * _LN_DELTA[0] ** 2)
#: Beyond the G_fm table: G_fm = (ln ℓ + c)/√π with c matched to the last entry.
_C_FM = _G_FM[-1] * math.sqrt(math.pi) - math.log(_LENGTH_RATIO[-1])


def poiseuille_flow_rate(delta: ArrayLike) -> FloatArray:
    """G_P(δ) (dimensionless) of an infinite slit for the rarefaction parameter δ = p h/(μ v0) >= 0.

    Inside the table (1e-4 <= δ <= 50) a monotone cubic in δ (within 1.5e-4 of the kinetic solution
    between the table's points); above it the slip asymptote
    δ/6 + σ_P + a/δ, below it Cercignani's free-molecular asymptote −ln(δ)/√π + C + b δ ln²δ, a and b
    matched to the table's ends. G_P(0) = inf (the infinite slit's free-molecular flow diverges).
    """
    d = np.asarray(delta, dtype=float)
    out = np.empty(d.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        ln_d = np.log(d)
        hi, lo = d > _D_HI, d < _D_LO
        mid = ~(hi | lo)
        out[mid] = _GP_SPLINE(d[mid])
        out[hi] = d[hi] / 6.0 + SIGMA_P + _A_HI / d[hi]
        lo_d, lo_ln = d[lo], ln_d[lo]
        out[lo] = np.where(lo_d > 0, -lo_ln / math.sqrt(math.pi) + FREE_MOLECULAR_CONSTANT + _B_LO * lo_d * lo_ln**2,
                           np.inf)
    return out


_GP_KNOTS = _GP_SPLINE.x.tolist()
_GP_PIECES = [tuple(_GP_SPLINE.c[:, i].tolist()) for i in range(len(_GP_KNOTS) - 1)]


def poiseuille_flow_rate_at(delta: float) -> float:
    """:func:`poiseuille_flow_rate` at one δ in plain floats, the asymptotes outside the table included (an ODE calls
    it ~10⁵ times)."""
    if delta > _D_HI:
        return delta / 6.0 + SIGMA_P + _A_HI / delta
    if delta < _D_LO:
        if delta > 0:
            ln_d = math.log(delta)
            return -ln_d / _SQRT_PI + FREE_MOLECULAR_CONSTANT + _B_LO * delta * ln_d**2
        return math.inf  # (as the array function: G_P(0) = inf)
    i = min(bisect.bisect_right(_GP_KNOTS, delta) - 1, len(_GP_PIECES) - 1)
    a, b, c, d = _GP_PIECES[i]
    h = delta - _GP_KNOTS[i]
    return ((a * h + b) * h + c) * h + d


def finite_slit_free_molecular(length_ratio: float) -> float:
    """G_fm(ℓ) (dimensionless): the free-molecular flow rate of a slit of length ℓ = L/h >= 1 (heights),
    ℓ W(ℓ)/√π with W the Clausing transmission probability; (ln ℓ + c)/√π beyond the table (ℓ > 500)."""
    return float(finite_slit_free_molecular_many(np.array([float(length_ratio)]))[0])


def finite_slit_free_molecular_many(length_ratio: ArrayLike) -> FloatArray:
    """:func:`finite_slit_free_molecular` of every ℓ in an array (the same numbers, one call)."""
    ell = np.asarray(length_ratio, dtype=float)
    inside = ell <= _LENGTH_RATIO[-1]
    far = (np.log(np.where(inside, _LENGTH_RATIO[-1], ell)) + _C_FM) / _SQRT_PI
    return np.where(inside, _FM_SPLINE(np.log(np.clip(ell, 1.0, _LENGTH_RATIO[-1]))), far)


def _minimum() -> tuple[float, float]:
    res = minimize_scalar(lambda x: float(_GP_SPLINE(x)), bounds=(0.3, 3.0), method="bounded", options={"xatol": 1e-12})
    return float(res.x), float(res.fun)


_DELTA_MIN, _G_MIN = _minimum()


def knudsen_minimum() -> tuple[float, float]:
    """(δ, G_P) at the Knudsen minimum of the infinite slit's flow rate (δ ≈ 1, G_P ≈ 1.54)."""
    return _DELTA_MIN, _G_MIN


def capped_rarefactions(length_ratio: ArrayLike) -> FloatArray:
    """δ_ℓ of :func:`capped_rarefaction` for every ℓ in an array, by bisection in ln δ on all at once (a gas sheet
    needs it at some 240 lengths; root found to 10⁻¹² in ln δ, as the scalar function's)."""
    g_cap = finite_slit_free_molecular_many(length_ratio)
    short = g_cap <= _G_MIN
    # G_P(e^x) − g_cap decreases in x below the minimum; at x = lo it is ≈ 1 + C > 0 (free-molecular asymptote)
    lo = np.where(short, 0.0, -_SQRT_PI * (g_cap + 1.0))
    hi = np.where(short, 0.0, math.log(_DELTA_MIN))
    # each δ_ℓ halves its own bracket until it is below 1e-12 (its number the same whatever the others'); a width of
    # 2⁶⁰ takes 100 halvings; an infinite ℓ stays at δ_ℓ = 0, the infinite slit
    for _ in range(200):
        going = hi - lo > 1e-12
        if not going.any():
            break
        mid = 0.5 * (lo + hi)
        above = poiseuille_flow_rate(np.exp(mid)) > g_cap
        lo, hi = np.where(going & above, mid, lo), np.where(going & ~above, mid, hi)
    return np.where(short, _DELTA_MIN, np.exp(0.5 * (lo + hi)))


@functools.lru_cache(maxsize=4096)
def capped_rarefaction(length_ratio: float) -> float:
    """δ_ℓ: the smallest rarefaction parameter a slit of length ℓ = L/h sees (docs/theory.md §11.4).

    The infinite slit's G_P grows without bound as δ → 0; a slit of length L cannot carry more than
    its free-molecular flow G_fm(ℓ). δ_ℓ solves G_P(δ_ℓ) = G_fm(ℓ) on the free-molecular side of the
    Knudsen minimum, and the flow rate of the finite slit is G_P(max(δ, δ_ℓ)); a slit too short to
    reach the minimum's flow (G_fm(ℓ) <= min G_P) gets δ_ℓ at the minimum. The numbers of
    :func:`capped_rarefactions`, at one ℓ.
    """
    return float(capped_rarefactions(np.array([float(length_ratio)]))[0])


def _low_integral(d: FloatArray) -> FloatArray:
    """∫_0^δ of the free-molecular asymptote −ln(t)/√π + C + b t ln²t, δ > 0."""
    ln_d = np.log(d)
    return (-(d * ln_d - d) / math.sqrt(math.pi) + FREE_MOLECULAR_CONSTANT * d
            + _B_LO * (0.5 * d**2 * ln_d**2 - 0.5 * d**2 * ln_d + 0.25 * d**2))


_H_LO = float(_low_integral(np.array(_D_LO)))
_H_HI = _H_LO + float(_H_SPLINE(_D_HI))


def flow_rate_integral(delta: ArrayLike, delta_cap: float = 0.0) -> FloatArray:
    """H(δ) = ∫_0^δ G_P(max(t, δ_ℓ)) dt (dimensionless) for δ >= 0; ``delta_cap`` δ_ℓ (0: an infinite slit).

    Exact for the interpolant and the asymptotes of :func:`poiseuille_flow_rate` (finite at δ = 0 although
    G_P is not: −ln t is integrable).
    """
    d = np.asarray(delta, dtype=float)
    if delta_cap > 0.0:
        g_cap = float(poiseuille_flow_rate(delta_cap))
        free = flow_rate_integral(np.maximum(d, delta_cap)) - float(flow_rate_integral(delta_cap)) + g_cap * delta_cap
        return np.where(d <= delta_cap, g_cap * d, free)
    out = np.zeros(d.shape)
    lo, hi = (d > 0) & (d < _D_LO), d > _D_HI
    mid = (d >= _D_LO) & ~hi
    out[lo] = _low_integral(d[lo])
    out[mid] = _H_LO + _H_SPLINE(d[mid])
    dh = d[hi]
    out[hi] = _H_HI + (dh**2 - _D_HI**2) / 12.0 + SIGMA_P * (dh - _D_HI) + _A_HI * np.log(dh / _D_HI)
    return out


def pressure_integral(knudsen_scale: ArrayLike, upper: ArrayLike, lower: ArrayLike, delta_cap: float = 0.0) -> FloatArray:
    """∫_{lower}^{upper} p f(c/p) dp in Pa² for the kinetic f = 6 G_P/δ, δ = (√π/2) p/c: (24 c²/π) (H(δ_u) − H(δ_l)).

    ``knudsen_scale`` c = λ p/h (Pa) makes Kn = c/p; ``upper`` >= ``lower`` >= 0 absolute pressures (Pa);
    ``delta_cap`` δ_ℓ of a finite slit (:func:`capped_rarefaction`; 0: an infinite slit). c = 0 gives the
    no-slip (upper² − lower²)/2. Broadcasts.
    """
    c, a, b = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (knudsen_scale, upper, lower)))
    out = np.asarray(0.5 * (a - b) * (a + b), dtype=float).copy()
    rare = c > 0
    if rare.any():
        k = 0.5 * math.sqrt(math.pi) / c[rare]
        cs = c[rare]
        out[rare] = 24.0 * cs**2 / math.pi * (flow_rate_integral(k * a[rare], delta_cap)
                                                - flow_rate_integral(k * b[rare], delta_cap))
    return out
