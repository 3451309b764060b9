"""The Sobol' sensitivity of an uncertain prediction in words, tables and records (``predict --sensitivity N``).

:class:`~sealeak.cases.sensitivity.SobolIndices` holds, per result row and uncertain input, the first-order
and total indices of log10 Q and the half-widths of their 95 % intervals; this module turns them into the
table block under the uncertainty table (:func:`sensitivity_columns`, :func:`sensitivity_heading`,
:func:`sensitivity_legend`), the plain-words sentence per case (:func:`sensitivity_sentences`), the
per-row record fields of JSON and CSV (:func:`sensitivity_fields`: ``sobol_first[KEY]``,
``sobol_first_conf[KEY]``, ``sobol_total[KEY]``, ``sobol_total_conf[KEY]``, dimensionless) and the JSON
``sensitivity`` object (:func:`sensitivity_json`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..cases.sobol import (
    BOOTSTRAP_RESAMPLES,
    CONFIDENCE_LEVEL,
    FLOOR_DECADES,
    SensitivityColumns,
    SobolIndices,
    chosen_rows,
    sensitivity_summary,
)
from ..cases.uncertainty import UncertainStudy
from ..io.quantities import descriptions_of, expand_keys, units_of
from .notes import load_text
from .uncertainty import row_columns

__all__ = ["sensitivity_columns", "sensitivity_heading", "sensitivity_legend", "sensitivity_sentences", "sensitivity_fields",
           "sensitivity_units", "sensitivity_json", "SENSITIVITY_FIELDS"]

#: The per-row fields of each input (``FIELD[KEY]``), what they hold (all dimensionless).
SENSITIVITY_FIELDS = {k.split("[")[0]: v for k, v in descriptions_of(SensitivityColumns).items()}


def _cell(total: float, first: float) -> str:
    return "—" if not np.isfinite(total) else f"{total:.2f} ({first:.2f})"


def sensitivity_columns(s: SobolIndices, study: UncertainStudy) -> tuple[list[str], list[list[str]]]:
    """The headers and cells of the sensitivity table: per row its variant (a study), load, "ST (S1)" of each input, and
    the share of samples that sealed."""
    rows = study.rows
    headers, cols = row_columns(rows)
    headers += [f"{k} ST (S1)" for k in s.names] + ["sealed"]
    cols += [[_cell(s.total[j, i], s.first[j, i]) for j in range(len(rows))] for i in range(len(s.names))]
    cols.append([f"{100 * v:.0f} %" for v in s.sealed_fraction])
    return headers, [list(r) for r in zip(*cols)]


def sensitivity_heading(s: SobolIndices) -> str:
    """The sentence above the sensitivity table: what was analysed, with how many predictions."""
    conf = np.r_[s.first_conf.ravel(), s.total_conf.ravel()]
    widest = f"; 95 % intervals ± {np.nanmax(conf):.2f} at most" if np.isfinite(conf).any() else ""
    return (f"sensitivity: Sobol' indices of log10 Q, {s.base_samples} base samples "
            f"({s.evaluations} predictions, seed {s.seed}){widest}:")


def sensitivity_legend() -> str:
    """What the cells of the sensitivity table mean."""
    return ("ST (S1): the share of the variance of log10 Q an input explains with its interactions (alone); "
            f"a sealed sample counts {FLOOR_DECADES:g} decade below the row's smallest leak; —: no variance "
            "(the same Q in every sample); estimates: with few base samples they stray beyond 0–1 or put S1 above ST, "
            "by about the interval")


def sensitivity_sentences(s: SobolIndices, study: UncertainStudy) -> list[str]:
    """One plain-words sentence per case, at its middle load (:func:`~sealeak.cases.sensitivity.chosen_rows`)."""
    out = []
    for j in chosen_rows(study):
        row = study.rows[j]
        where = f"{row.variant}, " if row.variant else ""
        out.append(f"at {where}{load_text(row.load_name, row.load)}: {sensitivity_summary(s, j)}")
    return out


def sensitivity_fields(s: SobolIndices) -> list[dict[str, float]]:
    """Per row, the record fields ``sobol_first[KEY]`` ... of every input (dimensionless; NaN: no variance)."""
    arrays = {"sobol_first": s.first, "sobol_first_conf": s.first_conf, "sobol_total": s.total, "sobol_total_conf": s.total_conf}
    return [{f"{name}[{key}]": float(a[j, i]) for i, key in enumerate(s.names) for name, a in arrays.items()}
            for j in range(s.first.shape[0])]


def sensitivity_units(s: SobolIndices) -> dict[str, str]:
    """The unit of every field of :func:`sensitivity_fields` (all "1")."""
    return expand_keys(units_of(SensitivityColumns), input=s.names)


def sensitivity_json(s: SobolIndices, study: UncertainStudy) -> dict[str, Any]:
    """The JSON ``sensitivity`` object: the method, the design, the treatment of sealed samples, per row the sealed share,
    the floor and the variance of log10 Q, and the plain-words sentence per case."""
    def number(v: float) -> float | None:
        return float(v) if np.isfinite(v) else None

    return {
        "method": "Sobol' indices (Saltelli 2010 first order, Jansen 1999 total) by SALib on Saltelli's design",
        "output": "log10 of leak_rate (m^3/s)",
        "base_samples": s.base_samples, "predictions": s.evaluations, "seed": s.seed,
        "confidence_level": CONFIDENCE_LEVEL, "bootstrap_resamples": BOOTSTRAP_RESAMPLES,
        "inputs": list(s.names),
        "fields": SENSITIVITY_FIELDS,
        "sealed_samples": f"counted at a floor {FLOOR_DECADES:g} decade below the smallest leak rate sampled in the row",
        "rows": [{"sealed_fraction": float(s.sealed_fraction[j]), "floor": number(s.floor[j]),
                  "variance_log10": number(s.variance[j])} for j in range(len(study.rows))],
        "summaries": sensitivity_sentences(s, study),
    }
