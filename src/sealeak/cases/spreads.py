"""Uncertain inputs of a case file: spreads written beside a value, and the ``[uncertainty]`` table.

A value may carry a spread (a normal distribution)::

    h_rms = "1.5 um ± 10 %"        # relative: a standard deviation of 10 % of the value ("+/-" also reads)
    viscosity = "1 mPa*s ± 0.1 mPa*s"   # absolute, in any unit of the same kind
    hurst = "0.8 ± 0.05"            # a plain number

and ``[uncertainty]`` gives other distributions, keyed by ``"section.key"``::

    [uncertainty]
    "theory.alpha" = { distribution = "normal", sd = 0.1 }
    "surface.h_rms" = { distribution = "lognormal", sd = "20 %" }
    "seal.force_factor" = { distribution = "uniform", low = 0.9, high = 1.1 }
    "fluid.viscosity" = { distribution = "triangular", low = "0.8 mPa*s", high = "1.5 mPa*s" }
    "theory.model" = { distribution = "choice", values = ["critical-junction", "effective-medium"] }

:func:`split_spreads` takes them out of the parsed TOML document: what is left is the nominal
document (the deterministic case, unchanged), and each :class:`UncertainInput` maps points of the unit
interval to values (:meth:`UncertainInput.ppf` in SI, :meth:`UncertainInput.written` as TOML values the
builders read). ``conditions.max_leak_rate`` (the specification a seal must meet) is taken out too.
Every refusal is one :class:`~sealeak.errors.InputError` naming ``section.key``. docs/case-files.md
("Uncertain inputs") is the reference; docs/theory.md §14 the method.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from ..errors import InputError, did_you_mean
from ..io.leak_units import barrer_as_molar
from ..io.units import difference_factor, pint_unit, quantity_parts, registry
from .form import FIELD_KINDS
from .limits import at_most
from .schema import SECTIONS

__all__ = ["DISTRIBUTIONS", "TRUNCATION", "MAX_UNCERTAIN_INPUTS", "UncertainInput", "Spreads", "split_spreads"]

#: The distributions an uncertain input may follow, and the parameters of each in ``[uncertainty]``.
DISTRIBUTIONS: dict[str, tuple[str, ...]] = {
    "normal": ("sd",), "lognormal": ("sd",), "uniform": ("low", "high"), "triangular": ("low", "high"),
    "choice": ("values",),
}
#: Normal and lognormal inputs are truncated at this many standard deviations (of the value, or of its logarithm).
TRUNCATION = 3.0
#: Uncertain inputs of one case file (each a dimension of the sample space).
MAX_UNCERTAIN_INPUTS = 32
#: Sections whose keys may not carry a spread.
_NO_SPREAD = ("study", "simulation", "uncertainty")
_PLUS_MINUS = re.compile(r"±|\+/-")
_CHOICE_MAX = 16
#: How a number starts (nan and inf too: they are refused as numbers, not as text).
_NUMBER_START = re.compile(r"\s*([-+.0-9]|[-+]?(nan|inf))", re.IGNORECASE)


@dataclass(frozen=True)
class UncertainInput:
    """One uncertain input: a case-file key and its distribution.

    Attributes
    ----------
    key
        The case-file key, ``"section.key"``.
    label
        How charts and tables name it: the key and its spread as written (``"surface.h_rms: 1.5 um ± 10 %"``).
    distribution
        One of :data:`DISTRIBUTIONS`.
    nominal
        The value as the case file writes it (the deterministic case's value).
    unit
        The unit the value is written in ('' for a plain number or a choice).
    parameters
        The distribution's parameters in that unit: ``mean``, ``sd`` (normal; lognormal: ``median``, ``sigma`` of
        the logarithm), ``low``, ``mode``, ``high`` (uniform, triangular).
    choices
        The values of a ``choice`` (e.g. two theories), as written.
    si_factor
        SI value per written value for a unit without offset (1 for a plain number), NaN for an offset unit (°C).
    """

    key: str
    label: str
    distribution: str
    nominal: Any
    unit: str = ""
    parameters: dict[str, float] = field(default_factory=dict)
    choices: tuple[str, ...] = ()
    si_factor: float = 1.0

    @property
    def is_zero(self) -> bool:
        """Whether every sample is the nominal value (a spread of zero)."""
        p = self.parameters
        if self.distribution in ("normal", "lognormal"):
            return p["sd"] == 0.0
        if self.distribution == "choice":
            return False
        return p["low"] == p["high"]

    def values(self, u: NDArray[np.float64]) -> NDArray[Any]:
        """The values at points ``u`` of the unit interval, in the written unit (a choice: the index of its value)."""
        u = np.asarray(u, dtype=float)
        p = self.parameters
        if self.distribution == "choice":
            return np.minimum((u * len(self.choices)).astype(int), len(self.choices) - 1)
        if self.is_zero:  # the very float the deterministic case reads
            return np.full(u.shape, float(quantity_parts(self.key, self.nominal)[0]))
        if self.distribution in ("normal", "lognormal"):
            lo, hi = stats.norm.cdf(-TRUNCATION), stats.norm.cdf(TRUNCATION)
            z = stats.norm.ppf(lo + u * (hi - lo))
            if self.distribution == "normal":
                return p["mean"] + p["sd"] * z
            return p["median"] * np.exp(p["sigma"] * z)
        if self.distribution == "uniform":
            return p["low"] + u * (p["high"] - p["low"])
        width = p["high"] - p["low"]
        return np.asarray(stats.triang.ppf(u, (p["mode"] - p["low"]) / width, loc=p["low"], scale=width))

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The values at points ``u`` of the unit interval in SI units (a choice: the index of its value, 0, 1, ...)."""
        v = self.values(u)
        if self.distribution == "choice":
            return v.astype(float)
        if math.isnan(self.si_factor):  # an offset unit: °C → K
            return np.asarray(registry().Quantity(v, pint_unit(self.key, self.unit)).to_base_units().magnitude, dtype=float)
        return v * self.si_factor

    def written(self, u: NDArray[np.float64]) -> list[Any]:
        """The values at points ``u`` as the case file would write them (for the builders): text with the unit, a
        number, or the chosen value."""
        v = self.values(u)
        if self.is_zero:  # the value as written: the deterministic case bit for bit
            return [self.nominal] * v.size
        if self.distribution == "choice":
            return [self.choices[int(i)] for i in v]
        if not self.unit:
            return [float(x) for x in v]
        return [f"{float(x)!r} {self.unit}" for x in v]


