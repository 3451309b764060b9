"""Units at the edges: parse quantities written by people into SI floats, and format SI floats back.

Only case files, data files, the CLI and reports use this module; the physics modules take and
return plain floats in SI units. Every quantity a user writes (case files, command-line options,
data-file headers, topography options) is read by one parser, :func:`parse_quantity`, with one
deliberately small syntax:

    quantity  :=  number [unit]         e.g. "44 um", "2.3MPa", "9.1e3 1/m", "0.5"
    number    :=  an ASCII decimal number: optional sign, digits with at most one decimal
                  point, optional exponent ("2.3", "-1e-3", ".5", "4E6"); nothing else
    unit      :=  unit names that pint knows (prefixes included: "um", "µm", "kPa", "cP", "%"),
                  joined by "*", "/" or a space, each optionally raised to an integer power of at
                  most two digits ("m^3", "m**-1", "m²"), with brackets ("Pa/(m*s)") and "1" as a
                  numerator ("1/m", "1 1/um")

Nothing is evaluated: no arithmetic between numbers ("1/0 MPa", "3 MPa + 2 kPa",
"2**1000 Pa"), no named constants as numbers ("pi MPa"), no unit without a number ("MPa").
Anything else, and every failure (an unknown unit, a unit of the wrong dimension, a number that
is not finite or not representable as a float), raises :class:`~sealeak.errors.UnitError` naming
the field, the value and what is allowed.

**No commas.** A comma is never part of a number: ``"2,3 MPa"`` (a decimal comma) and
``"1,000 Pa"`` (a thousands separator) are refused with a message saying how to write them
(``write 2.3 MPa: use a decimal point; ',' is not allowed in numbers``), never read as 23 MPa.
Data files use the same rule for their cells (:mod:`sealeak.io.tables`).

Leak-rate units (volume flows, pV throughputs such as "mbar*l/s", standard volume flows, molar and
mass flows) and the conversions between them are :mod:`sealeak.io.leak_units`.
"""

from __future__ import annotations

import math
import re
import unicodedata
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np
import pint
from numpy.typing import NDArray

from ..errors import UnitError, cut_middle

__all__ = ["registry", "parse_quantity", "parse_number", "is_number", "unit_factor", "unit_dimension", "to_si",
           "comma_advice", "split_quantities", "format_quantity", "length_unit", "SI_UNITS", "DIMENSIONS",
           "SI_RANGE", "MAX_TEMPERATURE", "outside_si_range"]

#: SI unit of each physical dimension the project uses (the unit strings JSON output declares).
SI_UNITS = {
    "length": "m",
    "pressure": "Pa",
    "viscosity": "Pa*s",
    "wavevector": "1/m",
    "psd": "m^4",
    "volume_flow": "m^3/s",
    "throughput": "Pa*m^3/s",
    "density": "kg/m^3",
    "mass": "kg",
    "force": "N",
    "force_per_length": "N/m",
    "surface_tension": "N/m",  # a force per length too; its own name words its messages
    "area_per_time": "m^2/s",
    "molar_permeability": "mol/(m*s*Pa)",
    "time": "s",
    "acceleration": "m/s^2",
    "volume": "m^3",
    "thermal_expansion": "1/K",
    "molar_energy": "J/mol",
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
    "throughput": "[mass] * [length] ** 2 / [time] ** 3",
    "density": "[mass] / [length] ** 3",
    "mass": "[mass]",
    "force": "[mass] * [length] / [time] ** 2",
    "force_per_length": "[mass] / [time] ** 2",
    "surface_tension": "[mass] / [time] ** 2",
    "area_per_time": "[length] ** 2 / [time]",
    "molar_permeability": "[substance] * [time] / [mass]",
    "time": "[time]",
    "acceleration": "[length] / [time] ** 2",
    "volume": "[length] ** 3",
    "thermal_expansion": "1 / [temperature]",
    "molar_energy": "[mass] * [length] ** 2 / [time] ** 2 / [substance]",
    "dimensionless": "",
}

