"""Length-unit parsing for the topography layer (pint, at the edge only).

Inside sealeak every length is a float in metres; this module turns user or file text such as
``"um"``, ``"µm"``, ``"nm"``, ``"0.5 um"`` into metres and nothing else.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

import numpy as np

from ..errors import UnitError
from ..io.units import SI_RANGE, parse_quantity, unit_factor

__all__ = ["length_unit_factor", "parse_length", "cli_option_names", "option_name", "option_example",
           "MissingUnitsError"]


def length_unit_factor(unit: str, field: str = "unit") -> float:
    """Metres per ``unit`` (e.g. ``"um"``, ``"µm"``, ``"μm"``, ``"nm"``, ``"mm"``, ``"m"``, ``"Å"``, or a scaled unit ``"0.5 um"``).

    Parsed by the project's one quantity parser (:func:`sealeak.io.units.unit_factor`: nothing is
    evaluated, no decimal commas). Raises :class:`~sealeak.errors.UnitError` (naming ``field``) for
    unknown units, units that are not lengths and factors that are not > 0.
    """
    if not isinstance(unit, str) or not unit.strip():
        raise UnitError(field, unit, "a length unit such as 'm', 'mm', 'um', 'nm'")
    value = unit_factor(field, unit.strip(), "length")
    if not value > 0:
        raise UnitError(field, unit, "must be a positive length unit, such as 'm', 'mm', 'um', 'nm'")
    return value


def parse_length(value: Any, field: str) -> float:
    """A length in metres from a number (already in m) or a string with unit (``"0.5 um"``), within
    :data:`~sealeak.io.units.SI_RANGE` (1e-100 m to 1e100 m)."""
    if isinstance(value, str):
        v = parse_quantity(field, value, "length")
    elif isinstance(value, bool) or not isinstance(value, (int, float)):
        raise UnitError(field, value, "a positive length like '0.5 um' or a number in m")
    else:
        v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise UnitError(field, value, "a positive length like '0.5 um' or a number in m")
    if not SI_RANGE[0] <= v <= SI_RANGE[1]:  # as a length with a unit (parse_quantity): near the ends of the doubles
        raise UnitError(field, value, f"a length between {SI_RANGE[0]:g} m and {SI_RANGE[1]:g} m, far "
                                      f"{'beyond' if v > 1.0 else 'below'} any seal's")
    return v


# ---------------------------------------------------------------------------- option names in messages
# Messages name the option the user can act on: the keyword argument of the Python API by default,
# the command-line flag inside ``with cli_option_names():`` (set by sealeak's CLI around its calls).
_CLI_FLAGS = {
    "size": "--size",
    "pixel_size": "--pixel-size",
    "height_unit": "--height-unit",
    "lateral_unit": "--lateral-unit",
    "periodic": "--periodic",
    "channel": "--channel",
    "bins_per_decade": "--bins-per-decade",
    "low_cut": "--low-cut",
    "resolution": "--resolution",
    "resolution_pixels": "--resolution-pixels",
}
_STYLE: ContextVar[str] = ContextVar("sealeak_topography_option_style", default="api")


@contextmanager
def cli_option_names() -> Iterator[None]:
    """Within this block, messages name command-line flags (``--height-unit um``) instead of keyword
    arguments (``height_unit='um'``)."""
    token = _STYLE.set("cli")
    try:
        yield
    finally:
        _STYLE.reset(token)


@contextmanager
def case_option_names() -> Iterator[None]:
    """Within this block, messages name case-file keys (``surface.height_unit = "um"``)."""
    token = _STYLE.set("case")
    try:
        yield
    finally:
        _STYLE.reset(token)


def option_name(name: str) -> str:
    """``"height_unit"``; inside :func:`cli_option_names` ``"--height-unit"``; inside
    :func:`case_option_names` ``"surface.height_unit"``."""
    style = _STYLE.get()
    if style == "cli":
        return _CLI_FLAGS.get(name, name)
    return f"surface.{name}" if style == "case" else name


def option_example(name: str, value: str) -> str:
    """``height_unit='um'``; on the command line ``--height-unit um`` (quoted when it has a space);
    in a case file ``surface.height_unit = "um"``."""
    style = _STYLE.get()
    if style == "cli":
        shown = f"'{value}'" if " " in value else value
        return f"{_CLI_FLAGS.get(name, name)} {shown}"
    if style == "case":
        return f'surface.{name} = "{value}"'
    return f"{name}={value!r}"


class MissingUnitsError(UnitError):
    """A file lacks units the user must give; one message names every missing option.

    ``missing`` lists the API names (``"height_unit"``, ``"size"`` (or ``pixel_size``),
    ``"lateral_unit"``); ``field`` is the first of them.
    """

    def __init__(self, path: Any, missing: list[str], what: list[str]) -> None:
        hints = []
        for key in missing:
            if key == "height_unit":
                hints.append(f"{option_name('height_unit')} (e.g. {option_example('height_unit', 'um')})")
            elif key == "size":
                pair = ("--size '1 mm, 0.5 mm'" if _STYLE.get() == "cli" else "size=('1 mm', '0.5 mm')")
                hints.append(f"{option_name('size')} (whole map, e.g. {option_example('size', '100 um')}, or "
                             f"{pair} for x and y) or "
                             f"{option_name('pixel_size')} (e.g. {option_example('pixel_size', '0.5 um')})")
            elif key == "lateral_unit":
                hints.append(f"{option_name('lateral_unit')} (unit of the x, y columns, "
                             f"e.g. {option_example('lateral_unit', 'um')})")
            else:  # pragma: no cover - programming error
                raise ValueError(key)
        super().__init__(missing[0], None, "")
        self.path = str(path)
        self.missing = tuple(missing)
        text = what[0] if len(what) == 1 else ", no ".join(what[:-1]) + " and no " + what[-1]
        self.args = (f"{path} states no {text}; pass {'; and '.join(hints)}",)
