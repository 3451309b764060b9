"""Figures of an uncertain prediction: the fan chart, the tornado chart and the distribution of Q at one load.

* :func:`figure_fan_chart`: the leak rate against the load (P0 or an O-ring's compression) on a log axis, per
  case its median over the samples (solid), the 5–95 % band (light) and optionally the 25–75 % band (darker),
  the deterministic prediction of the nominal inputs (dashed) and the specification ``max_leak_rate``
  (red, dash-dotted); sealed samples (Q = 0) have no place on a log axis, so a grey strip below the
  leak rates, its tick named "sealed", stands for them: a band that reaches into it seals in at least 5 % of the samples, a
  median drawn in it (▽) in at least half;
* :func:`figure_tornado`: Sobol' total (ST) and first-order (S1) indices of log10 Q per uncertain input,
  sorted, largest on top, with their bootstrap intervals (:mod:`sealeak.cases.sensitivity`);
* :func:`figure_leak_distribution`: the histogram of Q at one load over the samples (log axis), the
  share of sealed samples, the specification line and the probability of passing it.

They are built from plain arrays (leak rates in m³/s, or another unit named by the caller) and compute
no physics; they follow the house style of :mod:`sealeak.render.plotstyle`. :func:`uncertainty_figures`
builds them from a propagation (:class:`~sealeak.cases.uncertainty.UncertaintyResult`) and its Sobol'
indices: the fan chart of every case, the distribution and the tornado chart at the first case's middle
load (:func:`~sealeak.cases.sobol.chosen_rows`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.ticker import FixedLocator, FuncFormatter

from ..cases.sobol import SobolIndices, chosen_rows, sensitivity_summary
from ..cases.uncertainty import SAMPLER_NAMES, UncertaintyResult
from ..cases.uncertainty import record_values as record_leak_rates
from .life import volume_limit
from .notes import load_axis_label, load_text
from .plotstyle import (
    GAS_LEAK_LABEL,
    LIMIT_DECADES,
    ML_PER_MIN_PER_M3_PER_S,
    PA_M3_PER_MBAR_L,
    color,
    finish_axes,
    laid_out,
    limit_in_axis_unit,
    limit_line,
    log_axis,
    ml_per_min_axis,
    new_figure,
    pa_m3_axis,
    place_legend,
    pressure_axis,
    say_nothing,
    spans_decades,
    subtitle,
)

__all__ = ["LeakBand", "figure_fan_chart", "figure_tornado", "figure_leak_distribution", "UNCERTAINTY_FIGURE_NAMES",
           "uncertainty_figures", "uncertainty_figure_names"]

#: The file names of the uncertainty figures (``predict --plots DIR``).
UNCERTAINTY_FIGURE_NAMES = ("leak_rate_band.png", "sensitivity.png", "leak_rate_distribution.png")

#: Height of the "sealed" strip below the leak rates, as a share of the decades the axis shows.
_SEALED_STRIP = 0.09
#: Decades a leak-rate axis spans at most below its largest value: a percentile of a load where nearly every sample
#: seals may be 1e-38 m³/s, which would squeeze what matters into the top of the figure.
_MAX_DECADES = 8.0
#: The most variants (study values, a life case's times and temperatures) a fan chart draws a band for.
MAX_FAN_BANDS = 6
_SPEC_COLOUR = "tab:red"


@dataclass(frozen=True)
class LeakBand:
    """One case's leak rate over the samples against its loads, for :func:`figure_fan_chart`.

    ``x``: the loads as drawn (kPa, MPa or % of compression: the caller's axis); ``p05``, ``p50``,
    ``p95`` (and optionally ``p25``, ``p75``): percentiles of the leak rate over the samples, 0 where
    sealed; ``nominal``: the deterministic prediction (0 or NaN: no leak channel), or None.
    """

    x: np.ndarray
    p05: np.ndarray
    p50: np.ndarray
    p95: np.ndarray
    p25: np.ndarray | None = None
    p75: np.ndarray | None = None
    nominal: np.ndarray | None = None
    label: str = ""
    #: Per percentile (5th, 50th, 95th) and load, [3, loads], whether it is taken from samples outside the theory's
    #: validity (:meth:`~sealeak.cases.uncertainty.UncertaintyResult.outside`): the median drawn hollow, the band's edges
    #: with small hollow circles; or None.
    outside: np.ndarray | None = None
    #: The variant's place among all of them (its colour, as in the other figures), where the chart draws a selection.
    index: int | None = None


def _positive(*arrays: np.ndarray | None) -> np.ndarray:
    """The positive finite values of every array given."""
    v = np.concatenate([np.asarray(a, dtype=float).ravel() for a in arrays if a is not None] or [np.zeros(0)])
    return v[np.isfinite(v) & (v > 0)]


def _leak_limits(values: np.ndarray, sealed: bool) -> tuple[float, float, float]:
    """(bottom, top of the sealed strip, top) of a log leak-rate axis showing ``values``, a decade at least and
    :data:`_MAX_DECADES` at most; with ``sealed`` a strip below the leak rates stands for the sealed samples (else its top
    is ``bottom``)."""
    lo, hi = float(values.min()), float(values.max())
    lo_d, hi_d = np.log10(lo) - 0.15, np.log10(hi) + 0.15
    lo_d = max(lo_d, hi_d - _MAX_DECADES)
    if hi_d - lo_d < 1.0:
        mid = (hi_d + lo_d) / 2
        lo_d, hi_d = mid - 0.5, mid + 0.5
    strip = _SEALED_STRIP * (hi_d - lo_d) if sealed else 0.0
    return 10.0 ** (lo_d - strip), 10.0 ** lo_d, 10.0 ** hi_d


def _far_from(leaking: np.ndarray, limit: float | None) -> str:
    """"above" or "below" where ``limit`` lies more than :data:`~sealeak.render.plotstyle.LIMIT_DECADES` above the
    largest of the positive ``leaking`` values (as far as the other leak-rate figures widen their axes for it, see
    :func:`~sealeak.render.plotstyle.draw_limit`), or farther below it than the axis reaches (:data:`_MAX_DECADES`);
    "" otherwise (or without either). As the axis' end, such a limit would squeeze the leak rates into its floor (a
    1e-3 ml/min limit over leak rates near 1e-19 m³/s left every median below the axis): it is named in the legend."""
    if limit is None or not (np.isfinite(limit) and limit > 0) or not leaking.size:
        return ""
    gap = float(np.log10(limit) - np.log10(leaking.max()))
    return "above" if gap > LIMIT_DECADES else "below" if gap < -_MAX_DECADES else ""


def _sealed_strip(ax, top: float, bottom: float) -> None:
    """Shade the strip of sealed samples (below ``top``); :func:`_sealed_tick` names it."""
    ax.axhspan(bottom, top, color="0.88", zorder=0, lw=0)


def _sealed_tick(axis: Axis, at: float, limit: float) -> None:
    """Name the strip of sealed samples (Q = 0) by a tick "sealed" at ``at`` among the leak-rate ticks, which stay
    above ``limit`` (a name inside the strip would lie under the markers of the sealed loads)."""
    lo, hi = sorted(axis.get_view_interval())
    ticks = [float(v) for v in axis.get_major_locator().tick_values(lo, hi) if limit * (1 - 1e-9) <= v <= hi * (1 + 1e-9)]
    label = axis.get_major_formatter()
    axis.set_major_locator(FixedLocator([at, *ticks]))
    axis.set_major_formatter(FuncFormatter(lambda v, pos: "sealed" if v == at else label(v, pos)))


def _leak_label(unit: str) -> str:
    """The axis label of leak rates in ``unit``: a gas's pV throughput in mbar·l/s, else the leak rate Q."""
    return f"{GAS_LEAK_LABEL} ({unit})" if unit == "mbar·l/s" else f"leak rate Q ({unit})"


