"""Builders of band seals: ``[seal] shape = "o-ring"`` and ``[seal] pressure_profile = "file.csv"``.

An O-ring case gives the cross-section diameter d, the seal line's diameter (``mean_diameter``, or
``inner_diameter`` + d) and ``[conditions] compression`` (ε = δ/d) or ``groove_depth``; the
rubber's Young's modulus (or ``rubber.shore_a``) sets the contact (:mod:`sealeak.physics.oring`).
A profile case gives a file with columns ``x`` and ``pressure`` (with their units), the seal line
``length`` and ``[conditions] profile_scale`` (default 1). docs/case-files.md lists the keys;
docs/theory.md §10 the physics.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, InputError, UnitError
from ..io.tables import UnitTable, read_unit_table
from ..io.units import SI_UNITS, format_quantity, parse_quantity, unit_factor
from ..physics.contact import MIN_SQUEEZE_PRESSURE
from ..physics.oring import MIN_COMPRESSION, ForceTable, compression_from_groove_depth, oring_contact
from ..physics.profile import PressureProfile
from ..physics.seal import Seal
from .limits import MAX_LOADS, at_most, whole_number
from .model import BandSeal
from .schema import Section, case_keys

__all__ = ["SEAL_SHAPES", "is_band_seal", "build_band", "with_loads", "read_pressure_profile", "read_force_table", "BAND_SEAL_KEYS", "BAND_CONDITION_KEYS"]

#: [seal] keys of each band seal, and the [conditions] keys that replace squeeze_pressure.
BAND_SEAL_KEYS = {"o-ring": {"shape", "cross_section_diameter", "inner_diameter", "mean_diameter", "faces",
                             "force_factor", "force_table"},
                  "profile": {"pressure_profile", "length", "faces"}}
BAND_CONDITION_KEYS = {"o-ring": ("compression", "groove_depth"), "profile": ("profile_scale",)}

#: The values of [seal] shape (a seal with a pressure_profile takes none).
SEAL_SHAPES = ("ring", "rectangle", "o-ring")

_X_NAMES = ("x", "position", "distance")
_P_NAMES = ("pressure", "p", "contact_pressure")
_EPS_NAMES = ("compression", "epsilon", "ε", "squeeze")
_F_NAMES = ("line_load", "force_per_length", "force", "load")


def is_band_seal(seal: Section) -> str | None:
    """"o-ring" or "profile" when the [seal] section describes a band seal, else None.

    A ``shape`` that is none of :data:`SEAL_SHAPES` is refused here, naming ``seal.shape`` (with
    "did you mean 'o-ring'?" for "O-ring", "oring", "o_ring"), before any other key of [seal] is read.
    """
    if seal.has("shape") and not seal.has("pressure_profile"):
        seal.choice("shape", SEAL_SHAPES)
    if seal.has("pressure_profile"):
        if seal.has("shape"):
            raise InputError(seal.field("shape"), seal.raw("shape"),
                             "a seal with a pressure_profile takes no shape (its file sets the band): remove shape")
        return "profile"
    return "o-ring" if seal.raw("shape") == "o-ring" else None


def condition_values(cond: Section, key: str, dimension: str) -> tuple[NDArray[np.float64], list[object]]:
    """A list (or one value, or a {start, stop, num} range) of ``key`` in SI."""
    value = cond.raw(key)
    field = cond.field(key)
    if isinstance(value, dict):
        unknown = set(value) - {"start", "stop", "num", "spacing"}
        if unknown:
            k = sorted(unknown)[0]
            raise InputError(f"{field}.{k}", value[k], "unknown key; a range takes start, stop, num, spacing")
        start = parse_quantity(f"{field}.start", value.get("start"), dimension)
        stop = parse_quantity(f"{field}.stop", value.get("stop"), dimension)
        num = whole_number(f"{field}.num", value.get("num", 20), 1, MAX_LOADS)
        spacing = value.get("spacing", "linear")
        if spacing not in ("log", "linear"):
            raise InputError(f"{field}.spacing", spacing, "allowed: 'log', 'linear'")
        if not stop > start:
            raise InputError(f"{field}.stop", value.get("stop"), f"must exceed start ({value.get('start')})")
        if spacing == "log" and not start > 0:
            raise InputError(f"{field}.start", value.get("start"), "must be > 0 for a log range")
        out = np.geomspace(start, stop, num) if spacing == "log" else np.linspace(start, stop, num)
        return out, list(out)
    items = value if isinstance(value, list) else [value]
    if not items:
        raise InputError(field, [], "is empty: give at least one value")
    at_most(field, items, MAX_LOADS, "values (each a contact solution of its own)")
    return np.array([parse_quantity(f"{field}[{i}]" if isinstance(value, list) else field, v, dimension)
                     for i, v in enumerate(items)]), items


def failing_item(cond: Section, key: str, ok: NDArray[np.bool_]) -> tuple[int, str, object]:
    """The item of :func:`condition_values` that failed a check (``ok``: the check per item, not all True) to name in
    the message: (its index, its field, its value as written). From a list its first failing item
    (``conditions.compression[2]``, ``'35 %'``); one value as ``conditions.compression``; from a {start, stop, num}
    range, whose items the user never wrote, the end that fails (its start if both do) as written
    (``conditions.compression.stop``, ``'130 %'``): the checks bound a value from below or above, so an item between
    two ends that pass passes too."""
    value, field = cond.raw(key), cond.field(key)
    if isinstance(value, dict):
        end = "start" if not ok[0] or ok[-1] else "stop"
        return (0 if end == "start" else ok.size - 1), f"{field}.{end}", value.get(end)
    i = int(np.argmin(ok))
    return (i, f"{field}[{i}]", value[i]) if isinstance(value, list) else (i, field, value)


def _faces(seal: Section) -> int:
    faces = seal.raw("faces", 1)
    if isinstance(faces, bool) or faces not in (1, 2):
        raise InputError(seal.field("faces"), faces, "must be 1 (the rough counterface) or 2 (the groove bottom too, "
                                                     "as rough, in parallel)")
    return int(faces)


def _check_keys(seal: Section, cond: Section, kind: str) -> None:
    for key in seal.data:
        if key not in BAND_SEAL_KEYS[kind]:
            what = "an O-ring" if kind == "o-ring" else "a seal with a pressure_profile"
            raise InputError(seal.field(key), seal.raw(key),
                             f"not used by {what}; its keys: {', '.join(sorted(BAND_SEAL_KEYS[kind]))}")
    if cond.has("squeeze_pressure"):
        keys = " or ".join(f"conditions.{k}" for k in BAND_CONDITION_KEYS[kind])
        raise InputError(cond.field("squeeze_pressure"), cond.raw("squeeze_pressure"),
                         f"the contact pressure of {'an O-ring' if kind == 'o-ring' else 'a profile seal'} follows from "
                         f"{keys}: remove squeeze_pressure")
    other = "profile" if kind == "o-ring" else "o-ring"
    for key in BAND_CONDITION_KEYS[other]:
        if cond.has(key):
            raise InputError(cond.field(key), cond.raw(key),
                             f"is for {'an O-ring' if other == 'o-ring' else 'a pressure-profile seal'}; "
                             f"this seal takes {' or '.join(BAND_CONDITION_KEYS[kind])}")


def build_band(kind: str, seal: Section, cond: Section, rubber: Section, youngs_modulus: float, poisson_ratio: float,
               case_dir: Path, q0_fixed: float | None) -> tuple[BandSeal, Seal, NDArray[np.float64]]:
    """The band seal, its widest band as a :class:`Seal`, and each load's mean pressure (Pa).

    ``q0_fixed``: q0 set in the case file (``theory.lowest_wavevector``/``square_side``), else
    None and each load gets q0 = 2π/w (docs/theory.md §10.1).
    """
    _check_keys(seal, cond, kind)
    faces = _faces(seal)
    if kind == "o-ring":
        d = seal.quantity("cross_section_diameter", "length")
        if seal.has("mean_diameter") and seal.has("inner_diameter"):
            raise InputError(seal.field("mean_diameter"), seal.raw("mean_diameter"),
                             "give either mean_diameter or inner_diameter, not both")
        if seal.has("mean_diameter"):
            mean_d = seal.quantity("mean_diameter", "length")
            if not mean_d > d:
                raise InputError(seal.field("mean_diameter"), seal.raw("mean_diameter"),
                                 f"must exceed the cross-section diameter ({d:.6g} m): the ring's line of contact "
                                 "runs around its centre")
        elif seal.has("inner_diameter"):
            mean_d = seal.quantity("inner_diameter", "length") + d
        else:
            raise InputError(seal.field("inner_diameter"), None,
                             "is required for an O-ring (or mean_diameter): the diameter of the seal line")
        has_c, has_g = cond.has("compression"), cond.has("groove_depth")
        if has_c == has_g:
            raise InputError("conditions.compression", cond.raw("compression"),
                             "give either compression (e.g. [\"15 %\", \"25 %\"]) or groove_depth for an O-ring"
                             if not has_c else "give either compression or groove_depth, not both")
        if has_c:
            eps, raw = condition_values(cond, "compression", "dimensionless")
            inside = (MIN_COMPRESSION <= eps) & (eps < 1)
            if not inside.all():
                raise InputError(*failing_item(cond, "compression", inside)[1:],
                                     f"must lie between {100 * MIN_COMPRESSION:g} % (a smaller squeeze is below any roughness) "
                                     "and 100 % (ε = squeeze / cross-section diameter)")
        else:
            depth, raw = condition_values(cond, "groove_depth", "length")
            with case_keys({"groove_depth": "conditions.groove_depth"}):
                eps = compression_from_groove_depth(d, depth)
        factor, table = _force_relation(seal, case_dir)
        with case_keys({"compression": "conditions.compression", "youngs_modulus": rubber.field("youngs_modulus"),
                        "shore_a": rubber.field("shore_a")}):
            contact = oring_contact(d, youngs_modulus, poisson_ratio, eps, force_factor=factor, force_table=table)
        profiles = tuple(contact.profile(i) for i in range(eps.size))
        length = np.pi * mean_d
        notes = (contact.source,) + contact.warnings
        band_args = dict(oring=contact, cross_section_diameter=d, mean_diameter=mean_d)
        loads, load_name = np.asarray(eps, dtype=float), "compression"
    else:
        name = seal.raw("pressure_profile")
        if not isinstance(name, str) or not name:
            raise InputError(seal.field("pressure_profile"), name, "must be the name of a file with columns x and pressure")
        path = Path(name) if Path(name).is_absolute() else case_dir / name
        base = read_pressure_profile(path)
        length = seal.quantity("length", "length")
        if cond.has("profile_scale"):
            loads, _ = condition_values(cond, "profile_scale", "dimensionless")
            positive = np.isfinite(loads) & (loads > 0)
            if not positive.all():
                raise InputError(*failing_item(cond, "profile_scale", positive)[1:],
                                 "must be > 0 (a factor on the file's pressures)")
        else:
            loads = np.ones(1)
        _check_scales(cond, loads, base, (seal.field("pressure_profile"), name))
        profiles = tuple(base.scaled(float(f)) for f in loads)
        notes = (f"pressure profile from {path.name}: {base.x.size} points over w = {base.width * 1e3:.4g} mm, "
                 f"mean {base.mean_pressure / 1e6:.4g} MPa, max {base.max_pressure / 1e6:.4g} MPa (before profile_scale)",
                 *_profile_warnings(seal, path, base, length))
        band_args = dict(profile_source=str(path))
        load_name = "profile_scale"
    widths = np.array([p.width for p in profiles])
    q0 = np.full(widths.size, q0_fixed) if q0_fixed is not None else 2.0 * np.pi / widths
    band = BandSeal(kind=kind, length=length, load_name=load_name, loads=loads, profiles=profiles, q0=q0, faces=faces,
                    notes=notes, q0_fixed=q0_fixed, **band_args)  # type: ignore[arg-type]
    with case_keys():
        rect = Seal(width=float(widths.max()), length=length, shape=kind)
    return band, rect, np.array([p.mean_pressure for p in profiles])


#: A pressure profile wider than this (m) gets a warning: seal contact bands are some µm to a few cm wide.
PROFILE_WIDTH_LIMIT = 0.1

#: The largest peak contact pressure (Pa) profile_scale may give: a thousand GPa, beyond any solid's modulus
#: (the theory's own warning starts at half the rubber's modulus); larger ones overflow the numbers.
MAX_CONTACT_PRESSURE = 1e12


def _check_scales(cond: Section, loads: NDArray[np.float64], base: PressureProfile, file: tuple[str, object]) -> None:
    """Each profile_scale gives a peak pressure that the physics can use (MIN_SQUEEZE_PRESSURE to MAX_CONTACT_PRESSURE);
    without profile_scale the file's own peak, named by ``file`` (its field and value)."""
    with np.errstate(over="ignore"):
        peaks = loads * base.max_pressure
    for ok, bound, why in ((peaks >= MIN_SQUEEZE_PRESSURE, f"at least {MIN_SQUEEZE_PRESSURE:g} Pa",
                            "a seal's contact pressure is some kPa to MPa: give a larger profile_scale"),
                           (np.isfinite(peaks) & (peaks <= MAX_CONTACT_PRESSURE), f"at most {MAX_CONTACT_PRESSURE:.0e} Pa",
                            "far beyond any seal")):
        if ok.all():
            continue
        if not cond.has("profile_scale"):
            raise InputError(*file, f"its peak contact pressure is {peaks[0]:.3g} Pa: {bound}, {why} (are the file's "
                                    "pressures in the unit its header names?)")
        i, field, written = failing_item(cond, "profile_scale", ok)
        raise InputError(field, written, f"gives a peak contact pressure of {peaks[i]:.3g} Pa: {bound} (the file's peak "
                                         f"is {base.max_pressure:.4g} Pa), {why}")


