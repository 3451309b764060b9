"""Checks of the solvers' array arguments (private)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError


def square_grid(values: ArrayLike, field: str, plural: str) -> NDArray[np.float64]:
    """``values`` as a float64 N×N array (N >= 2) of finite numbers; else an :class:`InputError` naming
    ``field`` (``plural`` names the values in the message, e.g. "gaps")."""
    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 2 or a.shape[0] != a.shape[1] or a.shape[0] < 2:
        raise InputError(field, f"array of shape {a.shape}", "must be a square N×N array with N >= 2")
    if not np.isfinite(a).all():
        raise InputError(field, "non-finite values", f"{plural} must be finite (no NaN or inf)")
    return a
