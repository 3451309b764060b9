"""The uncertainty band of a prediction in words and tables: what ``sealeak predict`` prints under the deterministic
table, the report's table and the JSON ``uncertainty`` object (:class:`~sealeak.cases.uncertainty.UncertaintyResult`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..cases.life import time_text
from ..cases.life_answers import LifeAnswer, life_answers
from ..cases.uncertainty import PASS_PROBABILITY, SAMPLER_NAMES, PassingLoad, ResultRow, UncertaintyResult
from ..io.leak_units import celsius, to_ml_per_min
from .notes import load_text, loads_text

__all__ = ["row_columns", "uncertainty_columns", "uncertainty_heading", "uncertainty_legend", "passing_lines",
           "uncertainty_summary"]



def _shown(unc: UncertaintyResult) -> list[tuple[str, str, Any]]:
    """(record key, column name, SI → shown unit) of the leak rates the table shows: the gas's mbar·l/s (and with
    permeation the total, interface leak plus permeation), else Q in ml/min; a liquid's helium equivalent beside it."""
    out: list[tuple[str, str, Any]] = []
    if "leak_rate_mbar_l_s" in unc.values:
        out.append(("leak_rate_mbar_l_s", "Q {} (mbar·l/s)", lambda v: v))
        if "leak_rate_total_mbar_l_s" in unc.values:  # with permeation: what a leak test measures (and max_leak_rate)
            out.append(("leak_rate_total_mbar_l_s", "Q_total {} (mbar·l/s)", lambda v: v))
    else:
        out.append(("leak_rate", "Q {} (ml/min)", to_ml_per_min))
        if "leak_rate_helium_mbar_l_s" in unc.values:
            out.append(("leak_rate_helium_mbar_l_s", "Q_He {} (mbar·l/s)", lambda v: v))
    return out


def row_columns(rows: Sequence[ResultRow]) -> tuple[list[str], list[list[str]]]:
    """The headers and cells of the first columns of a table with one row per result row: its variant (a study only)
    and its load (P0 in kPa, compression in %, a profile's scale)."""
    name, values = rows[0].load_name, [r.load for r in rows]
    if name == "squeeze_pressure":
        head, loads = "P0 (kPa)", [f"{v / 1e3:.4g}" for v in values]
    elif name == "compression":
        head, loads = "ε (%)", [f"{100 * v:.4g}" for v in values]
    else:
        head, loads = "scale", [f"{v:.4g}" for v in values]
    if any(r.variant for r in rows):
        return ["variant", head], [[r.variant for r in rows], loads]
    return [head], [loads]


def uncertainty_columns(unc: UncertaintyResult) -> tuple[list[str], list[list[str]]]:
    """The headers and cells of the uncertainty table: per result row its variant (a study), load, the 5th, 50th and
    95th percentiles of Q, the share of samples that seal, and the probability of exceeding ``max_leak_rate``; without
    uncertain inputs (``max_leak_rate`` alone) the pass-or-fail table of :func:`_verdict_columns`."""
    if not unc.study.inputs:
        return _verdict_columns(unc)
    headers, cols = row_columns(unc.study.rows)
    for key, name, convert in _shown(unc):
        p, outside = convert(unc.percentiles(key)), unc.outside(key)
        for i, which in enumerate(("p05", "p50", "p95")):
            headers.append(name.format(which))
            # as the leak rates above; a sealed percentile: 0; one taken from samples outside the theory: starred
            cols.append([(f"{v:.3e}" if v else "0") + ("*" if out and v else "") for v, out in zip(p[i], outside[i], strict=True)])
    headers.append("sealed")
    cols.append([f"{100 * v:.0f} %" for v in np.mean(unc.sealed, axis=0)])
    outside_fraction = unc.outside_fraction
    if outside_fraction is not None and outside_fraction.any():
        headers.append("outside")
        cols.append([f"{100 * v:.0f} %" for v in outside_fraction])
    exceed = unc.exceed_probability
    if exceed is not None:
        headers.append("P(Q > max)")
        cols.append([f"{v:.3f}" for v in exceed])
    return headers, [list(r) for r in zip(*cols)]


