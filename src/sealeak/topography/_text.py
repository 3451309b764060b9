"""Native reader for plain numeric text: a height matrix, x y h columns, x h columns or one column.

Layouts (detected from the number of columns; comment lines start with ``#``, ``%`` or ``//``;
separators: whitespace, ``,`` or ``;``; numbers have a decimal point):

* 1 column, or a single row: heights of one profile on a uniform grid (needs a pixel size or length);
* 2 columns: ``x h`` of one profile; x may be non-uniform (then interpolated onto a uniform grid);
* 3 columns: ``x y h`` on a complete uniform grid;
* 4 or more columns: a matrix of heights, file row = y, column = x (SurfaceTopography's layout:
  the map is the transpose of the file's table).

Comment lines of the form ``# key: value`` (or ``key = value``) state units and size; the reader
understands ``size`` (``# size: 1 mm, 0.5 mm``; one length for a square map), ``pixel_size``,
``height_unit``, ``lateral_unit`` and ``periodic`` (true/false). ``sealeak surface synthesize``
writes them, and users may add them to their own files instead of passing the options.

A comma is a separator only: in a line whose values are separated by ``;`` or white space, a
number written with a comma (``0,3456;0,8216`` or ``0,3456 0,8216``, and the ambiguous ``1,5 2,3``)
is a decimal comma (or a thousands separator) and the file is refused, naming the line and saying
how to write the number, rather than read with the commas taken as separators.

This module only parses; units are applied by :mod:`._readers`. Every failure is a
:class:`~sealeak.errors.FileFormatError` naming the file and the line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError
from ..io.units import comma_advice, is_number

__all__ = ["RawTable", "parse_text", "looks_binary", "NotPlainText"]


class NotPlainText(FileFormatError):
    """The file has non-numeric lines: maybe an instrument export (tried next with SurfaceTopography)."""

_SPLIT = re.compile(r"[,;\s]+")
_OTHER_SPLIT = re.compile(r"[;\s]+")  # the separators besides ','
_COMMA_NUMBER = re.compile(r"[+-]?[0-9]+(?:,[0-9]+)+(?:[eE][+-]?[0-9]+)?")  # 0,3456 / -1,3e-3 / 1,000
_HEADER = re.compile(r"^(?:#|%|//)\s*(size|pixel[ _]size|height[ _]unit|lateral[ _]unit|periodic)\s*[:=]\s*(.*?)\s*$",
                     re.IGNORECASE)
_COMMENT = ("#", "%", "//")
MAX_TEXT_BYTES = 512 * 2**20


@dataclass(frozen=True)
class RawTable:
    """Parsed content, still in file units."""

    kind: str  # "matrix", "xyz", "xh", "h"
    heights: NDArray[np.float64]  # matrix: [x, y]; xyz: [x, y]; xh/h: 1D
    x: NDArray[np.float64] | None = None  # xh: positions; xyz: unique x
    y: NDArray[np.float64] | None = None  # xyz: unique y
    meta: dict[str, tuple[int, str]] = field(default_factory=dict)  # header key -> (line number, value)


def looks_binary(data: bytes) -> bool:
    """True when the first 4 KiB contain NUL bytes or mostly non-text bytes."""
    head = data[:4096]
    if b"\x00" in head:
        return True
    if not head:
        return False
    text_chars = bytes(range(32, 127)) + b"\n\r\t\f\b\xb5"
    nontext = sum(1 for b in head if b not in text_chars and b < 128)
    return nontext / len(head) > 0.1


def _decode(path: Path, data: bytes) -> str:
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def _table(path: Path, text: str, meta: dict[str, tuple[int, str]] | None = None) -> NDArray[np.float64]:
    rows: list[list[float]] = []
    width = None
    first_line = 0
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith(_COMMENT):
            m = _HEADER.match(stripped) if meta is not None else None
            if m:
                assert meta is not None  # m is only matched when headers are kept
                key = m.group(1).lower().replace(" ", "_")
                if key in meta:
                    raise FileFormatError(path, f"line {lineno}: header {key!r} given twice (first on line "
                                                f"{meta[key][0]})")
                meta[key] = (lineno, m.group(2))
            continue
        tokens = [t for t in _SPLIT.split(stripped) if t]
        if not tokens:
            continue
        _refuse_comma_numbers(path, lineno, stripped)
        try:
            values = [float(t) for t in tokens]
        except ValueError:
            bad = next(t for t in tokens if not is_number(t, float))
            raise NotPlainText(path, f"line {lineno}: {bad[:40]!r} is not a number "
                                        f"(plain text files must hold numbers only; comments start with #)") from None
        if width is None:
            width, first_line = len(values), lineno
        elif len(values) != width:
            raise FileFormatError(path, f"line {lineno} has {len(values)} values but line {first_line} has {width} "
                                        f"(ragged table: truncated or malformed file)")
        rows.append(values)
    if not rows:
        raise FileFormatError(path, "no numeric data (empty or only comments)")
    # infinite heights (or numbers beyond float64) are no-data markers, dealt with when units are applied
    return np.asarray(rows, dtype=float)


def _refuse_comma_numbers(path: Path, lineno: int, line: str) -> None:
    """Refuse a line whose values are separated by ';' or white space but which holds a number with a
    comma between its digits (a decimal comma, or a thousands separator): read with ',' as a separator
    it would give twice the values, silently. A line separated by commas alone (also ``0.1, 0.2``, a comma
    next to a space) is left to the caller."""
    if ";" not in line and (not re.search(r"\s", line) or re.search(r",\s|\s,", line)):
        return
    cells = [c for c in _OTHER_SPLIT.split(line) if c]
    bad = next((c for c in cells if _COMMA_NUMBER.fullmatch(c)), None)
    if bad is not None:
        raise FileFormatError(path, f"line {lineno}: {bad[:40]!r}: {comma_advice(bad)} (the values are separated "
                                    f"by {repr(';') if ';' in line else 'spaces or tabs'}, so a ',' inside a value is a decimal comma)")


def parse_text(path: Path, data: bytes) -> RawTable:
    """Parse plain numeric text into a :class:`RawTable` (no units applied)."""
    if len(data) > MAX_TEXT_BYTES:
        raise FileFormatError(path, f"text file of {len(data) / 2**20:.0f} MiB is larger than the "
                                    f"{MAX_TEXT_BYTES / 2**20:.0f} MiB the text reader accepts; save it as .npy")
    meta: dict[str, tuple[int, str]] = {}
    table = _table(path, _decode(path, data), meta)
    return replace(_layout(path, table), meta=meta)


def _layout(path: Path, table: NDArray[np.float64]) -> RawTable:
    nrows, ncols = table.shape
    if ncols == 1 or nrows == 1:
        h = table.ravel()
        if h.size < 4:
            raise FileFormatError(path, f"only {h.size} height values; a profile needs at least 4")
        return RawTable("h", h)
    if ncols == 2:
        return _xh(path, table)
    if ncols == 3:
        return _xyz(path, table)
    if nrows < 2:
        raise FileFormatError(path, "a height matrix needs at least 2 rows")
    return RawTable("matrix", np.ascontiguousarray(table.T))


def _xh(path: Path, table: NDArray[np.float64]) -> RawTable:
    x, h = table[:, 0], table[:, 1]
    if not np.isfinite(x).all():
        raise FileFormatError(path, f"x column: position on data row {int(np.argmax(~np.isfinite(x))) + 1} is "
                                    f"{x[~np.isfinite(x)][0]} (positions must be finite numbers)")
    order = np.argsort(x, kind="stable")
    x, h = x[order], h[order]
    if (np.diff(x) <= 0).any():
        i = int(np.argmax(np.diff(x) <= 0))
        raise FileFormatError(path, f"x column: position {x[i]:.6g} occurs twice (x h columns need distinct x)")
    if np.isfinite(h).sum() < 4:
        raise FileFormatError(path, "x h columns: fewer than 4 defined heights")
    return RawTable("xh", h, x=x)


def _xyz(path: Path, table: NDArray[np.float64]) -> RawTable:
    if not np.isfinite(table[:, :2]).all():
        raise FileFormatError(path, "x y h columns: some x or y positions are NaN or infinite")
    xs, ix = np.unique(table[:, 0], return_inverse=True)
    ys, iy = np.unique(table[:, 1], return_inverse=True)
    if xs.size < 2 or ys.size < 2:
        raise FileFormatError(path, f"x y h columns span {xs.size} x value(s) and {ys.size} y value(s); "
                                    f"a map needs at least 2 of each")
    if xs.size * ys.size != table.shape[0]:
        raise FileFormatError(path, f"x y h columns: {table.shape[0]} rows do not fill the {xs.size}×{ys.size} grid "
                                    f"of distinct x and y values (incomplete grid or duplicates)")
    heights = np.full((xs.size, ys.size), np.nan)
    if np.unique(ix * ys.size + iy).size != ix.size:
        raise FileFormatError(path, "x y h columns: some (x, y) positions occur twice")
    heights[ix, iy] = table[:, 2]
    for name, v in (("x", xs), ("y", ys)):
        d = np.diff(v)
        if (np.abs(d - d.mean()) > 1e-3 * d.mean()).any():
            raise FileFormatError(path, f"x y h columns: the {name} positions are not uniformly spaced "
                                        f"(spacing {d.min():.6g}..{d.max():.6g}); maps need a uniform grid")
    return RawTable("xyz", heights, x=xs, y=ys)
