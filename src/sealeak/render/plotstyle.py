"""The shared style of every sealeak figure: axes, units, titles, legends and series with validity.

The rules these helpers implement are listed in :mod:`sealeak.render.figures` ("How the figures
read"); the prediction, band, laboratory and simulation figures all use them. Figures are built
without pyplot, so importing sealeak never selects or changes a matplotlib backend.
"""

from __future__ import annotations

import functools
import textwrap
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, ParamSpec, TypeVar

import matplotlib as mpl
import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.axis import Axis
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.legend import Legend
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator, ScalarFormatter

from ..io.leak_units import ML_PER_MIN_PER_M3_PER_S, PA_M3_PER_MBAR_L, celsius

__all__ = ["pressure_axis", "sweep_axis", "new_figure", "subtitle", "place_legend", "finish_axes", "log_axis", "power_unit", "spans_decades",
           "ml_per_min_axis", "say_nothing", "Series", "draw_series", "color", "ML_PER_MIN_PER_M3_PER_S", "laid_out",
           "literal_text", "LITERAL_TEXT", "wrap_phrases",
           "invalid_note", "draw_limit", "limit_line",
           "merge_identical", "series_peaks", "STYLE", "second_leak_axis", "pa_m3_axis", "PA_M3_PER_MBAR_L", "limit_in_axis_unit", "GAS_LEAK_LABEL",
           "gas_conditions_text", "gas_regime_text", "gas_series"]

P = ParamSpec("P")
R = TypeVar("R")

#: Characters of a title line at 9 pt that fit the figure's 6.4 in width.
_TITLE_CHARS = 92

STYLE: Any = {"figure.figsize": (6.4, 4.6), "figure.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
          "axes.titlesize": 10, "legend.fontsize": 8}

#: Values spanning more than this many decades are drawn on a log axis.
_LOG_DECADES = 2.0

_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:olive",
           "tab:cyan", "tab:gray")
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def color(i: int) -> str:
    """The colour of the i-th curve (a case, a variant of a study, a squeeze pressure)."""
    return _COLORS[i % len(_COLORS)]


# ---------------------------------------------------------------------- axes and units
def pressure_axis(p: Any) -> tuple[float, str]:
    """(scale, unit) for showing pressures: kPa, or MPa when the largest exceeds 2 MPa (NaN ignored)."""
    v = np.asarray(p, dtype=float).ravel()
    v = v[np.isfinite(v)]
    return (1e6, "MPa") if v.size and v.max() > 2e6 else (1e3, "kPa")


def spans_decades(values: Any, decades: float = _LOG_DECADES) -> bool:
    """Whether the positive finite ``values`` span more than ``decades`` decades (then draw them on a log axis)."""
    v = np.abs(np.asarray(values, dtype=float).ravel())
    v = v[np.isfinite(v) & (v > 0)]
    return bool(v.size > 1 and v.max() > v.min() * 10.0 ** decades)


def power_unit(values: Any, unit: str) -> tuple[float, str]:
    """(scale, label) of a linear axis: values/scale below 10⁴, the power of ten written in the unit label.

    E.g. leak rates of about 3e-10 m³/s give (1e-12, "10⁻¹² m³/s"): the axis reads 0 … 300.
    Values between 0.01 and 10⁴ keep their unit (scale 1).
    """
    v = np.abs(np.asarray(values, dtype=float).ravel())
    v = v[np.isfinite(v) & (v > 0)]
    if not v.size:
        return 1.0, unit
    e = float(np.log10(v.max()))
    if -2.0 <= e < 4.0:
        return 1.0, unit
    k = int(3 * np.floor(e / 3))
    return 10.0 ** k, f"10{str(k).translate(_SUPERSCRIPT)} {unit}"


