"""Plain-text renderings of case results: the table ``sealeak predict`` prints (SI in, readable units out)."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..cases import Case, CaseResult
from ..cases.sobol import SobolIndices
from ..cases.uncertainty import UncertaintyResult
from ..io.leak_units import celsius, to_ml_per_min
from ..io.units import length_unit
from ..physics.effective_medium import EffectiveMediumResult
from ..physics.validity import pressures_text
from .notes import capillary_legend, load_text, worded
from .sensitivity import sensitivity_columns, sensitivity_heading, sensitivity_legend, sensitivity_sentences
from .uncertainty import passing_lines, uncertainty_columns, uncertainty_heading, uncertainty_legend

__all__ = ["prediction_table", "prediction_columns", "validity_notes", "fmt", "gas_tables", "gas_notes", "band_legend",
           "GAS_INCOMPRESSIBLE_NOTE"]
__all__ += ["capillary_tables", "capillary_notes", "uncertainty_lines", "sensitivity_lines"]


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
            if seal.shape == "ring" and seal.inner_diameter is not None and seal.outer_diameter is not None else "rectangle")
    theory = [f"theory    critical junction, α = {case.alpha:g}, p_c = {case.percolation_threshold:g} "
              f"(A/A0 = {1 - case.percolation_threshold:.3g} at ζc), γ = {case.gamma:g}, "
              f"q0 = {case.q0:.4g} 1/m ({case.q0_note})"]
    if em is not None:
        theory.append("          effective medium: 2D Bruggeman over P(u), σ(u) = u³/(12η), no fit factor "
                      "(stops percolating at A(ζ1)/A0 = 0.5)")
    theory += _coupling_lines(case)
    return {
        "rubber": [f"rubber    E = {case.youngs_modulus / 1e6:.4g} MPa, ν = {case.poisson_ratio:g}, "
                   f"E* = {case.e_star / 1e6:.4g} MPa" + _set_text(case)],
        "seal": [f"seal      {geom}: Lx = {seal.width * 1e3:.4g} mm, Ly = {seal.length * 1e3:.4g} mm, "
                 f"Ly/Lx = {seal.aspect_ratio:.4g}"],
        "fluid": _fluid_lines(case),
        "theory": theory,
    }


def _set_text(case: Case) -> str:
    """``"; compression set c = 12.3 %: ε (1 − c) in the table"``: the set of an ageing O-ring (rubber.compression_set)."""
    c = case.life.compression_set if case.life is not None else None
    return "" if c is None else f"; compression set c = {100 * c:.3g} % (the table's ε is what it leaves: ε (1 − c))"


def _kpa(p: float) -> str:
    return f"{p / 1e3:.4g} kPa"


def _fluid_lines(case: Case) -> list[str]:
    """The fluid: its viscosity and ΔP; for a named fluid its temperature and absolute pressures; for a gas its properties."""
    fluid = case.fluid
    name = f"{fluid.name}, " if fluid.name and case.fluid_state is not None else ""
    temp = f"T = {celsius(case.temperature):.4g} °C, " if case.fluid_state is not None else ""
    if case.absolute_pressures is not None:
        pa, pb = case.absolute_pressures
        pressures = f"P_a = {_kpa(pa)} → P_b = {_kpa(pb)} (absolute), ΔP = {_kpa(case.pressure_difference)}"
    else:
        pressures = f"ΔP = {_kpa(case.pressure_difference)}"
    eta = f"{fluid.viscosity * 1e6:.4g} µPa·s" if fluid.viscosity < 1e-4 else f"{fluid.viscosity * 1e3:.4g} mPa·s"
    lines = [f"fluid     {name}η = {eta}, {temp}{pressures}"]
    if case.gas is not None:
        g = case.gas
        lines.append(f"          a gas: M = {g.gas.molar_mass * 1e3:.4g} g/mol, mean free path {g.gas.mean_free_path(g.mean_pressure) * 1e9:.4g} nm "
                     f"at the mean pressure; rarefaction {g.rarefaction} (docs/theory.md §11.4)")
    if case.fluid_state is not None:
        lines.append(f"          properties: {case.fluid_state.source}"
                     + (" (viscosity given in the case file)" if abs(fluid.viscosity / case.fluid_state.viscosity - 1) > 1e-12 else ""))
    return lines


#: A table's column: (header, width, cells), and for a gas table the record field each cell shows ("" if none).
Column = tuple[str, int, list[str]]
GasColumn = tuple[str, int, list[str], str]


def _gas_columns(r: CaseResult, theory: str) -> list[GasColumn]:
    """(header, width, cells, record field) of the gas table of one theory ("critical_junction" or "effective_medium")."""
    assert r.gas is not None
    rows = r.gas[theory]
    n = range(rows.conductance.size)
    suffix = "_effective_medium" if theory == "effective_medium" else ""
    cols: list[GasColumn] = _row_and_gap_columns(r, rows.gap)
    f = rows.fields()

    def col(head: str, width: int, key: str, spec: str) -> GasColumn:
        return head, width, [fmt(f[key][i], spec) for i in n], key + suffix

    if rows.leaks is not None:
        cols += [col("Kn", 9, "knudsen_number", ".3g"),
                 ("regime", 15, [f["flow_regime"][i] or "—" for i in n], "flow_regime" + suffix),
                 col("Q_pV (Pa·m³/s)", 15, "leak_rate_pv", ".3e"),
                 col("Q (mbar·l/s)", 13, "leak_rate_mbar_l_s", ".3e"),
                 col("ṁ (kg/s)", 10, "leak_rate_mass", ".3e"),
                 col("ṅ (mol/s)", 10, "leak_rate_molar", ".3e"),
                 col("Q (sccm)", 10, "leak_rate_sccm", ".3e")]
    if rows.helium is not None:
        cols.append(col("He-eq (mbar·l/s)", 17, "leak_rate_helium_mbar_l_s", ".3e"))
    if rows.permeation is not None:
        cols += [col("Q_perm (Pa·m³/s)", 17, "leak_rate_permeation_pv", ".3e"),
                 col("t_lag (s)", 10, "permeation_breakthrough_time", ".3g"),
                 col("Q_total (mbar·l/s)", 19, "leak_rate_total_mbar_l_s", ".3e")]
    return cols


def _row_and_gap_columns(r: CaseResult, gap: np.ndarray) -> list[GasColumn]:
    """The leading columns of a gas or capillarity table: the row's squeeze pressure or load, and the narrowest gap."""
    if r.band is not None:
        b = r.band.band
        first = (("ε (%)", 7, [f"{100 * v:.4g}" for v in b.loads], "") if b.load_name == "compression"
                 else ("scale", 7, [f"{v:.4g}" for v in b.loads], ""))
    else:
        first = ("P0 (kPa)", 10, [f"{p / 1e3:.4g}" for p in r.critical_junction.squeeze_pressure], "")
    g_scale, g_unit = length_unit(gap[np.isfinite(gap)] if np.isfinite(gap).any() else np.array([1e-6]))
    return [first, (f"gap ({g_unit})", 10, [fmt(g / g_scale, ".4g") for g in gap], "")]


