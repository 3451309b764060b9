"""Figures of a seal whose contact pressure varies across the band: an O-ring or a pressure-profile file.

For such a seal one squeeze pressure P0 does not describe the contact (docs/theory.md §10), so the
uniform figures against P0 give way to these, one curve per load (an O-ring's compression ε or a
profile file's scale factor):

* :func:`figure_pressure_profile`: the nominal contact pressure p(x) across the band, and below it,
  per load, the part of the band that holds 90 % of the flow resistance R = ∫dx/σ(p(x))
  (:func:`~sealeak.physics.profile.resistance_band`, docs/theory.md §10.1);
* :func:`figure_local_critical_gap`: the local critical gap u_c(x) (log axis), the gap of the
  critical junction of a uniform seal at the local pressure p(x), with the fluid's molecular size;
* :func:`figure_band_leak_rate`: the leak rate through the band against the load (log axis), both
  theories when computed, with the leak rate of a uniform seal at the mean contact pressure dashed
  in the same colour; loads without a leak channel are marked at the bottom, not left out.

They draw what :class:`~sealeak.cases.band.BandResult` holds (the profiles, the quadrature points
of R and their σ, the leak rates) and compute no physics; they follow the rules of
:mod:`sealeak.render.figures`. An O-ring's profiles are drawn about the centre of the contact
(x − w/2), a profile file's at the file's own x.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..cases import CaseResult
from ..cases.band import BandResult
from ..cases.life import time_text
from ..cases.model import BandSeal
from ..io.units import format_quantity
from ..physics.profile import RESISTANCE_FRACTION, BandIntegral, PressureProfile
from . import plotstyle
from .notes import load_axis_label, load_text, loads_text

__all__ = ["band_figures", "BAND_FIGURE_NAMES", "figure_pressure_profile", "figure_local_critical_gap",
           "figure_band_leak_rate", "load_labels", "profile_curve", "resistance_spans", "local_gap_curve",
           "is_band_run"]

#: The band figures :func:`band_figures` returns (``figures.prediction_figures`` adds spectrum.png).
BAND_FIGURE_NAMES = ("pressure_profile.png", "local_critical_gap.png", "leak_rate.png")

#: Line styles of the variants of a study whose curves differ (the colour is the load's).
_VARIANT_STYLES = ("-", "--", ":", "-.")
#: Dash patterns of the molecular-size lines of a study's fluids.
_MOLECULAR_STYLES = ("--", (0, (6, 2, 1, 2)), (0, (2, 2)), (0, (8, 3)))
#: Points of a drawn Hertz (semi-elliptic) profile.
_ELLIPSE_POINTS = 241


def is_band_run(results: Sequence[CaseResult]) -> bool:
    """Whether every result is an O-ring or pressure-profile seal (then the band figures replace the uniform ones)."""
    return bool(results) and all(r.band is not None for r in results)


def _band(r: CaseResult) -> BandResult:
    assert r.band is not None
    return r.band


# ---------------------------------------------------------------------- what the curves are
def load_labels(band: BandSeal) -> list[str]:
    """Legend label of each load, as the notes write it: "compression 12.5 %" or "profile scale 0.75"."""
    return [load_text(band.load_name, v) for v in band.loads]


def _load_axis(band: BandSeal) -> tuple[np.ndarray, str]:
    """The x values of the leak-rate figure and their axis label."""
    scale = 100.0 if band.load_name == "compression" else 1.0
    return scale * np.asarray(band.loads, dtype=float), load_axis_label(band.load_name)


def _centre(band: BandSeal, profile: PressureProfile) -> float:
    """The x the figures subtract: w/2 for an O-ring (drawn about its contact's centre), 0 for a profile file."""
    return profile.width / 2.0 if band.kind == "o-ring" else 0.0


def _x_unit(results: Sequence[CaseResult]) -> tuple[float, str]:
    """mm when some band is at least 1 mm wide, else µm."""
    widest = max(float(np.max(_band(r).contact_width)) for r in results)
    return (1e-3, "mm") if widest >= 1e-3 else (1e-6, "µm")


def _x_label(results: Sequence[CaseResult], unit: str) -> str:
    if all(_band(r).band.kind == "o-ring" for r in results):
        return f"position from the centre of the contact x − w/2 ({unit})"
    return f"position across the band x ({unit})"


def profile_curve(profile: PressureProfile) -> tuple[np.ndarray, np.ndarray]:
    """(x, p) of a drawn profile (m, Pa): a file's nodes as they are; a Hertz profile on points gathered at its edges."""
    if profile.shape == "semi-elliptic":
        theta = np.linspace(0.0, np.pi, _ELLIPSE_POINTS)
        x = profile.width * (1.0 - np.cos(theta)) / 2.0
        return x, profile.at(x)
    return np.asarray(profile.x, dtype=float), np.asarray(profile.pressure, dtype=float)


def _cell_edges(integral: BandIntegral) -> np.ndarray:
    """Edges (m) of the strips the quadrature points stand for: the running sum of their widths (Σ dx = w)."""
    return np.concatenate([[0.0], np.cumsum(integral.dx)])


def _level_set(profile: PressureProfile, level: float, strict: bool = False) -> list[tuple[float, float]]:
    """The x intervals (m) where p(x) >= ``level`` (> with ``strict``) of a piecewise-linear profile, merged."""
    out: list[tuple[float, float]] = []
    for a, b, pa, pb in zip(profile.x[:-1], profile.x[1:], profile.pressure[:-1], profile.pressure[1:]):
        if b <= a:
            continue
        above_a = pa > level if strict else pa >= level
        above_b = pb > level if strict else pb >= level
        if above_a and above_b:
            lo, hi = a, b
        elif above_a or above_b:
            cut = a + (b - a) * (level - pa) / (pb - pa)
            lo, hi = (a, cut) if above_a else (cut, b)
        else:
            continue
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((float(lo), float(hi)))
    return out


def _merged(spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Sorted intervals with those that touch joined."""
    out: list[tuple[float, float]] = []
    for lo, hi in spans:
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out


def _measure(spans: list[tuple[float, float]]) -> float:
    return float(sum(hi - lo for lo, hi in spans))


def resistance_spans(profile: PressureProfile, width: float) -> list[tuple[float, float]]:
    """Where the band's resistance sits: the x intervals (m) of the highest pressures, ``width`` wide in all.

    ``width`` is the band's :attr:`~sealeak.cases.band.BandTheory.resistance_band_width` (the
    narrowest part holding 90 % of R, docs/theory.md §10.1). σ(p) falls as p rises (the assumption of
    :func:`~sealeak.physics.profile.series_resistance`), so that part is the level set p(x) >= p* whose
    width is ``width``: a centred interval of a Hertz profile, found by bisection on p* for a profile
    file (where a plateau holds the level, the missing width is taken next to the higher pressures). Empty when
    ``width`` is NaN (a sealed band).
    """
    if not (np.isfinite(width) and width > 0):
        return []
    w = profile.width
    if profile.shape == "semi-elliptic":
        half = min(width, w) / 2.0
        return [(w / 2.0 - half, w / 2.0 + half)]
    lo, hi = 0.0, float(profile.max_pressure)
    for _ in range(200):  # measure({p >= level}) falls as the level rises
        mid = (lo + hi) / 2.0
        if _measure(_level_set(profile, mid)) >= width:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-13 * profile.max_pressure:
            break
    spans = _level_set(profile, lo)
    missing = width - _measure(_level_set(profile, lo, strict=True))
    if _measure(spans) > width * (1 + 1e-6) and missing > 0:  # a plateau at the level: only part of it
        spans = _level_set(profile, lo, strict=True)
        flats = [(a, b) for a, b, pa, pb in zip(profile.x[:-1], profile.x[1:], profile.pressure[:-1], profile.pressure[1:])
                 if b > a and pa == pb and abs(pa - lo) <= 1e-9 * profile.max_pressure]
        total = sum(b - a for a, b in flats)
        ends = [hi for _, hi in spans]
        starts = [lo for lo, _ in spans]
        tol = 1e-12 * w
        for a, b in flats:
            part = missing * (b - a) / total
            if any(abs(e - a) <= tol for e in ends):  # next to the higher pressures beside the plateau
                spans.append((a, a + part))
            elif any(abs(st - b) <= tol for st in starts):
                spans.append((b - part, b))
            else:
                spans.append(((a + b - part) / 2.0, (a + b + part) / 2.0))
        spans = _merged(sorted(spans))
    return spans


def local_gap_curve(result: CaseResult, i: int) -> tuple[np.ndarray, np.ndarray]:
    """(x, u_c) in m of load ``i``: :meth:`BandResult.local_critical_gap` on the quadrature points, where it is > 0.

    A constant piece of a profile file is one point standing for its whole width: it is drawn as a
    level line across that width (its two ends), so a step in p(x) is a step in u_c(x).
    """
    band = _band(result)
    g = band.critical_junction.integrals[i]
    uc = band.local_critical_gap(i, result.case.alpha, result.case.fluid.viscosity)
    profile = band.band.profiles[i]
    xs, ys = [], []
    edges = _cell_edges(g)
    for k, (x, u) in enumerate(zip(g.x, uc)):
        if not (np.isfinite(u) and u > 0):
            continue
        a, b = edges[k], edges[k + 1]
        inner = (b - a) * 1e-9
        flat = profile.shape == "table" and b > a and bool(np.all(profile.at(np.array([a + inner, b - inner])) == g.pressure[k]))
        if flat:
            xs += [a, b]
            ys += [u, u]
        else:
            xs.append(x)
            ys.append(u)
    return np.array(xs, dtype=float), np.array(ys, dtype=float)


# ---------------------------------------------------------------------- grouping the variants of a study
def _same_profiles(a: BandSeal, b: BandSeal) -> bool:
    if a.kind != b.kind or a.loads.shape != b.loads.shape or not np.array_equal(a.loads, b.loads):
        return False
    return all(p.shape == q.shape and p.peak == q.peak and np.array_equal(p.x, q.x) and np.array_equal(p.pressure, q.pressure)
               for p, q in zip(a.profiles, b.profiles))


def _groups(results: Sequence[CaseResult], same: object) -> list[list[CaseResult]]:
    """The results grouped by ``same(r1, r2)``: variants that would draw the same curves are drawn once."""
    groups: list[list[CaseResult]] = []
    for r in results:
        for g in groups:
            if same(g[0], r):  # type: ignore[operator]
                g.append(r)
                break
        else:
            groups.append([r])
    return groups


def _main(r: CaseResult) -> tuple[str, object]:
    """The theory a study's bars and notes follow: the critical junction, or the effective medium alone."""
    band = _band(r)
    if r.shows_critical_junction or band.effective_medium is None:
        return "critical junction", band.critical_junction
    return "effective medium", band.effective_medium


def _spans_of(r: CaseResult) -> list[list[tuple[float, float]]]:
    theory = _main(r)[1]
    widths = theory.resistance_band_width  # type: ignore[attr-defined]
    return [resistance_spans(p, float(wd)) for p, wd in zip(_band(r).band.profiles, widths)]


def _same_spans(a: CaseResult, b: CaseResult) -> bool:
    if not _same_profiles(_band(a).band, _band(b).band):
        return False
    sa, sb = _spans_of(a), _spans_of(b)
    return all(len(x) == len(y) and np.allclose(np.array(x), np.array(y), rtol=1e-9, atol=0) for x, y in zip(sa, sb))


def _same_gaps(a: CaseResult, b: CaseResult) -> bool:
    if not _same_profiles(_band(a).band, _band(b).band):
        return False
    for i in range(len(_band(a))):
        xa, ua = local_gap_curve(a, i)
        xb, ub = local_gap_curve(b, i)
        if xa.shape != xb.shape or not (np.allclose(xa, xb, rtol=1e-12, atol=0) and np.allclose(ua, ub, rtol=1e-9, atol=0)):
            return False
    return True


def _group_name(group: list[CaseResult]) -> str:
    return " = ".join(r.case.label for r in group if r.case.label)


def _add_variant_entries(handles: list[object], labels: list[str], groups: Sequence[list[CaseResult]]) -> None:
    """Add a legend entry per variant of a study (its line style), when there are several."""
    if len(groups) > 1:
        for gi, g in enumerate(groups):
            handles.append(Line2D([], [], ls=_VARIANT_STYLES[gi % len(_VARIANT_STYLES)], color="0.3"))
            labels.append(_group_name(g) or f"variant {gi + 1}")


# ---------------------------------------------------------------------- the figures
@dataclass(frozen=True)
class _Row:
    """One row of the resistance bars: its label, colour and intervals (m, before centring)."""

    label: str
    color: str
    spans: list[tuple[float, float]]
    centre: float


@plotstyle.laid_out
def figure_pressure_profile(results: Sequence[CaseResult]) -> Figure:
    """p(x) of every load (one curve each) and, below, the part of each band that holds 90 % of R."""
    sx, xunit = _x_unit(results)
    pmax = max(float(np.max(_band(r).max_contact_pressure)) for r in results)
    ps, punit = plotstyle.pressure_axis([pmax])
    bar_groups = _groups(results, _same_spans)
    rows: list[_Row] = []
    for g in bar_groups:
        b = _band(g[0])
        name = _group_name(g) if len(bar_groups) > 1 else ""
        for i, (label, spans) in enumerate(zip(load_labels(b.band), _spans_of(g[0]))):
            rows.append(_Row(f"{name}, {label}" if name else label, plotstyle.color(i), spans, _centre(b.band, b.band.profiles[i])))
    n = len(rows)
    with mpl.rc_context(plotstyle.STYLE):
        fig = Figure(figsize=(6.4, 4.4 + 0.17 * n), layout="constrained")
        ax, bars = fig.subplots(2, 1, sharex=True, height_ratios=[3.4, 0.45 + 0.17 * n])
    ax._sealeak_heading = "Contact pressure across the band"  # type: ignore[attr-defined]

    profile_groups = _groups(results, lambda a, b: _same_profiles(_band(a).band, _band(b).band))
    handles: list[object] = []
    labels: list[str] = []
    for gi, g in enumerate(profile_groups):
        b = _band(g[0])
        style = _VARIANT_STYLES[gi % len(_VARIANT_STYLES)]
        for i, (profile, label) in enumerate(zip(b.band.profiles, load_labels(b.band))):
            x, p = profile_curve(profile)
            (line,) = ax.plot((x - _centre(b.band, profile)) / sx, p / ps, ls=style, color=plotstyle.color(i), lw=1.4)
            if gi == 0:
                handles.append(line)
                labels.append(label)
    _add_variant_entries(handles, labels, profile_groups)
    ax.set_ylim(bottom=0)
    ax.set_ylabel(f"contact pressure p ({punit})")
    ax.label_outer()

    for k, row in enumerate(rows):
        for lo, hi in row.spans:  # a thick line per interval: its ends are exact in x
            bars.plot([(lo - row.centre) / sx, (hi - row.centre) / sx], [k, k], color=row.color, lw=6, solid_capstyle="butt")
    lo_x, hi_x = ax.get_xlim()
    for k, row in enumerate(rows):
        if not row.spans:
            bars.text((lo_x + hi_x) / 2.0, k, "no leak channel: the band seals", ha="center", va="center", fontsize=7,
                      color="0.25")
    bars.set_ylim(n - 0.5, -0.5)
    bars.set_yticks(range(n), [row.label for row in rows], fontsize=7)
    bars.grid(False, axis="y")
    bars.set_xlabel(_x_label(results, xunit))
    theory = {_main(r)[0] for r in results}
    bars.set_title(f"the narrowest part of each band holding {100 * RESISTANCE_FRACTION:.0f} % of the flow resistance "
                   f"R = ∫dx/σ(p)\n({', '.join(sorted(theory))})", fontsize=8, loc="left")

    notes = []
    first = _band(results[0]).band
    if first.kind == "o-ring":
        notes.append("Hertz (semi-elliptic) pressure of each compression, centred on the contact")
    else:
        notes.append(f"profile from {first.profile_source.rsplit('/', 1)[-1] or 'the case file'}, multiplied by each scale")
    if len(profile_groups) > 1:
        notes.append("line style: the study's variant")
    elif len(results) > 1:
        notes.append("the same for every variant of the study")
    plotstyle.subtitle(ax, "\n".join(notes))
    for a in (ax, bars):
        plotstyle.finish_axes(a)
    bars.set_yticks(range(n), [row.label for row in rows], fontsize=7)  # finish_axes set a number format on y
    plotstyle.place_legend(ax, handles, labels)  # type: ignore[arg-type]
    return fig


@plotstyle.laid_out
def figure_local_critical_gap(results: Sequence[CaseResult]) -> Figure:
    """u_c(x) of every load (log axis) with each fluid's molecular size (dashed)."""
    fig, ax = plotstyle.new_figure("Local critical gap across the band")
    sx, xunit = _x_unit(results)
    groups = _groups(results, _same_gaps)
    curves = []
    for gi, g in enumerate(groups):
        r = g[0]
        b = _band(r)
        for i, label in enumerate(load_labels(b.band)):
            x, u = local_gap_curve(r, i)
            if x.size:
                curves.append((gi, i, label, (x - _centre(b.band, b.band.profiles[i])) / sx, u))
    sealed_text = []
    for g in groups:
        b = _band(g[0])
        sealed = ~b.critical_junction.percolates
        if sealed.any():
            name = _group_name(g) if len(groups) > 1 else ""
            sealed_text.append((f"{name}: " if name else "") + loads_text(b.band.load_name, b.band.loads[sealed]))
    ax.set_xlabel(_x_label(results, xunit))
    if not curves:
        ax.set_ylabel("local critical gap u_c (nm)")
        widest = max(float(np.max(_band(r).contact_width)) for r in results) / sx
        ax.set_xlim(*((-widest / 2, widest / 2) if _band(results[0]).band.kind == "o-ring" else (0.0, widest)))
        plotstyle.say_nothing(ax, "no leak channel at any load (" + "; ".join(sealed_text) + "):\nthe non-contact area does not "
                        "percolate where the pressure is highest")
        plotstyle.finish_axes(ax)
        return fig
    every = np.concatenate([u for *_, u in curves])
    us, uunit = (1e-9, "nm") if every.min() < 1e-6 else (1e-6, "µm")
    handles: list[object] = []
    labels: list[str] = []
    for gi, i, label, x, u in curves:
        (line,) = ax.semilogy(x, u / us, ls=_VARIANT_STYLES[gi % len(_VARIANT_STYLES)], color=plotstyle.color(i), lw=1.3)
        if gi == 0:
            handles.append(line)
            labels.append(label)
    _add_variant_entries(handles, labels, groups)
    ax.set_ylabel(f"local critical gap u_c ({uunit})")
    lo, hi = every.min() / us, every.max() / us
    sizes: dict[float, list[str]] = {}
    for r in results:
        sizes.setdefault(r.case.fluid.molecular_length, []).append(r.case.fluid.name or r.case.label)
    for k, (d, names) in enumerate(sorted(sizes.items())):
        who = ", ".join(dict.fromkeys(n for n in names if n))
        handles.append(ax.axhline(d / us, color="0.25", lw=1.0, ls=_MOLECULAR_STYLES[k % len(_MOLECULAR_STYLES)]))
        labels.append(f"molecular size{' of ' + who if who else ''}: d = {d * 1e9:.3g} nm")
        lo, hi = min(lo, d / us), max(hi, d / us)
    pad = (hi / lo) ** 0.05
    ax.set_ylim(lo / pad, hi * pad)
    notes = ["u_c of a uniform seal at the local pressure p(x) (critical junction); the smallest sets the leak rate",
             "below a dashed line the gap is narrower than a molecule of the fluid: no continuum flow"]
    if sealed_text:
        notes.append("no leak channel (sealed band, not drawn) at " + "; ".join(sealed_text))
    if len(groups) > 1:
        notes.append("line style: the study's variant")
    elif len(results) > 1:
        notes.append("the same for every variant of the study")
    plotstyle.subtitle(ax, "\n".join(notes))
    plotstyle.finish_axes(ax)
    plotstyle.place_legend(ax, handles, labels)  # type: ignore[arg-type]
    return fig


def _is_gas(results: Sequence[CaseResult]) -> bool:
    """Whether every result is a gas case with gas leak rates: its leak figure shows Q_pV (docs/theory.md §11.9)."""
    return all(r.case.gas is not None and r.gas for r in results)


def _leak_series(results: Sequence[CaseResult], gas: bool = False) -> tuple[list[plotstyle.Series], list[tuple[plotstyle.Series, np.ndarray]]]:
    """(every series to draw, (solid series, sealed mask) of each theory through the band).

    Per case and theory a solid series (the band) and a dashed one (a uniform seal at the mean
    pressure) in one colour; each theory's rows carry its own verdicts (valid, valid_effective_medium). With ``gas``
    the solid series is the gas leak rate Q_pV through the band in mbar·l/s (the records'
    ``leak_rate_mbar_l_s``) and the dashed one its helium equivalent, when computed (docs/theory.md §11.9).
    """
    several = len(results) > 1
    out: list[plotstyle.Series] = []
    solid: list[tuple[plotstyle.Series, np.ndarray]] = []
    k = 0
    for r in results:
        b = _band(r)
        x, _ = _load_axis(b.band)
        theories = []
        if r.shows_critical_junction:
            theories.append(("critical junction", b.critical_junction, r.valid, r.validity))
        if b.effective_medium is not None:
            valid_em = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(b), dtype=bool)
            theories.append(("effective medium", b.effective_medium, valid_em, r.validity_effective_medium or ()))
        for name, theory, valid, why in theories:
            label = f"{r.case.label}, {name}" if several and r.case.label else name
            if gas:
                rows = (r.gas or {})[name.replace(" ", "_")]
                drawn = plotstyle.gas_series(x, rows, np.asarray(valid, dtype=bool), why, plotstyle.color(k), label)
                out += drawn
                solid.append((drawn[0], ~theory.percolates))
                k += 1
                continue
            s = plotstyle.Series(x, theory.leak_rate, np.asarray(valid, dtype=bool), plotstyle.color(k), "-", label, why)
            out.append(s)
            out.append(plotstyle.Series(x, theory.uniform_mean_pressure, np.ones(len(b), dtype=bool), plotstyle.color(k), "--", None))
            held = (r.capillary or {}).get(name.replace(" ", "_"))  # a liquid held by capillarity: Q = 0 too
            solid.append((s, ~theory.percolates | (held.held if held is not None else False)))
            k += 1
    return out, solid


