"""Leak rate of a seal with a non-uniform contact pressure: O-rings and pressure-profile files.

Each load (an O-ring's compression, or a scale factor on a profile file) gives a nominal pressure
profile p(x) across the band. Strip by strip the seal conducts like a uniform seal at p(x), with
the sheet conductance of the theory (docs/theory.md §10.1):

* critical junction: σ(p) = α u_c(p)³/(12η) (Lorenz & Persson (2009) eq. 2 per unit width);
* effective medium: σ(p) = σ_eff(p) (Bruggeman; docs/theory.md §5.3).

The strips are in series, Q = faces · Ly ΔP / ∫₀^w dx/σ(p(x)) (:func:`sealeak.physics.profile.series_resistance`).
Every strip uses the contact mechanics of the band, with q0 = 2π/w (w the load's contact width)
unless the case file sets q0. Beside it the leak rate that a uniform pressure equal to the mean
would give, Q_u = faces · (Ly/w) σ(p_mean) ΔP, shows what averaging the pressure would do.

The effective medium costs a few ms per pressure, so its σ(p) is interpolated between exact values at
Chebyshev points in ln p (barycentric, in ln σ) over [p_max·TABLE_FLOOR, p_max] (TABLE_FLOOR = 1e-3), the points
doubled until R changes by less than TABLE_RTOL (1e-5); pressures below the table's end take σ there (a strip of
relative width ~5e-7 for a Hertz profile, where σ is largest). With the fluid pressure coupled the tables reach
down to LIFT_OFF_FLOOR × the pressure (docs/theory.md §13.3); a sweep's loads share one σ_eff surface
(:class:`~sealeak.cases.band_tables.SweepSurface`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.quantities import quantity
from ..physics.contact import PerssonContact
from ..physics.coupling import LIFT_OFF_FLOOR, CoupledBand, coupled_band_flow, effective_pressure_integral
from ..physics.critical_junction import critical_junction
from ..physics.effective_medium import bruggeman_threshold
from ..physics.profile import RTOL, BandIntegral, PressureProfile, resistance_band, series_resistance
from .band_tables import (
    JUNCTION_RTOL,
    TABLE_FLOOR,
    TABLE_POINTS,
    TABLE_RTOL,
    JunctionSurface,
    SigmaTable,
    SweepSurface,
    effective_medium_exact,
    effective_medium_sigma_table,
    junction_exact,
    persson_contact,
)
from .cancel import check as check_cancelled
from .model import BandSeal, Case
from .notes import Note, NoteLike
from .schema import case_keys

__all__ = ["ScaledJunctions", "scaled_junctions", "BandResult", "BandTheory", "run_band", "band_conductance", "BandColumns",
           "BandEffectiveMediumColumns", "load_value"]

FloatArray = NDArray[np.float64]

#: A sweep of this many loads or more shares one σ_eff surface (:class:`~sealeak.cases.band_tables.SweepSurface`).
SURFACE_MIN_LOADS = 5
#: ... and from this many loads on one critical-junction surface (:class:`~sealeak.cases.band_tables.JunctionSurface`):
#: its 2 300–4 600 exact values cost what some ten loads' own calls of the junction do (the `o-ring` example's 9 loads take
#: as long either way; 50 loads a quarter less with it), and a band evaluated again (a web update of ΔP or η) reads kept
#: exact values faster than it interpolates the surface's 513 points.
JUNCTION_SURFACE_MIN_LOADS = 16


@dataclass(frozen=True, kw_only=True)
class BandColumns:
    """The record columns of a band seal's critical-junction result, one value per load (JSON ``results``, CSV)."""

    contact_width: FloatArray = quantity("m", "contact width w of the load's pressure profile")
    force_per_length: FloatArray = quantity("N/m", "force per length f = ∫p dx")
    mean_contact_pressure: FloatArray = quantity("Pa", "mean contact pressure f/w")
    max_contact_pressure: FloatArray = quantity("Pa", "highest contact pressure p_max")
    pressure_difference: FloatArray = quantity("Pa", "pressure difference across the seal")
    percolates: NDArray[np.bool_] = quantity("1", "the strip at p_max percolates (a leak channel exists)")
    leak_rate: FloatArray = quantity("m^3/s", "leak rate Q through the band (strips in series)")
    leak_rate_uniform_mean_pressure: FloatArray = quantity("m^3/s", "leak rate of a uniform pressure equal to the mean")
    critical_gap_at_max_pressure: FloatArray = quantity("m", "critical gap u_c where the pressure is highest")
    resistance_band_width: FloatArray = quantity("m", "width of the narrowest part of the band holding 90 % of R")
    resistance_peak_position: FloatArray = quantity("m", "position where 1/σ is largest")
    lowest_wavevector: FloatArray = quantity("1/m", "q0 of the load")
    integral_relative_change: FloatArray = quantity("1", "estimated relative error of the resistance R")


