"""Renderings of measured-surface analyses (``sealeak surface analyze``): text, JSON, C(q) table."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..io.quantities import units_for
from ..physics.spectrum import PowerSpectrum
from ..topography import Analysis, BinnedSpectrum, LineScans, SurfaceStatistics, Topography
from .records import json_document, json_value

__all__ = ["analysis_text", "analysis_json", "spectrum_csv", "SURFACE_UNITS"]


def _stat_rows(stats: SurfaceStatistics) -> list[tuple[str, str, float | None, float | None]]:
    return [
        ("h_rms", "µm", stats.h_rms, stats.spectrum_h_rms),
        ("slope_rms", "1", stats.slope_rms, stats.spectrum_slope_rms),
        ("curvature_rms", "1/mm", stats.curvature_rms, stats.spectrum_curvature_rms),
        ("area_ratio", "1", stats.area_ratio, stats.spectrum_area_ratio),
        ("skewness", "1", stats.skewness, None),
        ("kurtosis", "1", stats.kurtosis, None),
    ]


_SCALE = {"µm": 1e6, "1/mm": 1e-3, "1": 1.0}


def _fmt(v: float | None, unit: str) -> str:
    return "—" if v is None or not np.isfinite(v) else f"{v * _SCALE[unit]:.4g}"


def _source_size(surface: Topography | LineScans) -> list[float]:
    return list(surface.size) if hasattr(surface, "size") else [surface.length]


def _binned(src: Any) -> Any:
    """A source's binned spectrum: its 2D C(q), or the profile C1D(q) of line scans that have no 2D one."""
    binned = src.spectrum or src.profile_spectrum
    assert binned is not None  # every analysed source has one of them
    return binned


def analysis_text(an: Analysis) -> str:
    """What ``sealeak surface analyze`` prints: sources, statistics, C(q) range, fit, what was done."""
    lines = []
    for src in an.sources:
        s = src.surface
        lines.append(f"source  {src.label}")
        shape = "x".join(str(n) for n in np.shape(s.heights))
        extent = " x ".join(f"{v * 1e6:.4g}" for v in _source_size(s))
        lines.append(f"        {type(s).__name__} {shape} points, {extent} µm")
        if src.spectrum_problem is None:
            assert src.spectrum is not None  # a reliable C(q) exists when there is no problem
            lo, hi = src.spectrum.q_reliable
            lines.append(f"        reliable range q = {lo:.4g} .. {hi:.4g} 1/m")
        elif len(an.sources) > 1:
            lines.append(f"        no C(q): {src.spectrum_problem}")
        lines.extend(f"        warning: {w}" for w in src.warnings)
    lines.append("")
    header = "statistics of the single measurement" if len(an.sources) == 1 else "statistics of each measurement"
    lines.append(header)
    if len(an.sources) == 1:
        lines.append(f"  {'quantity':15s} {'unit':6s} {'from heights':>13s} {'from C(q)':>11s}")
        for name, unit, a, b in _stat_rows(an.statistics):
            lines.append(f"  {name:15s} {unit:6s} {_fmt(a, unit):>13s} {_fmt(b, unit):>11s}")
    else:
        for src in an.sources:
            lines.append(f"  [{src.label}]")
            for name, unit, a, _ in _stat_rows(src.statistics):
                lines.append(f"  {name:15s} {unit:6s} {_fmt(a, unit):>13s}")
        if an.has_spectrum:
            lines.append("  [stitched C(q)]")
            for name, unit, _, b in _stat_rows(an.statistics):
                if b is not None:
                    lines.append(f"  {name:15s} {unit:6s} {_fmt(b, unit):>13s}")
            lines.append(f"  (JSON statistics: {an.statistics.method})")
    lines.append("")
    if an.has_spectrum:
        sp = an.spectrum
        lines.append(f"C(q): {sp.q.size} points, reliable range q = {sp.q_min:.4g} .. {sp.q_max:.4g} 1/m "
                     f"(λ = {2 * np.pi / sp.q_max * 1e6:.4g} .. {2 * np.pi / sp.q_min * 1e6:.4g} µm)")
    elif len(an.sources) > 1:
        lines.append("C(q): none: no measurement gives a reliable C(q) (reasons above)")
    else:
        lines.append(f"C(q): none: {an.spectrum_problem}")
    if an.fit is not None:
        f = an.fit
        qr = (f"q_r = {f.q_rolloff:.4g} ± {f.q_rolloff_err:.2g} 1/m" if f.rolloff_resolved
              else "no roll-off resolved")
        herr = f"± {f.hurst_err:.3f}" if np.isfinite(f.hurst_err) else "(at the bound of 0 < H < 1)"
        herr_h = f" ± {f.h_rms_err * 1e6:.2g}" if np.isfinite(f.h_rms_err) else ""
        lines.append(f"self-affine fit: H = {f.hurst:.3f} {herr}, {qr}, "
                     f"h_rms = {f.h_rms * 1e6:.4g}{herr_h} µm, reduced χ² = {f.chi2_red:.3g}")
        lines.extend(f"  warning: {w}" for w in f.warnings)
    if an.notes:
        lines.append("")
        lines.append("what was done:")
        lines.extend(f"  - {n}" for n in an.notes)
    return "\n".join(lines) + "\n"


