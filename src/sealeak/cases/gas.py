"""The gas leak of a case's seal per row, and its helium equivalent (docs/theory.md §11.5, §11.9).

:func:`gas_rows` turns a seal's conductance K and narrowest gap h into the pV throughput, molar,
mass and standard volume flow of the case's gas with its rarefaction, and the helium leak of the
same seal in the standard test (1 bar against vacuum, 20 °C); :func:`gas_throughput` is the pV
throughput at other pressure differences (the fit, the Q(ΔP) curves). With the fluid pressure coupled, the leak
and the helium equivalent are the exact gas coupling of each row's seal (:class:`CoupledGasSeal`,
docs/theory.md §13.5); with ``rubber.permeability``, the permeation through the rubber (§11.11).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..io.leak_units import to_mbar_l_per_s, to_sccm
from ..io.quantities import quantity, record_fields, units_of
from ..physics.contact import PerssonContact
from ..physics.coupling import LIFT_OFF_FLOOR, GasSheet, Sheet, coupled_gas_band_flow, coupled_gas_integral, gas_sheet
from ..physics.critical_junction import CriticalJunctionResult, critical_junction
from ..physics.effective_medium import EffectiveMediumResult
from ..physics.gas import Gas, GasLeak, gas_leak, pressure_integral, with_throughput
from ..physics.permeation import OringPermeation, oring_permeation, slab_permeation
from ..physics.profile import PressureProfile
from ..physics.properties import fluid_state
from .band import BandResult
from .band_tables import effective_medium_sigma_table, persson_contact
from .model import Case
from .prediction import FloatArray, Model, _band_effective_gap
from .schema import case_keys

__all__ = ["GasRows", "GasColumns", "HeliumColumns", "PermeationColumns", "gas_rows", "GAS_UNITS", "HELIUM_UNITS",
           "PERMEATION_UNITS", "HELIUM_TEST", "helium_test_gas", "gas_throughput", "CoupledGasSeal", "uniform_gas_seals",
           "band_gas_seal"]

@dataclass(frozen=True, kw_only=True)
class GasColumns:
    """The gas record columns of one theory, one value per row (a gas case); the effective medium's keys carry the
    suffix ``_effective_medium``."""

    knudsen_number: FloatArray = quantity("1", "Knudsen number λ/h at the mean pressure")
    flow_regime: list[str] = quantity("", "flow regime named by the Knudsen number")
    leak_rate_pv: FloatArray = quantity("Pa*m^3/s", "pV throughput of the gas at its temperature (fluid pressure "
                                                    "coupled: the gas pressure taken off the contact, docs/theory.md §13.5)")
    leak_rate_mbar_l_s: FloatArray = quantity("mbar*l/s", "pV throughput in mbar·l/s")
    leak_rate_mass: FloatArray = quantity("kg/s", "mass flow")
    leak_rate_molar: FloatArray = quantity("mol/s", "molar flow")
    leak_rate_sccm: FloatArray = quantity("sccm", "standard volume flow")


@dataclass(frozen=True, kw_only=True)
class HeliumColumns:
    """The helium-equivalent record columns (a gas case, or a liquid with ``conditions.helium_equivalent``)."""

    leak_rate_helium_pv: FloatArray = quantity("Pa*m^3/s", "helium leak in the standard test (1 bar against vacuum, 20 °C)")
    leak_rate_helium_mbar_l_s: FloatArray = quantity("mbar*l/s", "helium leak in the standard test in mbar·l/s")


@dataclass(frozen=True, kw_only=True)
class PermeationColumns:
    """The permeation columns of a gas case with ``rubber.permeability`` (docs/theory.md §11.11)."""

    leak_rate_permeation_pv: FloatArray = quantity("Pa*m^3/s", "steady pV throughput of the gas through the rubber "
                                                               "(an O-ring's cord, or the slab seal.height × width)")
    permeation_breakthrough_time: FloatArray = quantity("s", "time lag t²/(6D) of the permeation (null without "
                                                             "rubber.diffusivity)")
    leak_rate_total_pv: FloatArray = quantity("Pa*m^3/s", "interface leak plus permeation: what a leak test measures "
                                                          "once the permeation has broken through")
    leak_rate_total_mbar_l_s: FloatArray = quantity("mbar*l/s", "interface leak plus permeation in mbar·l/s")


#: SI unit of the gas fields of a record, from :class:`GasColumns`.
GAS_UNITS: dict[str, str] = units_of(GasColumns)
#: SI unit of the helium-equivalent fields, from :class:`HeliumColumns`.
HELIUM_UNITS: dict[str, str] = units_of(HeliumColumns)
#: SI unit of the permeation fields, from :class:`PermeationColumns`.
PERMEATION_UNITS: dict[str, str] = units_of(PermeationColumns)

#: The standard helium leak test: helium at 1 bar (absolute) against vacuum, 20 °C (docs/theory.md §11.9).
HELIUM_TEST = {"upstream_pressure": 1e5, "downstream_pressure": 0.0, "temperature": 293.15}


def helium_test_gas() -> Gas:
    """Helium at 20 °C and 1 bar from the property library: the gas of the helium-equivalent leak rate."""
    t, p = HELIUM_TEST["temperature"], HELIUM_TEST["upstream_pressure"]
    return fluid_state("helium", t, p).gas()


@dataclass(frozen=True)
class GasRows:
    """One theory's gas leak per row (squeeze pressure or load), SI units (docs/theory.md §11.5, §11.9).

    Attributes
    ----------
    conductance
        K = Q/ΔP of the seal with the case's viscosity (m³/(Pa·s)); 0 where no leak channel.
    gap
        h, the gap of the narrowest constriction (m): u_c (critical junction), u_e (effective
        medium), or u_c at the peak contact pressure of a band seal; NaN where no leak channel.
    length
        L, the constriction's length along the flow (m): the critical junction's λ_c, which caps the
        kinetic model's free-molecular flow (docs/theory.md §11.4); NaN: an infinite slit.
    leaks
        The :class:`~sealeak.physics.gas.GasLeak` of the case's gas per row (None: a liquid case,
        or no leak channel).
    helium
        Q_pV of helium in the standard test (1 bar against vacuum, 20 °C) through the same seal,
        Pa·m³/s (None: not asked for).
    permeation
        The permeation through the rubber of a gas case with ``rubber.permeability`` (an O-ring, a ring or
        rectangle with ``seal.height``), per row, else None; the total (interface + permeation) counts a row without a leak channel as
        permeation alone.
    seals
        The :class:`CoupledGasSeal` of each row when the fluid pressure is coupled (docs/theory.md §13.5), else None:
        the Q_pV(ΔP) curves use them.

    Rows without a leak channel hold NaN leak rates (``null`` in JSON), as the liquid's ``leak_rate``.
    """

    conductance: FloatArray
    gap: FloatArray
    length: FloatArray
    leaks: tuple[GasLeak | None, ...] | None
    helium: FloatArray | None
    permeation: OringPermeation | None = None
    seals: tuple[CoupledGasSeal, ...] | None = None

    def fields(self, suffix: str = "") -> dict[str, Any]:
        """The record fields (:data:`GAS_UNITS`, :data:`HELIUM_UNITS`, with ``suffix``) as arrays per row."""
        out: dict[str, Any] = {}
        if self.leaks is not None:
            def pick(attr: str) -> FloatArray:
                return np.array([getattr(g, attr) if g is not None else np.nan for g in self.leaks or ()])

            pv = pick("throughput")
            molar = pick("molar_flow")
            out |= record_fields(GasColumns(
                knudsen_number=pick("knudsen_mean"), flow_regime=[g.regime if g is not None else "" for g in self.leaks],
                leak_rate_pv=pv, leak_rate_mbar_l_s=to_mbar_l_per_s(pv), leak_rate_mass=pick("mass_flow"),
                leak_rate_molar=molar, leak_rate_sccm=to_sccm(molar)))
        if self.helium is not None:
            out |= record_fields(HeliumColumns(leak_rate_helium_pv=self.helium,
                                               leak_rate_helium_mbar_l_s=to_mbar_l_per_s(self.helium)))
        if self.permeation is not None:
            perm = self.permeation.throughput
            interface = np.array([g.throughput if g is not None else 0.0 for g in self.leaks or ()])
            total = interface + perm if interface.size else perm
            out |= record_fields(PermeationColumns(
                leak_rate_permeation_pv=perm, permeation_breakthrough_time=self.permeation.breakthrough_time,
                leak_rate_total_pv=total, leak_rate_total_mbar_l_s=to_mbar_l_per_s(total)))
        return {k + suffix: v for k, v in out.items()}


def gas_rows(case: Case, conductance: ArrayLike, gap: ArrayLike, length: ArrayLike | None = None,
             permeation: OringPermeation | None = None, seals: list[CoupledGasSeal] | None = None, *,
             helium: bool = True) -> GasRows:
    """The case's gas leak (if a gas case) and the helium equivalent (if asked for) per row.

    ``conductance`` K (m³/(Pa·s)) was computed with ``case.fluid.viscosity``, the gas's own
    viscosity for a gas case (K ∝ 1/μ: Poiseuille flow). The helium equivalent is the helium leak
    of the same seal: K μ_case/μ_He, the same gap, helium's rarefaction, 1 bar against vacuum at
    20 °C (docs/theory.md §11.9). ``length`` (m, per row): the constriction's length along the flow,
    the critical junction's λ_c, which caps the kinetic model's free-molecular flow (docs/theory.md
    §11.4); None or NaN: an infinite slit. ``seals`` (one per row): the fluid pressure acts on the contact, and the
    leaks and the helium equivalent are the exact gas coupling of each row's seal (docs/theory.md §13.5; K, h and
    the Knudsen numbers stay those above). ``helium`` False: no helium column even if the case asks for it.
    """
    k = np.atleast_1d(np.asarray(conductance, dtype=float))
    h = np.atleast_1d(np.asarray(gap, dtype=float))
    channel = (k > 0) & np.isfinite(h) & (h > 0)
    lengths = np.broadcast_to(np.nan if length is None else np.asarray(length, dtype=float), k.shape)

    def cap(i: int) -> float | None:
        return float(lengths[i]) if np.isfinite(lengths[i]) and lengths[i] > 0 else None
    leaks = None
    gas = case.gas
    if gas is not None:
        with case_keys():
            leaks = tuple(gas_leak(float(k[i]), float(h[i]), gas.gas, gas.upstream_pressure, gas.downstream_pressure,
                                   gas.rarefaction, cap(i)) if channel[i] else None for i in range(k.size))
            if seals is not None:
                pa, pb = gas.upstream_pressure, gas.downstream_pressure
                leaks = tuple(None if g is None else with_throughput(g, seal.throughput(gas.gas, gas.rarefaction, pa, pb),
                                                                     gas.gas) for g, seal in zip(leaks, seals, strict=True))
    he_pv = None
    if case.helium_equivalent and helium:
        he = helium_test_gas()
        scale = case.fluid.viscosity / he.viscosity
        pa, pb = HELIUM_TEST["upstream_pressure"], HELIUM_TEST["downstream_pressure"]
        with case_keys():
            he_pv = np.array([np.nan if not channel[i] else seals[i].throughput(he, case.rarefaction, pa, pb)
                              if seals is not None else
                              gas_leak(float(k[i]) * scale, float(h[i]), he, pa, pb, case.rarefaction, cap(i)).throughput
                              for i in range(k.size)])
    return GasRows(np.where(channel, k, 0.0), np.where(channel, h, np.nan), np.array(lengths, dtype=float), leaks, he_pv,
                   permeation if leaks is not None else None, tuple(seals) if seals is not None else None)


def _uniform_gas(case: Case, res: CriticalJunctionResult, em: EffectiveMediumResult | None) -> dict[str, GasRows]:
    """Gas rows of a uniform seal: K = Q/ΔP of each theory; the gap u_c, or u_e for the effective medium; the
    constriction's length λ_c for both (docs/theory.md §11.9); with the fluid pressure coupled, the exact gas
    coupling of each row (§13.5); with the permeation through the rubber slab ``seal.height`` × w (§11.11) when the
    case gives it."""
    def seals(model: Model, percolates: NDArray[np.bool_]) -> list[CoupledGasSeal] | None:
        return uniform_gas_seals(case, model, res.squeeze_pressure, percolates) if case.coupled else None

    perm = None
    if case.permeation is not None and case.gas is not None and case.permeation.height is not None:
        with case_keys({"permeability": "rubber.permeability", "diffusivity": "rubber.diffusivity"}):
            perm = slab_permeation(case.permeation.permeability, case.permeation.diffusivity,
                                   np.full(res.squeeze_pressure.size, case.permeation.height), case.seal.width,
                                   case.seal.length, case.gas.upstream_pressure - case.gas.downstream_pressure)

    out = {"critical_junction": gas_rows(case, np.where(res.percolates, res.leak_rate / res.pressure_difference, 0.0),
                                         res.critical_gap, res.critical_wavelength, perm,
                                         seals("critical-junction", res.percolates))}
    if em is not None:
        out["effective_medium"] = gas_rows(case, np.where(em.percolates, em.leak_rate / em.pressure_difference, 0.0),
                                           np.where(em.percolates, em.effective_gap, np.nan), res.critical_wavelength,
                                           perm, seals("effective-medium", em.percolates))
    return out


def _band_gas(case: Case, band: BandResult) -> dict[str, GasRows]:
    """Gas rows of a band seal: K = Q/ΔP of the band; the gap of the narrowest constriction, u_c at the peak
    contact pressure (critical junction) or u_e = (12 μ σ_min)^(1/3) of the smallest σ along the band (effective
    medium), docs/theory.md §11.9; with the permeation through the rubber (§11.11) when the case gives it; with the
    fluid pressure coupled, the exact gas coupling of each load's band (§13.5)."""
    out = {}
    perm = None
    b = band.band
    if case.permeation is not None and case.gas is not None and b.cross_section_diameter is not None:
        with case_keys({"permeability": "rubber.permeability", "diffusivity": "rubber.diffusivity"}):
            perm = oring_permeation(case.permeation.permeability, case.permeation.diffusivity, b.cross_section_diameter,
                                    b.loads, b.length, case.gas.upstream_pressure - case.gas.downstream_pressure)
    for name, theory in (("critical_junction", band.critical_junction), ("effective_medium", band.effective_medium)):
        if theory is None or theory.leak_rate is None:
            continue
        k = np.where(theory.percolates, np.nan_to_num(theory.leak_rate) / band.pressure_difference, 0.0)
        gap = band.critical_gap_at_max_pressure if name == "critical_junction" else _band_effective_gap(case, theory)
        model: Model = "critical-junction" if name == "critical_junction" else "effective-medium"
        seals = ([band_gas_seal(case, model, i, bool(ok)) for i, ok in enumerate(theory.percolates)]
                 if case.coupled else None)
        out[name] = gas_rows(case, k, gap, band.critical_wavelength_at_max_pressure, perm, seals)
    return out