def _log_label(v: float, plain: bool, digits: int = 2) -> str:
    """Tick label of a log axis: a plain number (``plain``), else 10ⁿ or m×10ⁿ (text, not mathtext: quick to lay out),
    m to ``digits`` significant digits."""
    if not (np.isfinite(v) and v > 0):
        return ""
    if plain:
        return f"{v:.4g}"
    e = int(np.floor(np.log10(v) + 1e-9))
    m = v / 10.0 ** e
    power = "10" + str(e).translate(_SUPERSCRIPT)
    return power if abs(m - 1.0) < 1e-6 else f"{m:.{digits}g}×{power}"


def log_axis(axis: Axis, lo: float | None = None, hi: float | None = None) -> None:
    """Ticks of a log axis: 1–9 within a decade (1, 2, 3, 5, 7 from 0.4 decades on where the labels are m×10ⁿ, which
    8×10ⁿ, 9×10ⁿ and 10ⁿ⁺¹ would overprint), 1, 2, 5 over a few decades, powers of ten beyond.

    ``lo``, ``hi``: the axis range (default: its current view interval).
    """
    if lo is None or hi is None:
        lo, hi = sorted(axis.get_view_interval())
    if not (lo > 0 and hi > lo and np.isfinite(hi)):
        return
    decades = float(np.log10(hi / lo))
    plain = lo >= 1e-3 and hi < 1e4  # one style per axis: plain numbers where they are all short
    within: Sequence[float] = [float(s) for s in range(1, 10)] if plain or decades < 0.4 else (1.0, 2.0, 3.0, 5.0, 7.0)
    subs: Sequence[float] = within if decades < 1.0 else (1.0, 2.0, 5.0) if decades <= 3.0 else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs, numticks=12))
    # an axis of a small part of a decade is ticked linearly by matplotlib (2.2, 2.25, 2.3 ...): m needs more digits
    # (two gave "2.2×10⁻⁹" twice)
    digits = 2 + max(0, int(np.ceil(np.log10(0.3 / decades)))) if decades < 0.3 else 2
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: _log_label(v, plain, digits)))
    # minor ticks at 2..9 while they can be told apart; beyond six decades they are noise (and slow to draw)
    axis.set_minor_locator(LogLocator(base=10.0, subs=[float(s) for s in range(2, 10)], numticks=12) if decades <= 6.0 else NullLocator())
    axis.set_minor_formatter(NullFormatter())


def _plain_axis(axis: Axis) -> None:
    """A linear axis without offset or multiplier text (its scale belongs in the label, see :func:`power_unit`)."""
    fmt = ScalarFormatter(useOffset=False)
    fmt.set_scientific(False)
    axis.set_major_formatter(fmt)


def sweep_axis(ax: Axes, x: Any, label: str) -> None:
    """Label the x axis and span every x of a sweep (log when they span decades), with a margin of 4 %.

    The axis covers the whole sweep, also the loads with nothing to draw (no leak channel); non-finite
    and non-positive x are left out of the range.
    """
    ax.set_xlabel(label)
    v = np.asarray(x, dtype=float).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    if not v.size:
        return
    lo, hi = float(v.min()), float(v.max())
    if spans_decades(v):
        ax.set_xscale("log")
        pad = (hi / lo) ** 0.04
        ax.set_xlim(lo / pad, hi * pad)
    elif hi > lo:
        ax.set_xlim(lo - 0.04 * (hi - lo), hi + 0.04 * (hi - lo))
    else:
        ax.set_xlim(0.9 * lo, 1.1 * hi)


def finish_axes(ax: Axes) -> None:
    """Tick formats for both axes of ``ax``: :func:`log_axis` on log axes, plain numbers on linear ones."""
    limits = {"x": ax.get_xlim(), "y": ax.get_ylim()}  # settles pending autoscaling
    for name, axis, scale in (("x", ax.xaxis, ax.get_xscale()), ("y", ax.yaxis, ax.get_yscale())):
        if scale == "log":
            log_axis(axis, *sorted(limits[name]))
        elif scale == "linear":
            _plain_axis(axis)


def scale_functions(k: float) -> tuple[Callable[[Any], Any], Callable[[Any], Any]]:
    """(y ↦ k·y, m ↦ m/k): the forward and inverse maps of a second axis that reads the first in a unit k times smaller."""
    def forward(y: Any) -> Any:
        return np.asarray(y) * k

    def inverse(m: Any) -> Any:
        return np.asarray(m) / k
    return forward, inverse


