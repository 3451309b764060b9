"""Measured data files: leak rates against the load / pressure difference, rig readings (an edge module).

A data file is a numeric table (comma, semicolon, tab or space separated; '#' comments) whose
first row names every column with its unit in parentheses or brackets, e.g.::

    squeeze_pressure (kPa), leak_rate (ml/min), pressure_difference (kPa)
    20, 380, 10
    ...

The load of each row is one of three columns, as the case's seal takes it: ``squeeze_pressure``
(a flat seal pressed uniformly, a pressure), ``compression`` (an O-ring, ε = δ/d: ``compression (%)``,
or a fraction ``compression (1)``) or ``profile_scale`` (a pressure-profile seal, the factor on the
profile file's pressures: ``profile_scale (1)`` or ``profile_scale`` with no unit). Which one the
case needs is checked where the case is known (:func:`sealeak.cases.run_fit`).

Column names (case-insensitive; spaces and hyphens count as underscores; aliases in brackets):
squeeze_pressure [p0, squeezing_pressure, contact_pressure, nominal_pressure],
compression [compression_ratio], profile_scale [scale, load_factor],
leak_rate [q, leakage, leak], pressure_difference [dp, delta_p, Δp, pressure_drop],
time [t], height [h, level, water_height]. Units: any pint knows, written as
:mod:`sealeak.io.units` reads them (``kPa``, ``ml/min``, ``1/um``; no arithmetic), for the leak rate either a
volume flow (``ml/min``, ``l/h``, ``m^3/s``, ...) or a leak-test pV throughput (``mbar*l/s``, ``Pa*m^3/s``, ...).

Leak-test units. A throughput in mbar·l/s or Pa·m³/s is pressure × volume per time: the volume
flow is throughput / p, at the pressure p the volume is measured at. That pressure is stated by the
user (``sealeak fit --at-pressure "1 atm"``); the default is 1 atm = 101325 Pa (ambient). The conversion
is :func:`sealeak.io.leak_units.leak_rate_factor`. E.g.
1 mbar·l/s = 0.1 Pa·m³/s = 0.1/101325 m³/s = 9.869e-7 m³/s at 1 atm.

Gas leak units. Every leak-rate unit of :func:`sealeak.io.leak_units.leak_rate_unit` is read: besides
volume flows and pV throughputs, standard volume flows (``sccm``, ``slm``), molar flows (``mol/s``)
and mass flows (``kg/s``, ``g/a``). :attr:`LeakData.leak_rate_kind` and
:attr:`LeakData.leak_rate_si` keep the leak rates as written (in the kind's SI unit), for a gas case
to convert with its gas (:func:`sealeak.cases.run_fit`, docs/theory.md §11.9); ``leak_rate`` (m³/s)
is NaN for the three gas-only kinds, which a liquid case refuses.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, UnitError
from ..io.files import input_file
from ..io.leak_units import ATMOSPHERE, leak_rate_factor, leak_rate_unit
from ..io.quantities import quantity
from ..io.tables import UnitTable, read_unit_table
from ..io.units import unit_factor
from ..physics.contact import MIN_SQUEEZE_PRESSURE

__all__ = ["LOAD_COLUMNS", "MAX_DATA_BYTES", "MAX_DATA_ROWS", "MAX_READINGS", "LeakData", "read_bounded_table",
           "read_leak_data", "read_readings_table", "read_rig_readings"]

FloatArray = NDArray[np.float64]

#: The columns that give a row's load: a uniform squeeze pressure, an O-ring's compression, a profile's scale factor.
LOAD_COLUMNS = ("squeeze_pressure", "compression", "profile_scale")
#: The most data rows of a file of measured leak rates (fit, --linearity): as many as a case's squeeze pressures.
MAX_DATA_ROWS = 10_000
#: The most readings of a rig's readings file (water column or pressure decay): one every 10 s for more than a day.
MAX_READINGS = 10_000
#: The most bytes of a data or readings file, refused before it is read: 10 000 rows of a few numbers take under 1 MiB.
MAX_DATA_BYTES = 2 * 1024 * 1024
#: A line as str.splitlines (and so :func:`~sealeak.io.tables.read_unit_table`) cuts a text into lines.
_LINE = re.compile(r"[^\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029]+")
_DATA_ROWS_WHY = " (as many as a case's squeeze pressures; each row is a prediction); average repeated measurements first"
_READINGS_WHY = " (one every 10 s for more than a day); thin the readings out"

_ALIASES = {
    "squeeze_pressure": {"squeeze_pressure", "p0", "squeezing_pressure", "contact_pressure", "nominal_pressure"},
    "compression": {"compression", "compression_ratio"},
    "profile_scale": {"profile_scale", "scale", "load_factor"},
    "leak_rate": {"leak_rate", "q", "leakage", "leak"},
    "pressure_difference": {"pressure_difference", "dp", "delta_p", "δp", "pressure_drop"},
    "time": {"time", "t"},
    "height": {"height", "h", "level", "water_height"},
}
_DIMENSION = {"squeeze_pressure": "pressure", "pressure_difference": "pressure", "time": "time", "height": "length"}


@dataclass(frozen=True, kw_only=True)
class LeakData:
    """Measured leak rates in SI: squeeze_pressure, pressure_difference (Pa; NaN where the file has no
    such column or the row's cell is empty: the case's ΔP applies), leak_rate (m³/s); ``columns`` maps
    each found column to its header text.

    ``load_name`` is the column that gives each row's load (one of :data:`LOAD_COLUMNS`, '' if the
    file has none); for ``compression`` (a fraction ε, 1) and ``profile_scale`` (1) the values are in
    ``band_load`` and ``squeeze_pressure`` is NaN. :attr:`load` is that column whichever it is."""

    path: str
    squeeze_pressure: FloatArray
    pressure_difference: FloatArray
    leak_rate: FloatArray
    columns: dict[str, str] = field(default_factory=dict)
    reference_pressure: float = quantity("Pa", "pressure at which the data's pV throughputs were converted to volume flows",
                                         default=ATMOSPHERE)
    throughput: bool = False  # the leak rates were pV throughputs, converted at reference_pressure
    lines: tuple[int, ...] = ()  # line number in the file of each data row
    load_name: str = "squeeze_pressure"
    band_load: FloatArray | None = None
    leak_rate_kind: str = "volume_flow"  # a key of sealeak.io.leak_units.LEAK_RATE_KINDS
    leak_rate_si: FloatArray | None = None  # the leak rates as written, in the SI unit of their kind

    @property
    def load(self) -> FloatArray:
        """Each row's load: P0 (Pa), a compression ε (1) or a profile scale (1), as :attr:`load_name` says."""
        if self.load_name in ("compression", "profile_scale") and self.band_load is not None:
            return self.band_load
        return self.squeeze_pressure

    def line_of(self, row: int) -> int:
        """Line number in the file of data row ``row`` (0-based)."""
        return self.lines[row] if self.lines else row + 1

    def __len__(self) -> int:
        return int(self.leak_rate.size)


