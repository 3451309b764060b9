"""Checks of the solvers' array arguments (private)."""

from __future__ import annotations

from typing import Any

from numpy.typing import ArrayLike

from ..errors import InputError
from ._xp import namespace


def square_grid(values: ArrayLike, field: str, plural: str) -> Any:
    """``values`` as a float64 N×N array (N >= 2) of finite numbers; else an :class:`InputError` naming
    ``field`` (``plural`` names the values in the message, e.g. "gaps").

    An array of another namespace (CuPy, array-API) stays in it (:mod:`._xp`); anything else becomes NumPy.
    """
    xp = namespace(values)
    a = xp.asarray(values, dtype=xp.float64)
    if a.ndim != 2 or a.shape[0] != a.shape[1] or a.shape[0] < 2:
        raise InputError(field, f"array of shape {tuple(a.shape)}", "must be a square N×N array with N >= 2")
    if not bool(xp.all(xp.isfinite(a))):
        raise InputError(field, "non-finite values", f"{plural} must be finite (no NaN or inf)")
    return a
