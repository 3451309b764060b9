"""Renderings of the convergence and validation study (``sealeak simulate --grid 64,128,256``): table, JSON, figures.

The numbers come from :func:`sealeak.cases.convergence.convergence_study` (docs/theory.md §6.8); this
module only shows them: per grid α and A/A0 with their standard errors, the threshold, the extrapolation
to the continuum, the threshold beside the published values, and the flags.
"""

from __future__ import annotations

from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..cases import Case
from ..cases.convergence import PUBLISHED_THRESHOLDS, ConvergenceStudy, Extrapolation, GridStatistics
from ..io.quantities import units_of
from .notes import worded
from .plotstyle import STYLE, color, finish_axes, laid_out, new_figure, place_legend, spans_decades, subtitle
from .records import case_summary, json_document, json_value
from .simulation import SIMULATION_UNITS, simulation_rows
from .text import fmt

__all__ = ["convergence_table", "convergence_json", "convergence_figures", "CONVERGENCE_FIGURE_NAMES",
           "CONVERGENCE_UNITS"]

#: The figures of a study's ``--plots``.
CONVERGENCE_FIGURE_NAMES = ("convergence_alpha.png", "convergence_threshold.png")

#: Units of a study's keys: the per-grid records' (:data:`~sealeak.render.simulation.SIMULATION_UNITS`), each
#: grid's statistics' and the extrapolations' (declared on :class:`GridStatistics`' and :class:`Extrapolation`'s fields).
CONVERGENCE_UNITS = SIMULATION_UNITS | units_of(GridStatistics) | units_of(Extrapolation)


def _model(fit: Extrapolation) -> str:
    """'p = 1 fixed' or 'p = 1.3 ± 0.2 fitted'."""
    if fit.exponent_fitted:
        return f"p = {fit.exponent:.3g} ± {fit.exponent_stderr:.2g} fitted"
    return f"p = {fit.exponent:g} fixed"


def _verdict(ok: bool | None) -> str:
    return {True: "converged", False: "NOT converged", None: "cannot tell"}[ok]


def _pm(x: float, se: float, spec: str = ".3f") -> str:
    """'0.412 ± 0.013' (or '0.412 ± —' without a standard error, '—' without a value)."""
    if not np.isfinite(x):
        return "—"
    return f"{x:{spec}} ± {se:.2g}" if np.isfinite(se) else f"{x:{spec}} ± —"