def _canonical(name: str) -> str | None:
    key = name.strip().lower().replace(" ", "_").replace("-", "_")
    for canon, names in _ALIASES.items():
        if key in names:
            return canon
    return None


def read_bounded_table(path: str | Path, *, max_rows: int, rows: str = "data rows", why: str = "",
                       min_columns: int = 1) -> UnitTable:
    """:func:`~sealeak.io.tables.read_unit_table` of a file of at most :data:`MAX_DATA_BYTES` bytes and ``max_rows``
    rows, checked before the table is parsed: a larger file is refused on its size before a byte is read, and the
    lines are counted up to the first one past the limit (a header and that row allowed for), so a file far over
    the limit costs no more than one at it. ``rows`` names the rows and ``why`` follows the limit in the message,
    e.g. ``big.csv: has more than 10000 data rows: at most 10000 (...)``."""
    p = input_file(path)
    raw = b""
    try:
        size = p.stat().st_size
        if size <= MAX_DATA_BYTES:
            with p.open("rb") as f:
                raw = f.read(MAX_DATA_BYTES + 1)  # (a file that grew since: read no further than the limit)
            size = max(size, len(raw))
    except OSError as exc:
        raise FileFormatError(p, f"cannot read it: {exc.strerror or exc}") from None
    if size > MAX_DATA_BYTES:
        raise FileFormatError(p, f"is {size} bytes: at most {MAX_DATA_BYTES} bytes ({MAX_DATA_BYTES // 2**20} MiB, "
                                 f"ample for {max_rows} {rows}); average or thin the rows out")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(p, "is not a UTF-8 text table") from None
    count = 0
    for line in _LINE.finditer(text):
        cells = line.group().strip()
        if cells and not cells.startswith("#"):
            count += 1
            if count > max_rows + 2:  # (a header and the first row past the limit are the table's to count exactly)
                raise FileFormatError(p, f"has more than {max_rows} {rows}: at most {max_rows}{why}")
    table = read_unit_table(p, min_columns=min_columns)
    n = table.data.shape[0]
    if n > max_rows:
        raise FileFormatError(p, f"has {n} {rows}: at most {max_rows}{why}")
    return table


