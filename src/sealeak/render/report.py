"""One self-contained HTML report of a case (an edge module: SI in, readable units out).

The file has no external resources: styles are inline in a <style> element, figures are PNG
embedded as base64 data URIs, so it opens in a browser without network access. Contents: the
inputs as written in the case file (with their units), the spectrum and its statistics, the
assumptions (p_c, γ, α, whether the spectrum is a model or a measurement, which theories), every
prediction figure, the result tables (both theories when the case asks for them) and, when the case
has a [rig], the virtual rig.
"""

from __future__ import annotations

import base64
import html
import io
from collections.abc import Mapping, Sequence
from typing import Any

from matplotlib.figure import Figure

from .._version import __version__
from ..cases import CaseResult
from .figures import prediction_figures
from .lab_figures import figure_rig
from .text import fmt

__all__ = ["html_report", "figure_to_data_uri"]

_CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 2em auto; max-width: 70em;
       color: #222; line-height: 1.45; padding: 0 1em; }
h1 { font-size: 1.6em; border-bottom: 2px solid #446; padding-bottom: .2em; }
h2 { font-size: 1.25em; margin-top: 1.8em; color: #335; }
table { border-collapse: collapse; margin: .6em 0; font-size: .9em; }
th, td { border: 1px solid #bbc; padding: .25em .6em; text-align: right; }
th { background: #eef; }
td.k, th.k { text-align: left; }
figure { display: inline-block; margin: .8em; vertical-align: top; }
figure img { max-width: 38em; width: 100%; border: 1px solid #ddd; }
figcaption { font-size: .85em; color: #555; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: .4em .8em; margin: .4em 0; }
"""


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def figure_to_data_uri(fig: Figure) -> str:
    """A matplotlib figure as a ``data:image/png;base64,...`` URI."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]], left: int = 1) -> str:
    out = ["<table>", "<tr>" + "".join(f"<th class=\"k\">{_e(h)}</th>" if i < left else f"<th>{_e(h)}</th>"
                                      for i, h in enumerate(header)) + "</tr>"]
    for row in rows:
        out.append("<tr>" + "".join(f"<td class=\"k\">{_e(c)}</td>" if i < left else f"<td>{_e(c)}</td>"
                                    for i, c in enumerate(row)) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def _inputs(inputs: Mapping[str, Any]) -> str:
    rows = []
    for section, value in inputs.items():
        if isinstance(value, dict):
            for key, v in value.items():
                rows.append((f"[{section}] {key}", v if not isinstance(v, (list, dict)) else _compact(v)))
        else:
            rows.append((section, value))
    return _table(("input (as written in the case file, with its unit)", "value"), rows, left=2)


def _compact(v: Any) -> str:
    if isinstance(v, dict):
        return ", ".join(f"{k} = {x}" for k, x in v.items())
    return ", ".join(str(x) for x in v)


def _figure(name: str, fig: Figure, caption: str) -> str:
    return (f"<figure id=\"fig-{_e(name)}\"><img alt=\"{_e(caption)}\" src=\"{figure_to_data_uri(fig)}\">"
            f"<figcaption>{_e(name)}: {_e(caption)}</figcaption></figure>")


def html_report(results: Sequence[CaseResult], inputs: Mapping[str, Any]) -> str:
    """The HTML text of the report of a case file run (one case, or the variants of a study).

    ``results``: :func:`~sealeak.cases.run_case` of each case; ``inputs``: the case file as the user
    wrote it (:attr:`~sealeak.cases.CaseFile.inputs`), shown with its units.
    """
    cases = [r.case for r in results]
    first = cases[0]
    effective = [r.effective_medium for r in results]
    any_em = any(em is not None for em in effective)
    parts: list[str] = ["<!DOCTYPE html>", "<html lang=\"en\">", "<head>", "<meta charset=\"utf-8\">",
                        f"<title>{_e(first.title)} — sealeak report</title>", f"<style>{_CSS}</style>", "</head>",
                        "<body>", f"<h1>{_e(first.title)}</h1>",
                        f"<p>sealeak {_e(__version__)} — leak rate of a rubber seal from surface roughness "
                        "(Persson contact mechanics, percolation, Poiseuille flow; Lorenz &amp; Persson, "
                        f"EPL 86 (2009) 44006). Case file: <code>{_e(first.source or '—')}</code>.</p>"]

    parts.append("<h2 id=\"inputs\">Inputs</h2>")
    parts.append(_inputs(inputs))

    parts.append("<h2 id=\"spectrum\">Surface roughness spectrum</h2>")
    rows = []
    for c in cases:
        s = c.spectrum
        measured = "model (not a measurement)" if c.spectrum_is_model else f"measurement ({c.surface_model})"
        rows.append((c.label or "—", c.spectrum_note, measured, fmt(s.h_rms * 1e6), fmt(s.slope_rms),
                     fmt(s.curvature_rms), fmt(s.area_ratio), fmt(s.q_min), fmt(s.q_max), fmt(c.q0)))
    parts.append(_table(("variant", "spectrum", "kind", "h_rms (µm)", "slope_rms (1)", "curvature_rms (1/m)",
                         "A_true/A0 (1)", "q_min (1/m)", "q1 (1/m)", "q0 (1/m)"), rows, left=3))

    parts.append("<h2 id=\"assumptions\">Assumptions</h2><ul>")
    theories = {"critical-junction": "critical-junction theory (the reference paper)",
                "effective-medium": "effective-medium theory (2D Bruggeman over the gap distribution P(u))",
                "both": "both the critical-junction and the effective-medium theory"}
    parts.append(f"<li>Leak-rate theory: {_e(theories[first.model])}.</li>")
    parts.append(f"<li>Percolation threshold p_c = {first.percolation_threshold:g}: the critical junction sits where "
                 f"A(ζc)/A0 = 1 − p_c = {1 - first.percolation_threshold:.3g}.</li>")
    parts.append(f"<li>γ = {first.gamma:g} in the interfacial separation ū(ζ) (1: the formula as printed in the paper; "
                 "0.42 recommended by Yang &amp; Persson).</li>")
    parts.append(f"<li>α = {first.alpha:g}: the shape factor of the critical constriction (the paper fits 0.2); "
                 "the effective-medium prediction has no fit factor.</li>")
    kinds = {("model" if "model" in r[2] else "measurement") for r in rows}
    parts.append(f"<li>The roughness spectrum is a {'model' if kinds == {'model'} else 'measurement'}: "
                 f"{_e(first.spectrum_note)}.</li>")
    parts.append(f"<li>q0 = 2π/L = {first.q0:.4g} 1/m ({_e(first.q0_note)}); incompressible Newtonian fluid, "
                 "laminar flow; P0 ≫ ΔP (the fluid pressure does not change the contact); rigid substrate "
                 "unless [substrate] is given.</li>")
    if any_em:
        parts.append("<li>Plain 2D Bruggeman stops percolating at A/A0 = 0.5; numerically exact studies find ≈ 0.42.</li>")
    parts.append("</ul>")

    parts.append("<h2 id=\"results\">Results</h2>")
    for r in results:
        case, res, em = r.case, r.critical_junction, r.effective_medium
        if case.label:
            parts.append(f"<h3>{_e(case.label)}</h3>")
        header = ["P0 (kPa)", "A(ζ1)/A0", "ζc", "λc (µm)", "u_c (µm)", "Q critical junction (m³/s)"]
        if em is not None:
            header += ["ū(1) (µm)", "mean of P(u) (µm)", "σ_eff (m³/(Pa·s))", "Q effective medium (m³/s)"]
        rows = []
        for i in range(len(res)):
            row = [fmt(res.squeeze_pressure[i] / 1e3), fmt(res.contact_area_at_cutoff[i], ".3f"),
                   fmt(res.critical_magnification[i]), fmt(res.critical_wavelength[i] * 1e6),
                   fmt(res.critical_gap[i] * 1e6), fmt(res.leak_rate[i], ".4e")]
            if em is not None:
                row += [fmt(em.mean_gap[i] * 1e6), fmt(em.gap_distribution_mean[i] * 1e6),
                        fmt(em.effective_conductivity[i], ".4e") if em.percolates[i] else "—",
                        fmt(em.leak_rate[i], ".4e")]
            rows.append(row)
        parts.append(_table(header, rows, left=0))
        notes = list(res.messages) + ([f"effective medium: {m}" for m in em.messages] if em is not None else [])
        for m in notes:
            parts.append(f"<p class=\"note\">{_e(m)}</p>")

    parts.append("<h2 id=\"figures\">Figures</h2>")
    captions = {
        "spectrum.png": "surface roughness power spectrum C(q)",
        "contact_area.png": "apparent relative contact area against magnification",
        "separation.png": "mean separation ū(ζ) and u1(ζ)",
        "gap_distribution.png": "distribution of interfacial separations P(u)",
        "leak_rate.png": "leak rate against squeeze pressure",
        "leak_rate_log.png": "leak rate against squeeze pressure, log scale",
        "critical_junction.png": "critical constriction against squeeze pressure",
        "critical_magnification.png": "critical magnification against squeeze pressure",
        "leak_rate_vs_pressure_difference.png": "leak rate against pressure difference",
    }
    figures = prediction_figures(results)
    for name, fig in figures.items():
        parts.append(_figure(name, fig, captions.get(name, name)))

    pred = results[0].rig
    if len(cases) == 1 and first.rig is not None and pred is not None:
        rig = first.rig
        parts.append("<h2 id=\"rig\">Virtual water-column rig</h2>")
        parts.append(f"<p>Load {rig.load:.4g} N ({_e(rig.load_note)}) on the seal: P0 = {pred.squeeze_pressure / 1e3:.4g} kPa; "
                     f"cylinder diameter {rig.cylinder_diameter * 100:.4g} cm, initial height {rig.initial_height * 100:.4g} cm, "
                     f"ρ = {rig.density:g} kg/m³, ΔP = ρgH.</p>")
        rows = []
        for name, k in pred.conductance.items():
            col = pred.columns[name]
            rows.append((name, fmt(k, ".4e"), fmt(col.final_height * 100), fmt(pred.drain_time[name] / 60)))
        parts.append(_table(("model", "K = Q/ΔP (m³/(s·Pa))", "final height (cm)", "time to final height (min)"), rows))
        parts.append(_figure("rig.png", figure_rig(rig, pred.columns, pred.squeeze_pressure), "water height against time"))
        for m in pred.messages:
            parts.append(f"<p class=\"note\">{_e(m)}</p>")

    parts.append("</body>")
    parts.append("</html>")
    return "\n".join(parts) + "\n"
