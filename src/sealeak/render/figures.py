"""Figures of a prediction (matplotlib, PNG).

One function per figure; each takes case results (:class:`~sealeak.cases.CaseResult`) and the
curves computed for them (:func:`~sealeak.cases.prediction_curves`) and returns a matplotlib
:class:`~matplotlib.figure.Figure`; nothing here computes physics. Figures are built without
pyplot, so importing sealeak never selects or changes a matplotlib backend (a notebook keeps its
own). :func:`prediction_figures` returns them all by file name; :func:`save_figures` renders them
all, then writes them atomically.
Every axis is labelled with its unit. The reference paper's theory figures are: C(q) (its Fig. 4),
Q against P0 on a linear and a log10 scale (Figs. 6, 7), the critical pore size against P0 (Fig. 8)
and ζc against P0 (Fig. 9); Q against ΔP (Fig. 5) and A(ζ), ū(ζ), u1(ζ) complete the set.

How the figures read (the same rules for the laboratory figures, :mod:`sealeak.render.lab_figures`):

* an axis whose values span more than two decades is logarithmic, with a labelled tick at least
  every few decades (1, 2, 5 within a decade or two); a linear axis carries its power of ten in
  the unit label ("leak rate Q (10⁻¹² m³/s)"), never as a floating offset;
* leak rates have a second axis in ml/min (the unit of the command-line table);
* points outside the theory's validity (:attr:`~sealeak.cases.CaseResult.valid`, docs/theory.md
  §9.11: u_c below the fluid's molecular size, or not a thin film) are drawn hollow, not joined to
  the curve, and do not set the axis limits; one beyond the limits is a hollow triangle at that edge;
* a legend sits inside the axes only where it covers no data, otherwise below the axes;
* a figure with nothing to draw says so on the figure (e.g. no leak channel at any pressure).
"""

from __future__ import annotations

import functools
import io
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ParamSpec

import matplotlib as mpl
import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.legend import Legend
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator, ScalarFormatter

from ..cases import Case, CaseResult, CurveSet, PredictionCurves, prediction_curves
from ..io.files import atomic_write
from ..io.units import length_unit
from ..physics.validity import pressures_text

__all__ = ["prediction_figures", "save_figures", "render_figures", "pressure_axis", "PREDICTION_FIGURE_NAMES",
           "new_figure", "subtitle", "place_legend", "finish_axes", "log_axis", "power_unit", "spans_decades",
           "ml_per_min_axis", "say_nothing", "Series", "draw_series", "color", "ML_PER_MIN_PER_M3_PER_S", "pressure_x",
           "figure_png", "laid_out"]

P = ParamSpec("P")

#: Characters of a title line at 9 pt that fit the figure's 6.4 in width.
_TITLE_CHARS = 92

_STYLE = {"figure.figsize": (6.4, 4.6), "figure.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
          "axes.titlesize": 10, "legend.fontsize": 8}

#: ml/min per m³/s (the command-line table's second leak-rate unit).
ML_PER_MIN_PER_M3_PER_S = 6e7

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


def _log_label(v: float, plain: bool) -> str:
    """Tick label of a log axis: a plain number (``plain``), else 10ⁿ or m×10ⁿ (text, not mathtext: quick to lay out)."""
    if not (np.isfinite(v) and v > 0):
        return ""
    if plain:
        return f"{v:.4g}"
    e = int(np.floor(np.log10(v) + 1e-9))
    m = v / 10.0 ** e
    power = "10" + str(e).translate(_SUPERSCRIPT)
    return power if abs(m - 1.0) < 1e-6 else f"{m:.2g}×{power}"


