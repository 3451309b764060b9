"""Special functions of the Persson-theory separation integral (private).

The inner pressure integral of ū(ζ) (docs/theory.md §2.7–§2.8) reduces, with y = s p, x = s p', to

    F(y) = ∫_y^∞ dx/x [γ + 3(1-γ) erf²(x)] e^(-x²) = γ E1(y²)/2 + 3(1-γ) K(y)
    K(y) = ∫_y^∞ erf²(x) e^(-x²)/x dx
    F'(y) = -[γ + 3(1-γ) erf²(y)] e^(-y²)/y

E1 is scipy.special.exp1. K is smooth and finite on [0, ∞) (erf²(x)/x ~ 4x/π at small x). It is
tabulated once on y ∈ [0, Y] with spacing h = Y/N: the table values come from 12-point
Gauss–Legendre on every interval, summed from Y downwards, K(Y) = E1(Y²)/2 (1 - erf² < 1e-30 there);
between nodes a cubic Hermite interpolant uses the exact derivative K'(y) = -erf²(y) e^(-y²)/y.
With Y = 6.5 and N = 2600 the interpolation error is below 1e-12 (checked in the tests against
adaptive quadrature). For y > Y, K(y) = E1(y²)/2 to double precision.

E1 itself (:func:`exp1`, the cost of the separation integrals) is evaluated through g(x) = eˣ E1(x),
which is smooth and slowly varying in v = ln x (g ≈ -γ_E - v at small x, g ≈ 1/x at large x;
Abramowitz & Stegun 5.1.11 and 5.1.51): a cubic Hermite table of g against v on 1e-2 <= x <= 700
with 1024 intervals per unit of v, exact derivative dg/dv = x g - 1 (from dE1/dx = -e^(-x)/x);
relative error below 5e-15 (h⁴/384 times g's relative fourth v-derivative, which is of order one;
checked against scipy.special.exp1 in the tests). Below x = 1e-2 the convergent series
E1(x) = -γ_E - ln x - Σ_{k>=1} (-x)^k/(k·k!) (A&S 5.1.11) to x⁵ (remainder < x⁶/4320 < 3e-16);
above x = 700 (E1 < 1e-306) the asymptotic series of eˣ E1(x) to 1/x⁷ (A&S 5.1.51). About 8x faster than
scipy.special.exp1.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy import special


@lru_cache(maxsize=8)
def gauss_legendre(order: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss–Legendre abscissae and weights of ``order`` points on [-1, 1] (read-only; computed once per order)."""
    x, w = np.polynomial.legendre.leggauss(order)
    x.setflags(write=False)
    w.setflags(write=False)
    return x, w

_Y_MAX = 6.5
_N = 2600
_H = _Y_MAX / _N


def _k_integrand(x: NDArray[np.float64]) -> NDArray[np.float64]:
    xs = np.where(x > 0, x, 1.0)
    return np.where(x > 0, special.erf(xs) ** 2 * np.exp(-(xs**2)) / xs, 0.0)


def weighted_sum(values: NDArray[np.float64], weights: NDArray[np.float64], axis: int = -1) -> NDArray[np.float64]:
    """Σ_j w_j v_j over the first (``axis = 0``) or last (``axis = -1``) axis of ``values``, added in a fixed order.

    The quadrature sums of the physics use this rather than a matrix product: BLAS kernels may add
    in an order that depends on the arrays' alignment in memory, so the same inputs could give
    results that differ in the last bit from one call (or run) to the next. Here each term is an
    element-wise product added element-wise, j = 0, 1, ...: the same bits every time.
    """
    w = np.asarray(weights, dtype=float)
    v = np.asarray(values, dtype=float)
    if axis != 0:
        v = np.moveaxis(v, axis, 0)
    out = v[0] * w[0]
    for j in range(1, w.size):
        out += v[j] * w[j]
    return out


def _build_table() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    nodes, weights = np.polynomial.legendre.leggauss(12)
    edges = np.linspace(0.0, _Y_MAX, _N + 1)
    a, b = edges[:-1, None], edges[1:, None]
    x = 0.5 * (b - a) * nodes[None, :] + 0.5 * (a + b)
    piece = 0.5 * (b[:, 0] - a[:, 0]) * weighted_sum(_k_integrand(x), weights)
    tail = 0.5 * special.exp1(_Y_MAX**2)
    values = tail + np.concatenate([np.cumsum(piece[::-1])[::-1], [0.0]])
    slopes = -_k_integrand(edges)
    values.setflags(write=False)
    slopes.setflags(write=False)
    return values, slopes


_K_VALUES, _K_SLOPES = _build_table()

_E1_X_LO, _E1_X_HI = 1e-2, 700.0
_E1_V0 = float(np.log(_E1_X_LO))
_E1_PER_UNIT = 1024
_E1_N = int(np.ceil((np.log(_E1_X_HI) - _E1_V0) * _E1_PER_UNIT))
_E1_H = (float(np.log(_E1_X_HI)) - _E1_V0) / _E1_N
_EULER = 0.57721566490153286061


