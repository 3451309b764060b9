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
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError
from ..io.units import comma_advice, is_number
from ._common import MAX_POINTS

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
#: Text is read in pieces of whole lines of at least this many characters (parsed by numpy at once).
_PIECE_CHARS = 2**18
_COMMENT_CHARS = ("#", "%", "//")
_COMMENT_LINE = re.compile(r"^[^\S\n]*(?:#|%|//)[^\n]*", re.MULTILINE)  # a comment line (white space before it)
_ODD_BREAK = re.compile("[\r\v\f\x1c\x1d\x1e\x85\u2028\u2029]")  # what str.splitlines() takes for a line end besides \n
_NON_COMMA_SEPARATORS = (";", " ", "\t", "\x1f")
_SEPARATORS_TO_SPACE = str.maketrans(",;", "  ")
_SPACE = re.compile(r"\s")
#: The ASCII characters str.split() takes for white space, by code.
_ASCII_SPACE = np.zeros(256, dtype=bool)
_ASCII_SPACE[[ord(c) for c in " \t\n\v\f\r\x1c\x1d\x1e\x1f"]] = True


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
    """The numeric table of ``text`` (rows × columns), header lines into ``meta``.

    Read in pieces of whole lines (:data:`_PIECE_CHARS` characters or more): each piece is parsed with numpy
    at once (a few bytes per character of text, 8 per value); a piece numpy cannot take (a bad token, a
    ragged row, a decimal comma, unusual line breaks or characters) is read line by line, which names the
    first bad line. A table of more than :data:`MAX_POINTS` heights is refused as soon as it is reached.
    """
    scan = _Scan(path, {} if meta is None else meta, keep_headers=meta is not None)
    lineno = 0
    for piece in _pieces(text):
        lineno = scan.piece(piece, lineno)
    if not scan.blocks:
        raise FileFormatError(path, "no numeric data (empty or only comments)")
    # infinite heights (or numbers beyond float64) are no-data markers, dealt with when units are applied
    return scan.blocks[0] if len(scan.blocks) == 1 else np.concatenate(scan.blocks)


def _pieces(text: str) -> Iterator[str]:
    """``text`` in pieces of whole lines, each of at least :data:`_PIECE_CHARS` characters (but the last)."""
    start, n = 0, len(text)
    while start < n:
        newline = text.find("\n", start + _PIECE_CHARS - 1)
        end = n if newline < 0 else newline + 1
        yield text[start:end]
        start = end


