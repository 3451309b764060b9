"""The critical-junction leak rate of many samples at once, by the scaling of Persson's contact (docs/theory.md eq. 14.6).

A sample that multiplies h_rms by s (the spectrum's shape kept), E* by k, α/η by f and ΔP by d has the nominal
contact's critical gap at the scaled pressure P0/(k s), times s: u_c(P0) = s u_c,nom(P0/(k s)). So one nominal
contact serves every sample:

* the fluid pressure ignored, Q = (Ly/Lx) d ΔP s³ f σ_nom(P0/(k s)), σ_nom evaluated exactly, all samples' scaled
  pressures in one vectorised call;
* coupled (docs/theory.md eq. 13.2), Q = (Ly/Lx) k s⁴ f ∫ σ_nom(τ) dτ over (P0 − d ΔP)/(k s) .. P0/(k s): one
  Gauss–Legendre quadrature of all rows of all samples, σ_nom from a table (:func:`sigma_table`) below 90 % of the
  percolation limit, exact above.

:func:`scaled_leak_rate` does this for one uniform case; which samples may use it is
:func:`sealeak.cases.uncertainty.sample_values`' choice.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from ..physics.contact import PerssonContact
from ..physics.coupling import LIFT_OFF_FLOOR, effective_pressure_integral
from ..physics.critical_junction import CriticalJunctionResult, critical_junction, percolation_limit
from .band import junction_sigma
from .band_tables import persson_contact, piecewise
from .model import Case
from .verdicts import _uniform_verdicts

__all__ = ["scaled_leak_rate", "scaled_validity", "sigma_table",
           "band_junction_tables", "SCALING_RTOL", "SCALING_TABLE_POINTS", "SCALING_TABLE_TOP", "SCALING_BLOCK"]

FloatArray = NDArray[np.float64]

#: The table of σ_nom(τ) (a cubic spline of ln σ in ln τ) is refined, its intervals halved, until it meets the exact
#: σ_nom at the midpoints of its intervals within this (relative).
SCALING_RTOL = 1e-7
#: The table's first and largest number of points; a table that has not met :data:`SCALING_RTOL` at the largest
#: gives way to the exact σ_nom.
SCALING_TABLE_POINTS = (65, 8193)
#: The table covers scaled pressures up to this fraction of the percolation limit; above it σ_nom falls by tens of
#: decades within a few per cent (ζ_c runs to the end of the resolved band) and is evaluated exactly.
SCALING_TABLE_TOP = 0.9
#: A band's tables (:func:`band_junction_tables`) stop at this fraction of the percolation limit: they span 8 decades
#: of pressure, and nearer the limit a spline within :data:`SCALING_RTOL` needs more than the largest table.
BAND_TABLE_TOP = 0.7
#: ... and a second table from there to this fraction of the limit (exact above).
BAND_TABLE_UPPER = 0.97
#: Rows (samples × squeeze pressures) computed at once: bounds the memory of the quadrature (up to 128 nodes a row)
#: and of the exact σ.
SCALING_BLOCK = 4096


def sigma_table(contact: PerssonContact, exact: Callable[[FloatArray], FloatArray], low: float, high: float,
                percolation_threshold: float, top: float = SCALING_TABLE_TOP, limit: float | None = None,
                ) -> Callable[[FloatArray], FloatArray]:
    """σ_nom(τ) (m³/(Pa·s)) for scaled pressures τ in [``low``, ``high``] (Pa): a cubic spline of ln σ against ln τ
    through exact values at equally spaced ln τ up to ``top`` (:data:`SCALING_TABLE_TOP`) of the percolation limit,
    ``exact`` above it (and everywhere when the spline does not meet :data:`SCALING_RTOL`). ``limit``: that limit (Pa)
    when the caller has it."""
    if limit is None:
        limit = percolation_limit(contact, percolation_threshold)
    top = min(high, top * limit)
    if not top > low:
        return exact
    n = SCALING_TABLE_POINTS[0]
    x = np.linspace(np.log(low), np.log(top), n)
    values = exact(np.exp(x))
    while np.all(values > 0):
        spline = CubicSpline(x, np.log(values))
        mid = (x[1:] + x[:-1]) / 2.0
        at_mid = exact(np.exp(mid))
        if not np.all(at_mid > 0):
            break
        if np.all(np.abs(np.expm1(spline(mid) - np.log(at_mid))) < SCALING_RTOL):
            return _spliced(spline, top, exact)
        if 2 * n - 1 > SCALING_TABLE_POINTS[1]:
            break
        x = np.insert(x, np.arange(1, n), mid)
        values = np.insert(values, np.arange(1, n), at_mid)
        n = x.size
    return exact


def band_junction_tables(case: Case, length_low: float, length_high: float,
                         ) -> dict[float, Callable[[FloatArray], FloatArray]]:
    """For each load of a band case, by its q0 (1/m): σ̃_nom(τ) (m³/(Pa·s)) of the nominal contact at α = 1 and
    η = 1 Pa·s (:func:`sigma_table`: a spline within :data:`SCALING_RTOL`, exact near the percolation limit) over the
    scaled pressures τ = p/(k s) that samples with h_rms × s, s in [``length_low``, ``length_high``], reach: a sample's
    profile is the nominal one × k (Lindley's force ∝ E), so τ runs up to p_max/s, and down to 1e-7 of the mean
    pressure over s (below the coupled band's floor, 1e-6 of its pressures); NaN outside that range (the caller
    takes the exact σ there). Used through :class:`sealeak.cases.band.ScaledJunctions` (docs/theory.md §14.5)."""
    assert case.band is not None
    unit = replace(case, alpha=1.0, fluid=replace(case.fluid, viscosity=1.0))
    out: dict[float, Callable[[FloatArray], FloatArray]] = {}
    for profile, q0 in zip(case.band.profiles, case.band.q0.tolist(), strict=True):
        contact = persson_contact(case, q0)
        exact = junction_sigma(unit, contact)
        low, high = 1e-7 * profile.mean_pressure / length_high, profile.max_pressure / length_low
        limit = percolation_limit(contact, case.percolation_threshold)
        table = sigma_table(contact, exact, low, high, case.percolation_threshold, BAND_TABLE_TOP, limit)
        if table is exact:
            continue
        split = BAND_TABLE_TOP * limit
        if split < high:  # the last stretch below the limit, where σ falls fastest: a table of its own
            upper = sigma_table(contact, exact, split, high, case.percolation_threshold, BAND_TABLE_UPPER, limit)
            table = _joined(table, upper, split)
        out[q0] = _within(table, low, high)
    return out


def _joined(lower: Callable[[FloatArray], FloatArray], upper: Callable[[FloatArray], FloatArray],
            split: float) -> Callable[[FloatArray], FloatArray]:
    """``lower`` up to ``split`` (Pa), ``upper`` above."""
    def sigma(tau: FloatArray) -> FloatArray:
        return piecewise(tau, tau <= split, lower, upper)
    return sigma


def _within(sigma: Callable[[FloatArray], FloatArray], low: float, high: float) -> Callable[[FloatArray], FloatArray]:
    """``sigma`` on [``low``, ``high``] (Pa), NaN outside."""
    def inside(tau: FloatArray) -> FloatArray:
        tau = np.asarray(tau, dtype=float)
        return piecewise(tau, (tau >= low) & (tau <= high), sigma, lambda t: np.full(t.shape, np.nan))
    return inside


def _spliced(spline: CubicSpline, top: float, exact: Callable[[FloatArray], FloatArray]) -> Callable[[FloatArray], FloatArray]:
    """σ from ``spline`` (ln σ against ln τ) up to ``top`` (Pa), ``exact`` above."""
    def sigma(p: FloatArray) -> FloatArray:
        return piecewise(p, p <= top, lambda q: np.exp(spline(np.log(q))), exact)
    return sigma


def scaled_leak_rate(case: Case, result: CriticalJunctionResult, length: FloatArray, modulus: FloatArray,
                     flow: FloatArray, pressure_difference: FloatArray) -> FloatArray:
    """The critical-junction leak rate Q (m³/s) of a uniform liquid ``case`` per sample and squeeze pressure,
    [samples, rows], NaN where no leak channel percolates.

    ``result`` is the case's own prediction; per sample, ``length`` = s (h_rms/h_rms,nom), ``modulus`` = k
    (E*/E*_nom), ``flow`` = f ((α/η)/(α/η)_nom) and ``pressure_difference`` = d (ΔP/ΔP_nom), all > 0
    (docs/theory.md eqs. 14.6, 14.7). The samples are taken :data:`SCALING_BLOCK` rows at a time.
    """
    p0 = result.squeeze_pressure
    dp = np.broadcast_to(result.pressure_difference, p0.shape)
    ks = modulus * length
    tau = p0[None, :] / ks[:, None]  # the scaled squeeze pressures P0/(k s) (Pa)
    dtau = dp[None, :] * pressure_difference[:, None] / ks[:, None]  # the scaled ΔP
    contact = case.contact()
    sigma = junction_sigma(case, contact)
    if case.coupled:
        low = np.maximum(tau - dtau, LIFT_OFF_FLOOR * tau)
        sigma = sigma_table(contact, sigma, float(low.min()), float(tau.max()), case.percolation_threshold)
    value = np.full(tau.shape, np.nan)
    step = max(1, SCALING_BLOCK // p0.size)
    for i in range(0, tau.shape[0], step):
        value[i:i + step] = _block(case, contact, sigma, tau[i:i + step], dtau[i:i + step])
    factor = result.aspect_ratio * flow * length**3
    if case.coupled:
        return (factor * ks)[:, None] * value  # eq. 14.7
    return factor[:, None] * value * dp[None, :] * pressure_difference[:, None]  # eq. 14.6


def scaled_validity(case: Case, result: CriticalJunctionResult, length: FloatArray, modulus: FloatArray,
                    pressure_difference: FloatArray) -> NDArray[np.bool_]:
    """Per sample and squeeze pressure, [samples, rows], the validity verdict (docs/theory.md §9.11) of the samples whose
    leak rates :func:`scaled_leak_rate` gives: the nominal contact at τ = P0/(k s) with its gap u_c scaled by s (λc,
    an in-plane length, is not), against the fluid's molecular size, λc, and ΔP = d ΔP_nom against P0 (eq. 14.6)."""
    p0 = result.squeeze_pressure
    tau = p0[None, :] / (modulus * length)[:, None]
    res = critical_junction(case.contact(), squeeze_pressure=tau.ravel(), pressure_difference=1.0,
                            viscosity=case.fluid.viscosity, aspect_ratio=1.0, alpha=case.alpha,
                            percolation_threshold=case.percolation_threshold)
    dp = np.broadcast_to(result.pressure_difference, p0.shape)[None, :] * pressure_difference[:, None]
    sample = replace(res, squeeze_pressure=np.broadcast_to(p0, tau.shape).ravel(), pressure_difference=dp.ravel(),
                     critical_gap=(res.critical_gap.reshape(tau.shape) * length[:, None]).ravel())
    return _uniform_verdicts(case, sample, None)[0].reshape(tau.shape)


def _block(case: Case, contact: PerssonContact, sigma: Callable[[FloatArray], FloatArray], tau: FloatArray,
           dtau: FloatArray) -> FloatArray:
    """Per sample and row at scaled pressures ``tau`` (Pa): σ_nom(τ) (m³/(Pa·s)), or with the fluid pressure coupled
    ∫σ_nom over τ − ``dtau`` .. τ (m³/s; ``sigma`` the table); NaN where no leak channel percolates at τ."""
    res = critical_junction(contact, squeeze_pressure=tau.ravel(), pressure_difference=1.0,
                            viscosity=case.fluid.viscosity, aspect_ratio=1.0, alpha=case.alpha,
                            percolation_threshold=case.percolation_threshold)
    percolates = res.percolates.reshape(tau.shape)
    out = np.full(tau.shape, np.nan)
    if not case.coupled:
        out[percolates] = res.leak_rate.reshape(tau.shape)[percolates]
    elif percolates.any():
        out[percolates] = effective_pressure_integral(sigma, tau[percolates], dtau[percolates]).value
    return out
