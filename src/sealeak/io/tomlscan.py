"""TOML read with bounded cost: a linear pre-scan of the text, then :mod:`tomllib`.

tomllib's cost grows with the square of a dotted key's parts (``x.x.x…x = 1``: 20 000 parts took
3.5 GB), it recurses once per level of nested inline tables and arrays (a few thousand levels end
in ``RecursionError``), and Python refuses to convert integers of more than 4300 digits with a
``ValueError`` that is not a TOML error. :func:`scan_toml` reads the text once, in time and memory
linear in its length, and refuses before tomllib runs:

* a dotted key (``a.b.c = …`` or a table header ``[a.b.c]``) of more than :data:`MAX_KEY_PARTS` parts;
* tables and arrays nested more than :data:`MAX_DEPTH` deep, counting every level of the document:
  each part of a table header or dotted key, each inline table and each array;
* a bare word (a bare key, a number, a date, ``true``) of more than :data:`MAX_BARE` characters.

The scanner knows TOML's four kinds of string and its comments, so brackets, dots and ``#`` inside
them count for nothing. Where the text stops being TOML the scan stops too: tomllib reports that
place as malformed before it reads on. :func:`parse_toml` is the pre-scan and tomllib together;
every error is a :class:`~sealeak.errors.FileFormatError` of one line that names the source.
"""

from __future__ import annotations

import re
import tomllib
from typing import Any

from ..errors import FileFormatError

__all__ = ["MAX_KEY_PARTS", "MAX_DEPTH", "MAX_BARE", "scan_toml", "parse_toml"]

#: Most parts of one dotted key or table header (``a.b.c`` has 3).
MAX_KEY_PARTS = 32
#: Deepest nesting of tables and arrays: the keys and indices on the path from the document to a value.
MAX_DEPTH = 32
#: Longest bare word (bare key, number, date, boolean) in characters: below the 4300 digits Python converts to an int.
MAX_BARE = 1000

_TOKEN = re.compile(r"""
      (?P<space>[ \t\r]+)
    | (?P<newline>\n)
    | (?P<comment>\#[^\n]*)
    | (?P<mlbasic>"{3}[^"\\]*(?:(?:\\[\s\S]|"(?!""))[^"\\]*)*"{3,5})
    | (?P<mlliteral>'{3}[\s\S]*?'{3,5})
    | (?P<basic>"(?!"")[^"\\\n]*(?:\\.[^"\\\n]*)*")
    | (?P<literal>'(?!'')[^'\n]*')
    | (?P<unterminated>["'])
    | (?P<punct>[\[\]{}=,.])
    | (?P<bare>[^\s\[\]{}=,.\#"']+)
    | (?P<other>[\s\S])
""", re.VERBOSE)

_STRINGS = ("basic", "literal", "mlbasic", "mlliteral")
_KEY, _VALUE, _AFTER = "key", "value", "after"


