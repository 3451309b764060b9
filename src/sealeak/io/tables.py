"""Numeric text tables whose header names each column with its unit (an edge module).

Format: optional comment lines starting with '#', then optionally one header row naming the
columns, each with its unit in parentheses or brackets, e.g.::

    # sandpaper spectrum
    q (1/m), C (m^4)
    1.0e3, 2.1e-17
    ...

Columns are separated by commas, semicolons, tabs or spaces (a space-separated header reads
``q (1/m) C (m^4)``: a unit in brackets belongs to the name before it). In a comma, semicolon or
tab separated file an empty cell is a missing value (NaN); the caller decides whether a column may
have any. Without a header the caller's default units apply. Every problem raises
:class:`FileFormatError` naming the file, the line and the problem.

Numbers are ASCII decimals (``2.3``, ``-1e-3``; ``nan``/``inf`` are read, for the caller to judge).
A comma is never part of a number: in a semicolon or tab separated file a cell such as ``2,3``
(a decimal comma) or ``1,000`` (a thousands separator) is refused, naming the file and line and
saying how to write it; so is a space-separated line of numbers with such a number in it (``2,3 1,5``,
``1e3 1,5e-20``), also on the first line of a file without header. In a comma
separated file the commas separate the columns; a row with more cells than the header names, whose
cells are separated by ', ' but which has a ',' between two digits (``20,5, 380``), gets the same hint.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, UnitError
from .files import input_file
from .units import SI_RANGE, comma_advice, is_number, outside_si_range, parse_number, unit_factor

__all__ = ["UnitTable", "read_unit_table", "read_spectrum_table"]

_HEADER_CELL = re.compile(r"^\s*([^\(\)\[\]]*?)\s*(?:[\(\[]\s*(.*?)\s*[\)\]])?\s*$")


@dataclass(frozen=True)
class UnitTable:
    """Columns of a table: ``names`` and ``units`` as written (unit '' if none) and the numbers."""

    path: str
    names: tuple[str, ...]
    units: tuple[str, ...]
    data: NDArray[np.float64]  # (rows, columns)
    has_header: bool
    lines: tuple[int, ...] = ()  # line number in the file of each data row

    def line_of(self, row: int) -> int:
        """Line number in the file of data row ``row`` (0-based)."""
        return self.lines[row] if self.lines else row + 1

    def in_si(self, column: int, factor: float, unit: str) -> NDArray[np.float64]:
        """Column ``column`` times ``factor`` (its unit's SI factor; ``unit`` the SI unit, for the message): each
        value NaN (a missing cell, the caller's to judge), 0 or of a magnitude within
        :data:`~sealeak.io.units.SI_RANGE`, as a case file's; else :class:`FileFormatError` naming the line and the
        cell as written."""
        raw = self.data[:, column]
        with np.errstate(over="ignore"):
            out = raw * factor
        bad = outside_si_range(out) | ((out == 0.0) & (raw != 0.0))  # (1e-320 ml/min underflows to 0 in SI: not a zero)
        if bad.any():
            i = int(np.argmax(bad))
            where = "beyond" if abs(out[i]) > 1.0 else "below"
            end = SI_RANGE[1] if abs(out[i]) > 1.0 else SI_RANGE[0]
            shown = f"{self.names[column]} = {raw[i]:g}" + (f" {self.units[column]}" if self.units[column] else "")
            raise FileFormatError(self.path, f"line {self.line_of(i)}: {shown}: {where} {end:g} {unit} in SI units, far "
                                             f"{where} any seal's")
        return out


_SEPARATOR = re.compile(r"[,;\t]")
_STRONG_SEPARATOR = re.compile(r"[;\t]")
_SPACED_HEADER_CELL = re.compile(r"[^\s(\[]+(?:\s*[\(\[][^\)\]]*[\)\]])?")
_COMMA_NUMBER = re.compile(r"[+-]?[0-9]*[0-9],[0-9][0-9,]*(?:[eE][+-]?[0-9]+)?")
_SPACED_COMMA_NUMBER = re.compile(r"[+-]?[0-9]+(?:,[0-9]+)+(?:[eE][+-]?[0-9]+)?")  # no ',' at the end: '20,5,' is a cell and a separator


class _CommaInNumber(ValueError):
    """A cell that is a number written with a decimal comma or thousands separator."""


def _separator(line: str) -> re.Pattern[str] | None:
    """How a line's cells are separated: ';' or tab (then a ',' is inside a cell), else ',', else white space
    (None). A space-separated line of numbers some of which have a comma ('1,5 2,3', '1e3 1,5e-20') is decimal
    commas (refused by :func:`_number`), not a comma-separated line with a space inside a cell."""
    if _STRONG_SEPARATOR.search(line):
        return _STRONG_SEPARATOR
    if "," in line:
        tokens = line.split()
        if len(tokens) > 1 and any(_SPACED_COMMA_NUMBER.fullmatch(t) for t in tokens) and all(
                _SPACED_COMMA_NUMBER.fullmatch(t) or is_number(t) for t in tokens):
            return None
        return re.compile(",")
    return None


def _split(line: str, width: int | None = None) -> list[str]:
    """Cells of a data line. ``width``: the number of columns so far (header or first row); one
    trailing separator beyond it (as spreadsheet exports write, ``1;2;``) makes no extra column."""
    line = line.strip()
    sep = _separator(line)
    if sep is None:
        return line.split()
    cells = [c.strip() for c in sep.split(line)]
    if cells[-1] == "" and len(cells) > 1 and (width is None or len(cells) == width + 1):
        cells.pop()
    return cells


def _split_header(line: str) -> list[str]:
    """Header cells; with spaces as separators, 'name (unit)' stays one cell."""
    line = line.strip()
    return _split(line) if _SEPARATOR.search(line) else _SPACED_HEADER_CELL.findall(line)


def _number(cell: str, delimited: bool) -> float:
    """A cell's value; an empty cell of a delimited row is a missing value (NaN).

    Numbers are read strictly (:func:`~sealeak.io.units.parse_number`: ASCII decimals, ``nan`` and
    ``inf`` for the caller to judge); a number with a comma raises :class:`_CommaInNumber`.
    """
    if delimited and cell == "":
        return float("nan")
    if _COMMA_NUMBER.fullmatch(cell):
        raise _CommaInNumber(cell)
    return parse_number(cell)


def read_unit_table(path: str | Path, min_columns: int = 2) -> UnitTable:
    """Read a numeric table with an optional unit header (see the module docstring)."""
    p = input_file(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(p, "is not a UTF-8 text table") from None
    except OSError as exc:
        raise FileFormatError(p, f"cannot read it: {exc.strerror or exc}") from None
    names: tuple[str, ...] = ()
    units: tuple[str, ...] = ()
    rows: list[list[float]] = []
    lines: list[int] = []
    header = False
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        cells = _split(line, len(names) if names else (len(rows[0]) if rows else None))
        delimited = _separator(line) is not None
        try:
            values = [_number(c, delimited) for c in cells]
        except _CommaInNumber as exc:
            raise FileFormatError(p, f"line {lineno}: {str(exc)!r}: {comma_advice(str(exc))}") from None
        except ValueError as exc:
            if rows or header:
                raise FileFormatError(p, f"line {lineno}: {exc}") from None
            header = True
            cells = _split_header(line)
            parsed = [_HEADER_CELL.match(c) for c in cells]
            names = tuple((m.group(1) if m else c).strip() for m, c in zip(parsed, cells))
            units = tuple(((m.group(2) or "") if m else "").strip() for m in parsed)
            continue
        if names and len(values) != len(names):
            # commas followed by a space separate the cells; one glued between digits looks like a decimal comma
            decimal_commas = ", " in line and re.search(r"[0-9],[0-9]", line) and len(values) > len(names)
            hint = (" (if a ',' is a decimal comma: use a decimal point, write 1.5, not 1,5; ',' is not allowed in "
                    "numbers)") if decimal_commas else ""
            raise FileFormatError(p, f"line {lineno}: {len(values)} values, but the header names {len(names)} "
                                     f"columns{hint}")
        if rows and len(values) != len(rows[0]):
            raise FileFormatError(p, f"line {lineno}: {len(values)} values, the rows above have {len(rows[0])}")
        rows.append(values)
        lines.append(lineno)
    if not rows:
        raise FileFormatError(p, "no numeric rows (empty file or header only)")
    data = np.asarray(rows, dtype=float)
    if data.shape[1] < min_columns:
        raise FileFormatError(p, f"needs at least {min_columns} columns, found {data.shape[1]}")
    if not names:
        names = tuple(f"column {i + 1}" for i in range(data.shape[1]))
        units = ("",) * data.shape[1]
    return UnitTable(str(p), names, units, data, header, tuple(lines))


def read_spectrum_table(path: str | Path) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Read a two-column power-spectrum table: q (default 1/m) and C (default m⁴).

    Units come from a header row such as ``q (1/um), C (um^4)``. Rows are checked: no NaN or inf,
    q strictly increasing and positive, C positive. Returns (q in 1/m, C in m⁴).
    """
    table = read_unit_table(path)
    if table.data.shape[1] != 2:
        raise FileFormatError(path, f"a spectrum table has two columns (q, C); found {table.data.shape[1]}")
    try:
        fq = unit_factor(f"{path}: column '{table.names[0]}' unit", table.units[0] or "1/m", "wavevector")
        fc = unit_factor(f"{path}: column '{table.names[1]}' unit", table.units[1] or "m^4", "psd")
    except UnitError as exc:
        raise FileFormatError(path, str(exc)) from None
    q = table.in_si(0, fq, "1/m")
    c = table.in_si(1, fc, "m^4")
    for name, col in (("q", q), ("C", c)):
        bad = ~np.isfinite(col)
        if bad.any():
            raise FileFormatError(path, f"line {table.line_of(int(np.argmax(bad)))}: {name} is {col[bad][0]} "
                                        "(missing, NaN or inf: not allowed)")
        bad = col <= 0
        if bad.any():
            raise FileFormatError(path, f"line {table.line_of(int(np.argmax(bad)))}: {name} = {col[bad][0]:.6g} "
                                        "(must be > 0)")
    steps = np.diff(q)
    if (steps <= 0).any():
        i = int(np.argmax(steps <= 0)) + 1
        raise FileFormatError(path, f"line {table.line_of(i)}: q = {q[i]:.6g} 1/m is not above the previous row's "
                                    f"{q[i - 1]:.6g} 1/m (q must be strictly increasing)")
    return q, c
