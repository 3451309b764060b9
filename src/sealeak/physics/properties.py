"""Properties of named fluids at a temperature and pressure, from the CoolProp property library.

CoolProp (Bell, Wronski, Quoilin & Lemort, Ind. Eng. Chem. Res. 53, 2498 (2014); MIT licence)
evaluates each fluid's reference equation of state and viscosity correlation, e.g. Lemmon &
Jacobsen (2004) for air, nitrogen and argon, Arp, McCarty & Friend (1998) for helium, Huber et al.
(2009, IAPWS 2008) for water. Which correlation serves a fluid is in :attr:`FluidState.source`;
the choice of library and the accuracies are in docs/theory.md §11.1.

Only the fluids of :data:`KNOWN_FLUIDS` are offered (by name or alias, case and ``-``/``_``/space
insensitive): an unknown name is refused with the list. Oils are in no property library: their
viscosity must be given by hand (``fluid.viscosity``), which overrides any looked-up value anyway.
Errors name the functions' own parameters (``fluid``, ``temperature``, ``pressure``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from types import ModuleType
from typing import Any

from ..errors import InputError, did_you_mean
from ..io.leak_units import ATMOSPHERE, celsius
from .gas import MOLAR_GAS_CONSTANT, Gas

__all__ = ["KNOWN_FLUIDS", "FluidState", "fluid_state", "canonical_fluid_name", "close_fluid_name", "known_fluid_names",
           "property_library",
           "vapour_pressure_note"]
__all__ += ["surface_tension"]

#: name → (CoolProp's name, aliases). Gases at room conditions first, then refrigerants, then liquids.
KNOWN_FLUIDS: dict[str, tuple[str, tuple[str, ...]]] = {
    "helium": ("Helium", ("He", "R704")),
    "hydrogen": ("Hydrogen", ("H2", "R702")),
    "air": ("Air", ("dry air", "R729")),
    "nitrogen": ("Nitrogen", ("N2", "R728")),
    "oxygen": ("Oxygen", ("O2", "R732")),
    "argon": ("Argon", ("Ar", "R740")),
    "carbon dioxide": ("CarbonDioxide", ("CO2", "R744")),
    "methane": ("Methane", ("CH4", "R50")),
    "propane": ("n-Propane", ("C3H8", "R290")),
    "sulfur hexafluoride": ("SulfurHexafluoride", ("SF6",)),
    "ammonia": ("Ammonia", ("NH3", "R717")),
    "R134a": ("R134a", ("HFC-134a",)),
    "R1234yf": ("R1234yf", ("HFO-1234yf",)),
    "R1234ze(E)": ("R1234ze(E)", ("R1234ze", "HFO-1234ze(E)")),
    "R32": ("R32", ("HFC-32",)),
    "R410A": ("R410A", ()),
    "R407C": ("R407C", ()),
    "R404A": ("R404A", ()),
    "water": ("Water", ("H2O",)),
    "ethanol": ("Ethanol", ("C2H5OH",)),
}

_OIL = re.compile(r"oil|iso\s*vg|\bvg\s*\d|sae\s*\d|glycerol|glycerine|grease|lubricant|hydraulic|silicone", re.IGNORECASE)
_PHASES = {"gas": "gas", "supercritical_gas": "gas", "supercritical": "supercritical", "liquid": "liquid",
           "supercritical_liquid": "liquid", "twophase": "two-phase"}


def _coolprop() -> tuple[Any, ModuleType]:
    """(CoolProp, CoolProp.CoolProp), imported on first use: importing CoolProp takes ~3 s, and a case
    whose fluid's viscosity is given by hand needs no property at all (docs/architecture.md)."""
    import CoolProp
    import CoolProp.CoolProp as CP

    return CoolProp, CP


def _key(name: str) -> str:
    return re.sub(r"[\s_\-]+", "", name).lower()


@lru_cache(maxsize=1)
def _lookup() -> dict[str, str]:
    table = {}
    for name, (_, aliases) in KNOWN_FLUIDS.items():
        for spelling in (name, *aliases):
            table[_key(spelling)] = name
    return table


def known_fluid_names() -> str:
    """The known names with their aliases, for messages: "helium (He, R704), hydrogen (H2, R702), ..."."""
    return ", ".join(f"{n} ({', '.join(a)})" if a else n for n, (_, a) in KNOWN_FLUIDS.items())


