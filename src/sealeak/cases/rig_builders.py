"""The ``[rig]`` section of a case file: the water column (default) or the pressure-decay test.

``kind = "water-column"`` (the reference paper's apparatus, docs/theory.md §4) or
``kind = "pressure-decay"`` (a test volume of gas leaking through the seal, docs/theory.md §11.7).
Each kind has its own keys (:data:`RIG_KEYS`); a key of the other kind is refused naming it.
The water column's builder stays in :mod:`sealeak.cases.builders` (``_rig``); this module checks
the keys and builds the pressure-decay rig.
"""

from __future__ import annotations

import math
from typing import Any

from ..errors import InputError, UnitError
from ..io.leak_units import celsius
from ..io.units import parse_quantity, parse_temperature
from ..lab.pressure_decay import PressureDecaySetup
from ..lab.rig import RIG_KINDS, DecayRigSetup
from ..physics.fluid import Fluid
from ..physics.gas import DEFAULT_RAREFACTION, RAREFACTION_MODELS
from ..physics.properties import fluid_state
from .model import BandSeal
from .schema import Section, case_keys

__all__ = ["RIG_KEYS", "RigSection", "decay_rig_setup", "DEFAULT_TEMPERATURE"]

#: The keys of each rig kind (``kind`` itself in both).
RIG_KEYS: dict[str, set[str]] = {
    "water-column": {"kind", "cylinder_diameter", "initial_height", "final_height", "load", "density", "duration", "gravity"},
    "pressure-decay": {"kind", "volume", "initial_pressure", "outside_pressure", "temperature", "pressure_loss", "duration",
                       "load", "gravity"},
}

#: The temperature of a test when neither [rig] nor [fluid] gives one: 20 °C (K).
DEFAULT_TEMPERATURE = 293.15

_DECAY_KEYS = {"volume": "rig.volume", "initial_pressure": "rig.initial_pressure", "outside_pressure": "rig.outside_pressure",
               "pressure_loss": "rig.pressure_loss", "duration": "rig.duration", "load": "rig.load",
               "rarefaction_model": "theory.rarefaction"}


class RigSection(Section):
    """The ``[rig]`` table, its keys checked against its ``kind`` (:data:`RIG_KEYS`)."""

    def __init__(self, data: Any) -> None:
        if not isinstance(data, dict):
            raise InputError("rig", data, "must be a TOML table ([rig])")
        self.name = "rig"
        self.data = data
        kind = data.get("kind", "water-column")
        if kind not in RIG_KINDS:
            raise InputError("rig.kind", kind, f"allowed: {', '.join(repr(k) for k in RIG_KINDS)} (default 'water-column')")
        self.kind: str = kind
        allowed = RIG_KEYS[kind]
        for key in data:
            if key not in allowed:
                other = [k for k in RIG_KINDS if k != kind and key in RIG_KEYS[k]]
                why = f"is for kind = {other[0]!r}; " if other else "unknown key in [rig]; "
                raise InputError(f"rig.{key}", data[key], f"{why}the keys of kind = {kind!r}: {', '.join(sorted(allowed))}")


def _volume(sec: RigSection) -> float:
    """rig.volume in m³ (e.g. '0.5 l', '250 ml', '1e-4 m^3')."""
    allowed = "a volume with its unit, e.g. '0.5 l', '250 ml', '1e-4 m^3'"
    value = sec.raw("volume")
    if value is None:
        raise InputError("rig.volume", None, f"is required: the test volume, {allowed}")
    if isinstance(value, bool) or isinstance(value, (int, float)):
        raise UnitError("rig.volume", value, f"a bare number has no unit; give {allowed}")
    v = parse_quantity("rig.volume", value, "volume")
    if not v > 0:
        raise InputError("rig.volume", value, "must be > 0: the gas-filled test volume")
    return v