def _blank_below(axis: Axis, limit: float) -> None:
    """Leave the tick labels of ``axis`` below ``limit`` empty ."""
    label = axis.get_major_formatter()
    axis.set_major_formatter(FuncFormatter(lambda v, pos: "" if v < limit * (1 - 1e-9) else label(v, pos)))


@laid_out
def figure_fan_chart(bands: Sequence[LeakBand], x_label: str, *, max_leak_rate: float | None = None, unit: str = "m³/s",
                     notes: str = "", log_x: bool = False, limit_text: str = "", y_label: str = "") -> Figure:
    """The leak rate with its 5–95 % band against the load, per case (see the module's text).

    ``unit``: the unit of the leak rates (m³/s adds an axis in ml/min, a gas's mbar·l/s one in Pa·m³/s); ``max_leak_rate``: the
    specification in that unit, or None (``limit_text``: as the case file writes it, for the legend);
    ``notes``: subtitle lines (samples, seed, inputs); ``log_x``: a log load axis; ``y_label``: the leak rate's axis
    label, where not the unit's usual one.
    """
    fig, ax = new_figure("Leak rate with its uncertainty: median and 5–95 % band")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label or _leak_label(unit))
    leaking = _positive(*[a for b in bands for a in (b.p05, b.p25, b.p50, b.p75, b.p95, b.nominal)])
    far = _far_from(leaking, max_leak_rate)
    values = leaking if far else _positive(leaking, np.array([max_leak_rate if max_leak_rate is not None else np.nan]))
    if not values.size:
        say_nothing(ax, "sealed in every sample at every load: no leak rate to draw")
        subtitle(ax, notes)
        return fig
    sealed_any = any((np.asarray(b.p05) <= 0).any() for b in bands)
    bottom, strip_top, top = _leak_limits(values, sealed_any)
    at_sealed = float(np.sqrt(bottom * strip_top))
    ax.set_yscale("log")
    if log_x:
        ax.set_xscale("log")
    # a leak below the axis runs along its floor (above the strip of the sealed samples, which is not a leak rate)
    shown = lambda v: np.where(np.asarray(v, dtype=float) > 0, np.maximum(v, strip_top), at_sealed)  # noqa: E731
    below_any = outside_any = edges_any = False
    # one band: every element in the legend; several: one entry per band (its colour, its name) and one per element in grey
    single = len(bands) == 1
    drawn: dict[str, tuple[str, dict[str, Any]]] = {}  # element label -> (marker or line style, keywords), for the grey entries

    def label(text: str, style: str = "", **kw: Any) -> str:
        if not single:
            drawn.setdefault(text, (style, kw))
        return text if single else "_nolegend_"

    for i, b in enumerate(bands):
        k = i if b.index is None else b.index
        c = color(k)
        ax.fill_between(b.x, shown(b.p05), shown(b.p95), color=c, alpha=0.18, lw=0,
                        label="5–95 % of the samples" if single else b.label or f"variant {k + 1}")
        if b.p25 is not None and b.p75 is not None:
            ax.fill_between(b.x, shown(b.p25), shown(b.p75), color=c, alpha=0.35, lw=0, label=label("25–75 %", "fill"))
        leaks = np.asarray(b.p50) > 0
        below = leaks & (np.asarray(b.p50, dtype=float) < strip_top)
        marker = "o" if len(b.x) <= 12 else ""
        ax.plot(b.x, np.where(leaks & ~below, b.p50, np.nan), "-", marker=marker, ms=3, color=c,
                label=label("median", "-", marker=marker, ms=3))
        flags = np.zeros((3, len(b.x)), dtype=bool) if b.outside is None else np.asarray(b.outside, dtype=bool)
        outside = leaks & ~below & flags[1]
        if np.any(outside):
            outside_any = True
            ax.plot(np.asarray(b.x)[outside], np.asarray(b.p50, dtype=float)[outside], "o", mfc="white", mec=c, ms=6,
                    label=label("median from samples outside the theory", "o", mfc="white", ms=6))
        edges = np.asarray([b.p05, b.p95], dtype=float)  # both edges in one line (one legend entry)
        marked = flags[[0, 2]] & (edges >= strip_top)
        if marked.any():
            edges_any = True
            ax.plot(np.broadcast_to(np.asarray(b.x, dtype=float), edges.shape)[marked], edges[marked], "o",
                    mfc="white", mec=c, ms=3.5, mew=0.8,
                    label=label("5th or 95th percentile from samples outside the theory", "o", mfc="white", ms=3.5, mew=0.8))
        if below.any():
            below_any = True
            ax.plot(np.asarray(b.x)[below], np.full(int(below.sum()), strip_top), "v", mfc="none", mec=c, ms=5,
                    clip_on=False, label=label("median below the axis", "v", mfc="none", ms=5))
        if (~leaks).any():
            ax.plot(np.asarray(b.x)[~leaks], np.full(int((~leaks).sum()), at_sealed), "v", mfc="none", mec=c, ms=5,
                    label=label("median sealed (half the samples or more)", "v", mfc="none", ms=5))
        if b.nominal is not None:
            nominal = np.asarray(b.nominal, dtype=float)
            ax.plot(b.x, np.where(nominal >= strip_top, nominal, np.nan), "--", color=c, lw=1.0,
                    label=label("deterministic (nominal inputs)", "--", lw=1.0))
    if not single:  # what each element is, in grey, after the bands' names
        ax.fill_between([], [], [], color="0.35", alpha=0.18, lw=0, label="5–95 % of the samples")
        for text, (style, kw) in drawn.items():
            if style == "fill":
                ax.fill_between([], [], [], color="0.35", alpha=0.35, lw=0, label=text)
            elif style in ("-", "--"):
                ax.plot([], [], style, color="0.35", label=text, **kw)
            else:
                ax.plot([], [], style, mec="0.35", color="0.35", label=text, **kw)
    if max_leak_rate is not None and not far:
        limit_line(ax, max_leak_rate, limit_text or f"{max_leak_rate:.3g} {unit}", _SPEC_COLOUR)
    elif max_leak_rate is not None:  # named in the legend, with how far beyond the axis it lies
        decades = abs(np.log10(max_leak_rate) - np.log10(top if far == "above" else strip_top))
        side = "above the top" if far == "above" else "below the foot"
        ax.plot([], [], "^" if far == "above" else "v", color=_SPEC_COLOUR, ms=7,
                label=f"max_leak_rate = {limit_text or f'{max_leak_rate:.3g} {unit}'}: {decades:.1f} decades {side} of the axis")
    ax.set_ylim(bottom, top)
    if sealed_any:
        _sealed_strip(ax, strip_top, bottom)
    if outside_any or edges_any:
        what = " or (small) a 5th or 95th percentile" if edges_any else ""
        notes += ("\n" if notes else "") + (f"hollow: a median{what} taken from samples that leak outside the theory's "
                                             "validity (the table's 'outside', *): no leak rate to rely on")
    if values.min() < strip_top:  # the axis was cut
        notes += ("\n" if notes else "") + (f"axis cut {_MAX_DECADES:g} decades below the largest leak rate: bands "
                                             "below it run along its floor" + (", ▽ marks a median there" if below_any else ""))
    subtitle(ax, notes)
    finish_axes(ax)
    log_axis(ax.yaxis, bottom, top)
    second, factor = {"m³/s": (ml_per_min_axis, ML_PER_MIN_PER_M3_PER_S), "mbar·l/s": (pa_m3_axis, PA_M3_PER_MBAR_L)}.get(
        unit, (None, 1.0))
    axis2 = second(ax) if second is not None else None
    if sealed_any:  # no leak-rate tick in the strip of the sealed samples: a tick that names it
        _sealed_tick(ax.yaxis, at_sealed, strip_top)
        if axis2 is not None:
            _blank_below(axis2.yaxis, strip_top * factor)
    place_legend(ax)
    return fig