_EXAMPLES = {
    "length": "'44 um', '3 cm'",
    "pressure": "'60 kPa', '0.1 MPa'",
    "viscosity": "'1 mPa*s'",
    "wavevector": "'9.1e3 1/m', '1 1/um'",
    "psd": "'1e-20 m^4'",
    "volume_flow": "'1 ml/min', '1e-9 m^3/s'",
    "throughput": "'1e-6 mbar*l/s', '1e-7 Pa*m^3/s' (a leak-test pV throughput)",
    "density": "'1000 kg/m^3'",
    "mass": "'2 kg'",
    "force": "'20 N'",
    "force_per_length": "'5 N/mm', '5000 N/m'",
    "surface_tension": "'72.8 mN/m', '0.0728 N/m'",
    "area_per_time": "'1e-10 m^2/s', '1e-6 cm^2/s', '1e-13 Pa*m^3*m/(m^2*s*Pa)'",
    "molar_permeability": "'1e-15 mol/(m*s*Pa)', '1e-15 mol*m/(m^2*s*Pa)'",
    "time": "'10 s', '5 min'",
    "acceleration": "'9.81 m/s^2'",
    "volume": "'0.5 l', '250 ml', '1e-4 m^3'",
    "thermal_expansion": "'2.3e-4 1/K' (a linear expansion coefficient)",
    "molar_energy": "'80 kJ/mol'",
    "dimensionless": "'0.5'",
}

#: The longest quantity or unit text read (longer text is refused, not parsed).
MAX_TEXT = 200
_MAX_DEPTH = 3  # brackets nested in a unit

_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NOT_FINITE = re.compile(r"[+-]?(?:nan|inf(?:inity)?)(?![A-Za-z])", re.IGNORECASE)
_UNIT_TOKEN = re.compile(r"\s*(?:(?P<name>[^\W\d_][\w]*|%)|(?P<pow>\*\*|\^)|(?P<op>[*/])|(?P<open>\()|(?P<close>\))"
                         r"|(?P<int>[+-]?[0-9]+))")
_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_KNOWN_SPELLINGS = ("Pa", "kPa", "MPa", "GPa", "hPa", "mPa", "mbar", "bar", "psi", "atm", "um", "nm", "mm", "cm", "m", "km",
                    "s", "min", "h", "ml", "l", "N", "kN", "kg", "g", "cP")


class _Unreadable(ValueError):
    """Internal: why a quantity or unit text cannot be read (turned into a UnitError naming the field)."""


class _WrongDimension(_Unreadable):
    """Internal: the unit reads, but is not of the dimension asked for."""


@lru_cache(maxsize=1)
def registry() -> Any:
    """The project's pint UnitRegistry (created once, on first use)."""
    return pint.UnitRegistry()


def _normalise(text: str) -> str:
    """One spelling for the symbols people type: µ/μ → u, · → *, − → -, superscript powers → ^n,
    any run of white space (also non-breaking) → one space."""
    text = re.sub(r"\s+", " ", text).strip()
    text = text.replace("µ", "u").replace("\u212b", "Å").replace("μ", "u").replace("·", "*").replace("⋅", "*").replace("−", "-")
    return re.sub(r"[⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺]+", lambda m: "^" + m.group().translate(_SUPERSCRIPTS), text)


def _unit_examples(dimension: str) -> str:
    """The examples of a dimension without their numbers: "'kPa', 'MPa'"."""
    return re.sub(r"'[-+0-9.eE]+ ", "'", _EXAMPLES[dimension])


def _dim_name(dimension: str) -> str:
    return dimension.replace("_", " ")


def _article(name: str) -> str:
    """"a pressure", "an acceleration"."""
    return f"{'an' if name[0] in 'aeiou' else 'a'} {name}"


def _allowed(dimension: str) -> str:
    if dimension == "dimensionless":
        return f"a number, e.g. {_EXAMPLES[dimension]}"
    return f"{_article(_dim_name(dimension))} with its unit, e.g. {_EXAMPLES[dimension]}"