def log_axis(axis: Axis, lo: float | None = None, hi: float | None = None) -> None:
    """Ticks of a log axis: 1–9 within a decade, 1, 2, 5 over a few decades, powers of ten beyond.

    ``lo``, ``hi``: the axis range (default: its current view interval).
    """
    if lo is None or hi is None:
        lo, hi = sorted(axis.get_view_interval())
    if not (lo > 0 and hi > lo and np.isfinite(hi)):
        return
    decades = float(np.log10(hi / lo))
    subs: Sequence[float] = np.arange(1.0, 10.0) if decades < 1.0 else (1.0, 2.0, 5.0) if decades <= 3.0 else (1.0,)
    axis.set_major_locator(LogLocator(base=10.0, subs=subs, numticks=12))
    plain = lo >= 1e-3 and hi < 1e4  # one style per axis: plain numbers where they are all short
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: _log_label(v, plain)))
    # minor ticks at 2..9 while they can be told apart; beyond six decades they are noise (and slow to draw)
    axis.set_minor_locator(LogLocator(base=10.0, subs=np.arange(2.0, 10.0), numticks=12) if decades <= 6.0 else NullLocator())
    axis.set_minor_formatter(NullFormatter())


def _plain_axis(axis: Axis) -> None:
    """A linear axis without offset or multiplier text (its scale belongs in the label, see :func:`power_unit`)."""
    fmt = ScalarFormatter(useOffset=False)
    fmt.set_scientific(False)
    axis.set_major_formatter(fmt)


def finish_axes(ax: Axes) -> None:
    """Tick formats for both axes of ``ax``: :func:`log_axis` on log axes, plain numbers on linear ones."""
    limits = {"x": ax.get_xlim(), "y": ax.get_ylim()}  # settles pending autoscaling
    for name, axis, scale in (("x", ax.xaxis, ax.get_xscale()), ("y", ax.yaxis, ax.get_yscale())):
        if scale == "log":
            log_axis(axis, *sorted(limits[name]))
        elif scale == "linear":
            _plain_axis(axis)


def ml_per_min_axis(ax: Axes, scale: float = 1.0) -> Any:
    """A right-hand axis that reads the leak rate in ml/min.

    ``ax`` plots Q/``scale`` in m³/s (``scale`` from :func:`power_unit`; 1 on a log axis). Call it
    once the y limits are final.
    """
    lo, hi = ax.get_ylim()
    if ax.get_yscale() == "log":
        k = ML_PER_MIN_PER_M3_PER_S
        sec = ax.secondary_yaxis("right", functions=(lambda y: y * k, lambda m: m / k))
        sec.set_ylabel("leak rate Q (ml/min)")
        log_axis(sec.yaxis, lo * k, hi * k)
    else:
        mscale, munit = power_unit([hi * scale * ML_PER_MIN_PER_M3_PER_S], "ml/min")
        k = scale * ML_PER_MIN_PER_M3_PER_S / mscale
        sec = ax.secondary_yaxis("right", functions=(lambda y: y * k, lambda m: m / k))
        sec.set_ylabel(f"leak rate Q ({munit})")
        _plain_axis(sec.yaxis)
    return sec


# ---------------------------------------------------------------------- figure, title, message, legend
def new_figure(title: str, figsize: tuple[float, float] | None = None) -> tuple[Figure, Axes]:
    """A figure with one axes in the project's style; ``title`` is the heading, :func:`subtitle` adds lines.

    The figure uses matplotlib's constrained layout, so labels, a second axis and a legend below the
    axes all fit inside it.
    """
    with mpl.rc_context(_STYLE):
        fig = Figure(figsize=figsize, layout="constrained") if figsize else Figure(layout="constrained")
        ax = fig.add_subplot()
    ax._sealeak_heading = title  # type: ignore[attr-defined]
    subtitle(ax, "")
    return fig, ax


def laid_out(make: Callable[P, Figure]) -> Callable[P, Figure]:
    """Decorate a figure function: lay the finished figure out once (constrained layout), then keep that layout.

    Constrained layout fits labels, a second axis and a legend below the axes inside the figure, but
    it costs two extra layout passes on every draw; the figures are finished when their function
    returns, so the layout is computed once and frozen (later draws and savefig reuse it).
    """
    @functools.wraps(make)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> Figure:
        fig = make(*args, **kwargs)
        engine = fig.get_layout_engine()
        if engine is not None and not isinstance(engine, PlaceHolderLayoutEngine):
            engine.execute(fig)
            fig.set_layout_engine("none")
        return fig
    return wrapper


