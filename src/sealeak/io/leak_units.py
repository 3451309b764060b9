"""Leak-rate units: the one module where a leak rate changes unit (docs/theory.md §11.6); and gas permeabilities.

A leak rate is written in one of five kinds of unit, each with its SI unit:

* a volume flow, m³/s (``ml/min``, ``l/h``): a liquid's leak, or a gas's at a stated pressure;
* a pV throughput, Pa·m³/s (``mbar*l/s``, ``Torr*l/s``, ``atm*cc/s``): the unit of gas leak tests;
* a standard volume flow, m³/s at 0 °C and 101325 Pa (``sccm``, ``slm``);
* a molar flow, mol/s, and a mass flow, kg/s (``g/a``).

Between the kinds: a pV throughput is a volume flow times the pressure p it is counted at
(:func:`leak_rate_factor`, the default p is 1 atm), and, for a gas of molar mass M at temperature T
(ideal gas), ṅ = Q_pV/(R T) = ṁ/M = P0 V̇0/(R T0) (:func:`molar_flow_factor`,
:func:`convert_leak_rate`, :func:`pv_throughput`). Units are read by pint (through
:mod:`sealeak.io.units`); the constants R, 1 atm and 0 °C are :mod:`scipy.constants`'. The named
factors below (ml/min, mbar·l/s, sccm) are the ones front ends print with.

A gas permeability is written in the pV form sealeak computes with, m²/s (the pV throughput of the
gas at its temperature T per area and per pressure gradient), or as published: a molar
permeability Π in mol/(m·s·Pa), or in Barrer (10⁻¹⁰ cm³(STP)·cm/(cm²·s·cmHg)). The pV form is
P = Π R T (:func:`parse_permeability`).
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.constants import R, atm, bar, centi, hour, liter, milli, minute, mmHg, zero_Celsius

from ..errors import UnitError
from .units import _finite, _normalise, _split, _unit, _Unreadable, _with_allowed, comma_advice, parse_quantity, registry, unit_dimension

__all__ = ["MOLAR_GAS_CONSTANT", "ZERO_CELSIUS", "ATMOSPHERE", "STANDARD_TEMPERATURE", "STANDARD_PRESSURE",
           "M3_PER_S_PER_ML_PER_MIN", "ML_PER_MIN_PER_M3_PER_S", "PA_M3_PER_MBAR_L", "MBAR_L_PER_PA_M3", "MOL_PER_STANDARD_M3",
           "MOL_PER_S_PER_SCCM", "LEAK_RATE_KINDS", "celsius", "to_ml_per_min", "to_mbar_l_per_s", "to_sccm",
           "leak_rate_unit", "leak_rate_factor", "molar_flow_factor", "convert_leak_rate", "parse_leak_rate", "pv_throughput",
           "MOL_PER_M_S_PA_PER_BARRER", "parse_permeability", "barrer_as_molar"]

#: The molar gas constant R = N_A k_B, J/(mol·K) (exact since 2019; :data:`scipy.constants.R`).
MOLAR_GAS_CONSTANT: float = R

#: 0 °C in K.
ZERO_CELSIUS: float = zero_Celsius

#: 1 atm in Pa: the default pressure at which pV throughputs (mbar·l/s, Pa·m³/s) become volume flows (ambient).
ATMOSPHERE: float = atm

#: Standard conditions of standard volume flows (sccm, slm): 0 °C and 101325 Pa (DIN 1343, SEMI E12), ideal gas.
STANDARD_TEMPERATURE: float = ZERO_CELSIUS
STANDARD_PRESSURE: float = ATMOSPHERE

#: m³/s per ml/min, and ml/min per m³/s (the command-line table's second leak-rate unit).
M3_PER_S_PER_ML_PER_MIN: float = milli * liter / minute
ML_PER_MIN_PER_M3_PER_S: float = 1.0 / M3_PER_S_PER_ML_PER_MIN

#: Pa·m³/s per mbar·l/s (100 Pa × 1 l = 0.1 Pa·m³), and mbar·l/s per Pa·m³/s.
PA_M3_PER_MBAR_L: float = milli * bar * liter
MBAR_L_PER_PA_M3: float = 1.0 / PA_M3_PER_MBAR_L

#: mol per m³ of an ideal gas at the standard conditions, P0/(R T0).
MOL_PER_STANDARD_M3: float = STANDARD_PRESSURE / (MOLAR_GAS_CONSTANT * STANDARD_TEMPERATURE)

#: Kinds of leak rate → (SI unit, pint dimensionality, examples).
LEAK_RATE_KINDS = {
    "throughput": ("Pa*m^3/s", "[mass] * [length] ** 2 / [time] ** 3", "'mbar*l/s', 'Pa*m^3/s'"),
    "standard_volume_flow": ("m^3/s at 0 °C and 101325 Pa", "", "'sccm', 'slm'"),
    "molar_flow": ("mol/s", "[substance] / [time]", "'mol/s'"),
    "mass_flow": ("kg/s", "[mass] / [time]", "'kg/s', 'g/a'"),
    "volume_flow": ("m^3/s", "[length] ** 3 / [time]", "'ml/min' (at a stated pressure)"),
}
#: Standard volume flows: unit name → m³/s (at STANDARD_TEMPERATURE and STANDARD_PRESSURE) per unit.
_STANDARD_FLOWS = {"sccm": milli * liter / minute, "sccs": milli * liter, "slm": liter / minute, "slpm": liter / minute,
                   "scch": milli * liter / hour}
_LEAK_UNITS_ALLOWED = ("a leak rate: a pV throughput ('mbar*l/s', 'Pa*m^3/s', 'Torr*l/s'), a standard volume flow ('sccm', "
                       "'slm'), a molar flow ('mol/s') or a mass flow ('kg/s', 'g/a')")

#: mol/s per sccm (1 cm³/min at the standard conditions).
MOL_PER_S_PER_SCCM: float = _STANDARD_FLOWS["sccm"] * STANDARD_PRESSURE / (MOLAR_GAS_CONSTANT * STANDARD_TEMPERATURE)


def celsius(temperature: Any) -> Any:
    """An absolute temperature (K) in °C, for display."""
    return temperature - ZERO_CELSIUS


def to_ml_per_min(volume_flow: Any) -> Any:
    """A volume flow (m³/s) in ml/min."""
    return volume_flow * ML_PER_MIN_PER_M3_PER_S


def to_mbar_l_per_s(throughput: Any) -> Any:
    """A pV throughput (Pa·m³/s) in mbar·l/s."""
    return throughput / PA_M3_PER_MBAR_L


def to_sccm(molar_flow: Any) -> Any:
    """A molar flow (mol/s) as a standard volume flow in sccm (cm³/min at 0 °C and 101325 Pa)."""
    return molar_flow / MOL_PER_S_PER_SCCM


def _leak_text(unit: str) -> str:
    """Normalised leak-rate unit text: also 'mbar.l/s' (a dot between two unit names is a product) and 'Torr'."""
    text = _normalise(unit)
    text = re.sub(r"(?<=[A-Za-z])\.(?=[A-Za-z])", "*", text)
    return re.sub(r"\bTorr\b", "torr", text)


def leak_rate_unit(field: str, unit: str) -> tuple[str, float]:
    """(kind, factor) of a leak-rate unit: the kind (a key of :data:`LEAK_RATE_KINDS`) and the factor to its SI unit.

    ``"mbar*l/s"`` (also ``"mbar l/s"``, ``"mbar·l/s"``, ``"mbar.l/s"``) → ``("throughput", 0.1)``;
    ``"sccm"`` → ``("standard_volume_flow", 1e-6/60)``; ``"mol/s"`` → ``("molar_flow", 1.0)``;
    ``"g/a"`` → ``("mass_flow", 1e-3/31557600)`` (a Julian year of 365.25 days). Raises
    :class:`UnitError` naming ``field`` for anything else.
    """
    if not isinstance(unit, str) or not unit.strip():
        raise UnitError(field, unit, f"missing: give {_LEAK_UNITS_ALLOWED}")
    text = _leak_text(unit)
    if text.lower() in _STANDARD_FLOWS:
        return "standard_volume_flow", _STANDARD_FLOWS[text.lower()]
    if "," in text:
        raise UnitError(field, unit, comma_advice(text))
    try:
        u = _unit(text)
    except _Unreadable as exc:
        raise UnitError(field, unit, f"{exc}; give {_LEAK_UNITS_ALLOWED}") from None
    ureg = registry()
    for kind, (si, dims, _examples) in LEAK_RATE_KINDS.items():
        if dims and u.dimensionality == ureg.get_dimensionality(dims):
            factor = float(ureg.Quantity(1.0, u).to(ureg.parse_units(si.replace("^", "**"))).magnitude)
            return kind, factor
    raise UnitError(field, unit, f"its unit '{unit}' is not a leak rate; give {_LEAK_UNITS_ALLOWED}")


def molar_flow_factor(field: str, unit: str, *, temperature: float, molar_mass: float, pressure: float | None = None) -> float:
    """mol/s per one ``unit`` of leak rate of a gas of ``molar_mass`` M (kg/mol) at ``temperature`` T (K).

    pV throughput: ṅ = Q_pV/(R T) (the pV counted at the gas temperature T); standard volume flow:
    ṅ = P0 V̇0/(R T0) with T0 = 273.15 K, P0 = 101325 Pa; mass flow: ṅ = ṁ/M; a plain volume flow
    needs the absolute ``pressure`` p (Pa) it is counted at: ṅ = p V̇/(R T). Ideal gas throughout
    (docs/theory.md §11.6).
    """
    kind, factor = leak_rate_unit(field, unit)
    if not (math.isfinite(temperature) and temperature > 0):
        raise UnitError("temperature", temperature, "must be an absolute temperature > 0 K")
    if not (math.isfinite(molar_mass) and molar_mass > 0):
        raise UnitError("molar_mass", molar_mass, "must be a molar mass > 0 (kg/mol)")
    if kind == "throughput":
        return factor / (MOLAR_GAS_CONSTANT * temperature)
    if kind == "standard_volume_flow":
        return factor * STANDARD_PRESSURE / (MOLAR_GAS_CONSTANT * STANDARD_TEMPERATURE)
    if kind == "molar_flow":
        return factor
    if kind == "mass_flow":
        return factor / molar_mass
    if pressure is None or not (math.isfinite(pressure) and pressure > 0):
        raise UnitError(field, unit, "a volume flow of a gas needs the absolute pressure it is counted at; give a pV "
                                     "throughput ('mbar*l/s') or a standard volume flow ('sccm') instead")
    return factor * pressure / (MOLAR_GAS_CONSTANT * temperature)


def convert_leak_rate(value: float, from_unit: str, to_unit: str, *, temperature: float, molar_mass: float,
                      pressure: float | None = None, field: str = "leak rate") -> float:
    """``value`` in ``from_unit`` converted to ``to_unit`` for a gas of ``molar_mass`` (kg/mol) at ``temperature`` (K).

    Through the molar flow: value · n(from_unit)/n(to_unit), with :func:`molar_flow_factor`; e.g.
    1 mbar·l/s of helium at 20 °C is 0.1/(R · 293.15 K) mol/s = 4.1e-5 mol/s.
    """
    n_from = molar_flow_factor(field, from_unit, temperature=temperature, molar_mass=molar_mass, pressure=pressure)
    n_to = molar_flow_factor(field, to_unit, temperature=temperature, molar_mass=molar_mass, pressure=pressure)
    return float(value) * n_from / n_to


def parse_leak_rate(field: str, value: Any, *, temperature: float, molar_mass: float, pressure: float | None = None) -> float:
    """A leak rate written with its unit (``"1e-6 mbar*l/s"``, ``"2 sccm"``, ``"5 g/a"``) as a molar flow in mol/s.

    Number syntax as :func:`parse_quantity`; the unit as :func:`leak_rate_unit`; the conversion as
    :func:`molar_flow_factor`. Raises :class:`UnitError` naming ``field``.
    """
    if isinstance(value, bool) or isinstance(value, (int, float)):
        raise UnitError(field, value, f"a bare number has no unit; give {_LEAK_UNITS_ALLOWED}")
    if not isinstance(value, str) or not value.strip():
        raise UnitError(field, value, f"give {_LEAK_UNITS_ALLOWED}")
    try:
        number, unit = _split(_leak_text(value))
        magnitude = _finite(number)
    except (_Unreadable, ValueError) as exc:
        raise UnitError(field, value, _with_allowed(str(exc), _LEAK_UNITS_ALLOWED)) from None
    if not unit:
        raise UnitError(field, value, f"it has no unit; give {_LEAK_UNITS_ALLOWED}")
    return magnitude * molar_flow_factor(field, unit, temperature=temperature, molar_mass=molar_mass, pressure=pressure)


def leak_rate_factor(unit: str, reference_pressure: float = ATMOSPHERE, field_name: str = "leak_rate unit") -> float:
    """Factor converting numbers in ``unit`` to a volume flow in m³/s.

    Volume flows convert directly; pV throughputs (pressure × volume / time, e.g. ``mbar*l/s``, ``Pa*m^3/s``)
    are divided by ``reference_pressure`` (Pa), the pressure at which the volume is counted.
    """

    allowed = ("a volume flow (e.g. 'ml/min', 'm^3/s') or a leak-test throughput (e.g. 'mbar*l/s', "
               "'Pa*m^3/s')")
    if not isinstance(unit, str) or not unit.strip():
        raise UnitError(field_name, unit, f"missing: give {allowed}")
    if not (np.isfinite(reference_pressure) and reference_pressure > 0):
        raise UnitError("reference pressure (--at-pressure)", reference_pressure, "must be a pressure > 0")
    dimension, factor = unit_dimension(field_name, unit, ("volume_flow", "throughput"))
    return factor if dimension == "volume_flow" else factor / reference_pressure


def pv_throughput(value: ArrayLike, kind: str, *, temperature: float, molar_mass: float,
                  pressure: float) -> NDArray[np.float64]:
    """Leak rates of one ``kind`` (a key of :data:`LEAK_RATE_KINDS`, in its SI unit) as pV throughputs Pa·m³/s
    of a gas of ``molar_mass`` M (kg/mol) at ``temperature`` T (K) (docs/theory.md §11.6).

    Throughput as is; molar flow ṅ R T; mass flow ṁ R T/M; standard volume flow ṅ = P0 V̇/(R T0)
    first; a plain volume flow p V̇ with p the absolute ``pressure`` (Pa) it is counted at.
    """
    q = np.asarray(value, dtype=float)
    rt = MOLAR_GAS_CONSTANT * temperature
    if kind == "throughput":
        return q
    if kind == "molar_flow":
        return q * rt
    if kind == "mass_flow":
        return q / molar_mass * rt
    if kind == "standard_volume_flow":
        return q * MOL_PER_STANDARD_M3 * rt
    return q * pressure


#: mol/(m·s·Pa) per Barrer: 1 Barrer = 10⁻¹⁰ cm³(STP)·cm/(cm²·s·cmHg), where 1 cm³(STP) is
#: P0·(1 cm³)/(R T0) mol of an ideal gas (0 °C, 101325 Pa) and 1 cmHg = 10 torr = 1333.22 Pa:
#: 3.346e-16 (= 760e-15/(R T0) exactly), i.e. a pV permeability of 7.60e-13 m²/s at 0 °C.
MOL_PER_M_S_PA_PER_BARRER: float = 1e-10 * (centi**3 * STANDARD_PRESSURE / (MOLAR_GAS_CONSTANT * STANDARD_TEMPERATURE)) \
    * centi / (centi**2 * 10 * mmHg)
_PERMEABILITY_FORMS = ("; or a published permeability, converted at the gas temperature T by P = Π R T: molar "
                       "('1e-15 mol/(m*s*Pa)') or in Barrer ('3 barrer')")


def _barrer(field: str, value: Any) -> float | None:
    """The number of Barrer of a permeability written in Barrer (``"3 barrer"``, any case), else None."""
    if not isinstance(value, str):
        return None
    try:
        number, unit = _split(_normalise(value))
    except _Unreadable:
        return None  # parse_quantity words what is wrong
    if unit.lower() != "barrer":
        return None
    try:
        return _finite(number)
    except ValueError as exc:
        raise UnitError(field, value, _with_allowed(str(exc), "a number of Barrer, e.g. '3 barrer'")) from None


def barrer_as_molar(field: str, value: Any) -> Any:
    """A permeability written in Barrer as the same value in mol/(m*s*Pa) (``"3 barrer"`` → ``"1.00...e-15
    mol/(m*s*Pa)"``), for readers that know no Barrer (pint); any other value as it is."""
    barrer = _barrer(field, value)
    return value if barrer is None else f"{barrer * MOL_PER_M_S_PA_PER_BARRER!r} mol/(m*s*Pa)"


def parse_permeability(field: str, value: Any, *, temperature: float) -> float:
    """A gas permeability written with its unit as the pV permeability P in m²/s of the gas at ``temperature`` T (K).

    The pV form (an area per time: ``"2e-12 m^2/s"``, ``"2e-8 cm^2/s"``) is taken as is; a molar
    permeability Π (``"1e-15 mol/(m*s*Pa)"``) or one in Barrer (``"3 barrer"``, any case, Π =
    3.346e-16 mol/(m·s·Pa) per Barrer) becomes P = Π R T, the pV throughput at T of the moles
    that permeate (ideal gas; docs/case-files.md). Number syntax as :func:`parse_quantity`. Raises
    :class:`UnitError` naming ``field``; the sign is the caller's to check.
    """
    if not (math.isfinite(temperature) and temperature > 0):
        raise UnitError("temperature", temperature, "must be an absolute temperature > 0 K")
    barrer = _barrer(field, value)
    if barrer is not None:
        return barrer * MOL_PER_M_S_PA_PER_BARRER * MOLAR_GAS_CONSTANT * temperature
    try:
        return parse_quantity(field, value, "area_per_time")
    except UnitError as exc:
        try:
            return parse_quantity(field, value, "molar_permeability") * MOLAR_GAS_CONSTANT * temperature
        except UnitError:
            raise UnitError(field, value, exc.allowed + _PERMEABILITY_FORMS) from None
