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
in its row (:func:`~sealeak.cases.sobol.log_leak_rate`). The limit: with sealed samples the indices describe "whether it
seals" and "how much it leaks" at once, and they change with the floor; :attr:`~sealeak.cases.sobol.SobolIndices.sealed_fraction`
says how many samples that concerns. A row with no variance (sealed in every sample, or the same Q in
every one) has no indices (NaN).

Reproducibility: the same ``seed`` gives the same points and the same bootstrap, so the same bytes on
one machine. The estimators are Saltelli et al. (2010) for S1 and Jansen (1999) for ST, as SALib
implements them (docs/architecture.md says why SALib over SciPy's ``sobol_indices``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from ..errors import InputError
from .run import CaseResult
from .sobol import (
    BOOTSTRAP_RESAMPLES,
    CONFIDENCE_LEVEL,
    MAX_EVALUATIONS,
    SobolIndices,
    check_base_samples,
    check_design,
    log_leak_rate,
)
from .uncertainty import UncertainStudy, leak_rates

__all__ = ["study_sensitivity", "sobol_points", "sobol_analysis", "sobol_indices"]


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
    _check_evaluations(base_samples, n * (d + 2) * d, f"with {d} uncertain inputs", "sensitivity")
    return sobol_sample.sample(_problem(d), n, calc_second_order=False, scramble=True, seed=_seeds(seed)[0])


def _check_evaluations(base_samples: int, numbers: int, what: str, field: str) -> None:
    """Refuse a design whose arrays would hold more than :data:`MAX_EVALUATIONS` numbers (``what``: why so many)."""
    if numbers > MAX_EVALUATIONS:
        raise InputError(field, base_samples, f"{what} holds {numbers} numbers; at most {MAX_EVALUATIONS}: "
                                              "give a smaller N")


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
                        n, seed)


def sobol_indices(f: Callable[[np.ndarray], np.ndarray], names: Sequence[str], base_samples: int, seed: int,
                  floor: float | None = None) -> SobolIndices:
    """Sobol' first-order and total indices of log10 f per row: f maps unit points [n, d] to leak rates [n, rows] (m³/s).

    ``f`` is called once, on all N·(d + 2) points of :func:`sobol_points`; see the module's text for the
    treatment of sealed samples (``floor``) and the reproducibility with ``seed``.
    """
    points = sobol_points(len(names), base_samples, seed)
    return sobol_analysis(names, f(points), base_samples, seed, floor)


def study_sensitivity(study: UncertainStudy, base_samples: int, seed: int,
                      nominal: list[CaseResult] | None = None) -> SobolIndices:
    """Sobol' indices of log10 Q of every row of an uncertain study (``predict --sensitivity N``).

    The model is :func:`~sealeak.cases.uncertainty.leak_rates` (the leak rate each row shows: a liquid's Q, a gas's
    pV throughput; 0 where sealed), run on the N·(d + 2) points of :func:`sobol_points`; the inputs are named by their
    keys. ``nominal``: the nominal cases' results, when already at hand (else run where a fast path needs them).
    """
    if not study.inputs:
        raise InputError("--sensitivity", base_samples, "needs uncertain inputs: give a value a spread, e.g. "
                                                         "h_rms = \"1.5 um ± 10 %\" (docs/case-files.md, Uncertain inputs)")
    n = check_design(len(study.inputs), base_samples)
    _check_evaluations(base_samples, n * (len(study.inputs) + 2) * len(study.rows),
                       f"with {len(study.inputs)} uncertain inputs and {len(study.rows)} rows", "--sensitivity")
    return sobol_indices(lambda u: leak_rates(study, u, nominal), [i.key for i in study.inputs], base_samples, seed)