# ---------------------------------------------------------------------------------------- commas
def comma_advice(text: str) -> str:
    """Why ``text`` (which holds a ',') is refused, and how to write it.

    ``"2,3 MPa"`` → ``"write 2.3 MPa: use a decimal point; ',' is not allowed in numbers"``;
    ``"1,000,000 Pa"`` → thousands separators; ``"1,000 Pa"`` (either) names both readings.
    """
    text = text.strip()
    m = re.search(r"[0-9]+(?:,[0-9]+)+", text)
    if m is None:  # a comma not inside a number: a list, or a stray comma
        return "',' is not allowed here: give one number and its unit, without a comma"
    groups = m.group().split(",")
    after = text[m.end():m.end() + 1]
    without = text[:m.start()] + "".join(groups) + text[m.end():]
    decimal = text[:m.start()] + ".".join(groups) + text[m.end():]
    grouped = all(len(g) == 3 for g in groups[1:])  # 1,000 or 12,345,678: thousands separators
    if len(groups) > 2 or after == ".":
        if grouped:
            return f"write {without}: ',' is not allowed in numbers (no thousands separators)"
        return "',' is not allowed in numbers: use a decimal point, and no thousands separators"
    if grouped and after not in ("e", "E"):
        return (f"',' is not allowed in numbers: write {without} (no thousands separator), "
                f"or {decimal} if the comma is a decimal comma")
    return f"write {decimal}: use a decimal point; ',' is not allowed in numbers"


def split_quantities(field: str, text: str, max_items: int = 2) -> list[str]:
    """Split a comma-separated list of quantities (``"1 mm, 0.5 mm"``) into its items.

    A comma between two digits is a decimal comma, not a separator: ``"2,3 mm"`` is refused
    with :func:`comma_advice` (write ``"2.3 mm"``, or ``"2 mm, 3 mm"`` for two values).
    """
    if re.search(r"[0-9],[0-9]", text):
        m = re.search(r"[0-9]+,[0-9]+", text)
        assert m is not None
        a, b = m.group().split(",", 1)
        unit = text[m.end():].strip() or "mm"
        raise UnitError(field, text, f"{comma_advice(text)} (for two values, give each its unit: '{a} {unit}, {b} {unit}')")
    parts = [p.strip() for p in text.split(",")]
    if any(not p for p in parts) or not 1 <= len(parts) <= max_items:
        raise UnitError(field, text, f"one value, or up to {max_items} separated by a comma, e.g. '1 mm, 0.5 mm'")
    return parts


# ---------------------------------------------------------------------------------------- numbers
def parse_number(text: str) -> float:
    """A number written as an ASCII decimal (``"2.3"``, ``"-1e-3"``, ``".5"``); ``nan`` and ``inf``
    (any case) are read as such, for the caller to refuse or accept.

    Raises ``ValueError`` for anything else: decimal commas and thousands separators (``"2,3"``,
    ``"1,000"``; the message is :func:`comma_advice`), ``"1_000"``, hexadecimal, non-ASCII digits,
    expressions. Unlike ``float()``, a number too large for a float is refused, not returned as
    inf, and a non-zero number too small for a float is refused, not returned as 0.
    """
    s = text.strip()
    if "," in s:
        raise ValueError(comma_advice(s))
    if _NOT_FINITE.fullmatch(s):
        return float(s)
    if not _NUMBER.fullmatch(s):
        raise ValueError(f"{s!r} is not a number")
    return _finite(s)


def _finite(number: str) -> float:
    value = float(number)
    if math.isinf(value):
        # (cut: a data cell of 100 000 digits made a 100 kB line)
        raise ValueError(f"the number {cut_middle(number, 39)} is too large (a float holds at most 1.8e308)")
    mantissa = re.split(r"[eE]", number)[0]
    if value == 0.0 and re.search(r"[1-9]", mantissa):
        raise ValueError(f"the number {cut_middle(number, 39)} is too small (below 1e-308 a float reads it as 0)")
    return value


def is_number(text: str, parse: Callable[[str], float] = parse_number) -> bool:
    """Whether ``parse`` (:func:`parse_number`, or e.g. ``float``) reads ``text`` as a number."""
    try:
        parse(text)
    except ValueError:
        return False
    return True


