"""Figures of the seal over its life: the leak rate against time at each temperature, and against temperature at
each time (``[conditions] time`` and ``temperature``, :mod:`sealeak.cases.life`; docs/user-guide.md).

Each case of such a file is one (time, temperature); each load of the seal (a row of the cases' records: a squeeze
pressure, a compression or a load factor) of each ``[study]`` variant gets a panel of its own, headed by the variant
and the load, stacked with a shared time or temperature axis: up to :data:`MAX_PANELS`, evenly spread over them where
there are more. Each draws the leak rate Q of the theory
the tables show, or a gas's pV throughput Q_pV in mbar·l/s (docs/theory.md §11.9) as the other gas figures do.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import CaseResult
from ..cases.life import life_variant, time_text, time_unit
from ..cases.model import STANDARD_TEMPERATURE_CASE
from ..cases.uncertainty import UncertaintyResult, record_values
from ..io.leak_units import celsius
from .plotstyle import (
    GAS_LEAK_LABEL,
    STYLE,
    Series,
    color,
    draw_series,
    finish_axes,
    invalid_note,
    laid_out,
    limit_in_axis_unit,
    limit_line,
    ml_per_min_axis,
    pa_m3_axis,
    place_legend,
    power_unit,
    say_nothing,
    spans_decades,
    subtitle,
)

__all__ = ["LIFE_FIGURE_NAMES", "MAX_PANELS", "life_figure_names", "life_figures", "volume_limit", "as_assembled"]

#: The figures :func:`life_figures` can return, by the number of times and temperatures they need.
LIFE_FIGURE_NAMES = ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png")

#: The most panels (loads) a life figure stacks; with more loads it draws this many, evenly spread (first and last).
MAX_PANELS = 4

#: Height (in) of a life figure of one panel and of each panel more.
_HEIGHT, _PANEL_HEIGHT = 4.6, 2.8


def _grid(results: Sequence[CaseResult]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[str], bool]:
    """(times s, temperatures K, Q [panel, temperature, time], valid [panel, temperature, time], load text per panel,
    gas) of the life cases among ``results``, one panel per load of each ``[study]`` variant (its text led by the
    variant's label) (NaN where a (time, temperature) is missing or has no leak channel): Q of the theory the tables
    show in m³/s, or a gas's Q_pV in mbar·l/s where every life case is a gas case (``gas``)."""
    life = [r for r in results if r.case.life is not None]
    gas = bool(life) and all(r.case.gas is not None and r.gas for r in life)
    key = "leak_rate_mbar_l_s" if gas else "leak_rate"
    times = np.unique([r.case.life.time for r in life if r.case.life is not None])
    temps = np.unique([r.case.life.temperature for r in life if r.case.life is not None])
    variants = list(dict.fromkeys(life_variant(r.case) for r in life))
    rows = min((len(r.records()) for r in life), default=0)
    q = np.full((len(variants) * rows, temps.size, times.size), np.nan)
    valid = np.ones_like(q, dtype=bool)
    name = "squeeze_pressure"
    loads: list[list[float]] = [[] for _ in range(q.shape[0])]
    for r in life:
        point, records = r.case.life, r.records()
        if point is None:
            continue
        i, j = int(np.searchsorted(temps, point.temperature)), int(np.searchsorted(times, point.time))
        name = r.band.band.load_name if r.band is not None else "squeeze_pressure"
        shown = record_values([r])[key]  # Q of the theory the tables show, as the answers compare it; 0: it seals
        first = variants.index(life_variant(r.case)) * rows
        for n, row in enumerate(records[:rows]):
            q[first + n, i, j] = shown[n] if shown[n] > 0 else np.nan
            valid[first + n, i, j] = bool(row.get("valid", True))
            loads[first + n].append(float(row[name]))
    texts = [_load_text(name, v) for v in loads]
    if len(variants) > 1:
        texts = [f"{variants[k // rows]}: {t}" for k, t in enumerate(texts)]
    return times, temps, q, valid, texts, gas


def _panels(rows: int) -> list[int]:
    """The loads (row indices) the figures draw: every one up to :data:`MAX_PANELS`, else that many evenly spread."""
    if rows <= MAX_PANELS:
        return list(range(rows))
    return sorted({int(round(k)) for k in np.linspace(0, rows - 1, MAX_PANELS)})


def _load_text(name: str, loads: list[float]) -> str:
    """``"at P0 = 300 kPa"``, ``"at compression = 19.3 … 20.7 %"`` (an O-ring's changes with temperature and with its
    compression set): the load (Pa, or a fraction, or a load factor) a panel of a life figure draws."""
    if not loads:
        return ""
    label, scale, unit = {"squeeze_pressure": ("P0", 1e3, " kPa"), "compression": ("compression", 0.01, " %")}.get(
        name, (name.replace("_", " "), 1.0, ""))
    lo, hi = min(loads) / scale, max(loads) / scale
    value = f"{lo:.3g}" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g} … {hi:.3g}"
    return f"at {label} = {value}{unit}" + (" (it changes over the life)" if value != f"{lo:.3g}" else "")