def subtitle(ax: Axes, text: str) -> None:
    """Set the axes title to its heading plus ``text`` on the lines below (long lines wrapped to the figure's width)."""
    heading = getattr(ax, "_sealeak_heading", "")
    lines = [w for line in text.splitlines() for w in (textwrap.wrap(line, _TITLE_CHARS) or [""])] if text else []
    ax.set_title("\n".join([heading, *lines]), fontsize=9)


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
        offsets = coll.get_offsets()
        if len(offsets):
            out.append(coll.get_offset_transform().transform(offsets))
    pts = np.concatenate(out)
    keep = (pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)
    return pts[keep]


def _covers(leg: Legend, points: np.ndarray, texts: Sequence[Any], pad: float = 4.0) -> bool:
    box = leg.get_window_extent().padded(pad)
    inside = ((points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1))
    return bool(inside.any()) or any(box.overlaps(t) for t in texts)


def place_legend(ax: Axes, handles: Sequence[Artist] | None = None, labels: Sequence[str] | None = None,
                 **kwargs: Any) -> Legend | None:
    """A legend inside the axes where it covers no data, else below the axes (as wide as the figure allows).

    Call it last, once everything is drawn and the limits are final: it lays the figure out to see
    where the data are (and, with the legend inside, keeps that layout; see :func:`laid_out`).
    """
    if handles is None or labels is None:
        handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    fig = ax.get_figure()
    assert isinstance(fig, Figure)
    ax.get_xlim(), ax.get_ylim()  # settle the autoscaled limits
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)  # lay out (not a full draw): the data's display positions are final from here
    points = _drawn_points(ax)
    texts = [t.get_window_extent() for t in ax.texts if t.get_visible() and t.get_text()]
    for loc in _INSIDE:
        leg = ax.legend(handles, labels, loc=loc, **kwargs)
        if not _covers(leg, points, texts):
            if engine is not None:
                fig.set_layout_engine("none")  # a legend inside the axes leaves the layout as it is: keep it
            return leg
        leg.remove()
    kwargs.pop("ncol", None)
    leg = None
    for ncol in (3, 2, 1):
        leg = fig.legend(handles, labels, loc="outside lower center", ncol=min(ncol, len(handles)), **kwargs)
        if ncol == 1 or leg.get_window_extent().width <= 0.98 * fig.bbox.width:
            break
        leg.remove()
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
    if any("molecular" in r for r in reasons):
        gap = next((r.split(" ", 1)[0] for r in reasons if "molecular" in r), "u_c")
        kinds.append(f"{gap} below molecular size: outside the continuum theory")
    if any(r and "molecular" not in r for r in reasons):
        kinds.append("not a thin film: outside the theory")
    return "; ".join(kinds) or "outside the theory's validity"


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
        marker = "o" if x.size <= 12 else ""
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


def _invalid_note(series: Sequence[Series]) -> str:
    """A subtitle line explaining hollow markers, when a figure has any."""
    if not any((~np.asarray(s.valid)).any() for s in series):
        return ""
    return "hollow markers: outside the theory's validity (▽/△ in the band at an edge: beyond the axis)"


# ---------------------------------------------------------------------- the prediction figures
def _set_label(cs: CurveSet, curves: PredictionCurves) -> str:
    """Legend label of a curve set: its squeeze pressure (and, in a study, the variant's name)."""
    scale, unit = pressure_axis(cs.case.squeeze_pressure)
    label = f"P0 = {cs.squeeze_pressure / scale:.3g} {unit}"
    return f"{cs.case.label}, {label}" if len(curves.spectra) > 1 else label


def _label(case: Case, fallback: str = "") -> str:
    return case.label or fallback


def pressure_x(ax: Axes, p0: np.ndarray) -> float:
    """Label the x axis with the squeeze pressure and span the whole sweep (log when it spans decades); returns the scale.

    The axis covers every pressure of the sweep, also those with nothing to draw (no leak channel).
    """
    scale, unit = pressure_axis(p0)
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    p = np.asarray(p0, dtype=float)
    p = p[np.isfinite(p) & (p > 0)] / scale
    if not p.size:
        return scale
    lo, hi = float(p.min()), float(p.max())
    if spans_decades(p):
        ax.set_xscale("log")
        pad = (hi / lo) ** 0.04
        ax.set_xlim(lo / pad, hi * pad)
    elif hi > lo:
        ax.set_xlim(lo - 0.04 * (hi - lo), hi + 0.04 * (hi - lo))
    else:
        ax.set_xlim(0.9 * lo, 1.1 * hi)
    return scale


