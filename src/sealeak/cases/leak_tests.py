"""Leak tests of a case: the pressure-decay test of a gas-filled volume (docs/theory.md §11.7).

The case's ``[rig] kind = "pressure-decay"`` (:class:`~sealeak.lab.rig.DecayRigSetup`) holds a test
volume V at an initial absolute pressure P1 and an outside pressure P2, at temperature T. Each model
the case asks for gives the seal's no-slip conductance K (m³/(Pa·s)) and the gap h of its narrowest
constriction:

* critical junction (docs/theory.md §3): K = α (Ly/Lx) u_c³/(12μ), h = u_c;
* effective medium (§5): K = (Ly/Lx) σ_eff, h = u_e = (12 μ σ_eff)^(1/3);
* an O-ring or pressure-profile seal (§10): K = faces · Ly / ∫dx/σ(p(x)) of the band, h the
  critical gap at the peak contact pressure (critical junction) or the effective gap of the
  smallest σ along the band (effective medium).

K is that of the case's fluid viscosity μ_case; at the test's temperature the gas has μ(T), so the
rig uses K μ_case/μ(T) (both theories are Poiseuille flows, K ∝ 1/μ). The seal's pV throughput
(§11.5) is Q_pV(P, P2) = K ∫_{P2}^{P} p f(Kn(p)) dp with Kn(p) = λ(p)/h and the rig's rarefaction
model, and V dP/dt = −Q_pV(P, P2) is integrated by :func:`~sealeak.lab.pressure_decay.pressure_decay`.
From readings (t_i, P_i), the scale factor on each model's K is
:func:`~sealeak.lab.pressure_decay.scale_factor_from_decay` (for the critical junction: α itself).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..io.quantities import quantity
from ..lab.pressure_decay import DecayReadings, PressureDecay, ScaleFromDecay, leak_rate_from_decay, pressure_decay, scale_factor_from_decay, viscous_decay_time
from ..lab.rig import DecayRigSetup
from ..physics.critical_junction import critical_junction, pressure_difference_large
from ..physics.effective_medium import effective_medium
from ..physics.gas import Gas, GasLeak, gas_leak, pressure_integral, with_throughput
from ..physics.validity import strain_warning
from .band import BandResult, run_band
from .band_tables import chebyshev_lobatto_interpolate
from .gas import CoupledGasSeal, band_gas_seal, uniform_gas_seals
from .model import Case
from .notes import Note, NoteLike
from .prediction import Model
from .schema import case_keys

__all__ = ["DecayModel", "DecayPrediction", "decay_prediction", "DecayReadingsResult", "decay_readings", "decay_rig"]

#: How the rig names the models (the same names as the water-column rig).
_NAMES = {"critical-junction": "critical junction", "effective-medium": "effective medium (Bruggeman)"}


@dataclass(frozen=True)
class DecayModel:
    """One model's pressure decay (SI units; docs/theory.md §11.7).

    Attributes
    ----------
    conductance
        K (m³/(Pa·s)) of the seal at the test temperature (0: no leak channel).
    gap
        h (m), the narrowest gap, for the Knudsen number (NaN without a leak channel).
    decay
        P(t) (Pa) against t (s), the throughput Q_pV (Pa·m³/s) along it, the time Δt to lose ΔP and V ΔP/Δt.
    initial_leak
        The gas leak at t = 0 (between P1 and P2): throughput, mass and molar flow, Kn, regime.
    viscous_time_to_loss
        Δt (s) of the same seal without rarefaction: the continuum reference (inf without a leak channel), in closed
        form (docs/theory.md §11.7), or with the fluid pressure coupled by integrating the no-slip coupled throughput.
    flow
        Q_pV(P, P2) (Pa·m³/s) of the seal at the test temperature, absolute pressures P, P2 (Pa).
    """

    name: str
    conductance: float
    gap: float
    decay: PressureDecay
    initial_leak: GasLeak | None
    viscous_time_to_loss: float
    flow: Callable[[float, float], float] = field(repr=False, compare=False, default=lambda p, p2: 0.0)


@dataclass(frozen=True, kw_only=True)
class DecayPrediction:
    """The pressure-decay test simulated for a case (docs/theory.md §11.7).

    Attributes
    ----------
    squeeze_pressure
        P0 from the load (Pa), or a band seal's mean contact pressure.
    models
        The decay per model the case asks for, by display name.
    messages
        Notes (no leak channel, rarefaction regime, ΔP not small against P0).
    band
        For an O-ring or pressure-profile seal, the band at the case's one load.
    """

    squeeze_pressure: float = quantity("Pa", "P0 from the load (a band seal: its mean contact pressure)")
    models: dict[str, DecayModel]
    messages: tuple[NoteLike, ...] = ()
    band: BandResult | None = None

    @property
    def conductance(self) -> dict[str, float]:
        """K (m³/(Pa·s)) per model, by display name."""
        return {name: m.conductance for name, m in self.models.items()}


def decay_rig(case: Case) -> DecayRigSetup:
    """The case's pressure-decay rig; InputError naming ``rig.kind`` when the case has another (or none)."""
    rig = case.rig
    if not isinstance(rig, DecayRigSetup):
        raise InputError("rig.kind", getattr(rig, "kind", None), "the case has no pressure-decay rig: give [rig] kind = "
                                                                 "\"pressure-decay\" with volume, initial_pressure, outside_pressure")
    return rig