# ---------------------------------------------------------------------------------------- units
def _pint_unit_text(unit: str) -> str:
    """Check ``unit`` against the unit syntax of the module docstring; return it in pint's syntax.

    Raises :class:`_Unreadable` (the reason) for anything else. Only this checked text reaches
    pint's parser, which therefore never evaluates arithmetic.
    """
    if len(unit) > MAX_TEXT:
        raise _Unreadable(f"the unit is longer than {MAX_TEXT} characters")
    out: list[str] = []
    pos, depth, state = 0, 0, "operand"  # operand: a unit name, '(' or '1/' expected; after: an operator or the end
    while pos < len(unit):
        m = _UNIT_TOKEN.match(unit, pos)
        if m is None or m.end() == pos:
            bad = unit[pos:].strip()[:1]
            why = " (arithmetic is not evaluated: write one number, then the unit)" if bad in "+-" else ""
            raise _Unreadable(f"'{bad}' is not allowed in a unit{why}")
        pos, kind, tok = m.end(), m.lastgroup, m.group().strip()
        if kind == "name":
            if state == "after":
                out.append("*")  # "Pa s" = Pa*s
            out.append("percent" if tok == "%" else tok)
            state = "after"
        elif kind == "open":
            if state == "after":
                out.append("*")
            depth += 1
            if depth > _MAX_DEPTH:
                raise _Unreadable(f"brackets nested deeper than {_MAX_DEPTH}")
            out.append("(")
            state = "operand"
        elif kind == "close":
            if state != "after" or depth == 0:
                raise _Unreadable("unbalanced brackets" if depth == 0 else "')' after an operator")
            depth -= 1
            out.append(")")
            state = "after"
        elif kind == "op":
            if state != "after":
                raise _Unreadable(f"'{tok}' without a unit before it")
            out.append(tok)
            state = "operand"
        elif kind == "pow":
            e = _UNIT_TOKEN.match(unit, pos)
            if state != "after" or not out or out[-1].startswith("**") or e is None or e.lastgroup != "int":
                raise _Unreadable(f"'{tok}' must follow a unit and be followed by a whole number, e.g. 'm^3'")
            digits = e.group().strip().lstrip("+-")
            if len(digits) > 2:
                raise _Unreadable(f"the power {e.group().strip()} is too large (at most two digits)")
            out.append("**" + e.group().strip())
            pos = e.end()
        else:  # a bare integer: only "1" as a numerator ("1/m", "1/(m*s)")
            nxt = _UNIT_TOKEN.match(unit, pos)
            if tok != "1" or state != "operand" or nxt is None or nxt.group().strip() != "/":
                raise _Unreadable(f"the number {tok} inside the unit (give one number, then the unit)")
            out.append("1")
            state = "after"
    if depth:
        raise _Unreadable("unbalanced brackets")
    if state != "after":
        raise _Unreadable("the unit ends with an operator")
    if "percent" in out and len(out) > 1:  # "10 % %" would be 0.1 % (percent squared), "5 %/%" 5
        raise _Unreadable("'%' stands alone in a quantity: write one number, then '%' (e.g. '10 %')")
    return "".join(out)


@lru_cache(maxsize=512)
def _unit(unit: str) -> Any:
    """The pint Unit of a normalised unit text (cached); raises :class:`_Unreadable`."""
    text = _pint_unit_text(unit)
    try:
        return registry().parse_units(text)
    except pint.errors.UndefinedUnitError as exc:
        names = [str(n) for n in (exc.unit_names if isinstance(exc.unit_names, (list, tuple)) else [exc.unit_names])]
        hint = ""
        for n in names:
            near = [k for k in _KNOWN_SPELLINGS if k.lower() == n.lower()]
            if near:
                hint = f" (units are case-sensitive: did you mean {' or '.join(repr(k) for k in near)}?)"
                break
        raise _Unreadable(f"unknown unit {', '.join(repr(n) for n in names)}{hint}") from None
    except Exception as exc:  # pint's parser on text that passed the syntax check: report, never crash
        raise _Unreadable(f"cannot read the unit ({type(exc).__name__})") from None


@lru_cache(maxsize=512)
def _si_factor(unit: str, dimension: str) -> float:
    """SI factor of a normalised unit text for ``dimension``; raises :class:`_Unreadable`."""
    u = _unit(unit)
    ureg = registry()
    target = ureg.parse_units(SI_UNITS[dimension].replace("^", "**")) if dimension != "dimensionless" else None
    if u.dimensionality != ureg.get_dimensionality(DIMENSIONS[dimension]):
        shown = f"{u:~}" or "1"
        what = "dimensionless" if u.dimensionless else _article(_dim_of(u))
        raise _WrongDimension(f"its unit '{shown}' is {what}, not {_article(_dim_name(dimension))}")
    try:
        q = ureg.Quantity(1.0, u)
        factor = float(q.to(target).magnitude if target is not None else q.to("dimensionless").magnitude)
    except Exception as exc:  # offset units (degC) and the like
        raise _Unreadable(f"cannot convert the unit ({type(exc).__name__})") from None
    if not (math.isfinite(factor) and factor > 0):
        raise _Unreadable("the unit is not a finite positive multiple of the SI unit")
    return factor