@laid_out
def figure_spectrum(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """C(q) against q, log-log, with q0 and the spectrum's nodes."""
    fig, ax = new_figure("Surface roughness power spectrum")
    for i, (case, (q, c)) in enumerate(zip(cases, curves.spectra)):
        keep = np.isfinite(q) & np.isfinite(c) & (q > 0) & (c > 0)
        ax.loglog(q[keep], c[keep], color=color(i), label=_label(case, case.spectrum.label or "C(q)"))
    case = cases[0]
    ax.axvline(case.q0, color="0.5", ls=":", lw=1)
    ax.annotate("q0 = 2π/L", (case.q0, 0.03), xycoords=ax.get_xaxis_transform(), rotation=90, va="bottom", ha="right",
                fontsize=8, color="0.4")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    stats = (f"h_rms = {case.spectrum.h_rms * 1e6:.3g} µm, slope_rms = {case.spectrum.slope_rms:.3g}, "
             f"A_true/A0 = {case.spectrum.area_ratio:.3g}") if len(cases) == 1 else ""
    subtitle(ax, (case.spectrum_note + ("\n" + stats if stats else "")) if len(cases) == 1 else "")
    finish_axes(ax)
    if len(cases) > 1 or case.spectrum.label:
        place_legend(ax)
    return fig


@laid_out
def figure_contact_area(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """A(ζ)/A0 against ζ for a few squeeze pressures, with the percolation level 1 - p_c."""
    fig, ax = new_figure("Apparent relative contact area against magnification")
    for i, cs in enumerate(curves.sets):
        ax.semilogx(cs.zeta, cs.area, color=color(i), label=_set_label(cs, curves))
        if cs.percolates:
            ax.plot([cs.zeta_c], [1 - cs.case.percolation_threshold], "o", color=color(i), ms=4)
    pc = cases[0].percolation_threshold
    ax.axhline(1 - pc, color="k", ls="--", lw=0.8, label=f"percolation: A/A0 = 1 - p_c = {1 - pc:.2f}")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("relative contact area A(ζ)/A0 (1)")
    ax.set_ylim(0, 1.02)
    closed = [cs for cs in curves.sets if not cs.percolates]
    subtitle(ax, "dots: critical magnification ζc" + (
        "\nno dot: A(ζ) stays above 1 - p_c up to the cut-off, no leak channel" if closed else ""))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_separation(cases: Sequence[Case], curves: PredictionCurves) -> Figure:
    """ū(ζ) (solid) and u1(ζ) (dashed) against ζ for the same squeeze pressures."""
    fig, ax = new_figure("Interfacial separation against magnification")
    top, bottom = 0.0, np.inf
    closed = [cs for cs in curves.sets if cs.in_full_contact]
    hollow = False
    for i, cs in enumerate(curves.sets):
        if cs.in_full_contact:
            continue
        label, z, ubar, u1 = _set_label(cs, curves), cs.zeta[:-1], cs.mean_gap, cs.u1
        top = max(top, 3.0 * ubar[0])
        bottom = min(bottom, 1e-3 * ubar[0])
        shown = ubar > 1e-6 * ubar[0]
        ax.loglog(z[shown], ubar[shown] * 1e6, color=color(i), label=label)
        shown = np.isfinite(u1) & (u1 > 1e-6 * ubar[0]) & (u1 < 1e3 * ubar[0])
        ax.loglog(z[1:][shown], u1[shown] * 1e6, ls="--", color=color(i))
        if cs.percolates and np.isfinite(cs.u1_c) and cs.u1_c > 0:
            hollow |= not cs.valid
            ax.plot([cs.zeta_c], [cs.u1_c * 1e6], "o", color=color(i), ms=4.5,
                    mfc=color(i) if cs.valid else "none")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("separation (µm)")
    if top == 0.0:
        say_nothing(ax, "no separation to draw: the surfaces are in full contact\n"
                        + pressures_text([cs.squeeze_pressure for cs in closed], [True] * len(closed)))
        ax.set_xscale("log")
        ax.set_xlim(1.0, max(float(cs.zeta[-1]) for cs in curves.sets))
        finish_axes(ax)
        return fig
    ax.set_ylim(bottom * 1e6, top * 1e6)
    d = cases[0].fluid.molecular_length
    if bottom < d < top:
        ax.axhline(d * 1e6, color="0.3", ls=":", lw=1, label=f"molecular size d = {d * 1e9:.2g} nm")
    notes = ["solid: mean separation ū(ζ); dashed: u1(ζ); dots: u_c = u1(ζc)"
             + ("; hollow: u_c below molecular size" if hollow else "")]
    if closed:
        notes.append("full contact (nothing to draw) at "
                     + ", ".join(f"{cs.squeeze_pressure / pressure_axis([cs.squeeze_pressure])[0]:.3g} "
                                 f"{pressure_axis([cs.squeeze_pressure])[1]}" for cs in closed))
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_gap_distribution(curves: PredictionCurves) -> Figure:
    """P(u) (continuous part) for a few squeeze pressures; the δ(u) weight A(ζ1)/A0 in the legend."""
    fig, ax = new_figure("Distribution of interfacial separations P(u)")
    # u P(u) on a log u axis: the probability per unit ln u, readable across scales
    u = curves.gap
    top = 0.0
    closed = []
    for i, (cs, y) in enumerate(zip(curves.sets, curves.gap_density)):
        d = cs.distribution
        if cs.in_full_contact or not u.size:
            closed.append(cs)
            continue
        top = max(top, float(np.nanmax(y)))
        ax.semilogx(u * 1e6, y, color=color(i),
                    label=f"{_set_label(cs, curves)}: δ(u) weight A(ζ1)/A0 = {d.contact_fraction[0]:.3g}")
        ax.axvline(d.mean_gap[0] * 1e6, color=color(i), ls=":", lw=1)
    ax.set_xlabel("interfacial separation u (µm)")
    ax.set_ylabel("u·P(u), probability per unit ln u (1)")
    if top == 0.0:
        say_nothing(ax, "no gap distribution to draw: the surfaces are in full contact\n"
                        + pressures_text([cs.squeeze_pressure for cs in closed], [True] * len(closed)))
        ax.set_xscale("log")
        ax.set_xlim(1e-4, 1e2)
        finish_axes(ax)
        return fig
    ax.set_xlim(u[0] * 1e6, u[-1] * 1e6)
    ax.set_ylim(0, 1.05 * top)
    subtitle(ax, "continuous part of P(u) (the δ(u) contact weight is in the legend); dotted: ū(1)"
             + ("\nfull contact (δ(u) weight 1) at " + pressures_text([c.squeeze_pressure for c in closed],
                                                                     [True] * len(closed)) if closed else ""))
    finish_axes(ax)
    place_legend(ax)
    return fig


def _settings(case: Case) -> str:
    return (f"α = {case.alpha:g}, ΔP = {case.pressure_difference / 1e3:.3g} kPa, "
            f"η = {case.fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {case.seal.aspect_ratio:.3g}, "
            f"p_c = {case.percolation_threshold:g}, γ = {case.gamma:g}")


def _no_leak_text(results: Sequence[CaseResult]) -> str:
    """Why a leak-rate figure is empty: no leak channel anywhere, or Q = 0 where there is one."""
    channel = any(r.critical_junction.percolates.any() or (r.effective_medium is not None and r.effective_medium.percolates.any())
                  for r in results)
    p0 = np.concatenate([r.critical_junction.squeeze_pressure for r in results])
    if channel:
        return f"the leak rate is zero at every squeeze pressure\n(ΔP = {results[0].case.pressure_difference:.3g} Pa)"
    return "no leak channel at any squeeze pressure\n(the non-contact area does not percolate: " + pressures_text(p0, np.ones(p0.size, bool)) + ")"


def _leak_series(results: Sequence[CaseResult], x_scale: float) -> list[Series]:
    """The leak-rate series of a run: critical junction (solid) and effective medium (dashed, or solid alone)."""
    out = []
    several = len(results) > 1
    for i, r in enumerate(results):
        res, em = r.critical_junction, r.effective_medium
        name = r.case.label if several else ""
        x = res.squeeze_pressure / x_scale
        if r.shows_critical_junction:
            label = name or ("critical junction" if em is not None else None)
            if em is not None and name:
                label = f"{name}, critical junction"
            out.append(Series(x, res.leak_rate, r.valid, color(i), "-", label or None, r.validity))
        if em is not None:
            valid = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(em), bool)
            why = r.validity_effective_medium or ()
            label = (f"{name}, effective medium" if name else "effective medium (Bruggeman)") if r.shows_critical_junction else (name or None)
            out.append(Series(em.squeeze_pressure / x_scale, np.where(em.percolates, em.leak_rate, np.nan), valid, color(i),
                              "--" if r.shows_critical_junction else "-", label, why))
    return out


def _series_peaks(series: Sequence[Series]) -> list[float]:
    peaks = []
    for s in series:
        y = np.asarray(s.y, dtype=float)
        ok = np.isfinite(y) & (y > 0) & s.valid
        if ok.any():
            peaks.append(float(y[ok].max()))
    return peaks


@laid_out
def figure_leak_rate(results: Sequence[CaseResult], log: bool) -> Figure:
    """Q against P0, linear (paper Fig. 6) or log (paper Fig. 7), with a second axis in ml/min.

    Effective-medium curves (model "both") are drawn dashed next to the critical-junction ones, or
    alone (model "effective-medium"). The linear figure turns logarithmic when the curves' maxima
    differ by more than two decades (on a linear axis all but the largest would lie flat on zero).
    """
    cases = [r.case for r in results]
    p_all = np.concatenate([r.critical_junction.squeeze_pressure for r in results])
    fig, ax = new_figure("Leak rate against squeeze pressure" + (" (log scale)" if log else ""))
    scale = pressure_x(ax, p_all)
    series = _leak_series(results, scale)
    peaks = _series_peaks(series)
    logy = log or spans_decades(peaks, 1.0)  # a curve below a tenth of the largest would lie flat on zero
    shown_cj = any(r.shows_critical_junction for r in results)
    shown_em = any(r.effective_medium is not None for r in results)
    settings = _settings(cases[0]) if shown_cj else (
        f"effective medium (2D Bruggeman, no fit factor): ΔP = {cases[0].pressure_difference / 1e3:.3g} kPa, "
        f"η = {cases[0].fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {cases[0].seal.aspect_ratio:.3g}, γ = {cases[0].gamma:g}")
    if shown_em and shown_cj:
        settings += "\nsolid: critical junction; dashed: effective medium (no fit factor)"
    any_q = any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series)
    if not any_q:
        say_nothing(ax, _no_leak_text(results))
        ax.set_ylabel("leak rate Q (m³/s)")
        subtitle(ax, settings)
        finish_axes(ax)
        return fig
    qscale, qunit = (1.0, "m³/s") if logy else power_unit(peaks, "m³/s")
    scaled = [Series(s.x, s.y / qscale, s.valid, s.color, s.style, s.label, s.why) for s in series]
    draw_series(ax, scaled, logy=logy, bottom_zero=not logy)
    ax.set_ylabel(f"leak rate Q ({qunit})")
    missing = any((~r.critical_junction.percolates).any() for r in results if r.shows_critical_junction)
    missing = missing or any(r.effective_medium is not None and (~r.effective_medium.percolates).any() for r in results)
    notes = [settings]
    if not log and logy:
        notes.append("log scale: the curves differ by decades")
    if missing:
        notes.append("missing points: no leak channel (the non-contact area does not percolate)")
    hollow = _invalid_note(series)
    if hollow:
        notes.append(hollow)
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    ml_per_min_axis(ax, qscale)
    place_legend(ax)
    return fig