def _profile_warnings(seal: Section, path: Path, base: PressureProfile, length: float) -> tuple[str, ...]:
    """Warnings on a profile seal's size: a band wider than :data:`PROFILE_WIDTH_LIMIT`, a seal line shorter than its band."""
    out = []
    if base.width > PROFILE_WIDTH_LIMIT:
        out.append(f"the pressure profile {path.name} spans x over {format_quantity(base.width, 'length', 4)}: a seal's contact band is µm to a few "
                   f"cm wide (warned above {PROFILE_WIDTH_LIMIT * 100:g} cm); check the unit of its x column")
    if length < base.width:
        out.append(f"{seal.field('length')} = {seal.raw('length')!r} is shorter than the band's width w = "
                   f"{format_quantity(base.width, 'length', 4)}: "
                   "the theory treats the band as a strip much longer than wide (leak channels run across it); check both")
    return tuple(out)


_Column = tuple[tuple[str, ...], str, str]


def two_column_table(path: Path, columns: tuple[_Column, _Column],
                 example: str) -> tuple[UnitTable, list[int], list[NDArray[np.float64]]]:
    """The two-column table at ``path``, the index of each wanted column and its values in SI.

    ``columns``: (accepted names, dimension, example unit) of each; the header names each column
    with its unit (``example``), which only a dimensionless column may omit. Raises :class:`FileFormatError`.
    """
    table = read_unit_table(path)
    if not table.has_header:
        raise FileFormatError(path, f"the first row must name the columns with their units, e.g. '{example}'")
    names = [n.strip().lower().replace(" ", "_") for n in table.names]
    found = [next((i for i, n in enumerate(names) if n in accepted), None) for accepted, _, _ in columns]
    if any(i is None for i in found) or table.data.shape[1] != len(columns):
        wanted = " and ".join(accepted[0] for accepted, _, _ in columns)
        raise FileFormatError(path, f"needs two columns, {wanted}, each with its unit (found: {', '.join(table.names)})")
    out = []
    for i, (_, dim, unit) in zip(found, columns, strict=True):
        assert i is not None
        if not table.units[i] and dim != "dimensionless":
            raise FileFormatError(path, f"column '{table.names[i]}' has no unit: write it in parentheses, e.g. "
                                        f"'{table.names[i]} ({unit})'")
        try:
            factor = unit_factor(f"column '{table.names[i]}' unit", table.units[i], dim)
        except UnitError as exc:
            raise FileFormatError(path, str(exc)) from None
        out.append(table.in_si(i, factor, SI_UNITS[dim]))
    return table, [i for i in found if i is not None], out


