"""Answers about the seal over its life against ``conditions.max_leak_rate``: per load, the time at which the leak
rate first exceeds the specification at each temperature, and at the latest time the lowest temperature from which up
it holds (the cold limit: the cord shrinks, the rubber stiffens) and the highest up to which it holds (the warm limit:
relaxation and compression set run faster) (docs/user-guide.md, "The seal over its life").

The answers use the deterministic (nominal) leak rate of each (time, temperature) case, compared as
:mod:`sealeak.cases.uncertainty` compares it (Q of the theory the tables show, or the gas's pV throughput, or a
liquid's helium equivalent), each against the limit of its own case (a standard or molar flow, or a mass flow, is a
pV throughput at the gas's temperature there).
Between two computed times the leak rate is taken as a power law of the time (log Q linear in log t); between two
temperatures log Q is linear in T. A row without a leak channel seals (Q = 0).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..io.quantities import quantity
from .life import life_variant
from .model import LifePoint
from .uncertainty import UncertaintyResult, record_values

__all__ = ["LifeAnswer", "first_exceeded", "life_answers", "lowest_holding_temperature", "highest_holding_temperature"]


@dataclass(frozen=True)
class LifeAnswer:
    """The answers for one load of the seal (the row index ``row`` of every life case) of one study variant.

    Attributes
    ----------
    load_name, loads
        The load's record key and its values over the cases (Pa, or 1: an O-ring's compression changes with T).
    temperatures
        The temperatures computed (K), ascending.
    exceeded_from
        Per temperature, the time (s) from which the leak rate exceeds the specification, or None where it holds
        to the latest time.
    earliest_time, latest_time
        The earliest and the latest time computed (s).
    holds_from
        The lowest temperature (K) from which up it holds at the latest time, or None where it exceeds at the
        warmest; ``holds_from == temperatures[0]`` where it holds already at the coldest computed.
    holds_to
        The highest temperature (K) up to which it holds at the latest time, or None where it exceeds at the
        coldest; ``holds_to == temperatures[-1]`` where it holds still at the warmest computed.
    variant
        The ``[study]`` variant whose life cases these are (their label without its life part; ``""`` without one).
    """

    row: int
    load_name: str
    loads: tuple[float, ...] = quantity("<load>", "the load's values over the life cases (an O-ring's compression "
                                                   "changes with temperature)", key="values")
    temperatures: tuple[float, ...] = quantity("K", "the temperatures computed, ascending")
    exceeded_from: tuple[float | None, ...] = quantity(
        "s", "per temperature, the time from which the leak rate first exceeds conditions.max_leak_rate, interpolated "
             "in log t (the earliest time: already there; null: it holds to the latest time)")
    earliest_time: float = quantity("s", "the earliest time since assembly computed")
    latest_time: float = quantity("s", "the latest time since assembly computed")
    holds_from: float | None = quantity(
        "K", "the lowest temperature from which up the leak rate holds conditions.max_leak_rate at the latest time, "
             "interpolated (the coldest computed: holds at every one; null: exceeds even at the warmest)")
    holds_to: float | None = quantity(
        "K", "the highest temperature up to which the leak rate holds conditions.max_leak_rate at the latest time, "
             "interpolated (the warmest computed: holds at every one; null: exceeds even at the coldest)")
    variant: str = ""


def _crossing(x0: float, x1: float, q0: float, q1: float, limit: float, log_x: bool) -> float:
    """Where Q goes through ``limit`` between (x0, q0) and (x1, q1): log Q linear in x (in log x with ``log_x``);
    Q linear where one end is 0 (it seals), x linear where x0 is 0 (no log)."""
    if q0 > 0 and q1 > 0:
        f = (math.log(limit) - math.log(q0)) / (math.log(q1) - math.log(q0))
    else:
        f = (limit - q0) / (q1 - q0)
    if log_x and x0 > 0:
        return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))
    return x0 + f * (x1 - x0)


def first_exceeded(times: Sequence[float], q: Sequence[float], limit: float) -> float | None:
    """The first time (s) at which Q (at ``times``, ascending, s) exceeds ``limit``, interpolated in log t between
    the last time it holds and the first it does not (:func:`_crossing`), or None where it holds at every time."""
    for k, (t, v) in enumerate(zip(times, q)):
        if v > limit:
            return float(t) if k == 0 else _crossing(times[k - 1], t, q[k - 1], v, limit, log_x=True)
    return None


def lowest_holding_temperature(temperatures: Sequence[float], q: Sequence[float], limit: float) -> float | None:
    """The lowest temperature (K) from which up Q (at ``temperatures``, ascending, K) holds ``limit``: interpolated
    between the warmest temperature at which it exceeds and the next, the coldest where it holds at every one,
    None where it exceeds at the warmest."""
    failing = [k for k, v in enumerate(q) if v > limit]
    if not failing:
        return float(temperatures[0])
    k = failing[-1]
    if k == len(q) - 1:
        return None
    return _crossing(temperatures[k], temperatures[k + 1], q[k], q[k + 1], limit, log_x=False)


def highest_holding_temperature(temperatures: Sequence[float], q: Sequence[float], limit: float) -> float | None:
    """The highest temperature (K) up to which Q (at ``temperatures``, ascending, K) holds ``limit``: the mirror of
    :func:`lowest_holding_temperature` (the warmest where it holds at every one, None where it exceeds at the
    coldest)."""
    mirrored = lowest_holding_temperature([-t for t in reversed(temperatures)], list(reversed(q)), limit)
    return None if mirrored is None else -mirrored


def life_answers(unc: UncertaintyResult) -> list[LifeAnswer]:
    """Per ``[study]`` variant and load of the seal, the answers of its life cases against
    ``conditions.max_leak_rate`` (the nominal results); empty without the specification or without life cases with
    more than one time or temperature."""
    if unc.limits is None or unc.limit_keys is None:
        return []
    variants: dict[str, dict[int, LifePoint]] = {}
    for i, r in enumerate(unc.nominal):
        if r.case.life is not None:
            variants.setdefault(life_variant(r.case), {})[i] = r.case.life
    return [a for variant, life in variants.items() for a in _variant_answers(unc, variant, life)]


def _variant_answers(unc: UncertaintyResult, variant: str, life: dict[int, LifePoint]) -> list[LifeAnswer]:
    """The answers of one variant's life cases (``life``: case index → its (time, temperature)), one per load."""
    assert unc.limits is not None and unc.limit_keys is not None
    index: dict[int, list[int]] = {}
    for j, row in enumerate(unc.study.rows):
        index.setdefault(row.case, []).append(j)
    times = sorted({p.time for p in life.values()})
    temps = sorted({p.temperature for p in life.values()})
    if len(times) < 2 and len(temps) < 2:
        return []
    loads = min(len(index.get(i, [])) for i in life)
    shown = {i: record_values([unc.nominal[i]]) for i in life}  # Q of the theory the tables show, 0 where it seals
    out = []
    for n in range(loads):
        # Q over the limit of its own (T, t) cell: a gas's limit in sccm, mol/s or kg/s is a pV throughput at the
        # cell's temperature; Q/limit > 1 exceeds it, and log(Q/limit) is interpolated as log Q is
        ratio = np.zeros((len(temps), len(times)))
        values = []
        for i, point in life.items():
            j = index[i][n]
            ratio[temps.index(point.temperature), times.index(point.time)] = \
                shown[i][unc.limit_keys[j]][n] / float(unc.limits[j])
            values.append(float(unc.study.rows[j].load))
        latest = ratio[:, -1].tolist()
        out.append(LifeAnswer(
            row=n, load_name=unc.study.rows[index[next(iter(life))][n]].load_name, loads=tuple(values),
            temperatures=tuple(temps), exceeded_from=tuple(first_exceeded(times, r.tolist(), 1.0) for r in ratio),
            earliest_time=times[0], latest_time=times[-1], holds_from=lowest_holding_temperature(temps, latest, 1.0),
            holds_to=highest_holding_temperature(temps, latest, 1.0), variant=variant))
    return out