class _Scan:
    """The scanner's state: where a key or a value belongs, the open arrays and inline tables."""

    def __init__(self, text: str, source: str) -> None:
        self.text = text
        self.source = source
        self.stack: list[tuple[str, int]] = []  # open "[" and "{" with the depth of the value they are
        self.base = 0  # depth of the current [table] or [[array]] entry
        self.state = _KEY
        self.dots = 0  # dots of the key read so far
        self.key_at = -1  # where the key began (-1: no key yet)
        self.header = 0  # 0: no table header open; 1: [table]; 2: [[array of tables]]
        self.pending = 0  # depth of the value that comes next (state _VALUE)
        self.line = 1

    def fail(self, what: str) -> FileFormatError:
        return FileFormatError(self.source, f"line {self.line}: {what}")

    def depth(self, depth: int) -> int:
        if depth > MAX_DEPTH:
            raise self.fail(f"tables and arrays nested more than {MAX_DEPTH} deep (each part of a dotted key and "
                            f"each inline table or array is a level): at most {MAX_DEPTH}")
        return depth

    def key_dot(self) -> None:
        self.dots += 1
        if self.dots >= MAX_KEY_PARTS:
            start = self.text[self.key_at:self.key_at + 40].splitlines()[0] if self.key_at >= 0 else ""
            raise self.fail(f"the dotted key {start}… has more than {MAX_KEY_PARTS} parts: at most {MAX_KEY_PARTS}")

    def key_done(self) -> int:
        """The parts of the key just read; ready for the next key."""
        parts = self.dots + 1
        self.dots, self.key_at = 0, -1
        return parts

    def run(self) -> None:  # noqa: C901 - one state machine, read in one place
        text = self.text
        skip = ""  # the second bracket of "[[" or "]]" of an array-of-tables header
        for m in _TOKEN.finditer(text):
            kind, tok = m.lastgroup, m[0]
            if skip:
                if tok != skip:
                    return  # "[ [a]]": tomllib stops here
                skip = ""
                continue
            if kind in ("space", "comment"):
                continue
            if kind == "unterminated":
                return  # a string that never ends: tomllib stops here
            if kind == "newline":
                self.line += 1
                if self.header:
                    return  # a table header across lines: tomllib stops here
                if not self.stack:
                    self.state = _KEY
                    self.dots, self.key_at = 0, -1
                continue
            if kind in ("mlbasic", "mlliteral"):
                self.line += tok.count("\n")
            if kind == "bare" and len(tok) > MAX_BARE:
                raise self.fail(f"a bare key or value of {len(tok)} characters ({tok[:20]}…): at most {MAX_BARE} "
                                "(text belongs in quotes)")
            if self.state == _KEY or self.header:
                if kind == "bare" or kind in _STRINGS:
                    if self.key_at < 0:
                        self.key_at = m.start()
                elif tok == ".":
                    self.key_dot()
                elif tok == "=" and not self.header and self.key_at >= 0:
                    parts = self.key_done()
                    self.pending = self.depth((self.stack[-1][1] if self.stack else self.base) + parts)
                    self.state = _VALUE
                elif tok == "]" and self.header and self.key_at >= 0:
                    self.base = self.depth(self.key_done() + self.header - 1)
                    if self.header == 2:
                        if not text.startswith("]", m.end()):
                            return
                        skip = "]"
                    self.header, self.state = 0, _AFTER
                elif tok == "[" and not self.stack and not self.header and self.key_at < 0 and not self.dots:
                    self.header = 2 if text.startswith("[", m.end()) else 1
                    skip = "[" if self.header == 2 else ""
                elif tok == "}" and self.stack and self.stack[-1][0] == "{" and self.key_at < 0 and not self.dots:
                    self.stack.pop()  # {}
                    self.state = _AFTER
                else:
                    return  # not TOML where a key belongs: tomllib stops here
            elif self.state == _VALUE:
                if tok in ("[", "{"):
                    self.stack.append((tok, self.depth(self.pending)))
                    if tok == "[":
                        self.pending += 1
                    else:
                        self.state = _KEY
                elif tok == "]" and self.stack and self.stack[-1][0] == "[":
                    self.stack.pop()  # [] or a trailing comma
                    self.state = _AFTER
                elif kind == "bare" or kind in _STRINGS or tok == ".":
                    self.state = _AFTER
                else:
                    return
            else:  # _AFTER: the rest of a value (a float's fraction, a date's time), then "," or a bracket
                if tok == "," and self.stack:
                    if self.stack[-1][0] == "[":
                        self.state, self.pending = _VALUE, self.stack[-1][1] + 1
                    else:
                        self.state = _KEY
                elif tok in ("]", "}") and self.stack and self.stack[-1][0] == ("[" if tok == "]" else "{"):
                    self.stack.pop()
                elif not (kind == "bare" or kind in _STRINGS or tok == "."):
                    return


def scan_toml(text: str, source: str = "<text>") -> None:
    """Refuse TOML text whose keys, nesting or bare words exceed the limits (one pass, linear time and memory).

    Raises :class:`~sealeak.errors.FileFormatError` naming ``source``, the line and the limit. Text that
    is not TOML passes where tomllib itself reports it.
    """
    _Scan(text, source).run()


def parse_toml(text: str, source: str = "<text>") -> dict[str, Any]:
    """TOML text into a dict, after :func:`scan_toml`; malformed text is a one-line
    :class:`~sealeak.errors.FileFormatError` naming ``source`` (never a traceback)."""
    scan_toml(text, source)
    try:
        return tomllib.loads(text)
    except (ValueError, RecursionError) as exc:  # TOMLDecodeError is a ValueError; so are over-long integers
        raise FileFormatError(source, f"malformed TOML: {exc}") from None