@laid_out
def figure_tornado(labels: Sequence[str], first: np.ndarray, total: np.ndarray, first_conf: np.ndarray | None = None,
                   total_conf: np.ndarray | None = None, *, notes: str = "") -> Figure:
    """Sobol' indices of log10 Q per input as horizontal bars, the largest total index on top.

    ``first``, ``total``: S1 and ST per input (shares of the variance, 0–1); ``*_conf``: the half-widths
    of their confidence intervals, drawn as error bars; ``notes``: subtitle lines (the load, the plain-words
    summary, N). Estimates slightly below 0 (sampling noise) are drawn at 0 with their interval.
    """
    first, total = np.asarray(first, dtype=float), np.asarray(total, dtype=float)
    fig, ax = new_figure("Which input matters: Sobol' indices of log10 Q",
                         figsize=(6.4, max(2.6, 1.7 + 0.5 * len(labels))))
    ax.set_xlabel("share of the variance of log10 Q (1)")
    if not np.isfinite(total).any():
        say_nothing(ax, "no variance of log10 Q: the leak rate is the same in every sample")
        subtitle(ax, notes)
        return fig
    order = sorted(range(len(labels)), key=lambda i: -np.nan_to_num(total[i], nan=-1.0))[::-1]  # largest drawn last = on top
    y = np.arange(len(order), dtype=float)
    h = 0.38
    err = lambda conf: None if conf is None else np.asarray(conf, dtype=float)[order]  # noqa: E731
    ax.barh(y + h / 2, np.clip(total[order], 0, None), h, xerr=err(total_conf), color="tab:blue",
            error_kw={"elinewidth": 0.8, "capsize": 2, "ecolor": "0.25"}, label="total index ST (alone and with interactions)")
    ax.barh(y - h / 2, np.clip(first[order], 0, None), h, xerr=err(first_conf), color="tab:cyan",
            error_kw={"elinewidth": 0.8, "capsize": 2, "ecolor": "0.25"}, label="first-order index S1 (alone)")
    # the input's name above its spread ("surface.h_rms" / "1 um ± 10 %"): the bars keep the figure's width
    ax.set_yticks(y, [labels[i].replace(": ", "\n", 1) for i in order], fontsize=8.5)
    ax.grid(False, axis="y")
    ax.set_xlim(0, 1.05)
    ax.set_ylim(-0.7, len(order) - 0.3)
    subtitle(ax, notes + ("\n" if notes else "") + "bars: estimates; whiskers: 95 % bootstrap intervals")
    place_legend(ax)
    return fig


