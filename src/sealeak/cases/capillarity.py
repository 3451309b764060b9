"""Capillarity of a liquid case: the entry pressure of each row's narrowest gap, and the rows it holds.

A case whose ``[fluid]`` gives a contact angle (``fluid.contact_angle``, or ``contact_angle_rubber``
and ``contact_angle_surface``) gets per theory and row the entry pressure p_e = −γ (cos θ_r + cos θ_s)/u
of the narrowest constriction u of the leak path (:mod:`sealeak.physics.capillarity`; docs/theory.md
§12): u_c for the critical junction, u_e for the effective medium, and for a band seal u_c at the
peak contact pressure or the effective medium's narrowest u_e along the band (the gaps of the gas
rows, docs/theory.md §11.9). Where ΔP < p_e the meniscus holds the liquid: the row's leak rate is 0
and it is flagged ``held_by_capillarity``; elsewhere the leak rate is the usual one. A case without
a contact angle has no capillarity and none of these columns.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.quantities import quantity, record_fields, units_of
from ..physics.capillarity import Wetting, check_contact_angle, check_surface_tension
from ..physics.critical_junction import CriticalJunctionResult
from ..physics.effective_medium import EffectiveMediumResult
from ..physics.properties import canonical_fluid_name, surface_tension
from .band import BandResult, BandTheory
from .model import Case
from .notes import Note
from .prediction import FloatArray, Model, _band_effective_gap, predict, predict_effective_medium
from .schema import CAPILLARITY_KEYS, Section, case_keys

__all__ = ["CapillaryColumns", "CapillaryRows", "CAPILLARY_UNITS", "build_wetting", "uniform_capillarity",
           "band_capillarity", "entry_steps", "held_sweep", "entry_pressures"]

#: The record key of each theory's columns (the effective medium's carry the suffix).
SUFFIX = {"critical_junction": "", "effective_medium": "_effective_medium"}


@dataclass(frozen=True, kw_only=True)
class CapillaryColumns:
    """The capillarity record columns of one theory, one value per row (a case with a contact angle)."""

    capillary_entry_pressure: FloatArray = quantity(
        "Pa", "entry pressure −γ(cos θ_r + cos θ_s)/u of the narrowest gap u (negative: a wetting liquid's suction)")
    held_by_capillarity: NDArray[np.bool_] = quantity("1", "ΔP is below the entry pressure: the liquid is held, Q = 0")


#: SI unit of the capillarity fields of a record, from :class:`CapillaryColumns`.
CAPILLARY_UNITS: dict[str, str] = units_of(CapillaryColumns)


@dataclass(frozen=True)
class CapillaryRows:
    """One theory's capillarity per row (squeeze pressure or load), SI units.

    ``gap`` the narrowest gap u (m; NaN where no leak channel), ``entry_pressure`` p_e (Pa; NaN there),
    ``held`` where ΔP < p_e (the row's leak rate is then 0).
    """

    gap: FloatArray
    entry_pressure: FloatArray
    held: NDArray[np.bool_]

    def fields(self, suffix: str = "") -> dict[str, Any]:
        """The record fields (:data:`CAPILLARY_UNITS`, with ``suffix``) as arrays per row."""
        out = record_fields(CapillaryColumns(capillary_entry_pressure=self.entry_pressure, held_by_capillarity=self.held))
        return {k + suffix: v for k, v in out.items()}


def build_wetting(fsec: Section, fluid_name: str, temperature: float, *, gas: bool) -> tuple[Wetting | None, tuple[str, ...]]:
    """The case's :class:`~sealeak.physics.capillarity.Wetting` from ``[fluid]`` (None without a contact angle), and warnings.

    ``fluid_name`` is the fluid's name as the case runs it, ``temperature`` T (K), ``gas`` whether it
    runs as a gas (a contact angle is then refused). γ is ``fluid.surface_tension``, else the property
    library's for a named liquid at T.
    """
    given = [k for k in CAPILLARITY_KEYS if fsec.has(k)]
    if not given:
        return None, ()
    if gas:
        raise InputError(fsec.field(given[0]), fsec.raw(given[0]), f"capillarity is for liquids: {fluid_name} is a gas "
                         "here, and a gas has no meniscus; remove the key")
    gamma = None
    if fsec.has("surface_tension"):
        gamma = check_surface_tension(fsec.field("surface_tension"), fsec.quantity("surface_tension", "surface_tension"))
    both = ("contact_angle_rubber", "contact_angle_surface")
    if fsec.has("contact_angle"):
        for key in both:
            if fsec.has(key):
                raise InputError(fsec.field(key), fsec.raw(key), "give either fluid.contact_angle (the same on both walls) "
                                 "or contact_angle_rubber and contact_angle_surface, not both")
        theta_r = theta_s = check_contact_angle(fsec.field("contact_angle"), fsec.raw("contact_angle"))
    elif all(fsec.has(k) for k in both):
        theta_r, theta_s = (check_contact_angle(fsec.field(k), fsec.raw(k)) for k in both)
    elif any(fsec.has(k) for k in both):
        missing, present = sorted(both, key=fsec.has)
        raise InputError(fsec.field(missing), None, f"is required with {fsec.field(present)}: give the contact angles on "
                         "both walls (or fluid.contact_angle for both)")
    else:
        return None, (f"{fsec.field('surface_tension')} = {fsec.raw('surface_tension')!r} is not used: capillarity needs "
                      "a contact angle (fluid.contact_angle, or contact_angle_rubber and contact_angle_surface)",)
    if gamma is not None:
        return Wetting(gamma, theta_r, theta_s), ()
    try:
        name = canonical_fluid_name(fluid_name)
    except InputError:
        raise InputError(fsec.field("surface_tension"), None, "is required with a contact angle for a liquid outside "
                         "the property library: give it with its unit (e.g. \"30 mN/m\")") from None
    with case_keys({"fluid": fsec.field("name"), "temperature": fsec.field("temperature")}):
        gamma, source = surface_tension(name, temperature)
    return Wetting(gamma, theta_r, theta_s, source), ()


def _rows(wetting: Wetting, gap: FloatArray, pressure_difference: float) -> CapillaryRows:
    u = np.where(np.isfinite(gap) & (gap > 0), gap, np.nan)
    return CapillaryRows(u, wetting.entry_pressure(u), wetting.held(u, pressure_difference))


def uniform_capillarity(case: Case, res: CriticalJunctionResult, em: EffectiveMediumResult | None
                        ) -> tuple[CriticalJunctionResult, EffectiveMediumResult | None, dict[str, CapillaryRows]]:
    """A uniform seal's results with the rows the meniscus holds set to Q = 0 (and a note), and each theory's rows.

    The narrowest gap is u_c (critical junction) and u_e (effective medium), NaN where no leak channel.
    """
    wetting = case.capillarity
    assert wetting is not None
    dp = case.pressure_difference
    rows = {"critical_junction": _rows(wetting, np.where(res.percolates, res.critical_gap, np.nan), dp)}
    res = _held(res, rows["critical_junction"], "critical junction", "squeeze_pressure", res.squeeze_pressure, dp)
    if em is not None:
        rows["effective_medium"] = _rows(wetting, np.where(em.percolates, em.effective_gap, np.nan), dp)
        em = _held(em, rows["effective_medium"], "", "squeeze_pressure", res.squeeze_pressure, dp)
    return res, em, rows


def band_capillarity(case: Case, band: BandResult) -> tuple[BandResult, dict[str, CapillaryRows]]:
    """A band seal's result with the loads the meniscus holds set to Q = 0 (and a note), and each theory's rows.

    The narrowest gap is u_c at the peak contact pressure (critical junction) or the effective medium's
    u_e = (12 μ σ_min)^(1/3) along the band (docs/theory.md §11.9, §12.1).
    """
    wetting = case.capillarity
    assert wetting is not None
    dp = case.pressure_difference
    rows: dict[str, CapillaryRows] = {}
    theories: dict[str, BandTheory | None] = {"critical_junction": band.critical_junction,
                                              "effective_medium": band.effective_medium}
    for name, theory in theories.items():
        if theory is None or theory.leak_rate is None:
            continue
        gap = band.critical_gap_at_max_pressure if name == "critical_junction" else _band_effective_gap(case, theory)
        rows[name] = _rows(wetting, np.where(theory.percolates, gap, np.nan), dp)
        theories[name] = _held(theory, rows[name], name.replace("_", " "), band.band.load_name, band.band.loads, dp)
    cj = theories["critical_junction"]
    assert cj is not None
    return replace(band, critical_junction=cj, effective_medium=theories["effective_medium"]), rows


def _held(result: Any, rows: CapillaryRows, theory: str, load_name: str, loads: FloatArray, dp: float) -> Any:
    """``result`` (a theory's result with ``leak_rate`` and ``messages``) with Q = 0 where ``rows`` hold, and a note
    (``held_by_capillarity``) naming the theory ("" for none) and the loads held (``load_name``: the case's load)."""
    if not rows.held.any():
        return result
    note = Note("held_by_capillarity", {"theory": theory, "load_name": load_name,
                                        "loads": tuple(np.asarray(loads, dtype=float)[rows.held].tolist()),
                                        "pressure_difference": dp,
                                        "entry_pressure": float(np.nanmin(rows.entry_pressure[rows.held]))})
    return replace(result, leak_rate=np.where(rows.held, 0.0, result.leak_rate), messages=(*result.messages, note))


def entry_steps(capillary: dict[str, CapillaryRows] | None, row: int, pressure_difference: FloatArray) -> FloatArray:
    """The ascending ΔP values (Pa) of a sweep with each theory's positive entry pressure of row ``row`` within their
    range added, and the float just below it: a figure then draws the step of eq. 12.3 upright."""
    top = float(pressure_difference[-1])
    entries = [float(rows.entry_pressure[row]) for rows in (capillary or {}).values()]
    extra = [x for p in entries if np.isfinite(p) and 0.0 < p < top for x in (float(np.nextafter(p, 0.0)), p)]
    return np.unique(np.concatenate([pressure_difference, extra])) if extra else pressure_difference


def held_sweep(rows: CapillaryRows | None, row: int, pressure_difference: FloatArray, q: FloatArray) -> FloatArray:
    """Q (m³/s) against ΔP (Pa) at the squeeze pressure of row ``row``, 0 where ΔP is below its entry pressure (eq. 12.3);
    ``q`` as it is without capillarity (``rows`` None)."""
    if rows is None:
        return q
    return np.where(pressure_difference < rows.entry_pressure[row], 0.0, q)


def entry_pressures(case: Case, models: tuple[Model, ...] | list[Model], squeeze_pressure: float,
                    band: BandResult | None = None) -> dict[Model, float]:
    """The capillary entry pressure p_e (Pa) of each model's narrowest gap at one load, without a contact angle none.

    A uniform seal at ``squeeze_pressure`` P0 (Pa): u_c or u_e there; a band seal: ``band``, its result at the one load
    (u_c at the peak, the effective medium's narrowest u_e). NaN where the model has no leak channel (docs/theory.md
    eq. 12.2). p_e does not depend on ΔP.
    """
    if case.capillarity is None:
        return {}
    if band is not None:
        rows = band_capillarity(case, band)[1]
    else:
        cj = predict(case, squeeze_pressure=[squeeze_pressure], pressure_difference=1.0)
        em = (predict_effective_medium(case, squeeze_pressure=[squeeze_pressure], pressure_difference=1.0)
              if "effective-medium" in models else None)
        rows = uniform_capillarity(case, cj, em)[2]
    return {m: float(rows[m.replace("-", "_")].entry_pressure[0]) for m in models}