@dataclass(frozen=True)
class Spreads:
    """What :func:`split_spreads` took out of a case document: the uncertain inputs, and the specification."""

    inputs: tuple[UncertainInput, ...] = ()
    #: ``conditions.max_leak_rate`` as written (a leak rate with its unit), or None.
    max_leak_rate: Any = None

    @property
    def active(self) -> bool:
        """Whether the case file asks for the uncertainty propagation (spreads or a specification)."""
        return bool(self.inputs) or self.max_leak_rate is not None


def _si_factor(key: str, unit: str) -> float:
    if not unit:
        return 1.0
    ureg = registry()
    try:
        one, two = (float(ureg.Quantity(x, pint_unit(key, unit)).to_base_units().magnitude) for x in (1.0, 2.0))
    except Exception:  # pragma: no cover - a unit pint cannot express in base units
        return math.nan
    return one if math.isclose(two, 2.0 * one, rel_tol=1e-12) else math.nan  # NaN: an offset unit (°C)


def _number(field: str, value: Any, unit: str, *, relative_to: float | None = None) -> float:
    """A parameter (a spread or a bound) in the value's ``unit``: text with a unit, a plain number, or ``"10 %"`` of
    ``relative_to`` (a spread)."""
    magnitude, u = quantity_parts(field, value)
    if u == "%" and relative_to is not None:  # relative, also for a value in % ("20 % ± 0.02" is 2 points)
        return magnitude / 100.0 * abs(relative_to)
    return magnitude * difference_factor(field, value, u, unit)


def _is_relative(value: Any) -> bool:
    """Whether a spread as written is relative ("10 %")."""
    return isinstance(value, str) and value.strip().endswith("%")