@laid_out
def figure_leak_distribution(q: np.ndarray, *, max_leak_rate: float | None = None, nominal: float | None = None,
                             unit: str = "m³/s", notes: str = "", limit_text: str = "", x_label: str = "") -> Figure:
    """The distribution of the leak rate at one load over the samples: a histogram on a log axis.

    ``q``: the samples' leak rates (0 or NaN: sealed, counted in the legend, not drawn);
    ``max_leak_rate``: the specification (same unit), drawn with the share of samples at or below it
    (the probability of passing; a sealed sample passes; ``limit_text``: as written); ``nominal``: the deterministic
    prediction.
    """
    q = np.asarray(q, dtype=float).ravel()
    leaks = np.isfinite(q) & (q > 0)
    sealed = 1.0 - float(leaks.mean()) if q.size else 0.0
    fig, ax = new_figure("Distribution of the leak rate over the samples")
    ax.set_xlabel(x_label or _leak_label(unit))
    ax.set_ylabel("share of the samples per bin (1)")
    lines = [notes] if notes else []
    lines.append(f"{q.size} samples; {100 * sealed:.0f} % sealed (Q = 0, not drawn)")
    if max_leak_rate is not None:
        passing = float(np.mean(~leaks | (q <= max_leak_rate)))
        lines.append(f"probability of passing max_leak_rate = {limit_text or f'{max_leak_rate:.3g} {unit}'}: {100 * passing:.1f} %")
    if not leaks.any():
        say_nothing(ax, "sealed in every sample: no leak rate to draw")
        subtitle(ax, "\n".join(lines))
        return fig
    v = q[leaks]
    lo, hi = np.log10(v.min()), np.log10(v.max())
    if hi - lo < 0.2:
        lo, hi = (lo + hi) / 2 - 0.1, (lo + hi) / 2 + 0.1
    bins = 10.0 ** np.linspace(lo, hi, int(np.clip(np.sqrt(v.size), 8, 40)) + 1)
    share, _, _ = ax.hist(v, bins=list(bins), weights=np.full(v.size, 1.0 / q.size), color="tab:blue", alpha=0.6,
                          label=f"leaking samples ({100 * (1 - sealed):.0f} %)")
    # its outline as a line: the legend's placement sees the bars (plotstyle.place_legend looks at lines)
    ax.plot(np.repeat(bins, 2)[1:-1], np.repeat(share, 2), color="tab:blue", lw=1.0)
    ax.set_xscale("log")
    median = float(np.median(np.nan_to_num(q)))  # a sealed sample counts as Q = 0
    if median > 0:
        ax.axvline(median, color="0.2", lw=1.2, label="median")
    if nominal is not None and np.isfinite(nominal) and nominal > 0:
        ax.axvline(nominal, color="0.2", ls="--", lw=1.0, label="deterministic (nominal inputs)")
    far = _far_from(_positive(v, np.array([nominal if nominal is not None else np.nan])), max_leak_rate)
    shown = [bins[0], bins[-1]] + [v for v in (nominal, None if far else max_leak_rate) if v is not None and np.isfinite(v) and v > 0]
    ax.set_xlim(min(shown) / 10 ** 0.1, max(shown) * 10 ** 0.1)  # the bins and the lines, a tenth of a decade beyond
    if max_leak_rate is not None and not far:
        ax.axvline(max_leak_rate, color=_SPEC_COLOUR, ls="-.", lw=1.2, label=f"max_leak_rate = {limit_text or f'{max_leak_rate:.3g} {unit}'}")
    elif max_leak_rate is not None:  # far from the samples: named in the legend with how far it lies, not the axis' end
        edge = max(shown) * 10 ** 0.1 if far == "above" else min(shown) / 10 ** 0.1
        decades = abs(np.log10(max_leak_rate / edge))
        ax.plot([], [], ">" if far == "above" else "<", color=_SPEC_COLOUR, ms=7,
                label=f"max_leak_rate = {limit_text or f'{max_leak_rate:.3g} {unit}'}: {decades:.1f} decades "
                      f"beyond the axis' {'right' if far == 'above' else 'left'} end")
    subtitle(ax, "\n".join(lines))
    finish_axes(ax)
    place_legend(ax)
    return fig