def gas_tables(r: CaseResult) -> list[tuple[str, list[GasColumn]]]:
    """The gas tables of ``sealeak predict`` (the report shows the same): (title, columns) per theory shown.

    Each column is (header, width, cells, record field): the cells show the record's field (the
    ``predict --json`` value) in the header's unit, formatted; the field is "" for the load and gap columns.
    Empty for a case without gas rows (a liquid without ``conditions.helium_equivalent``).
    """
    if r.gas is None:
        return []
    gap_of = {"critical_junction": "u_c at the peak contact pressure" if r.band is not None else "u_c",
              "effective_medium": "u_e at the peak contact pressure" if r.band is not None else "u_e"}
    out = []
    for theory, rows in r.gas.items():
        if theory == "critical_junction" and not r.shows_critical_junction:
            continue
        what = "gas leak" if rows.leaks is not None else "helium-equivalent leak"
        out.append((f"{what}, {theory.replace('_', ' ')} (gap: {gap_of[theory]})", _gas_columns(r, theory)))
    return out


def gas_notes(r: CaseResult) -> list[str]:
    """What the gas tables' columns mean: where Kn is taken, the temperature of Q_pV, the helium test's conditions."""
    case = r.case
    notes = []
    if case.gas is not None:
        notes.append(f"Kn = λ/gap at the mean pressure {_kpa(case.gas.mean_pressure)}; Q_pV counted at "
                     f"{celsius(case.temperature):.4g} °C; sccm: cm³/min at 0 °C and 101.325 kPa")
    if case.helium_equivalent:
        notes.append("He-eq: helium through the same seal at 1 bar against vacuum, 20 °C (the helium leak test)")
    coupled = " and ".join(name for name, on in (("Q_pV", case.gas is not None), ("He-eq", case.helium_equivalent)) if on)
    if case.coupled and coupled:
        notes.append(f"fluid pressure coupled: {coupled} take the gas pressure off the contact pressure along its drop, "
                     "each strip with its own gap and slip (docs/theory.md §13.5); the gap and Kn shown are the "
                     "narrowest constriction's")
    if case.gas is not None and case.permeation is not None:
        path = "the squeezed cord" if case.permeation.height is None else "the slab seal.height × seal width"
        notes.append(f"Q_perm: the gas's steady permeation through the rubber of {path} (rubber.permeability: "
                     f"P = {case.permeation.permeability:.4g} m²/s, pV at {celsius(case.temperature):.4g} °C), "
                     "reached after about t_lag (rubber.diffusivity); Q_total = Q_pV + Q_perm, what a leak test measures "
                     "once the permeation has broken through (docs/theory.md §11.11)")
    return notes


