"""The exceptions sealeak raises.

Every error a user can cause derives from :class:`SealeakError`; the CLI catches that base class,
prints the message and exits non-zero without a traceback. Anything else escaping is a bug.

    SealeakError
    ├── InputError            a value is outside what is allowed (names the field, value, allowed range)
    │   └── UnitError         a quantity has an unknown unit or the wrong dimension
    ├── FileFormatError       a file is missing, empty, truncated or malformed (names the file)
    ├── ConvergenceError      an iterative solver did not reach its tolerance
    ├── SolutionCheckError    a computed solution failed its own consistency check
    └── ResourceError         a job would need more memory (or time) than the machine has
"""

from __future__ import annotations

import datetime
import difflib
import json
import math
import numbers
import re
from collections.abc import Iterable
from typing import Any

__all__ = [
    "did_you_mean",
    "SealeakError",
    "InputError",
    "UnitError",
    "FileFormatError",
    "ConvergenceError",
    "SolutionCheckError",
    "ResourceError",
    "show_value",
    "cut_middle",
    "positive_number",
    "positive_values",
]


class SealeakError(Exception):
    """Base class of every error sealeak raises on purpose."""


class InputError(SealeakError, ValueError):
    """A value outside what is allowed.

    Parameters
    ----------
    field:
        Name of the offending field, as the user wrote it (e.g. ``rubber.youngs_modulus``).
    value:
        The offending value (printed with ``repr``-like formatting).
    allowed:
        Human-readable description of what is allowed.
    """

    def __init__(self, field: str, value: Any, allowed: str) -> None:
        self.field = field
        self.value = value
        self.allowed = allowed
        name = _one_line(field)  # a key is the user's text too: "a\nb" or 100 000 characters stay one short line
        if value is None:  # a missing field: "surface.hurst is required", not "= None"
            super().__init__(f"{name} {allowed}" if allowed.startswith("is ") else f"{name}: {allowed}")
        else:
            super().__init__(f"{name} = {show_value(value)}: {allowed}")


class UnitError(InputError):
    """A quantity with an unknown unit or a unit of the wrong dimension."""


