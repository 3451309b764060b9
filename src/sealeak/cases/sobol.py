"""Sobol' indices of the leak rate as results: :class:`SobolIndices`, the sample-size rule, sealed samples, the plain words.

What :mod:`sealeak.cases.sensitivity` computes (with SALib) and the renderers show, without SALib itself: the
record of the indices, the check of the base samples N, the treatment of sealed samples (log10 Q with a floor,
:func:`log_leak_rate`), the sentence of :func:`sensitivity_summary` and the row each case is summarised at
(:func:`chosen_rows`). docs/theory.md §15 has the definitions.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..io.quantities import quantity
from .limits import MAX_EVALUATIONS
from .uncertainty import UncertainStudy

__all__ = ["SobolIndices", "SensitivityColumns", "check_base_samples", "check_design",
           "log_leak_rate", "sensitivity_summary", "chosen_rows", "MIN_BASE_SAMPLES",
           "MAX_BASE_SAMPLES", "MAX_EVALUATIONS", "MAX_PREDICTIONS", "CONFIDENCE_LEVEL", "BOOTSTRAP_RESAMPLES", "FLOOR_DECADES"]

#: The fewest and most base samples N (a power of two): Saltelli's design runs the model N·(d + 2) times.
MIN_BASE_SAMPLES = 16
MAX_BASE_SAMPLES = 65536
#: The most predictions one ``predict --sensitivity`` may run (each a full prediction of every row).
MAX_PREDICTIONS = 16384
#: The confidence level of the bootstrap intervals and the number of bootstrap resamples.
CONFIDENCE_LEVEL = 0.95
BOOTSTRAP_RESAMPLES = 200
#: The default floor of a sealed sample: this many decades below the smallest leak rate sampled in its row.
FLOOR_DECADES = 1.0


@dataclass(frozen=True)
class SobolIndices:
    """Sobol' indices of log10 Q per row of a prediction and per uncertain input.

    ``first``, ``total``: S1 and ST, shape (rows, inputs), dimensionless shares of the variance of
    log10 Q (NaN for a row without variance); ``first_conf``, ``total_conf``: the half-widths of their
    :data:`CONFIDENCE_LEVEL` bootstrap intervals; ``sealed_fraction``: per row, the share of samples that
    did not leak (counted at ``floor``, m³/s, per row; NaN where nothing leaked); ``variance``: per row,
    the variance of log10 Q (decades²). ``base_samples`` N and ``evaluations`` = N·(d + 2) model runs.
    """

    names: tuple[str, ...]
    first: np.ndarray
    first_conf: np.ndarray
    total: np.ndarray
    total_conf: np.ndarray
    sealed_fraction: np.ndarray
    floor: np.ndarray
    variance: np.ndarray
    base_samples: int
    seed: int

    @property
    def evaluations(self) -> int:
        """The model runs of Saltelli's design, N·(d + 2)."""
        return self.base_samples * (len(self.names) + 2)

    def ranking(self, row: int) -> list[int]:
        """The inputs of ``row`` by decreasing total index (NaN last): the measurement to improve first leads."""
        total = self.total[row]
        return sorted(range(len(self.names)), key=lambda i: (not np.isfinite(total[i]), -np.nan_to_num(total[i], nan=0.0)))


@dataclass(frozen=True, kw_only=True)
class SensitivityColumns:
    """The Sobol' fields of a result row (``predict --sensitivity N``), one of each per uncertain input ``<input>``
    (its case-file key, e.g. ``sobol_total[surface.h_rms]``); NaN (null) where log10 Q has no variance."""

    sobol_first: float = quantity("1", "first-order Sobol' index S1 of log10 Q: the share of its variance the input explains "
                                       "alone", key="sobol_first[<input>]")
    sobol_first_conf: float = quantity("1", "half-width of the 95 % bootstrap interval of sobol_first",
                                       key="sobol_first_conf[<input>]")
    sobol_total: float = quantity("1", "total Sobol' index ST of log10 Q: the share the input explains alone and with "
                                       "every interaction", key="sobol_total[<input>]")
    sobol_total_conf: float = quantity("1", "half-width of the 95 % bootstrap interval of sobol_total",
                                       key="sobol_total_conf[<input>]")