def _build_e1_table() -> tuple[NDArray[np.float64], ...]:
    """Cubic coefficients a0..a3 of g(V0 + (i + τ) h) = a0 + τ(a1 + τ(a2 + τ a3)) per interval i, 0 <= τ <= 1.

    The Hermite cubic through g and h dg/dv at both ends of every interval (g = eˣ E1(x), x = e^v, values from
    scipy.special.exp1); one interval more than the range, so that v at the upper end (τ = 0 there) has one too.
    """
    v = _E1_V0 + _E1_H * np.arange(_E1_N + 2)
    x = np.exp(v)
    g = special.exp1(x) * np.exp(x)
    d = _E1_H * (x * g - 1.0)
    g0, g1, d0, d1 = g[:-1], g[1:], d[:-1], d[1:]
    coefficients = (g0, d0, 3.0 * (g1 - g0) - 2.0 * d0 - d1, 2.0 * (g0 - g1) + d0 + d1)
    for c in coefficients:
        c.setflags(write=False)
    return coefficients


_E1_A0, _E1_A1, _E1_A2, _E1_A3 = _build_e1_table()


def exp1(x: NDArray[np.float64], log_x: NDArray[np.float64] | None = None,
         exp_neg_x: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """E1(x) = ∫_x^∞ e^(-t)/t dt for x > 0 (module docstring; same values as scipy.special.exp1 to ~5e-15 relative).

    ``log_x`` (ln x) and ``exp_neg_x`` (e^(-x)) may be passed when the caller has them already.
    """
    x = np.asarray(x, dtype=float)
    shape = x.shape
    x = x.ravel()
    v = np.log(x) if log_x is None else np.asarray(log_x, dtype=float).ravel()
    e = np.exp(-x) if exp_neg_x is None else np.asarray(exp_neg_x, dtype=float).ravel()
    u = v - _E1_V0
    u *= 1.0 / _E1_H
    i = u.astype(np.intp)  # outside the table (x < 1e-2, x > 700) i is clipped and the value replaced below
    u -= i  # the position τ in the interval, 0 <= τ < 1 inside the table
    out = np.take(_E1_A3, i, mode="clip")
    coefficient = np.empty_like(out)
    for table in (_E1_A2, _E1_A1, _E1_A0):
        out *= u
        out += np.take(table, i, out=coefficient, mode="clip")
    out *= e
    if x.size and x.min() < _E1_X_LO:
        low = x < _E1_X_LO
        xl, vl = x[low], v[low]
        # -γ - ln x + x - x²/4 + x³/18 - x⁴/96 + x⁵/600
        out[low] = -_EULER - vl + xl * (1.0 + xl * (-0.25 + xl * (1.0 / 18.0 + xl * (-1.0 / 96.0 + xl / 600.0))))
    if x.size and x.max() > _E1_X_HI:
        # x > 700: E1 < 1e-306 and e^x E1 = (1/x)(1 - 1/x + 2/x² - ... + 720/x⁶), remainder < 5040/x⁷ < 1e-16 (A&S 5.1.51)
        high = x > _E1_X_HI
        r = 1.0 / x[high]
        series = 1.0 - r * (1.0 - 2.0 * r * (1.0 - 3.0 * r * (1.0 - 4.0 * r * (1.0 - 5.0 * r * (1.0 - 6.0 * r)))))
        out[high] = e[high] * r * series
    return out.reshape(shape)


def k_function(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """K(y) = ∫_y^∞ erf²(x) e^(-x²)/x dx for y >= 0 (vectorised)."""
    y = np.asarray(y, dtype=float)
    inside = y < _Y_MAX
    yc = np.clip(y, 0.0, _Y_MAX * (1 - 1e-15))
    u = yc / _H
    i = np.minimum(u.astype(np.intp), _N - 1)
    t = u - i
    t2 = t * t
    t3 = t2 * t
    h00 = 2 * t3 - 3 * t2 + 1
    h10 = t3 - 2 * t2 + t
    h01 = -2 * t3 + 3 * t2
    h11 = t3 - t2
    table = (h00 * _K_VALUES[i] + h10 * _H * _K_SLOPES[i]
             + h01 * _K_VALUES[i + 1] + h11 * _H * _K_SLOPES[i + 1])
    if inside.all():
        return table
    outside = ~inside
    table[outside] = 0.5 * exp1(y[outside] ** 2)
    return table


def f_function(y: NDArray[np.float64], gamma: float) -> NDArray[np.float64]:
    """F(y) = γ E1(y²)/2 + 3(1-γ) K(y), y > 0."""
    y = np.asarray(y, dtype=float)
    out = 0.5 * gamma * exp1(y * y)
    if gamma != 1.0:
        out = out + 3.0 * (1.0 - gamma) * k_function(y)
    return out


def f_derivative(y: NDArray[np.float64], gamma: float) -> NDArray[np.float64]:
    """F'(y) = -[γ + 3(1-γ) erf²(y)] e^(-y²)/y, y > 0."""
    weight = gamma if gamma == 1.0 else gamma + 3.0 * (1.0 - gamma) * special.erf(y) ** 2
    return -weight * np.exp(-y * y) / y


def f_and_slope(y2: NDArray[np.float64], log_y2: NDArray[np.float64], gamma: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """F(y) and P(y) = -y F'(y) = [γ + 3(1-γ) erf²(y)] e^(-y²) at y² = ``y2`` (> 0), given ln y² = ``log_y2``.

    One e^(-y²) serves both, and E1 needs no logarithm of its own (the separation integrals have ln y² at hand).
    """
    e = np.exp(-y2)
    f = exp1(y2, log_y2, e)
    f *= 0.5 * gamma
    if gamma == 1.0:
        return f, e
    y = np.sqrt(y2)
    f += 3.0 * (1.0 - gamma) * k_function(y)
    return f, (gamma + 3.0 * (1.0 - gamma) * special.erf(y) ** 2) * e
