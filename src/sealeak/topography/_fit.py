"""Least-squares fit of the self-affine model with roll-off to a measured C(q).

Model (docs/theory.md §1.4; the fit is §7.7)::

    C(q) = C0                       q < q_r
    C(q) = C0 (q/q_r)^(-2(1+H))     q >= q_r

fitted in log C over the reliable bins with scipy.optimize.least_squares, parameters
(H, ln q_r, ln C0), each bin weighted by the standard error of its log, ≈ 1/√(modes/2) (the
bin average of `modes` exponentially distributed values with ± q pairs identical). Standard errors
come from the covariance (JᵀJ)⁻¹ scaled by the reduced χ² (as scipy's curve_fit with
absolute_sigma=False does), so systematic misfit widens them. When no plateau is resolved
(q_r at or below the lowest bin), the pure power law (H, C at the lowest bin) is fitted instead and
q_r is reported as not resolved.

H is restricted to the model's 0 <= H <= 1. When the data want a value outside (a spectrum
steeper than q⁻⁴ or flatter than q⁻², by more than two standard errors), the fit stays at the
bound, ``hurst_in_range`` is False, ``hurst_wanted`` holds the unconstrained value and ``warnings``
says so. Every fit that ends at a bound of H carries a warning, also when the unconstrained value is
within two standard errors of it (a poorly determined H), and so does every fit whose reduced χ²
exceeds ``CHI2_WARN`` = 100: the model then misses the bins by ten times their statistical scatter
or more, and its parameters are a compromise (the standard errors, scaled by √χ², do not say that
the model is wrong). A spectrum that shows no
power-law decay at all over the fitted range (white noise, a flat C(q)) cannot determine H: that
raises :class:`~sealeak.errors.InputError` with the reason. A roll-off that would reach the top of
the range is clipped to it. No RuntimeWarning escapes: undefined standard errors are NaN.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from ..errors import ConvergenceError, InputError
from ..physics.spectrum import PowerSpectrum
from ._spectrum import BinnedSpectrum

__all__ = ["SelfAffineFit", "fit_self_affine", "CHI2_WARN"]

#: Reduced χ² above which a fit carries a warning (misfit of ten times the bins' scatter).
CHI2_WARN = 100.0

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, kw_only=True)
class SelfAffineFit:
    """Fitted self-affine parameters with standard errors.

    Attributes
    ----------
    hurst, hurst_err:
        Hurst exponent H and its standard error.
    q_rolloff, q_rolloff_err:
        Roll-off wavevector q_r (1/m) and its standard error (NaN when not resolved).
    rolloff_resolved:
        False when the data show no plateau (then q_rolloff is the lowest fitted bin).
    C0, C0_err:
        Plateau value C(q_r) (m⁴) and its standard error.
    h_rms, h_rms_err:
        RMS height (m) of the fitted model over the fitted q range, with its standard error.
    q_range:
        (q_min, q_max) of the fitted bins (1/m); the model spectrum spans it.
    chi2_red:
        Reduced χ² of the weighted log residuals (1 for pure scatter).
    covariance:
        Covariance of (H, ln q_r, ln C0) (only the first and last for a pure power law).
    spectrum:
        The fitted model as a :class:`~sealeak.physics.spectrum.PowerSpectrum` over ``q_range``.
    hurst_in_range:
        False when the data want H outside 0 < H < 1 (then ``hurst`` is the bound, ``hurst_err`` NaN).
    hurst_wanted:
        The unconstrained best H (equal to ``hurst`` when in range).
    warnings:
        Sentences for the user when the fit is questionable: H at a bound of 0 <= H <= 1, reduced
        χ² above ``CHI2_WARN`` (empty when the fit describes the data).
    warning:
        The same joined into one text, or None.
    """

    hurst: float
    hurst_err: float
    q_rolloff: float
    q_rolloff_err: float
    rolloff_resolved: bool
    C0: float
    C0_err: float
    h_rms: float
    h_rms_err: float
    q_range: tuple[float, float]
    chi2_red: float
    covariance: FloatArray
    spectrum: PowerSpectrum
    hurst_in_range: bool = True
    hurst_wanted: float = float("nan")
    warnings: tuple[str, ...] = ()

    @property
    def warning(self) -> str | None:
        """The warnings as one text, or None."""
        return "; ".join(self.warnings) if self.warnings else None

    def __repr__(self) -> str:
        qr = f"{self.q_rolloff:.4g}{_error(self.q_rolloff_err, '.2g')} 1/m" if self.rolloff_resolved else "not resolved"
        bound = "" if self.hurst_in_range else " (H held at a bound)"
        return (f"SelfAffineFit(H = {self.hurst:.3f}{_error(self.hurst_err, '.3f')}{bound}, q_r = {qr}, "
                f"C0 = {self.C0:.4g}{_error(self.C0_err, '.2g')} m⁴, h_rms = {self.h_rms:.4g}{_error(self.h_rms_err, '.2g')} m)")


def _error(err: float, spec: str) -> str:
    """" ± err", or "" where the fit has no standard error (NaN: H held at its bound, and what depends on it)."""
    return f" ± {err:{spec}}" if np.isfinite(err) else ""


def _model(p: FloatArray, lq: FloatArray) -> FloatArray:
    H, lqr, lC0 = p
    return lC0 - 2.0 * (1.0 + H) * np.maximum(lq - lqr, 0.0)


def _sd(variance: float) -> float:
    """√variance, NaN when the variance is undefined or negative (ill-conditioned covariance)."""
    v = float(variance)
    return float(np.sqrt(v)) if np.isfinite(v) and v >= 0 else float("nan")


def _spectrum(H: float, qr: float, C0: float, q0: float, q1: float) -> PowerSpectrum:
    if qr >= q1:  # roll-off at or beyond the top of the range: the plateau spans it (clipped)
        return PowerSpectrum.from_arrays(np.array([q0, q1]), np.array([C0, C0]), label=f"self-affine fit, H = {H:.3f}")
    if qr > q0:
        nodes = np.array([q0, qr, q1])
        C = np.array([C0, C0, C0 * (q1 / qr) ** (-2.0 * (1.0 + H))])
    else:
        nodes = np.array([q0, q1])
        C = np.array([C0 * (q0 / qr) ** (-2.0 * (1.0 + H)), C0 * (q1 / qr) ** (-2.0 * (1.0 + H))])
    return PowerSpectrum.from_arrays(nodes, C, label=f"self-affine fit, H = {H:.3f}")


def fit_self_affine(
    data: BinnedSpectrum | PowerSpectrum,
    *,
    rolloff: bool | None = None,
    q_range: tuple[float, float] | None = None,
) -> SelfAffineFit:
    """Fit (H, q_r, C0) to a measured 2D C(q) (see the module docstring).

    ``data``: a :class:`BinnedSpectrum` (its reliable bins, weighted by mode counts) or a
    :class:`~sealeak.physics.spectrum.PowerSpectrum` (its nodes, equal weights). ``rolloff``: True to
    force a roll-off, False for a pure power law, None to decide from the data. ``q_range``
    restricts the fit (1/m).
    """
    if isinstance(data, BinnedSpectrum):
        if data.dim != 2:
            raise InputError("spectrum.dim", data.dim, "fit a 2D C(q) (convert profile spectra first)")
        keep = data.reliable & (data.C > 0)
        q, C = data.q[keep], data.C[keep]
        sigma = 1.0 / np.sqrt(np.maximum(data.modes[keep] / 2.0, 1.0))
    else:
        q, C = np.asarray(data.q), np.asarray(data.C)
        sigma = np.ones(q.size)
    if q_range is not None:
        m = (q >= q_range[0]) & (q <= q_range[1])
        q, C, sigma = q[m], C[m], sigma[m]
    if q.size < 4:
        raise InputError("spectrum", f"{q.size} bins", "at least 4 bins in the fitted range")
    lq, lC = np.log(q), np.log(C)

    lo_q, hi_q = lq[0], lq[-1]
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")  # scipy's optimiser warnings are reflected in the result checks
        # start: straight line through the upper half for H, plateau at the lowest bins
        half = lq >= np.median(lq)
        slope = np.polyfit(lq[half], lC[half], 1)[0]
        H0 = float(np.clip(-slope / 2.0 - 1.0, 0.05, 0.95)) if np.isfinite(slope) else 0.5
        return _fit(q, lq, lC, sigma, H0, lo_q, hi_q, rolloff)


_H_LO, _H_HI = 0.0, 1.0
_AT_BOUND = 1e-4
_MIN_POWER_LAW_BINS = 3


def _fit(q: FloatArray, lq: FloatArray, lC: FloatArray, sigma: FloatArray, H0: float, lo_q: float, hi_q: float,
         rolloff: bool | None) -> SelfAffineFit:
    def residuals(p: FloatArray) -> FloatArray:
        return (lC - _model(p, lq)) / sigma

    def residuals_pl(p: FloatArray) -> FloatArray:
        return (lC - (p[1] - 2.0 * (1.0 + p[0]) * (lq - lo_q))) / sigma

    def solve(fun, p0: FloatArray, lower: list[float], upper: list[float]):  # type: ignore[no-untyped-def]
        res = least_squares(fun, p0, bounds=(lower, upper), x_scale="jac", method="trf")
        if not res.success or not np.all(np.isfinite(res.x)):
            raise ConvergenceError(f"self-affine fit did not converge: {res.message}")
        return res

    def power_law(h_lo: float, h_hi: float):  # type: ignore[no-untyped-def]
        return solve(residuals_pl, np.array([float(np.clip(H0, h_lo + 0.05, h_hi - 0.05)), lC[0]]),
                     [h_lo, lC.min() - 50.0], [h_hi, lC.max() + 50.0])

    band = f"q = {q[0]:.4g}..{q[-1]:.4g} 1/m"
    resolved = False
    res = None
    if rolloff is not False:
        best = None
        for f in (0.1, 0.3, 0.5):
            s = lo_q + f * (hi_q - lo_q)
            p0 = np.array([H0, s, float(np.max(lC[lq <= s + 1e-12])) if (lq <= s).any() else lC[0]])
            r = solve(residuals, p0, [_H_LO, lo_q - 1.0, lC.min() - 20.0], [_H_HI, hi_q, lC.max() + 20.0])
            if best is None or r.cost < best.cost:
                best = r
        assert best is not None
        res = best
        resolved = bool(res.x[1] > lo_q + 1e-6) or rolloff is True
        above = int(np.sum(lq > res.x[1] + 1e-9))
        if resolved and above < _MIN_POWER_LAW_BINS:
            # the best plateau reaches (nearly) the top of the range: no power law to determine H from
            slope, slope_err = _loglog_slope(lq, lC, sigma)
            raise InputError("spectrum", band,
                             f"C(q) shows no power-law decay: the fitted plateau reaches q = {np.exp(res.x[1]):.4g} "
                             f"1/m with {above} bin(s) above it (log-log slope over the range {slope:.2f} ± "
                             f"{slope_err:.2f}; a self-affine surface has -2(1+H), between -2 and -4). H cannot be "
                             f"determined: white noise or a measurement dominated by noise?")
    if not resolved:
        res = power_law(_H_LO, _H_HI)
        params = np.array([res.x[0], lo_q, res.x[1]])
        idx = [0, 2]
    else:
        assert res is not None  # a resolved roll-off comes from the fit above
        params = np.array(res.x)
        idx = [0, 1, 2]
    H = float(params[0])
    in_range, wanted = True, H
    warns: list[str] = []
    if H <= _H_LO + _AT_BOUND or H >= _H_HI - _AT_BOUND:
        free = power_law(-3.0, 5.0) if not resolved else solve(
            residuals, params, [-3.0, lo_q - 1.0, lC.min() - 20.0], [5.0, hi_q, lC.max() + 20.0])
        wanted = float(free.x[0])
        sd = _h_sigma(free, q.size)
        margin = max(2.0 * sd, _AT_BOUND) if np.isfinite(sd) else _AT_BOUND  # within 2σ: consistent with it
        bound = _H_LO if H <= 0.5 else _H_HI
        if _H_LO - margin < wanted < _H_HI + margin:
            shown = f"{wanted:.3f} ± {sd:.3f}" if np.isfinite(sd) else f"{wanted:.3f}"
            warns.append(f"H = {bound:g} lies at the bound of the self-affine model's 0 <= H <= 1 (without the bound "
                         f"the fit gives H = {shown}): H is poorly determined by this C(q) (check the reliable "
                         f"range and the instrument's noise floor)")
        else:
            in_range = False
            params[0] = bound  # held exactly at the bound
            warns.append(f"the data want H = {wanted:.2f} (C ∝ q^{-2 * (1 + wanted):.2f}), outside the self-affine "
                         f"model's 0 < H < 1; the fit is held at H = {bound:g} and does not describe this C(q) "
                         f"(check the detrending, the reliable range and the instrument's noise floor)")
            tail = lq > params[1] + 1e-9 if resolved else np.ones(lq.size, dtype=bool)
            slope, _ = _loglog_slope(lq[tail], lC[tail], sigma[tail])
            if slope > -1.0:
                where = f" above the roll-off {np.exp(params[1]):.4g} 1/m" if resolved else ""
                raise InputError("spectrum", band,
                                 f"C(q) hardly decreases{where} (log-log slope {slope:.2f}; a self-affine surface "
                                 f"has -2(1+H), between -2 and -4): H cannot be determined: white noise or a "
                                 f"measurement dominated by noise?")
    J = res.jac
    dof = max(q.size - len(idx), 1)
    chi2_red = float(2.0 * res.cost / dof)
    if chi2_red > CHI2_WARN:
        factor = float(np.exp(np.sqrt(np.mean((res.fun * sigma) ** 2))))  # rms of the log residuals
        warns.append(f"reduced χ² = {chi2_red:.3g}: the model misses the bins by {np.sqrt(chi2_red):.2g} times their "
                     f"statistical scatter (typically a factor {factor:.2g} in C): this C(q) is not one power law with "
                     f"a roll-off over {band} (structure, a noise floor, or stitched measurements that disagree); "
                     f"H, q_r and C0 are a compromise and their standard errors do not show it")
    try:
        cov_small = np.linalg.inv(J.T @ J) * max(chi2_red, 1e-300)
    except np.linalg.LinAlgError:
        cov_small = np.full((len(idx), len(idx)), np.nan)
    if not in_range:  # a parameter held at its bound has no standard error; the others are conditional on it
        cov_small[0, :] = cov_small[:, 0] = np.nan
    cov = np.full((3, 3), np.nan)
    cov[np.ix_(idx, idx)] = cov_small
    H, lqr, lC0 = (float(v) for v in params)
    qr, C0 = float(np.exp(lqr)), float(np.exp(lC0))
    spec = _spectrum(H, qr, C0, float(q[0]), float(q[-1]))

    def hrms(p: FloatArray) -> float:
        return _spectrum(float(p[0]), float(np.exp(p[1])), float(np.exp(p[2])), float(q[0]), float(q[-1])).h_rms

    grad = np.zeros(3)
    for i in idx:
        step = np.zeros(3)
        step[i] = 1e-6 * max(1.0, abs(params[i]))
        grad[i] = (hrms(params + step) - hrms(params - step)) / (2.0 * step[i])
    g = grad[idx]
    ok = np.isfinite(cov_small).all(axis=0)
    h_var = float(g[ok] @ cov_small[np.ix_(ok, ok)] @ g[ok]) if ok.any() else float("nan")
    return SelfAffineFit(
        hurst=H, hurst_err=_sd(cov[0, 0]),
        q_rolloff=qr, q_rolloff_err=float(qr * _sd(cov[1, 1])) if resolved else float("nan"),
        rolloff_resolved=resolved,
        C0=C0, C0_err=float(C0 * _sd(cov[2, 2])),
        h_rms=spec.h_rms, h_rms_err=_sd(h_var), q_range=(float(q[0]), float(q[-1])),
        chi2_red=chi2_red, covariance=cov, spectrum=spec,
        hurst_in_range=in_range, hurst_wanted=wanted, warnings=tuple(warns),
    )


def _h_sigma(res, n: int) -> float:  # type: ignore[no-untyped-def]
    """Standard error of H (first parameter) of a least-squares result, scaled by the reduced χ²."""
    J = res.jac
    chi2 = 2.0 * res.cost / max(n - J.shape[1], 1)
    try:
        return _sd(np.linalg.inv(J.T @ J)[0, 0] * chi2)
    except np.linalg.LinAlgError:
        return float("nan")


def _loglog_slope(lq: FloatArray, lC: FloatArray, sigma: FloatArray) -> tuple[float, float]:
    """Weighted straight-line slope of log C against log q, with its standard error."""
    w = 1.0 / sigma**2
    x0 = np.sum(w * lq) / np.sum(w)
    sxx = np.sum(w * (lq - x0) ** 2)
    slope = float(np.sum(w * (lq - x0) * lC) / sxx)
    resid = lC - (np.sum(w * lC) / np.sum(w) + slope * (lq - x0))
    chi2 = float(np.sum(w * resid**2) / max(lq.size - 2, 1))
    return slope, _sd(max(chi2, 1.0) / sxx)
