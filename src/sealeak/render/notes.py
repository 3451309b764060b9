"""The wording of the notes the cases layer returns (:class:`sealeak.cases.notes.Note`).

Each note's code has one function here that writes its sentence, and a load or a pressure is written in a sentence
in one way only (:func:`load_text`, :func:`loads_text`, :func:`kpa_text`). Tables, JSON ``notes`` and figures call
:func:`word` (or :func:`worded`) on a result's notes; a note that is still a plain sentence passes unchanged.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from ..cases.notes import Note, NoteLike
from ..io.leak_units import celsius
from ..io.units import format_quantity
from ..physics.capillarity import Wetting

__all__ = ["load_text", "loads_text", "load_axis_label", "kpa_text", "capillary_legend", "word", "worded"]


def load_text(name: str, value: float) -> str:
    """One load in a sentence or a legend: "compression 20 %" (a fraction, written in %), "profile scale 1.5", or a
    squeeze pressure (Pa) "P0 = 200 kPa" (:func:`loads_text` of one value)."""
    return loads_text(name, [value])


def loads_text(name: str, values: Iterable[float]) -> str:
    """Several loads in a sentence: all of up to four ("compression 15, 20 %"), else the range and how many."""
    if name == "squeeze_pressure":
        return kpa_text(list(values))
    if name == "compression":
        shown = [f"{100 * v:.4g}" for v in values]
        unit, label = " %", "compression"
    else:
        shown = [f"{v:.4g}" for v in values]
        unit, label = "", name.replace("_", " ")
    if len(shown) <= 4:
        return f"{label} {', '.join(shown)}{unit}"
    return f"{label} {shown[0]} .. {shown[-1]}{unit} ({len(shown)} values)"


def load_axis_label(name: str) -> str:
    """A figure's axis label for a band seal's load: an O-ring's compression (in %) or a profile file's scale."""
    if name == "compression":
        return "compression ε = δ/d (%)"
    return "profile scale (1): factor on the file's pressures"


def kpa_text(pressures: Sequence[float]) -> str:
    """Squeeze pressures (Pa) in a sentence: all of up to four ("P0 = 73, 100 kPa"), else the range and how many."""
    if len(pressures) <= 4:
        return "P0 = " + ", ".join(f"{x / 1e3:.4g}" for x in pressures) + " kPa"
    return f"P0 = {min(pressures) / 1e3:.4g} .. {max(pressures) / 1e3:.4g} kPa ({len(pressures)} pressures)"


# ---------------------------------------------------------------------- one function per note code
def _junction_unresolved(v: Mapping[str, Any]) -> str:
    grid, cells = v["grid"], v["min_cells"]
    resolved = (f"resolves the spectrum only up to q = {v['cut_at']:.4g} 1/m (ζ1 = {v['zeta_1']:.4g})"
                if v["cut_at"] is not None else f"has {grid} cells across the square")
    parts = []
    if v["coarse"]:
        parts.append(f"at {kpa_text(v['coarse'])} the theory's critical junction "
                     f"λc = L/ζc spans fewer than {cells} cells: the grid resolves it poorly and little "
                     "resolved roughness is left to hold the surfaces apart, so u_c falls steeply and α there "
                     "(marked *) reflects the grid more than the seal")
    if v["at_end"]:
        parts.append(f"at {kpa_text(v['at_end'])} the junction sits at the very end of the band, where "
                     "u_c vanishes: no critical-junction leak rate and no α")
    return (f"grid = {grid}: the {grid}x{grid} grid {resolved}; " + "; ".join(parts)
            + ". A finer grid (--grid, or grid in [simulation]) resolves the junction.")


def _band_junction_unresolved(v: Mapping[str, Any]) -> str:
    parts = []
    if v["coarse"]:
        parts.append(f"at {loads_text(v['load_name'], v['coarse'])} the theory's critical junction where the pressure "
                     f"is highest spans fewer than {v['min_cells']} cells: the grid resolves it poorly, and α there "
                     "(marked *) reflects the grid more than the seal")
    if v["at_end"]:
        parts.append(f"at {loads_text(v['load_name'], v['at_end'])} the theory's critical junction where the pressure "
                     "is highest sits at the very end of the resolved spectrum, where u_c vanishes: no "
                     "series-resistance leak rate and no α")
    return "; ".join(parts) + f". A finer grid (a larger {v['grid_field']}) resolves it."


def _hertz_width_differs(v: Mapping[str, Any]) -> str:
    return (f"the simulation presses a cylinder on a half-space (Hertz): its contact width at "
            f"{load_text(v['load_name'], v['load'])} is {1e3 * v['hertz_width']:.4g} mm where the case's "
            f"O-ring relation gives {1e3 * v['model_width']:.4g} mm; the series-resistance prediction "
            "below uses the Hertz profile of the same force, so α measures the series assumption only")


def _smooth_check_off(v: Mapping[str, Any]) -> str:
    return (f"smooth check: at {load_text(v['load_name'], v['load'])} the smooth cylinder is off Hertz by "
            f"{100 * v['width_error']:+.2g} % in width and {100 * v['pressure_error']:+.2g} % in peak pressure "
            f"(allowed {100 * v['tolerance']:g} %): the band spans only {v['cells']:.0f} cells; use a "
            f"larger {v['grid_field']}")


def _band_touches_edge(v: Mapping[str, Any]) -> str:
    return (f"the rough contact reached the edge of the domain at {loads_text(v['load_name'], v['loads'])}: "
            "the band there is wider than the domain holds and its leak rate is not that of an isolated band")


def _band_sealed(v: Mapping[str, Any]) -> str:
    return (f"{v['theory']}: no leak channel at {loads_text(v['load_name'], v['loads'])}: where the contact pressure is "
            "highest the non-contact area does not percolate, which seals the whole band")


def _helium_test_lifts(v: Mapping[str, Any]) -> str:
    where = "the band's peak contact pressure" if v["band"] else "the squeeze pressure P0"
    limit = ("the limit ΔP → lift-off, a lower bound: the open seal leaks more" if v["coupled"] else
             "computed with the contact unchanged by the gas (theory.fluid_pressure = \"ignored\"), which the open seal "
             "is not")
    return (f"He-eq at {loads_text(v['load_name'], v['loads'])}: the helium test's ΔP = {v['pressure_difference'] / 1e3:g} kPa "
            f"(1 bar against vacuum) reaches {where}, so the helium test opens the seal there; the He-eq shown is {limit}")


def _band_coupled_not_converged(v: Mapping[str, Any]) -> str:
    return (f"{v['theory']}: the coupled flow (the fluid pressure in the band) did not converge at "
            f"{loads_text(v['load_name'], v['loads'])}; the leak rate shown is its upper bound, with the full pressure "
            "difference acting against the contact pressure across the whole band")


def _band_not_converged(v: Mapping[str, Any]) -> str:
    return (f"{v['theory']}: the integral ∫dx/σ did not converge to {v['tolerance']:g} at "
            f"{load_text(v['load_name'], v['load'])} (last relative change {v['change']:.2g}); the leak rate is less "
            "certain")


def _fit_excluded(v: Mapping[str, Any]) -> str:
    return f"{v['theory']}: line {v['line']} ({load_text(v['load_name'], v['load'])}) excluded: {v['reason']}"


def _fit_outside_validity(v: Mapping[str, Any]) -> str:
    lines = ", ".join(f"{line} ({load_text(v['load_name'], load)})" for line, load in zip(v["lines"], v["loads"]))
    s, them = ("s", "them") if len(v["lines"]) > 1 else ("", "it")
    return (f"{v['theory']}: line{s} {lines} outside the theory's validity (predict's valid = NO: {v['reason']}); kept in "
            f"the fit, though the theory's value there is the formula's, not a prediction (remove the line{s} from the "
            f"data file to fit without {them})")


def _fit_pressure_difference_large(v: Mapping[str, Any]) -> str:
    if v["load_name"] == "squeeze_pressure":
        against, assume = f"P0 = {v['pressure']:.6g} Pa", "P0 >> ΔP"
    else:
        against = (f"the peak contact pressure {v['pressure']:.6g} Pa at {load_text(v['load_name'], v['load'])}")
        assume = "p >> ΔP"
    if v.get("coupled"):
        return (f"line {v['line']}: ΔP = {v['pressure_difference']:.6g} Pa reaches the lift-off pressure difference, "
                f"{against} ({v['rows']} row(s) like it): the fluid pressure opens the seal; the models there are the "
                "limit at lift-off")
    return (f"line {v['line']}: ΔP = {v['pressure_difference']:.6g} Pa is not small against {against} "
            f"({v['rows']} row(s) like it): both theories assume {assume}")


#: Why an extrapolation a → 0 is not to be trusted, by the note's ``kind``.
_EXTRAPOLATION_SENTENCES = {
    "none": "{name}: fewer than two grids give a value, so there is no extrapolation.",
    "two": ("{name}: the extrapolation rests on 2 grids, a straight line through two points with nothing to test it; "
            "a third grid would check the model."),
    "non-monotonic": ("{name}: the values do not change in one direction from grid to grid, so a power law in a is not "
                      "the right model (or the scatter hides the trend); the extrapolated value is not trustworthy."),
    "chi2": ("{name}: the model X∞ + c·a^p does not fit the grids (χ²/dof {chi2}); its standard error was scaled up, "
             "but the extrapolation is doubtful."),
    "diverging": ("{name}: the finest two grids differ by more than their combined standard error, so it has not "
                  "converged (NOT converged above); the extrapolation leans on the model X∞ + c·a^p, and a finer grid "
                  "would tell whether it holds."),
    "unresolved": ("{name}: the change from the coarsest to the finest grid is smaller than its standard error: the "
                   "trend the extrapolation follows is not resolved, and X∞ is no better determined than the finest "
                   "grid's value."),
}


def _extrapolation_doubtful(v: Mapping[str, Any]) -> str:
    if v["quantity"] == "alpha":
        name, chi2 = f"α at {kpa_text(v['pressures'])}", "far above 1"
    else:
        name, chi2 = f"the {v['quantity']}", f"= {v['chi2']:.3g}" if "chi2" in v else ""
    return _EXTRAPOLATION_SENTENCES[v["kind"]].format(name=name, chi2=chi2)


def _held_by_capillarity(v: Mapping[str, Any]) -> str:
    return (f"{v['theory'] + ': ' if v['theory'] else ''}held by capillarity at {loads_text(v['load_name'], v['loads'])}: "
            f"ΔP = {format_quantity(v['pressure_difference'], 'pressure', 4)} is below the entry pressure of the narrowest "
            f"gap (at least {format_quantity(v['entry_pressure'], 'pressure', 4)} there), so the non-wetting liquid does "
            "not pass it: Q = 0 (held_by_capillarity)")


def _fit_pv_throughputs(v: Mapping[str, Any]) -> str:
    return (f"leak rates compared as pV throughputs of {v['gas']} at {celsius(v['temperature']):.4g} °C "
            f"(Pa·m³/s), P_b = {v['downstream_pressure']:.6g} Pa and P_a = P_b + ΔP of each row")


def _decay_no_leak_channel(v: Mapping[str, Any]) -> str:
    return (f"{v['model']}: no leak channel at P0 = {v['squeeze_pressure']:.6g} Pa: the pressure stays at "
            f"{v['initial_pressure']:.6g} Pa")


def _decay_rarefied(v: Mapping[str, Any]) -> str:
    return (f"{v['model']}: Kn = {v['knudsen']:.3g} at the gap h = {v['gap']:.3g} m ({v['regime']} flow): "
            f"rarefaction changes the leak rate by a factor {v['factor']:.3g} against no-slip flow")


def _decay_not_lost(v: Mapping[str, Any]) -> str:
    return (f"{v['model']}: the volume did not lose ΔP = {v['loss']:.6g} Pa within the simulated "
            f"{v['duration']:.6g} s (rig.duration)")


def _decay_pressure_difference_large(v: Mapping[str, Any]) -> str:
    what = "the peak contact pressure" if v["band"] else "P0"
    if v.get("coupled"):
        return (f"P1 − P2 = {format_quantity(v['pressure_difference'], 'pressure', 4)} reaches the lift-off pressure "
                f"difference, {what} = {format_quantity(v['pressure'], 'pressure', 4)}: the gas opens the seal; the "
                "models there are the limit at lift-off (the open seal leaks more)")
    return (f"P1 − P2 = {v['pressure_difference']:.4g} Pa is not small against {what} {v['pressure']:.4g} Pa: the "
            "theory assumes that the gas pressure does not change the contact (p >> ΔP)")


def _rig_no_leak(v: Mapping[str, Any]) -> str:
    return (f"{v['model']}: no leak at P0 = {format_quantity(v['squeeze_pressure'], 'pressure', 4)}, the level stays at "
            f"{format_quantity(v['initial_height'], 'length', 4)}")


def _rig_held_by_capillarity(v: Mapping[str, Any]) -> str:
    head = (f"{v['model']}: the capillary entry pressure of the narrowest gap is p_e = "
            f"{format_quantity(v['entry_pressure'], 'pressure', 4)}")
    if v["time_to_stop"] == 0:
        return (head + f", above ρgH0: the meniscus holds the liquid (Q = 0) and the level stays at H0 = "
                f"{v['initial_height']:.4g} m")
    when = (f" after {v['time_to_stop']:.4g} s" if math.isfinite(v["time_to_stop"])
            else " (not reached within the simulated span)")
    return head + f": the level stops at H = p_e/(ρg) = {v['stop_height']:.4g} m{when}, where the meniscus holds the liquid"


def _rig_pressure_difference_large(v: Mapping[str, Any]) -> str:
    if v.get("coupled"):
        against = (f"the peak contact pressure {format_quantity(v['pressure'], 'pressure', 4)}" if v["band"]
                   else f"P0 = {format_quantity(v['pressure'], 'pressure', 4)}")
        return (f"ΔP = ρgH0 = {format_quantity(v['pressure_difference'], 'pressure', 4)} reaches the lift-off pressure "
                f"difference, {against}: the water column opens the seal; the models there are the limit at lift-off "
                "(the open seal leaks more)")
    if v["band"]:
        return (f"ΔP = ρgH0 = {v['pressure_difference']:.4g} Pa is not small against the peak contact pressure "
                f"{v['pressure']:.4g} Pa: the theory assumes p >> ΔP")
    return (f"ΔP = ρgH0 = {v['pressure_difference']:.4g} Pa is not small against P0 = {v['pressure']:.4g} Pa: the "
            "theory assumes P0 >> ΔP")


def _linearity_held_by_capillarity(v: Mapping[str, Any]) -> str:
    text = (f"{v['model']}: {v['points']} measured point(s) lie below the capillary entry pressure p_e = "
            f"{format_quantity(v['entry_pressure'], 'pressure', 4)}, where the model holds the liquid (Q = 0), so its "
            "line through the measured ΔP has an offset")
    if v["leaking"]:
        text += (f"; {v['leaking']} of them leaked: the narrowest gap is wider, or the liquid wets it better, than "
                 "the model's")
    return text


def _linearity_one_load_needed(v: Mapping[str, Any]) -> str:
    name = v["load_name"]
    one = "compression" if name == "compression" else "profile scale"
    return (f"the case has {v['loads']} values of conditions.{name} and the data file no {name} column: give one "
            f"{one} (in the case, or as a column with one value) to compare with the models")


def _h_rms_change(v: Mapping[str, Any]) -> str:
    """The spectrum's h_rms (m) before and after a cut, in µm, if the note carries it."""
    if v.get("h_rms") is None:
        return ""
    before, after = v["h_rms"]
    return f" (h_rms {before * 1e6:.4g} -> {after * 1e6:.4g} µm)"


