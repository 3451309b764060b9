"""The two leak-rate theories applied to a case, and a seal's conductance K = Q/ΔP at other loads.

* :func:`predict`, :func:`predict_effective_medium`: one theory at the case's (or given) pressures;
* :func:`conductance`: K = Q/ΔP of a model at squeeze pressures, or at the loads of an O-ring or
  pressure-profile seal (both theories are linear in ΔP, docs/theory.md §3, §5 and §10.1), used by
  the rig, the linearity check and the fit;
* the band seal at other loads (compressions ε or profile scales): its profiles, K and the effective
  medium's narrowest gap (docs/theory.md §10.1, §11.9).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Literal, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..physics.coupling import LIFT_OFF_FLOOR, coupled_band_flow, effective_pressure_integral
from ..physics.critical_junction import CriticalJunctionResult, critical_junction
from ..physics.effective_medium import EffectiveMediumResult, effective_medium
from ..physics.seal import Seal
from .band import BandResult, BandTheory, junction_sigma, run_band
from .band_tables import effective_medium_sigma_table, persson_contact
from .model import Case
from .notes import NoteLike
from .schema import case_keys
from .seals import with_loads

__all__ = ["predict", "predict_effective_medium", "conductance", "leak_curve", "Model", "MODEL_NAMES"]

FloatArray = NDArray[np.float64]
ResultT = TypeVar("ResultT", CriticalJunctionResult, EffectiveMediumResult)

#: A leak-rate model: the critical-junction theory (docs/theory.md §3) or the effective medium (§5).
Model = Literal["critical-junction", "effective-medium"]

#: How front ends name the models.
MODEL_NAMES: dict[str, str] = {"critical-junction": "critical junction", "effective-medium": "effective medium"}


# ---------------------------------------------------------------------- the theories for a case
def predict(case: Case, squeeze_pressure: ArrayLike | None = None,
            pressure_difference: ArrayLike | None = None) -> CriticalJunctionResult:
    """Critical-junction leak rate of ``case`` at its squeeze pressures (or the ones given), in SI units.

    Lorenz & Persson (2009) eq. 2 (docs/theory.md §3); with ``theory.fluid_pressure = "coupled"`` the leak rate
    is (Ly/w) ∫σ(s) ds over the effective squeeze pressures P0 − ΔP .. P0 (docs/theory.md eq. 13.2).
    """
    with case_keys():
        contact = case.contact()
        res = critical_junction(
            contact,
            squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
            pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
            viscosity=case.fluid.viscosity,
            aspect_ratio=case.seal.aspect_ratio,
            alpha=case.alpha,
            percolation_threshold=case.percolation_threshold,
            fluid_pressure_neglected=not case.coupled,
        )
        return _coupled(case, res, junction_sigma(case, contact)) if case.coupled else res


def predict_effective_medium(case: Case, squeeze_pressure: ArrayLike | None = None,
                             pressure_difference: ArrayLike | None = None) -> EffectiveMediumResult:
    """Bruggeman effective-medium leak rate Q = (Ly/Lx) σ_eff ΔP of ``case`` in m³/s (Bruggeman (1935); docs/theory.md §5.3).

    With ``theory.fluid_pressure = "coupled"``, (Ly/Lx) ∫σ_eff(s) ds over P0 − ΔP .. P0 (docs/theory.md eq. 13.2),
    σ_eff interpolated between exact values (:func:`~sealeak.cases.band_tables.effective_medium_sigma_table`).
    """
    with case_keys():
        contact = case.contact()
        res = effective_medium(
            contact,
            squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
            pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
            viscosity=case.fluid.viscosity,
            aspect_ratio=case.seal.aspect_ratio,
        )
        if not case.coupled:
            return res
        p0 = res.squeeze_pressure
        low = float(np.min(np.maximum(p0 - res.pressure_difference, LIFT_OFF_FLOOR * p0)))
        return _coupled(case, res, effective_medium_sigma_table(case, contact, float(p0.max()), low / float(p0.max())))


def _coupled(case: Case, res: ResultT, sigma: Callable[[FloatArray], FloatArray]) -> ResultT:
    """``res`` with the leak rate of the fluid pressure acting on the contact: (Ly/Lx) ∫_{P0−ΔP}^{P0} σ(s) ds
    (docs/theory.md eq. 13.2; rows with ΔP ≥ P0 at the lift-off limit ΔP = P0)."""
    integral = effective_pressure_integral(sigma, res.squeeze_pressure, res.pressure_difference)
    leak = np.where(res.percolates, res.aspect_ratio * integral.value, np.nan)
    return replace(res, leak_rate=leak)


def conductance(case: Case, squeeze_pressure: ArrayLike, model: Model = "critical-junction") -> FloatArray:
    """K = Q/ΔP of the seal (m³/(Pa·s)) at each squeeze pressure P0 (Pa), for one model.

    Both theories are linear in ΔP at fixed P0, so K is the leak rate at ΔP = 1 Pa: for the
    critical junction K = α (Ly/Lx) u_c³/(12η) (Lorenz & Persson (2009) eq. 2), for the effective
    medium K = (Ly/Lx) σ_eff (docs/theory.md §5). K = 0 where the model predicts no leak channel.

    For an O-ring or pressure-profile seal (``case.band``) ``squeeze_pressure`` holds the loads
    instead, compressions ε (1) or profile scales (1), and K = faces · Ly / ∫₀^w dx/σ(p(x)) of the
    band at each (docs/theory.md §10.1); the effective medium costs 1–2 s per load.
    """
    return _conductance(case, squeeze_pressure, model)[0]


def _conductance(case: Case, squeeze_pressure: ArrayLike, model: Model,
                 pressure_difference: float | None = None) -> tuple[FloatArray, tuple[NoteLike, ...]]:
    """:func:`conductance` and the model's notes (why there is no leak channel, where there is none); for a uniform
    seal with the fluid pressure coupled, K = Q/ΔP at ``pressure_difference`` (Pa; None: 1 Pa, the limit ΔP → 0)."""
    if model not in ("critical-junction", "effective-medium"):
        raise InputError("model", model, "allowed: 'critical-junction', 'effective-medium'")
    if case.band is not None:
        ks, _ = _band_conductance(case, squeeze_pressure, (model,))
        return ks[model]
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    dp = 1.0 if pressure_difference is None else pressure_difference
    res: CriticalJunctionResult | EffectiveMediumResult
    if model == "critical-junction":
        res = predict(case, squeeze_pressure=p0, pressure_difference=dp)
    else:
        res = predict_effective_medium(case, squeeze_pressure=p0, pressure_difference=dp)
    return np.where(res.percolates, res.leak_rate / dp, 0.0), res.messages


def leak_curve(case: Case, model: Model, load: float, pressure_difference: ArrayLike) -> FloatArray:
    """Q(ΔP) (m³/s) of one model at one load and each pressure difference ΔP > 0 (Pa); 0 where it has no leak channel.

    ``load``: P0 (Pa) of a uniform seal, a band seal's compression ε or profile scale (1). With the fluid pressure
    coupled, Q is eq. 13.2 (a uniform seal) or the band's eq. 13.3 solved at each ΔP, one σ(p) for all; ignored,
    Q = K ΔP (docs/theory.md §13.5). Capillarity is not applied (docs/theory.md §12: the caller's threshold).
    """
    dp = np.atleast_1d(np.asarray(pressure_difference, dtype=float))
    if case.band is None:
        run = predict if model == "critical-junction" else predict_effective_medium
        return np.nan_to_num(run(case, squeeze_pressure=np.full(dp.size, load), pressure_difference=dp).leak_rate)
    at = _band_at(case, [load])
    band = at.band
    assert band is not None
    if not case.coupled:
        return _band_conductance(at, None, (model,))[0][model][0][0] * dp
    profile = band.profiles[0]
    with case_keys():
        contact = persson_contact(at, float(band.q0[0]))
        sigma = (junction_sigma(at, contact) if model == "critical-junction"
                 else effective_medium_sigma_table(at, contact, profile.max_pressure, LIFT_OFF_FLOOR))
        flows = [coupled_band_flow(profile, sigma, float(x)).flow for x in dp]
    return band.faces * band.length * np.array(flows)


# ---------------------------------------------------------------------- band seals at other loads
def _q0_fixed(case: Case) -> float | None:
    """The q0 (1/m) a band case's file fixed (``theory.lowest_wavevector``/``square_side``), or None: 2π/w per load."""
    assert case.band is not None
    return case.band.q0_fixed


def _band_at(case: Case, loads: ArrayLike) -> Case:
    """The band case at other loads (compressions ε or profile scales, 1): its profiles, q0, seal and mean pressures.

    :func:`~sealeak.cases.seals.with_loads` builds the same seal at ``loads``; q0 stays fixed if the
    case file fixed it, else it is 2π/w of each load's contact width (docs/theory.md §10.1).
    """
    band = case.band
    assert band is not None
    values = np.atleast_1d(np.asarray(loads, dtype=float))
    if np.array_equal(values, band.loads):
        return case
    new = with_loads(band, values, case.youngs_modulus, case.poisson_ratio, _q0_fixed(case))
    widths = np.array([p.width for p in new.profiles])
    with case_keys():
        seal = Seal(width=float(widths.max()), length=new.length, shape=new.kind)
    return replace(case, band=new, seal=seal, squeeze_pressure=np.array([p.mean_pressure for p in new.profiles]))


def _band_k(band_result: BandResult, theory: BandTheory) -> FloatArray:
    """K = faces · Ly / R (m³/(Pa·s)) of each load, 0 where the band holds no leak channel (docs/theory.md §10.1);
    with the fluid pressure coupled, K = Q/ΔP at the band's ΔP (docs/theory.md §13)."""
    band = band_result.band
    if band_result.coupled:
        return np.where(theory.percolates, theory.leak_rate / band_result.pressure_difference, 0.0)
    with np.errstate(divide="ignore"):
        return np.where(theory.percolates, band.faces * band.length / theory.resistance, 0.0)


def _band_conductance(case: Case, loads: ArrayLike | None,
                      models: tuple[str, ...]) -> tuple[dict[str, tuple[FloatArray, tuple[NoteLike, ...]]], BandResult]:
    """K of a band seal per model at ``loads`` (None: the case's), with each theory's notes, and the band result.

    One :func:`~sealeak.cases.band.run_band` serves both models (the effective medium only when asked:
    it costs 1–2 s per load).
    """
    at = case if loads is None else _band_at(case, loads)
    res = run_band(at, effective="effective-medium" in models)
    out: dict[str, tuple[FloatArray, tuple[NoteLike, ...]]] = {}
    for model in models:
        theory = res.critical_junction if model == "critical-junction" else res.effective_medium
        assert theory is not None
        out[model] = (_band_k(res, theory), theory.messages)
    return out, res


def _model_name(case: Case, model: Model) -> str:
    """How the rig and the linearity check name a model (with α for the critical junction)."""
    return f"critical junction (α = {case.alpha:g})" if model == "critical-junction" else "effective medium (Bruggeman)"


def _band_effective_gap(case: Case, theory: BandTheory) -> FloatArray:
    """u_e = (12 μ σ_min)^(1/3) (m) per load: the effective medium's narrowest constriction along the band, σ_min the
    smallest sheet conductance of its quadrature; NaN where the band holds no leak channel (docs/theory.md §11.9)."""
    return np.array([float(np.cbrt(12.0 * case.fluid.viscosity * np.min(g.conductance[g.conductance > 0])))
                     if ok and np.any(g.conductance > 0) else np.nan
                     for g, ok in zip(theory.integrals, theory.percolates)])