def second_leak_axis(ax: Axes, factor: float, unit: str, quantity: str = "leak rate Q", scale: float = 1.0) -> Any:
    """A right-hand axis that reads the left axis's leak rate times ``factor`` in ``unit``.

    ``ax`` plots the leak rate divided by ``scale`` (from :func:`power_unit`; 1 on a log axis) in
    its own unit; ``factor`` converts that unit into ``unit``. A linear second axis carries its power
    of ten in the label. Call it once the y limits are final.
    """
    lo, hi = ax.get_ylim()
    if ax.get_yscale() == "log":
        k = factor
        sec = ax.secondary_yaxis("right", functions=scale_functions(k))
        sec.set_ylabel(f"{quantity} ({unit})")
        log_axis(sec.yaxis, lo * k, hi * k)
    else:
        mscale, munit = power_unit([hi * scale * factor], unit)
        k = scale * factor / mscale
        sec = ax.secondary_yaxis("right", functions=scale_functions(k))
        sec.set_ylabel(f"{quantity} ({munit})")
        _plain_axis(sec.yaxis)
    return sec


def ml_per_min_axis(ax: Axes, scale: float = 1.0) -> Any:
    """A right-hand axis that reads the leak rate in ml/min.

    ``ax`` plots Q/``scale`` in m³/s (``scale`` from :func:`power_unit`; 1 on a log axis). Call it
    once the y limits are final.
    """
    return second_leak_axis(ax, ML_PER_MIN_PER_M3_PER_S, "ml/min", scale=scale)


def pa_m3_axis(ax: Axes, scale: float = 1.0) -> Any:
    """A right-hand axis that reads a pV throughput plotted in mbar·l/s (divided by ``scale``) in Pa·m³/s.

    1 mbar·l/s = 100 Pa × 10⁻³ m³/s = 0.1 Pa·m³/s (docs/theory.md §11.6).
    """
    return second_leak_axis(ax, PA_M3_PER_MBAR_L, "Pa·m³/s", quantity="pV throughput Q_pV", scale=scale)


# ---------------------------------------------------------------------- gas cases (docs/theory.md §11.9)
#: The y label of a gas leak rate: the pV throughput in the leak-test unit.
GAS_LEAK_LABEL = "gas leak rate Q_pV"


def _pressure_text(p: float) -> str:
    """An absolute pressure for a figure title: "1 bar", "250 mbar", "0 Pa (vacuum)"."""
    if p == 0:
        return "0 (vacuum)"
    if p >= 1e4:
        return f"{p / 1e5:.4g} bar"
    if p >= 1.0:
        return f"{p / 1e2:.4g} mbar"
    return f"{p:.3g} Pa"


def gas_conditions_text(case: Any) -> str:
    """The gas line of a gas figure's title: gas, T, P_a, P_b (absolute) and the rarefaction model.

    ``case`` is a :class:`~sealeak.cases.Case` with ``case.gas`` set (a gas case, docs/theory.md §11.9).
    """
    gas = case.gas
    return (f"{gas.gas.name}, T = {celsius(gas.temperature):.4g} °C, absolute P_a = {_pressure_text(gas.upstream_pressure)}, "
            f"P_b = {_pressure_text(gas.downstream_pressure)}; rarefaction {gas.rarefaction}")


def gas_regime_text(rows: Sequence[Any], gap: str = "h the narrowest gap") -> str:
    """Where the Knudsen numbers of the drawn rows lie, and their flow regimes (a subtitle line).

    ``rows``: :class:`~sealeak.cases.GasRows` of the drawn theories; Kn = λ/h at the mean pressure
    (P_a + P_b)/2 and the narrowest gap h (docs/theory.md §11.9), which ``gap`` names. Empty when nothing leaks.
    """
    kn, regimes = [], []
    for r in rows:
        for leak in r.leaks or ():
            if leak is not None and np.isfinite(leak.knudsen_mean):
                kn.append(leak.knudsen_mean)
                if leak.regime not in regimes:
                    regimes.append(leak.regime)
    if not kn:
        return ""
    lo, hi = min(kn), max(kn)
    span = f"{lo:.2g}" if hi <= lo * 1.005 else f"{lo:.2g} to {hi:.2g}"
    return f"Kn = λ/h = {span} ({', '.join(regimes)}), λ at the mean pressure, {gap}"