def convergence_table(case: Case, study: ConvergenceStudy) -> str:
    """The text ``sealeak simulate --grid N1,N2,...`` prints: per grid, extrapolation, literature, flags."""
    first = study.results[0]
    grids = ", ".join(str(n) for n in study.grids)
    spacings = ", ".join(f"{g.spacing * 1e6:.3g}" for g in study.statistics)
    lines = [f"{case.title}: convergence study of the numerically exact route",
             f"grids {grids} on a square of side {study.size * 1e3:.4g} mm (lattice spacing a = L/N = {spacings} µm), "
             f"{first.realizations} realisation(s) per grid, seed {first.seed}",
             "± se: standard error of the mean, sd/√n over the n realisations used (for α: the percolating ones)"]
    if first.gas is not None:
        lines.append("α here is that of the incompressible formula with the gas's viscosity; α_gas is in each grid's "
                     "single-grid run (--grid N), not in the study")
    lines.append("")
    lines.append(f"{'N':>5} {'a (µm)':>7} {'P0 (kPa)':>9} {'A/A0 ± se':>17} {'α ± se':>19} {'n':>3}")
    for g in study.statistics:
        for i, p in enumerate(study.squeeze_pressure):
            star = "*" if np.isfinite(g.alpha[i]) and not g.alpha_resolved[i] else " "
            lines.append(f"{g.grid:5d} {g.spacing * 1e6:7.3g} {p / 1e3:9.4g} "
                         f"{_pm(g.relative_contact_area[i], g.relative_contact_area_stderr[i]):>17} "
                         f"{_pm(g.alpha[i], g.alpha_stderr[i], '.3g'):>18}{star} {g.alpha_count[i]:3d}")
    lines.append("* λc spans fewer than 8 grid cells: α reflects the grid, left out of the extrapolation")
    lines += ["", "percolation threshold: the relative contact area A/A0 at which the non-contact area stops "
                  "percolating (inlet to outlet)",
              f"{'N':>5} {'a (µm)':>7} {'A/A0 ± se':>17} {'n':>3}"]
    for g in study.statistics:
        lines.append(f"{g.grid:5d} {g.spacing * 1e6:7.3g} {_pm(g.threshold, g.threshold_stderr):>17} {g.threshold_count:3d}")
    lines += ["", "continuum extrapolation: X(a) = X∞ + c·a^p by weighted least squares (weights 1/se²), a = L/N → 0; "
                  "se of X∞ from the fit's covariance, scaled by √(χ²/dof) when that exceeds 1; "
                  "converged: the finest two grids agree within their combined se",
              f"{'quantity':>22} {'X∞ ± se':>19} {'model':>26} {'grids':>5} {'χ²/dof':>7}  finest two grids"]
    rows = [("threshold A/A0", study.threshold_extrapolation, study.threshold_converged)]
    rows += [(f"α at P0 = {p / 1e3:.4g} kPa", fit, ok)
             for p, fit, ok in zip(study.squeeze_pressure, study.alpha_extrapolation, study.alpha_converged, strict=True)]
    missing = [name for name, fit, _ in rows if fit is None]
    for name, fit, ok in rows:
        if fit is None:
            continue
        lines.append(f"{name:>22} {_pm(fit.value, fit.stderr, '.4g'):>19} {_model(fit):>26} {fit.points:5d} "
                     f"{fmt(fit.chi2_reduced, '7.3g')}  {_verdict(ok)}")
    if missing:
        lines.append(f"{'':>22} no extrapolation (fewer than two grids with a value) for {len(missing)} of {len(rows)}: "
                     "see the flags")
    lines += ["", "percolation threshold against published values (self-affine surfaces):"]
    for c in study.comparison:
        diff = f"{c.difference:+.2g} se" if np.isfinite(c.difference) else "— (no se)"
        lines.append(f"  ours, {c.ours_label}: {_pm(c.ours, c.ours_stderr)}   vs {c.source}: {c.published:g}   "
                     f"difference {c.ours - c.published:+.3f} = {diff}")
    if not study.comparison:
        lines.append("  no threshold found (see the notes)")
    lines.append("  conditions: " + study.conditions)
    if study.flags:
        lines += ["", "flags (what the numbers above cannot carry):"]
        lines += [f"  - {f}" for f in worded(study.flags)]
    notes = [(r.grid, n) for r in study.results for n in worded(r.notes)]
    if notes:
        lines.append("")
        lines += [f"note (grid {n}): {text}" for n, text in notes]
    return "\n".join(lines) + "\n"


def _fit_json(fit: Extrapolation | None, ok: bool | None) -> dict[str, Any] | None:
    if fit is None:
        return None
    return {"value": json_value(fit.value), "stderr": json_value(fit.stderr),
            "stderr_unscaled": json_value(fit.stderr_unscaled), "slope": json_value(fit.slope),
            "exponent": fit.exponent, "exponent_stderr": json_value(fit.exponent_stderr),
            "exponent_fitted": fit.exponent_fitted, "chi2": json_value(fit.chi2), "dof": fit.dof,
            "chi2_reduced": json_value(fit.chi2_reduced), "weighted": fit.weighted, "points": fit.points,
            "monotonic": fit.monotonic, "converged": ok}


def convergence_json(case: Case, study: ConvergenceStudy) -> str:
    """The ``simulate --json`` document of a study: ``grids`` (per grid its records), ``extrapolation``, ``threshold``."""
    grids = []
    for res, g in zip(study.results, study.statistics, strict=True):
        rows = simulation_rows(res)
        for i, row in enumerate(rows):
            row |= {"alpha_stderr": json_value(g.alpha_stderr[i]), "alpha_count": int(g.alpha_count[i]),
                    "relative_contact_area_stderr": json_value(g.relative_contact_area_stderr[i])}
        grids.append({"grid": g.grid, "spacing": g.spacing, "realizations": g.realizations, "results": rows,
                      "percolation_threshold": json_value(g.threshold),
                      "percolation_threshold_stderr": json_value(g.threshold_stderr),
                      "percolation_threshold_count": g.threshold_count,
                      "spectrum_cut_wavevector": g.q_cut, "spectrum": res.spectrum_note, "notes": worded(res.notes)})
    doc: dict[str, Any] = {
        "units": CONVERGENCE_UNITS,
        "grids": grids,
        "extrapolation": {
            "model": "X(a) = X_inf + slope * a^exponent, a = size/grid (m); weighted least squares, weights 1/stderr^2; "
                     "stderr of X_inf from the covariance, scaled by sqrt(chi2/dof) when > 1; exponent fixed at 1 below "
                     "4 grids, else fitted; converged: the finest two grids agree within sqrt(se1^2 + se2^2)",
            "alpha": [{"squeeze_pressure": float(p)} | (_fit_json(fit, ok) or {"value": None})
                      for p, fit, ok in zip(study.squeeze_pressure, study.alpha_extrapolation, study.alpha_converged,
                                            strict=True)],
            "threshold": _fit_json(study.threshold_extrapolation, study.threshold_converged),
        },
        "threshold": {
            "quantity": "relative contact area at which the non-contact area stops percolating (inlet to outlet)",
            "comparison": [{"ours": c.ours_label, "value": json_value(c.ours), "stderr": json_value(c.ours_stderr),
                            "source": c.source, "published": c.published, "difference": json_value(c.ours - c.published),
                            "difference_in_stderr": json_value(c.difference)} for c in study.comparison],
            "conditions": study.conditions,
            "hurst_estimate": json_value(study.hurst),
            "rolloff_wavelengths": json_value(study.rolloff_wavelengths),
        },
        "settings": {"grids": list(study.grids), "realizations": study.results[0].realizations,
                     "seed": study.results[0].seed, "size": study.size},
        "spread_note": "*_stderr are standard errors of the mean (sd/sqrt(n), n = *_count); *_std standard deviations "
                       "over the realisations (ddof = 1)",
        "flags": worded(study.flags),
        "case": case_summary(case),
    }
    return json_document(doc)