@laid_out
def figure_critical_junction(results: Sequence[CaseResult]) -> Figure:
    """u_c (solid) and λc (dashed) against P0 (the critical pore size, paper Fig. 8)."""
    fig, ax = new_figure("Critical constriction against squeeze pressure")
    p_all = np.concatenate([r.critical_junction.squeeze_pressure for r in results])
    scale = pressure_x(ax, p_all)
    # one length unit for both curves, chosen by the smaller quantity (the valid gaps)
    gaps = np.concatenate([np.where(r.valid, r.critical_junction.critical_gap, np.nan) for r in results])
    lscale, lunit = length_unit(gaps)
    several = len(results) > 1
    series = []
    for i, r in enumerate(results):
        res = r.critical_junction
        x = res.squeeze_pressure / scale
        series.append(Series(x, res.critical_gap / lscale, r.valid, color(i), "-",
                             r.case.label if several else "height u_c", r.validity))
        series.append(Series(x, res.critical_wavelength / lscale, r.valid, color(i), "--",
                             None if several else "width λc = L/ζc"))
    ax.set_ylabel(f"critical pore size ({lunit})")
    if not draw_series(ax, series, logy=True):
        ax.set_yscale("linear")
        say_nothing(ax, _no_leak_text(results).replace("the leak rate is zero", "no critical constriction"))
        finish_axes(ax)
        return fig
    lo, hi = ax.get_ylim()
    d = results[0].case.fluid.molecular_length / lscale
    notes = ["solid: height u_c; dashed: width λc = L/ζc"] if several else []
    if lo < d < hi:
        ax.axhline(d, color="0.3", ls=":", lw=1, label=f"molecular size d = {d * lscale * 1e9:.2g} nm")
    if len(results) == 1:
        res = results[0].critical_junction
        ok = res.percolates & results[0].valid
        if ok.any():
            ratio = np.median(res.critical_wavelength[ok] / res.critical_gap[ok])
            notes.append(f"median λc/u_c = {ratio:.3g}")
    hollow = _invalid_note(series)
    if hollow:
        notes.append(hollow)
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_critical_magnification(results: Sequence[CaseResult]) -> Figure:
    """ζc against P0 (paper Fig. 9); log when ζc spans more than two decades."""
    fig, ax = new_figure("Critical magnification against squeeze pressure")
    p_all = np.concatenate([r.critical_junction.squeeze_pressure for r in results])
    scale = pressure_x(ax, p_all)
    several = len(results) > 1
    series = [Series(r.critical_junction.squeeze_pressure / scale, r.critical_junction.critical_magnification, r.valid,
                     color(i), "-", r.case.label if several else None, r.validity) for i, r in enumerate(results)]
    values = np.concatenate([np.where(s.valid, s.y, np.nan) for s in series])
    ax.set_ylabel("critical magnification ζc (1)")
    if not draw_series(ax, series, logy=spans_decades(values)):
        say_nothing(ax, _no_leak_text(results).replace("the leak rate is zero", "no critical magnification"))
        finish_axes(ax)
        return fig
    notes = [f"A(ζc)/A0 = 1 - p_c = {1 - results[0].case.percolation_threshold:.2f}"]
    hollow = _invalid_note(series)
    if hollow:
        notes.append(hollow)
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    place_legend(ax)
    return fig