def _dim_of(u: Any) -> str:
    """The project's name of a unit's dimension, else pint's dimensionality text."""
    ureg = registry()
    for name, dims in DIMENSIONS.items():
        if name != "dimensionless" and u.dimensionality == ureg.get_dimensionality(dims):
            return _dim_name(name)
    return f"quantity of dimension {u.dimensionality}"


def _split(text: str) -> tuple[str, str]:
    """(number text, unit text) of a normalised quantity; raises :class:`_Unreadable`."""
    if "," in text:
        raise _Unreadable(comma_advice(text))
    if len(text) > MAX_TEXT:
        raise _Unreadable(f"longer than {MAX_TEXT} characters")
    m = _NOT_FINITE.match(text)
    if m:
        raise _Unreadable(f"{m.group()} is not a finite number")
    m = _NUMBER.match(text)
    if m is None:
        first = text[:1]
        if not first.isascii() and unicodedata.numeric(first, None) is not None:
            raise _Unreadable(f"'{first}' is not a plain number: write numbers with the digits 0-9 and a decimal point")
        token = _UNIT_TOKEN.match(text)
        if token is not None and token.lastgroup == "name":
            raise _Unreadable("it has no number: write the number before the unit")
        raise _Unreadable("it does not start with a number")
    rest = text[m.end():].strip()
    if rest[:1] in (".", "e", "E") and rest[1:2].isdigit():
        raise _Unreadable(f"the number {m.group()}{rest.split(' ')[0]} is malformed (give one number, then the unit)")
    if rest[:1] in ("*", "/", "+", "-", "^"):
        raise _Unreadable("arithmetic is not evaluated: write one number, then the unit")
    if rest[:1].isdigit() and not re.match(r"1\s*/", rest):  # "1 000 Pa", "2 3 MPa"; "1 1/um" is fine
        raise _Unreadable("two numbers: write one number (no spaces inside it), then the unit")
    return m.group(), rest


def parse_quantity(field: str, value: Any, dimension: str) -> float:
    """Parse ``value`` (e.g. ``"44 um"``) as a quantity of ``dimension``; return its SI magnitude.

    The syntax is that of the module docstring: one decimal number and a unit, nothing evaluated,
    no comma. A bare number (a TOML number or a string without a unit) is accepted only for
    ``"dimensionless"``: a dimensional quantity must carry its unit, which is never guessed. The
    result is finite. Raises :class:`UnitError` naming ``field``, the value and what is allowed;
    never another exception.
    """
    if dimension not in DIMENSIONS:
        raise ValueError(f"unknown dimension {dimension!r}")
    allowed = _allowed(dimension)
    if isinstance(value, bool):
        raise UnitError(field, value, allowed)
    if isinstance(value, (int, float)):
        if dimension != "dimensionless":
            raise UnitError(field, value, f"a bare number has no unit; give {allowed}")
        try:
            plain = float(value)
        except OverflowError:
            raise UnitError(field, value, f"the number is too large (a float holds at most 1.8e308); give {allowed}") from None
        if not math.isfinite(plain):
            raise UnitError(field, value, f"must be a finite number; give {allowed}")
        return plain
    if not isinstance(value, str) or not value.strip():
        raise UnitError(field, value, allowed)
    text = _normalise(value)
    try:
        number, unit = _split(text)
        magnitude = _finite(number)
    except (_Unreadable, ValueError) as exc:
        raise UnitError(field, value, _with_allowed(str(exc), allowed)) from None
    if not unit:
        if dimension != "dimensionless":
            raise UnitError(field, value, f"it has no unit; give {allowed}")
        return magnitude
    try:
        factor = _si_factor(unit, dimension)
    except _Unreadable as exc:
        raise UnitError(field, value, _with_allowed(str(exc), allowed)) from None
    out = magnitude * factor
    if dimension == "dimensionless":  # (a fraction in %, a factor: each key bounds its own)
        if not math.isfinite(out):
            raise UnitError(field, value, f"too large: beyond 1.8e308; give {allowed}")
        return out
    if outside_si_range(np.array([out]))[0] or (out == 0.0 and magnitude != 0.0):
        raise UnitError(field, value, (f"too large: beyond {SI_RANGE[1]:g}" if abs(out) > 1.0 else
                                       f"too small: between 0 and {SI_RANGE[0]:g}")
                        + f" {SI_UNITS[dimension]} in SI units, far {'beyond' if abs(out) > 1.0 else 'below'} any "
                          f"seal's; give {allowed}")
    return out


