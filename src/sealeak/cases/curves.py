"""The curves the prediction figures draw, computed here so that the figures only draw.

A(ζ), ū(ζ), u1(ζ) at a few squeeze pressures (docs/theory.md §2), the gap distribution P(u)
(§5.1) and Q against ΔP (§3.5, §5) for the cases of one run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..physics.critical_junction import CriticalJunctionResult
from ..physics.gaps import GapDistribution, gap_distribution
from .model import Case
from .run import CaseResult, predict, predict_effective_medium

__all__ = ["PredictionCurves", "CurveSet", "PressureDifferenceSweep", "prediction_curves", "representative_pressures"]

FloatArray = NDArray[np.float64]


def representative_pressures(result: CriticalJunctionResult, count: int = 4) -> FloatArray:
    """A few percolating squeeze pressures spread over the sweep (log-spaced indices), Pa."""
    p = result.squeeze_pressure[result.percolates]
    if p.size == 0:
        p = result.squeeze_pressure
    if p.size <= count:
        return p
    idx = np.unique(np.round(np.linspace(0, p.size - 1, count)).astype(int))
    return p[idx]


@dataclass(frozen=True)
class CurveSet:
    """Curves of one case at one squeeze pressure, against magnification ζ and gap u (SI units).

    Attributes
    ----------
    case
        The case.
    squeeze_pressure
        P0 (Pa).
    zeta
        ζ from 1 to q1/q0.
    area
        A(ζ)/A0 on ``zeta`` (docs/theory.md §2.4).
    zeta_c, percolates
        The critical magnification (NaN if none) and whether it exists (docs/theory.md §3.3).
    mean_gap
        ū(ζ) on ``zeta[:-1]`` (m; docs/theory.md §2.7).
    u1
        u1(ζ) on ``zeta[1:-1]`` (m; docs/theory.md §2.10).
    u1_c
        u1(ζc) (m).
    distribution
        P(u) at this pressure (docs/theory.md §5.1).
    """

    case: Case
    squeeze_pressure: float
    zeta: FloatArray
    area: FloatArray
    zeta_c: float
    percolates: bool
    mean_gap: FloatArray
    u1: FloatArray
    u1_c: float
    distribution: GapDistribution


@dataclass(frozen=True)
class PressureDifferenceSweep:
    """Q against ΔP at one squeeze pressure (Pa, m³/s); ``effective_medium`` None unless asked for."""

    case: Case
    squeeze_pressure: float
    pressure_difference: FloatArray
    critical_junction: FloatArray
    effective_medium: FloatArray | None


@dataclass(frozen=True)
class PredictionCurves:
    """What the prediction figures draw besides the per-pressure results.

    Attributes
    ----------
    spectra
        (q, C(q)) of each case (1/m, m⁴).
    sets
        :class:`CurveSet` at a few pressures (one case: up to four pressures; a study: one per variant).
    gap
        Gaps u (m) on a log grid spanning every set's distribution.
    gap_density
        u·P(u) of each set on ``gap`` (the probability per unit ln u, dimensionless).
    pressure_difference
        One :class:`PressureDifferenceSweep` per case that has a leak channel.
    """

    spectra: list[tuple[FloatArray, FloatArray]]
    sets: list[CurveSet]
    gap: FloatArray
    gap_density: list[FloatArray]
    pressure_difference: list[PressureDifferenceSweep]


def _curve_set(case: Case, p0: float) -> CurveSet:
    contact = case.contact()
    z = np.geomspace(1.0, case.spectrum.q_max / case.q0, 200)
    area = contact.area(z, p0)
    zc, ok = contact.zeta_at_area(1 - case.percolation_threshold, p0)
    ubar = contact.mean_gap(z[:-1], p0)
    u1 = contact.u1(z[1:-1], p0)  # u1 -> inf as ζ -> 1 (A'(1) = 0)
    u1_c = float(contact.u1(zc, p0)) if ok else float("nan")
    dist = gap_distribution(contact, [p0])
    return CurveSet(case, float(p0), z, area, float(zc), bool(ok), ubar, u1, u1_c, dist)


def prediction_curves(results: list[CaseResult]) -> PredictionCurves:
    """Compute the curves of the prediction figures for the cases of one run (docs/theory.md §2–§5)."""
    spectra = [r.case.spectrum.sample(400) for r in results]
    sets: list[CurveSet] = []
    if len(results) == 1:
        res = results[0].critical_junction
        sets = [_curve_set(results[0].case, float(p)) for p in representative_pressures(res)]
    else:
        for r in results:
            rep = representative_pressures(r.critical_junction, 3)
            p = float(rep[1 if rep.size > 1 else 0])
            sets.append(_curve_set(r.case, p))
    dists = [cs.distribution for cs in sets]
    lo = 1e-3 * min(float(d.mean_gap[0]) for d in dists)
    hi = 10.0 * max(max(float(d.mean[0]), float(d.mean_gap[0])) for d in dists)
    u = np.geomspace(lo, hi, 600)
    density = [u * d.density(u)[0] for d in dists]
    sweeps = []
    for r in results:
        res, case = r.critical_junction, r.case
        ok = res.squeeze_pressure[res.percolates]
        if ok.size == 0:
            continue
        p0 = float(ok[np.argmin(np.abs(np.log(ok / np.sqrt(ok[0] * ok[-1]))))])
        dp = np.linspace(0.0, 2.0 * max(case.pressure_difference, 1.0), 21)
        q = predict(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
        q_em = (predict_effective_medium(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
                if r.effective_medium is not None else None)
        sweeps.append(PressureDifferenceSweep(case, p0, dp, q, q_em))
    return PredictionCurves(spectra, sets, u, density, sweeps)
