"""Length-unit parsing for the topography layer (pint, at the edge only).

Inside sealeak every length is a float in metres; this module turns user or file text such as
``"um"``, ``"µm"``, ``"nm"``, ``"0.5 um"`` into metres and nothing else.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from ..errors import UnitError

__all__ = ["length_unit_factor", "parse_length"]


def _registry() -> Any:
    from ..units import registry

    return registry()


@lru_cache(maxsize=64)
def _factor(text: str) -> float:
    import pint

    ureg = _registry()
    try:
        quantity = ureg.Quantity(text) if any(c.isspace() or c.isdigit() for c in text) else ureg.Quantity(1.0, text)
        value = float(quantity.to("m").magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError("not a length") from None
    except Exception:  # pint raises many types for garbage (UndefinedUnitError, SyntaxError, ...)
        raise ValueError("unknown unit") from None
    if not np.isfinite(value) or value <= 0:
        raise ValueError("must be a positive length")
    return value


def length_unit_factor(unit: str, field: str = "unit") -> float:
    """Metres per ``unit`` (e.g. ``"um"``, ``"µm"``, ``"μm"``, ``"nm"``, ``"mm"``, ``"m"``, ``"Å"``).

    Raises :class:`~sealeak.errors.UnitError` (naming ``field``) for unknown units and units that are
    not lengths.
    """
    if not isinstance(unit, str) or not unit.strip():
        raise UnitError(field, unit, "a length unit such as 'm', 'mm', 'um', 'nm'")
    try:
        return _factor(unit.strip())
    except ValueError as exc:
        raise UnitError(field, unit, f"{exc}; allowed: a length unit such as 'm', 'mm', 'um', 'nm'") from None


def parse_length(value: Any, field: str) -> float:
    """A length in metres from a number (already in m) or a string with unit (``"0.5 um"``)."""
    if isinstance(value, str):
        text = value.strip()
        try:
            return _factor(text)
        except ValueError as exc:
            raise UnitError(field, value, f"{exc}; allowed: a positive length like '0.5 um' or a number in m") from None
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise UnitError(field, value, "a positive length like '0.5 um' or a number in m") from None
    if not np.isfinite(v) or v <= 0:
        raise UnitError(field, value, "a positive length like '0.5 um' or a number in m")
    return v