def _spectrum_cut_by_grid(v: Mapping[str, Any]) -> str:
    grid = v["grid"]
    return (f"the {grid}x{grid} grid resolves q up to {v['q_cut']:.4g} 1/m ({v['points_per_wavelength']} points per "
            f"wavelength), below the spectrum's cut-off q1 = {v['q1']:.4g} 1/m: the spectrum was cut there for the "
            f"simulation AND for the {v['theory']} theory it is compared with" + _h_rms_change(v))


def _waviness_left_out(v: Mapping[str, Any]) -> str:
    return (f"wavelengths longer than the widest band (q < q0 = {v['q0']:.4g} 1/m) are left out of the surface: the "
            "theory treats them as waviness of the band, not roughness" + _h_rms_change(v))


def _threshold_not_found(v: Mapping[str, Any]) -> str:
    where = "still spans" if v["still_spans"] else "does not span even"
    return (f"realisation {v['realization']}: the fluid {where} at P0 = {v['squeeze_pressure']:.4g} Pa; no "
            "percolation threshold found")


def _map_cut_to_square(v: Mapping[str, Any]) -> str:
    (mx, my), (nx, ny) = v["points"], v["map_points"]
    return f"cut to its central square of {v['side'] * 1e6:.4g} µm ({mx}x{my} of {nx}x{ny} points)"