def _log_sd(ratio: float) -> float:
    """σ, the standard deviation of the logarithm, of a lognormal whose standard deviation is ``ratio`` times its median
    m (docs/theory.md eq. 14.2). Its standard deviation is m √(x (x − 1)) with x = e^(σ²), so x = (1 + √(1 + 4 ratio²))/2:
    σ² = ln x = ln(1 + 2 ratio²/(1 + √(1 + 4 ratio²))), and ≈ ln ratio + ln(1 + 1/(2 ratio)) where ratio² would overflow.
    (√ln(1 + ratio²) is the σ for a spread relative to the *mean*: with the value as the median it gave a standard
    deviation 3 % too large at 25 %, 41 % at 100 %.)"""
    if ratio < 1e150:
        return math.sqrt(math.log1p(2.0 * ratio * ratio / (1.0 + math.hypot(1.0, 2.0 * ratio))))
    return math.sqrt(math.log(ratio) + math.log1p(0.5 / ratio))


def _bound(field: str, value: Any, unit: str) -> float:
    """A bound (low, high) in the value's unit (an absolute value: offsets converted)."""
    magnitude, u = quantity_parts(field, value)
    if u == unit:
        return magnitude
    try:
        return float(registry().Quantity(magnitude, pint_unit(field, u)).to(pint_unit(field, unit)).magnitude)
    except Exception:
        raise InputError(field, value, f"does not convert to the value's unit '{unit or '1'}': give it in a unit of the "
                                       "same kind") from None


def _make(key: str, nominal: Any, distribution: str, params: dict[str, Any], written: str) -> UncertainInput:
    """The :class:`UncertainInput` of ``key`` (value ``nominal``) with the parameters as written."""
    label = f"{key}: {nominal}" + (f" ± {params.get('sd')}" if written == "±" else f" ({distribution}, "
                                   + ", ".join(f"{k} = {v}" for k, v in params.items() if k != "distribution") + ")")
    if distribution != "choice":
        nominal = barrer_as_molar(key, nominal)
        params = {k: barrer_as_molar(f"uncertainty.{key}.{k}", v) for k, v in params.items()}
    table = written == "[uncertainty]"
    where, shown = (f"uncertainty.{key}.sd", params.get("sd")) if table else (key, f"{nominal} ± {params.get('sd')}")
    if distribution == "choice":
        values = params.get("values")
        if not isinstance(values, list) or not 2 <= len(values) <= _CHOICE_MAX:
            raise InputError(f"uncertainty.{key}.values", values, f"must be a list of 2 to {_CHOICE_MAX} values to choose from")
        if key == "theory.model" and "both" in values:  # (its rows show the critical junction: the spread collapsed)
            raise InputError(f"uncertainty.{key}.values", values, "choose between single theories ('critical-junction', "
                                                                  "'effective-medium'): 'both' computes both and its rows "
                                                                  "show the critical junction, which it would sample again")
        return UncertainInput(key, f"{key}: one of {', '.join(map(str, values))}", "choice", nominal,
                              choices=tuple(values))
    if isinstance(nominal, str) and not _PLUS_MINUS.search(nominal) and not _NUMBER_START.match(nominal):
        raise InputError(key, nominal, f"is text: a spread needs a number or a quantity ({distribution} allowed only on "
                                       "numbers; for text give { distribution = \"choice\", values = [...] })")
    x, unit = quantity_parts(key, nominal)
    p: dict[str, float] = {}
    if distribution in ("normal", "lognormal"):
        # a temperature in °C or °F counts from an arbitrary zero: its spread is judged on the absolute temperature
        offset = math.isnan(_si_factor(key, unit))
        if offset and distribution == "lognormal":
            raise InputError(where, shown, f"a lognormal of a value in {unit} counts from that scale's arbitrary zero: "
                                           "give the value in K")
        if offset and _is_relative(params["sd"]):
            raise InputError(where, shown, f"a relative spread of a value in {unit} counts from that scale's arbitrary "
                                           "zero: give the spread in kelvin ('± 5 K'), or the value in K")
        try:
            sd = _number(where, params["sd"], unit, relative_to=x)
        except InputError as exc:  # named as written: "1.5 um ± 10", not its spread "10" alone
            raise InputError(where, shown, exc.allowed) from None
        if not (math.isfinite(sd) and sd >= 0):
            raise InputError(where, shown, "the spread must be a standard deviation >= 0")
        if distribution == "normal":
            # a temperature in °C or °F: the spread in kelvin against the absolute temperature
            absolute, size = (_bound(key, nominal, "K"), sd * difference_factor(where, nominal, unit, "K")) if offset else (x, sd)
            shown_value = f"{absolute:g} K" if offset else f"{x:g} {unit}"
            if absolute > 0 and size > 0 and size * TRUNCATION >= absolute:
                raise InputError(where, shown, f"a normal spread must stay below 1/{TRUNCATION:g} of the value "
                                                      f"({shown_value}) so that no sample reaches zero (the normal is "
                                                      f"truncated at ±{TRUNCATION:g} sd); use a lognormal for wider spreads")
            p = {"mean": x, "sd": sd}
        else:
            if not x > 0:
                raise InputError(key, nominal, "a lognormal needs a value > 0 (its median)")
            sigma = _log_sd(sd / x)
            if not math.isfinite(sigma):
                raise InputError(where, shown, f"the spread is too wide for a lognormal of median {x:g} {unit}")
            p = {"median": x, "sd": sd, "sigma": sigma}
    else:
        lo = _bound(f"uncertainty.{key}.low", params["low"], unit)
        hi = _bound(f"uncertainty.{key}.high", params["high"], unit)
        if not lo <= hi:
            raise InputError(f"uncertainty.{key}", {"low": params["low"], "high": params["high"]}, "low must not exceed high")
        if not lo <= x <= hi:
            raise InputError(f"uncertainty.{key}", {"low": params["low"], "high": params["high"]},
                             f"the value {nominal!r} must lie between low and high (it is the deterministic case's value"
                             + (" and the triangle's mode)" if distribution == "triangular" else ")"))
        p = {"low": lo, "high": hi} | ({"mode": x} if distribution == "triangular" else {})
    return UncertainInput(key, label, distribution, nominal, unit, p, si_factor=_si_factor(key, unit))


