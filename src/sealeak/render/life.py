"""Figures of the seal over its life: the leak rate against time at each temperature, and against temperature at
each time (``[conditions] time`` and ``temperature``, :mod:`sealeak.cases.life`; docs/user-guide.md).

Each case of such a file is one (time, temperature); a figure draws one load of the seal (the middle row of the
cases' records: a squeeze pressure, a compression or a load factor), the leak rate Q of the theory the tables show.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import CaseResult
from ..cases.life import time_text, time_unit
from ..cases.uncertainty import UncertaintyResult
from ..io.leak_units import celsius
from .plotstyle import (
    Series,
    color,
    draw_series,
    finish_axes,
    laid_out,
    ml_per_min_axis,
    new_figure,
    place_legend,
    power_unit,
    say_nothing,
    spans_decades,
    subtitle,
)

__all__ = ["LIFE_FIGURE_NAMES", "life_figure_names", "life_figures", "volume_limit"]

#: The figures :func:`life_figures` can return, by the number of times and temperatures they need.
LIFE_FIGURE_NAMES = ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png")


def _grid(results: Sequence[CaseResult]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, str]:
    """(times s, temperatures K, Q [temperature, time] m³/s, valid [temperature, time], load text) of the middle
    load of the life cases among ``results`` (NaN where a (time, temperature) is missing or has no leak channel)."""
    life = [r for r in results if r.case.life is not None]
    times = np.unique([r.case.life.time for r in life if r.case.life is not None])
    temps = np.unique([r.case.life.temperature for r in life if r.case.life is not None])
    q = np.full((temps.size, times.size), np.nan)
    valid = np.ones_like(q, dtype=bool)
    name, loads = "squeeze_pressure", []
    for r in life:
        point, records = r.case.life, r.records()
        if point is None or not records:
            continue
        row = records[len(records) // 2]
        i, j = int(np.searchsorted(temps, point.temperature)), int(np.searchsorted(times, point.time))
        q[i, j] = row["leak_rate"] if row.get("percolates", True) else np.nan
        valid[i, j] = bool(row.get("valid", True))
        name = r.band.band.load_name if r.band is not None else "squeeze_pressure"
        loads.append(float(row[name]))
    return times, temps, q, valid, _load_text(name, loads)


def _load_text(name: str, loads: list[float]) -> str:
    """``"at P0 = 300 kPa"``, ``"at compression = 19.3 … 20.7 %"`` (an O-ring's changes with temperature): the
    load (Pa, or a fraction, or a load factor) a life figure draws."""
    if not loads:
        return ""
    label, scale, unit = {"squeeze_pressure": ("P0", 1e3, " kPa"), "compression": ("compression", 0.01, " %")}.get(
        name, (name.replace("_", " "), 1.0, ""))
    lo, hi = min(loads) / scale, max(loads) / scale
    value = f"{lo:.3g}" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g} … {hi:.3g}"
    return f"at {label} = {value}{unit}" + (" (it changes with temperature)" if value != f"{lo:.3g}" else "")


def _coincide(series: list[Series], what: str) -> list[str]:
    """A note when every curve lies on the first (Q does not change with ``what``): only one colour shows."""
    first = series[0].y if series else np.array([])
    same = len(series) > 1 and all(np.allclose(s.y, first, rtol=1e-6, atol=0.0, equal_nan=True) for s in series[1:])
    return [f"the curves coincide: Q does not change with {what} here"] if same else []


def life_figure_names(times: int, temperatures: int) -> tuple[str, ...]:
    """The life figures of a file with this many times and temperatures: Q(t) for several times, Q(T) for several
    temperatures."""
    return tuple(n for n, k in zip(LIFE_FIGURE_NAMES, (times, temperatures)) if k > 1)


def volume_limit(unc: UncertaintyResult | None) -> tuple[float, str] | None:
    """``conditions.max_leak_rate`` as a leak rate Q (m³/s) and as written, where it is compared with Q (a volume
    flow), else None (none given, or a gas's pV throughput: not on a Q axis)."""
    if unc is None or unc.limits is None or not unc.limit_keys or set(unc.limit_keys) != {"leak_rate"}:
        return None
    return float(unc.limits[0]), str(unc.study.max_leak_rate)


def life_figures(results: Sequence[CaseResult], limit: tuple[float, str] | None = None) -> dict[str, Figure]:
    """The figures of the seal over its life (:data:`LIFE_FIGURE_NAMES`) that the life cases among ``results``
    call for (none without life cases); ``limit``: ``conditions.max_leak_rate`` (m³/s, as written), drawn as a line
    (:func:`volume_limit`)."""
    times, temps, q, valid, load = _grid(results)
    out: dict[str, Figure] = {}
    if times.size > 1:
        out["leak_rate_vs_time.png"] = figure_leak_rate_vs_time(times, temps, q, valid, load, limit)
    if temps.size > 1:
        out["leak_rate_vs_temperature.png"] = figure_leak_rate_vs_temperature(times, temps, q, valid, load, limit)
    return out


def _draw(ax: Axes, series: list[Series], notes: list[str], empty: str, limit: tuple[float, str] | None) -> None:
    """Draw leak-rate series (m³/s) against the x set by the caller: a log axis where they span decades, the notes,
    ``limit`` (m³/s, as written) as a dash-dotted line, the ml/min axis and the legend; an axes with nothing to draw
    says ``empty``."""
    q = np.concatenate([s.y for s in series] + ([np.array([limit[0]])] if limit else [])) if series else np.array([])
    if not np.any(np.isfinite(q) & (q > 0)):
        say_nothing(ax, empty)
        ax.set_ylabel("leak rate Q (m³/s)")
        subtitle(ax, "\n".join(notes))
        finish_axes(ax)
        return
    logy = spans_decades(q, 1.0)
    scale, unit = (1.0, "m³/s") if logy else power_unit(q, "m³/s")
    draw_series(ax, [replace(s, y=s.y / scale) for s in series], logy=logy, bottom_zero=not logy)
    if not logy:  # a flat curve (Q that does not change) is drawn below the top, not on it
        ax.set_ylim(0.0, max(ax.get_ylim()[1], 1.1 * float(np.nanmax(q)) / scale))
    ax.set_ylabel(f"leak rate Q ({unit})")
    if limit is not None:
        ax.axhline(limit[0] / scale, color="0.2", linestyle="-.", linewidth=1.2, label=f"max_leak_rate = {limit[1]}")
    if any(not s.valid.all() for s in series):
        notes = [*notes, "hollow markers: outside the theory's validity"]
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    ml_per_min_axis(ax, scale)
    place_legend(ax)


_NO_LEAK = "no leak channel at any time and temperature\n(the non-contact area does not percolate)"


@laid_out
def figure_leak_rate_vs_time(times: np.ndarray, temps: np.ndarray, q: np.ndarray, valid: np.ndarray,
                             load: str, limit: tuple[float, str] | None = None) -> Figure:
    """Q (m³/s) against the time since assembly (log axis, in s … a) at each temperature (K, shown in °C), one line
    each; a time of 0 s (just after assembly) has no place on a log axis and is left out, said below the title."""
    fig, ax = new_figure("Leak rate over the life of the seal")
    shown = times > 0
    unit, factor = time_unit(float(times[shown].min()) if shown.any() else 1.0)
    series = [Series(times[shown] / factor, q[i, shown], valid[i, shown], color(i), "-", f"T = {celsius(t):.4g} °C")
              for i, t in enumerate(temps)]
    ax.set_xscale("log")
    ax.set_xlabel(f"time since assembly t ({unit})")
    notes = [load, *_coincide(series, "temperature")]
    notes += ["t = 0 (just after assembly) is not on the log time axis"] if not shown.all() else []
    _draw(ax, series, notes, _NO_LEAK, limit)
    return fig


@laid_out
def figure_leak_rate_vs_temperature(times: np.ndarray, temps: np.ndarray, q: np.ndarray, valid: np.ndarray,
                                    load: str, limit: tuple[float, str] | None = None) -> Figure:
    """Q (m³/s) against the temperature (K, shown in °C) at each time since assembly (s), one line each."""
    fig, ax = new_figure("Leak rate against temperature over the life of the seal")
    x = np.array([celsius(t) for t in temps])
    series = [Series(x, q[:, j], valid[:, j], color(j), "-", f"t = {time_text(float(t))}") for j, t in enumerate(times)]
    ax.set_xlabel("temperature T (°C)")
    ax.set_xlim(x.min() - 0.04 * (x.max() - x.min()), x.max() + 0.04 * (x.max() - x.min()))
    _draw(ax, series, [load, *_coincide(series, "time")], _NO_LEAK, limit)
    return fig