def convergence_figures(case: Case, study: ConvergenceStudy) -> dict[str, Figure]:
    """The study's figures by file name: α against A/A0 per grid, and the threshold and α against a."""
    return {"convergence_alpha.png": _alpha_figure(case, study), "convergence_threshold.png": _threshold_figure(study)}


@laid_out
def _alpha_figure(case: Case, study: ConvergenceStudy) -> Figure:
    """α ± se against A/A0 ± se, one colour per grid, the extrapolated α∞ and the theory's α = 1."""
    fig, ax = new_figure("α against relative contact area, per grid (± standard error)")
    values: list[float] = []
    coarse: list[float] = []
    for k, g in enumerate(study.statistics):
        ok = np.isfinite(g.alpha)
        good = ok & g.alpha_resolved
        bad = ok & ~g.alpha_resolved
        if good.any():
            ax.errorbar(g.relative_contact_area[good], g.alpha[good], yerr=np.nan_to_num(g.alpha_stderr[good]),
                        xerr=np.nan_to_num(g.relative_contact_area_stderr[good]), fmt="o", ms=4, capsize=2,
                        color=color(k), label=f"N = {g.grid} (a = {g.spacing * 1e6:.3g} µm)")
            values += list(g.alpha[good])
        if bad.any():
            ax.plot(g.relative_contact_area[bad], g.alpha[bad], "o", mfc="none", ms=4, color=color(k),
                    label=f"N = {g.grid}: λc < 8 cells (grid too coarse)")
            coarse += list(g.alpha[bad])
    fine = study.statistics[-1]
    ext = np.array([f.value if f is not None else np.nan for f in study.alpha_extrapolation])
    ext_se = np.array([f.stderr if f is not None else np.nan for f in study.alpha_extrapolation])
    show = np.isfinite(ext) & np.isfinite(fine.relative_contact_area)
    logy = spans_decades(values + list(ext[show]))
    if logy:
        show &= ext > 0
    if show.any():
        ax.errorbar(fine.relative_contact_area[show], ext[show], yerr=np.nan_to_num(ext_se[show]), fmt="D", ms=5,
                    capsize=3, color="black", mfc="white", label=f"extrapolated a → 0 (at the N = {fine.grid} A/A0)")
        values += list(ext[show])
    ax.axhline(1.0, color="0.3", ls="--", lw=1.0, label="theory: α = 1")
    if case.alpha != 1.0:
        ax.axhline(case.alpha, color="0.5", ls=":", lw=1.0, label=f"case α = {case.alpha:g}")
    if logy:
        ax.set_yscale("log")
    elif values:  # coarse-grid α can be absurdly large: shown up to 3 times the resolved values' range
        top = max(1.0, float(np.nanmax(values)))
        top = max([top] + [v for v in coarse if v <= 3.0 * top])
        ax.set_ylim(0.0, 1.1 * top)
    if not values:
        ax.text(0.5, 0.5, "no α: no realisation percolates at any squeeze pressure", transform=ax.transAxes,
                ha="center", va="center")
    ax.set_xlabel("relative contact area A/A0 (mean over realisations)")
    ax.set_ylabel("α = Q_num / Q_cj(α = 1)")
    subtitle(ax, f"{study.results[0].realizations} realisation(s) per grid, square of side {study.size * 1e3:.3g} mm")
    finish_axes(ax)
    place_legend(ax)
    return fig