def capillary_tables(r: CaseResult) -> list[tuple[str, list[GasColumn]]]:
    """The capillarity tables of ``sealeak predict`` (the report shows the same): (title, columns) per theory shown.

    Columns as :func:`gas_tables`' (the entry pressure p_e and held, with their record fields). Empty for a case
    without a contact angle.
    """
    out: list[tuple[str, list[GasColumn]]] = []
    gap_of = {"critical_junction": "u_c at the peak contact pressure" if r.band is not None else "u_c",
              "effective_medium": "narrowest u_e along the band" if r.band is not None else "u_e"}
    for theory, rows in (r.capillary or {}).items():
        if theory == "critical_junction" and not r.shows_critical_junction:
            continue
        suffix = "_effective_medium" if theory == "effective_medium" else ""
        p_scale, p_unit = _pressure_unit(np.abs(rows.entry_pressure))
        n = range(rows.gap.size)
        cols = _row_and_gap_columns(r, rows.gap) + [
            (f"p_e ({p_unit})", 10, [fmt(rows.entry_pressure[i] / p_scale, ".4g") for i in n],
             "capillary_entry_pressure" + suffix),
            ("held", 5, ["yes" if rows.held[i] else "no" if np.isfinite(rows.gap[i]) else "—" for i in n],
             "held_by_capillarity" + suffix)]
        out.append((f"capillarity, {theory.replace('_', ' ')} (gap: {gap_of[theory]})", cols))
    return out


def capillary_notes(r: CaseResult) -> list[str]:
    """What the capillarity tables mean: γ, the contact angles, and whether the liquid is held or drawn in."""
    wetting = r.case.capillarity
    return [capillary_legend(wetting)] if r.capillary and wetting is not None else []


