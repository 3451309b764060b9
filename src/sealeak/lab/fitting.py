"""Fitting the theory to measured leak rates (docs/theory.md §8).

Scale fit (``sealeak fit``; applied to a case by :func:`sealeak.cases.fit_models`). Both theories predict Q_i = α q_i with q_i the prediction at α = 1 for
the i-th measurement (its P0 and ΔP): for the critical-junction theory α is its shape factor, for the
effective-medium theory a factor that multiplies its prediction (1 without a fit). With
multiplicative (log-normal) scatter, least squares in ln Q has the closed form (§8.1)::

    r_i = ln Q_i - ln q_i,   ln α = mean(r),   se(ln α) = std(r, ddof=1)/√n,   α_std = α se(ln α)

(α_std by the delta method; the interval α exp(±se) is the asymmetric version). The rms residual is
reported in decades: √(mean((r_i - ln α)²))/ln 10. Points the model cannot use are excluded with a
message, never silently: where the model predicts no leak channel (the non-contact area does not
percolate at that P0), where it predicts no flow (ΔP = 0) and where the measured leak rate is zero
(no logarithm).

Linearity check (``sealeak fit --linearity``, the reference paper's first test; §8.2): ordinary least
squares Q = slope ΔP + intercept with the textbook standard errors (s² = RSS/(n - 2)); a linear law
through the origin has an intercept consistent with zero.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..io.quantities import quantity

__all__ = ["ScaleFit", "fit_scale", "LinearFit", "fit_line", "MODELS"]

FloatArray = NDArray[np.float64]

MODELS = ("critical_junction", "effective_medium")


@dataclass(frozen=True, kw_only=True)
class ScaleFit:
    """α fitted by least squares in log Q (docs/theory.md §8.1).

    Attributes
    ----------
    model
        Name of the model the prediction comes from.
    alpha, alpha_std
        The factor (dimensionless) and its standard error α·se(ln α) (NaN with one point).
    log10_alpha_std
        The standard error of log10 α.
    rms_log10_residual
        Rms residual in decades.
    n_used
        Number of points in the fit.
    used
        Mask of the points in the fit.
    prediction
        The model at α = 1 for every point (m³/s, NaN where it has none).
    excluded
        (index, reason) of every point left out.
    """

    model: str
    alpha: float = quantity("1", "the fitted factor α on the model's leak rate")
    alpha_std: float = quantity("1", "standard error of α")
    log10_alpha_std: float = quantity("1", "standard error of log10 α")
    rms_log10_residual: float = quantity("decades (log10)", "rms residual of log10 Q about the fitted model")
    n_used: int = quantity("1", "data rows in the fit", key="points_used")
    used: NDArray[np.bool_]
    prediction: FloatArray
    excluded: tuple[tuple[int, str], ...] = field(default=())

    @property
    def fitted(self) -> bool:
        """Whether α could be fitted (at least one usable point)."""
        return self.n_used > 0 and np.isfinite(self.alpha)


def fit_scale(measured: ArrayLike, predicted: ArrayLike, model: str = "model", held: ArrayLike | None = None) -> ScaleFit:
    """Closed-form least squares of ln(measured) = ln α + ln(predicted); excluded points explained.

    A point is excluded when the prediction is missing (NaN: no leak channel) or zero (no pressure
    difference), or the measurement is 0, or ``held`` marks it (the model holds the liquid by capillarity there,
    Q = 0 whatever α: docs/theory.md eq. 12.3; the reason says whether the measurement leaked all the same).
    ln α = mean(ln Q_i - ln q_i), se(ln α) = std(ddof=1)/√n (docs/theory.md §8.1); NaN from one point, or from rows
    that all repeat one measurement (the same Q against the same prediction). Both arrays in m³/s (any
    common unit: α is a ratio).
    """
    q = np.asarray(measured, dtype=float).ravel()
    p = np.asarray(predicted, dtype=float).ravel()
    if q.shape != p.shape:
        raise InputError("fit", (q.size, p.size), "one prediction per measurement")
    excluded = []
    capillary = np.zeros(q.shape, dtype=bool) if held is None else np.asarray(held, dtype=bool).ravel()
    no_model = ~(np.isfinite(p) & (p > 0)) & ~capillary
    for i in np.flatnonzero(capillary):
        excluded.append((int(i), "the model holds the liquid there by capillarity (ΔP below its entry pressure, Q = 0)"
                         + (", yet it leaked: the narrowest gap is wider, or wetted better, than the model's" if q[i] > 0
                            else ", as measured")))
    zero = (q <= 0) & ~no_model & ~capillary
    for i in np.flatnonzero(no_model):
        excluded.append((int(i), "the model predicts no leak channel there (the non-contact area does not percolate)"
                         if not np.isfinite(p[i]) else "the model predicts no flow there (zero pressure difference)"))
    for i in np.flatnonzero(zero):
        excluded.append((int(i), "the measured leak rate is zero (no logarithm; a fit in log Q cannot use it)"))
    used = ~no_model & ~capillary & ~zero
    n = int(used.sum())
    if n == 0:
        return ScaleFit(model=model, alpha=np.nan, alpha_std=np.nan, log10_alpha_std=np.nan, rms_log10_residual=np.nan,
                        n_used=0, used=used, prediction=p, excluded=tuple(sorted(excluded)))
    r = np.log(q[used]) - np.log(p[used])
    ln_alpha = float(np.mean(r))
    # rows that repeat one measurement (the same Q at the same load) carry no scatter: no standard error, as one point
    distinct = np.unique(np.stack([q[used], p[used]]), axis=1).shape[1]
    se = float(np.std(r, ddof=1) / np.sqrt(n)) if distinct > 1 else np.nan
    alpha = float(np.exp(ln_alpha))
    rms = float(np.sqrt(np.mean((r - ln_alpha) ** 2)) / np.log(10.0))
    return ScaleFit(model=model, alpha=alpha, alpha_std=alpha * se, log10_alpha_std=se / np.log(10.0),
                    rms_log10_residual=rms, n_used=n, used=used, prediction=p, excluded=tuple(sorted(excluded)))


@dataclass(frozen=True, kw_only=True)
class LinearFit:
    """Q = slope x + intercept by ordinary least squares, with standard errors and the rms residual (docs/theory.md §8.2).

    For x = ΔP in Pa and Q in m³/s the slope is in m³/(Pa·s) and the intercept in m³/s.
    """

    slope: float = quantity("m^3/(s*Pa)", "slope of the line Q = slope ΔP + intercept")
    slope_std: float = quantity("m^3/(s*Pa)", "standard error of the slope")
    intercept: float = quantity("m^3/s", "intercept of the line (0 for a leak linear in ΔP)")
    intercept_std: float = quantity("m^3/s", "standard error of the intercept")
    rms_residual: float = quantity("m^3/s", "rms residual about the line")
    r_squared: float = quantity("1", "coefficient of determination R² of the line")
    n: int = quantity("1", "data rows in the fit", key="points")


def fit_line(x: ArrayLike, y: ArrayLike) -> LinearFit:
    """Ordinary least squares y = slope x + intercept (needs >= 3 points with distinct x for the errors).

    se(slope) = √(s²/S_xx), se(intercept) = √(s² (1/n + x̄²/S_xx)), s² = RSS/(n - 2) (docs/theory.md §8.2).
    """
    xa = np.asarray(x, dtype=float).ravel()
    ya = np.asarray(y, dtype=float).ravel()
    n = xa.size
    if n < 2 or xa.size != ya.size:
        raise InputError("linearity data", n, "needs at least two (ΔP, Q) points")
    if not (np.isfinite(xa).all() and np.isfinite(ya).all()):
        raise InputError("linearity data", "NaN or inf", "every (ΔP, Q) point must be finite")
    xm, ym = xa.mean(), ya.mean()
    sxx = float(np.sum((xa - xm) ** 2))
    if sxx == 0:
        raise InputError("pressure_difference", float(xa[0]), "all rows have the same ΔP: a line needs different values")
    slope = float(np.sum((xa - xm) * (ya - ym)) / sxx)
    intercept = float(ym - slope * xm)
    resid = ya - (intercept + slope * xa)
    rss = float(np.sum(resid**2))
    if n > 2:
        s2 = rss / (n - 2)
        slope_std = float(np.sqrt(s2 / sxx))
        intercept_std = float(np.sqrt(s2 * (1.0 / n + xm**2 / sxx)))
    else:
        slope_std = intercept_std = float("nan")
    syy = float(np.sum((ya - ym) ** 2))
    r2 = 1.0 - rss / syy if syy > 0 else 1.0
    return LinearFit(slope=slope, slope_std=slope_std, intercept=intercept, intercept_std=intercept_std,
                     rms_residual=float(np.sqrt(rss / n)), r_squared=r2, n=n)