def read_pressure_profile(path: Path) -> PressureProfile:
    """A nominal pressure profile from a text table with columns x and pressure, each with its unit.

    Example header: ``x (mm), pressure (MPa)``. x must not decrease (two equal x make a step);
    pressures must be >= 0. Raises :class:`FileFormatError` naming the file and the line.
    """
    table, (ix, ip), (x, p) = two_column_table(path, ((_X_NAMES, "length", "mm"), (_P_NAMES, "pressure", "MPa")),
                                           "x (mm), pressure (MPa)")
    bad = ~(np.isfinite(x) & np.isfinite(p))
    if bad.any():
        raise FileFormatError(path, f"line {table.line_of(int(np.argmax(bad)))}: a value is missing or not finite")
    steps = np.diff(x)
    if (steps < 0).any():
        i = int(np.argmax(steps < 0)) + 1
        raise FileFormatError(path, f"line {table.line_of(i)}: x = {table.data[i, ix]:g} is below the previous row's "
                                    f"{table.data[i - 1, ix]:g} (x must not decrease across the band)")
    if (p < 0).any():
        i = int(np.argmax(p < 0))
        raise FileFormatError(path, f"line {table.line_of(i)}: pressure = {table.data[i, ip]:g} is negative "
                                    "(a contact pressure is >= 0)")
    if not x[-1] > x[0]:
        raise FileFormatError(path, "x spans no width: the band needs at least two different positions")
    if not p.max() > 0:
        raise FileFormatError(path, "every pressure is zero: nothing presses the seal")
    if x.size > 100000:
        raise FileFormatError(path, f"{x.size} rows: at most 100000 points")
    try:
        return PressureProfile.table(x, p)
    except InputError as exc:
        raise FileFormatError(path, str(exc)) from None