def _gas_block(r: CaseResult) -> list[str]:
    """The gas tables and the capillarity tables (one per theory) and what their columns mean."""
    lines: list[str] = []
    for title, cols in gas_tables(r) + capillary_tables(r):
        lines += ["", f"{title}:"]
        lines += _table_lines(cols)
    return lines + ["          " + n for n in gas_notes(r) + capillary_notes(r)] if lines else []


def _settings(r: CaseResult) -> dict[str, list[str]]:
    """The setting lines of a result: those of its case, with the band's seal line for a band seal."""
    blocks = _setting_lines(r.case, r.effective_medium)
    if r.band is not None:
        blocks["seal"] = _band_setting(r)
        case = r.case
        blocks["theory"] = [f"theory    {'critical junction, α = ' + format(case.alpha, 'g') if case.model != 'effective-medium' else 'effective medium'}"
                            f"{' and effective medium' if case.model == 'both' else ''}, strips in series across the band "
                            f"(Q = Ly ΔP / ∫dx/σ(p(x))), {case.q0_note}"] + _coupling_lines(case)
    return blocks


def _coupling_lines(case: Case) -> list[str]:
    """The header line saying that the fluid pressure in the band acts on the contact (none when it is ignored)."""
    if not case.coupled:
        return []
    peak = "the peak contact pressure" if case.band is not None else "P0"
    return [f"          fluid pressure coupled: the contact is pressed by p − p_f; the seal opens at ΔP = {peak}"]


def _cj_columns(r: CaseResult) -> list[Column]:
    """(header, width, cells) of the critical-junction table (with Q_EM beside Q_CJ for model "both")."""
    res, em = r.critical_junction, r.effective_medium
    lam_scale, lam_unit = length_unit(res.critical_wavelength)
    gap_scale, gap_unit = length_unit(res.critical_gap)
    n = range(len(res))
    cols = [
        ("P0 (kPa)", 10, [f"{res.squeeze_pressure[i] / 1e3:.4g}" for i in n]),
        ("ζc", 9, [fmt(res.critical_magnification[i], ".4g") for i in n]),
        (f"λc ({lam_unit})", 10, [fmt(res.critical_wavelength[i] / lam_scale, ".4g") for i in n]),
        (f"u_c ({gap_unit})", 10, [fmt(res.critical_gap[i] / gap_scale, ".4g") for i in n]),
    ]
    q = _q_head(r)
    if em is not None:
        cols += [(q("Q_CJ", "m³/s"), 12, [fmt(res.leak_rate[i], ".3e") for i in n]),
                 (q("Q_EM", "m³/s"), 12, [fmt(em.leak_rate[i], ".3e") for i in n]),
                 (q("Q_CJ", "ml/min"), 14, [fmt(to_ml_per_min(res.leak_rate[i]), ".4g") for i in n]),
                 (q("Q_EM", "ml/min"), 14, [fmt(to_ml_per_min(em.leak_rate[i]), ".4g") for i in n])]
    else:
        cols += [(q("Q", "m³/s"), 11, [fmt(res.leak_rate[i], ".3e") for i in n]),
                 (q("Q", "ml/min"), 11, [fmt(to_ml_per_min(res.leak_rate[i]), ".4g") for i in n])]
    cols.append(("A(ζ1)/A0", 9, [f"{res.contact_area_at_cutoff[i]:.3f}" for i in n]))
    valid_em = r.valid_effective_medium
    cols.append(("valid", 6, [_verdict(bool(res.percolates[i]), bool(r.valid[i]))
                              + ("" if valid_em is None or em is None else
                                 "/" + _verdict(bool(em.percolates[i]), bool(valid_em[i]))) for i in n]))
    return cols


def _q_head(r: CaseResult) -> Callable[[str, str], str]:
    """The header of a column of the incompressible Q = K ΔP: "Q_CJ (m³/s)", or for a gas case "Q_CJ incompr. (m³/s)"
    (the liquid formula with the gas's viscosity, shown for comparison; the gas's leak rate is in the gas table)."""
    mark = " incompr." if r.case.gas is not None else ""

    def head(name: str, unit: str) -> str:
        return f"{name}{mark} ({unit})"
    return head