def _bottom_band(ax: Axes) -> float:
    """The y (data) of the band below the lowest value of a log axis: the band of the ▽ markers, or a new one."""
    below = [float(np.nanmin(np.asarray(line.get_ydata()))) for line in ax.get_lines()
             if line.get_marker() == "v" and len(np.asarray(line.get_ydata()))]
    if below:
        return min(below)
    lo, hi = ax.get_ylim()
    span = float(np.log10(hi / lo))
    ax.set_ylim(lo / 10.0 ** (0.07 * span), hi)
    return float(lo / 10.0 ** (0.035 * span))


@plotstyle.laid_out
def figure_band_leak_rate(results: Sequence[CaseResult], limit: tuple[float, str] | None = None) -> Figure:
    """Q through the band against the load (log axis), both theories, with Q of a uniform seal at p_mean dashed;
    ``limit``: ``conditions.max_leak_rate`` as :func:`~sealeak.render.life.volume_limit` gives it (m³/s, a gas's
    Pa·m³/s), drawn as a line."""
    first = _band(results[0]).band
    word = "compression" if first.load_name == "compression" else "profile scale"
    gas = _is_gas(results)
    names = sorted({r.case.gas.gas.name for r in results if r.case.gas is not None})
    # the seal over its life draws here the case as assembled: at which time (its other times have figures of their own)
    life = results[0].case.life
    when = f" at t = {time_text(life.time)}" if life is not None and len(results) == 1 else ""
    fig, ax = plotstyle.new_figure(f"Leak rate of {' / '.join(names)} against {word}{when}" if gas
                                   else f"Leak rate against {word}{when}")
    x_all = np.concatenate([_load_axis(_band(r).band)[0] for r in results])
    ax.set_xlabel(_load_axis(first)[1])
    lo_x, hi_x = float(x_all.min()), float(x_all.max())
    if plotstyle.spans_decades(x_all):
        ax.set_xscale("log")
        ax.set_xlim(lo_x / (hi_x / lo_x) ** 0.04, hi_x * (hi_x / lo_x) ** 0.04)
    elif hi_x > lo_x:
        ax.set_xlim(lo_x - 0.04 * (hi_x - lo_x), hi_x + 0.04 * (hi_x - lo_x))
    series, solid = _leak_series(results, gas)
    case = results[0].case
    etas = {r.case.fluid.viscosity for r in results}
    settings = [f"ΔP = {format_quantity(case.pressure_difference, 'pressure', 3)}", f"Ly = {first.length * 1e3:.4g} mm"]
    if len(etas) == 1:
        settings.append(f"η = {case.fluid.viscosity * 1e3:.3g} mPa·s")
    if any(r.shows_critical_junction for r in results):
        settings.append(f"α = {case.alpha:g}")
    if first.faces != 1:
        settings.append(f"{first.faces} faces in parallel")
    notes = [", ".join(settings) + "; solid: through the band (strips in series), dashed: a uniform seal at the mean "
             "contact pressure"]
    ax.set_ylabel("leak rate Q (m³/s)")
    if gas:
        settings[0] = ("Q_pV through the band, the gas pressure taken off the contact (theory §13.5)" if case.coupled
                       else "Q_pV = K ∫ p f(Kn) dp over P_b…P_a, K through the band (strips in series)")
        if len(etas) == 1:
            settings[2] = f"η = {case.fluid.viscosity * 1e6:.4g} µPa·s"
        conditions = {plotstyle.gas_conditions_text(r.case) for r in results}
        notes = [plotstyle.gas_conditions_text(case) if len(conditions) == 1 else "gas conditions differ between the variants (see the text output)",
                 ", ".join(settings) + ("; dashed: helium equivalent (1 bar He against vacuum, 20 °C)"
                                        if any(s.style == "--" for s in series) else "")]
        regime = plotstyle.gas_regime_text([g for r in results for g in (r.gas or {}).values()],
                                           gap="h = u_c at the peak contact pressure")
        if regime:
            notes.append(regime)
        ax.set_ylabel(f"{plotstyle.GAS_LEAK_LABEL} (mbar·l/s)")
    if not any(np.any(np.isfinite(s.y) & (s.y > 0)) for s in series):
        plotstyle.say_nothing(ax, f"no leak channel at any {word}:\nthe non-contact area does not percolate")
        plotstyle.subtitle(ax, "\n".join(notes[:2]) if gas else notes[0])
        plotstyle.finish_axes(ax)
        return fig
    plotstyle.draw_series(ax, series, logy=True)
    if where := plotstyle.draw_limit(ax, plotstyle.limit_in_axis_unit(limit, gas)):
        notes.append(where)
    handles, labels = ax.get_legend_handles_labels()
    for s, _ in solid:  # a theory without a drawn point still names its colour (its × and dashed curve)
        if s.label and s.label not in labels:
            handles.insert(len(labels), Line2D([], [], color=s.color, marker="o", ms=3))
            labels.append(s.label)
    if any(mask.any() for _, mask in solid):
        at = _bottom_band(ax)
        sealed = [(s, mask) for s, mask in solid if mask.any()]
        opened = False  # a row sealed without the fluid's pressure, which opens it (not valid): ▲, hollow
        for j, (s, mask) in enumerate(sealed):
            # side by side where several theories or variants seal at the same load
            shift = 0.014 * (j - (len(sealed) - 1) / 2.0)
            x = s.x * (hi_x / lo_x) ** shift if ax.get_xscale() == "log" else s.x + shift * (hi_x - lo_x)
            shut = mask & np.asarray(s.valid, dtype=bool)
            ax.plot(x[shut], np.full(int(shut.sum()), at), "x", color=s.color, ms=5, mew=1.4)
            if (mask & ~shut).any():
                opened = True
                ax.plot(x[mask & ~shut], np.full(int((mask & ~shut).sum()), at), "^", mfc="none", mec=s.color, ms=6,
                        mew=1.3)
        if any((mask & np.asarray(s.valid, dtype=bool)).any() for s, mask in sealed):
            handles.append(Line2D([], [], ls="none", marker="x", color="0.3", ms=6, mew=1.5))
            held = any(rows.held.any() for r in results for rows in (r.capillary or {}).values())
            labels.append("no leak channel, or the liquid held by capillarity (× at the bottom)" if held
                          else "no leak channel: the band seals (× at the bottom)")
        if opened:
            handles.append(Line2D([], [], ls="none", marker="^", mfc="none", mec="0.3", ms=6, mew=1.3))
            labels.append("sealed but for ΔP, which opens it: valid = NO (△ at the bottom)")
    if not gas:
        handles.append(Line2D([], [], ls="--", color="0.4"))
        labels.append("uniform seal at the mean contact pressure")
    if any(not np.asarray(s.valid).all() for s in series):
        notes.append("hollow: outside the theory's validity where the pressure is highest (▽: below the axis)")
    if not gas and any(r.capillary for r in results):  # docs/theory.md §12
        notes.append("capillarity holds the liquid where ΔP is below the narrowest gap's entry pressure; the dashed "
                     "uniform seal is drawn without it")
    plotstyle.subtitle(ax, "\n".join(notes))
    plotstyle.finish_axes(ax)
    if gas:
        plotstyle.pa_m3_axis(ax, 1.0)
    else:
        plotstyle.ml_per_min_axis(ax, 1.0)
    plotstyle.place_legend(ax, handles, labels)
    return fig


def band_figures(results: Sequence[CaseResult], limit: tuple[float, str] | None = None) -> dict[str, Figure]:
    """The band figures of a run of O-ring or pressure-profile seals, keyed by PNG file name (:data:`BAND_FIGURE_NAMES`);
    ``limit``: ``conditions.max_leak_rate`` for the leak-rate figure (:func:`figure_band_leak_rate`)."""
    return {
        "pressure_profile.png": figure_pressure_profile(results),
        "local_critical_gap.png": figure_local_critical_gap(results),
        "leak_rate.png": figure_band_leak_rate(results, limit),
    }