def _map_resampled(v: Mapping[str, Any]) -> str:
    (nx, ny), n = v["points"], v["grid"]
    return f"resampled from {nx}x{ny} to the {n}x{n} solver grid (Fourier)"


def capillary_legend(w: Wetting) -> str:
    """What the capillarity columns mean for a case's wetting ``w``: γ, the angles, and whether the liquid is held
    or drawn in."""
    head = (f"capillarity: γ = {w.surface_tension * 1e3:.4g} mN/m ({w.surface_tension_source}), θ_rubber = "
            f"{w.contact_angle_rubber:g}°, θ_surface = {w.contact_angle_surface:g}°; entry pressure "
            "p_e = −γ(cos θ_r + cos θ_s)/u at the narrowest gap u")
    if w.wets:
        return (head + f": negative, the liquid wets the gap (cos θ_r + cos θ_s = {w.cosines:.3g} > 0) and capillarity "
                "draws it in with the suction −p_e; the leak rate is the usual one")
    if w.cosines == 0:
        return head + ": zero (cos θ_r + cos θ_s = 0), no capillary pressure; the leak rate is the usual one"
    return (head + ": where ΔP < p_e the liquid is held (held: yes, Q = 0); above p_e the leak rate is the usual one, "
            "driven by the whole ΔP")