class _Scan:
    """The state of reading a table piece by piece: the width, the header lines and the rows read so far."""

    def __init__(self, path: Path, meta: dict[str, tuple[int, str]], keep_headers: bool) -> None:
        self.path = path
        self.meta = meta
        self.keep_headers = keep_headers
        self.width: int | None = None
        self.first_line = 0
        self.blocks: list[NDArray[np.float64]] = []
        self.heights = 0

    def piece(self, piece: str, lineno: int) -> int:
        """Read ``piece`` (whole lines; the first is line ``lineno + 1``); the number of the last line read."""
        fast = self._fast(piece, lineno)
        if fast is None:
            return self._lines(piece, lineno)
        rows, last, headers, width, first_line = fast
        self.meta.update(headers)
        if width is not None and self.width is None:
            self.width, self.first_line = width, first_line
        self._add(rows, last)
        return last

    def _add(self, rows: NDArray[np.float64], last: int) -> None:
        if not rows.size:
            return
        self.blocks.append(rows)
        self.heights += rows.shape[0] if rows.shape[1] in (2, 3) else rows.size  # x h and x y h: one height a row
        if self.heights > MAX_POINTS:
            raise FileFormatError(self.path, f"more than {MAX_POINTS:,} heights by line {last}; at most {MAX_POINTS:,} "
                                             f"(8192 × 8192) are read: crop or resample the data, or save them as .npy")

    def _fast(self, piece: str, lineno: int) -> tuple[NDArray[np.float64], int, dict[str, tuple[int, str]], int | None, int] | None:
        """The rows of ``piece`` parsed at once, or None when it needs reading line by line."""
        piece = piece.replace("\r\n", "\n")
        if _ODD_BREAK.search(piece):  # line breaks besides \n: counted line by line
            return None
        nlines = piece.count("\n") + (0 if piece.endswith("\n") else 1)
        headers: dict[str, tuple[int, str]] = {}
        if any(c in piece for c in _COMMENT_CHARS):
            at, number = 0, lineno + 1
            for m in _COMMENT_LINE.finditer(piece):
                number += piece.count("\n", at, m.start())
                at = m.start()
                h = _HEADER.match(m.group().strip()) if self.keep_headers else None
                if h:
                    key = h.group(1).lower().replace(" ", "_")
                    if key in self.meta or key in headers:
                        return None  # refused line by line, in the order of the lines
                    headers[key] = (number, h.group(2))
            piece = _COMMENT_LINE.sub("", piece)
        if not piece.isascii():
            return None
        if "," in piece and any(c in piece for c in _NON_COMMA_SEPARATORS):
            for line in piece.split("\n"):
                if "," in line and _comma_number(line.strip()) is not None:
                    return None
        table = piece.translate(_SEPARATORS_TO_SPACE)
        chars = np.frombuffer(table.encode("ascii"), dtype=np.uint8)
        space = _ASCII_SPACE[chars]
        starts = np.flatnonzero(~space & np.concatenate(([True], space[:-1])))  # where each value begins
        counts = np.bincount(np.searchsorted(np.flatnonzero(chars == 10), starts), minlength=nlines)
        data_lines = np.flatnonzero(counts)
        if not data_lines.size:
            return np.empty((0, 1)), lineno + nlines, headers, None, 0
        width = int(counts[data_lines[0]]) if self.width is None else self.width
        if (counts[data_lines] != width).any():
            return None  # a ragged row: named line by line
        try:
            values = np.concatenate([np.array(part.split(), dtype=float) for part in _parts(table)])
        except ValueError:
            return None  # a value that is not a number: named line by line
        if values.size != starts.size:  # pragma: no cover - the counts and the split agree on ASCII text
            return None
        return values.reshape(-1, width), lineno + nlines, headers, width, lineno + int(data_lines[0]) + 1

    def _lines(self, piece: str, lineno: int) -> int:
        """Read ``piece`` line by line (the first is line ``lineno + 1``); the number of its last line."""
        rows: list[list[float]] = []
        for lineno, line in enumerate(piece.splitlines(), start=lineno + 1):
            stripped = line.strip()
            if not stripped or stripped.startswith(_COMMENT):
                m = _HEADER.match(stripped) if self.keep_headers else None
                if m:
                    key = m.group(1).lower().replace(" ", "_")
                    if key in self.meta:
                        raise FileFormatError(self.path, f"line {lineno}: header {key!r} given twice (first on line "
                                                         f"{self.meta[key][0]})")
                    self.meta[key] = (lineno, m.group(2))
                continue
            tokens = [t for t in _SPLIT.split(stripped) if t]
            if not tokens:
                continue
            _refuse_comma_numbers(self.path, lineno, stripped)
            try:
                values = [float(t) for t in tokens]
            except ValueError:
                bad = next(t for t in tokens if not is_number(t, float))
                raise NotPlainText(self.path, f"line {lineno}: {bad[:40]!r} is not a number (plain text files must "
                                              f"hold numbers only; comments start with #)") from None
            if self.width is None:
                self.width, self.first_line = len(values), lineno
            elif len(values) != self.width:
                raise FileFormatError(self.path, f"line {lineno} has {len(values)} values but line {self.first_line} has "
                                                 f"{self.width} (ragged table: truncated or malformed file)")
            rows.append(values)
            if len(rows) * self.width > _PIECE_CHARS:  # a long stretch of lines: kept as an array
                self._add(np.asarray(rows, dtype=float), lineno)
                rows = []
        if rows:
            self._add(np.asarray(rows, dtype=float), lineno)
        return lineno


def _parts(table: str) -> Iterator[str]:
    """``table`` (values separated by white space) cut at white space into parts of about :data:`_PIECE_CHARS`
    characters, so that a very long line is not split into all its values at once."""
    start, n = 0, len(table)
    while start < n:
        end = start + _PIECE_CHARS
        if end < n:
            m = _SPACE.search(table, end)
            end = n if m is None else m.start()
        yield table[start:end]
        start = end


def _comma_number(line: str) -> str | None:
    """The first value of ``line`` written with a comma between digits, where the line's values are separated by
    ';' or white space (so the comma is a decimal comma or a thousands separator); None if there is none. A line
    separated by commas alone (also ``0.1, 0.2``, a comma next to a space) has none."""
    if ";" not in line and (not re.search(r"\s", line) or re.search(r",\s|\s,", line)):
        return None
    cells = [c for c in _OTHER_SPLIT.split(line) if c]
    return next((c for c in cells if _COMMA_NUMBER.fullmatch(c)), None)


def _refuse_comma_numbers(path: Path, lineno: int, line: str) -> None:
    """Refuse a line whose values are separated by ';' or white space but which holds a number with a
    comma between its digits (a decimal comma, or a thousands separator): read with ',' as a separator
    it would give twice the values, silently. A line separated by commas alone (also ``0.1, 0.2``, a comma
    next to a space) is left to the caller."""
    bad = _comma_number(line)
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