@dataclass(frozen=True, kw_only=True)
class BandEffectiveMediumColumns:
    """The record columns of a band seal's effective-medium result, one value per load (with the case's model)."""

    percolates_effective_medium: NDArray[np.bool_] = quantity("1", "the effective medium conducts at p_max")
    leak_rate_effective_medium: FloatArray = quantity("m^3/s", "effective-medium leak rate Q through the band")
    leak_rate_effective_medium_uniform_mean_pressure: FloatArray = quantity(
        "m^3/s", "effective-medium leak rate of a uniform pressure equal to the mean")
    resistance_band_width_effective_medium: FloatArray = quantity(
        "m", "width of the narrowest part of the band holding 90 % of the effective medium's R")
    integral_relative_change_effective_medium: FloatArray = quantity(
        "1", "estimated relative error of the effective medium's R")


@dataclass(frozen=True, kw_only=True)
class BandTheory:
    """One theory's leak rates over the loads of a band seal (arrays per load, SI units).

    Attributes
    ----------
    leak_rate
        Q = faces · Ly ΔP / R (m³/s); NaN where the band holds no leak channel.
    percolates
        False where some strip (the one at p_max) does not percolate.
    uniform_mean_pressure
        faces · (Ly/w) σ(p_mean) ΔP (m³/s), NaN where the mean pressure does not percolate.
    resistance
        R = ∫dx/σ (Pa·s/m²).
    resistance_band_width, resistance_peak_position
        Width of the narrowest part of the band holding 90 % of R, and where 1/σ is largest (m).
    integrals
        The quadrature of each load (points, p, σ), for the figures.
    change, evaluations
        Estimated relative error of R (quadrature and, for the effective medium, the change between
        the last two tables) and the number of σ evaluations.
    messages
        Notes (no channel at some loads, a quadrature that did not converge), worded by
        :mod:`sealeak.render.notes`.
    """

    leak_rate: FloatArray
    percolates: NDArray[np.bool_]
    uniform_mean_pressure: FloatArray
    resistance: FloatArray
    resistance_band_width: FloatArray
    resistance_peak_position: FloatArray
    integrals: tuple[BandIntegral, ...]
    change: FloatArray
    evaluations: NDArray[np.int_]
    messages: tuple[NoteLike, ...] = ()