def _pressure_unit(values: np.ndarray) -> tuple[float, str]:
    top = float(np.nanmax(values)) if np.isfinite(values).any() else 1e6
    return (1e6, "MPa") if top >= 1e6 else (1e3, "kPa")


def _band_columns(r: CaseResult) -> list[Column]:
    """(header, width, cells) of the table of an O-ring or pressure-profile seal, one row per load."""
    b = r.band
    assert b is not None
    cj, em = b.critical_junction, b.effective_medium
    n = range(len(b))
    w_scale, w_unit = length_unit(b.contact_width)
    p_scale, p_unit = _pressure_unit(b.max_contact_pressure)
    load = (("ε (%)", 7, [f"{100 * v:.4g}" for v in b.band.loads]) if b.band.load_name == "compression"
            else ("scale", 7, [f"{v:.4g}" for v in b.band.loads]))
    regime = ([("regime", 13, list(b.band.oring.regime))] if b.band.oring is not None else [])
    cols = [load, *regime,
            (f"w ({w_unit})", 9, [fmt(b.contact_width[i] / w_scale, ".4g") for i in n]),
            (f"p_mean ({p_unit})", 13, [fmt(b.mean_contact_pressure[i] / p_scale, ".4g") for i in n]),
            (f"p_max ({p_unit})", 12, [fmt(b.max_contact_pressure[i] / p_scale, ".4g") for i in n])]
    q = _q_head(r)
    both = em is not None and r.shows_critical_junction
    if cj.leak_rate is not None and r.shows_critical_junction:
        cols += [(q("Q_CJ" if both else "Q", "m³/s"), 12, [fmt(cj.leak_rate[i], ".3e") for i in n]),
                 (q("Q_CJ" if both else "Q", "ml/min"), 14, [fmt(to_ml_per_min(cj.leak_rate[i]), ".4g") for i in n])]
    if em is not None:  # (in ml/min too, as the critical junction's and as the uniform seal's tables give both)
        cols += [(q("Q_EM", "m³/s"), 12, [fmt(em.leak_rate[i], ".3e") for i in n]),
                 (q("Q_EM", "ml/min"), 14, [fmt(to_ml_per_min(em.leak_rate[i]), ".4g") for i in n])]
    main = cj if r.shows_critical_junction else em
    assert main is not None
    cols += [(q("Q_u,CJ(p_mean)" if both else "Q_u(p_mean)", "m³/s"), 17, [fmt(main.uniform_mean_pressure[i], ".3e") for i in n]),
             (f"90% of R ({w_unit})", 15, [fmt(main.resistance_band_width[i] / w_scale, ".3g") for i in n])]
    if r.shows_critical_junction:
        cols.append(("valid CJ" if both else "valid", 6, [_verdict(bool(cj.percolates[i]), bool(r.valid[i])) for i in n]))
    if em is not None:
        valid_em = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(b), bool)
        cols.append(("valid EM" if both else "valid", 6, [_verdict(bool(em.percolates[i]), bool(valid_em[i])) for i in n]))
    return cols


def band_legend(r: CaseResult) -> str:
    """What the columns of a band table mean (``sealeak predict`` prints it under the table, the report above it)."""
    both = r.band is not None and r.band.effective_medium is not None and r.shows_critical_junction
    return ("w: contact width; p_mean, p_max: mean and peak contact pressure; "
            + ("Q_u,CJ(p_mean)" if both else "Q_u(p_mean)")
            + ": the leak rate of a uniform seal of the same width and length at the mean contact pressure p_mean = f/w"
            + (" (critical junction)" if both else "") + ", for comparison (docs/theory.md §10.1)"
            + ("; it takes no capillarity: on a row the liquid is held (Q = 0) it is the uniform seal's leak rate once "
               "the liquid passes" if r.capillary and any(c.held.any() for c in r.capillary.values()) else "")
            + "; 90% of R: the width "
            "of the band holding 90 % of the flow resistance"
            + ("; valid CJ, valid EM: the verdicts of the critical junction and of the effective medium" if both else ""))