def _verdict_columns(unc: UncertaintyResult) -> tuple[list[str], list[list[str]]]:
    """Per result row its load, the deterministic leak rates the table would show percentiles of (one sample: each
    percentile is the same number; 0 without a leak channel, starred outside the theory's validity) and whether it
    passes ``max_leak_rate``."""
    headers, cols = row_columns(unc.study.rows)
    for key, name, convert in _shown(unc):
        q, outside = convert(unc.percentiles(key))[1], unc.outside(key)[1]
        headers.append(name.replace(" {}", ""))
        cols.append([(f"{v:.3e}" if v else "0") + ("*" if out and v else "") for v, out in zip(q, outside, strict=True)])
    if unc.exceed_probability is not None:
        headers.append("passes")
        cols.append(["no" if v > 0 else "yes" for v in unc.exceed_probability])
    return headers, [list(r) for r in zip(*cols)]


def uncertainty_heading(unc: UncertaintyResult) -> str:
    """The sentence above the table: how many samples of which inputs."""
    inputs = unc.study.inputs
    if not inputs:
        return ("pass or fail: no uncertain inputs, so the leak rates are the deterministic ones (give a value a spread "
                "for a band and the probability of passing)")
    return (f"uncertainty: {unc.samples} samples ({SAMPLER_NAMES[unc.sampler]}, seed {unc.seed}) of "
            f"{len(inputs)} uncertain input{'s' if len(inputs) != 1 else ''}:")


def uncertainty_legend(unc: UncertaintyResult) -> str:
    """What the columns of the uncertainty table mean."""
    if not unc.study.inputs:
        text = "the leak rates of the table above (0: no leak channel)"
        outside = unc.outside_fraction
        if outside is not None and outside.any():
            text += "; * outside the theory's validity (see the notes of the table above): not a leak rate to rely on"
        if unc.limits is not None:
            text += f"; passes: the leak rate is at most conditions.max_leak_rate = {unc.study.max_leak_rate}"
            text += _compared(unc)
        return text
    text = ("p05, p50, p95: the 5th, 50th and 95th percentiles of the leak rate over the samples (a sample without a "
            "leak channel counts as 0); sealed: the share of samples without a leak channel")
    outside = unc.outside_fraction
    if outside is not None and outside.any():
        text += ("; outside: the share of samples that leak outside the theory's validity (a gap narrower than the "
                 "fluid's molecules, a seal the fluid pressure opens; see the notes of the table above), and * a "
                 "percentile taken from such samples: not a leak rate to rely on")
    if unc.limits is not None:
        text += f"; P(Q > max): the probability that the leak rate exceeds conditions.max_leak_rate = {unc.study.max_leak_rate}"
        text += _compared(unc)
    return text


def _compared(unc: UncertaintyResult) -> str:
    """What ``max_leak_rate`` is compared with, where it is not the leak rate itself."""
    keys = set(unc.limit_keys or ())
    if "leak_rate_helium_pv" in keys:
        return " (compared with the helium equivalent)"
    if "leak_rate_total_pv" in keys:
        return " (compared with Q_total, the interface leak plus permeation through the rubber: what a leak test measures)"
    return ""


def passing_lines(unc: UncertaintyResult) -> list[str]:
    """For the seal over its life first one line per load: when it first exceeds ``max_leak_rate`` at each temperature
    and between which temperatures it holds at the latest time (:func:`~sealeak.cases.life_answers.life_answers`);
    then one line per case: the load at which it passes with 95 % probability, or why there is none."""
    return [_life_line(unc, a) for a in life_answers(unc)] + [_passing_line(unc, p) for p in unc.passing_loads()]