@dataclass(frozen=True, kw_only=True)
class BandResult:
    """A band seal's leak rates per load, with its contact (SI units; arrays per load).

    Attributes
    ----------
    band
        The seal (loads, profiles, O-ring contact).
    pressure_difference
        ΔP (Pa).
    contact_width, force_per_length, mean_contact_pressure, max_contact_pressure
        w (m), f = ∫p dx (N/m), f/w and p_max (Pa) of each load's profile.
    q0
        q0 of each load (1/m).
    critical_junction
        The critical-junction theory (α of the case).
    effective_medium
        The effective medium, when the case asks for it.
    critical_gap_at_max_pressure, critical_wavelength_at_max_pressure
        u_c and λc where the pressure is highest (m): the narrowest constriction of the band,
        which the validity verdict judges.
    coupled
        Whether the leak rates take the fluid pressure in the band into account (docs/theory.md §13).
    """

    band: BandSeal
    pressure_difference: float
    contact_width: FloatArray
    force_per_length: FloatArray
    mean_contact_pressure: FloatArray
    max_contact_pressure: FloatArray
    q0: FloatArray
    critical_junction: BandTheory
    effective_medium: BandTheory | None
    critical_gap_at_max_pressure: FloatArray
    critical_wavelength_at_max_pressure: FloatArray
    coupled: bool = False

    def __len__(self) -> int:
        return int(self.band.loads.size)

    def columns(self) -> BandColumns:
        """The critical-junction record columns per load."""
        cj = self.critical_junction
        return BandColumns(
            contact_width=self.contact_width, force_per_length=self.force_per_length,
            mean_contact_pressure=self.mean_contact_pressure, max_contact_pressure=self.max_contact_pressure,
            pressure_difference=np.full(len(self), self.pressure_difference), percolates=cj.percolates,
            leak_rate=cj.leak_rate, leak_rate_uniform_mean_pressure=cj.uniform_mean_pressure,
            critical_gap_at_max_pressure=self.critical_gap_at_max_pressure,
            resistance_band_width=cj.resistance_band_width, resistance_peak_position=cj.resistance_peak_position,
            lowest_wavevector=self.q0, integral_relative_change=cj.change)

    def effective_medium_columns(self) -> BandEffectiveMediumColumns | None:
        """The effective-medium record columns per load (None when the case does not ask for that model)."""
        em = self.effective_medium
        if em is None:
            return None
        return BandEffectiveMediumColumns(
            percolates_effective_medium=em.percolates, leak_rate_effective_medium=em.leak_rate,
            leak_rate_effective_medium_uniform_mean_pressure=em.uniform_mean_pressure,
            resistance_band_width_effective_medium=em.resistance_band_width,
            integral_relative_change_effective_medium=em.change)

    def local_critical_gap(self, i: int, alpha: float, viscosity: float) -> FloatArray:
        """u_c(x) = (12 η σ(x)/α)^(1/3) (m) on the points of load ``i``'s critical-junction quadrature."""
        sigma = self.critical_junction.integrals[i].conductance
        return np.cbrt(12.0 * viscosity * sigma / alpha)


@dataclass(frozen=True)
class ScaledJunctions:
    """The critical junction of a case whose contact is a nominal one scaled (docs/theory.md eqs. 14.6, 14.8): h_rms × s
    (``length``) and E* × k (``modulus``) give u_c(p) = s u_c,nom(p/(k s)), so σ(p) = (α/η) s³ σ̃_nom(p/(k s)) with
    σ̃_nom the nominal σ at α = 1 and η = 1 Pa·s. ``tables`` holds σ̃_nom by the load's q0 (1/m): a function of
    scaled pressures (Pa) that is NaN where it does not reach (the exact σ is taken there). Set for a block of code by
    :func:`scaled_junctions`; the uncertainty band's samples of a band seal use it (cases/uncertainty.py)."""

    tables: Mapping[float, Callable[[FloatArray], FloatArray]]
    length: float
    modulus: float


_SCALED_JUNCTIONS: ContextVar[ScaledJunctions | None] = ContextVar("scaled_junctions", default=None)


@contextmanager
def scaled_junctions(scaled: ScaledJunctions) -> Iterator[None]:
    """Within the block, a band's critical-junction σ at a load whose q0 ``scaled`` tabulates comes from the table."""
    token = _SCALED_JUNCTIONS.set(scaled)
    try:
        yield
    finally:
        _SCALED_JUNCTIONS.reset(token)


def junction_sigma(case: Case, contact: PerssonContact, surface: JunctionSurface | None = None,
                   ) -> Callable[[FloatArray], FloatArray]:
    """σ(p) = α u_c³/(12η) (m³/(Pa·s)), 0 where the non-contact area does not percolate; from the nominal contact's
    table where :func:`scaled_junctions` gives one for this contact's q0, else from a sweep's ``surface`` where given
    (exact where the table or surface does not reach)."""
    exact = junction_exact(case, contact)
    scaled = _SCALED_JUNCTIONS.get()
    table = scaled.tables.get(contact.q0) if scaled is not None else None
    if scaled is None or table is None:
        return exact if surface is None else surface.for_load(case, contact)
    factor = case.alpha / case.fluid.viscosity * scaled.length**3
    stretch = scaled.modulus * scaled.length

    def sigma(p: FloatArray) -> FloatArray:
        p = np.asarray(p, dtype=float)
        out = factor * table(p / stretch)
        missing = np.isnan(out)
        if missing.any():
            out[missing] = exact(p[missing])
        return out
    return sigma