_STAT_KEYS = ("h_rms", "slope_rms", "curvature_rms", "area_ratio", "skewness", "kurtosis")
_SPECTRAL_KEYS = ("spectrum_h_rms", "spectrum_slope_rms", "spectrum_curvature_rms", "spectrum_area_ratio")
#: The ``units`` of ``surface analyze --json`` (declared on the statistics', spectra's and maps' fields).
SURFACE_UNITS = units_for((*_STAT_KEYS, "q", "C", "size", "reliable_range"), SurfaceStatistics, PowerSpectrum, Topography,
                          BinnedSpectrum)


def analysis_json(an: Analysis) -> str:
    """The ``sealeak surface analyze --json`` document (statistics, C(q), sources, fit; SI units).

    ``warnings`` (top level) lists everything the text output prints as a warning: each source's
    data warnings (also in its own ``warnings``) and the fit's (also in ``fit.warnings``; ``fit.warning``
    is the same joined into one text, or null).
    """
    st = an.statistics
    stats = {k: json_value(getattr(st, k)) for k in _STAT_KEYS + _SPECTRAL_KEYS}
    stats["method"] = st.method
    doc: dict[str, Any] = {
        "units": SURFACE_UNITS,
        "statistics": stats,
        "psd": ({"q": an.spectrum.q.tolist(), "C": an.spectrum.C.tolist()} if an.has_spectrum else None),
        "sources": [{
            "label": s.label,
            "kind": "map" if hasattr(s.surface, "size") else "line scans",
            "grid": list(np.shape(s.surface.heights)),
            "size": _source_size(s.surface),
            "periodic": bool(s.surface.periodic),
            "reliable_range": list(_binned(s).q_reliable),
            "spectrum_problem": s.spectrum_problem,
            "statistics": {**{k: json_value(getattr(s.statistics, k)) for k in _STAT_KEYS + _SPECTRAL_KEYS},
                           "method": s.statistics.method},
            "warnings": list(s.warnings),
            "notes": list(s.notes)} for s in an.sources],
        "warnings": list(an.warnings),
        "notes": list(an.notes),
    }
    if not an.has_spectrum:
        doc["psd_problem"] = an.spectrum_problem
    if an.fit is not None:
        f = an.fit
        doc["fit"] = {k: json_value(getattr(f, k)) for k in (
            "hurst", "hurst_err", "q_rolloff", "q_rolloff_err", "rolloff_resolved", "C0", "C0_err",
            "h_rms", "h_rms_err", "chi2_red", "hurst_in_range", "hurst_wanted", "warning")}
        doc["fit"]["warnings"] = list(f.warnings)
    return json_document(doc)


def spectrum_csv(spectrum: PowerSpectrum) -> str:
    """C(q) as a two-column table with units in the header (q in 1/m, C in m⁴)."""
    rows = ["q (1/m), C (m^4)"] + [f"{q:.10g}, {c:.10g}" for q, c in zip(spectrum.q, spectrum.C)]
    return "\n".join(rows) + "\n"