def read_readings_table(path: str | Path, min_columns: int = 1) -> UnitTable:
    """A rig's readings as a table: :func:`read_bounded_table` with at most :data:`MAX_READINGS` rows."""
    return read_bounded_table(path, max_rows=MAX_READINGS, rows="readings", why=_READINGS_WHY, min_columns=min_columns)


def _columns(path: Path, wanted: tuple[str, ...], optional: tuple[str, ...], may_be_empty: tuple[str, ...] = (),
             load_column: str | None = None, *, max_rows: int = MAX_DATA_ROWS, rows: str = "data rows",
             why: str = _DATA_ROWS_WHY):
    """The table and {column: index}. ``"load"`` in ``wanted``/``optional`` stands for one of :data:`LOAD_COLUMNS`
    (``load_column``: the one the caller's case takes, named when none is found). At most ``max_rows`` rows
    (:func:`read_bounded_table`)."""
    table = read_bounded_table(path, max_rows=max_rows, rows=rows, why=why, min_columns=1)
    if not table.has_header:
        raise FileFormatError(path, "the first row must name every column with its unit, e.g. "
                                    "'squeeze_pressure (kPa), leak_rate (ml/min)'")
    takes = [c for c in wanted + optional if c != "load"]
    if "load" in wanted + optional:
        takes[0:0] = LOAD_COLUMNS
    found: dict[str, int] = {}
    for i, name in enumerate(table.names):
        canon = _canonical(name)
        if canon is None or canon not in takes:
            raise FileFormatError(path, f"column {i + 1} '{name}' is not one of the columns this file takes: "
                                        f"{', '.join(takes)}")
        if canon in found:
            raise FileFormatError(path, f"column {i + 1} '{name}' repeats column {found[canon] + 1} ({canon})")
        found[canon] = i
    loads = [c for c in LOAD_COLUMNS if c in found]
    if len(loads) > 1:
        raise FileFormatError(path, f"columns {' and '.join(loads)}: give one load column, the one the case's seal takes "
                                    "(squeeze_pressure for a flat seal, compression for an O-ring, profile_scale for a "
                                    "pressure profile)")
    missing = [w for w in wanted if w not in found and not (w == "load" and loads)]
    if missing:
        load_text = (f"{load_column} (the load of the case's seal)" if load_column else
                     "squeeze_pressure (or compression for an O-ring, profile_scale for a pressure profile)")
        names = [load_text if m == "load" else m for m in missing]
        raise FileFormatError(path, f"missing column{'s' if len(missing) > 1 else ''} {', '.join(names)} "
                                    f"(found: {', '.join(table.names)})")
    bad = ~np.isfinite(table.data)
    for canon in may_be_empty:  # missing values allowed here (NaN: the caller supplies a default)
        if canon in found:
            bad[:, found[canon]] = np.isinf(table.data[:, found[canon]])
    if bad.any():
        r, c = np.argwhere(bad)[0]
        what = ("is empty or NaN (not a finite number)" if np.isnan(table.data[r, c])
                else f"{table.data[r, c]} is not a finite number")
        raise FileFormatError(path, f"line {table.line_of(int(r))}, column '{table.names[c]}': {what}")
    return table, found