def gas_throughput(case: Case, k: FloatArray, gap: FloatArray, dp: FloatArray, length: FloatArray | None = None,
                   seals: Sequence[CoupledGasSeal] | None = None) -> FloatArray:
    """Q_pV (Pa·m³/s) per row: P_b the case's, P_a = P_b + ΔP of the row (docs/theory.md §11.5, §11.9, §13.5).

    ``k`` the no-slip conductance K (m³/(Pa·s)), ``gap`` the narrowest gap h (m) and ``dp`` ΔP (Pa) per
    row; NaN where K = 0 or there is no gap, 0 where ΔP = 0. Without ``seals``: K ∫ p f dp at the gap h, ``length``
    (m, per row) the constriction's length λ_c, as in :func:`gas_rows` (None or NaN: an infinite slit). With
    ``seals`` (one :class:`CoupledGasSeal` per row, the fluid pressure coupled): the exact gas coupling of each row's
    seal at its P_a (eqs. 13.6, 13.7), as :func:`gas_rows` computes the leak at the case's pressures.
    """
    gas = case.gas
    assert gas is not None
    pb = gas.downstream_pressure
    out = np.full(k.size, np.nan)
    for i in range(k.size):
        if k[i] > 0 and np.isfinite(gap[i]) and gap[i] > 0 and dp[i] == 0:
            out[i] = 0.0
        elif k[i] > 0 and np.isfinite(gap[i]) and gap[i] > 0 and dp[i] > 0:
            with case_keys():
                if seals is not None:
                    out[i] = seals[i].throughput(gas.gas, gas.rarefaction, pb + float(dp[i]), pb)
                    continue
                cap = None if length is None or not np.isfinite(length[i]) or length[i] <= 0 else float(length[i])
                out[i] = k[i] * pressure_integral(float(gap[i]), gas.gas, pb + float(dp[i]), pb, gas.rarefaction, cap)
    return out