#: Rows of a force table at most (a force–compression curve needs some tens).
MAX_FORCE_ROWS = 10000


def read_force_table(path: Path) -> ForceTable:
    """An O-ring's force–compression curve from a text table with columns compression and line load.

    Example header: ``compression (%), line_load (N/mm)`` (compression may be a plain fraction:
    ``compression``). At least two rows; compression >= 0 and line load >= 0, both increasing row
    by row. Raises :class:`FileFormatError` naming the file (and the line).
    """
    table, _, (eps, f) = two_column_table(path, ((_EPS_NAMES, "dimensionless", "%"), (_F_NAMES, "force_per_length", "N/mm")),
                                      "compression (%), line_load (N/mm)")
    bad = ~(np.isfinite(eps) & np.isfinite(f))
    if bad.any():
        raise FileFormatError(path, f"line {table.line_of(int(np.argmax(bad)))}: a value is missing or not finite")
    if eps.size < 2:
        raise FileFormatError(path, "one row: a force curve needs at least two (compression, line load) points")
    if eps.size > MAX_FORCE_ROWS:
        raise FileFormatError(path, f"{eps.size} rows: at most {MAX_FORCE_ROWS}")
    for values, what in ((eps, "compression"), (f, "line load")):
        if (values < 0).any():
            raise FileFormatError(path, f"line {table.line_of(int(np.argmax(values < 0)))}: the {what} is negative (must be >= 0)")
        steps = np.diff(values) <= 0
        if steps.any():
            raise FileFormatError(path, f"line {table.line_of(int(np.argmax(steps)) + 1)}: the {what} does not exceed the previous "
                                        "row's (compression and line load must both increase row by row)")
    return ForceTable(eps, f, name=path.name)


