"""Where the theories stop holding: validity verdicts of results and warnings about inputs.

Two kinds of check (docs/theory.md §9):

* **Verdicts on results** (:func:`continuum_verdict`). Both leak-rate theories treat the fluid as a
  continuum flowing through a gap (Poiseuille flow, σ = u³/(12η); docs/theory.md §3.5, §5.2). A
  gap narrower than one molecule of the fluid is no channel for a continuum: a result whose
  critical gap u_c (or effective gap u_e) is below the fluid's molecular size d is computed, but
  marked as outside the theory's reach.
* **Warnings about inputs** (:func:`assumption_warnings`). Inputs far outside what the contact
  mechanics assumes — slopes of order one or more, roughness as large as the seal, a roughness
  cut-off below atomic size, squeeze pressures comparable to the rubber's modulus, full contact —
  are named once, in plain words. The numbers are still computed.

Plain SI floats in and out; no knowledge of case files (the cases layer relabels fields).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..io.units import format_quantity

__all__ = [
    "MOLECULAR_SIZES", "DEFAULT_MOLECULAR_SIZE", "ATOMIC_SIZE", "SLOPE_LIMIT", "STRAIN_LIMIT", "ALPHA_RANGE",
    "FULL_CONTACT", "RUBBER_MODULUS_LIMIT", "strain_warning", "pressures_text", "no_channel_note", "molecular_size", "continuum_verdict", "assumption_warnings",
]

#: Molecular size d (m) of common fluids, by lower-case name: the kinetic (collision) diameter for
#: small molecules, the cross-section of the chain for oils (docs/theory.md §9.11). Kinetic diameters
#: as tabulated by Breck, *Zeolite Molecular Sieves* (Wiley, 1974), ch. 8 (water 0.265 nm, N2 0.364 nm,
#: He 0.26 nm, H2 0.289 nm, O2 0.346 nm, CO2 0.33 nm, CH4 0.38 nm); an alkane chain is about 0.45 nm
#: across; the larger molecules (glycerol, silicone oil) are rounded estimates.
MOLECULAR_SIZES: dict[str, float] = {
    "water": 0.265e-9,
    "air": 0.364e-9,
    "nitrogen": 0.364e-9,
    "oxygen": 0.346e-9,
    "helium": 0.26e-9,
    "hydrogen": 0.289e-9,
    "carbon dioxide": 0.33e-9,
    "methane": 0.38e-9,
    "ethanol": 0.45e-9,
    "glycerol": 0.5e-9,
    "oil": 0.45e-9,
    "mineral oil": 0.45e-9,
    "hexadecane": 0.45e-9,
    "silicone oil": 0.6e-9,
}

#: d (m) of a fluid not in :data:`MOLECULAR_SIZES`: of the order of a small molecule.
DEFAULT_MOLECULAR_SIZE = 0.3e-9

#: The smallest length a surface can be rough on: about one interatomic distance (m).
ATOMIC_SIZE = 0.1e-9

#: rms slope above which the small-slope contact mechanics is doubtful (docs/theory.md §2.1).
SLOPE_LIMIT = 1.0

#: P0/E above which the rubber's nominal strain is too large for linear elasticity.
STRAIN_LIMIT = 0.5

#: Young's modulus (Pa) above which the seal is taken for no rubber: rubbers lie at about 1-100 MPa, hard
#: elastomers and PTFE below 1 GPa; metals and ceramics at 50-400 GPa neither seal this way nor follow
#: the O-ring relations.
RUBBER_MODULUS_LIMIT = 1e9

#: Range of the shape factor α beyond which it is taken for a mistake (it is of order one).
ALPHA_RANGE = (0.01, 100.0)

#: A(ζ1)/A0 at or above which the seal counts as in full contact.
FULL_CONTACT = 0.99


def molecular_size(name: str) -> tuple[float, bool]:
    """(d in m, whether ``name`` is a fluid of :data:`MOLECULAR_SIZES`); the default d otherwise."""
    key = " ".join(name.lower().replace("_", " ").replace("-", " ").split())
    if key in MOLECULAR_SIZES:
        return MOLECULAR_SIZES[key], True
    return DEFAULT_MOLECULAR_SIZE, False


def _nm(x: float) -> str:
    return f"{x * 1e9:.3g} nm"


def no_channel_note(squeeze_pressure: ArrayLike, percolates: ArrayLike, contact_area_at_cutoff: ArrayLike, why: str) -> str:
    """One note for every squeeze pressure without a leak channel: which P0, A(ζ1)/A0 there, and ``why``
    ('' when every pressure percolates). Both theories' notes (docs/theory.md §3.3, §5.4) are made here."""
    closed = ~np.asarray(percolates, dtype=bool)
    if not closed.any():
        return ""
    a = np.asarray(contact_area_at_cutoff, dtype=float)[closed]
    shown = f"{a[0]:.3f}" if a.size == 1 else f"{a.min():.3f} … {a.max():.3f}"
    return (f"{pressures_text(squeeze_pressure, closed)}: the contact area at the roughness cut-off is "
            f"A/A0 = {shown}{why}")