def _junction_at_peak(case: Case, contact: PerssonContact, p_max: float,
                      sigma: Callable[[FloatArray], FloatArray], surface: JunctionSurface | None = None,
                      ) -> tuple[float, float]:
    """(u_c, λc) (m, m) of the critical junction at a band's peak pressure ``p_max`` (Pa), NaN where it does not
    percolate. Where :func:`scaled_junctions` tabulates this contact's σ (an uncertainty sample: a new contact, whose
    exact junction at one pressure costs ~1 ms), or a sweep has its ``surface``, from the band's own ``sigma``
    (:func:`junction_sigma`; nothing beyond the percolation limit): u_c = (12 η σ(p_max)/α)^(1/3) (docs/theory.md eq. 3.5, within the table's
    tolerance) and λc = 2π/(ζc q0), ζc in closed form (eq. 3.3); otherwise the critical junction itself."""
    scaled = _SCALED_JUNCTIONS.get()
    if (scaled is not None and contact.q0 in scaled.tables) or surface is not None:
        zeta_c, percolates = contact.zeta_at_area(1.0 - case.percolation_threshold, np.array([p_max]))
        if not percolates[0]:
            return np.nan, np.nan
        value = float(sigma(np.array([p_max]))[0])  # (0 where ζc reaches the end of the roughness: u_c = 0)
        return (float(np.cbrt(12.0 * case.fluid.viscosity * max(value, 0.0) / case.alpha)),
                float(2.0 * np.pi / (zeta_c[0] * contact.q0)))
    top = critical_junction(contact, squeeze_pressure=[p_max], pressure_difference=1.0,
                            viscosity=case.fluid.viscosity, aspect_ratio=1.0, alpha=case.alpha,
                            percolation_threshold=case.percolation_threshold)
    if not top.percolates[0]:
        return np.nan, np.nan
    return float(top.critical_gap[0]), float(top.critical_wavelength[0])


def _em_integral(case: Case, contact: PerssonContact, profile: PressureProfile,
                 exact: Callable[[FloatArray], FloatArray] | None = None) -> tuple[BandIntegral, float, bool]:
    """R of the effective medium through the σ(p) table, refined until R changes by < RTOL; (integral, change, converged).
    ``exact`` as for :func:`effective_medium_sigma_table`."""
    exact = effective_medium_exact(case, contact) if exact is None else exact
    p_max = profile.max_pressure
    if float(exact(np.array([p_max]))[0]) <= 0:
        return series_resistance(profile, lambda p: np.zeros_like(p)), 0.0, True
    # plateaus (constant pieces) and p_max are evaluated exactly; the table serves the rest
    table = SigmaTable(exact, p_max, TABLE_POINTS[0], threshold=bruggeman_threshold(contact))
    plateaus: dict[float, float] = {}
    if profile.shape == "table":
        flat = (np.diff(profile.pressure) == 0) & (np.diff(profile.x) > 0) & (profile.pressure[:-1] > 0)
        levels = np.unique(profile.pressure[:-1][flat])
        if levels.size:
            plateaus = dict(zip(levels.tolist(), exact(levels).tolist()))

    def sigma_of(tab: SigmaTable) -> Callable[[FloatArray], FloatArray]:
        def sigma(p: FloatArray) -> FloatArray:
            out = tab(p)
            for level, value in plateaus.items():
                out = np.where(p == level, value, out)
            return out
        return sigma

    integral = series_resistance(profile, sigma_of(table))
    change = float("inf")
    while True:
        if table.s.size >= TABLE_POINTS[1] or not table.ok:
            return integral, max(change, integral.change), False
        finer = table.refine(exact)
        again = series_resistance(profile, sigma_of(finer))
        change = abs(again.resistance - integral.resistance) / again.resistance if again.resistance > 0 else 0.0
        table, integral = finer, again
        if change <= TABLE_RTOL:
            return integral, max(change, again.change), again.converged


