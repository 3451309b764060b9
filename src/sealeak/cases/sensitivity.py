"""Sobol' sensitivity of the leak rate to its uncertain inputs: which measurement would narrow the band most.

The uncertain inputs of a case (an ``[uncertainty]`` table, docs/case-files.md) are mapped onto the
unit hypercube [0, 1)^d (input i's value is its distribution's ``ppf(u_i)``), so a model is a
vectorised callable ``f(unit_points[n, d]) -> Q[n, rows]`` (leak rates in m³/s, one column per row of
the prediction). :func:`sobol_indices` draws Saltelli's design on that cube (SALib's scrambled
Sobol' sequence, ``base_samples · (d + 2)`` model runs), evaluates ``f`` once on all points and
returns, per row and input, Sobol's first-order index S1 (the share of the variance of log10 Q that
input explains alone) and total index ST (alone and with every interaction), each with the
half-width of its bootstrap confidence interval (docs/theory.md §15).

What is analysed is y = log10 Q, not Q: leak rates span decades, and the variance of Q itself is
carried by the few largest samples. A sealed sample (Q = 0, or no leak channel: NaN) has no
logarithm; it counts as ``floor`` (m³/s), by default one decade below the smallest leak rate sampled
in its row (:func:`log_leak_rate`). The limit: with sealed samples the indices describe "whether it
seals" and "how much it leaks" at once, and they change with the floor; :attr:`SobolIndices.sealed_fraction`
says how many samples that concerns. A row with no variance (sealed in every sample, or the same Q in
every one) has no indices (NaN).

Reproducibility: the same ``seed`` gives the same points and the same bootstrap, so the same bytes on
one machine. The estimators are Saltelli et al. (2010) for S1 and Jansen (1999) for ST, as SALib
implements them (docs/architecture.md says why SALib over SciPy's ``sobol_indices``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from ..errors import InputError

__all__ = ["SobolIndices", "sobol_points", "sobol_analysis", "sobol_indices", "log_leak_rate", "check_base_samples",
           "sensitivity_summary", "MIN_BASE_SAMPLES", "MAX_BASE_SAMPLES", "MAX_EVALUATIONS", "CONFIDENCE_LEVEL",
           "BOOTSTRAP_RESAMPLES"]

#: The fewest and most base samples N (a power of two): Saltelli's design runs the model N·(d + 2) times.
MIN_BASE_SAMPLES = 16
MAX_BASE_SAMPLES = 65536
#: The most model evaluations (points × rows) one analysis may hold in memory (≈ 80 MB of float64).
MAX_EVALUATIONS = 10_000_000
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
    evaluations: int
    seed: int

    def ranking(self, row: int) -> list[int]:
        """The inputs of ``row`` by decreasing total index (NaN last): the measurement to improve first leads."""
        total = self.total[row]
        return sorted(range(len(self.names)), key=lambda i: (not np.isfinite(total[i]), -np.nan_to_num(total[i], nan=0.0)))


def check_base_samples(value: object, field: str = "sensitivity") -> int:
    """The number of base samples N, checked: an integer power of two from :data:`MIN_BASE_SAMPLES` to :data:`MAX_BASE_SAMPLES`."""
    allowed = f"must be a power of two from {MIN_BASE_SAMPLES} to {MAX_BASE_SAMPLES} (base samples N; the model runs N·(inputs + 2) times)"
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise InputError(field, value, allowed)
    n = int(value)
    if not (MIN_BASE_SAMPLES <= n <= MAX_BASE_SAMPLES) or n & (n - 1):
        raise InputError(field, value, allowed)
    return n


def _problem(d: int) -> dict[str, object]:
    return {"num_vars": d, "names": [f"u{i}" for i in range(d)], "bounds": [[0.0, 1.0]] * d}


def _seeds(seed: int) -> tuple[int, int]:
    """Independent seeds of the sample and of the bootstrap, both from ``seed`` (SALib's bootstrap takes seed 0 as 'none')."""
    sample, boot = np.random.SeedSequence(seed).spawn(2)
    return int(sample.generate_state(1)[0]), int(boot.generate_state(1)[0]) | 1


def sobol_points(d: int, base_samples: int, seed: int) -> np.ndarray:
    """Saltelli's design on the unit cube: N·(d + 2) points [n, d] in [0, 1) (rows A, A_B^(1..d), B per base sample).

    The points are SALib's scrambled Sobol' sequence drawn with a seed from ``seed``; N is checked
    (:func:`check_base_samples`).
    """
    n = check_base_samples(base_samples)
    if d < 1:
        raise InputError("uncertainty", d, "needs at least one uncertain input for a sensitivity analysis")
    if n * (d + 2) * d > MAX_EVALUATIONS:
        raise InputError("sensitivity", base_samples, f"with {d} uncertain inputs must be at most {MAX_EVALUATIONS // ((d + 2) * d)}")
    return sobol_sample.sample(_problem(d), n, calc_second_order=False, scramble=True, seed=_seeds(seed)[0])


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


def sobol_analysis(names: Sequence[str], q: np.ndarray, base_samples: int, seed: int,
                   floor: float | None = None) -> SobolIndices:
    """Sobol' indices of log10 Q from the model's leak rates ``q`` [N·(d + 2), rows] (m³/s) on :func:`sobol_points`.

    ``names``: the d inputs, in the order of the cube's axes; ``seed``: the one given to
    :func:`sobol_points` (it also seeds the bootstrap); ``floor``: see :func:`log_leak_rate`.
    """
    d, n = len(names), check_base_samples(base_samples)
    q = np.asarray(q, dtype=float)
    q = q[:, None] if q.ndim == 1 else q
    if q.ndim != 2 or q.shape[0] != n * (d + 2):
        raise InputError("leak rates", f"shape {q.shape}", f"must have {n * (d + 2)} rows (N·(d + 2) model runs)")
    rows = q.shape[1]
    out = {k: np.full((rows, d), np.nan) for k in ("S1", "S1_conf", "ST", "ST_conf")}
    sealed, floors, variance = np.zeros(rows), np.full(rows, np.nan), np.zeros(rows)
    boot_seed = _seeds(seed)[1]
    for j in range(rows):
        y, floors[j], sealed[j] = log_leak_rate(q[:, j], floor)
        variance[j] = float(np.var(y)) if np.isfinite(y).all() else float("nan")
        if not variance[j] > 0:
            continue  # sealed everywhere, or one Q for every sample: nothing to share out
        s = sobol_analyze.analyze(_problem(d), y, calc_second_order=False, num_resamples=BOOTSTRAP_RESAMPLES,
                                  conf_level=CONFIDENCE_LEVEL, seed=boot_seed)
        for k in out:
            out[k][j] = s[k]
    return SobolIndices(tuple(names), out["S1"], out["S1_conf"], out["ST"], out["ST_conf"], sealed, floors, variance,
                        n, n * (d + 2), seed)


def sobol_indices(f: Callable[[np.ndarray], np.ndarray], names: Sequence[str], base_samples: int, seed: int,
                  floor: float | None = None) -> SobolIndices:
    """Sobol' first-order and total indices of log10 f per row: f maps unit points [n, d] to leak rates [n, rows] (m³/s).

    ``f`` is called once, on all N·(d + 2) points of :func:`sobol_points`; see the module's text for the
    treatment of sealed samples (``floor``) and the reproducibility with ``seed``.
    """
    points = sobol_points(len(names), base_samples, seed)
    return sobol_analysis(names, f(points), base_samples, seed, floor)


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