# ---------------------------------------------------------------------- from a propagation


def uncertainty_figure_names(sensitivity: bool) -> tuple[str, ...]:
    """The files :func:`uncertainty_figures` returns (sensitivity.png only with Sobol' indices)."""
    return tuple(n for n in UNCERTAINTY_FIGURE_NAMES if sensitivity or n != "sensitivity.png")


def _leak_key(unc: UncertaintyResult) -> tuple[str, str, float | None]:
    """(record key, unit, ``max_leak_rate`` in that unit or None) of the figures: a gas's pV throughput in mbar·l/s (the
    unit of its other figures), else Q in m³/s; the limit where every row compares that quantity with the same one."""
    gas = "leak_rate_mbar_l_s" in unc.values
    total = "leak_rate_total_mbar_l_s" in unc.values  # with permeation: the total, which max_leak_rate is compared with
    key, unit = ("leak_rate_total_mbar_l_s" if total else "leak_rate_mbar_l_s", "mbar·l/s") if gas else ("leak_rate", "m³/s")
    # volume_limit: only a limit compared with what is drawn
    limit = limit_in_axis_unit(volume_limit(unc, "leak_rate_total_pv" if total else None), gas)
    return key, unit, None if limit is None else limit[0]


def _load_x(load_name: str, loads: np.ndarray) -> tuple[float, str]:
    """(scale, axis label) of the loads: P0 in kPa or MPa, compression in %, a profile's scale as it is."""
    if load_name == "squeeze_pressure":
        scale, unit = pressure_axis(loads)
        return scale, f"squeeze pressure P0 ({unit})"
    return (0.01 if load_name == "compression" else 1.0), load_axis_label(load_name)


