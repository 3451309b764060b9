"""Units at the edges: parse quantities written by people into SI floats, and format SI floats back.

Only case files, data files, the CLI and reports use this module; the physics modules take and
return plain floats in SI units. Parsing uses pint, so any unit pint knows works ("44 um",
"44 µm", "2.3 MPa", "1 mPa*s", "9.1e3 1/m", "0.69 mm", "10 kPa", "ml/min"). Leak-test throughputs
("mbar*l/s", "Pa*m^3/s"), which need a reference pressure to become volume flows, are converted in
:func:`sealeak.lab.data.leak_rate_factor`.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np
import pint

from ..errors import UnitError

__all__ = ["registry", "parse_quantity", "to_si", "format_quantity", "length_unit", "SI_UNITS", "DIMENSIONS"]

#: SI unit of each physical dimension the project uses (the unit strings JSON output declares).
SI_UNITS = {
    "length": "m",
    "pressure": "Pa",
    "viscosity": "Pa*s",
    "wavevector": "1/m",
    "psd": "m^4",
    "volume_flow": "m^3/s",
    "density": "kg/m^3",
    "mass": "kg",
    "force": "N",
    "time": "s",
    "dimensionless": "1",
}

#: pint dimensionality strings of the dimensions above.
DIMENSIONS = {
    "length": "[length]",
    "pressure": "[mass] / [length] / [time] ** 2",
    "viscosity": "[mass] / [length] / [time]",
    "wavevector": "1 / [length]",
    "psd": "[length] ** 4",
    "volume_flow": "[length] ** 3 / [time]",
    "density": "[mass] / [length] ** 3",
    "mass": "[mass]",
    "force": "[mass] * [length] / [time] ** 2",
    "time": "[time]",
    "dimensionless": "",
}

_EXAMPLES = {
    "length": "'44 um', '3 cm'",
    "pressure": "'60 kPa', '0.1 MPa'",
    "viscosity": "'1 mPa*s'",
    "wavevector": "'9.1e3 1/m', '1 1/um'",
    "psd": "'1e-20 m^4'",
    "volume_flow": "'1 ml/min', '1e-9 m^3/s'",
    "density": "'1000 kg/m^3'",
    "mass": "'2 kg'",
    "force": "'20 N'",
    "time": "'10 s', '5 min'",
    "dimensionless": "'0.5'",
}


@lru_cache(maxsize=1)
def registry() -> Any:
    """The project's pint UnitRegistry (created once, on first use)."""
    return pint.UnitRegistry()


def _normalise(text: str) -> str:
    return (text.strip().replace("µ", "u").replace("μ", "u").replace("·", "*").replace("−", "-")
            .replace("²", "^2").replace("³", "^3").replace("⁴", "^4"))


def parse_quantity(field: str, value: Any, dimension: str) -> float:
    """Parse ``value`` (e.g. ``"44 um"``) as a quantity of ``dimension``; return its SI magnitude.

    A bare number is accepted only for ``"dimensionless"``: a dimensional quantity must carry its
    unit, which is never guessed. Raises :class:`UnitError` naming ``field``, the value and what is
    allowed.
    """
    if dimension not in DIMENSIONS:
        raise ValueError(f"unknown dimension {dimension!r}")
    allowed = f"a {dimension.replace('_', ' ')} with its unit, e.g. {_EXAMPLES[dimension]}"
    if isinstance(value, bool):
        raise UnitError(field, value, allowed)
    if isinstance(value, (int, float)):
        if dimension == "dimensionless":
            return float(value)
        raise UnitError(field, value, f"a bare number has no unit; give {allowed}")
    if not isinstance(value, str) or not value.strip():
        raise UnitError(field, value, allowed)
    ureg = registry()
    try:
        q = ureg.Quantity(_normalise(value))
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, SyntaxError, KeyError) as exc:
        raise UnitError(field, value, f"cannot read it ({_short(exc)}); give {allowed}") from None
    if not isinstance(q, ureg.Quantity):  # a plain number written as a string
        q = ureg.Quantity(float(q), "")
    if q.dimensionless and dimension != "dimensionless":
        raise UnitError(field, value, f"it has no unit; give {allowed}")
    try:
        mag = q.to(SI_UNITS[dimension].replace("^", "**")).magnitude
    except pint.errors.DimensionalityError:
        raise UnitError(field, value, f"its unit '{q.units:~}' is not a {dimension.replace('_', ' ')}; "
                                      f"give {allowed}") from None
    mag = float(mag)
    if not math.isfinite(mag):
        raise UnitError(field, value, f"must be finite; give {allowed}")
    return mag


def to_si(value: float, unit: str, field: str = "value", dimension: str | None = None) -> float:
    """Convert a number in ``unit`` to SI (checking the dimension when given)."""
    text = f"{value!r} {unit}" if unit.strip() not in ("", "1") else repr(value)
    if dimension is None:
        return float(registry().Quantity(_normalise(text)).to_base_units().magnitude)
    return parse_quantity(field, text, dimension)


def unit_factor(field: str, unit: str, dimension: str) -> float:
    """The factor that converts numbers in ``unit`` to SI for ``dimension`` (validates the unit)."""
    if unit.strip() in ("", "1"):
        if dimension == "dimensionless":
            return 1.0
        raise UnitError(field, unit, f"needs a unit of {dimension.replace('_', ' ')}")
    try:
        return parse_quantity(field, f"1 {unit}", dimension)
    except UnitError as exc:  # name the unit as written, not the "1 <unit>" parsed here
        raise UnitError(field, unit, exc.allowed) from None


_DISPLAY = {
    "length": [(1e-9, "nm"), (1e-6, "µm"), (1e-3, "mm"), (1.0, "m")],
    "pressure": [(1.0, "Pa"), (1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa")],
    "volume_flow": [(1e-9 / 60, "µl/min"), (1e-6 / 60, "ml/min"), (1e-3 / 60, "l/min")],
}


def length_unit(values: Any) -> tuple[float, str]:
    """(scale, name) of one length unit for a whole column or axis of ``values`` (m): nm when all
    are below 1 µm, mm when all are at least 1 cm, else µm (NaN and zeros ignored)."""
    v = np.abs(np.asarray(values, dtype=float))
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() < 1e-6:
        return 1e-9, "nm"
    if v.size and v.min() >= 1e-2:
        return 1e-3, "mm"
    return 1e-6, "µm"


def format_quantity(value: float, dimension: str, digits: int = 4) -> str:
    """Readable text for an SI value, choosing a convenient unit (e.g. 4.4e-05 m -> '44 µm')."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    scales = _DISPLAY.get(dimension)
    if not scales:
        return f"{value:.{digits}g} {SI_UNITS.get(dimension, '')}".strip()
    chosen = scales[0]
    for factor, name in scales:
        if abs(value) >= factor * 0.9999:
            chosen = (factor, name)
    return f"{value / chosen[0]:.{digits}g} {chosen[1]}"


def _short(exc: Exception) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text if len(text) < 100 else text[:97] + "..."
