"""Figures of the critical-junction prediction (matplotlib, PNG).

One function per figure; each takes cases and their results and returns a matplotlib Figure.
:func:`prediction_figures` returns them all by file name (the CLI writes them atomically).
Every axis is labelled with its unit. The reference paper's theory figures are: C(q) (its Fig. 4),
Q against P0 on a linear and a log10 scale (Figs. 6, 7), the critical pore size against P0 (Fig. 8)
and ζc against P0 (Fig. 9); Q against ΔP (Fig. 5) and A(ζ), ū(ζ), u1(ζ) complete the set.
"""

from __future__ import annotations

from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from .case import Case, predict  # noqa: E402
from .leakage import CriticalJunctionResult  # noqa: E402
from .units import length_unit  # noqa: E402

__all__ = ["prediction_figures", "figure_gap_distribution", "representative_pressures", "pressure_axis"]

_STYLE = {"figure.figsize": (6.4, 4.4), "figure.dpi": 150, "axes.grid": True, "grid.alpha": 0.3,
          "axes.titlesize": 10, "legend.fontsize": 8}


def pressure_axis(p: np.ndarray) -> tuple[float, str]:
    """(scale, unit) for showing pressures: kPa, or MPa when the largest exceeds 2 MPa."""
    return (1e6, "MPa") if np.nanmax(p) > 2e6 else (1e3, "kPa")


def representative_pressures(result: CriticalJunctionResult, count: int = 4) -> np.ndarray:
    """A few percolating squeeze pressures spread over the sweep (log-spaced indices)."""
    p = result.squeeze_pressure[result.percolates]
    if p.size == 0:
        p = result.squeeze_pressure
    if p.size <= count:
        return p
    idx = np.unique(np.round(np.linspace(0, p.size - 1, count)).astype(int))
    return p[idx]


def _label(case: Case, fallback: str = "") -> str:
    return case.label or fallback


def _fig(title: str) -> tuple[Figure, plt.Axes]:
    """A figure with one axes; ``title`` is the heading, ``ax.set_title`` adds a second line below."""
    with plt.rc_context(_STYLE):
        fig, ax = plt.subplots()
    ax._sealeak_heading = title  # type: ignore[attr-defined]
    ax.set_title(title, fontsize=10, fontweight="bold")
    return fig, ax


def _subtitle(ax: plt.Axes, text: str) -> None:
    heading = getattr(ax, "_sealeak_heading", "")
    ax.set_title(heading + ("\n" + text if text else ""), fontsize=9)


def figure_spectrum(cases: Sequence[Case]) -> Figure:
    """C(q) against q, log-log, with q0 and the spectrum's nodes."""
    fig, ax = _fig("Surface roughness power spectrum")
    for case in cases:
        q, c = case.spectrum.sample(400)
        ax.loglog(q, c, label=_label(case, case.spectrum.label or "C(q)"))
    case = cases[0]
    ax.axvline(case.q0, color="0.5", ls=":", lw=1)
    ax.annotate("q0 = 2π/L", (case.q0, ax.get_ylim()[0]), rotation=90, va="bottom", ha="right", fontsize=8, color="0.4")
    ax.set_xlabel("wavevector q (1/m)")
    ax.set_ylabel("power spectrum C(q) (m⁴)")
    stats = (f"h_rms = {case.spectrum.h_rms * 1e6:.3g} µm, slope_rms = {case.spectrum.slope_rms:.3g}, "
             f"A_true/A0 = {case.spectrum.area_ratio:.3g}") if len(cases) == 1 else ""
    _subtitle(ax, (case.spectrum_note + ("\n" + stats if stats else "")) if len(cases) == 1 else "")
    if len(cases) > 1 or case.spectrum.label:
        ax.legend()
    return fig


def _zeta_grid(case: Case, num: int = 200) -> np.ndarray:
    return np.geomspace(1.0, case.spectrum.q_max / case.q0, num)