def _plus_minus(key: str, text: str) -> tuple[str, str]:
    """(value, spread) of ``"1.5 um ± 10 %"``; one line naming ``key`` when it is not of that form."""
    parts = _PLUS_MINUS.split(text)
    if len(parts) != 2 or not parts[0].strip() or not parts[1].strip():
        raise InputError(key, text, "a spread is written 'VALUE ± SPREAD' (or +/-), e.g. '1.5 um ± 10 %' or "
                                    "'1.5 um ± 0.2 um'")
    return parts[0].strip(), parts[1].strip()


def _check_no_nested(where: str, value: Any) -> None:
    """Refuse a spread inside a list or a table (a sweep, a study value): spreads go on single values."""
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for k, v in items:
        if isinstance(v, str) and _PLUS_MINUS.search(v):
            raise InputError(f"{where}[{k!r}]" if isinstance(k, str) else f"{where}[{k}]", v,
                             "a spread (±) goes on a single value, not on an item of a list or table")
        if isinstance(v, (list, dict)):
            _check_no_nested(f"{where}[{k!r}]" if isinstance(k, str) else f"{where}[{k}]", v)


def _table_entries(table: Any) -> dict[str, Any]:
    """``[uncertainty]``'s entries by ``"section.key"``: quoted keys as they are, dotted keys (a nested table) joined."""
    if not isinstance(table, dict):
        raise InputError("uncertainty", table, "must be a table of \"section.key\" = { distribution = ..., ... }")
    out: dict[str, Any] = {}
    for name, spec in table.items():
        if isinstance(spec, dict) and "distribution" not in spec and all(isinstance(v, dict) for v in spec.values()):
            out |= {f"{name}.{k}": v for k, v in spec.items()}
        else:
            out[name] = spec
    return out


def _studied(doc: dict[str, Any]) -> str:
    study = doc.get("study")
    vary = study.get("vary") if isinstance(study, dict) else None
    return vary if isinstance(vary, str) else ""


#: The specification, which is compared with the samples and takes no spread of its own.
_SPECIFICATION = "conditions.max_leak_rate"
_NO_SPECIFICATION_SPREAD = ("is the specification the samples are compared with: it takes no spread; give the limit "
                            "itself, e.g. '1e-6 mbar*l/s'")
#: Kinds of key whose value is text as written (a name, a label, a file, a choice): a "±" in it is no spread.
_TEXT_KINDS = frozenset({"text", "choice", "file", "files", "bool"})
#: Lists of text the form shows as lists: a study's labels.
_TEXT_LISTS = frozenset({"study.labels"})