def continuum_verdict(gap: ArrayLike, molecular_size: float, name: str = "u_c", width: ArrayLike | None = None,
                      width_name: str = "λc") -> tuple[NDArray[np.bool_], tuple[str, ...]]:
    """Whether each result's gap (m) is a channel the flow theory describes (docs/theory.md §9.11).

    A result is outside the theory where ``gap`` < ``molecular_size`` d (no continuum flow through a
    gap narrower than a molecule), or, when ``width`` (m, the lateral size of the channel, e.g. λc)
    is given, where ``gap`` > ``width`` (Poiseuille's thin-film flow needs a gap small against the
    channel's width). Returns (valid, reasons): ``valid[i]`` False outside, ``reasons[i]`` says why
    ('' where valid). A NaN gap (no leak channel) counts as valid: the answer "no channel" needs
    no flow.
    """
    g = np.atleast_1d(np.asarray(gap, dtype=float))
    w = np.full_like(g, np.inf) if width is None else np.broadcast_to(np.asarray(width, dtype=float), g.shape)
    below = np.isfinite(g) & (g < molecular_size)
    thick = np.isfinite(g) & ~below & (g > w)
    reasons = tuple(
        f"{name} = {_gap_text(float(v))} is below the fluid's molecular size {_nm(molecular_size)}: "
        "the fluid cannot flow, as a continuum or as molecules, through a gap narrower than its molecules" if b else
        f"{name} = {format_quantity(float(v), 'length', 3)} is not small against the channel's width {width_name} = "
        f"{format_quantity(float(wi), 'length', 3)}: not a thin film" if t else ""
        for v, wi, b, t in zip(g, w, below, thick, strict=True)
    )
    return ~(below | thick), reasons


def _gap_text(v: float) -> str:
    return f"{v * 1e9:.3g} nm"


def pressures_text(squeeze_pressure: ArrayLike, where: ArrayLike) -> str:
    """Which squeeze pressures a note is about: "P0 = 1.2 MPa", or "P0 = 1.06 MPa … 10 MPa (20 of 40 pressures)"."""
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    sel = p0[np.asarray(where, dtype=bool)]
    if sel.size == 1:
        return f"P0 = {format_quantity(float(sel[0]), 'pressure', 4)}"
    span = f"P0 = {format_quantity(float(sel.min()), 'pressure', 4)} … {format_quantity(float(sel.max()), 'pressure', 4)}"
    return span + (" (all pressures)" if sel.size == p0.size else f" ({sel.size} of {p0.size} pressures)")