#: The SI unit of each kind of leak rate (:data:`sealeak.io.leak_units.LEAK_RATE_KINDS`), for a message.
_SI_LEAK_UNITS = {"volume_flow": "m^3/s", "throughput": "Pa*m^3/s", "standard_volume_flow": "m^3/s", "molar_flow": "mol/s",
                  "mass_flow": "kg/s"}


#: A unit to show for a column of each dimension that has none.
_EXAMPLE_UNITS = {"pressure": "kPa", "time": "min", "length": "cm", "dimensionless": "1"}


def _factor(path: Path, table, i: int, dimension: str) -> float:
    unit = table.units[i]
    if not unit:
        raise FileFormatError(path, f"column '{table.names[i]}' has no unit: write it in parentheses, "
                                    f"e.g. '{table.names[i]} ({_EXAMPLE_UNITS.get(dimension, 'kPa')})'")

    try:
        return unit_factor(f"column '{table.names[i]}' unit", unit, dimension)
    except UnitError as exc:
        raise FileFormatError(path, str(exc)) from None


def read_leak_data(path: str | Path, *, reference_pressure: float = ATMOSPHERE,
                   required: tuple[str, ...] = ("load", "leak_rate"), load_column: str | None = None) -> LeakData:
    """Read measured leak rates (see the module docstring). Every problem is a FileFormatError naming the file.

    ``required``: the columns the file must have, ``"load"`` standing for one of :data:`LOAD_COLUMNS`
    (the others of load, leak_rate, pressure_difference are optional). ``load_column``: the load
    column the case takes, named if the file has none (whether the file's one fits the case is
    checked with the case, :func:`sealeak.cases.run_fit`). Leak rates must be >= 0, squeeze
    pressures > 0 (ΔP >= 0), compressions between 0 and 100 %, profile scales > 0.
    """
    p = Path(path)
    optional = tuple(c for c in ("load", "leak_rate", "pressure_difference") if c not in required)
    # an empty ΔP cell means "the case's ΔP", unless ΔP is a required column (the linearity test's x)
    empty_ok = ("pressure_difference",) if "pressure_difference" not in required else ()
    table, found = _columns(p, required, optional, may_be_empty=empty_ok, load_column=load_column)
    n = table.data.shape[0]  # at most MAX_DATA_ROWS (each row a prediction at its load: 10 000 took a minute and a GB)
    out: dict[str, FloatArray] = {}
    for canon in ("squeeze_pressure", "pressure_difference"):
        if canon in found:
            i = found[canon]
            out[canon] = table.in_si(i, _factor(p, table, i, "pressure"), "Pa")
        else:
            out[canon] = np.full(n, np.nan)
    i = found["leak_rate"]
    unit_field = f"column '{table.names[i]}' unit"
    try:
        kind, si_factor = leak_rate_unit(unit_field, table.units[i])
    except UnitError:
        kind, si_factor = "", 1.0
    if kind in ("standard_volume_flow", "molar_flow", "mass_flow"):  # gas units: converted by a gas case
        fq, throughput = float("nan"), False
    else:
        try:
            fq = leak_rate_factor(table.units[i], reference_pressure, unit_field)
        except UnitError as exc:
            raise FileFormatError(p, str(exc)) from None
        throughput = fq != leak_rate_factor(table.units[i], 2.0 * reference_pressure, unit_field)
        kind, si_factor = ("throughput", fq * reference_pressure) if throughput else ("volume_flow", fq)
    q_si = table.in_si(i, si_factor, _SI_LEAK_UNITS.get(kind, "SI"))
    q = table.data[:, i] * fq
    if (q_si < 0).any():
        r = int(np.argmax(q_si < 0))
        raise FileFormatError(p, f"line {table.line_of(r)}: leak rate {table.data[r, i]:g} {table.units[i]} is negative")
    if "squeeze_pressure" in found and (out["squeeze_pressure"] <= 0).any():
        r = int(np.argmax(out["squeeze_pressure"] <= 0))
        raise FileFormatError(p, f"line {table.line_of(r)}: squeeze pressure must be > 0")
    if "squeeze_pressure" in found and (out["squeeze_pressure"] < MIN_SQUEEZE_PRESSURE).any():
        r = int(np.argmax(out["squeeze_pressure"] < MIN_SQUEEZE_PRESSURE))
        raise FileFormatError(p, f"line {table.line_of(r)}: squeeze pressure {table.data[r, found['squeeze_pressure']]:g} "
                                 f"{table.units[found['squeeze_pressure']]}: at least {MIN_SQUEEZE_PRESSURE:g} Pa, a "
                                 "seal's squeeze pressure is some kPa to MPa")
    dp = out["pressure_difference"]
    if "pressure_difference" in found and (dp < 0).any():
        r = int(np.argmax(dp < 0))
        raise FileFormatError(p, f"line {table.line_of(r)}: pressure difference must be >= 0")
    if "pressure_difference" in found and ((dp == 0) & (q_si > 0)).any():
        r = int(np.argmax((dp == 0) & (q_si > 0)))
        raise FileFormatError(p, f"line {table.line_of(r)}: a leak rate of {table.data[r, i]:g} {table.units[i]} at "
                                 "zero pressure difference: no pressure drives a flow (check the row; leave the cell "
                                 "empty to use the case's pressure difference)")
    load_name = next((c for c in LOAD_COLUMNS if c in found), "")
    band_load = _band_load(p, table, load_name, found[load_name]) if load_name in ("compression", "profile_scale") else None
    columns = {c: f"{table.names[j]} ({table.units[j]})" if table.units[j] else table.names[j] for c, j in found.items()}
    return LeakData(path=str(p), squeeze_pressure=out["squeeze_pressure"],
                    pressure_difference=out["pressure_difference"], leak_rate=q, columns=columns,
                    reference_pressure=reference_pressure,
                    throughput=throughput, lines=table.lines, load_name=load_name, band_load=band_load,
                    leak_rate_kind=kind,
                    leak_rate_si=q_si)