def _pick_pressure(study: ConvergenceStudy) -> int | None:
    """The squeeze pressure whose α is shown against a: the one extrapolated from the most grids (middle one of ties)."""
    counts = np.array([f.points if f is not None else 0 for f in study.alpha_extrapolation])
    if not counts.size or counts.max() < 2:
        return None
    best = np.flatnonzero(counts == counts.max())
    return int(best[best.size // 2])


def _against_spacing(ax: Axes, study: ConvergenceStudy, x: np.ndarray, se: np.ndarray, fit: Extrapolation | None,
                     use: np.ndarray) -> None:
    """Points X ± se against a (µm), the fitted X∞ + c·a^p from a = 0, and X∞ ± se at a = 0."""
    a = np.array([g.spacing for g in study.statistics])
    ax.errorbar(a[use] * 1e6, x[use], yerr=np.nan_to_num(se[use]), fmt="o", ms=5, capsize=3, color=color(0),
                label="per grid, ± se")
    for k in np.flatnonzero(use):
        ax.annotate(f"N = {study.statistics[k].grid}", (a[k] * 1e6, x[k]), textcoords="offset points", xytext=(6, 6),
                    fontsize=7, color="0.3")
    if fit is not None:
        grid_a = np.linspace(0.0, a.max() * 1.05, 200)
        ax.plot(grid_a * 1e6, fit.value + fit.slope * grid_a**fit.exponent, "-", color=color(1), lw=1.0,
                label=f"fit X∞ + c·a^p ({_model(fit)})")
        ax.errorbar([0.0], [fit.value], yerr=[np.nan_to_num(fit.stderr)], fmt="D", ms=5, capsize=3, color="black",
                    mfc="white", label=f"extrapolated: {_pm(fit.value, fit.stderr, '.3g')}")
    ax.set_xlim(left=-0.04 * a.max() * 1e6, right=a.max() * 1.12e6)


@laid_out
def _threshold_figure(study: ConvergenceStudy) -> Figure:
    """The threshold (top) and α at one squeeze pressure (bottom) against a = L/N, with the extrapolation."""
    with mpl.rc_context(STYLE):
        fig = Figure(figsize=(6.4, 7.4), layout="constrained")
        top, bottom = fig.subplots(2, 1)
    x = np.array([g.threshold for g in study.statistics])
    se = np.array([g.threshold_stderr for g in study.statistics])
    use = np.isfinite(x)
    if use.any():
        _against_spacing(top, study, x, se, study.threshold_extrapolation, use)
    if use.any():
        lo, hi = min(v for _, v in PUBLISHED_THRESHOLDS), max(v for _, v in PUBLISHED_THRESHOLDS)
        top.axhspan(lo, hi, color="0.8", zorder=0,
                    label="published: " + ", ".join(f"{v:g} ({s.split(',')[0]})" for s, v in PUBLISHED_THRESHOLDS))
    else:
        top.text(0.5, 0.5, "no percolation threshold at any grid\n(--no-threshold, or the search found none)",
                 transform=top.transAxes, ha="center", va="center", fontsize=9)
        top.set_yticks([])
        top.set_xlim(-0.04 * study.statistics[0].spacing * 1e6, study.statistics[0].spacing * 1.12e6)
    top.set_ylabel("threshold A/A0")
    top.set_title("Percolation threshold: contact area at which the non-contact area stops percolating", fontsize=9)
    top.set_xlabel("lattice spacing a = L/N (µm); a = 0: the continuum")
    k = _pick_pressure(study)
    if k is None:
        bottom.text(0.5, 0.5, "α is extrapolated at no squeeze pressure (fewer than two grids with a resolved α)",
                    transform=bottom.transAxes, ha="center", va="center", fontsize=8)
        bottom.set_yticks([])
    else:
        xa = np.array([g.alpha[k] for g in study.statistics])
        sa = np.array([g.alpha_stderr[k] for g in study.statistics])
        ua = np.isfinite(xa) & np.array([bool(g.alpha_resolved[k]) for g in study.statistics])
        _against_spacing(bottom, study, xa, sa, study.alpha_extrapolation[k], ua)
        bottom.set_ylabel("α = Q_num / Q_cj(α = 1)")
        bottom.set_title(f"α at P0 = {study.squeeze_pressure[k] / 1e3:.4g} kPa (the pressure extrapolated from the most "
                         "grids; theory: α = 1)", fontsize=9)
    bottom.set_xlabel("lattice spacing a = L/N (µm); a = 0: the continuum")
    for ax in (top, bottom):  # everything drawn and labelled before the first legend fixes the layout
        finish_axes(ax)
    for ax in (top, bottom):
        place_legend(ax)
    return fig