def _life_line(unc: UncertaintyResult, a: LifeAnswer) -> str:
    """``"P0 = 600 kPa: at -20 °C first exceeds 1e-6 mbar*l/s at t = 3.2 a; at 20 °C holds to 10 a; holds from
    -15 °C up at 10 a"``."""
    spec, latest = unc.study.max_leak_rate, time_text(a.latest_time)
    parts = [f"at {celsius(t):.4g} °C " + (
        f"holds to {latest}" if e is None else
        f"exceeds {spec} already at t = {time_text(e) if e > 0 else '0'} (the earliest computed)" if e == a.earliest_time
        else f"first exceeds {spec} at t = {time_text(e)}") for t, e in zip(a.temperatures, a.exceeded_from)]
    if len(a.temperatures) > 1:
        parts.append(_holding_text(a, latest))
    prefix = f"{a.variant}, " if a.variant else ""
    return f"{prefix}{loads_text(a.load_name, sorted(set(a.loads)))}: " + "; ".join(parts)


def _holding_text(a: LifeAnswer, latest: str) -> str:
    """Where the seal holds at the latest time: from the cold limit up, up to the warm limit, or both."""
    cold, warm = a.holds_from, a.holds_to
    if cold == a.temperatures[0]:
        return f"holds at every temperature computed at {latest}"
    if cold is None and warm is None:
        if any(e is None for e in a.exceeded_from):  # some temperature between holds to the latest time
            return f"exceeds it at the coldest and the warmest at {latest}, holds only between them (see the rows)"
        return f"exceeds it at every temperature at {latest}"
    limits = [f"up to {celsius(warm):.3g} °C" if warm is not None else "", f"from {celsius(cold):.3g} °C up" if cold is not None else ""]
    return f"holds {' and '.join(t for t in limits if t)} at {latest}"


def _passing_line(unc: UncertaintyResult, p: PassingLoad) -> str:
    prefix = f"{p.variant}: " if p.variant else ""
    if not unc.study.inputs:
        return prefix + _verdict_line(unc, p)
    if np.isfinite(p.passing_load):
        (lo, hi), (p_lo, p_hi) = p.between, p.between_passing_probability
        line = (f"{prefix}passes {unc.study.max_leak_rate} with {100 * PASS_PROBABILITY:.0f} % probability from about "
                f"{load_text(p.load_name, float(f'{p.passing_load:.3g}'))} on, interpolated between the rows at "
                f"{load_text(p.load_name, lo)} (passes in {100 * p_lo:.1f} % of the samples) and "
                f"{load_text(p.load_name, hi)} ({100 * p_hi:.1f} %)")
        if _far_apart(p.load_name, lo, hi):
            line += ": rows that far apart place it roughly; compute loads between them to place it better"
        return line + _outside_there(p)
    if np.isfinite(p.between[0]):  # the higher row seals: nothing to interpolate towards
        (lo, hi), (p_lo, p_hi) = p.between, p.between_passing_probability
        return (f"{prefix}passes {unc.study.max_leak_rate} with {100 * PASS_PROBABILITY:.0f} % probability from somewhere "
                f"between the rows at {load_text(p.load_name, lo)} (passes in {100 * p_lo:.1f} % of the samples) and "
                f"{load_text(p.load_name, hi)} ({100 * p_hi:.1f} %), where at least {100 * PASS_PROBABILITY:.0f} % of the "
                "samples seal: no leak rate to interpolate towards; compute loads between them to place it"
                + _outside_there(p))
    return f"{prefix}{p.note}"