@laid_out
def figure_pressure_difference(curves: PredictionCurves) -> Figure:
    """Q against ΔP at a fixed squeeze pressure (paper Fig. 5: linear through the origin), with ml/min.

    With effective-medium results for a case (model "both"), its Bruggeman leak rate is drawn dashed.
    When the cases' leak rates differ by more than two decades, both axes are logarithmic (Q ∝ ΔP
    is then a line of slope one).
    """
    fig, ax = new_figure("Leak rate against fluid pressure difference")
    ax.set_xlabel("pressure difference ΔP = P_a - P_b (kPa)")
    sweeps = curves.pressure_difference
    if not sweeps:
        say_nothing(ax, "no leak channel at any squeeze pressure:\nno leak rate to draw against ΔP")
        ax.set_ylabel("leak rate Q (m³/s)")
        finish_axes(ax)
        return fig
    several = len({id(sw.case) for sw in sweeps}) > 1
    series = []
    for i, sw in enumerate(sweeps):
        case, p0, dp = sw.case, sw.squeeze_pressure, sw.pressure_difference
        scale, unit = pressure_axis(np.array([p0]))
        label = (f"{case.label}, " if several and case.label else "") + f"P0 = {p0 / scale:.3g} {unit}"
        both = sw.effective_medium is not None
        if case.model != "effective-medium" or not both:
            series.append(Series(dp / 1e3, sw.critical_junction, np.full(dp.size, sw.valid), color(i), "-",
                                 ("critical junction, " if both else "") + label))
        if sw.effective_medium is not None:
            series.append(Series(dp / 1e3, sw.effective_medium, np.full(dp.size, sw.valid_effective_medium), color(i),
                                 "--" if case.model != "effective-medium" else "-",
                                 ("effective medium, " if case.model != "effective-medium" else "") + label))
    peaks = _series_peaks(series)
    if not peaks and not any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series):
        say_nothing(ax, "the leak rate is zero at every pressure difference")
        ax.set_ylabel("leak rate Q (m³/s)")
        finish_axes(ax)
        return fig
    log = spans_decades(peaks, 1.0)
    qscale, qunit = (1.0, "m³/s") if log else power_unit(peaks, "m³/s")
    scaled = [Series(s.x, s.y / qscale, s.valid, s.color, s.style, s.label, s.why) for s in series]
    draw_series(ax, scaled, logy=log, logx=log, bottom_zero=not log)
    if not log:
        ax.set_xlim(left=0)
    ax.set_ylabel(f"leak rate Q ({qunit})")
    formulas = []
    if any(sw.case.model != "effective-medium" or sw.effective_medium is None for sw in sweeps):
        formulas.append("Q = α (Ly/Lx) u_c³ ΔP/(12η)")
    if any(sw.effective_medium is not None for sw in sweeps):
        formulas.append("Q = (Ly/Lx) σ_eff ΔP (effective medium)")
    notes = [", ".join(formulas) + ": linear in ΔP at fixed P0 (P0 >> ΔP assumed)"]
    if log:
        notes.append("log-log: the cases' leak rates differ by decades (Q ∝ ΔP has slope one)")
    if not all(s.valid.all() for s in series):
        notes.append("hollow markers: outside the theory's validity at that P0")
    subtitle(ax, "\n".join(notes))
    finish_axes(ax)
    ml_per_min_axis(ax, qscale)
    place_legend(ax)
    return fig