def _band_load(path: Path, table, name: str, i: int) -> FloatArray:
    """An O-ring's compression (a fraction, from '%' or '1') or a profile's scale factor (1), checked row by row."""
    header = table.names[i]
    if name == "compression":
        if not table.units[i]:
            raise FileFormatError(path, f"column '{header}' has no unit: write 'compression (%)' for per cent, or "
                                        "'compression (1)' for a fraction (0.2 = 20 %)")
        values = table.data[:, i] * _factor(path, table, i, "dimensionless")
        for r, v in enumerate(values):
            if not 0 < v < 1:
                hint = (f" (as a fraction: for per cent write '{header} (%)')"
                        if v >= 1 and unit_factor("unit", table.units[i], "dimensionless") == 1.0 else "")
                raise FileFormatError(path, f"line {table.line_of(r)}, column '{header}': {table.data[r, i]:g} "
                                            f"{table.units[i]} is not a compression between 0 and 100 %{hint}")
        return values
    values = table.data[:, i] * (_factor(path, table, i, "dimensionless") if table.units[i] else 1.0)
    for r, v in enumerate(values):
        if not v > 0:
            raise FileFormatError(path, f"line {table.line_of(r)}, column '{header}': {table.data[r, i]:g} must be > 0 "
                                        "(a factor on the profile file's pressures)")
    return values


def read_rig_readings(path: str | Path) -> tuple[FloatArray, FloatArray]:
    """Rig readings: columns time and height with units (e.g. 'time (min), height (cm)'); returns (s, m).
    At most :data:`MAX_READINGS` readings in at most :data:`MAX_DATA_BYTES` bytes, checked before the file is parsed."""
    p = Path(path)
    table, found = _columns(p, ("time", "height"), (), max_rows=MAX_READINGS, rows="readings", why=_READINGS_WHY)
    t = table.in_si(found["time"], _factor(p, table, found["time"], "time"), "s")  # (1e-300 min: refused, naming the cell)
    h = table.in_si(found["height"], _factor(p, table, found["height"], "length"), "m")
    return t, h