def _curve_sets(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> list[tuple[Case, float, str]]:
    if len(cases) == 1:
        scale, unit = pressure_axis(results[0].squeeze_pressure)
        return [(cases[0], p, f"P0 = {p / scale:.3g} {unit}") for p in representative_pressures(results[0])]
    out = []
    for case, res in zip(cases, results):
        p = representative_pressures(res, 3)[1 if representative_pressures(res, 3).size > 1 else 0]
        scale, unit = pressure_axis(res.squeeze_pressure)
        out.append((case, p, f"{case.label}, P0 = {p / scale:.3g} {unit}"))
    return out


def figure_contact_area(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> Figure:
    """A(ζ)/A0 against ζ for a few squeeze pressures, with the percolation level 1 - p_c."""
    fig, ax = _fig("Apparent relative contact area against magnification")
    for case, p0, label in _curve_sets(cases, results):
        z = _zeta_grid(case)
        line, = ax.semilogx(z, case.contact().area(z, p0), label=label)
        zc, ok = case.contact().zeta_at_area(1 - case.percolation_threshold, p0)
        if ok:
            ax.plot([zc], [1 - case.percolation_threshold], "o", color=line.get_color(), ms=4)
    pc = cases[0].percolation_threshold
    ax.axhline(1 - pc, color="k", ls="--", lw=0.8, label=f"percolation: A/A0 = 1 - p_c = {1 - pc:.2f}")
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("relative contact area A(ζ)/A0 (1)")
    ax.set_ylim(0, 1.02)
    _subtitle(ax, "dots: critical magnification ζc")
    ax.legend()
    return fig


def figure_separation(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> Figure:
    """ū(ζ) (solid) and u1(ζ) (dashed) against ζ for the same squeeze pressures."""
    fig, ax = _fig("Interfacial separation against magnification")
    top, bottom = 0.0, np.inf
    for case, p0, label in _curve_sets(cases, results):
        z = _zeta_grid(case)[:-1]
        contact = case.contact()
        ubar = contact.mean_gap(z, p0)
        u1 = contact.u1(z[1:], p0)  # u1 -> inf as ζ -> 1 (A'(1) = 0)
        top = max(top, 3.0 * ubar[0])
        bottom = min(bottom, 1e-3 * ubar[0])
        shown = (ubar > 1e-6 * ubar[0])
        line, = ax.loglog(z, np.where(shown, ubar, np.nan) * 1e6, label=f"ū, {label}")
        shown = np.isfinite(u1) & (u1 > 1e-6 * ubar[0]) & (u1 < 1e3 * ubar[0])
        ax.loglog(z[1:], np.where(shown, u1, np.nan) * 1e6, ls="--",
                  color=line.get_color(), label=f"u1, {label}")
        zc, ok = contact.zeta_at_area(1 - case.percolation_threshold, p0)
        if ok:
            ax.plot([zc], [contact.u1(zc, p0) * 1e6], "o", color=line.get_color(), ms=4)
    ax.set_ylim(bottom * 1e6, top * 1e6)
    ax.set_xlabel("magnification ζ = q/q0 (1)")
    ax.set_ylabel("separation (µm)")
    _subtitle(ax, "solid: mean separation ū(ζ); dashed: u1(ζ); dots: u_c = u1(ζc)")
    ax.legend(ncol=2 if len(ax.lines) > 8 else 1)
    return fig


def _per_pressure(cases: Sequence[Case], results: Sequence[CriticalJunctionResult], title: str,
                  ylabel: str, values, log: bool) -> Figure:
    fig, ax = _fig(title)
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    for case, res in zip(cases, results):
        y = values(res)
        ax.plot(res.squeeze_pressure / scale, y, "-o" if len(res) <= 12 else "-", ms=3,
                label=_label(case) or None)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel(ylabel)
    if any(c.label for c in cases):
        ax.legend()
    return fig


def _settings(case: Case) -> str:
    return (f"α = {case.alpha:g}, ΔP = {case.pressure_difference / 1e3:.3g} kPa, "
            f"η = {case.fluid.viscosity * 1e3:.3g} mPa·s, Ly/Lx = {case.seal.aspect_ratio:.3g}, "
            f"p_c = {case.percolation_threshold:g}, γ = {case.gamma:g}")


def figure_leak_rate(cases, results, log: bool, effective=None) -> Figure:
    """Q against P0, linear (paper Fig. 6) or log10 (paper Fig. 7).

    ``effective``: effective-medium results per case (or None); their curves are drawn dashed next
    to the critical-junction ones (model "both"), or alone (model "effective-medium").
    """
    ems = list(effective) if effective is not None else [None] * len(cases)
    title = "Leak rate against squeeze pressure" + (" (log scale)" if log else "")
    fig, ax = _fig(title)
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    shown_cj = shown_em = False
    for case, res, em in zip(cases, results, ems):
        prefix = f"{case.label}: " if case.label else ""
        marker = "-o" if len(res) <= 12 else "-"
        color = None
        if em is None or case.model != "effective-medium":
            y = np.log10(res.leak_rate) if log else res.leak_rate
            line, = ax.plot(res.squeeze_pressure / scale, y, marker, ms=3,
                            label=prefix + f"critical junction (α = {case.alpha:g})" if (em is not None or case.label) else None)
            color = line.get_color()
            shown_cj = True
        if em is not None:
            with np.errstate(divide="ignore"):
                y = np.log10(em.leak_rate) if log else em.leak_rate
            ax.plot(em.squeeze_pressure / scale, y, "--" if color else marker, ms=3, color=color,
                    label=prefix + "effective medium (Bruggeman)")
            shown_em = True
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("log10 of leak rate Q / (m³/s)" if log else "leak rate Q (m³/s)")
    if not log:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
        ax.set_ylim(bottom=0)
    if ax.get_legend_handles_labels()[0]:
        ax.legend()
    missing = any((~r.percolates).any() for r in results) if shown_cj else False
    missing = missing or any(em is not None and (~em.percolates).any() for em in ems)
    settings = _settings(cases[0]) if shown_cj else (
        f"ΔP = {cases[0].pressure_difference / 1e3:.3g} kPa, η = {cases[0].fluid.viscosity * 1e3:.3g} mPa·s, "
        f"Ly/Lx = {cases[0].seal.aspect_ratio:.3g}, γ = {cases[0].gamma:g}")
    if shown_em and shown_cj:
        settings += "\nsolid: critical junction; dashed: effective medium (no fit factor)"
    _subtitle(ax, settings + ("\nmissing points: the non-contact area does not percolate" if missing else ""))
    return fig


def figure_gap_distribution(cases: Sequence[Case], results: Sequence[CriticalJunctionResult]) -> Figure:
    """P(u) (continuous part) for a few squeeze pressures; the δ(u) weight A(ζ1)/A0 in the legend."""
    from .gaps import gap_distribution

    fig, ax = _fig("Distribution of interfacial separations P(u)")
    sets = _curve_sets(cases, results)
    dists = [gap_distribution(case.contact(), [p0]) for case, p0, _ in sets]
    # u P(u) on a log u axis: the probability per unit ln u, readable across scales
    lo = 1e-3 * min(float(d.mean_gap[0]) for d in dists)
    hi = 10.0 * max(max(float(d.mean[0]), float(d.mean_gap[0])) for d in dists)
    u = np.geomspace(lo, hi, 600)
    top = 0.0
    for (case, p0, label), d in zip(sets, dists):
        y = u * d.density(u)[0]
        top = max(top, float(y.max()))
        line, = ax.semilogx(u * 1e6, y,
                            label=f"{label}: δ(u) weight A(ζ1)/A0 = {d.contact_fraction[0]:.3g}")
        ax.axvline(d.mean_gap[0] * 1e6, color=line.get_color(), ls=":", lw=1)
    ax.set_xlim(lo * 1e6, hi * 1e6)
    ax.set_ylim(0, 1.45 * top)  # room for the legend
    ax.set_xlabel("interfacial separation u (µm)")
    ax.set_ylabel("u·P(u), probability per unit ln u (1)")
    _subtitle(ax, "continuous part of P(u) (the δ(u) contact weight is in the legend); dotted: ū(1)")
    ax.legend()
    return fig


def figure_critical_junction(cases, results) -> Figure:
    """u_c (solid) and λc (dashed) against P0 (the critical pore size, paper Fig. 8)."""
    fig, ax = _fig("Critical constriction against squeeze pressure")
    scale, unit = pressure_axis(np.concatenate([r.squeeze_pressure for r in results]))
    # one length unit for both curves, chosen by the smaller quantity (the gap)
    lscale, lunit = length_unit(np.concatenate([r.critical_gap for r in results]))
    for case, res in zip(cases, results):
        suffix = f", {case.label}" if case.label else ""
        line, = ax.semilogy(res.squeeze_pressure / scale, res.critical_gap / lscale, label="height u_c" + suffix)
        ax.semilogy(res.squeeze_pressure / scale, res.critical_wavelength / lscale, ls="--",
                    color=line.get_color(), label="width λc = L/ζc" + suffix)
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel(f"critical pore size ({lunit})")
    if len(results) == 1:
        ok = results[0].percolates
        if ok.any():
            ratio = np.median(results[0].critical_wavelength[ok] / results[0].critical_gap[ok])
            _subtitle(ax, f"median λc/u_c = {ratio:.3g}")
    if len(cases) > 2:  # a study: the curves fill the axes, the legend goes below them
        ax.legend(ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=8)
    else:
        ax.legend()
    return fig


def figure_critical_magnification(cases, results) -> Figure:
    """ζc against P0 (paper Fig. 9)."""
    fig = _per_pressure(cases, results, "Critical magnification against squeeze pressure",
                        "critical magnification ζc (1)", lambda r: r.critical_magnification, False)
    _subtitle(fig.axes[0], f"A(ζc)/A0 = 1 - p_c = {1 - cases[0].percolation_threshold:.2f}")
    return fig


def figure_pressure_difference(cases, results, effective=None) -> Figure:
    """Q against ΔP at a fixed squeeze pressure (paper Fig. 5: linear through the origin).

    With effective-medium results for a case (model "both"), its Bruggeman leak rate is drawn dashed.
    """
    from .case import predict_effective_medium

    fig, ax = _fig("Leak rate against fluid pressure difference")
    ems = list(effective) if effective is not None else [None] * len(cases)
    for case, res, em in zip(cases, results, ems):
        ok = res.squeeze_pressure[res.percolates]
        if ok.size == 0:
            continue
        p0 = ok[np.argmin(np.abs(np.log(ok / np.sqrt(ok[0] * ok[-1]))))]
        dp = np.linspace(0.0, 2.0 * max(case.pressure_difference, 1.0), 21)
        q = predict(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
        scale, unit = pressure_axis(np.array([p0]))
        label = (f"{case.label}, " if case.label else "") + f"P0 = {p0 / scale:.3g} {unit}"
        line, = ax.plot(dp / 1e3, q, "-", label=("critical junction, " if em is not None else "") + label)
        if em is not None:
            q_em = predict_effective_medium(case, squeeze_pressure=np.full(dp.size, p0), pressure_difference=dp).leak_rate
            ax.plot(dp / 1e3, q_em, "--", color=line.get_color(), label="effective medium, " + label)
    ax.set_xlabel("pressure difference ΔP = P_a - P_b (kPa)")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    _subtitle(ax, "Q = α (Ly/Lx) u_c³ ΔP/(12η): linear in ΔP at fixed P0 (P0 >> ΔP assumed)")
    ax.legend()
    return fig


def prediction_figures(cases: Sequence[Case], results: Sequence[CriticalJunctionResult],
                       effective=None) -> dict[str, Figure]:
    """Every figure of a prediction, keyed by PNG file name (``effective``: see :func:`figure_leak_rate`)."""
    return {
        "spectrum.png": figure_spectrum(cases),
        "contact_area.png": figure_contact_area(cases, results),
        "separation.png": figure_separation(cases, results),
        "gap_distribution.png": figure_gap_distribution(cases, results),
        "leak_rate.png": figure_leak_rate(cases, results, log=False, effective=effective),
        "leak_rate_log.png": figure_leak_rate(cases, results, log=True, effective=effective),
        "critical_junction.png": figure_critical_junction(cases, results),
        "critical_magnification.png": figure_critical_magnification(cases, results),
        "leak_rate_vs_pressure_difference.png": figure_pressure_difference(cases, results, effective),
    }


def save_figures(figures: dict[str, Figure], folder) -> list[str]:
    """Write figures as PNG into ``folder`` atomically; returns the paths written."""
    from pathlib import Path

    from ._io import atomic_write

    written = []
    for name, fig in figures.items():
        path = Path(folder) / name
        with atomic_write(path) as tmp:
            fig.savefig(tmp, format="png", bbox_inches="tight")
        plt.close(fig)
        written.append(str(path))
    return written


PREDICTION_FIGURE_NAMES = ("spectrum.png", "contact_area.png", "separation.png", "gap_distribution.png", "leak_rate.png",
                           "leak_rate_log.png", "critical_junction.png", "critical_magnification.png",
                           "leak_rate_vs_pressure_difference.png")