def assumption_warnings(
    *,
    slope_rms: float,
    h_rms: float,
    seal_width: float,
    cutoff_wavevector: float,
    squeeze_pressure: ArrayLike,
    youngs_modulus: float,
    contact_area_at_cutoff: ArrayLike,
    alpha: float = 1.0,
) -> list[str]:
    """Plain-words warnings for inputs far outside what the contact mechanics assumes (docs/theory.md §9.11).

    Parameters (SI): ``slope_rms`` (1), ``h_rms`` (m), ``seal_width`` Lx (m), ``cutoff_wavevector``
    q1 (1/m), ``squeeze_pressure`` P0 (Pa), ``youngs_modulus`` E of the rubber (Pa),
    ``contact_area_at_cutoff`` A(ζ1)/A0 at each P0 (1), ``alpha`` the critical junction's shape
    factor α (1; of order one, docs/theory.md §3.5). Each warning names the input, its value,
    the assumption it breaks and what to distrust; an empty list when nothing is out of reach.
    """
    out: list[str] = []
    if slope_rms > SLOPE_LIMIT:
        out.append(f"the surface's rms slope is {slope_rms:.3g}, of order one or more: Persson's contact mechanics "
                   "assumes small slopes, so contact areas and gaps (and the leak rates built on them) may be "
                   "off by tens of percent")
    if h_rms > seal_width:
        out.append(f"h_rms = {format_quantity(h_rms, 'length', 3)} is larger than the seal width "
                   f"Lx = {format_quantity(seal_width, 'length', 3)}: the theory treats the seal as a nominally flat contact "
                   "much wider than the roughness; this result is not meaningful")
    cutoff = 2.0 * np.pi / cutoff_wavevector
    if cutoff < ATOMIC_SIZE:
        out.append(f"the roughness cut-off wavelength 2π/q1 = {cutoff:.3g} m is below atomic size "
                   f"({ATOMIC_SIZE * 1e9:g} nm): no surface is rough on that scale; check the cut-off")
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    if youngs_modulus > RUBBER_MODULUS_LIMIT:
        out.append(f"E = {format_quantity(youngs_modulus, 'pressure', 3)} is no rubber's Young's modulus (rubbers: about "
                   "1 to 100 MPa, hard plastics a few GPa, metals 50 to 400 GPa): the "
                   "theory assumes a soft elastic seal, and an O-ring's force and contact width follow rubber relations; "
                   "check rubber.youngs_modulus and its unit")
    strained = strain_warning(p0, youngs_modulus)
    if strained:
        out.append(strained)
    if not ALPHA_RANGE[0] <= alpha <= ALPHA_RANGE[1]:
        out.append(f"α = {alpha:.3g} is far from one: α is a shape factor of the critical constriction, of order one "
                   "(fits to experiment give 0.2 to 1); a value outside 0.01 … 100 points to a mistake, and Q ∝ α")
    area = np.atleast_1d(np.asarray(contact_area_at_cutoff, dtype=float))
    full = area >= FULL_CONTACT
    if full.all():
        out.append(f"the rubber is in full contact (A/A0 >= {FULL_CONTACT:g} at the roughness cut-off) at every squeeze "
                   "pressure: no leak channel; lower the squeeze pressure or check E and the roughness")
    elif full.any():
        out.append(f"at P0 >= {format_quantity(float(p0[full].min()), 'pressure', 3)} the rubber is in full contact (A/A0 >= {FULL_CONTACT:g} at "
                   "the roughness cut-off): no leak channel there")
    return out


def strain_warning(squeeze_pressure: ArrayLike, youngs_modulus: float, what: str = "the squeeze pressure") -> str:
    """A warning where a squeeze pressure P0 (Pa) exceeds :data:`STRAIN_LIMIT` × E (Pa), else "".

    ``what`` names where P0 comes from (e.g. "the rig's load gives P0 = 1.78 GPa, which").
    """
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    strained = p0 > STRAIN_LIMIT * youngs_modulus
    if not strained.any():
        return ""
    p = float(p0[strained].min())
    return (f"at P0 >= {format_quantity(p, 'pressure', 3)} {what} exceeds {STRAIN_LIMIT:g} E "
            f"(E = {format_quantity(youngs_modulus, 'pressure', 3)}, P0/E = {p / youngs_modulus:.3g}): "
            "the rubber's strain is far beyond the linear elasticity the theory assumes")