def outside_si_range(values: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Per SI value: not 0 and not of a magnitude within :data:`SI_RANGE` (inf included; NaN, a missing cell, not)."""
    size = np.abs(values)
    return (size > SI_RANGE[1]) | ((size < SI_RANGE[0]) & (values != 0))


#: The magnitudes (SI units) a dimensional quantity of a case file may have (a quantity with a unit; not a fraction
#: in % or another dimensionless one, which its key bounds), 0 aside: every real seal's lengths,
#: pressures, wavevectors, spectra, times and flows lie far inside; near the ends of the doubles (1e-320 mm, 1e308 mm)
#: the physics overflows or divides by zero.
SI_RANGE = (1e-100, 1e100)
#: The highest absolute temperature a case file may give (K): far above any rubber's.
MAX_TEMPERATURE = 1e4


def _with_allowed(reason: str, allowed: str) -> str:
    """The reason, and what is allowed (unless the reason already says how to write it)."""
    return reason if reason.startswith("write ") or "',' is not allowed" in reason else f"{reason}; give {allowed}"


def _scaled_factor(unit: str, dimension: str) -> float:
    """SI factor of a normalised unit (``"kPa"``, ``"1/um"``) or scaled unit (``"0.5 um"``);
    raises :class:`_Unreadable` (or :class:`_WrongDimension`)."""
    m = _NUMBER.match(unit)
    if m is not None and not unit[m.end():].lstrip().startswith("/"):  # "0.5 um", not "1/um"
        number, unit = _split(unit)
        try:
            scale = _finite(number)
        except ValueError as exc:
            raise _Unreadable(str(exc)) from None
    else:
        scale = 1.0
    if not unit and dimension != "dimensionless":
        raise _WrongDimension(f"no unit: needs a unit of {_dim_name(dimension)}")
    factor = scale * _si_factor(unit, dimension) if unit else scale
    if not (math.isfinite(factor) and factor > 0):
        raise _Unreadable("must be a positive multiple of a unit")
    return factor


def unit_factor(field: str, unit: str, dimension: str) -> float:
    """The factor that converts numbers in ``unit`` to SI for ``dimension`` (validates the unit).

    ``unit`` is a unit (``"kPa"``, ``"1/um"``) or a scaled unit (``"0.5 um"``: numbers in units of
    0.5 µm); ``""`` or ``"1"`` is dimensionless. Same syntax as :func:`parse_quantity`; raises
    :class:`UnitError` naming ``field`` and the unit as written, never another exception.
    """
    return unit_dimension(field, unit, (dimension,))[1]


def unit_dimension(field: str, unit: str, dimensions: tuple[str, ...]) -> tuple[str, float]:
    """Which of ``dimensions`` ``unit`` is, and its SI factor: e.g. ``("throughput", 0.1)`` for
    ``"mbar*l/s"`` among ``("volume_flow", "throughput")`` (the first that fits). Raises
    :class:`UnitError` naming ``field`` if the unit cannot be read or is none of them."""
    for dimension in dimensions:
        if dimension not in DIMENSIONS:
            raise ValueError(f"unknown dimension {dimension!r}")
    wanted = " or ".join("no unit (a plain number)" if d == "dimensionless" else f"a unit of {_dim_name(d)} (e.g. {_unit_examples(d)})"
                         for d in dimensions)
    if not isinstance(unit, str):
        raise UnitError(field, unit, wanted)
    text = _normalise(unit)
    if text in ("", "1"):
        if "dimensionless" in dimensions:
            return "dimensionless", 1.0
        raise UnitError(field, unit, f"missing: give {wanted}")
    if "," in text:
        raise UnitError(field, unit, comma_advice(text))
    wrong = ""
    for dimension in dimensions:
        try:
            return dimension, _scaled_factor(text, dimension)
        except _WrongDimension as exc:
            wrong = str(exc)
        except _Unreadable as exc:
            raise UnitError(field, unit, f"{exc}; give {wanted}") from None
    if len(dimensions) > 1:
        wrong = wrong.split(", not a ")[0] + ", not " + " nor ".join(f"a {_dim_name(d)}" for d in dimensions)
    raise UnitError(field, unit, f"{wrong}; give {wanted}")


def to_si(value: float, unit: str, field: str = "value", dimension: str | None = None) -> float:
    """Convert a number in ``unit`` to SI (checking the dimension when given; else any unit, to its
    SI base units)."""
    if dimension is not None:
        return float(value) * unit_factor(field, unit, dimension)
    try:
        u = _unit(_normalise(unit)) if unit.strip() not in ("", "1") else registry().dimensionless
    except _Unreadable as exc:
        raise UnitError(field, unit, str(exc)) from None
    return float(registry().Quantity(float(value), u).to_base_units().magnitude)


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


# ---------------------------------------------------------------------------------------- temperatures
# Absolute temperatures in offset units (°C, °F). Leak-rate units are :mod:`sealeak.io.leak_units`.
__all__ += ["parse_temperature"]

_ABSOLUTE_TEMPERATURE_UNITS = "K (kelvin, also mK), degC (°C), degF (°F), degR (rankine)"
_TEMPERATURE_ALLOWED = "a temperature with its unit, e.g. '20 degC', '20 °C', '293.15 K', '68 degF'"


def parse_temperature(field: str, value: Any) -> float:
    """An absolute temperature in K from text with its unit: ``"20 degC"``, ``"20 °C"``, ``"293.15 K"``, ``"68 degF"``.

    The number syntax is :func:`parse_quantity`'s. A bare number is refused (°C or K cannot be
    guessed), and so are a unit that is not a temperature (``"20 C"`` is coulombs: the message says
    to write ``degC``) and a temperature at or below absolute zero. Raises :class:`UnitError`
    naming ``field``.
    """
    if isinstance(value, bool) or isinstance(value, (int, float)):
        raise UnitError(field, value, f"a bare number has no unit (°C or K?); give {_TEMPERATURE_ALLOWED}")
    if not isinstance(value, str) or not value.strip():
        raise UnitError(field, value, f"give {_TEMPERATURE_ALLOWED}")
    text = _normalise(value).replace("°C", "degC").replace("°F", "degF").replace("℃", "degC").replace("°K", "K")
    try:
        number, unit = _split(text)
        magnitude = _finite(number)
        if not unit:
            raise _Unreadable("it has no unit (°C or K?)")
        u = _unit(unit)
    except (_Unreadable, ValueError) as exc:
        raise UnitError(field, value, _with_allowed(str(exc), _TEMPERATURE_ALLOWED)) from None
    ureg = registry()
    if u.dimensionality != ureg.get_dimensionality("[temperature]"):
        hint = " (for degrees Celsius write 'degC' or '°C')" if unit.strip() in ("C", "c", "deg C", "deg") else ""
        raise UnitError(field, value, f"its unit '{unit}' is not a temperature{hint}; give {_TEMPERATURE_ALLOWED}")
    if "delta" in str(u) or len(unit.split()) > 1 or any(c in unit for c in "*/^()"):
        # pint's delta_degC (a temperature difference) would read "20 delta_degC" as 20 K = -253 °C
        raise UnitError(field, value, f"'{unit}' is not the unit of an absolute temperature (a temperature difference or a "
                                      f"compound unit); allowed units: {_ABSOLUTE_TEMPERATURE_UNITS}; give {_TEMPERATURE_ALLOWED}")
    try:
        kelvin = float(ureg.Quantity(magnitude, u).to("kelvin").magnitude)
    except Exception as exc:  # e.g. a temperature difference unit pint cannot place on the absolute scale
        raise UnitError(field, value, f"cannot convert it to kelvin ({type(exc).__name__}); give {_TEMPERATURE_ALLOWED}") from None
    if not (math.isfinite(kelvin) and kelvin > 0):
        raise UnitError(field, value, f"is at or below absolute zero ({kelvin:.6g} K); give {_TEMPERATURE_ALLOWED}")
    if kelvin > MAX_TEMPERATURE:
        raise UnitError(field, value, f"is above {MAX_TEMPERATURE:g} K, far above any rubber's; give {_TEMPERATURE_ALLOWED}")
    return kelvin


# The units a time is shown in.
__all__ += ["TIME_UNITS", "YEAR"]

#: A (Julian) year in s: 365.25 days.
YEAR = 365.25 * 86400.0
#: The units a time (s) is shown in, longest first: (seconds per unit, symbol, word) — the symbols of
#: ``conditions.time`` ("a", "d"), the words of the rig's texts and figures ("years", "days").
TIME_UNITS: tuple[tuple[float, str, str], ...] = (
    (YEAR, "a", "years"), (86400.0, "d", "days"), (3600.0, "h", "h"), (60.0, "min", "min"), (1.0, "s", "s"))


# Spreads written beside a value ("1.5 um ± 10 %"): the parts of a quantity and the ratio of two units.
__all__ += ["quantity_parts", "difference_factor", "pint_unit"]


def quantity_parts(field: str, value: Any) -> tuple[float, str]:
    """(number, unit text) of a quantity as written: ``"1.5 um"`` → ``(1.5, "um")``, ``0.8`` → ``(0.8, "")``.

    The number syntax is :func:`parse_quantity`'s and the unit is checked against the unit syntax (not against a
    dimension: the caller parses the value with its dimension). Raises :class:`UnitError` naming ``field``.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise UnitError(field, value, "must be a number or a quantity with its unit, e.g. '1.5 um'")
    if not isinstance(value, str):
        return parse_quantity(field, value, "dimensionless"), ""
    try:
        number, unit = _split(_normalise(value))
        magnitude = _finite(number)
        if unit:
            _unit(unit)
    except (_Unreadable, ValueError) as exc:
        raise UnitError(field, value, _with_allowed(str(exc), "a number and its unit, e.g. '1.5 um'")) from None
    return magnitude, unit


