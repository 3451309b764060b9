"""One self-contained HTML report of a case (an edge module: SI in, readable units out).

The file has no external resources: styles are inline in a <style> element, figures are PNG
embedded as base64 data URIs, so it opens in a browser without network access. Contents: the
inputs as written in the case file (with their units, the ``[study]`` section included), the
spectrum and its statistics, the assumptions (p_c, γ, α, the fluid's molecular size, whether the
spectrum is a model or a measurement, which theories), the warnings about the inputs, the result
tables with the same columns and digits as ``sealeak predict`` (:func:`~sealeak.render.text.prediction_columns`,
validity verdicts included), every prediction figure in a two-column grid with a caption saying
what it shows and, when the case has a [rig], the virtual rig (K, Q and τ at the initial height,
the time to the final height).

For an O-ring or pressure-profile seal (every result has a ``band``, docs/theory.md §10) the report
adds a Seal section (geometry, the contact relations used, each load's force per length, contact
width and q0), shows the band table of ``sealeak predict`` instead of the uniform
one, and the band figures of :mod:`sealeak.render.band` with their own captions.
"""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Mapping, Sequence
from typing import Any

from matplotlib.figure import Figure

from .._version import __version__
from ..cases import Case, CaseResult
from ..cases.leak_tests import DecayPrediction
from ..cases.loader import shown_source
from ..cases.sobol import SobolIndices
from ..cases.uncertainty import UncertaintyResult
from ..lab.rig import RigSetup
from .band import is_band_run
from .figures import ML_PER_MIN_PER_M3_PER_S, figure_png, is_gas_run, prediction_figures
from .lab import decay_condition, decay_text
from .lab_figures import figure_decay, figure_rig
from .life import volume_limit
from .notes import worded
from .sensitivity import sensitivity_columns, sensitivity_heading, sensitivity_legend, sensitivity_sentences
from .text import GAS_INCOMPRESSIBLE_NOTE, band_legend, capillary_notes, capillary_tables, fmt, gas_notes, gas_tables, prediction_columns, validity_notes
from .uncertainty import passing_lines, uncertainty_columns, uncertainty_heading, uncertainty_legend
from .uncertainty_figures import uncertainty_figure_names, uncertainty_figures

__all__ = ["html_report", "figure_to_data_uri"]

_CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 2em auto; max-width: 82em;
       color: #222; line-height: 1.45; padding: 0 1em; }
