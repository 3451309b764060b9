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
from .capillarity import entry_steps, held_sweep
from .gas import gas_throughput
from .model import Case
from .prediction import predict, predict_effective_medium
from .run import CaseResult

__all__ = ["PredictionCurves", "CurveSet", "PressureDifferenceSweep", "prediction_curves", "representative_pressures",
           "FULL_CONTACT_GAP_WEIGHT"]

FloatArray = NDArray[np.float64]

#: A squeeze pressure counts as full contact (no gap distribution to draw) when the non-contact part
#: of P(u), 1 - A(ζ1)/A0, carries less than this fraction of the nominal area.
FULL_CONTACT_GAP_WEIGHT = 1e-9


def representative_pressures(result: CriticalJunctionResult, count: int = 4,
                             valid: NDArray[np.bool_] | None = None) -> FloatArray:
    """A few squeeze pressures spread over the sweep (log-spaced indices), Pa.

    Chosen among the pressures with a leak channel that are within the theory's validity
    (``valid``, e.g. :attr:`CaseResult.valid`); failing those, among the ones with a leak channel;
    failing those, among all pressures.
    """
    p = result.squeeze_pressure
    for keep in ((result.percolates & valid) if valid is not None else result.percolates, result.percolates):
        if keep.any():
            p = result.squeeze_pressure[keep]
            break
    if p.size <= count:
        return p
    idx = np.unique(np.round(np.linspace(0, p.size - 1, count)).astype(int))
    return p[idx]


@dataclass(frozen=True, kw_only=True)
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
    valid
        Whether the critical-junction prediction at this pressure is within the continuum theory
        (:attr:`CaseResult.valid`, docs/theory.md §9.11).
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
    valid: bool = True

    @property
    def in_full_contact(self) -> bool:
        """Whether the surfaces touch everywhere at this pressure (no separation to draw)."""
        return bool(1.0 - self.distribution.contact_fraction[0] < FULL_CONTACT_GAP_WEIGHT
                    or not self.distribution.mean_gap[0] > 0)