# ---------------------------------------------------------------------- the exact gas coupling (docs/theory.md §13.5)
def _cj_sheet(case: Case, contact: PerssonContact) -> Sheet:
    """σ = α u_c³/(12μ) (m³/(Pa·s)), the gap u_c and the length λ_c (m) of the critical junction at effective pressures."""
    def sheet(s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        res = critical_junction(contact, squeeze_pressure=s, pressure_difference=1.0, viscosity=case.fluid.viscosity,
                                aspect_ratio=1.0, alpha=case.alpha, percolation_threshold=case.percolation_threshold)
        ok = res.percolates
        return (np.where(ok, res.leak_rate, 0.0), np.where(ok, res.critical_gap, np.nan),
                np.where(ok, res.critical_wavelength, np.nan))
    return sheet


def _theory_sheet(case: Case, contact: PerssonContact, model: Model, low: float, high: float) -> GasSheet | None:
    """The :class:`~sealeak.physics.coupling.GasSheet` of one theory over effective pressures [low, high] (Pa): the
    critical junction's σ, u_c, λ_c, or the effective medium's σ_eff with its gap u_e = (12 μ σ_eff)^(1/3) and the
    critical junction's λ_c (docs/theory.md §11.9); None where the contact seals somewhere in the range."""
    cj = _cj_sheet(case, contact)
    if model == "critical-junction":
        return gas_sheet(cj, low, high)
    sigma_em = effective_medium_sigma_table(case, contact, high, low / high)

    def sheet(s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        sigma = sigma_em(s)
        return sigma, np.cbrt(12.0 * case.fluid.viscosity * sigma), cj(s)[2]
    return gas_sheet(sheet, low, high)


@dataclass(frozen=True)
class CoupledGasSeal:
    """One theory's seal at one row under the exact gas coupling (docs/theory.md §13.5, eqs. 13.6, 13.7).

    A uniform seal at ``squeeze_pressure`` P0 (Pa), ``factor`` = Ly/Lx, or a band of ``profile``, ``factor`` =
    faces · Ly (m); ``sheet`` None: no leak channel. σ was computed with ``viscosity`` (Pa·s).
    """

    sheet: GasSheet | None
    factor: float
    viscosity: float
    squeeze_pressure: float = 0.0
    profile: PressureProfile | None = None
    _done: dict[tuple[Gas, str, float, float], float] = field(default_factory=dict, compare=False, repr=False)

    def throughput(self, gas: Gas, model: str, upstream: float, downstream: float) -> float:
        """Q_pV (Pa·m³/s) of ``gas`` between the absolute pressures ``upstream`` and ``downstream`` (Pa), the
        rarefaction ``model``; 0 without a leak channel (σ ∝ 1/μ: rescaled to the gas's viscosity). Remembered: a
        helium case's helium equivalent is its own leak."""
        key = (gas, model, float(upstream), float(downstream))
        if self.sheet is None:
            return 0.0
        if key not in self._done:
            g = self.sheet.for_gas(gas, model, self.viscosity / gas.viscosity)
            if self.profile is None:
                q = float(coupled_gas_integral(g, self.squeeze_pressure, downstream, upstream - downstream).value[0])
            else:
                q = coupled_gas_band_flow(self.profile, g, downstream, upstream - downstream).flow
            self._done[key] = self.factor * q
        return self._done[key]


def uniform_gas_seals(case: Case, model: Model, squeeze_pressure: ArrayLike, percolates: ArrayLike) -> list[CoupledGasSeal]:
    """The :class:`CoupledGasSeal` of a uniform seal at each squeeze pressure P0 (Pa), one σ table for all rows
    (effective pressures from :data:`~sealeak.physics.coupling.LIFT_OFF_FLOOR` × the lowest P0 to the highest)."""
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    ok = np.broadcast_to(np.asarray(percolates, dtype=bool), p0.shape)
    sheet = (_theory_sheet(case, case.contact(), model, LIFT_OFF_FLOOR * float(p0[ok].min()), float(p0[ok].max()))
             if ok.any() else None)
    return [CoupledGasSeal(sheet if good else None, case.seal.aspect_ratio, case.fluid.viscosity, float(top))
            for top, good in zip(p0, ok, strict=True)]


def band_gas_seal(case: Case, model: Model, index: int, percolates: bool) -> CoupledGasSeal:
    """The :class:`CoupledGasSeal` of a band seal at its load ``index`` (its profile and q0)."""
    band = case.band
    assert band is not None
    profile = band.profiles[index]
    top = profile.max_pressure
    sheet = (_theory_sheet(case, persson_contact(case, float(band.q0[index])), model, LIFT_OFF_FLOOR * top, top)
             if percolates else None)
    return CoupledGasSeal(sheet, band.faces * band.length, case.fluid.viscosity, profile=profile)