def canonical_fluid_name(fluid: str) -> str:
    """The name in :data:`KNOWN_FLUIDS` that ``fluid`` spells (any case; ``-``, ``_`` and spaces ignored).

    Raises :class:`InputError` naming ``fluid``: for an oil, saying to give its viscosity; for any
    other unknown name, listing the known ones.
    """
    if not isinstance(fluid, str) or not fluid.strip():
        raise InputError("fluid", fluid, f"must be a fluid's name: one of {known_fluid_names()}")
    name = _lookup().get(_key(fluid))
    if name is not None:
        return name
    if _OIL.search(fluid):
        raise InputError("fluid", fluid, "oils are not in the property library: give the oil's viscosity at the seal's "
                                         "temperature by hand (fluid.viscosity, e.g. '46 mPa*s'; from its data sheet)")
    raise InputError("fluid", fluid, f"unknown fluid{close_fluid_name(fluid)}; known: {known_fluid_names()}; for any other "
                                     "fluid give its viscosity (fluid.viscosity)")


def close_fluid_name(fluid: str) -> str:
    """" (did you mean 'helium'?)" when ``fluid`` is a near miss of a known name or alias ("helum"), else ""."""
    spellings = [spelling for name, (_, aliases) in KNOWN_FLUIDS.items() for spelling in (name, *aliases)]
    hint = did_you_mean(fluid, [s for s in spellings if len(s) > 3])  # "H2", "Ar": any short word is near one
    return hint


def property_library() -> str:
    """"CoolProp <version>": the library the properties come from."""
    return f"CoolProp {_coolprop()[0].__version__}"


@dataclass(frozen=True, kw_only=True)
class FluidState:
    """A named fluid at ``temperature`` (K) and ``pressure`` (Pa), from CoolProp (SI units).

    Attributes
    ----------
    name, coolprop_name
        The known name (:data:`KNOWN_FLUIDS`) and CoolProp's.
    temperature, pressure
        The state: T (K) and absolute p (Pa).
    phase
        "gas" (also above the critical temperature at a density below the critical one), "liquid",
        "supercritical" or "two-phase".
    viscosity, density, molar_mass
        μ (Pa·s), ρ (kg/m³) and M (kg/mol).
    compressibility
        Z = p M/(ρ R T): 1 for an ideal gas; the gas-flow formulas of :mod:`sealeak.physics.gas`
        assume Z = 1.
    vapour_pressure
        Saturation pressure at T (Pa; NaN above the critical temperature).
    critical_temperature
        T_c (K).
    source
        Property library and viscosity correlation, e.g. "CoolProp 8.0.0, viscosity: Lemmon-IJT-2004".
    """

    name: str
    coolprop_name: str
    temperature: float
    pressure: float
    phase: str
    viscosity: float
    density: float
    molar_mass: float
    compressibility: float
    vapour_pressure: float
    critical_temperature: float
    source: str

    @property
    def is_gas(self) -> bool:
        """True for a gas (or a supercritical fluid, which flows as one)."""
        return self.phase in ("gas", "supercritical")

    def gas(self) -> Gas:
        """The ideal :class:`~sealeak.physics.gas.Gas` of this state (μ at this state's T and p).

        Raises :class:`InputError` naming ``fluid`` for a liquid."""
        if not self.is_gas:
            raise InputError("fluid", self.name, f"is a {self.phase} at {self.temperature:.6g} K and {self.pressure:.6g} Pa, "
                                                 "not a gas")
        return Gas(name=self.name, temperature=self.temperature, viscosity=self.viscosity, molar_mass=self.molar_mass)


def _prop(output: str, cp_name: str, temperature: float, pressure: float) -> float:
    return float(_coolprop()[1].PropsSI(output, "T", temperature, "P", pressure, cp_name))