@dataclass(frozen=True, kw_only=True)
class PressureDifferenceSweep:
    """Q against ΔP at one squeeze pressure (Pa, m³/s); ``effective_medium`` None unless asked for.

    For a gas case (``gas`` True) the leak rates are pV throughputs Q_pV = K ∫ p f(Kn) dp from P_b to
    P_b + ΔP (Pa·m³/s) at the case's downstream pressure P_b, with each theory's K and narrowest gap at
    this squeeze pressure (docs/theory.md §11.5, §11.9): not linear in ΔP; with the fluid pressure coupled, the exact
    gas coupling of this row's seal at each P_a (§13.5), which passes through the row's leak at the case's ΔP.

    ``valid``, ``valid_effective_medium``: whether each prediction at this pressure is within the
    continuum theory (docs/theory.md §9.11).
    """

    case: Case
    squeeze_pressure: float
    pressure_difference: FloatArray
    critical_junction: FloatArray
    effective_medium: FloatArray | None
    valid: bool = True
    valid_effective_medium: bool = True
    gas: bool = False


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
        Gaps u (m) on a log grid spanning every set's distribution (empty when every set is in full contact).
    gap_density
        u·P(u) of each set on ``gap`` (the probability per unit ln u, dimensionless; zeros for a set in full contact).
    pressure_difference
        One :class:`PressureDifferenceSweep` per case that has a leak channel (of a gas case: only when
        every case of the run is a gas case, since a pV throughput and a volume flow share no axis).
    """

    spectra: list[tuple[FloatArray, FloatArray]]
    sets: list[CurveSet]
    gap: FloatArray
    gap_density: list[FloatArray]
    pressure_difference: list[PressureDifferenceSweep]


def _curve_set(case: Case, p0: float, valid: bool = True) -> CurveSet:
    contact = case.contact()
    z = np.geomspace(1.0, case.spectrum.q_max / case.q0, 200)
    area = contact.area(z, p0)
    zc, ok = contact.zeta_at_area(1 - case.percolation_threshold, p0)
    ubar = contact.mean_gap(z[:-1], p0)
    u1 = contact.u1(z[1:-1], p0)  # u1 -> inf as ζ -> 1 (A'(1) = 0)
    u1_c = float(contact.u1(zc, p0)) if ok else float("nan")
    dist = gap_distribution(contact, [p0])
    return CurveSet(case=case, squeeze_pressure=float(p0), zeta=z, area=area, zeta_c=float(zc), percolates=bool(ok),
                    mean_gap=ubar, u1=u1, u1_c=u1_c, distribution=dist, valid=valid)


def _verdict_at(result: CaseResult, p0: float) -> bool:
    """The critical-junction verdict of ``result`` at one of its squeeze pressures (True if not found)."""
    hit = np.flatnonzero(result.critical_junction.squeeze_pressure == p0)
    return bool(result.valid[hit[0]]) if hit.size and result.valid.size else True


def prediction_curves(results: list[CaseResult]) -> PredictionCurves:
    """Compute the curves of the prediction figures for the cases of one run (docs/theory.md §2–§5).

    Degenerate runs give empty parts rather than errors: no gap grid when every set is in full
    contact, no ΔP sweep for a case without a leak channel at any of its pressures.
    """
    spectra = [r.case.spectrum.sample(400) for r in results]
    sets: list[CurveSet] = []
    for r in results:
        valid = r.valid if r.valid.size else None
        if len(results) == 1:
            chosen = list(representative_pressures(r.critical_junction, valid=valid))
        else:
            rep = representative_pressures(r.critical_junction, 3, valid=valid)
            chosen = [rep[1 if rep.size > 1 else 0]]
        sets += [_curve_set(r.case, float(p), _verdict_at(r, float(p))) for p in chosen]
    open_sets = [cs for cs in sets if not cs.in_full_contact]
    u = np.zeros(0)
    if open_sets:
        lo = 1e-3 * min(float(cs.distribution.mean_gap[0]) for cs in open_sets)
        hi = 10.0 * max(max(float(cs.distribution.mean[0]), float(cs.distribution.mean_gap[0])) for cs in open_sets)
        u = np.geomspace(lo, hi, 600)
    density = [np.zeros(u.size) if cs.in_full_contact else u * cs.distribution.density(u)[0] for cs in sets]
    sweeps = []
    all_gas = all(r.case.gas is not None for r in results)
    for r in results:
        res, case = r.critical_junction, r.case
        if (case.gas is not None) != all_gas:
            continue
        valid = r.valid if r.valid.size else np.ones(len(res), dtype=bool)
        leaks = res.percolates if r.effective_medium is None else res.percolates | r.effective_medium.percolates
        keep = leaks & valid if (leaks & valid).any() else leaks
        ok = res.squeeze_pressure[keep]
        if ok.size == 0:
            continue
        p0 = float(ok[np.argmin(np.abs(np.log(ok / np.sqrt(ok[0] * ok[-1]))))])
        i = int(np.flatnonzero(res.squeeze_pressure == p0)[0])
        dp = np.linspace(0.0, 2.0 * max(case.pressure_difference, 1.0), 21)
        if all_gas:
            sweeps.append(_gas_sweep(r, i, dp, bool(valid[i])))
            continue
        dp = entry_steps(r.capillary, i, dp)
        q = predict(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
        q_em = (predict_effective_medium(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
                if r.effective_medium is not None else None)
        cap = r.capillary or {}  # a liquid held by capillarity below the entry pressure (docs/theory.md §12)
        q = held_sweep(cap.get("critical_junction"), i, dp, q)
        q_em = held_sweep(cap.get("effective_medium"), i, dp, q_em) if q_em is not None else None
        valid_em = r.valid_effective_medium
        sweeps.append(PressureDifferenceSweep(case=case, squeeze_pressure=p0, pressure_difference=dp,
                                              critical_junction=q, effective_medium=q_em, valid=bool(valid[i]),
                                              valid_effective_medium=bool(valid_em[i]) if valid_em is not None and valid_em.size else True))
    return PredictionCurves(spectra, sets, u, density, sweeps)


def _gas_sweep(result: CaseResult, row: int, dp: FloatArray, valid: bool) -> PressureDifferenceSweep:
    """Q_pV against ΔP = P_a − P_b at the case's P_b, each theory's K and gap of row ``row`` (docs/theory.md §11.9); with
    the fluid pressure coupled, the exact gas coupling of that row's seal at each P_a (§13.5)."""
    case, gas = result.case, result.gas or {}

    def curve(name: str) -> FloatArray | None:
        rows = gas.get(name)
        if rows is None:
            return None
        return gas_throughput(case, np.full(dp.size, rows.conductance[row]), np.full(dp.size, rows.gap[row]), dp,
                              np.full(dp.size, rows.length[row]),
                              [rows.seals[row]] * dp.size if rows.seals is not None else None)

    cj, em = curve("critical_junction"), curve("effective_medium")
    valid_em = result.valid_effective_medium
    return PressureDifferenceSweep(case=case, squeeze_pressure=float(result.critical_junction.squeeze_pressure[row]),
                                   pressure_difference=dp,
                                   critical_junction=cj if cj is not None else np.full(dp.size, np.nan),
                                   effective_medium=em, valid=valid,
                                   valid_effective_medium=bool(valid_em[row]) if valid_em is not None and valid_em.size else True, gas=True)