def _models(case: Case) -> list[Model]:
    models: tuple[Model, ...] = ("critical-junction", "effective-medium")
    return [m for m in models if case.model in (m, "both")]


@dataclass(frozen=True)
class _Seal:
    """One model's seal in the rig: K at the case's viscosity (m³/(Pa·s)), the gap h and the slit length λ_c (m; NaN:
    an infinite slit) of its narrowest constriction, its notes, and with the fluid pressure coupled its
    :class:`~sealeak.cases.gas.CoupledGasSeal` (docs/theory.md §13.5)."""

    conductance: float
    gap: float
    length: float
    notes: tuple[NoteLike, ...]
    coupled: CoupledGasSeal | None = None


def _uniform(case: Case, rig: DecayRigSetup, model: Model) -> _Seal:
    """One model's :class:`_Seal` at the rig's P0 (flat seal): K at ΔP = 1 Pa, u_c or u_e, the critical junction's λ_c."""
    p0 = rig.squeeze_pressure(case.seal)
    with case_keys():
        cj = critical_junction(case.contact(), squeeze_pressure=[p0], pressure_difference=1.0, viscosity=case.fluid.viscosity,
                               aspect_ratio=case.seal.aspect_ratio, alpha=case.alpha,
                               percolation_threshold=case.percolation_threshold)
        length = float(cj.critical_wavelength[0]) if cj.percolates[0] else math.nan
        if model == "critical-junction":
            ok, k, gap, notes = bool(cj.percolates[0]), float(cj.leak_rate[0]), float(cj.critical_gap[0]), cj.messages
        else:
            em = effective_medium(case.contact(), squeeze_pressure=[p0], pressure_difference=1.0,
                                  viscosity=case.fluid.viscosity, aspect_ratio=case.seal.aspect_ratio)
            ok, k, gap, notes = bool(em.percolates[0]), float(em.leak_rate[0]), float(em.effective_gap[0]), em.messages
        coupled = uniform_gas_seals(case, model, [p0], [ok])[0] if case.coupled else None
        return _Seal(k if ok else 0.0, gap if ok else math.nan, length, notes, coupled)


def _band(case: Case, models: list[Model]) -> tuple[dict[Model, _Seal], BandResult]:
    """Each model's :class:`_Seal` of a band seal at its one load (docs/theory.md §10.1): K = faces · Ly/R, the gap
    u_c at the peak contact pressure or the narrowest effective gap, λ_c at the peak pressure."""
    band = case.band
    assert band is not None
    if band.loads.size != 1:
        raise InputError(f"conditions.{band.load_name}", None,
                         f"the pressure-decay rig runs at one {band.load_name}, which sets the contact; this case has "
                         f"{band.loads.size}: give one value for the rig (predict sweeps several)")
    res = run_band(case, effective="effective-medium" in models)
    out = {}
    for model in models:
        theory = res.critical_junction if model == "critical-junction" else res.effective_medium
        assert theory is not None
        ok = bool(theory.percolates[0]) and math.isfinite(float(theory.resistance[0])) and theory.resistance[0] > 0
        k = float(res.band.faces * res.band.length / theory.resistance[0]) if ok else 0.0
        if not ok:
            gap = math.nan
        elif model == "critical-junction":
            gap = float(res.critical_gap_at_max_pressure[0])
        else:  # the narrowest effective gap along the band: u_e = (12 μ σ_min)^(1/3)
            sigma = theory.integrals[0].conductance
            gap = float((12.0 * case.fluid.viscosity * np.min(sigma[sigma > 0])) ** (1.0 / 3.0))
        coupled = band_gas_seal(case, model, 0, ok) if case.coupled else None
        out[model] = _Seal(k, gap, float(res.critical_wavelength_at_max_pressure[0]), theory.messages, coupled)
    return out, res


