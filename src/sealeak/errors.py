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

import reprlib
from typing import Any

__all__ = [
    "SealeakError",
    "InputError",
    "UnitError",
    "FileFormatError",
    "ConvergenceError",
    "SolutionCheckError",
    "ResourceError",
    "show",
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
            super().__init__(f"{name} = {show(value)}: {allowed}")


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


#: How a value appears in a message: the first items and levels only, so that a message is one short line
#: whatever the value's size or nesting (reprlib never recurses deeper than ``maxlevel``).
_REPR = reprlib.Repr()
_REPR.maxlevel = 3
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = 72
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = _REPR.maxfrozenset = _REPR.maxdeque = 8
_SHOW_MAX = 80
#: Text (a path, a quantity) is shown whole up to this many characters, else its start and end.
_TEXT = reprlib.Repr()
_TEXT.maxstring = 120


def _one_line(text: str, limit: int = 120) -> str:
    """``text`` as a message names it: escapes for what does not print (a newline), at most ``limit`` characters."""
    if not text.isprintable():
        text = text.encode("unicode_escape").decode("ascii")
    return text if len(text) <= limit else text[:limit - 3] + "..."


def show(value: Any) -> str:
    """``value`` as a message shows it: text quoted (a long one by its start and end), a float to 6 digits,
    anything else as its ``repr`` of at most 80 characters (long or deep values elided with ``...``)."""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str):
        return _TEXT.repr(value)
    text = _REPR.repr(value)
    return text if len(text) <= _SHOW_MAX else text[:_SHOW_MAX - 3] + "..."