def check_base_samples(value: object, field: str = "sensitivity") -> int:
    """The number of base samples N, checked: an integer power of two from :data:`MIN_BASE_SAMPLES` to :data:`MAX_BASE_SAMPLES`."""
    allowed = f"must be a power of two from {MIN_BASE_SAMPLES} to {MAX_BASE_SAMPLES} (base samples N; the model runs N·(inputs + 2) times)"
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise InputError(field, value, allowed)
    n = int(value)
    if not (MIN_BASE_SAMPLES <= n <= MAX_BASE_SAMPLES) or n & (n - 1):
        raise InputError(field, value, allowed)
    return n


def check_design(inputs: int, base_samples: object, field: str = "--sensitivity") -> int:
    """N checked (:func:`check_base_samples`) and the predictions of Saltelli's design, N·(inputs + 2), at most
    :data:`MAX_PREDICTIONS` (each is a full prediction); returns N."""
    n = check_base_samples(base_samples, field)
    if n * (inputs + 2) > MAX_PREDICTIONS:
        largest = 1 << (MAX_PREDICTIONS // (inputs + 2)).bit_length() - 1
        raise InputError(field, base_samples, f"with {inputs} uncertain inputs runs N·(inputs + 2) = {n * (inputs + 2)} "
                                              f"predictions; at most {MAX_PREDICTIONS} (N up to {largest})")
    return n


def log_leak_rate(q: np.ndarray, floor: float | None = None) -> tuple[np.ndarray, float, float]:
    """(log10 Q with sealed samples at the floor, the floor in m³/s, the share of sealed samples) of one row.

    ``q``: leak rates in m³/s of one row's samples; 0 or NaN is a sealed sample. ``floor``: the leak
    rate a sealed sample counts as (m³/s); default :data:`FLOOR_DECADES` decades below the smallest
    positive Q sampled. When nothing leaks the floor is NaN and so is every log.
    """
    q = np.asarray(q, dtype=float)
    if np.isinf(q).any() or (q < 0).any():
        raise InputError("leak rate", float(q[np.isinf(q) | (q < 0)][0]), "must be finite and >= 0 (m³/s)")
    leaks = np.isfinite(q) & (q > 0)
    sealed = float(1.0 - leaks.mean()) if q.size else 0.0
    if floor is None:
        floor = float(q[leaks].min()) * 10.0 ** -FLOOR_DECADES if leaks.any() else float("nan")
    with np.errstate(invalid="ignore"):
        y = np.log10(np.where(leaks, q, floor))
    return y, floor, sealed


def sensitivity_summary(indices: SobolIndices, row: int, labels: Sequence[str] | None = None) -> str:
    """One plain sentence on ``row``: which input explains most of the variance of log Q, and what to measure better first.

    ``labels``: how to name the inputs (default their keys), e.g. "h_rms explains 72 % of the variance
    of log Q (alone: 68 %); measure it better first. Next: E (15 %)."
    """
    labels = list(labels or indices.names)
    if not indices.variance[row] > 0:
        why = "every sample sealed" if indices.sealed_fraction[row] == 1.0 else "the same leak rate in every sample"
        return f"No sensitivity: {why}; no input changes log Q."
    order = indices.ranking(row)
    top = order[0]
    text = (f"{labels[top]} explains {_percent(indices.total[row, top])} of the variance of log Q "
            f"(alone: {_percent(indices.first[row, top])}); measure it better first.")
    if len(order) > 1:
        nxt = order[1]
        text += f" Next: {labels[nxt]} ({_percent(indices.total[row, nxt])})."
    if indices.sealed_fraction[row] > 0:
        text += (f" {_percent(indices.sealed_fraction[row])} of the samples sealed (counted at {indices.floor[row]:.3g} m³/s): "
                 "the indices mix whether it seals with how much it leaks.")
    return text


def _percent(share: float) -> str:
    """A share as a whole percentage, clipped to 0–100 (an estimate may stray slightly outside)."""
    return f"{100.0 * min(max(float(share), 0.0), 1.0):.0f} %"


def chosen_rows(study: UncertainStudy) -> list[int]:
    """Per case of the study, the row whose sensitivity is put in words and drawn: the case's middle load
    (the lower middle of an even number of loads, in the order the case file gives them)."""
    rows: dict[int, list[int]] = {}
    for j, row in enumerate(study.rows):
        rows.setdefault(row.case, []).append(j)
    return [r[(len(r) - 1) // 2] for r in rows.values()]