def _theory(case: Case, band: BandSeal, integrals: list[BandIntegral], changes: list[float], converged: list[bool],
            name: str, mean_sigma: FloatArray, coupled: list[CoupledBand] | None = None) -> BandTheory:
    """One theory's :class:`BandTheory`; with ``coupled`` (the flows q and ∫σ ds at the mean pressure of each load's
    coupled solve, docs/theory.md §13) the leak rates are faces · Ly · q, the uniform ones faces · (Ly/w) ∫σ ds."""
    ly, dp = band.length * band.faces, case.pressure_difference
    r = np.array([g.resistance for g in integrals])
    sealed = np.array([g.sealed for g in integrals])
    widths = np.array([p.width for p in band.profiles])
    if coupled is None:
        with np.errstate(divide="ignore"):
            q = np.where(sealed, np.nan, ly * dp / r)
        uniform = np.where(mean_sigma > 0, ly / widths * mean_sigma * dp, np.nan)
    else:
        q = np.where(sealed, np.nan, ly * np.array([c.flow for c in coupled]))
        uniform = np.where(mean_sigma > 0, ly / widths * mean_sigma, np.nan)
    where = [resistance_band(g) for g in integrals]
    messages: list[NoteLike] = []
    if sealed.any():
        messages.append(Note("band_sealed", {"theory": name, "load_name": band.load_name,
                                             "loads": tuple(band.loads[sealed].tolist())}))
    if coupled is not None and not all(c.converged for c in coupled):
        failed = ~np.array([c.converged for c in coupled])
        messages.append(Note("band_coupled_not_converged", {"theory": name, "load_name": band.load_name,
                                                            "loads": tuple(band.loads[failed].tolist())}))
    not_converged = [i for i, ok in enumerate(converged) if not ok]
    if not_converged:
        i = not_converged[0]
        messages.append(Note("band_not_converged", {
            "theory": name, "tolerance": RTOL if name.startswith("critical") else TABLE_RTOL,
            "load_name": band.load_name, "load": float(band.loads[i]), "change": changes[i]}))
    return BandTheory(leak_rate=q, percolates=~sealed, uniform_mean_pressure=uniform, resistance=r,
                      resistance_band_width=np.array([w for w, _ in where]),
                      resistance_peak_position=np.array([x for _, x in where]),
                      integrals=tuple(integrals), change=np.array(changes),
                      evaluations=np.array([g.evaluations for g in integrals]), messages=tuple(messages))


def _mean_sigma(case: Case, sigma: Callable[[FloatArray], FloatArray], mean: float) -> float:
    """σ(p_mean) (m³/(Pa·s)) of a uniform pressure equal to the mean, or with the fluid pressure acting on it
    (``case.coupled``) ∫σ(s) ds over p_mean − ΔP .. p_mean (m³/s; docs/theory.md eq. 13.2): 0 where p_mean seals."""
    at_mean = float(sigma(np.array([mean]))[0])
    if not case.coupled or at_mean <= 0:
        return at_mean
    return float(effective_pressure_integral(sigma, mean, case.pressure_difference).value[0])


def _scaled(sigma: Callable[[FloatArray], FloatArray], factor: float) -> Callable[[FloatArray], FloatArray]:
    """σ(p) × ``factor``: σ at another viscosity (σ ∝ 1/η)."""
    def scaled(p: FloatArray) -> FloatArray:
        return sigma(p) * factor
    return scaled


def _per_viscosity(band: CoupledBand, viscosity: float) -> CoupledBand:
    """The coupled flow of a band solved at η = 1 Pa·s, for the viscosity η (Pa·s): q/η (docs/theory.md §13.3)."""
    return replace(band, flow=band.flow / viscosity)


def load_value(load_name: str, value: float) -> str | float:
    """A band seal's load as an error message shows it: a compression (a fraction) in %, a profile scale as it is."""
    return f"{100 * value:.6g} %" if load_name == "compression" else float(value)