class FileFormatError(SealeakError, ValueError):
    """A file that cannot be read: missing, empty, truncated or malformed."""

    def __init__(self, path: Any, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{_one_line(self.path, 4096)}: {problem}")  # a path whole (its name is at its end)


class ConvergenceError(SealeakError, RuntimeError):
    """An iterative solver stopped at its iteration limit without reaching its tolerance."""


class SolutionCheckError(SealeakError, RuntimeError):
    """A solution failed its own check (conservation, residual); no number is returned."""


class ResourceError(SealeakError, RuntimeError):
    """A job was refused up front because it would need more memory than is available."""


def positive_number(field: str, value: Any, *, allow_zero: bool = False, allowed: str = "",
                    below: tuple[float, str] | None = None) -> float:
    """``value`` as a float, finite and > 0 (>= 0 with ``allow_zero``) and, with ``below`` (a bound and how to name
    it), less than the bound; else an :class:`InputError` naming ``field``: "must be a number", ``allowed`` (by
    default "must be finite and > 0", or ">= 0"), or "must be below <name>"."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, value, "must be a number") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise InputError(field, value, allowed or ("must be finite and >= 0" if allow_zero else "must be finite and > 0"))
    if below is not None and not v < below[0]:
        raise InputError(field, value, f"must be below {below[1]}")
    return v


def positive_values(*checks: tuple[str, Any, str]) -> None:
    """Each ``(field, value, what)`` must be a finite real number > 0 given as a number (not text); else an
    :class:`InputError` naming ``field``: "must be finite, <what>" (the solvers' arguments)."""
    for field, value, what in checks:
        if not (isinstance(value, numbers.Real) and math.isfinite(value) and float(value) > 0):
            raise InputError(field, value, f"must be finite, {what}")


#: The longest value a message shows whole; a longer one keeps its start and its end (:func:`show_value`).
SHOWN_VALUE = 80


def show_value(value: Any) -> str:
    """A value in a message as the user wrote it, in TOML syntax (never a Python repr), at most :data:`SHOWN_VALUE`
    characters: a longer one is cut in the middle, so that a long path still shows its folder's start and its file's
    name (``'/home/ana/projects/seals/2026/lab-cam...ring-nbr70/simulations/grid-2048/store'``)."""
    return cut_middle(_toml(value, 0))


def cut_middle(text: str, width: int = SHOWN_VALUE) -> str:
    """``text`` of more than ``width`` characters cut in its middle to ``width`` ("..." in place of the cut)."""
    if len(text) <= width:
        return text
    head = (width - 3) // 2
    return text[:head] + "..." + text[len(text) - (width - 3 - head):]


def _spelling(text: str) -> str:
    """A name with case, ``-``, ``_`` and white space ignored: "O-ring", "o_ring", " oring " -> "oring"."""
    return re.sub(r"[\s_\-]+", "", text).lower()


def did_you_mean(value: Any, options: Iterable[str]) -> str:
    """" (did you mean 'o-ring'?)" when text ``value`` is a near miss of one of ``options``, else "".

    A near miss is the same name but for case, ``-``, ``_`` and spaces ("O-ring", "o_ring",
    "o-ring "), or a close spelling by :func:`difflib.get_close_matches` (ratio >= 0.75, e.g.
    "helum" for "helium"). The value is never corrected silently: the caller refuses it and shows
    this hint.
    """
    if not isinstance(value, str) or not value.strip():
        return ""
    names = list(options)
    same = [n for n in names if _spelling(n) == _spelling(value)]
    close = same or difflib.get_close_matches(_spelling(value), [_spelling(n) for n in names], n=2, cutoff=0.75)
    if not same:
        by_spelling = {_spelling(n): n for n in names}
        close = [by_spelling[c] for c in close]
    return f" (did you mean {' or '.join(repr(c) for c in close)}?)" if close else ""


def _toml(value: Any, depth: int) -> str:
    """``value`` written as a TOML value: ``'text'``, ``64.0``, ``true``, ``[1, 'a']``, ``{foo = 1}``, ``1979-05-27``.

    Floats keep a decimal point (64.0, not 64: an integer was expected), to six significant digits;
    nesting deeper than a few levels and long containers are shortened (a message is one line)."""
    if isinstance(value, str):
        return f"'{value}'" if "'" not in value and value.isprintable() else _basic(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        text = f"{value:.6g}"
        return text if any(c in text for c in ".eni") else text + ".0"
    if isinstance(value, (datetime.datetime, datetime.date, datetime.time)):
        return value.isoformat()
    if isinstance(value, (list, tuple, dict)) and depth >= 8:
        return "[...]" if not isinstance(value, dict) else "{...}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v, depth + 1) for v in value[:20]) + (", ...]" if len(value) > 20 else "]")
    if isinstance(value, dict):
        items = list(value.items())
        inner = ", ".join(f"{_bare_key(str(k))} = {_toml(v, depth + 1)}" for k, v in items[:20])
        return "{" + inner + (", ...}" if len(items) > 20 else "}")
    if value is None:
        return "nothing"
    text = str(value)
    return text if text.isprintable() else _basic(text)


def _basic(text: str) -> str:
    """A TOML basic string (double quotes, escapes)."""
    return json.dumps(text, ensure_ascii=False)


def _bare_key(key: str) -> str:
    return key if key and all(c.isascii() and (c.isalnum() or c in "_-") for c in key) else _basic(key)


def _one_line(text: str, limit: int = 120) -> str:
    """``text`` as a message names it: escapes for what does not print (a newline), at most ``limit`` characters."""
    if not text.isprintable():
        text = text.encode("unicode_escape").decode("ascii")
    return text if len(text) <= limit else text[:limit - 3] + "..."