def _is_text(section: str, key: str) -> bool:
    """Whether ``section.key`` holds text, not a quantity ("PDMS 2.3 ± 0.2 MPa batch" is a rubber's name)."""
    kind = FIELD_KINDS.get(f"{section}.{key}")
    return f"{section}.{key}" in _TEXT_LISTS or (kind is not None and kind.kind in _TEXT_KINDS)


def split_spreads(doc: dict[str, Any]) -> Spreads:
    """Take the spreads, ``[uncertainty]`` and ``conditions.max_leak_rate`` out of a parsed case document (in place):
    what is left is the nominal document, which the builders read as a deterministic case."""
    inputs: dict[str, UncertainInput] = {}
    vary = _studied(doc)
    for section, table in doc.items():
        if not isinstance(table, dict):
            continue
        for key, value in table.items():
            if isinstance(value, (list, dict)) and not _is_text(section, key):
                _check_no_nested(f"{section}.{key}", value)
            elif isinstance(value, str) and _PLUS_MINUS.search(value) and not _is_text(section, key):
                name = f"{section}.{key}"
                if name == _SPECIFICATION:
                    raise InputError(name, value, _NO_SPECIFICATION_SPREAD)
                if section in _NO_SPREAD:
                    raise InputError(name, value, f"[{section}] takes no spreads")
                nominal, spread = _plus_minus(name, value)
                inputs[name] = _make(name, nominal, "normal", {"sd": spread}, "±")
                table[key] = nominal
    table = doc.pop("uncertainty", None)
    for name, spec in (_table_entries(table) if table is not None else {}).items():
        where = f"uncertainty.{name}"
        section, _, entry = name.partition(".")
        if name == _SPECIFICATION:
            raise InputError(where, spec, _NO_SPECIFICATION_SPREAD)
        if section not in SECTIONS or section in _NO_SPREAD or entry not in SECTIONS[section]:
            known = [f"{s}.{k}" for s in SECTIONS if s not in _NO_SPREAD for k in sorted(SECTIONS[s])]
            raise InputError(where, spec, "names no case-file key: write \"section.key\", e.g. \"surface.h_rms\""
                                          + did_you_mean(name, known))
        if name in inputs:
            raise InputError(where, spec, f"{name} already has a spread (±) in [{section}]: give one or the other")
        if not isinstance(spec, dict):
            raise InputError(where, spec, "must be a table, e.g. { distribution = \"normal\", sd = \"10 %\" }")
        dist = spec.get("distribution")
        if not isinstance(dist, str) or dist not in DISTRIBUTIONS:
            raise InputError(f"{where}.distribution", dist, f"allowed: {', '.join(DISTRIBUTIONS)}"
                             + (did_you_mean(dist, tuple(DISTRIBUTIONS)) if isinstance(dist, str) else ""))
        allowed = set(DISTRIBUTIONS[dist]) | {"distribution"}
        for k in spec:
            if k not in allowed:
                raise InputError(f"{where}.{k}", spec[k], f"unknown key of a {dist} distribution; allowed: {', '.join(sorted(allowed))}")
        for k in DISTRIBUTIONS[dist]:
            if k not in spec:
                raise InputError(f"{where}.{k}", None, f"is required for a {dist} distribution")
        given = doc[section].get(entry) if isinstance(doc.get(section), dict) else None
        if given is None:
            raise InputError(name, None, f"is required: [uncertainty] gives it a spread; write its value in [{section}]")
        if isinstance(given, (list, dict)):
            raise InputError(name, given, "a spread goes on a single value, not on a list or table")
        inputs[name] = _make(name, given, dist, spec, "[uncertainty]")
    for name in inputs:
        if vary and (name == vary or name.split(".")[0] == vary):
            raise InputError(name, inputs[name].nominal, f"has a spread and is also what [study] varies ({vary}): "
                                                         "give one or the other")
    at_most("uncertainty", list(inputs), MAX_UNCERTAIN_INPUTS, "uncertain inputs")
    conditions = doc.get("conditions")
    limit = conditions.pop("max_leak_rate", None) if isinstance(conditions, dict) else None
    return Spreads(tuple(inputs.values()), limit)
