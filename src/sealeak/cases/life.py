"""The seal over its life: one case per (time, temperature) of ``[conditions] time`` and ``temperature``.

A case file with any of the keys of :data:`LIFE_KEYS` is expanded, like a ``[study]``, into one case per
temperature and time (labels ``"t = 1 h, T = -20 °C"``), each built from a copy of the document in which
(docs/theory.md §16.7):

* the rubber's modulus is the relaxed one, E(t/a_T(T)) of ``[rubber] relaxation`` (a Prony series, or a master-curve
  file read by :func:`read_master_curve`; eq. 16.8) for an
  O-ring at fixed compression (Lindley's force scales with it, eq. 16.13; the width follows the compression), and the
  creep modulus 1/J(t/a_T(T)) for a seal under a fixed squeeze pressure (a ring, a rectangle or a pressure profile);
* an O-ring's compression is the one at T of its cord and gland expanding from ``assembly_temperature`` (eq. 16.9:
  ``conditions.compression`` becomes 1 − h(T)/d(T), ``conditions.groove_depth`` h0 (1 + α_g ΔT)/(1 + α_r ΔT)), less
  its compression set c(t, T) fitted to ``[rubber] compression_set`` (eqs. 16.10–16.12: ε (1 − c));
* the fluid's properties are taken at T (``fluid.temperature``).

Without ``[rubber] relaxation`` the modulus is the elastic one at every time. Each case carries its :class:`LifePoint`
(time in s, temperature in K) and a warning near or below the glass transition (§16.5).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FileFormatError, InputError
from ..io.leak_units import celsius
from ..io.units import TIME_UNITS, parse_quantity, parse_temperature
from ..physics.viscoelastic import (
    MAX_POINTS,
    MAX_TERMS,
    ArrheniusShift,
    CompressionSet,
    MasterCurve,
    PronySeries,
    WLFShift,
    expansion_coefficient,
    fit_compression_set,
    glass_transition_warnings,
    modulus_at,
    remaining_compression,
    thermal_compression,
    universal_wlf_glass_transition,
)
from .limits import MAX_STUDY_VALUES, at_most
from .model import STANDARD_TEMPERATURE_CASE, Case, LifePoint
from .schema import Section, case_keys
from .seals import condition_values, failing_item, two_column_table

__all__ = ["LIFE_KEYS", "life_cases", "life_label", "life_variant", "time_text", "time_unit", "read_master_curve"]

#: The keys of each section that describe the seal over its life (docs/case-files.md, "The seal over its life").
LIFE_KEYS: dict[str, tuple[str, ...]] = {
    "rubber": ("relaxation", "reference_temperature", "wlf_c1", "wlf_c2", "activation_energy", "glass_transition",
               "thermal_expansion", "compression_set"),
    "seal": ("gland_thermal_expansion",),
    "conditions": ("time", "temperature", "assembly_temperature"),
}

_RELAXATION_KEYS = ("equilibrium_modulus", "moduli", "times")
_MASTER_CURVE = "master_curve"
_SET_KEYS = ("times", "temperatures", "sets")
#: A compression-set fit whose rms residual (a fraction of the squeeze) exceeds this gets a warning.
SET_RESIDUAL_WARNING = 0.03
_TIME_NAMES = ("time", "t", "reduced_time")
_MODULUS_NAMES = ("modulus", "e", "relaxation_modulus")


@dataclass(frozen=True)
class _Life:
    """The life keys of a case, read: the relaxation (or None), its shift law (or None), the glass transition
    (K, or None) and whether it is estimated, the expansion coefficients (1/K), the assembly temperature (K), the
    compression set fitted to the data (or None)."""

    relaxation: PronySeries | MasterCurve | None
    shift: WLFShift | ArrheniusShift | None
    glass_transition: float | None
    estimated: bool
    expansion: tuple[float, float] | None
    assembly_temperature: float
    compression_set: CompressionSet | None = None


def _filling(compression: Any, assembled: Any, temperature: float) -> None:
    """Refuse, naming ``conditions.temperature``, an O-ring's compression ε(T) (1) at ``temperature`` (K) that is
    <= 0: the cord, assembled with the compression ``assembled``, has shrunk more than the gland and no longer fills
    it (eq. 16.9)."""
    eps = np.ravel(np.asarray(compression, dtype=float))
    eps0 = np.ravel(np.broadcast_to(np.asarray(assembled, dtype=float), np.shape(compression)))
    bad = (eps <= 0) & (eps0 > 0)  # an assembly compression of 0 or less is its own key's error
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        raise InputError("conditions.temperature", None, f"the cord no longer fills the gland at "
                         f"{celsius(temperature):.4g} °C (ε(T) = {100 * eps[k]:.3g} %, {100 * eps0[k]:.3g} % at "
                         "assembly): it shrinks more than the gland (rubber.thermal_expansion against "
                         "seal.gland_thermal_expansion); compute warmer temperatures or check the coefficients")


def time_unit(seconds: float) -> tuple[str, float]:
    """(unit, its length in s) to show a time (s) in: the largest of a, d, h, min, s that it reaches (else s)."""
    return next(((u, f) for f, u, _ in TIME_UNITS if seconds >= f), ("s", 1.0))


def time_text(time: float) -> str:
    """``"1 h"``: a time (s) in the largest of a, d, h, min, s in which 4 digits show it exactly (else the largest
    it spans)."""
    spanned = [(u, f) for f, u, _ in TIME_UNITS if time >= f] or [("s", 1.0)]
    exact = [(u, f) for u, f in spanned if math.isclose(float(f"{time / f:.4g}"), time / f, rel_tol=1e-9)]
    unit, factor = (exact or spanned)[0]
    return f"{time / factor:.4g} {unit}"


def life_label(time: float, temperature: float) -> str:
    """``"t = 1 h, T = -20 °C"``: the time (s) as :func:`time_text` writes it, the temperature (K) in °C."""
    return f"t = {time_text(time)}, T = {celsius(temperature):.4g} °C"


def life_variant(case: Case) -> str:
    """The study variant a life case belongs to: its label without its life part (``"h_rms = 2 um"`` of
    ``"h_rms = 2 um; t = 1 h, T = -20 °C"``; ``""`` without a ``[study]``)."""
    if case.life is None:
        return case.label
    where = life_label(case.life.time, case.life.temperature)
    return "" if case.label == where else case.label.removesuffix("; " + where)


def _temperatures(cond: Section, key: str) -> list[float]:
    """``conditions.<key>``: one temperature, a list or a ``{start, stop, num}`` range (linear), in K."""
    value, field = cond.raw(key), cond.field(key)
    if isinstance(value, dict):
        unknown = sorted(set(value) - {"start", "stop", "num"})
        if unknown:
            raise InputError(f"{field}.{unknown[0]}", value[unknown[0]], "unknown key; a range takes start, stop, num")
        start = parse_temperature(f"{field}.start", value.get("start"))
        stop = parse_temperature(f"{field}.stop", value.get("stop"))
        num = value.get("num", 5)
        if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= MAX_STUDY_VALUES:
            raise InputError(f"{field}.num", num, f"must be a whole number from 1 to {MAX_STUDY_VALUES}")
        if not stop > start:
            raise InputError(f"{field}.stop", value.get("stop"), f"must exceed start ({value.get('start')})")
        return [float(t) for t in np.linspace(start, stop, num)]
    items = value if isinstance(value, list) else [value]
    if not items:
        raise InputError(field, [], "is empty: give at least one temperature, e.g. [\"-20 degC\", \"80 degC\"]")
    at_most(field, items, MAX_STUDY_VALUES, "temperatures (one case each)")
    return [parse_temperature(f"{field}[{i}]" if isinstance(value, list) else field, v) for i, v in enumerate(items)]


def _times(cond: Section) -> list[float]:
    """``conditions.time`` in s (>= 0): one value, a list or a range; default 0 s (just after assembly)."""
    if not cond.has("time"):
        return [0.0]
    values, _ = condition_values(cond, "time", "time")
    ok = np.isfinite(values) & (values >= 0)
    if not ok.all():
        raise InputError(*failing_item(cond, "time", ok)[1:], "must be >= 0 s: the time since assembly")
    return [float(t) for t in values]


def read_master_curve(path: Path, field: str) -> MasterCurve:
    """A relaxation master curve from a text table with columns time and modulus, each with its unit.

    Example header: ``time (s), modulus (MPa)``. 2 to :data:`~sealeak.physics.viscoelastic.MAX_POINTS` rows, times
    > 0 increasing, moduli > 0 not increasing. Raises :class:`FileFormatError` naming the file, the line and the value.
    ``field`` names the curve in the errors of :class:`MasterCurve` (``rubber.relaxation.master_curve``).
    """
    table, columns, (t, e) = two_column_table(path, ((_TIME_NAMES, "time", "s"), (_MODULUS_NAMES, "pressure", "MPa")),
                                          "time (s), modulus (MPa)")
    if t.size > MAX_POINTS:
        raise FileFormatError(path, f"{t.size} rows: at most {MAX_POINTS}")
    if t.size < 2:
        raise FileFormatError(path, "one row: a master curve needs at least two (time, modulus) points")

    def cell(i: int, k: int) -> str:  # row i's value of column k as written, with its unit
        return f"{table.names[columns[k]]} = {table.data[i, columns[k]]:.6g} {table.units[columns[k]]}"

    for i in range(t.size):
        line = f"line {table.line_of(i)}"
        for k, v in enumerate((t[i], e[i])):
            if not (math.isfinite(v) and v > 0):
                raise FileFormatError(path, f"{line}: {cell(i, k)}: must be finite and > 0 (the curve is interpolated "
                                            "in log–log)")
        if i and not t[i] > t[i - 1]:
            raise FileFormatError(path, f"{line}: {cell(i, 0)} does not exceed the previous row's (times increase "
                                        "row by row)")
        if i and e[i] > e[i - 1]:
            raise FileFormatError(path, f"{line}: {cell(i, 1)} exceeds the previous row's (a relaxation modulus falls "
                                        "with time)")
    return MasterCurve(tuple(t), tuple(e), field=field)


def _relaxation(rubber: Section, case_dir: Path) -> PronySeries | MasterCurve | None:
    """``rubber.relaxation``: ``{equilibrium_modulus, moduli, times}``, a Prony series (Pa, s), or ``{master_curve =
    "file.csv"}`` (relative to ``case_dir``), or None."""
    if not rubber.has("relaxation"):
        return None
    field, raw = rubber.field("relaxation"), rubber.raw("relaxation")
    for other in ("youngs_modulus", "shore_a"):
        if rubber.has(other):
            raise InputError(rubber.field(other), rubber.raw(other), "give either rubber.relaxation or "
                             f"rubber.{other}, not both: the relaxation sets the modulus")
    if not isinstance(raw, dict):
        raise InputError(field, raw, "must be a table {equilibrium_modulus = \"4 MPa\", moduli = [\"2 MPa\"], "
                                     "times = [\"10 s\"]} or {master_curve = \"file.csv\"}")
    if _MASTER_CURVE in raw:
        extra = sorted(set(raw) - {_MASTER_CURVE})
        if extra:
            raise InputError(f"{field}.{extra[0]}", raw[extra[0]], "give either master_curve (a file) or a Prony "
                                                                   "series (equilibrium_modulus, moduli, times), not both")
        name = raw[_MASTER_CURVE]
        if not isinstance(name, str) or not name or "\x00" in name:
            raise InputError(f"{field}.{_MASTER_CURVE}", name, "must be the name of a file with columns time and modulus")
        return read_master_curve(Path(name) if Path(name).is_absolute() else case_dir / name, f"{field}.{_MASTER_CURVE}")
    unknown = sorted(set(raw) - set(_RELAXATION_KEYS))
    if unknown:
        raise InputError(f"{field}.{unknown[0]}", raw[unknown[0]],
                         f"unknown key; allowed: {', '.join(_RELAXATION_KEYS)}, or {_MASTER_CURVE} alone")

    def terms(key: str, dimension: str) -> tuple[float, ...]:
        items = raw.get(key)
        if not isinstance(items, list) or not items:
            raise InputError(f"{field}.{key}", items, "must be a non-empty list of quantities with their units, "
                                                      "one per term of the series")
        at_most(f"{field}.{key}", items, MAX_TERMS, "terms")
        return tuple(parse_quantity(f"{field}.{key}[{i}]", v, dimension) for i, v in enumerate(items))

    e_inf = parse_quantity(f"{field}.equilibrium_modulus", raw.get("equilibrium_modulus"), "pressure")
    moduli, times = terms("moduli", "pressure"), terms("times", "time")
    if len(moduli) != len(times):
        raise InputError(f"{field}.times", raw["times"], f"must have one relaxation time per modulus ({len(moduli)})")
    return PronySeries(e_inf, moduli, times, field=field)


def _shift(rubber: Section, relaxation: PronySeries | MasterCurve | None) -> WLFShift | ArrheniusShift | None:
    """The shift law of ``rubber.wlf_c1``/``wlf_c2`` (WLF) or ``activation_energy`` (Arrhenius) at
    ``reference_temperature``, or None (the relaxation holds at every temperature)."""
    keys = [k for k in ("reference_temperature", "wlf_c1", "wlf_c2", "activation_energy") if rubber.has(k)]
    if not keys:
        return None
    if relaxation is None:
        raise InputError(rubber.field(keys[0]), rubber.raw(keys[0]), "shifts rubber.relaxation in time with temperature: "
                                                                     "give the relaxation too")
    wlf = rubber.has("wlf_c1") or rubber.has("wlf_c2")
    if wlf and rubber.has("activation_energy"):
        raise InputError(rubber.field("activation_energy"), rubber.raw("activation_energy"),
                         "give either wlf_c1 and wlf_c2 (WLF) or activation_energy (Arrhenius), not both")
    if not rubber.has("reference_temperature"):
        raise InputError(rubber.field("reference_temperature"), None, "is required with a shift law: the temperature "
                                                                      "at which rubber.relaxation was measured")
    tref = parse_temperature(rubber.field("reference_temperature"), rubber.raw("reference_temperature"))
    if wlf:
        return WLFShift(tref, rubber.number("wlf_c1", low=0.0), rubber.number("wlf_c2", low=0.0))
    if not rubber.has("activation_energy"):
        raise InputError(rubber.field("reference_temperature"), rubber.raw("reference_temperature"),
                         "needs a shift law: wlf_c1 and wlf_c2 (WLF), or activation_energy (Arrhenius)")
    return ArrheniusShift(tref, rubber.quantity("activation_energy", "molar_energy"))


def _compression_set(rubber: Section, seal: Section) -> CompressionSet | None:
    """``rubber.compression_set = {times, temperatures, sets}`` (measured points) fitted by eqs. 16.10–16.11, or None."""
    if not rubber.has("compression_set"):
        return None
    field, raw = rubber.field("compression_set"), rubber.raw("compression_set")
    if seal.raw("shape") != "o-ring":
        raise InputError(field, raw, "is for an O-ring (seal.shape = \"o-ring\"), whose compression the set reduces; a "
                                     "seal under a squeeze pressure keeps its pressure")
    if not isinstance(raw, dict):
        raise InputError(field, raw, "must be a table of measured points {times = [\"1000 h\", ...], temperatures = "
                                     "[\"70 degC\", ...], sets = [\"15 %\", ...]}")
    unknown = sorted(set(raw) - set(_SET_KEYS))
    if unknown:
        raise InputError(f"{field}.{unknown[0]}", raw[unknown[0]], f"unknown key; allowed: {', '.join(_SET_KEYS)}")

    def points(key: str, parse: Callable[[str, Any], float]) -> list[float]:
        items = raw.get(key)
        if not isinstance(items, list) or not items:
            raise InputError(f"{field}.{key}", items, "must be a non-empty list, one value per measured point")
        at_most(f"{field}.{key}", items, MAX_POINTS, "points")
        return [parse(f"{field}.{key}[{i}]", v) for i, v in enumerate(items)]

    times = points("times", lambda f, v: parse_quantity(f, v, "time"))
    temperatures = points("temperatures", parse_temperature)
    sets = points("sets", lambda f, v: parse_quantity(f, v, "dimensionless"))
    return fit_compression_set(times, temperatures, sets, reference_temperature=STANDARD_TEMPERATURE_CASE, field=field)


def _fit_warnings(life: _Life) -> tuple[str, ...]:
    """A warning where the compression-set fit misses its points by more than :data:`SET_RESIDUAL_WARNING` (rms)."""
    fit = life.compression_set
    if fit is None or not fit.rms_residual > SET_RESIDUAL_WARNING:
        return ()
    return (f"rubber.compression_set: the fit of eq. 16.10 misses the measured sets by {100 * fit.rms_residual:.2g} % "
            "(rms): the data do not follow one stretched exponential with an Arrhenius time scale; check them",)


def _expansion(section: Section, key: str) -> float:
    """A linear thermal expansion coefficient (1/K) of ``section.key``, checked; an error shows it as written."""
    alpha = section.quantity(key, "thermal_expansion", positive=False)
    try:
        return expansion_coefficient(section.field(key), alpha)
    except InputError as exc:
        raise InputError(exc.field, section.raw(key), exc.allowed) from None


def _read(doc: dict[str, Any], case_dir: Path) -> _Life:
    """The life keys of ``doc`` (its sections as written; files relative to ``case_dir``), checked."""
    def section(name: str) -> Section:
        table = doc.get(name)
        return Section(name, table if isinstance(table, dict) else {})

    rubber, seal, cond, fluid = section("rubber"), section("seal"), section("conditions"), section("fluid")
    relaxation = _relaxation(rubber, case_dir)
    shift = _shift(rubber, relaxation)
    estimated = False
    if rubber.has("glass_transition"):
        tg: float | None = parse_temperature(rubber.field("glass_transition"), rubber.raw("glass_transition"))
    elif isinstance(shift, WLFShift):
        tg, estimated = universal_wlf_glass_transition(shift), True
    else:
        tg = None
    given = [(s, k) for s, k in ((rubber, "thermal_expansion"), (seal, "gland_thermal_expansion")) if s.has(k)]
    expansion = None
    if given:
        if seal.raw("shape") != "o-ring":
            raise InputError(given[0][0].field(given[0][1]), given[0][0].raw(given[0][1]),
                             "is for an O-ring (seal.shape = \"o-ring\"), whose compression changes with temperature; "
                             "a seal under a squeeze pressure keeps its pressure")
        if len(given) == 1:
            other = "seal.gland_thermal_expansion" if given[0][1] == "thermal_expansion" else "rubber.thermal_expansion"
            raise InputError(other, None, f"is required with {given[0][0].field(given[0][1])}: the cord and the gland "
                                          "each expand with their own coefficient (1/K)")
        # material constants: checked once here, not in every case of a time and temperature
        expansion = (_expansion(rubber, "thermal_expansion"), _expansion(seal, "gland_thermal_expansion"))
    if cond.has("assembly_temperature") and expansion is None:
        raise InputError(cond.field("assembly_temperature"), cond.raw("assembly_temperature"),
                         "is for the thermal contraction of an O-ring: give rubber.thermal_expansion and "
                         "seal.gland_thermal_expansion too")
    if cond.has("temperature") and fluid.has("temperature"):
        raise InputError(fluid.field("temperature"), fluid.raw("temperature"), "give either fluid.temperature or "
                         "conditions.temperature, not both: the fluid is taken at each conditions.temperature")
    assembly = (parse_temperature(cond.field("assembly_temperature"), cond.raw("assembly_temperature"))
                if cond.has("assembly_temperature") else STANDARD_TEMPERATURE_CASE)
    return _Life(relaxation, shift, tg, estimated, expansion, assembly, _compression_set(rubber, seal))


#: Physics parameter names of the thermal contraction → the case-file keys.
_THERMAL_KEYS = {"compression": "conditions.compression", "temperature": "conditions.temperature",
                 "assembly_temperature": "conditions.assembly_temperature", "rubber_expansion": "rubber.thermal_expansion",
                 "gland_expansion": "seal.gland_thermal_expansion"}


def _variant(base: dict[str, Any], life: _Life, time: float, temperature: float, swept: bool) -> dict[str, Any]:
    """A copy of ``base`` (life keys removed) at ``time`` (s) and ``temperature`` (K): its modulus, compression and
    (``swept``: ``conditions.temperature`` given) fluid temperature set."""
    variant = copy.deepcopy(base)
    if life.relaxation is not None:
        with case_keys({"temperature": "conditions.temperature"}):
            if variant.get("seal", {}).get("shape") == "o-ring":  # fixed compression: the force relaxes (eq. 16.13)
                modulus = float(modulus_at(life.relaxation, time, temperature, life.shift))
            else:  # fixed squeeze pressure: the contact creeps with 1/J (§16.7)
                shift = 1.0 if life.shift is None else float(life.shift.shift(temperature))
                modulus = float(1.0 / life.relaxation.creep_compliance(time / shift))
        variant["rubber"]["youngs_modulus"] = f"{modulus!r} Pa"
    if life.expansion is not None or life.compression_set is not None:
        cond = Section("conditions", variant["conditions"])
        thermal = (temperature, life.assembly_temperature, *(life.expansion or (0.0, 0.0)))
        kept = 1.0 - (0.0 if life.compression_set is None else float(life.compression_set(time, temperature)))
        with case_keys(_THERMAL_KEYS):
            if cond.has("compression"):  # eq. 16.9: 1 − h(T)/d(T); eq. 16.12: less the set, ε (1 − c)
                eps, _ = condition_values(cond, "compression", "dimensionless")
                if life.expansion is not None:
                    eps, assembled = thermal_compression(eps, *thermal), eps
                    _filling(eps, assembled, temperature)
                variant["conditions"]["compression"] = [float(e) for e in remaining_compression(eps, 1.0 - kept)]
            if cond.has("groove_depth"):  # h(T)/d(T) = h0 (1 + α_g ΔT)/(1 + α_r ΔT) over d0; the set: d − (d − h)(1 − c)
                depth, _ = condition_values(cond, "groove_depth", "length")
                ratio = 1.0 - float(thermal_compression(0.0, *thermal)) if life.expansion is not None else 1.0
                d = Section("seal", variant["seal"]).quantity("cross_section_diameter", "length") \
                    if kept != 1.0 or ratio != 1.0 else 0.0
                if ratio != 1.0:
                    _filling([1.0 - float(h) * ratio / d for h in depth], [1.0 - float(h) / d for h in depth], temperature)
                variant["conditions"]["groove_depth"] = [f"{d - (d - float(h) * ratio) * kept!r} m" for h in depth]
    if swept and isinstance(variant.get("fluid"), dict):
        variant["fluid"]["temperature"] = f"{temperature!r} K"
    return variant


def life_cases(doc: dict[str, Any], build: Callable[[dict[str, Any], str], Case], label: str = "",
               case_dir: Path = Path(".")) -> list[Case] | None:
    """The cases of ``doc`` (a case document without its ``[study]``), one per temperature and time of
    ``[conditions]``; None when ``doc`` has no key of :data:`LIFE_KEYS` (the case is then built as it is).

    ``build(document, label)`` builds one case (:func:`~sealeak.cases.builders.build_case`); ``label`` (a study
    variant's) leads each case's label; a master-curve file is read relative to ``case_dir``. An error in one case
    names its time and temperature.
    """
    if not any(isinstance(doc.get(s), dict) and any(k in doc[s] for k in keys) for s, keys in LIFE_KEYS.items()):
        return None
    life = _read(doc, case_dir)
    cond = Section("conditions", doc["conditions"] if isinstance(doc.get("conditions"), dict) else {})
    fluid = doc.get("fluid")
    default_t = (parse_temperature("fluid.temperature", fluid["temperature"])
                 if isinstance(fluid, dict) and "temperature" in fluid else STANDARD_TEMPERATURE_CASE)
    temperatures = _temperatures(cond, "temperature") if cond.has("temperature") else [default_t]
    times = _times(cond)
    at_most("conditions.time", [(t, T) for T in temperatures for t in times], MAX_STUDY_VALUES,
            "times × temperatures (one case each)", shown=cond.raw("time"))
    base = copy.deepcopy(doc)
    for section, keys in LIFE_KEYS.items():
        for key in keys:
            if isinstance(base.get(section), dict):
                base[section].pop(key, None)
    shown = cond.has("time") or cond.has("temperature")
    cases = []
    for temperature in temperatures:
        for time in times:
            where = life_label(time, temperature)
            try:
                variant = _variant(base, life, time, temperature, cond.has("temperature"))
                case = build(variant, "; ".join(x for x in (label, where if shown else "") if x))
            except InputError as exc:
                raise InputError(f"{exc.field} (at {where})", exc.value, exc.allowed) from None
            warnings = () if life.glass_transition is None else glass_transition_warnings(
                temperature, life.glass_transition, estimated=life.estimated)
            c = None if life.compression_set is None else float(life.compression_set(time, temperature))
            cases.append(replace(case, life=LifePoint(time, temperature, case.youngs_modulus, c),
                                 input_warnings=case.input_warnings + warnings + _fit_warnings(life)))
    return cases