#: Under the main table of a gas case: what its Q columns are.
GAS_INCOMPRESSIBLE_NOTE = ("columns marked incompr.: the incompressible formula K ΔP with the gas's viscosity, for "
                           "comparison only; the gas's leak rate is the pV throughput Q_pV of the gas tables below")


def _band_setting(r: CaseResult) -> list[str]:
    b = r.band
    assert b is not None
    band = b.band
    faces = "" if band.faces == 1 else ", 2 faces in parallel (counterface and groove bottom)"
    if band.kind == "o-ring":
        d = band.cross_section_diameter or 0.0
        head = (f"seal      O-ring, cross-section d = {d * 1e3:.4g} mm, seal line diameter {(band.mean_diameter or 0) * 1e3:.4g} mm: "
                f"Ly = {band.length * 1e3:.4g} mm{faces}")
    else:
        head = f"seal      pressure profile, Ly = {band.length * 1e3:.4g} mm{faces}"
    return [head] + [f"          {line}" for line in band.notes[:1]]


def _verdict(percolates: bool, valid: bool) -> str:
    """A row's verdict: — for a valid row without a leak channel (nothing to judge), NO for one the fluid opens."""
    return "NO" if not valid else "—" if not percolates else "yes"


def _em_columns(r: CaseResult) -> list[Column]:
    """(header, width, cells) of the effective-medium table."""
    em = r.effective_medium
    assert em is not None
    u_scale, u_unit = length_unit(np.concatenate([em.mean_gap, em.gap_distribution_mean]))
    n = range(len(em))
    valid = r.valid_effective_medium if r.valid_effective_medium is not None else np.ones(len(em), bool)
    return [
        ("P0 (kPa)", 10, [f"{em.squeeze_pressure[i] / 1e3:.4g}" for i in n]),
        ("A(ζ1)/A0", 9, [f"{em.contact_area_at_cutoff[i]:.3f}" for i in n]),
        (f"ū(1) ({u_unit})", 10, [fmt(em.mean_gap[i] / u_scale, ".4g") for i in n]),
        (f"<u>_P ({u_unit})", 11, [fmt(em.gap_distribution_mean[i] / u_scale, ".4g") for i in n]),
        (f"u_e ({u_unit})", 10, [fmt(em.effective_gap[i] / u_scale if em.percolates[i] else np.nan, ".4g") for i in n]),
        ("σ_eff (m³/Pa/s)", 16, [fmt(em.effective_conductivity[i] if em.percolates[i] else np.nan, ".4e") for i in n]),
        (_q_head(r)("Q_EM", "m³/s"), 12, [fmt(em.leak_rate[i], ".3e") for i in n]),
        (_q_head(r)("Q_EM", "ml/min"), 14, [fmt(to_ml_per_min(em.leak_rate[i]), ".4g") for i in n]),
        ("valid", 6, [_verdict(bool(em.percolates[i]), bool(valid[i])) for i in n]),
    ]


def prediction_columns(result: CaseResult, table: str = "critical-junction") -> tuple[list[str], list[list[str]]]:
    """The headers and cell strings of one table of ``sealeak predict`` (the report shows the same).

    ``table``: "critical-junction" (the main table: P0, ζc, λc, u_c, Q in m³/s and ml/min, A(ζ1)/A0,
    the validity verdict) or "effective-medium" (the second table of model "both"/"effective-medium").
    A verdict is "yes", "NO" (outside the continuum theory, docs/theory.md §9.11) or "—" (no leak channel).
    """
    cols = (_band_columns(result) if result.band is not None and table == "critical-junction"
            else _cj_columns(result) if table == "critical-junction" else _em_columns(result))
    headers = [c[0] for c in cols]
    rows = [[c[2][i] for c in cols] for i in range(len(cols[0][2]))]
    return headers, rows