#: Chebyshev–Lobatto points over [P2, P1] at which the rig evaluates a band's exactly coupled Q_pV (docs/theory.md §13.5).
BAND_TABLE_POINTS = 9


def _flow(seal: _Seal, k: float, gas: Gas, model: str, p1: float, p2: float) -> Callable[[float, float], float]:
    """Q_pV(P, P2) (Pa·m³/s) of one model at the test temperature (K = ``k`` there): K ∫ p f dp with the slit length
    λ_c, or with the fluid pressure coupled the exact gas coupling (a band's interpolated in P between
    :data:`BAND_TABLE_POINTS` exact values over [P2, P1], exact at P1; outside it computed)."""
    if k <= 0:
        return lambda p, p_out: 0.0
    coupled = seal.coupled
    if coupled is None:
        length = seal.length if math.isfinite(seal.length) else None
        return lambda p, p_out: k * pressure_integral(seal.gap, gas, p, p_out, model, length)
    if coupled.profile is None:
        return lambda p, p_out: coupled.throughput(gas, model, p, p_out)
    n = BAND_TABLE_POINTS
    nodes = 0.5 * (p1 + p2) - 0.5 * (p1 - p2) * np.cos(np.pi * np.arange(n) / (n - 1))
    nodes[[0, -1]] = p2, p1
    values = np.array([coupled.throughput(gas, model, float(p), p2) for p in nodes])

    def flow(p: float, p_out: float) -> float:
        if p_out != p2 or not p2 <= p <= p1:
            return coupled.throughput(gas, model, p, p_out)
        return float(chebyshev_lobatto_interpolate(nodes, values, np.array([p]))[0])
    return flow


