"""How much a case may ask for: checked before any work, each refusal one line naming the key.

The limits are generous for real work (a pressure sweep of 40 points, an ensemble of 16 realisations)
and keep a mistyped or hostile input (a range of 10⁵ points, ``--realizations 1000000000000``) from
running for hours or exhausting memory. ``docs/case-files.md`` ("Limits") lists them; the TOML
pre-scan's own limits (dotted-key parts, nesting, bare words) are in :mod:`sealeak.io.tomlscan`.
"""

from __future__ import annotations

from collections.abc import Sized
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["MAX_CASE_FILE_BYTES", "MAX_PRESSURES", "MAX_LOADS", "MAX_STUDY_VALUES", "MAX_REALIZATIONS",
           "MAX_WORKERS", "MAX_GRIDS", "MAX_TOPOGRAPHY_FILES", "at_most", "whole_number"]

#: Bytes of a case file (1 MB); data files it names (profiles, C(q) tables, topographies) have their own limits.
MAX_CASE_FILE_BYTES = 1_000_000
#: Squeeze pressures of one case: a list or a ``{start, stop, num}`` range.
MAX_PRESSURES = 10_000
#: Compressions, groove depths or profile scales of one O-ring or pressure-profile case (each its own contact solution).
MAX_LOADS = 1_000
#: Values of a ``[study]`` (one case each).
MAX_STUDY_VALUES = 100
#: Random surfaces of ``sealeak simulate`` (``--realizations``, ``[simulation] realizations``).
MAX_REALIZATIONS = 10_000
#: Worker processes of a local Dask cluster (``--workers``).
MAX_WORKERS = 1_024
#: Measured topography files stitched into one spectrum (``surface.files``); each file has its own size limit.
MAX_TOPOGRAPHY_FILES = 100
#: Grids of one convergence study (``--grid 64,128,256``, ``[simulation] grid = [...]``).
MAX_GRIDS = 16
#: The most numbers one uncertainty analysis may hold per array (≈ 80 MB of float64): samples × rows of a band, the
#: Sobol' design's points × inputs and its answers, points × rows.
MAX_EVALUATIONS = 10_000_000


def at_most(field: str, values: Sized, limit: int, what: str, shown: Any = None) -> None:
    """Refuse ``values`` (items the user gave as ``field``) when more than ``limit``; ``what`` names them,
    ``shown`` is the value the message shows (default: ``values``)."""
    if len(values) > limit:
        raise InputError(field, values if shown is None else shown,
                         f"{len(values)} {what}: at most {limit} (docs/case-files.md, Limits)")


def whole_number(field: str, value: Any, low: int, high: int, what: str = "") -> int:
    """``value`` as an int from ``low`` to ``high``, else an :class:`~sealeak.errors.InputError` naming ``field``.

    ``what`` is added to the message (e.g. ``" (grid points per side)"``); True and False are not numbers.
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not low <= value <= high:
        raise InputError(field, value, f"must be a whole number from {low} to {high}{what}")
    return int(value)