def gas_series(x: np.ndarray, rows: Any, valid: np.ndarray, why: tuple[str, ...], colour: str, label: str,
               helium: bool = True) -> list[Series]:
    """The gas leak (solid) and, when computed and not the same numbers, its helium equivalent (dashed), in mbar·l/s.

    ``rows``: a :class:`~sealeak.cases.GasRows` (the record fields ``leak_rate_mbar_l_s`` and
    ``leak_rate_helium_mbar_l_s``, docs/theory.md §11.9); rows without a leak channel are NaN.
    """
    fields = rows.fields()
    out = []
    q = np.asarray(fields.get("leak_rate_mbar_l_s", np.full(len(x), np.nan)), dtype=float)
    if rows.leaks is not None:
        out.append(Series(x, q, np.asarray(valid, dtype=bool), colour, "-", label, why))
    he = fields.get("leak_rate_helium_mbar_l_s")
    if helium and he is not None:
        he = np.asarray(he, dtype=float)
        same = rows.leaks is not None and np.allclose(he, q, rtol=1e-9, equal_nan=True)
        if not same:
            out.append(Series(x, he, np.asarray(valid, dtype=bool), colour, "--",
                              f"{label}: helium equivalent" if label else "helium equivalent", why))
    return out


# ---------------------------------------------------------------------- figure, title, message, legend
def new_figure(title: str, figsize: tuple[float, float] | None = None) -> tuple[Figure, Axes]:
    """A figure with one axes in the project's style; ``title`` is the heading, :func:`subtitle` adds lines.

    The figure uses matplotlib's constrained layout, so labels, a second axis and a legend below the
    axes all fit inside it.
    """
    with mpl.rc_context(STYLE):
        fig = Figure(figsize=figsize, layout="constrained") if figsize else Figure(layout="constrained")
        ax = fig.add_subplot()
    ax._sealeak_heading = title  # type: ignore[attr-defined]
    subtitle(ax, "")
    return fig, ax


#: Every text of a sealeak figure is drawn as written: user text (titles, labels, study labels, file names) may
#: hold '$' ("$\\foo$", "h_rms $h_{rms$"), which matplotlib's mathtext would parse (and fail on, or change).
#: No figure of the project uses mathtext (units are written with Unicode: m³/s, µm, ΔP).
LITERAL_TEXT: Any = {"text.parse_math": False}


def literal_text(make: Callable[P, R]) -> Callable[P, R]:
    """Decorate a function that makes figures: every text it creates is literal (:data:`LITERAL_TEXT`, no mathtext).

    matplotlib fixes a text's ``parse_math`` when the text is created, so the figure's titles, labels,
    legends and tick labels set by the function are literal whenever and wherever it is drawn (PNG,
    report, web). :func:`laid_out` includes this; the other figure functions are decorated with it.
    """
    @functools.wraps(make)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        with mpl.rc_context(LITERAL_TEXT):
            return make(*args, **kwargs)
    return wrapper


def laid_out(make: Callable[P, Figure]) -> Callable[P, Figure]:
    """Decorate a figure function: lay the finished figure out once (constrained layout), then keep that layout.

    Constrained layout fits labels, a second axis and a legend below the axes inside the figure, but
    it costs two extra layout passes on every draw; the figures are finished when their function
    returns, so the layout is computed once and frozen (later draws and savefig reuse it). Its texts are
    literal (:func:`literal_text`).
    """
    @functools.wraps(make)
    @literal_text
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> Figure:
        fig = make(*args, **kwargs)
        engine = fig.get_layout_engine()
        if engine is not None and not isinstance(engine, PlaceHolderLayoutEngine):
            _lay_out(engine, fig)
            fig.set_layout_engine("none")
        return fig
    return wrapper


