"""The virtual rig of a case: the water column simulated, and measured readings analysed (docs/theory.md §4).

:func:`rig_prediction` → :class:`RigPrediction` (H(t) of each model; a pressure-decay rig goes to
:func:`~sealeak.cases.leak_tests.decay_prediction`), :func:`rig_readings` → the leak rate of
measured (t, H) readings.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator

from ..errors import InputError
from ..io.quantities import quantity
from ..lab.rig import DecayRigSetup, ReadingsAnalysis, WaterColumn, drain_time, leak_rate_from_readings, water_column
from ..physics.critical_junction import pressure_difference_large
from ..physics.validity import strain_warning
from .band import BandResult
from .capillarity import entry_pressures
from .leak_tests import DecayPrediction, decay_prediction
from .model import Case
from .notes import Note, NoteLike
from .prediction import FloatArray, Model, _band_conductance, _conductance, _model_name, leak_curve

__all__ = ["RigPrediction", "rig_prediction", "rig_readings"]

@dataclass(frozen=True, kw_only=True)
class RigPrediction:
    """The rig simulated for a case (docs/theory.md §4).

    Attributes
    ----------
    squeeze_pressure
        P0 from the load (Pa).
    conductance
        K = Q/ΔP of each model the case asks for (m³/(s·Pa); 0: no leak), by display name.
    columns
        The water column H(t) of each model.
    time_constant
        τ = A_cyl/(K ρ g) of each model (s; inf without leak).
    drain_time
        Closed-form time to fall to the final height, each model (s).
    messages
        Notes (no leak, ΔP not small against P0).
    band
        For an O-ring or pressure-profile seal, the band at the case's one load (contact width,
        mean and peak pressure; docs/theory.md §10); ``squeeze_pressure`` is then its mean
        contact pressure.
    entry_pressure
        With a contact angle, the capillary entry pressure p_e of each model's narrowest gap (Pa; NaN without a
        leak channel; docs/theory.md §12.1), by display name; the column stops at ρ g H = p_e
        (:attr:`~sealeak.lab.rig.WaterColumn.stop_height`). Empty without a contact angle.
    """

    squeeze_pressure: float = quantity("Pa", "P0 from the load (a band seal: its mean contact pressure)")
    conductance: dict[str, float]
    columns: dict[str, WaterColumn]
    time_constant: dict[str, float] = field(default_factory=dict)
    drain_time: dict[str, float] = field(default_factory=dict)
    messages: tuple[NoteLike, ...] = ()
    band: BandResult | None = None
    entry_pressure: dict[str, float] = field(default_factory=dict)


def _linear_leak(k: float) -> Callable[[ArrayLike], FloatArray]:
    """Q(ΔP) = K ΔP (m³/s) of a seal of conductance ``k`` (m³/(Pa·s))."""
    def leak(dp: ArrayLike) -> FloatArray:
        return k * np.asarray(dp, dtype=float)
    return leak


def _coupled_leak(case: Case, load: float, model: Model, dp0: float,
                  points: int) -> tuple[Callable[[ArrayLike], FloatArray], float]:
    """Q(ΔP) (m³/s) at one load (P0 in Pa, or a band seal's compression or profile scale) with the fluid pressure
    coupled, for 0 <= ΔP <= ΔP0 (Pa): monotone cubic (PCHIP) interpolation through Q at ``points`` pressure
    differences (:func:`~sealeak.cases.prediction.leak_curve`: docs/theory.md eq. 13.2, 13.3); and Q(ΔP0)."""
    grid = np.linspace(0.0, dp0, points)
    q = np.concatenate([[0.0], leak_curve(case, model, load, grid[1:])])
    curve = PchipInterpolator(grid, q)

    def leak(dp: ArrayLike) -> FloatArray:
        return np.asarray(curve(np.clip(np.asarray(dp, dtype=float), 0.0, dp0)), dtype=float)
    return leak, float(q[-1])


#: Pressure differences at which the rig tabulates Q(ΔP) of a uniform seal and of a band seal (each point of a band
#: is one shooting solve of eq. 13.3, about 50 ms).
UNIFORM_POINTS, BAND_POINTS = 33, 17


def rig_prediction(case: Case) -> RigPrediction | DecayPrediction:
    """Simulate the case's [rig]: P0 = load/(seal area), ΔP = ρgH, H(t) for each model of ``case.model`` (docs/theory.md §4.2).

    A ``[rig] kind = "pressure-decay"`` goes to :func:`~sealeak.cases.leak_tests.decay_prediction`
    (P(t) of the test volume, docs/theory.md §11.7).

    As printed (``theory.fluid_pressure = "ignored"``) both theories are linear in ΔP at fixed P0, so
    Q(ΔP) = K ΔP with K from :func:`conductance`; the ODE is still solved in general
    (:func:`~sealeak.lab.rig.water_column`) and the closed-form exponential gives the same curve. With the
    fluid pressure coupled, Q(ΔP) is eq. 13.2 (a uniform seal) or eq. 13.3 (a band seal) tabulated over the head
    range (:func:`_coupled_leak`), K = Q(ΔP0)/ΔP0 at the initial head, τ = A_cyl/(K ρ g) the initial time constant
    and the drain time the ODE's (docs/theory.md §13.5). With a contact angle, the level stops where ρgH falls to
    the capillary entry pressure of the narrowest gap (docs/theory.md §12.1): the drain time to a final height below
    it is infinite.

    An O-ring or pressure-profile seal runs at the case's one load (its compression or profile
    scale sets the contact; the [rig] has no load): as printed K = faces · Ly / ∫dx/σ of the band
    (docs/theory.md §10.5), with the fluid pressure coupled its flow of eq. 13.3 at ρgH over ρgH. Several loads
    raise an InputError naming conditions.compression or conditions.profile_scale.
    """
    rig = case.rig
    if rig is None:
        raise InputError("rig", None, "the case file has no [rig] section (cylinder_diameter, initial_height, load, ...)")
    if isinstance(rig, DecayRigSetup):
        return decay_prediction(case)
    models: list[Model] = [m for m in ("critical-junction", "effective-medium") if case.model in (m, "both")]
    k_of: dict[str, float] = {}
    leak_of: dict[str, Callable[[ArrayLike], FloatArray]] = {}
    messages: list[NoteLike] = []
    band = None
    dp0 = float(rig.pressure_difference(rig.initial_height))
    # with the fluid pressure coupled, K = Q(ΔP0)/ΔP0 at the initial head and Q(ΔP) along the fall (docs/theory.md §13.5)
    if case.band is not None:
        if case.band.loads.size != 1:
            raise InputError(f"conditions.{case.band.load_name}", None, _one_load_needed(case))
        by_model, band = _band_conductance(case, None, tuple(models))
        p0 = float(band.mean_contact_pressure[0])
        load, points = float(case.band.loads[0]), BAND_POINTS
        ks = {m: by_model[m] for m in models}
    else:
        p0 = load = rig.squeeze_pressure(case.seal)
        strained = strain_warning(p0, case.youngs_modulus, "the pressure of the rig's load")
        messages += [strained + "; check [rig] load"] if strained else []
        points = UNIFORM_POINTS
        ks = {m: _conductance(case, [p0], m, dp0 if case.coupled else None) for m in models}
    for model in models:
        name = _model_name(case, model)
        k, notes = float(ks[model][0][0]), ks[model][1]
        if case.coupled and k > 0:
            leak_of[name], q0 = _coupled_leak(case, load, model, dp0, points)
            k = k if band is None else q0 / dp0  # a band's K from _band_conductance is at the case's ΔP
        k_of[name] = k
        messages.extend(notes)
    entry = {_model_name(case, m): p for m, p in entry_pressures(case, models, p0, band).items()}
    columns, tau, t_final = {}, {}, {}
    area = rig.cylinder_area
    for name, k in k_of.items():
        if k == 0:
            messages.append(Note("rig_no_leak", {"model": name, "squeeze_pressure": float(p0),
                                                 "initial_height": float(rig.initial_height)}))
        p_e = entry.get(name, float("nan"))
        columns[name] = water_column(rig, leak_of.get(name, _linear_leak(k)),
                                     entry_pressure=p_e if k > 0 and np.isfinite(p_e) else 0.0)
        tau[name] = area / (k * rig.density * rig.gravity) if k > 0 else float("inf")
        col = columns[name]
        t_final[name] = (float("inf") if col.stop_height is not None and col.stop_height > col.final_height
                         else col.time_to_final if name in leak_of else drain_time(rig, k, col.final_height))
        if col.stop_height is not None:
            messages.append(Note("rig_held_by_capillarity", {
                "model": name, "entry_pressure": p_e, "stop_height": col.stop_height,
                "initial_height": float(rig.initial_height), "time_to_stop": col.time_to_stop}))
    # large: ΔP reaches the pressure and opens the seal (the fluid pressure coupled: the models take it off the contact
    # below that, docs/theory.md §13.4), or ΔP > pressure/2 (the fluid pressure ignored; §3.6)
    held = float(band.max_contact_pressure[0]) if band is not None else float(p0)
    if pressure_difference_large(held, dp0, case.coupled):
        messages.append(Note("rig_pressure_difference_large", {"pressure_difference": dp0, "pressure": held,
                                                               "band": band is not None, "coupled": case.coupled}))
    return RigPrediction(squeeze_pressure=p0, conductance=k_of, columns=columns, time_constant=tau, drain_time=t_final,
                         messages=tuple(messages), band=band, entry_pressure=entry)


def _one_load_needed(case: Case) -> str:
    """Why a band case with several loads has no rig, and what to do."""
    band = case.band
    assert band is not None
    shown = [f"{100 * v:.4g} %" if band.load_name == "compression" else f"{v:.4g}" for v in band.loads[:4]]
    values = ", ".join(shown) + (", ..." if band.loads.size > 4 else "")
    what = "compression (or groove_depth)" if band.kind == "o-ring" else "profile_scale"
    return (f"the rig runs at one {what}, which sets the contact; this case has {band.loads.size} ({values}): "
            "give one value for the rig (predict sweeps several)")


def rig_readings(case: Case, time: ArrayLike, height: ArrayLike, source: str = "readings") -> ReadingsAnalysis:
    """The leak rate read from measured (t, H) readings of the case's rig (docs/theory.md §4)."""
    if case.rig is None:
        raise InputError("rig", None, "the case file has no [rig] section")
    if isinstance(case.rig, DecayRigSetup):
        raise InputError("rig.kind", case.rig.kind, "(t, P) readings of a pressure-decay test go to "
                                                    "sealeak.cases.leak_tests.decay_readings")
    return leak_rate_from_readings(case.rig, time, height, source=source)