_WORDING: dict[str, Callable[[Mapping[str, Any]], str]] = {
    "held_by_capillarity": _held_by_capillarity,
    "junction_unresolved": _junction_unresolved,
    "band_junction_unresolved": _band_junction_unresolved,
    "hertz_width_differs": _hertz_width_differs,
    "smooth_check_off": _smooth_check_off,
    "band_touches_edge": _band_touches_edge,
    "band_sealed": _band_sealed,
    "band_not_converged": _band_not_converged,
    "band_coupled_not_converged": _band_coupled_not_converged,
    "helium_test_lifts": _helium_test_lifts,
    "fit_excluded": _fit_excluded,
    "fit_single_point": lambda v: "with one usable point α has no standard error",
    "fit_repeated_point": lambda v: (f"the {v['rows']} usable rows repeat one measurement (the same leak rate at the same "
                                     "load): their scatter is none, so α has no standard error; the measurement's own "
                                     "uncertainty is not known to the fit"),
    "fit_alpha_far": lambda v: (f"{v['theory']}: the fitted α = {v['alpha']:.3g} lies outside {v['low']:g} to {v['high']:g} "
                                "(α is a shape factor of order one, 0.1 to 2 in the literature; predict warns outside the "
                                "same range): the model "
                                "does not describe these data as given; check the data's units and load column, and the "
                                "case's roughness, rubber and seal (fit_alpha_far)"),
    "fit_mass_flow": lambda v: (f"the leak rates of column '{v['column']}' are mass flows: fitted as the volume flows "
                                f"ṁ/ρ with the liquid's density ρ = {v['density']:.6g} kg/m³"),
    "fit_outside_validity": _fit_outside_validity,
    "fit_pressure_difference_large": _fit_pressure_difference_large,
    "extrapolation_doubtful": _extrapolation_doubtful,
    "fit_pv_throughputs": _fit_pv_throughputs,
    "decay_no_leak_channel": _decay_no_leak_channel,
    "decay_rarefied": _decay_rarefied,
    "decay_not_lost": _decay_not_lost,
    "decay_pressure_difference_large": _decay_pressure_difference_large,
    "rig_no_leak": _rig_no_leak,
    "rig_held_by_capillarity": _rig_held_by_capillarity,
    "rig_pressure_difference_large": _rig_pressure_difference_large,
    "linearity_one_load_needed": _linearity_one_load_needed,
    "linearity_held_by_capillarity": _linearity_held_by_capillarity,
    "spectrum_cut_by_grid": _spectrum_cut_by_grid,
    "waviness_left_out": _waviness_left_out,
    "threshold_not_found": _threshold_not_found,
    "loads_sorted_by_force": lambda v: f"{v['load_name'].replace('_', ' ')}s were sorted in increasing order of force",
    "map_not_square": lambda v: "the periodic map is not square: its central square is not periodic (levelled and mirrored)",
    "map_cut_to_square": _map_cut_to_square,
    "map_mean_removed": lambda v: "periodic map: its mean removed",
    "map_mirrored": lambda v: ("not periodic: levelled (plane removed) and mirrored into a periodic 2L x 2L square "
                               "(artefact: slope kinks along the mirror lines)"),
    "map_resampled": _map_resampled,
    "map_low_pass": lambda v: f"low-pass filtered to q <= {v['q']:.4g} 1/m, the band of the theories it is compared with",
    "fluid_pressure_not_simulated": lambda v: (
        "the simulation presses the surface with the squeeze pressure alone (the fluid pressure in the band is not "
        "simulated), so its theory is the printed one, fluid_pressure = \"ignored\" (docs/theory.md §13)"),
    "linearity_no_squeeze_pressure": lambda v: ("no squeeze pressure known (give --squeeze-pressure): no comparison "
                                                "with the models"),
    "pressures_sorted": lambda v: "squeeze pressures were sorted in increasing order",
    "no_threshold_found": lambda v: "no percolation threshold found (see the notes above)",
    "of_map": lambda v: f"{v['label']}: {word(v['note'])}",
}


def word(note: NoteLike) -> str:
    """The sentence the user reads for ``note`` (a plain sentence passes unchanged)."""
    if isinstance(note, Note):
        return _WORDING[note.code](note.values)
    return note


def worded(notes: Iterable[NoteLike]) -> list[str]:
    """:func:`word` of each note, in order."""
    return [word(n) for n in notes]