def decay_prediction(case: Case) -> DecayPrediction:
    """Simulate the case's pressure-decay test: P(t) for each model of ``case.model`` (module docstring).

    The throughput of each model is Q_pV(P, P2) = K ∫_{P2}^{P} p f(Kn(p)) dp (Pa·m³/s) with the
    rig's rarefaction model and the critical junction's length λ_c (:func:`~sealeak.physics.gas.pressure_integral`),
    or with the fluid pressure coupled the exact gas coupling of docs/theory.md §13.5, as ``predict``'s gas rows;
    the ODE V dP/dt = −Q_pV is integrated to the test's duration and the time to lose ΔP found by an event
    (docs/theory.md §11.7).
    """
    rig = decay_rig(case)
    test, gas = rig.test, rig.gas
    models = _models(case)
    messages: list[NoteLike] = []
    band = None
    if case.band is not None:
        found, band = _band(case, models)
        p0 = float(band.mean_contact_pressure[0])
    else:
        found = {m: _uniform(case, rig, m) for m in models}
        p0 = rig.squeeze_pressure(case.seal)
        strained = strain_warning(p0, case.youngs_modulus, "the pressure of the rig's load")
        messages += [strained + "; check [rig] load"] if strained else []
    scale = case.fluid.viscosity / gas.viscosity  # K ∝ 1/μ: the case's K at the gas's viscosity at T
    p1, p2 = test.initial_pressure, test.outside_pressure
    out: dict[str, DecayModel] = {}
    for model in models:
        seal = found[model]
        name = _NAMES[model] + (f" (α = {case.alpha:g})" if model == "critical-junction" else "")
        messages.extend(seal.notes)
        k = seal.conductance * scale
        throughput = _flow(seal, k, gas, rig.rarefaction_model, p1, p2)
        leak: GasLeak | None = None
        if k > 0:
            length = seal.length if math.isfinite(seal.length) else None
            leak = gas_leak(k, seal.gap, gas, p1, p2, rig.rarefaction_model, length)
            if seal.coupled is not None:
                leak = replace(with_throughput(leak, throughput(p1, p2), gas),
                               throughput_no_slip=seal.coupled.throughput(gas, "no-slip", p1, p2))
        else:
            messages.append(Note("decay_no_leak_channel", {"model": name, "squeeze_pressure": float(p0),
                                                           "initial_pressure": float(p1)}))
        decay = pressure_decay(test, throughput)
        if seal.coupled is not None and k > 0 and rig.rarefaction_model != "no-slip":
            viscous = pressure_decay(test, _flow(seal, k, gas, "no-slip", p1, p2)).time_to_loss
        else:
            viscous = decay.time_to_loss if seal.coupled is not None and k > 0 else viscous_decay_time(test, k)
        out[name] = DecayModel(name=name, conductance=k, gap=seal.gap, decay=decay, initial_leak=leak,
                               viscous_time_to_loss=viscous, flow=throughput)
        if leak is not None and leak.regime != "continuum" and rig.rarefaction_model != "no-slip":
            messages.append(Note("decay_rarefied", {"model": name, "knudsen": float(leak.knudsen_mean), "gap": float(seal.gap),
                                                    "regime": leak.regime,
                                                    "factor": float(leak.throughput / leak.throughput_no_slip)}))
        if k > 0 and not math.isfinite(decay.time_to_loss):
            messages.append(Note("decay_not_lost", {"model": name, "loss": float(test.loss),
                                                    "duration": float(decay.time[-1])}))
    dp = p1 - p2
    p_ref = float(band.max_contact_pressure[0]) if band is not None else p0
    # coupled: the gas pressure's action on the contact is computed, up to lift-off (ΔP reaching p_ref opens the seal);
    # ignored: flagged where p >> ΔP is doubtful, as predict, fit and the other rigs flag it
    if pressure_difference_large(p_ref, dp, case.coupled):
        messages.append(Note("decay_pressure_difference_large", {"pressure_difference": float(dp), "pressure": float(p_ref),
                                                                 "band": band is not None, "coupled": case.coupled}))
    return DecayPrediction(squeeze_pressure=p0, models=out, messages=tuple(messages), band=band)


@dataclass(frozen=True)
class DecayReadingsResult:
    """What measured (t, P) readings of a pressure-decay test imply (docs/theory.md §11.7).

    Attributes
    ----------
    readings
        Interval leak rates, the standard leak rate over the readings and the viscous K.
    scale
        Per model (display name): the factor on its K that fits the readings, with its standard
        error; for the critical junction this is α (the case's α does not enter).
    fitted
        Per model: P(t) with that factor, from the first reading (t counted from it), over the readings.
    """

    readings: DecayReadings
    scale: dict[str, ScaleFromDecay]
    fitted: dict[str, PressureDecay] = field(default_factory=dict)


def decay_readings(case: Case, pred: DecayPrediction, time: ArrayLike, pressure: ArrayLike,
                   source: str = "readings") -> DecayReadingsResult:
    """The leak rate and each model's scale factor from readings t (s), absolute P (Pa) (docs/theory.md §11.7)."""
    rig = decay_rig(case)
    test = rig.test
    readings = leak_rate_from_decay(test, time, pressure, source=source)
    scale: dict[str, ScaleFromDecay] = {}
    curves: dict[str, PressureDecay] = {}
    for name, m in pred.models.items():
        if not m.conductance > 0:
            continue
        share = 1.0 / case.alpha if name.startswith("critical") else 1.0  # the throughput at α = 1 (Q ∝ α)

        def unit(p: float, p2: float, share: float = share, flow: Callable[[float, float], float] = m.flow) -> float:
            return share * flow(p, p2)

        sc = scale_factor_from_decay(test, readings.time, readings.pressure, unit, source=source)
        scale[name] = sc
        if sc.alpha > 0:
            p = readings.pressure
            start = replace(test, initial_pressure=float(p[0]), pressure_loss=None, duration=None)

            def fitted(pi: float, p2: float, unit=unit, a: float = sc.alpha) -> float:
                return a * unit(pi, p2)

            curves[name] = pressure_decay(start, fitted, t_eval=np.linspace(0.0, readings.time[-1] - readings.time[0], 101),
                                          rtol=1e-9)
    return DecayReadingsResult(readings, scale, curves)