def _force_relation(seal: Section, case_dir: Path) -> tuple[float, ForceTable | None]:
    """``force_factor`` (default 1) and ``force_table`` (or None) of an O-ring's [seal] (docs/case-files.md)."""
    factor, table = 1.0, None
    if seal.has("force_factor"):  # a number, also written as text ("1.2", "120 %", what a spread leaves)
        try:
            factor = seal.number("force_factor", low=1e-3, high=1e3, low_open=False, high_open=False)
        except InputError as exc:
            raise InputError(exc.field, exc.value, "must be a number from 0.001 to 1000 (a factor on the O-ring's force "
                                                   "per length; 1: as published)") from None
    if seal.has("force_table"):
        name = seal.raw("force_table")
        if not isinstance(name, str) or not name:
            raise InputError(seal.field("force_table"), name,
                             "must be the name of a file with columns compression and line_load (force per length)")
        table = read_force_table(Path(name) if Path(name).is_absolute() else case_dir / name)
    return factor, table


def with_loads(case_band: BandSeal, loads: NDArray[np.float64], youngs_modulus: float, poisson_ratio: float,
               q0_fixed: float | None = None) -> BandSeal:
    """The same seal at other loads (compressions or profile scales), e.g. those of measured data.

    ``q0_fixed``: the case's q0 if the case file set one, else None (q0 = 2π/w per load).
    """
    values = np.atleast_1d(np.asarray(loads, dtype=float))
    if case_band.kind == "o-ring":
        assert case_band.cross_section_diameter is not None
        with case_keys({"compression": "compression"}):
            contact = oring_contact(case_band.cross_section_diameter, youngs_modulus, poisson_ratio, values,
                                    force_factor=case_band.oring.force_factor if case_band.oring else 1.0,
                                    force_table=case_band.oring.force_table if case_band.oring else None)
        profiles = tuple(contact.profile(i) for i in range(values.size))
        extra: dict[str, object] = {"oring": contact}
    else:
        bad = ~(np.isfinite(values) & (values > 0))
        if bad.any():
            raise InputError("profile_scale", float(values[bad][0]), "must be > 0 (a factor on the file's pressures)")
        base = case_band.profiles[0].scaled(1.0 / float(case_band.loads[0]))
        profiles = tuple(base.scaled(float(f)) for f in values)
        extra = {}
    widths = np.array([p.width for p in profiles])
    q0 = np.full(widths.size, q0_fixed) if q0_fixed is not None else 2.0 * np.pi / widths
    return replace(case_band, loads=values, profiles=profiles, q0=q0, **extra)  # type: ignore[arg-type]