def _lay_out(engine: Any, fig: Figure) -> None:
    """Run the figure's layout engine. Where labels are too long to fit (an absurd input's 100-digit ticks) the
    figure keeps matplotlib's own layout, and the engine's warning stays off the user's stderr."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="constrained_layout not applied", category=UserWarning)
        engine.execute(fig)


def subtitle(ax: Axes, text: str) -> None:
    """Set the axes title to its heading plus ``text`` on the lines below (long lines wrapped to the figure's width,
    at phrase boundaries: :func:`wrap_phrases`)."""
    heading = getattr(ax, "_sealeak_heading", "")
    lines = [w for line in text.splitlines() for w in (wrap_phrases(line, _TITLE_CHARS) or [""])] if text else []
    ax.set_title("\n".join([heading, *lines]), fontsize=9)


def _phrases(line: str) -> list[str]:
    """``line`` cut after each ", " and "; " outside brackets, the separators kept with the phrase before them."""
    out, start, depth = [], 0, 0
    for i, ch in enumerate(line):
        depth += (ch in "([{") - (ch in ")]}")
        if ch in ",;" and depth <= 0 and line[i + 1:i + 2] == " ":
            out.append(line[start:i + 2])
            start = i + 2
    return out + [line[start:]] if line[start:] else out


def wrap_phrases(line: str, width: int) -> list[str]:
    """``line`` wrapped to ``width`` characters between phrases (after ", " or "; " outside brackets); a phrase
    longer than a line is wrapped between words. Never breaks "η = 19.6 µPa·s" or "(free molecular)" apart."""
    lines: list[str] = []
    current = ""
    for phrase in _phrases(line):
        if current and len(current + phrase.rstrip()) > width:
            lines.append(current.rstrip())
            current = ""
        if len(phrase.rstrip()) > width:
            *full, current = textwrap.wrap(phrase, width, break_on_hyphens=False) or [""]
            lines += full
            current += " "
        else:
            current += phrase
    return lines + [current.rstrip()] if current.strip() else lines


def say_nothing(ax: Axes, text: str) -> None:
    """Write on the axes why the figure has nothing to draw, and drop the meaningless y ticks."""
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=10, color="0.2",
            bbox={"boxstyle": "round,pad=0.6", "fc": "white", "ec": "0.6"})
    ax.set_yticks([])
    ax.grid(False, axis="y")


_INSIDE = ("upper right", "upper left", "lower left", "lower right", "center right", "center left", "upper center",
           "lower center", "center")


def _drawn_points(ax: Axes) -> np.ndarray:
    """Display coordinates of what the axes draw: line vertices and points every ~2 px along the segments."""
    out = [np.zeros((0, 2))]
    box = ax.bbox
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if xy.size == 0:
            continue
        d = line.get_transform().transform(xy)
        good = np.isfinite(d).all(axis=1)
        out.append(d[good])
        if line.get_linestyle() not in ("None", "none", "", " ") and len(d) > 1:
            a, b = d[:-1], d[1:]
            seg = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1)
            a, b = a[seg], b[seg]
            n = np.clip(np.ceil(np.hypot(*(b - a).T) / 2.0).astype(int), 1, 2000)
            t = np.concatenate([np.arange(k) / k for k in n]) if n.size else np.zeros(0)
            i = np.repeat(np.arange(len(a)), n)
            out.append(a[i] + (b[i] - a[i]) * t[:, None])
    for coll in ax.collections:
        offsets = np.asarray(coll.get_offsets())
        if len(offsets):
            out.append(coll.get_offset_transform().transform(offsets))
    pts = np.concatenate(out)
    keep = (pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)
    return pts[keep]


def _drawn_areas(ax: Axes) -> list[Any]:
    """The outlines, in display coordinates, of the filled areas the axes draw (bands: ``fill_between``)."""
    return [path.transformed(coll.get_transform()) for coll in ax.collections
            if isinstance(coll, PolyCollection) and coll.get_visible() for path in coll.get_paths()]


def _covers(leg: Legend, points: np.ndarray, texts: Sequence[Any], pad: float = 4.0, areas: Sequence[Any] = ()) -> bool:
    """Whether a legend inside the axes covers a data point, a filled area or a text, or is wider or taller than the
    axes (then it would cover the tick labels beside them)."""
    box = leg.get_window_extent().padded(pad)
    outer = leg.axes.bbox
    if box.width > outer.width + 2 * pad or box.height > outer.height + 2 * pad:
        return True
    inside = ((points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1))
    return (bool(inside.any()) or any(box.overlaps(t) for t in texts)
            or any(area.intersects_bbox(box, filled=True) for area in areas))


def merge_identical(curves: Sequence[Sequence[Any]], names: Sequence[str]) -> list[tuple[int, list[str]]]:
    """Each distinct curve once: (index of its first occurrence, the names of all its occurrences, in order, empty ones
    and repeats left out). ``curves``: per curve its arrays and numbers, compared element by element (NaN equal to
    NaN). Variants with one contact (a study of fluids) have the same curves, and drawn one over another only the last
    shows while the legend lists every colour."""
    out: list[tuple[int, list[str]]] = []
    for i, (curve, name) in enumerate(zip(curves, names, strict=True)):
        same = next((g for g in out if all(np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float), equal_nan=True)
                                           for a, b in zip(curves[g[0]], curve, strict=True))), None)
        if same is None:
            out.append((i, [name] if name else []))
        elif name and name not in same[1]:
            same[1].append(name)
    return out


#: Decades a log leak-rate axis is widened upwards, at most, to show ``conditions.max_leak_rate`` (:func:`draw_limit`).
LIMIT_DECADES = 3.0


def limit_in_axis_unit(limit: tuple[float, str] | None, gas: bool) -> tuple[float, str] | None:
    """``conditions.max_leak_rate`` as :func:`~sealeak.render.life.volume_limit` gives it (m³/s, a gas's Pa·m³/s: for a
    gas it gives only a limit compared with Q_pV; and as written) in the unit of a leak-rate figure's axis: m³/s, or
    mbar·l/s for a gas."""
    if limit is None or not gas:
        return limit
    return limit[0] / PA_M3_PER_MBAR_L, limit[1]


def draw_limit(ax: Axes, limit: tuple[float, str] | None, scale: float = 1.0) -> str:
    """``conditions.max_leak_rate`` (``limit``: its value in the axis' unit times ``scale``, and as written) as a
    dash-dotted line across a leak-rate figure, as the figures of the seal over its life draw it. A limit above the
    axis widens a log axis by up to :data:`LIMIT_DECADES`; one farther above, or one below the axis (whose foot may
    hold markers of points below it), is not drawn: the returned subtitle note says where it lies ("" otherwise)."""
    if limit is None:
        return ""
    y = limit[0] / scale
    lo, hi = ax.get_ylim()
    if y > hi and ax.get_yscale() == "log" and np.log10(y / hi) <= LIMIT_DECADES:
        hi = y * 10 ** 0.15
        ax.set_ylim(lo, hi)
    if not lo <= y <= hi:
        return (f"max_leak_rate = {limit[1]} lies {'above every leak rate drawn' if y > hi else 'below the axis'}"
                + ("" if y > hi else ": every leak rate drawn exceeds it"))
    limit_line(ax, y, limit[1])
    return ""


def limit_line(ax: Axes, y: float, text: str, color: str = "0.2") -> None:
    """``conditions.max_leak_rate`` at ``y`` (the axis' unit) as a dash-dotted line labelled with ``text`` (as written)."""
    ax.axhline(y, color=color, linestyle="-.", linewidth=1.2, label=f"max_leak_rate = {text}")


def place_legend(ax: Axes, handles: Sequence[Artist] | None = None, labels: Sequence[str] | None = None,
                 **kwargs: Any) -> Legend | None:
    """A legend inside the axes where it covers no data (points, lines, filled bands), else below the axes (as wide as
    the figure allows).

    Call it last, once everything is drawn and the limits are final: it lays the figure out to see
    where the data are (and, with the legend inside, keeps that layout; see :func:`laid_out`).
    """
    if handles is None or labels is None:
        handles, labels = ax.get_legend_handles_labels()
    handles, labels = list(handles), list(labels)
    if not handles:
        return None
    fig = ax.get_figure()
    assert isinstance(fig, Figure)
    ax.get_xlim(), ax.get_ylim()  # settle the autoscaled limits
    engine = fig.get_layout_engine()
    if engine is not None:
        _lay_out(engine, fig)  # lay out (not a full draw): the data's display positions are final from here
    points = _drawn_points(ax)
    texts = [t.get_window_extent() for t in ax.texts if t.get_visible() and t.get_text()]
    areas = _drawn_areas(ax)
    for loc in _INSIDE:
        leg = ax.legend(handles, labels, loc=loc, **kwargs)  # type: ignore[call-overload]  # the stubs reject **kwargs here
        if not _covers(leg, points, texts, areas=areas):
            if engine is not None:
                fig.set_layout_engine("none")  # a legend inside the axes leaves the layout as it is: keep it
            return leg
        leg.remove()
    kwargs.pop("ncol", None)
    for ncol in (3, 2, 1):
        leg = fig.legend(handles, labels, loc="outside lower center", ncol=min(ncol, len(handles)), **kwargs)
        if ncol == 1 or leg.get_window_extent().width <= 0.98 * fig.bbox.width:
            break
        leg.remove()
    # the figure grows by the legend's height beyond a fifth of it, so that a long legend below does not squeeze the axes
    extra = leg.get_window_extent().height / fig.dpi - 0.2 * fig.get_figheight()
    if extra > 0:
        fig.set_figheight(fig.get_figheight() + extra)
    return leg


# ---------------------------------------------------------------------- series with validity
@dataclass(frozen=True)
class Series:
    """One curve: x, y and a per-point validity verdict (False: drawn hollow, not joined, not scaling the axis)."""

    x: np.ndarray
    y: np.ndarray
    valid: np.ndarray
    color: str
    style: str = "-"
    label: str | None = None
    why: tuple[str, ...] = ()


def _invalid_label(reasons: Sequence[str]) -> str:
    """Legend text of the hollow markers, from the verdicts' reasons (docs/theory.md §9.11)."""
    kinds = []
    # ΔP against the contact pressure comes first in a reason; a gap's verdict may follow it ("...; also u_c ...")
    if any(r.startswith("ΔP") and "lift-off" in r for r in reasons):
        kinds.append("ΔP ≥ lift-off (its limit)")
    if any(r.startswith("ΔP") and "not small" in r for r in reasons):
        kinds.append("ΔP not small against p: outside the theory")
    rest = [r.split("; also ", 1)[1] if "; also " in r else "" if r.startswith("ΔP") else r for r in reasons]
    if any("molecular" in r for r in rest):
        gaps = dict.fromkeys(r.split(" ", 1)[0] for r in rest if "molecular" in r)  # u_c, u_e: each theory's gap
        kinds.append(f"{', '.join(gaps)} below molecular size: outside the continuum theory")
    if any(r and "molecular" not in r for r in rest):
        kinds.append("not a thin film: outside the theory")
    return "; ".join(kinds) or "outside the theory's validity"


#: The marker of a few points' series by its line style (:func:`draw_series`).
_MARKERS = {"-": "o", "--": "s", ":": "D", "-.": "^"}


def draw_series(ax: Axes, series: Sequence[Series], logy: bool = False, logx: bool = False,
                bottom_zero: bool = False) -> bool:
    """Draw the valid points of each series as a curve and the invalid ones hollow; True if anything was drawn.

    Valid points alone set the y limits (when there are any); invalid points near or beyond a limit
    get a narrow band beyond it, where those beyond are hollow triangles. Non-finite points (no leak
    channel) are left out, and on a log axis so are non-positive valid ones (an invalid zero, e.g.
    u_c = 0 at the end of the resolved band, is a triangle in the lower band). ``bottom_zero``: a
    linear axis from 0.
    """
    if logy:
        ax.set_yscale("log")
    if logx:
        ax.set_xscale("log")
    drawn, pending, reasons = False, [], []
    for s in series:
        x, y = np.asarray(s.x, dtype=float), np.asarray(s.y, dtype=float)
        finite = np.isfinite(x) & np.isfinite(y)
        if logx:
            finite &= x > 0
        # on a log axis a valid Q = 0 has no place; an invalid one (e.g. u_c = 0) goes below the axis
        ok, bad = finite & s.valid & ((y > 0) if logy else True), finite & ~s.valid
        # few points get markers, of a shape per line style: a dashed series (a helium equivalent) stays told apart
        # where its points stand alone (one load per curve, as a life case's)
        marker = _MARKERS.get(s.style, "o") if x.size <= 12 else ""
        if ok.any():
            ax.plot(x, np.where(ok, y, np.nan), s.style, marker=marker, ms=3, color=s.color, label=s.label)
            drawn = True
        elif s.label and bad.any():
            ax.plot([], [], s.style, color=s.color, label=s.label)
        if bad.any():
            pending.append((x[bad], y[bad], s.color))
            reasons += [r for r, b in zip(s.why, bad) if b] if len(s.why) == len(bad) else []
    if drawn and bottom_zero:
        ax.set_ylim(bottom=0)
    if not pending:
        return drawn
    hollow: dict[str, Any] = {"ls": "none", "mfc": "none", "ms": 4.5, "mew": 1.0}
    if not drawn:  # nothing valid: the invalid points are all there is, at their values
        pending = [(x[y > 0], y[y > 0], c) for x, y, c in pending] if logy else pending
        if not any(y.size for _, y, _ in pending):
            return False
        for x, y, c in pending:
            ax.plot(x, y, "o", mec=c, **hollow)
    else:
        ax.autoscale_view()
        lo, hi = ax.get_ylim()  # the valid points set the scale
        if logy:  # a non-positive invalid point lies below any log axis: in the lower band
            pending = [(x, np.where(y > 0, y, 1e-3 * lo), c) for x, y, c in pending]
        fwd, inv = (np.log10, lambda v: 10.0 ** v) if logy else (lambda v: v, lambda v: v)
        span = fwd(hi) - fwd(lo)
        ys = np.concatenate([y for _, y, _ in pending])
        # a band beyond each limit that has invalid points near or beyond it, for markers that stay whole
        low = bool((fwd(ys) < fwd(lo) + 0.03 * span).any())
        high = bool((fwd(ys) > fwd(hi) - 0.03 * span).any())
        band = 0.07 * span
        ax.set_ylim(inv(fwd(lo) - band) if low else lo, inv(fwd(hi) + band) if high else hi)
        for x, y, c in pending:
            inside = (y >= lo) & (y <= hi)
            ax.plot(x[inside], y[inside], "o", mec=c, **hollow)
            for sel, at, marker in ((y < lo, fwd(lo) - band / 2, "v"), (y > hi, fwd(hi) + band / 2, "^")):
                if sel.any():
                    ax.plot(x[sel], np.full(int(sel.sum()), inv(at)), marker, mec=c, **hollow)
    ax.plot([], [], "o", mec="0.35", label=_invalid_label(reasons), **hollow)
    return True


def invalid_note(series: Sequence[Series]) -> str:
    """A subtitle line explaining hollow markers, when a figure has any."""
    if not any((~np.asarray(s.valid)).any() for s in series):
        return ""
    return "hollow markers: outside the theory's validity (▽/△ in the band at an edge: beyond the axis)"


def series_peaks(series: Sequence[Series]) -> list[float]:
    """The largest valid positive value of each series that has one (what a linear axis must show)."""
    peaks = []
    for s in series:
        y = np.asarray(s.y, dtype=float)
        ok = np.isfinite(y) & (y > 0) & s.valid
        if ok.any():
            peaks.append(float(y[ok].max()))
    return peaks