def _load_error(band: BandSeal, i: int, profile: PressureProfile, exc: InputError) -> InputError:
    """An error of the physics about a contact pressure, named as the load (conditions.profile_scale[i]) that gave it."""
    field = f"conditions.{band.load_name}" + (f"[{i}]" if band.loads.size > 1 else "")
    return InputError(field, load_value(band.load_name, float(band.loads[i])), f"gives a mean contact pressure of {profile.mean_pressure:.4g} Pa (peak "
                                    f"{profile.max_pressure:.4g} Pa), which the theory cannot use: "
                                    + exc.allowed.replace("a larger squeeze pressure (Pa)", f"a larger {band.load_name}"))


def _sweep_range(case: Case, band: BandSeal) -> tuple[float, float] | None:
    """The pressures (Pa) a sweep of at least :data:`SURFACE_MIN_LOADS` loads asks its surfaces for: down to
    :data:`LIFT_OFF_FLOOR` × the lowest mean pressure with the fluid pressure coupled, else :data:`TABLE_FLOOR` × the
    lowest peak, up to the highest peak; None for fewer loads."""
    if band.loads.size < SURFACE_MIN_LOADS:
        return None
    profiles = band.profiles
    low = (LIFT_OFF_FLOOR * min(p.mean_pressure for p in profiles) if case.coupled
           else TABLE_FLOOR * min(p.max_pressure for p in profiles))
    if not (np.isfinite(low) and low > 0):
        return None
    return low, max(p.max_pressure for p in profiles)


def _surface(case: Case, band: BandSeal) -> SweepSurface | None:
    """The σ_eff surface of a sweep over the pressures of :func:`_sweep_range`, or None."""
    span = _sweep_range(case, band)
    if span is None:
        return None
    try:
        return SweepSurface.build(case, np.asarray(band.q0, dtype=float), *span)
    except InputError:  # a pressure the theory cannot use: the load that gives it says so below, exactly
        return None


def _junction_surface(case: Case, band: BandSeal) -> JunctionSurface | None:
    """The critical junction's surface of a sweep of at least :data:`JUNCTION_SURFACE_MIN_LOADS` loads over the
    pressures of :func:`_sweep_range`, or None (also where :func:`scaled_junctions` gives the loads' tables: an
    uncertainty sample)."""
    span = _sweep_range(case, band)
    if span is None or band.loads.size < JUNCTION_SURFACE_MIN_LOADS or _SCALED_JUNCTIONS.get() is not None:
        return None
    try:
        return JunctionSurface.build(case, np.asarray(band.q0, dtype=float), *span)
    except InputError:  # a pressure the theory cannot use: the load that gives it says so below, exactly
        return None


