"""Least-squares fit of the self-affine model with roll-off to a measured C(q).

Model (THEORY.md §1)::

    C(q) = C0                       q < q_r
    C(q) = C0 (q/q_r)^(-2(1+H))     q >= q_r

fitted in log C over the reliable bins with scipy.optimize.least_squares, parameters
(H, ln q_r, ln C0), each bin weighted by the standard error of its log, ≈ 1/√(modes/2) (the
bin average of `modes` exponentially distributed values with ± q pairs identical). Standard errors
come from the covariance (JᵀJ)⁻¹ scaled by the reduced χ² (as scipy's curve_fit with
absolute_sigma=False does), so systematic misfit widens them. When no plateau is resolved
(q_r at or below the lowest bin), the pure power law (H, C at the lowest bin) is fitted instead and
q_r is reported as not resolved.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from ..errors import ConvergenceError, InputError
from ..roughness import PowerSpectrum
from ._spectrum import BinnedSpectrum

__all__ = ["SelfAffineFit", "fit_self_affine"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
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
        The fitted model as a :class:`~sealeak.roughness.PowerSpectrum` over ``q_range``.
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

    def __repr__(self) -> str:
        qr = (f"{self.q_rolloff:.4g} ± {self.q_rolloff_err:.2g} 1/m" if self.rolloff_resolved
              else "not resolved")
        return (f"SelfAffineFit(H = {self.hurst:.3f} ± {self.hurst_err:.3f}, q_r = {qr}, "
                f"C0 = {self.C0:.4g} ± {self.C0_err:.2g} m⁴, h_rms = {self.h_rms:.4g} ± {self.h_rms_err:.2g} m)")


def _model(p: FloatArray, lq: FloatArray) -> FloatArray:
    H, lqr, lC0 = p
    return lC0 - 2.0 * (1.0 + H) * np.maximum(lq - lqr, 0.0)


def _spectrum(H: float, qr: float, C0: float, q0: float, q1: float) -> PowerSpectrum:
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
    :class:`~sealeak.roughness.PowerSpectrum` (its nodes, equal weights). ``rolloff``: True to
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

    # start: straight line through the upper half for H, plateau at the lowest bins
    half = lq >= np.median(lq)
    slope = np.polyfit(lq[half], lC[half], 1)[0]
    H0 = float(np.clip(-slope / 2.0 - 1.0, 0.05, 0.95))

    def residuals(p: FloatArray) -> FloatArray:
        return (lC - _model(p, lq)) / sigma

    def fit(p0: FloatArray, lower: list[float], upper: list[float]):  # type: ignore[no-untyped-def]
        res = least_squares(residuals, p0, bounds=(lower, upper), x_scale="jac", method="trf")
        if not res.success:
            raise ConvergenceError(f"self-affine fit did not converge: {res.message}")
        return res

    lo_q, hi_q = lq[0], lq[-1]
    try_rolloff = rolloff is not False
    res = None
    if try_rolloff:
        starts = [lo_q + f * (hi_q - lo_q) for f in (0.1, 0.3, 0.5)]
        best = None
        for s in starts:
            p0 = np.array([H0, s, float(np.max(lC[lq <= s + 1e-12])) if (lq <= s).any() else lC[0]])
            r = fit(p0, [-0.99, lo_q - 1.0, lC.min() - 20.0], [2.0, hi_q, lC.max() + 20.0])
            if best is None or r.cost < best.cost:
                best = r
        res = best
        resolved = bool(res.x[1] > lo_q + 1e-6) or rolloff is True
    if not try_rolloff or not resolved:
        def residuals_pl(p: FloatArray) -> FloatArray:
            return (lC - (p[1] - 2.0 * (1.0 + p[0]) * (lq - lo_q))) / sigma

        res = least_squares(residuals_pl, np.array([H0, lC[0]]), x_scale="jac")
        if not res.success:
            raise ConvergenceError(f"power-law fit did not converge: {res.message}")
        resolved = False
        params = np.array([res.x[0], lo_q, res.x[1]])
        J = res.jac
        idx = [0, 2]
    else:
        params = res.x
        J = res.jac
        idx = [0, 1, 2]
    dof = max(q.size - len(idx), 1)
    chi2_red = float(2.0 * res.cost / dof)
    try:
        cov_small = np.linalg.inv(J.T @ J) * max(chi2_red, 1e-300)
    except np.linalg.LinAlgError:
        cov_small = np.full((len(idx), len(idx)), np.nan)
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
    h_err = float(np.sqrt(max(g @ cov_small @ g, 0.0)))
    return SelfAffineFit(
        hurst=H, hurst_err=float(np.sqrt(cov[0, 0])),
        q_rolloff=qr, q_rolloff_err=float(qr * np.sqrt(cov[1, 1])) if resolved else float("nan"),
        rolloff_resolved=resolved,
        C0=C0, C0_err=float(C0 * np.sqrt(cov[2, 2])),
        h_rms=spec.h_rms, h_rms_err=h_err, q_range=(float(q[0]), float(q[-1])),
        chi2_red=chi2_red, covariance=cov, spectrum=spec,
    )