def fluid_state(fluid: str, temperature: float, pressure: float = ATMOSPHERE) -> FluidState:
    """The properties of the known fluid ``fluid`` at ``temperature`` T (K) and absolute ``pressure`` p (Pa).

    Raises :class:`InputError` naming ``fluid`` (unknown name, an oil), ``temperature`` (not a
    finite absolute temperature, or outside the range of the fluid's correlations, which is given)
    or ``pressure`` (not > 0, or out of range). A state on the saturation line is refused: give a
    pressure a little above or below the vapour pressure. docs/theory.md §11.1.
    """
    name = canonical_fluid_name(fluid)
    cp_name = KNOWN_FLUIDS[name][0]
    CP = _coolprop()[1]
    try:
        t = float(temperature)
    except (TypeError, ValueError):
        raise InputError("temperature", temperature, "must be an absolute temperature in K (a number)") from None
    try:
        p = float(pressure)
    except (TypeError, ValueError):
        raise InputError("pressure", pressure, "must be an absolute pressure in Pa (a number)") from None
    t_min, t_max = CP.PropsSI("Tmin", cp_name), CP.PropsSI("Tmax", cp_name)
    if not (math.isfinite(t) and t > 0):
        raise InputError("temperature", temperature, "must be an absolute temperature in K (> 0)")
    if not t_min <= t <= t_max:
        raise InputError("temperature", temperature, f"is outside the range of the property correlations of {name}: "
                                                     f"{t_min:.6g} K to {t_max:.6g} K")
    p_max = CP.PropsSI("pmax", cp_name)
    if not (math.isfinite(p) and 0 < p <= p_max):
        raise InputError("pressure", pressure, f"must be an absolute pressure > 0 and at most {p_max:.6g} Pa for {name}")
    t_crit = float(CP.PropsSI("Tcrit", cp_name))
    p_sat = float(CP.PropsSI("P", "T", t, "Q", 0, cp_name)) if t < t_crit else math.nan
    try:
        phase = _PHASES.get(CP.PhaseSI("T", t, "P", p, cp_name), "unknown")
        mu = _prop("V", cp_name, t, p)
        rho = _prop("D", cp_name, t, p)
    except ValueError as exc:
        raise InputError("temperature", temperature, f"no property of {name} at {t:.6g} K and {p:.6g} Pa from the "
                                                     f"property library ({str(exc).split(':')[0]})") from None
    molar_mass = float(CP.PropsSI("M", cp_name))
    if not all(math.isfinite(v) and v > 0 for v in (mu, rho)):
        raise InputError("temperature", temperature, f"no valid viscosity or density of {name} at {t:.6g} K and {p:.6g} Pa")
    z = p * molar_mass / (rho * MOLAR_GAS_CONSTANT * t)
    source = f"{property_library()}, viscosity: {CP.get_fluid_param_string(cp_name, 'BibTeX-VISCOSITY')}"
    return FluidState(name=name, coolprop_name=cp_name, temperature=t, pressure=p, phase=phase, viscosity=mu, density=rho,
                      molar_mass=molar_mass, compressibility=z, vapour_pressure=p_sat, critical_temperature=t_crit,
                      source=source)


def vapour_pressure_note(state: FluidState, upstream: float, downstream: float) -> str | None:
    """A warning when a liquid would boil in the leak path, else None (docs/theory.md §11.8).

    A liquid (``state.phase == "liquid"``) whose lower absolute pressure (Pa) lies below its vapour
    pressure at T may flash to vapour inside the seal: the liquid leak rate then does not hold.
    """
    if state.phase != "liquid" or not math.isfinite(state.vapour_pressure):
        return None
    low = min(float(upstream), float(downstream))
    if low >= state.vapour_pressure:
        return None
    return (f"{state.name} at {celsius(state.temperature):.4g} °C has a vapour pressure of {state.vapour_pressure:.4g} Pa; "
            f"the pressure {low:.4g} Pa at the seal is below it: the liquid may boil (flash to vapour) in the leak path, "
            "and the liquid leak rate assumes it does not")


def surface_tension(fluid: str, temperature: float) -> tuple[float, str]:
    """γ (N/m) of the known liquid ``fluid`` at ``temperature`` T (K), on its saturation line, and its source.

    The surface tension hardly depends on pressure, so the value at saturation serves a liquid at any
    pressure (docs/theory.md §12.2); e.g. water at 293.15 K: 0.0728 N/m (Mulero et al. 2012). Raises
    :class:`InputError` naming ``fluid`` for an unknown name and ``temperature`` where the fluid has no
    liquid surface (at or above its critical temperature, or outside the correlation's range).
    """
    name = canonical_fluid_name(fluid)
    cp_name = KNOWN_FLUIDS[name][0]
    CP = _coolprop()[1]
    t = float(temperature)
    try:
        gamma = float(CP.PropsSI("I", "T", t, "Q", 0, cp_name))
        source = CP.get_fluid_param_string(cp_name, "BibTeX-SURFACE_TENSION")
    except ValueError as exc:
        raise InputError("temperature", temperature, f"no surface tension of {name} at {t:.6g} K from the property "
                                                     f"library ({str(exc).split(':')[0]}); give fluid.surface_tension") from None
    if not (math.isfinite(gamma) and gamma > 0):
        raise InputError("temperature", temperature, f"no surface tension of {name} at {t:.6g} K (at or above its "
                                                     "critical temperature); give fluid.surface_tension")
    return gamma, f"{property_library()}, surface tension: {source}"