def uncertainty_figures(unc: UncertaintyResult, sensitivity: SobolIndices | None = None) -> dict[str, Figure]:
    """The figures of ``predict --plots`` for a case file with uncertain inputs, by file name
    (:func:`uncertainty_figure_names`): Q (m³/s; a gas's Q_pV in mbar·l/s) with its band, its distribution at the first case's middle load,
    and with ``sensitivity`` the tornado chart there. None (an empty dict) without uncertain inputs (``conditions.max_leak_rate``
    alone: no band, and the leak-rate figures draw the limit)."""
    if not unc.study.inputs:
        return {}
    key, unit, limit = _leak_key(unc)
    rows, q = unc.study.rows, unc.values[key]
    loads = np.array([r.load for r in rows])
    scale, x_label = _load_x(rows[0].load_name, loads)
    p05, p25, p50, p75, p95 = np.percentile(q, [5.0, 25.0, 50.0, 75.0, 95.0], axis=0)
    nominal = record_leak_rates(unc.nominal)[key]
    outside = unc.outside(key)
    bands = []
    for i, case in enumerate(unc.study.cases):
        idx = np.array([j for j, r in enumerate(rows) if r.case == i])
        idx = idx[np.argsort(loads[idx], kind="stable")]
        bands.append(LeakBand(loads[idx] / scale, p05[idx], p50[idx], p95[idx], p25[idx], p75[idx], nominal[idx], case.label,
                              outside[:, idx], i))
    inputs = ", ".join(inp.key for inp in unc.study.inputs)
    sampled = f"{unc.samples} samples ({SAMPLER_NAMES[unc.sampler]}, seed {unc.seed}) of {inputs}"
    label = ""
    if key == "leak_rate_total_mbar_l_s":
        sampled += "\nthe leak rate drawn: the interface leak plus permeation through the rubber, what a leak test measures"
        label = f"gas leak rate Q_total ({unit})"
    if len(bands) > MAX_FAN_BANDS:  # a band each for every time and temperature of a life case would hide the axes
        keep = sorted({int(round(k)) for k in np.linspace(0, len(bands) - 1, MAX_FAN_BANDS)})
        sampled += f"\n{len(bands)} variants: the fan chart draws {len(keep)} of them, evenly spread (the table gives all)"
        bands = [bands[k] for k in keep]
    written = str(unc.study.max_leak_rate) if limit is not None else ""
    figures = {"leak_rate_band.png": figure_fan_chart(bands, x_label, max_leak_rate=limit, unit=unit, log_x=spans_decades(loads),
                                                      limit_text=written, y_label=label,
                                                      notes=sampled + "\ndashed: the deterministic prediction; bands: 5–95 % and 25–75 %")}
    j = chosen_rows(unc.study)[0]
    at = (f"{rows[j].variant}, " if rows[j].variant else "") + load_text(rows[j].load_name, rows[j].load)
    figures["leak_rate_distribution.png"] = figure_leak_distribution(q[:, j], max_leak_rate=limit, nominal=float(nominal[j]), unit=unit,
                                                                     notes=f"at {at}; sampled: {inputs}", limit_text=written,
                                                                     x_label=label)
    if sensitivity is not None:
        labels = [inp.label for inp in unc.study.inputs]
        figures["sensitivity.png"] = figure_tornado(labels, sensitivity.first[j], sensitivity.total[j], sensitivity.first_conf[j],
                                                    sensitivity.total_conf[j],
                                                    notes=f"at {at}: {sensitivity_summary(sensitivity, j)}\n"
                                                          f"{sensitivity.base_samples} base samples, {sensitivity.evaluations} predictions, "
                                                          f"seed {sensitivity.seed}")
    return figures
