"""Plain-text renderings of case results: the table ``sealeak predict`` prints (SI in, readable units out)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..cases import Case, CaseResult
from ..io.units import length_unit
from ..physics.effective_medium import EffectiveMediumResult

__all__ = ["prediction_table", "fmt"]


def fmt(x: float | None, spec: str = ".4g") -> str:
    """``format(x, spec)``, or an em dash of the same width where ``x`` is None, NaN or infinite."""
    if x is None or not np.isfinite(x):
        width = int("".join(ch for ch in spec.split(".")[0] if ch.isdigit()) or 0)
        return "—".rjust(width)
    return format(x, spec)


def _setting_lines(case: Case, em: EffectiveMediumResult | None) -> dict[str, list[str]]:
    """Text lines describing the rubber, seal, fluid and theory of a case (for the table header)."""
    seal = case.seal
    geom = (f"ring Di = {seal.inner_diameter * 1e3:.4g} mm, Do = {seal.outer_diameter * 1e3:.4g} mm"
            if seal.shape == "ring" else "rectangle")
    theory = [f"theory    critical junction, α = {case.alpha:g}, p_c = {case.percolation_threshold:g} "
              f"(A/A0 = {1 - case.percolation_threshold:.3g} at ζc), γ = {case.gamma:g}, "
              f"q0 = {case.q0:.4g} 1/m ({case.q0_note})"]
    if em is not None:
        theory.append("          effective medium: 2D Bruggeman over P(u), σ(u) = u³/(12η), no fit factor "
                      "(stops percolating at A(ζ1)/A0 = 0.5)")
    return {
        "rubber": [f"rubber    E = {case.youngs_modulus / 1e6:.4g} MPa, ν = {case.poisson_ratio:g}, "
                   f"E* = {case.e_star / 1e6:.4g} MPa"],
        "seal": [f"seal      {geom}: Lx = {seal.width * 1e3:.4g} mm, Ly = {seal.length * 1e3:.4g} mm, "
                 f"Ly/Lx = {seal.aspect_ratio:.4g}"],
        "fluid": [f"fluid     η = {case.fluid.viscosity * 1e3:.4g} mPa·s, ΔP = {case.pressure_difference / 1e3:.4g} kPa"],
        "theory": theory,
    }


def prediction_table(results: Sequence[CaseResult]) -> str:
    """A plain-text report: the case, then one table row per squeeze pressure.

    With effective-medium results (model "both") their leak rate stands next to the critical-junction
    one, and a second table gives ū(1), the mean of P(u), u_e and σ_eff.
    """
    lines: list[str] = []
    first = results[0].case
    lines.append(first.title)
    lines.append("=" * min(len(first.title), 100))
    first_blocks = _setting_lines(first, results[0].effective_medium)
    for r in results:
        case, res, em = r.case, r.critical_junction, r.effective_medium
        s = case.spectrum
        if case.label or case is first:
            if case.label:
                lines.append("")
                lines.append(f"[{case.label}]")
            lines.append(f"surface   {case.spectrum_note}")
            lines.append(f"          h_rms = {s.h_rms * 1e6:.4g} µm, slope_rms = {s.slope_rms:.4g}, "
                         f"A_true/A0 = {s.area_ratio:.4g}, q = {s.q_min:.4g} .. {s.q_max:.4g} 1/m")
            # every setting for the first case; for the other variants, the settings that differ
            for key, block in _setting_lines(case, em).items():
                if case is first or block != first_blocks.get(key):
                    lines.extend(block)
        if r.shows_critical_junction:
            lines.append("")
            both = em is not None
            lam_scale, lam_unit = length_unit(res.critical_wavelength)
            gap_scale, gap_unit = length_unit(res.critical_gap)
            lines.append(f"{'P0 (kPa)':>10} {'ζc':>9} {f'λc ({lam_unit})':>10} {f'u_c ({gap_unit})':>10} "
                         + (f"{'Q_CJ (m³/s)':>12} {'Q_EM (m³/s)':>12} {'Q_CJ (ml/min)':>14} {'Q_EM (ml/min)':>14}"
                            if both else f"{'Q (m³/s)':>11} {'Q (ml/min)':>11}")
                         + f" {'A(ζ1)/A0':>9}")
            for i in range(len(res)):
                q = (f"{fmt(res.leak_rate[i], '12.3e')} {fmt(em.leak_rate[i], '12.3e')} "
                     f"{fmt(res.leak_rate[i] * 6e7, '14.4g')} {fmt(em.leak_rate[i] * 6e7, '14.4g')}" if both else
                     f"{fmt(res.leak_rate[i], '11.3e')} {fmt(res.leak_rate[i] * 6e7, '11.4g')}")
                lines.append(
                    f"{res.squeeze_pressure[i] / 1e3:10.4g} {fmt(res.critical_magnification[i], '9.4g')} "
                    f"{fmt(res.critical_wavelength[i] / lam_scale, '10.4g')} {fmt(res.critical_gap[i] / gap_scale, '10.4g')} "
                    f"{q} {res.contact_area_at_cutoff[i]:9.3f}")
            for m in res.messages:
                lines.append("note: " + m)
        if em is not None:
            lines.append("")
            lines.append("effective medium (2D Bruggeman):")
            u_scale, u_unit = length_unit(np.concatenate([em.mean_gap, em.gap_distribution_mean]))
            lines.append(f"{'P0 (kPa)':>10} {'A(ζ1)/A0':>9} {f'ū(1) ({u_unit})':>10} {f'<u>_P ({u_unit})':>11} "
                         f"{f'u_e ({u_unit})':>10} "
                         f"{'σ_eff (m³/Pa/s)':>16} {'Q_EM (m³/s)':>12} {'Q_EM (ml/min)':>14}")
            for i in range(len(em)):
                lines.append(
                    f"{em.squeeze_pressure[i] / 1e3:10.4g} {em.contact_area_at_cutoff[i]:9.3f} "
                    f"{fmt(em.mean_gap[i] / u_scale, '10.4g')} {fmt(em.gap_distribution_mean[i] / u_scale, '11.4g')} "
                    f"{fmt(em.effective_gap[i] / u_scale if em.percolates[i] else np.nan, '10.4g')} "
                    f"{fmt(em.effective_conductivity[i] if em.percolates[i] else np.nan, '16.4e')} "
                    f"{fmt(em.leak_rate[i], '12.3e')} {fmt(em.leak_rate[i] * 6e7, '14.4g')}")
            lines.append("          <u>_P: mean of the gap distribution P(u) (>= ū(1): the folded Gaussians add to it); "
                         "u_e: the gap whose u³/(12η) equals σ_eff")
            for m in em.messages:
                lines.append("note: " + m)
    return "\n".join(lines) + "\n"