def run_band(case: Case, *, effective: bool | None = None) -> BandResult:
    """Both theories (as ``case.model`` asks, or ``effective``) over the loads of a band seal (docs/theory.md §10.1)."""
    band = case.band
    if band is None:
        raise ValueError("run_band needs a case with a band seal (an O-ring or a pressure profile)")
    want_em = case.model != "critical-junction" if effective is None else effective
    cj_int: list[BandIntegral] = []
    cj_change: list[float] = []
    cj_ok: list[bool] = []
    em_int: list[BandIntegral] = []
    em_change: list[float] = []
    em_ok: list[bool] = []
    cj_mean, em_mean, uc_max, lc_max = [], [], [], []
    cj_flow: list[CoupledBand] = []
    em_flow: list[CoupledBand] = []
    dp = case.pressure_difference
    # the coupled flows are solved with σ at η = 1 Pa·s and divided by η (q ∝ 1/η, docs/theory.md §13.3): a band solved
    # once (coupling.py keeps it) serves every viscosity, e.g. the fluids of a study or a web update of η
    eta = case.fluid.viscosity
    unit = replace(case, fluid=replace(case.fluid, viscosity=1.0))
    with case_keys():
        surface = _surface(unit, band) if want_em else None  # at η = 1 Pa·s too: the same bits for every fluid
        junctions = _junction_surface(case, band)
        for i, (profile, q0) in enumerate(zip(band.profiles, band.q0, strict=True)):
            check_cancelled()  # (a client that has gone stops the band between loads)
            try:
                contact = persson_contact(case, float(q0))
                em_unit_exact = surface.for_load(contact) if surface is not None else None
                em_exact = effective_medium_exact(case, contact) if em_unit_exact is None else _scaled(em_unit_exact, 1.0 / eta)
                sigma = junction_sigma(case, contact, junctions)
                g = series_resistance(profile, sigma)
                cj_int.append(g)
                cj_change.append(g.change if junctions is None or g.sealed else max(g.change, JUNCTION_RTOL))
                cj_ok.append(g.converged)
                cj_mean.append(_mean_sigma(case, sigma, profile.mean_pressure))
                if case.coupled:  # a band sealed at its peak stays sealed (coupled_band_flow's answer, without its table)
                    cj_flow.append(CoupledBand(0.0, dp >= profile.max_pressure, True, 0) if g.sealed
                                   else _per_viscosity(coupled_band_flow(profile, junction_sigma(unit, contact, junctions), dp), eta))
                uc, lc = _junction_at_peak(case, contact, profile.max_pressure, sigma, junctions)
                uc_max.append(uc)
                lc_max.append(lc)
                if want_em:
                    ge, change, ok = _em_integral(case, contact, profile, em_exact)
                    em_int.append(ge)
                    em_change.append(change)
                    em_ok.append(ok)
                    if case.coupled:  # a band sealed at its peak stays sealed: σ is tabulated up to the mean only
                        p_top = profile.mean_pressure if ge.sealed else profile.max_pressure
                        em_unit = effective_medium_sigma_table(unit, contact, p_top, LIFT_OFF_FLOOR, em_unit_exact)
                        em_flow.append(CoupledBand(0.0, dp >= profile.max_pressure, True, 0) if ge.sealed
                                       else _per_viscosity(coupled_band_flow(profile, em_unit, dp), eta))
                        em_mean.append(_mean_sigma(case, _scaled(em_unit, 1.0 / eta), profile.mean_pressure))
                    else:
                        em_mean.append(float(em_exact(np.array([profile.mean_pressure]))[0]))
            except InputError as exc:  # the physics names the pressure; the case file gave the load
                if exc.field.partition("[")[0] != "squeeze_pressure":
                    raise
                raise _load_error(band, i, profile, exc) from None
    cj = _theory(case, band, cj_int, cj_change, cj_ok, "critical junction", np.array(cj_mean),
                 cj_flow if case.coupled else None)
    em = (_theory(case, band, em_int, em_change, em_ok, "effective medium", np.array(em_mean), em_flow if case.coupled else None)
          if want_em else None)
    profiles = band.profiles
    return BandResult(
        band=band, pressure_difference=case.pressure_difference,
        contact_width=np.array([p.width for p in profiles]),
        force_per_length=np.array([p.force_per_length for p in profiles]),
        mean_contact_pressure=np.array([p.mean_pressure for p in profiles]),
        max_contact_pressure=np.array([p.max_pressure for p in profiles]),
        q0=np.asarray(band.q0, dtype=float), critical_junction=cj, effective_medium=em,
        critical_gap_at_max_pressure=np.array(uc_max), critical_wavelength_at_max_pressure=np.array(lc_max),
        coupled=case.coupled,
    )


def band_conductance(case: Case, model: str = "critical-junction", loads: NDArray[np.float64] | None = None) -> FloatArray:
    """K = Q/ΔP (m³/(Pa·s)) of a band seal at each of its loads, for one theory (0 where sealed).

    K is the band's leak rate over the case's ΔP: the same at every ΔP as printed (docs/theory.md §10.1), at the
    case's ΔP with the fluid pressure coupled (§13.3).
    ``loads`` must be the case's loads (or None): other loads need a case built for them.
    """
    res = run_band(case, effective=model == "effective-medium")
    theory = res.critical_junction if model == "critical-junction" else res.effective_medium
    assert theory is not None
    return np.where(theory.percolates, theory.leak_rate / case.pressure_difference, 0.0)