def _table_lines(cols: Sequence[Column | GasColumn]) -> list[str]:
    widths = [max(c[1], len(c[0]) + 1) for c in cols]
    lines = [" ".join(c[0].rjust(w) for c, w in zip(cols, widths))]
    for i in range(len(cols[0][2])):
        lines.append(" ".join(c[2][i].rjust(w) for c, w in zip(cols, widths)))
    return lines


def validity_notes(result: CaseResult) -> list[str]:
    """One line per model and kind of invalid rows: which pressures, why, and where d comes from (docs/theory.md §9.11)."""
    fluid = result.case.fluid
    d = f"d = {fluid.molecular_length * 1e9:.3g} nm ({fluid.molecular_length_note}; fluid.molecular_size sets it)"
    out: list[str] = []
    if result.band is not None:
        b = result.band
        both = b.effective_medium is not None and result.shows_critical_junction
        verdicts = [("critical junction", b.critical_junction.percolates, result.valid, result.validity)]
        if (b.effective_medium is not None and result.valid_effective_medium is not None
                and result.validity_effective_medium is not None):
            verdicts.append(("effective medium", b.effective_medium.percolates, result.valid_effective_medium,
                             result.validity_effective_medium))
        for theory, percolates, valid, reasons in verdicts:
            if theory == "critical junction" and not result.shows_critical_junction:
                continue
            column = f"valid {'CJ' if theory == 'critical junction' else 'EM'}" if both else "valid"
            for i in np.flatnonzero(~valid):  # (a row without a leak channel too: the fluid pressure opens it)
                out.append(f"{load_text(b.band.load_name, b.band.loads[i])}: {column} = NO ({theory}): {reasons[i]}")
        return out
    res = result.critical_junction
    checks = [("critical junction", result.valid, res.squeeze_pressure, "u_c", result.validity, res.percolates)]
    if (result.effective_medium is not None and result.valid_effective_medium is not None
            and result.validity_effective_medium is not None):
        em = result.effective_medium
        checks.append(("effective medium", result.valid_effective_medium, em.squeeze_pressure, "u_e",
                       result.validity_effective_medium, em.percolates))
    for name, valid, p0, gap, reasons, percolates in checks:
        lifted = np.array([bool(r) and r.startswith("ΔP") for r in reasons])
        small = np.array([bool(r) and "molecular" in r for r in reasons]) & ~lifted
        thick = ~valid & ~small & ~lifted
        if (lifted & percolates).any() and result.case.coupled:  # (ignored: the theory's own note says it)
            out.append(f"{name}, {pressures_text(p0, lifted & percolates)}: valid = NO: ΔP reaches the lift-off pressure "
                       "difference (ΔP ≥ P0): the fluid pressure opens the seal; the leak rate shown is the limit ΔP → P0, "
                       "the open seal leaks more (theory §13.4)")
        if (lifted & ~percolates).any():
            out.append(f"{name}, {pressures_text(p0, lifted & ~percolates)}: valid = NO: "
                       + ("ΔP reaches the lift-off pressure difference (ΔP ≥ P0)" if result.case.coupled else
                          "ΔP is not small against P0") + ": the fluid pressure opens the seal that the theory finds shut "
                       "(no leak channel at P0 without the fluid's pressure): the open seal leaks, by how much the theory "
                       "does not say (theory §13.4)")
        if small.any():
            out.append(f"{name}, {pressures_text(p0, small)}: valid = NO: {gap} is below the molecular size of the "
                       f"fluid, {d}; a continuum theory of flow says nothing about a channel narrower than a molecule, "
                       "so Q there is the formula's value, not a prediction")
        if thick.any():
            out.append(f"{name}, {pressures_text(p0, thick)}: valid = NO: {gap} is as large as the channel's width, "
                       "so the flow is not the thin-film (Poiseuille) flow the theory assumes; check the roughness "
                       "amplitude and the seal's size")
    return out