def _coincide(series: list[Series], what: str) -> list[str]:
    """A note when every curve lies on the first (Q does not change with ``what``): only one colour shows."""
    first = series[0].y if series else np.array([])
    same = len(series) > 1 and all(np.allclose(s.y, first, rtol=1e-6, atol=0.0, equal_nan=True) for s in series[1:])
    return [f"the curves coincide: Q does not change with {what} here"] if same else []


def as_assembled(results: Sequence[CaseResult]) -> list[CaseResult]:
    """The results a band seal's own figures draw (pressure profile, leak rate against the load, local gap): of a file
    of the seal over its life with several cases, the one as assembled (the earliest time, at the temperature nearest
    the standard 20 °C), whose figures stay readable where the compression and the pressures of the cases differ by
    decades (the life figures draw the others); every result otherwise."""
    life = [r for r in results if r.case.life is not None]
    if len(life) < 2 or len(life) != len(results):
        return list(results)
    return [min(life, key=lambda r: (r.case.life.time, abs(r.case.life.temperature - STANDARD_TEMPERATURE_CASE))
                if r.case.life is not None else (0.0, 0.0))]


def life_figure_names(times: int, temperatures: int) -> tuple[str, ...]:
    """The life figures of a file with this many times and temperatures: Q(t) for several times, Q(T) for several
    temperatures."""
    return tuple(n for n, k in zip(LIFE_FIGURE_NAMES, (times, temperatures)) if k > 1)


def volume_limit(unc: UncertaintyResult | None, drawn: str | None = None) -> tuple[float, str] | None:
    """``conditions.max_leak_rate`` as compared and as written: a leak rate Q (m³/s) where it is compared with Q (a
    volume flow), a gas's pV throughput (Pa·m³/s) where with Q_pV (or with ``drawn``, the record key a figure draws
    where not these: a gas's total with permeation, ``leak_rate_total_pv``); else None (none given, a liquid's helium
    equivalent: on neither axis, or a limit that is no one line: a standard or molar flow, or a mass flow, is a pV
    throughput that differs with the gas's temperature from case to case)."""
    if unc is None or unc.limits is None or not unc.limit_keys or len(set(unc.limit_keys)) != 1 or \
            unc.limit_keys[0] not in ((drawn,) if drawn else ("leak_rate", "leak_rate_pv")) or len(set(unc.limits.tolist())) != 1:
        return None
    if unc.limit_keys[0] == "leak_rate" and any(c.gas is not None for c in unc.study.cases):
        return None  # a gas's figures draw Q_pV: a volume-flow limit is on none of their axes
    return float(unc.limits[0]), str(unc.study.max_leak_rate)


def life_figures(results: Sequence[CaseResult], limit: tuple[float, str] | None = None) -> dict[str, Figure]:
    """The figures of the seal over its life (:data:`LIFE_FIGURE_NAMES`) that the life cases among ``results``
    call for (none without life cases); ``limit``: ``conditions.max_leak_rate`` (m³/s, or Pa·m³/s for a gas; as
    written), drawn as a line (:func:`volume_limit`)."""
    times, temps, q, valid, loads, gas = _grid(results)
    limit = limit_in_axis_unit(limit, gas)  # drawn in the figure's mbar·l/s for a gas
    out: dict[str, Figure] = {}
    if times.size > 1:
        out["leak_rate_vs_time.png"] = figure_leak_rate_vs_time(times, temps, q, valid, loads, limit, gas)
    if temps.size > 1:
        out["leak_rate_vs_temperature.png"] = figure_leak_rate_vs_temperature(times, temps, q, valid, loads, limit, gas)
    return out


def _stack(title: str, loads: list[str], xlabel: str) -> tuple[Figure, list[tuple[Axes, int, list[str]]]]:
    """A figure of one panel per load drawn (:func:`_panels`), stacked with a shared x axis labelled ``xlabel`` under
    the bottom panel: (axes, load index, the lines below its heading) each; the first panel's heading is ``title``,
    the others' their load."""
    shown = _panels(len(loads)) or [0]
    with mpl.rc_context(STYLE):
        fig = Figure(figsize=(STYLE["figure.figsize"][0], _HEIGHT + _PANEL_HEIGHT * (len(shown) - 1)), layout="constrained")
        axes = fig.subplots(len(shown), 1, sharex=True, squeeze=False)[:, 0]
    more = [f"{len(shown)} of the {len(loads)} loads, evenly spread"] if len(shown) < len(loads) else []
    panels = []
    for k, (ax, n) in enumerate(zip(axes, shown)):
        load = loads[n] if n < len(loads) else ""
        ax._sealeak_heading = title if k == 0 else load  # type: ignore[attr-defined]
        ax.tick_params(axis="x", labelbottom=True)  # each panel keeps its ticks' values; the label goes below the last
        ax.set_xlabel(xlabel if k == len(shown) - 1 else "")
        panels.append((ax, n, ([load, *more] if k == 0 else [])))
    return fig, panels