def difference_factor(field: str, value: Any, from_unit: str, to_unit: str) -> float:
    """The factor that converts a difference (a spread) written in ``from_unit`` to ``to_unit``: ``"um"`` → ``"mm"`` is
    1e-3, ``"K"`` → ``"degC"`` is 1 (a difference of offset units has no offset). Units as :func:`quantity_parts` gives
    them ("" is dimensionless); raises :class:`UnitError` naming ``field`` and ``value`` when the dimensions differ."""
    if from_unit == to_unit:
        return 1.0
    ureg = registry()
    try:
        source = _unit(from_unit) if from_unit else ureg.dimensionless
        target = _unit(to_unit) if to_unit else ureg.dimensionless
        try:
            a, b = (ureg.Quantity(x, source) for x in (1.0, 2.0))
            factor = float(b.to(target).magnitude - a.to(target).magnitude)
        except Exception:  # a difference unit ("5 delta_degC") against an offset unit (degC, degF): to its difference
            factor = float(ureg.Quantity(1.0, source).to(_offset_difference(target)).magnitude)
    except Exception:  # pint's DimensionalityError and the like: one line naming the field
        shown = to_unit or "a plain number"
        raise UnitError(field, value, f"the spread's unit '{from_unit or '1'}' does not convert to the value's unit "
                                      f"'{shown}': give the spread in a unit of the same kind, or as a percentage") from None
    if not (math.isfinite(factor) and factor > 0):
        raise UnitError(field, value, "the spread's unit is not a positive multiple of the value's unit")
    return factor


def _offset_difference(unit: Any) -> Any:
    """The difference unit of an offset unit: degC → delta_degC (pint's name for a temperature difference in °C)."""
    return registry().Unit("delta_" + str(unit))


def pint_unit(field: str, unit: str) -> Any:
    """The pint Unit of a unit text as :func:`quantity_parts` gives it ("" is dimensionless); :class:`UnitError` naming
    ``field`` when it does not read."""
    if not unit:
        return registry().dimensionless
    try:
        return _unit(_normalise(unit))
    except _Unreadable as exc:
        raise UnitError(field, unit, str(exc)) from None