def prediction_figures(results: Sequence[CaseResult], curves: PredictionCurves | None = None) -> dict[str, Figure]:
    """Every figure of a prediction, keyed by PNG file name.

    ``curves`` defaults to :func:`~sealeak.cases.prediction_curves` of ``results``. Effective-medium
    curves are drawn dashed next to the critical-junction ones (model "both"), or alone
    (model "effective-medium").
    """
    if curves is None:
        curves = prediction_curves(list(results))
    cases = [r.case for r in results]
    return {
        "spectrum.png": figure_spectrum(cases, curves),
        "contact_area.png": figure_contact_area(cases, curves),
        "separation.png": figure_separation(cases, curves),
        "gap_distribution.png": figure_gap_distribution(curves),
        "leak_rate.png": figure_leak_rate(results, log=False),
        "leak_rate_log.png": figure_leak_rate(results, log=True),
        "critical_junction.png": figure_critical_junction(results),
        "critical_magnification.png": figure_critical_magnification(results),
        "leak_rate_vs_pressure_difference.png": figure_pressure_difference(curves),
    }


def figure_png(fig: Figure) -> bytes:
    """The PNG bytes of a figure (cropped to what it draws)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")
    return buf.getvalue()


def render_figures(figures: dict[str, Figure]) -> dict[str, bytes]:
    """Every figure as PNG bytes, by file name (render all before writing any: a failure leaves no file)."""
    return {name: figure_png(fig) for name, fig in figures.items()}


def save_figures(figures: dict[str, Figure] | dict[str, bytes], folder: str | Path) -> list[str]:
    """Write figures (or their PNG bytes) into ``folder`` atomically, all rendered first; returns the paths written."""
    pngs = {name: f if isinstance(f, bytes) else figure_png(f) for name, f in figures.items()}
    written = []
    for name, data in pngs.items():
        path = Path(folder) / name
        with atomic_write(path, "wb") as tmp:
            tmp.write_bytes(data)
        written.append(str(path))
    return written


PREDICTION_FIGURE_NAMES = ("spectrum.png", "contact_area.png", "separation.png", "gap_distribution.png", "leak_rate.png",
                           "leak_rate_log.png", "critical_junction.png", "critical_magnification.png",
                           "leak_rate_vs_pressure_difference.png")