def _cell_columns(headers: list[str], rows: list[list[str]]) -> list[Column]:
    """The columns of a table given as headers and rows of cells, each at least 8 wide and as wide as its widest cell
    (a study's variant names are longer than "variant")."""
    return [(h, max([8] + [len(r[i]) for r in rows]), [r[i] for r in rows]) for i, h in enumerate(headers)]


def uncertainty_lines(unc: UncertaintyResult) -> list[str]:
    """The uncertainty block ``sealeak predict`` prints under the deterministic table: the inputs, the percentiles per
    row, the passing loads (docs/user-guide.md, Uncertain inputs)."""
    lines = ["", uncertainty_heading(unc)]
    lines += [f"  {inp.label}" for inp in unc.study.inputs]
    lines += _table_lines(_cell_columns(*uncertainty_columns(unc)))
    lines.append("          " + uncertainty_legend(unc))
    lines += passing_lines(unc)
    return lines


def sensitivity_lines(s: SobolIndices, unc: UncertaintyResult) -> list[str]:
    """The sensitivity block ``sealeak predict --sensitivity N`` prints under the uncertainty block: ST (S1) per row and
    input, then one sentence per case on what to measure better first (docs/user-guide.md, Sensitivity)."""
    lines = ["", sensitivity_heading(s)]
    lines += _table_lines(_cell_columns(*sensitivity_columns(s, unc.study)))
    lines.append("          " + sensitivity_legend())
    return lines + sensitivity_sentences(s, unc.study)


def prediction_table(results: Sequence[CaseResult], uncertainty: UncertaintyResult | None = None,
                     sensitivity: SobolIndices | None = None) -> str:
    """A plain-text report: the case, then one table row per squeeze pressure.

    With effective-medium results (model "both") their leak rate stands next to the critical-junction
    one, and a second table gives ū(1), the mean of P(u), u_e and σ_eff. Warnings about the inputs
    come before the table, the notes and validity verdicts after it.
    """
    lines: list[str] = []
    first = results[0].case
    lines.append(first.title)
    lines.append("=" * min(len(first.title), 100))
    first_blocks = _settings(results[0])
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
            for key, block in _settings(r).items():
                if case is first or block != first_blocks.get(key):
                    lines.extend(block)
        lines.extend("warning: " + w for w in r.warnings)
        if r.band is not None:
            lines.append("")
            lines.extend(_table_lines(_band_columns(r)))
            lines.append("          " + band_legend(r))
            if case.gas is not None:
                lines.append("          " + GAS_INCOMPRESSIBLE_NOTE)
            lines.extend(_gas_block(r))
            lines.extend("note: " + m for m in worded(r.messages))
            lines.extend("note: " + m for m in validity_notes(r))
            continue
        if r.shows_critical_junction:
            lines.append("")
            lines.extend(_table_lines(_cj_columns(r)))
            if case.gas is not None:
                lines.append("          " + GAS_INCOMPRESSIBLE_NOTE)
            lines.extend("note: " + m for m in worded(res.messages))
        if em is not None:
            lines.append("")
            lines.append("effective medium (2D Bruggeman):")
            lines.extend(_table_lines(_em_columns(r)))
            lines.append("          <u>_P: mean of the gap distribution P(u) (>= ū(1): the folded Gaussians add to it); "
                         "u_e: the gap whose u³/(12η) equals σ_eff")
            lines.extend("note: " + m for m in worded(em.messages))
        lines.extend(_gas_block(r))
        lines.extend("note: " + m for m in validity_notes(r))
    if uncertainty is not None:
        lines += uncertainty_lines(uncertainty)
        if sensitivity is not None:
            lines += sensitivity_lines(sensitivity, uncertainty)
    return "\n".join(lines) + "\n"