def _verdict_line(unc: UncertaintyResult, p: PassingLoad) -> str:
    """Where a case without uncertain inputs passes ``max_leak_rate``: its deterministic leak rate reaching the limit
    between two rows (log-linear, docs/theory.md eq. 14.4), or why no load is placed."""
    spec, name = unc.study.max_leak_rate, p.load_name.replace("_", " ")
    lo, hi = p.between
    if np.isfinite(p.passing_load):
        line = (f"passes {spec} from about {load_text(p.load_name, float(f'{p.passing_load:.3g}'))} on, where the leak "
                f"rate reaches it (log-linear between the rows at {load_text(p.load_name, lo)} and "
                f"{load_text(p.load_name, hi)})")
        if _far_apart(p.load_name, lo, hi):
            line += ": rows that far apart place it roughly; compute loads between them to place it better"
    elif np.isfinite(lo):
        line = (f"passes {spec} from somewhere between the rows at {load_text(p.load_name, lo)} and "
                f"{load_text(p.load_name, hi)}, where it seals: no leak rate to interpolate towards; compute loads "
                "between them to place it")
    elif p.passes_at_lowest:
        line = f"passes {spec} already at the lowest {name} computed: compute lower loads to find where it starts to pass"
    else:
        line = f"exceeds {spec} at every {name} computed"
    outside = [load_text(p.load_name, x) for x, f in zip(p.between, p.between_outside, strict=True) if f > 0]
    if len(outside) == 1:
        line += f"; the row at {outside[0]} lies outside the theory's validity (starred)"
    elif outside:
        line += f"; the rows at {' and '.join(outside)} lie outside the theory's validity (starred)"
    return line


def _outside_there(p: PassingLoad) -> str:
    """"; 6 % and 53 % of the samples there leak outside the theory's validity (...)", or "" where none do."""
    fraction = [f for f in p.between_outside if f > 0]
    if not fraction:
        return ""
    return (f"; {' and '.join(f'{100 * f:.0f} %' for f in fraction)} of the samples there leak outside the theory's "
            "validity (the table's 'outside')")


def _far_apart(load_name: str, lo: float, hi: float) -> bool:
    """Whether two neighbouring rows are too far apart for a load interpolated between them to be more than rough:
    squeeze pressures or profile scales more than 10 % apart, compressions more than one point (the leak rate changes by
    a factor of several over such steps)."""
    return hi - lo > 0.01 if load_name == "compression" else hi > 1.1 * lo


def uncertainty_summary(unc: UncertaintyResult) -> dict[str, Any]:
    """The JSON ``uncertainty`` object: how it was sampled, the inputs, the specification and each case's passing load,
    and the sentences ``predict`` prints under its uncertainty table (``answers``: :func:`passing_lines`), which the web
    app shows."""
    sampled = bool(unc.study.inputs)  # (without uncertain inputs: the nominal prediction alone, nothing sampled)
    return {
        "samples": unc.samples if sampled else 0, "sampler": unc.sampler if sampled else None,
        "seed": unc.seed if sampled else None, "percentiles": [5, 50, 95] if sampled else None,
        "inputs": [{"key": i.key, "label": i.label, "distribution": i.distribution, "value": i.nominal,
                    "unit": i.unit or None, "parameters": i.parameters or None, "choices": list(i.choices) or None}
                   for i in unc.study.inputs],
        "max_leak_rate": unc.study.max_leak_rate,
        "compared_with": unc.limit_keys[0] if unc.limit_keys else None,
        "passing_probability": PASS_PROBABILITY,
        "passing_loads": [{"variant": p.variant or None, "load": p.load_name,
                           "passing_load": None if not np.isfinite(p.passing_load) else p.passing_load,
                           "between": None if not np.isfinite(p.between[0]) else list(p.between),
                           "between_passing_probability": None if not np.isfinite(p.between[0]) else list(p.between_passing_probability),
                           "unit": "Pa" if p.load_name == "squeeze_pressure" else "1", "note": p.note or None}
                          for p in unc.passing_loads()],
        "answers": passing_lines(unc),
    } | ({"life": [_life_record(a) for a in answers]} if (answers := life_answers(unc)) else {})


def _life_record(a: LifeAnswer) -> dict[str, Any]:
    """The JSON of one load's life answers: its study variant (null without one), its load (``values`` in ``unit``) and its fields in SI (s, K)."""
    return {"variant": a.variant or None, "load": a.load_name, "values": sorted(set(a.loads)), "unit": "Pa" if a.load_name == "squeeze_pressure" else "1",
            "temperatures": list(a.temperatures), "exceeded_from": list(a.exceeded_from),
            "earliest_time": a.earliest_time, "latest_time": a.latest_time, "holds_from": a.holds_from,
            "holds_to": a.holds_to}