def _temperature(sec: RigSection, fluid_doc: dict[str, Any]) -> tuple[float, str]:
    """T (K) of the test: rig.temperature, else fluid.temperature, else 20 °C; and where it came from."""
    if sec.has("temperature"):
        return parse_temperature("rig.temperature", sec.raw("temperature")), "rig.temperature"
    if "temperature" in fluid_doc:
        return parse_temperature("fluid.temperature", fluid_doc["temperature"]), "the fluid's temperature"
    return DEFAULT_TEMPERATURE, "20 °C (default)"


def decay_rig_setup(sec: RigSection, fluid: Fluid, fluid_doc: dict[str, Any], theory_doc: dict[str, Any],
                    band: BandSeal | None, load: tuple[float, str] | None) -> DecayRigSetup:
    """The pressure-decay rig of a ``[rig] kind = "pressure-decay"`` table (docs/theory.md §11.7).

    ``load``: the flat seal's load (N) and how it was given, or None for a band seal. The gas is
    the case's ``[fluid] name`` at the test temperature (CoolProp, docs/theory.md §11.1); a
    viscosity given in ``[fluid]`` overrides the library's. A liquid is refused naming
    ``fluid.name``. The rarefaction model is ``[theory] rarefaction`` (default "kinetic").
    """
    volume = _volume(sec)
    p1 = sec.quantity("initial_pressure", "pressure", positive=False)
    p2 = sec.quantity("outside_pressure", "pressure", positive=False)
    loss = sec.quantity("pressure_loss", "pressure") if sec.has("pressure_loss") else None
    duration = sec.quantity("duration", "time") if sec.has("duration") else None
    t, t_note = _temperature(sec, fluid_doc)
    with case_keys(_DECAY_KEYS):
        test = PressureDecaySetup(volume=volume, initial_pressure=p1, outside_pressure=p2, temperature=t,
                                  pressure_loss=loss, duration=duration)
    name = fluid.name
    if not name:
        raise InputError("fluid.name", None, "is required for rig.kind = 'pressure-decay': the gas in the test volume, "
                                             "e.g. 'air', 'nitrogen', 'helium'")
    t_field = "rig.temperature" if sec.has("temperature") else "fluid.temperature"
    with case_keys({"fluid": "fluid.name", "temperature": t_field, "pressure": "rig.initial_pressure"}):
        state = fluid_state(name, t, p1)
    if not state.is_gas:
        raise InputError("fluid.name", name, f"is a {state.phase} at {celsius(t):.4g} °C and {p1:.6g} Pa: rig.kind = "
                                             "'pressure-decay' needs a gas (air, nitrogen, helium, ...); a liquid leaks in "
                                             "the water-column rig (kind = 'water-column')")
    by_hand = "viscosity" in fluid_doc
    viscosity = fluid.viscosity if by_hand else state.viscosity
    rarefaction = theory_doc.get("rarefaction", DEFAULT_RAREFACTION) if isinstance(theory_doc, dict) else DEFAULT_RAREFACTION
    if rarefaction not in RAREFACTION_MODELS:
        raise InputError("theory.rarefaction", rarefaction, f"allowed: {', '.join(repr(m) for m in RAREFACTION_MODELS)}")
    note = (f"{state.name} at {celsius(t):.4g} °C ({t_note}): μ = {viscosity:.4g} Pa·s "
            f"({'fluid.viscosity' if by_hand else state.source}), M = {state.molar_mass * 1e3:.4g} g/mol")
    if not math.isclose(state.compressibility, 1.0, rel_tol=0.01):
        note += f"; Z = {state.compressibility:.4g} at P1 (the flow formulas take an ideal gas)"
    with case_keys(_DECAY_KEYS):
        gas = state.gas()
        if by_hand:
            gas = type(gas)(name=gas.name, temperature=gas.temperature, viscosity=viscosity, molar_mass=gas.molar_mass)
        return DecayRigSetup(test=test, gas=gas, rarefaction_model=rarefaction, load=None if load is None else load[0],
                             load_note="" if load is None else load[1], gas_note=note)