h1 { font-size: 1.6em; border-bottom: 2px solid #446; padding-bottom: .2em; }
h2 { font-size: 1.25em; margin-top: 1.8em; color: #335; }
h3 { font-size: 1.05em; margin-top: 1.2em; }
table { border-collapse: collapse; margin: .6em 0; font-size: .9em; }
th, td { border: 1px solid #bbc; padding: .25em .6em; text-align: right; font-variant-numeric: tabular-nums; }
th { background: #eef; }
td.k, th.k { text-align: left; }
tr.invalid td { color: #8a5a00; background: #fff8e0; }
.wide { overflow-x: auto; }
.figures { display: grid; grid-template-columns: repeat(auto-fill, minmax(30em, 1fr)); gap: 1.2em 1.6em; }
figure { margin: 0; }
figure img { width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: .88em; color: #444; margin-top: .3em; }
.note { background: #f3f5fa; border-left: 4px solid #99a; padding: .4em .8em; margin: .4em 0; }
.warning { background: #fff8e0; border-left: 4px solid #e0b000; padding: .4em .8em; margin: .4em 0; }
.legend { font-size: .85em; color: #555; }
"""


def _e(x: Any) -> str:
    return html.escape(str(x), quote=True)


def figure_to_data_uri(fig: Figure) -> str:
    """A matplotlib figure as a ``data:image/png;base64,...`` URI."""
    return "data:image/png;base64," + base64.b64encode(figure_png(fig)).decode("ascii")


def _table(header: Sequence[str], rows: Sequence[Sequence[Any]], left: int = 1,
           row_classes: Sequence[str] | None = None, values: Sequence[Sequence[Any]] | None = None) -> str:
    """An HTML table; ``values[n][i]``, where given and a finite float, is cell (n, i)'s number in full precision
    (its ``data-value`` attribute: the cell shows it rounded)."""
    out = ["<div class=\"wide\"><table>",
           "<tr>" + "".join(f"<th class=\"k\">{_e(h)}</th>" if i < left else f"<th>{_e(h)}</th>"
                            for i, h in enumerate(header)) + "</tr>"]
    for n, row in enumerate(rows):
        cls = f" class=\"{row_classes[n]}\"" if row_classes and row_classes[n] else ""
        cells = []
        for i, c in enumerate(row):
            v = values[n][i] if values is not None else None
            attrs = (" class=\"k\"" if i < left else "") + (f" data-value=\"{v!r}\"" if isinstance(v, float) and math.isfinite(v) else "")
            cells.append(f"<td{attrs}>{_e(c)}</td>")
        out.append(f"<tr{cls}>" + "".join(cells) + "</tr>")
    out.append("</table></div>")
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


def _figure(name: str, number: int, fig: Figure, caption: str) -> str:
    return (f"<figure id=\"fig-{_e(name)}\"><img alt=\"{_e(caption)}\" src=\"{figure_to_data_uri(fig)}\">"
            f"<figcaption><b>Figure {number}.</b> {_e(caption)}</figcaption></figure>")


#: What each prediction figure shows (the report's captions); the reference paper's figure where there is one.
CAPTIONS = {
    "spectrum.png": "Surface roughness power spectrum C(q) against wavevector q (log-log), the input of the contact "
                    "mechanics; the dotted line marks the lowest wavevector q0 = 2π/L.",
    "contact_area.png": "Relative contact area A(ζ)/A0 against magnification ζ = q/q0 at a few squeeze pressures: "
                        "where a curve crosses A/A0 = 1 − p_c (dashed) is the critical magnification ζc (dots), "
                        "the scale at which the open channels first cross the seal.",
    "separation.png": "Mean interfacial separation ū(ζ) (solid) and the separation u1(ζ) of the patches that lose "
                      "contact at ζ (dashed), at the same pressures; the dots are the critical gaps u_c = u1(ζc).",
    "gap_distribution.png": "Distribution of interfacial separations P(u), drawn as u·P(u) on a log u axis (the "
                            "probability per unit ln u); the part in contact (u = 0) is given in the legend, dotted "
                            "lines mark the mean separation ū(1).",
    "leak_rate.png": "Leak rate Q against squeeze pressure P0 (the reference paper's Fig. 6; log scale when the "
                     "curves differ by decades), in m³/s on the left and ml/min on the right.",
    "leak_rate_log.png": "Leak rate Q against squeeze pressure P0 on a log scale (the reference paper's Fig. 7), in "
                         "m³/s on the left and ml/min on the right.",
    "critical_junction.png": "The critical constriction against squeeze pressure: its height u_c (solid) and width "
                             "λc = L/ζc (dashed), the reference paper's Fig. 8.",
    "critical_magnification.png": "Critical magnification ζc against squeeze pressure (the reference paper's Fig. 9).",
    "leak_rate_vs_pressure_difference.png": "Leak rate Q against the fluid pressure difference ΔP at one squeeze "
                                            "pressure per case: a straight line through the origin (the reference "
                                            "paper's Fig. 5).",
}
#: Captions of the figures of an O-ring or pressure-profile seal (docs/theory.md §10).
BAND_CAPTIONS = {
    "spectrum.png": "Surface roughness power spectrum C(q) against wavevector q (log-log), the input of the contact "
                    "mechanics; the dotted line (and the shaded range, when the loads differ) marks the lowest "
                    "wavevector q0 of the loads (2π/w with w the load's contact width, unless the case file sets q0).",
    "pressure_profile.png": "Nominal contact pressure p(x) across the sealing band, one curve per load; below, for each "
                            "load, the narrowest part of the band that holds 90 % of the flow resistance R = ∫dx/σ(p(x)): "
                            "where the seal is decided.",
    "local_critical_gap.png": "Local critical gap u_c(x) across the band (log scale): the critical-junction gap of a "
                              "uniform seal at the local pressure p(x); the smallest u_c, where the pressure is highest, "
                              "sets the leak rate. Dashed: the fluid's molecular size, below which no continuum flow is "
                              "possible.",
    "leak_rate.png": "Leak rate Q through the band against the load (log scale), in m³/s on the left and ml/min on the "
                     "right: solid through the band (strips in series), dashed in the same colour a uniform seal at the "
                     "mean contact pressure; × at the bottom: no leak channel, the band seals.",
}
_HOLLOW = (" Hollow markers are results outside the theory's validity (see the valid column); they do not set "
           "the axis limits.")
_WITH_VERDICTS = {"leak_rate.png", "leak_rate_log.png", "critical_junction.png", "critical_magnification.png"}


#: The captions of a gas case's leak-rate figures, which draw the pV throughput Q_pV (docs/theory.md §11.9.1).
GAS_CAPTIONS = {
    "leak_rate.png": "Gas leak rate Q_pV against squeeze pressure P0 (log scale when the curves differ by decades), in "
                     "mbar·l/s on the left and Pa·m³/s on the right: the pV throughput of each theory (solid) and, dashed "
                     "where computed and not the same numbers, its helium-equivalent leak rate.",
    "leak_rate_log.png": "Gas leak rate Q_pV against squeeze pressure P0 on a log scale, in mbar·l/s on the left and "
                         "Pa·m³/s on the right: the pV throughput of each theory (solid) and, dashed where computed and "
                         "not the same numbers, its helium-equivalent leak rate.",
    "leak_rate_vs_pressure_difference.png": "Gas leak rate Q_pV against the pressure difference ΔP = P_a − P_b at the "
                                            "case's downstream pressure P_b and one squeeze pressure per case, in "
                                            "mbar·l/s on the left and Pa·m³/s on the right: not a straight line, the gas "
                                            "expands along the channel (without slip K (P_a² − P_b²)/2); dotted: the "
                                            "case's ΔP.",
}
GAS_BAND_CAPTIONS = {
    "leak_rate.png": "Gas leak rate Q_pV through the band against the load (log scale), in mbar·l/s on the left and "
                     "Pa·m³/s on the right: solid the case's gas through the band (strips in series), dashed in the same "
                     "colour its helium-equivalent leak rate where computed and not the same numbers; × at the bottom: no "
                     "leak channel, the band seals.",
}


#: What the figures of the seal over its life show (:mod:`sealeak.render.life`).
LIFE_CAPTIONS = {
    "leak_rate_vs_time.png": "The leak rate against the time since assembly (log axis) at each temperature, one panel "
                             "per load: the rubber relaxes (or creeps) with time, faster when warm.",
    "leak_rate_vs_temperature.png": "The leak rate against the temperature at each time since assembly, one panel per "
                                    "load: the fluid, the relaxation and an O-ring's compression follow the temperature.",
}


def _caption(name: str, any_invalid: bool, band: bool = False, gas: bool = False) -> str:
    text = ((GAS_BAND_CAPTIONS if band else GAS_CAPTIONS).get(name) if gas else None) or LIFE_CAPTIONS.get(name) or \
        (BAND_CAPTIONS if band else CAPTIONS).get(name, name)
    return text + (_HOLLOW if any_invalid and name in _WITH_VERDICTS else "")


def _result_table(r: CaseResult, which: str) -> str:
    header, rows = prediction_columns(r, which)
    verdicts = [i for i, h in enumerate(header) if h.startswith("valid")]
    classes = ["invalid" if any(row[i].strip().startswith("NO") or "/NO" in row[i] for i in verdicts) else ""
               for row in rows]
    return _table(header, rows, left=0, row_classes=classes)


def _gas_tables(r: CaseResult) -> list[str]:
    """The gas and capillarity tables of ``sealeak predict`` (:func:`~sealeak.render.text.gas_tables`,
    :func:`~sealeak.render.text.capillary_tables`); each cell's ``data-value`` is the ``predict --json`` record's value."""
    records = r.records()
    parts = []
    for title, cols in gas_tables(r) + capillary_tables(r):
        parts.append(f"<p><b>{_e(title[0].upper() + title[1:])}</b></p>")
        rows = [[c[2][i] for c in cols] for i in range(len(records))]
        values = [[records[i].get(c[3]) if c[3] else None for c in cols] for i in range(len(records))]
        parts.append(_table([c[0] for c in cols], rows, left=0, values=values))
    parts += [f"<p class=\"legend\">{_e(n)}</p>" for n in gas_notes(r) + capillary_notes(r)]
    return parts


def _band_section(results: Sequence[CaseResult]) -> list[str]:
    """The seal of an O-ring or pressure-profile case: its geometry, the relations used and each load's contact.

    Variants of a study with the same seal (e.g. a study of fluids) share one description.
    """
    described: dict[str, list[str]] = {}
    for r in results:
        if r.band is None:
            continue
        band, b = r.band.band, r.band
        faces = ("one rough face" if band.faces == 1 else
                 f"{band.faces} faces in parallel (the groove bottom counted as rough as the counterface)")
        if band.kind == "o-ring":
            part = [f"<p>O-ring, cross-section d = {(band.cross_section_diameter or 0) * 1e3:.4g} mm, seal line "
                    f"diameter {(band.mean_diameter or 0) * 1e3:.4g} mm: seal line length Ly = {band.length * 1e3:.4g} mm; "
                    f"{_e(faces)}.</p>"]
        else:
            part = [f"<p>Pressure profile from <code>{_e(shown_source(band.profile_source) if band.profile_source else '—')}</code>, seal line length "
                    f"Ly = {band.length * 1e3:.4g} mm; {_e(faces)}.</p>"]
        part += [f"<p class=\"note\">{_e(note)}</p>" for note in band.notes[:1]]
        load_head = "compression ε (%)" if band.load_name == "compression" else "profile scale (1)"
        loads = [fmt(100 * v if band.load_name == "compression" else v) for v in band.loads]
        cols = [loads, [fmt(v) for v in b.force_per_length], [fmt(v * 1e3) for v in b.contact_width], [fmt(v) for v in b.q0]]
        part.append(_table([load_head, "force per length f (N/m)", "contact width w (mm)", "q0 (1/m)"],
                           [list(row) for row in zip(*cols)], left=0))
        described.setdefault("\n".join(part), []).append(r.case.label)
    parts = ["<h2 id=\"seal\">Seal</h2>"]
    for text, labels in described.items():
        if len(described) > 1 and any(labels):
            parts.append(f"<h3>{_e(', '.join(label for label in labels if label))}</h3>")
        parts.append(text)
    return parts


def _gas_assumptions(cases: Sequence[Case], band: bool) -> list[str]:
    """What the gas model assumes (docs/theory.md §11.1–§11.5, §11.9), for the gas cases among ``cases``."""
    gas = next((c.gas for c in cases if c.gas is not None), None)
    if gas is None:
        return [] if not any(c.helium_equivalent for c in cases) else [_HELIUM_ASSUMPTION]
    slip = ("no slip: f = 1 at every Kn, the continuum law (to show how much rarefaction adds)" if gas.rarefaction == "no-slip"
            else f"{gas.rarefaction}: slip and, at large Kn, free-molecular flow through the factor f(Kn) on the slit "
                 "conductance (" + ("Beskok &amp; Karniadakis 1999" if gas.rarefaction == "beskok-karniadakis" else
                                    "the kinetic theory of a slit, linearized BGK equation")
                 + ", diffuse walls; docs/theory.md §11.4)")
    gap = ("u_c at the peak contact pressure (the effective medium: its u_e there) for the whole band, which errs "
           "towards a larger leak rate" if band else "u_c (the effective medium: u_e)")
    out = ["<li>The gas: an ideal gas (p = ρ R_s T) in compressible, isothermal, laminar flow (Reynolds and Mach numbers "
           "≪ 1, the walls hold it at T), docs/theory.md §11.3: its leak rate is the pV throughput Q_pV = K ∫ p f(Kn) dp "
           "from P_b to P_a, not K ΔP, with K the seal's no-slip conductance computed with the gas's viscosity (one "
           "viscosity for the whole pressure drop: a dilute gas's does not depend on pressure, §11.1); the contact "
           "does not depend on the fluid.</li>",
           f"<li>Rarefaction {slip}; Kn = λ/h at the gap h of the narrowest constriction, {_e(gap)} (§11.9), integrated "
           "along the pressure drop (§11.5); Kn and the flow regime in the gas tables are those at the mean pressure "
           "(P_a + P_b)/2.</li>"]
    if any(c.helium_equivalent for c in cases):
        out.append(_HELIUM_ASSUMPTION)
    return out


#: The helium equivalent's conditions (docs/theory.md §11.9).
_HELIUM_ASSUMPTION = ("<li>The helium-equivalent leak rate (He-eq) is helium through the same seal in the standard test, "
                      "1 bar (absolute) against vacuum at 20 °C: the seal's K scaled by μ_case/μ_He, the same gap, "
                      "helium's rarefaction (docs/theory.md §11.9).</li>")


def _decay_section(result: CaseResult, pred: DecayPrediction, number: int) -> list[str]:
    """The virtual pressure-decay test (docs/theory.md §11.7): the same text as ``sealeak rig``, and P(t)."""
    case = result.case
    parts = ["<h2 id=\"rig\">Virtual pressure-decay test</h2>", f"<pre style=\"white-space: pre-wrap\">{_e(decay_text(case, pred))}</pre>"]
    fig = figure_decay(case.rig, pred, decay_condition(case, pred, short=True))  # type: ignore[arg-type]
    parts.append("<div class=\"figures\">" + _figure("rig.png", number, fig, "Absolute pressure in the test volume against "
                                                    "time, for each model the case asks for.") + "</div>")
    return parts


def _rig_section(result: CaseResult, number: int) -> list[str]:
    case, pred = result.case, result.rig
    rig = case.rig
    if rig is None or pred is None:
        return []
    if isinstance(pred, DecayPrediction):
        return _decay_section(result, pred, number)
    assert isinstance(rig, RigSetup)  # the water column
    parts = ["<h2 id=\"rig\">Virtual water-column rig</h2>"]
    dp0 = float(rig.pressure_difference(rig.initial_height))
    parts.append(f"<p>Load {rig.load:.4g} N ({_e(rig.load_note)}) on the seal: P0 = {pred.squeeze_pressure / 1e3:.4g} kPa; "
                 f"cylinder diameter {rig.cylinder_diameter * 100:.4g} cm, initial height H0 = {rig.initial_height * 100:.4g} cm "
                 f"(ΔP = ρgH0 = {dp0 / 1e3:.4g} kPa), ρ = {rig.density:g} kg/m³, ΔP = ρgH. "
                 f"{'Both theories are' if len(pred.conductance) > 1 else 'The theory is'} linear in ΔP, so "
                 "Q = K ΔP and the level falls exponentially with time constant τ = A_cyl/(K ρ g).</p>")
    rows = []
    for name, k in pred.conductance.items():
        col = pred.columns[name]
        q0 = float(col.leak_rate[0]) if len(col.leak_rate) else k * dp0
        tau = pred.time_constant.get(name, float("nan"))
        rows.append((name, fmt(k, ".4e"), fmt(q0, ".3e"), fmt(q0 * ML_PER_MIN_PER_M3_PER_S, ".4g"),
                     fmt(tau / 60, ".4g"), fmt(col.final_height * 100), fmt(pred.drain_time.get(name, float("nan")) / 60)))
    parts.append(_table(("model", "K = Q/ΔP (m³/(s·Pa))", "Q at H0 (m³/s)", "Q at H0 (ml/min)", "τ (min)",
                         "final height (cm)", "time to final height (min)"), rows))
    parts.append("<div class=\"figures\">" + _figure("rig.png", number, figure_rig(rig, pred.columns, pred.squeeze_pressure),
                                                    "Water height H against time in the virtual rig, for each model the "
                                                    "case asks for; dots: when the level falls to the final height asked for.") + "</div>")
    for m in worded(pred.messages):
        parts.append(f"<p class=\"note\">{_e(m)}</p>")
    return parts


def _header(cases: Sequence[Case]) -> list[str]:
    """The document head, the title and the report's first paragraph (the case file it read)."""
    first = cases[0]
    return ["<!DOCTYPE html>", "<html lang=\"en\">", "<head>", "<meta charset=\"utf-8\">",
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">",
            f"<title>{_e(first.title)} — sealeak report</title>", f"<style>{_CSS}</style>", "</head>",
            "<body>", f"<h1>{_e(first.title)}</h1>",
            f"<p>sealeak {_e(__version__)} — leak rate of a rubber seal from surface roughness "
            "(Persson contact mechanics, percolation, Poiseuille flow; Lorenz &amp; Persson, "
            f"EPL 86 (2009) 44006). Case file: <code>{_e(shown_source(first.source) if first.source else '—')}</code>"
            + (f"; a study of {len(cases)} variants." if len(cases) > 1 else ".") + "</p>"]


def _spectrum_kind(c: Case) -> str:
    """Whether the case's spectrum is a model or a measurement (and of which surface model)."""
    return "model (not a measurement)" if c.spectrum_is_model else f"measurement ({c.surface_model})"


def _spectrum_section(cases: Sequence[Case]) -> list[str]:
    """The spectrum table: each variant's roughness statistics (h_rms in µm, SI otherwise) and q0."""
    rows = []
    for c in cases:
        s = c.spectrum
        q0 = fmt(c.q0) if c.band is None or c.band.q0.min() == c.band.q0.max() else (
            f"{fmt(float(c.band.q0.min()))} … {fmt(float(c.band.q0.max()))}")
        rows.append((c.label or "—", c.spectrum_note, _spectrum_kind(c), fmt(s.h_rms * 1e6), fmt(s.slope_rms),
                     fmt(s.curvature_rms), fmt(s.area_ratio), fmt(s.q_min), fmt(s.q_max), q0))
    return ["<h2 id=\"spectrum\">Surface roughness spectrum</h2>",
            _table(("variant", "spectrum", "kind", "h_rms (µm)", "slope_rms (1)", "curvature_rms (1/m)",
                    "A_true/A0 (1)", "q_min (1/m)", "q1 (1/m)", "q0 (1/m)"), rows, left=3)]


_THEORIES = {"critical-junction": "critical-junction theory (the reference paper)",
             "effective-medium": "effective-medium theory (2D Bruggeman over the gap distribution P(u))",
             "both": "both the critical-junction and the effective-medium theory"}


def _assumptions_section(results: Sequence[CaseResult], band: bool) -> list[str]:
    """The Assumptions list: theory, p_c, γ, α, the spectrum's kind, the contact, the flow and its validity."""
    cases = [r.case for r in results]
    first = cases[0]
    any_em = any(r.effective_medium is not None or (r.band is not None and r.band.effective_medium is not None) for r in results)
    gases = sum(c.gas is not None for c in cases)
    flow = ("the gas flows as described below" if gases == len(cases) else
            "incompressible Newtonian fluid, laminar flow" + (" (the liquids; the gases as described below)" if gases else ""))
    parts = ["<h2 id=\"assumptions\">Assumptions</h2><ul>"]
    parts.append(f"<li>Leak-rate theory: {_e(_THEORIES[first.model])}.</li>")
    parts.append(f"<li>Percolation threshold p_c = {first.percolation_threshold:g}: the critical junction sits where "
                 f"A(ζc)/A0 = 1 − p_c = {1 - first.percolation_threshold:.3g}.</li>")
    parts.append(f"<li>γ = {first.gamma:g} in the interfacial separation ū(ζ) (1: the formula as printed in the paper; "
                 "0.42 recommended by Yang &amp; Persson).</li>")
    parts.append(f"<li>α = {first.alpha:g}: the shape factor of the critical constriction (the paper fits 0.2); "
                 "the effective-medium prediction has no fit factor.</li>")
    kinds = {("model" if "model" in _spectrum_kind(c) else "measurement") for c in cases}
    parts.append(f"<li>The roughness spectrum is a {'model' if kinds == {'model'} else 'measurement'}: "
                 f"{_e(first.spectrum_note)}.</li>")
    if band:
        parts.append("<li>The contact pressure varies across the band: each strip dx at nominal pressure p(x) conducts like "
                     "a uniform seal at that pressure (sheet conductance σ(p)), and the strips are in series, "
                     "Q = Ly ΔP / ∫dx/σ(p(x)); a strip that does not percolate seals the whole band. This holds while "
                     "the band is wide against the roughness' longest wavelengths.</li>")
        parts.append(f"<li>{_e(first.q0_note)} (the seal table gives each load's q0); {flow}; p ≫ ΔP where the "
                     "contact pressure is highest (the fluid pressure does not change the contact); the validity verdict "
                     "judges the band where the pressure is highest; rigid substrate unless [substrate] is given.</li>")
    else:
        parts.append(f"<li>q0 = 2π/L = {first.q0:.4g} 1/m ({_e(first.q0_note)}); {flow}; P0 ≫ ΔP (the fluid "
                     "pressure does not change the contact); rigid substrate unless [substrate] is given.</li>")
    parts += _gas_assumptions(cases, band)
    fluid = first.fluid
    parts.append(f"<li>Continuum flow: a result is valid only where the flow channel is wider than the fluid's molecular "
                 f"size d = {fluid.molecular_length * 1e9:.3g} nm ({_e(fluid.molecular_length_note)}) and thin against "
                 "its width (docs/theory.md §9.11); the tables' valid column gives the verdict.</li>")
    if any_em:
        parts.append("<li>Plain 2D Bruggeman stops percolating at A/A0 = 0.5; numerically exact studies find ≈ 0.42.</li>")
    parts.append("</ul>")
    return parts


def _warnings_section(results: Sequence[CaseResult]) -> list[str]:
    """The warnings about the inputs, each with its variant's label (nothing when there are none)."""
    warned = [(r.case.label, w) for r in results for w in r.warnings]
    if not warned:
        return []
    parts = ["<h2 id=\"warnings\">Warnings about the inputs</h2>",
             "<p>The numbers below are computed all the same; these are the reasons to distrust them.</p>"]
    for label, w in warned:
        parts.append(f"<p class=\"warning\">{_e(label + ': ' if label else '')}{_e(w)}</p>")
    return parts


def _result_block(r: CaseResult) -> list[str]:
    """One result's tables (the columns of ``sealeak predict``), its notes and its validity warnings."""
    parts = []
    if r.band is not None:
        if r.case.label:
            parts.append(f"<h3>{_e(r.case.label)}</h3>")
        parts.append(_result_table(r, "critical-junction"))  # the band table (prediction_columns)
        parts += _gas_tables(r)
        parts += [f"<p class=\"note\">{_e(m)}</p>" for m in worded(r.messages)]
        parts += [f"<p class=\"warning\">{_e(m)}</p>" for m in validity_notes(r)]
        return parts
    case, res, em = r.case, r.critical_junction, r.effective_medium
    if case.label:
        parts.append(f"<h3>{_e(case.label)}</h3>")
    if r.shows_critical_junction:
        parts.append(_result_table(r, "critical-junction"))
    if em is not None:
        parts.append("<p>Effective medium (2D Bruggeman): Q effective medium = (Ly/Lx) σ_eff ΔP; ū(1): mean "
                     "separation, &lt;u&gt;_P: mean of P(u), u_e: the gap whose u³/(12η) equals σ_eff.</p>")
        parts.append(_result_table(r, "effective-medium"))
    parts += _gas_tables(r)
    notes = (worded(res.messages) if r.shows_critical_junction else []) + (
        [f"effective medium: {m}" for m in worded(em.messages)] if em is not None else [])
    for m in notes:
        parts.append(f"<p class=\"note\">{_e(m)}</p>")
    for m in validity_notes(r):
        parts.append(f"<p class=\"warning\">{_e(m)}</p>")
    return parts


def _results_section(results: Sequence[CaseResult], band: bool) -> list[str]:
    """The Results heading, the legend of its columns and each result's block."""
    parts = ["<h2 id=\"results\">Results</h2>"]
    # Q_CJ and Q_EM name the columns where both theories are shown side by side; one theory's column is plain Q
    both = ("Q_CJ: Q critical junction; Q_EM: Q effective medium; "
            if any(r.effective_medium is not None or (r.band is not None and r.band.effective_medium is not None)
                   for r in results) else "")
    if band:
        parts.append("<p class=\"legend\">The columns and digits of <code>sealeak predict</code>, one row per load. "
                     f"{both}{_e(band_legend(results[0]))}; a verdict: yes, NO "
                     "(outside the theory's validity where the pressure is highest: the row's numbers are the formula's, not a "
                     "prediction; highlighted) or — (no leak channel: the band seals).</p>")
    else:
        parts.append("<p class=\"legend\">The columns and digits of <code>sealeak predict</code>. "
                     f"{both}valid: yes, NO (outside the theory's validity: the row's numbers are the "
                     "formula's, not a prediction; highlighted) or — (no leak channel).</p>")
    if any(r.case.gas is not None for r in results):
        parts.append(f"<p class=\"legend\">{_e(GAS_INCOMPRESSIBLE_NOTE[0].upper() + GAS_INCOMPRESSIBLE_NOTE[1:])}.</p>")
    for r in results:
        parts += _result_block(r)
    return parts


def _figures_section(results: Sequence[CaseResult], band: bool,
                     uncertainty: UncertaintyResult | None = None) -> tuple[list[str], int]:
    """The grid of prediction figures with their captions, and how many figures it numbered."""
    parts = ["<h2 id=\"figures\">Figures</h2>"]
    any_invalid = any((~r.shown_valid).any() for r in results)
    parts.append("<div class=\"figures\">")
    figures = prediction_figures(results, limit=volume_limit(uncertainty))
    gas = is_gas_run(results)
    for number, (name, fig) in enumerate(figures.items(), start=1):
        parts.append(_figure(name, number, fig, _caption(name, any_invalid, band, gas)))
    parts.append("</div>")
    return parts, len(figures)


#: What each uncertainty figure shows (the report's captions).
UNCERTAINTY_CAPTIONS = {
    "leak_rate_band.png": "The leak rate over the samples of the uncertain inputs against the load: the median (solid), "
                          "the 5–95 % band (light) and the 25–75 % band (darker), the deterministic prediction of the "
                          "nominal inputs (dashed) and conditions.max_leak_rate (dash-dotted); a band reaching into the "
                          "grey strip at the foot seals in at least 5 % of the samples.",
    "leak_rate_distribution.png": "The distribution of the leak rate over the samples at the first case's middle load "
                                  "(log axis), with the share of sealed samples and the probability of passing "
                                  "conditions.max_leak_rate (a sealed sample passes).",
    "sensitivity.png": "Sobol' indices of log10 Q at the same load: the total index ST (the share of the variance an "
                       "input explains with its interactions) and the first-order index S1 (alone), with their 95 % "
                       "bootstrap intervals; the input on top is the one to measure better first.",
}


def _uncertainty_section(unc: UncertaintyResult, sensitivity: SobolIndices | None, number: int) -> list[str]:
    """The Uncertainty heading: the inputs, the percentiles per row (the table of ``sealeak predict``), the passing loads,
    the Sobol' indices with ``sensitivity``, and the figures numbered from ``number``."""
    header, rows = uncertainty_columns(unc)
    title = "Uncertainty" if unc.study.inputs else "Pass or fail"  # (max_leak_rate alone: no band, a verdict per row)
    parts = [f"<h2 id=\"uncertainty\">{title}</h2>", f"<p>{_e(uncertainty_heading(unc))}</p>"]
    if unc.study.inputs:
        parts.append("<ul>" + "".join(f"<li>{_e(i.label)}</li>" for i in unc.study.inputs) + "</ul>")
    parts.append(_table(header, rows, left=0))
    parts.append(f"<p class=\"legend\">{_e(uncertainty_legend(unc))}.</p>")
    parts += [f"<p>{_e(line)}</p>" for line in passing_lines(unc)]
    if sensitivity is not None:
        header, rows = sensitivity_columns(sensitivity, unc.study)
        parts += [f"<h3 id=\"sensitivity\">Sensitivity</h3><p>{_e(sensitivity_heading(sensitivity))}</p>",
                  _table(header, rows, left=0), f"<p class=\"legend\">{_e(sensitivity_legend())}.</p>"]
        parts += [f"<p class=\"note\">{_e(line)}</p>" for line in sensitivity_sentences(sensitivity, unc.study)]
    parts.append("<div class=\"figures\">")
    for n, (name, fig) in enumerate(uncertainty_figures(unc, sensitivity).items(), start=number):
        parts.append(_figure(name, n, fig, UNCERTAINTY_CAPTIONS[name]))
    parts.append("</div>")
    return parts


def html_report(results: Sequence[CaseResult], inputs: Mapping[str, Any], uncertainty: UncertaintyResult | None = None,
                sensitivity: SobolIndices | None = None) -> str:
    """The HTML text of the report of a case file run (one case, or the variants of a study).

    ``results``: :func:`~sealeak.cases.run_case` of each case; ``inputs``: the case file as the user
    wrote it (:attr:`~sealeak.cases.CaseFile.inputs`), shown with its units; ``uncertainty``: the
    propagation of its uncertain inputs, ``sensitivity`` their Sobol' indices (an Uncertainty section
    with their tables and figures).
    """
    cases = [r.case for r in results]
    band = is_band_run(results)
    parts = _header(cases)
    parts += ["<h2 id=\"inputs\">Inputs</h2>", _inputs(inputs)]
    parts += _spectrum_section(cases)
    parts += _assumptions_section(results, band)
    if band:
        parts += _band_section(results)
    parts += _warnings_section(results)
    parts += _results_section(results, band)
    figures, n_figures = _figures_section(results, band, uncertainty)
    parts += figures
    if uncertainty is not None:
        parts += _uncertainty_section(uncertainty, sensitivity, n_figures + 1)
        n_figures += len(uncertainty_figure_names(sensitivity is not None))
    if len(cases) == 1:
        parts += _rig_section(results[0], n_figures + 1)
    parts.append("</body>")
    parts.append("</html>")
    return "\n".join(parts) + "\n"