def _draw(ax: Axes, series: list[Series], notes: list[str], empty: str, limit: tuple[float, str] | None,
          gas: bool = False) -> None:
    """Draw leak-rate series (m³/s; a gas's Q_pV in mbar·l/s) against the x set by the caller: a log axis where they
    span decades, the notes, ``limit`` (in the series' unit, as written) as a dash-dotted line and the second axis
    (ml/min; Pa·m³/s for a gas) (the caller places the legend, once all panels are drawn); an axes with nothing to
    draw says ``empty``."""
    quantity, base, second = (GAS_LEAK_LABEL, "mbar·l/s", pa_m3_axis) if gas else ("leak rate Q", "m³/s", ml_per_min_axis)
    q = np.concatenate([s.y for s in series] + ([np.array([limit[0]])] if limit else [])) if series else np.array([])
    if not np.any(np.isfinite(q) & (q > 0)):
        say_nothing(ax, empty)
        ax.set_ylabel(f"{quantity} ({base})")
        subtitle(ax, "\n".join(notes))
        finish_axes(ax)
        return
    logy = spans_decades(q, 1.0)
    scale, unit = (1.0, base) if logy else power_unit(q, base)
    draw_series(ax, [replace(s, y=s.y / scale) for s in series], logy=logy, bottom_zero=not logy)
    if not logy:  # a flat curve (Q that does not change) is drawn below the top, not on it
        ax.set_ylim(0.0, max(ax.get_ylim()[1], 1.1 * float(np.nanmax(q)) / scale))
    ax.set_ylabel(f"{quantity} ({unit})")
    if limit is not None:
        limit_line(ax, limit[0] / scale, limit[1])
    notes = [*notes, invalid_note(series)] if invalid_note(series) else notes
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    second(ax, scale)


_NO_LEAK = "no leak channel at any time and temperature\n(the non-contact area does not percolate)"


@laid_out
def figure_leak_rate_vs_time(times: np.ndarray, temps: np.ndarray, q: np.ndarray, valid: np.ndarray,
                             loads: list[str], limit: tuple[float, str] | None = None, gas: bool = False) -> Figure:
    """Q (m³/s; ``gas``: Q_pV in mbar·l/s) against the time since assembly (log axis, in s … a) at each temperature (K, shown in °C), one line
    each, one panel per load (``q[load, temperature, time]``); a time of 0 s (just after assembly) has no place on a
    log axis and is left out, said below the title."""
    shown = times > 0
    unit, factor = time_unit(float(times[shown].min()) if shown.any() else 1.0)
    fig, panels = _stack("Leak rate over the life of the seal", loads, f"time since assembly t ({unit})")
    for k, (ax, n, notes) in enumerate(panels):
        series = [Series(times[shown] / factor, q[n, i, shown], valid[n, i, shown], color(i), "-", f"T = {celsius(t):.4g} °C")
                  for i, t in enumerate(temps)] if n < q.shape[0] else []
        ax.set_xscale("log")
        notes = [*notes, *_coincide(series, "temperature")]
        notes += ["t = 0 (just after assembly) is not on the log time axis"] if k == 0 and not shown.all() else []
        _draw(ax, series, notes, _NO_LEAK, limit, gas)
    place_legend(panels[0][0])  # each panel draws the same temperatures: one legend, in the first
    return fig


@laid_out
def figure_leak_rate_vs_temperature(times: np.ndarray, temps: np.ndarray, q: np.ndarray, valid: np.ndarray,
                                    loads: list[str], limit: tuple[float, str] | None = None, gas: bool = False) -> Figure:
    """Q (m³/s; ``gas``: Q_pV in mbar·l/s) against the temperature (K, shown in °C) at each time since assembly (s), one line each, one panel
    per load (``q[load, temperature, time]``)."""
    fig, panels = _stack("Leak rate against temperature over the life of the seal", loads, "temperature T (°C)")
    x = np.array([celsius(t) for t in temps])
    for ax, n, notes in panels:
        series = [Series(x, q[n, :, j], valid[n, :, j], color(j), "-", f"t = {time_text(float(t))}")
                  for j, t in enumerate(times)] if n < q.shape[0] else []
        ax.set_xlim(x.min() - 0.04 * (x.max() - x.min()), x.max() + 0.04 * (x.max() - x.min()))
        _draw(ax, series, [*notes, *_coincide(series, "time")], _NO_LEAK, limit, gas)
    place_legend(panels[0][0])  # each panel draws the same times: one legend, in the first
    return fig
