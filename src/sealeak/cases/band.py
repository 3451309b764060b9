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

The effective medium costs ~10 ms per pressure, so its σ(p) is interpolated between exact values at
Chebyshev points in ln p (barycentric, in ln σ) over [p_max·1e-6, p_max], the points doubled until R
changes by less than 1e-8; pressures below the table's end take σ(p_max·1e-6) (a strip of relative
width below 1e-12 for a Hertz profile).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy import special

from ..errors import InputError
from ..io.quantities import quantity
from ..physics.contact import PerssonContact
from ..physics.coupling import LIFT_OFF_FLOOR, CoupledBand, coupled_band_flow, effective_pressure_integral
from ..physics.critical_junction import critical_junction
from ..physics.effective_medium import effective_medium
from ..physics.gaps import CONDUCTIVITY_QUADRATURE, ArrayCache, contact_key
from ..physics.profile import RTOL, BandIntegral, PressureProfile, resistance_band, series_resistance
from .model import BandSeal, Case
from .notes import Note, NoteLike
from .schema import case_keys

__all__ = ["ScaledJunctions", "scaled_junctions", "BandResult", "BandTheory", "run_band", "band_conductance", "BandColumns",
           "BandEffectiveMediumColumns", "load_value"]

FloatArray = NDArray[np.float64]

#: The effective medium's σ(p) table: lowest pressure relative to p_max, Chebyshev points (first, most), and
#: the relative change of R between two tables at which it stops (far below the ~10 % of the Bruggeman model itself).
TABLE_FLOOR = 1e-3
TABLE_POINTS = (9, 33)
TABLE_RTOL = 1e-5
#: Bytes of effective-medium σ_eff values kept by :func:`_em_exact` (by contact, viscosity and list of pressures).
KEPT_SIGMA_BYTES = 16 * 2**20

#: The σ_eff surface the loads of a sweep share (:class:`_SweepSurface`): used from this many loads on; its relative
#: error against the exact σ_eff, checked off its points as it is built; its Chebyshev points in ln p (first, most) and
#: in ln q0 (first, most); its top as a fraction of the lowest Bruggeman threshold pressure of the loads.
SURFACE_MIN_LOADS = 5
SURFACE_RTOL = 1e-6
SURFACE_P_POINTS = (33, 129)
SURFACE_Q0_POINTS = (5, 9)
SURFACE_TOP = 0.8

_EM_SIGMA = ArrayCache(lambda: KEPT_SIGMA_BYTES)
_INTERPOLATE_ROWS = 512  # points per block of chebyshev_lobatto_interpolate: 512 × 129 terms, ~0.5 MB an array


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


def persson_contact(case: Case, q0: float) -> PerssonContact:
    """Persson's contact of the case's surface and rubber at q0 (1/m): one load of a band, a sample's table."""
    return PerssonContact(case.spectrum, case.e_star, q0, case.gamma)


@dataclass(frozen=True)
class ScaledJunctions:
    """The critical junction of a case whose contact is a nominal one scaled (docs/theory.md eq. 14.6): h_rms × s
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


def junction_sigma(case: Case, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
    """σ(p) = α u_c³/(12η) (m³/(Pa·s)), 0 where the non-contact area does not percolate; from the nominal contact's
    table where :func:`scaled_junctions` gives one for this contact's q0 (exact where the table does not reach)."""
    def exact(p: FloatArray) -> FloatArray:
        res = critical_junction(contact, squeeze_pressure=p, pressure_difference=1.0, viscosity=case.fluid.viscosity,
                                aspect_ratio=1.0, alpha=case.alpha, percolation_threshold=case.percolation_threshold)
        return np.where(res.percolates, res.leak_rate, 0.0)
    scaled = _SCALED_JUNCTIONS.get()
    table = scaled.tables.get(contact.q0) if scaled is not None else None
    if scaled is None or table is None:
        return exact
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
                      sigma: Callable[[FloatArray], FloatArray]) -> tuple[float, float]:
    """(u_c, λc) (m, m) of the critical junction at a band's peak pressure ``p_max`` (Pa), NaN where it does not
    percolate. Where :func:`scaled_junctions` tabulates this contact's σ (an uncertainty sample: a new contact, whose
    exact junction at one pressure costs ~1 ms), from the band's own ``sigma`` (:func:`junction_sigma`): u_c =
    (12 η σ(p_max)/α)^(1/3) (docs/theory.md eq. 3.5, within the table's tolerance) and λc = 2π/(ζc q0), ζc in closed form
    (eq. 3.3); otherwise the critical junction itself."""
    scaled = _SCALED_JUNCTIONS.get()
    if scaled is not None and contact.q0 in scaled.tables:
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


def _em_exact(case: Case, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
    """σ_eff(p) (m³/(Pa·s)) of the effective medium, 0 where it does not percolate; kept by contact, viscosity and the
    list of pressures (:data:`KEPT_SIGMA_BYTES`): a pressure's σ_eff depends on the others asked with it only in the last
    bit (the order of the Bruggeman sums), so a list is answered as it was computed, bit for bit (an update of ΔP or α
    evaluates the same tables)."""
    key = contact_key(contact, case.fluid.viscosity)

    def sigma(p: FloatArray) -> FloatArray:
        p = np.ascontiguousarray(p, dtype=float)
        digest = (key, p.shape, hashlib.blake2b(p.tobytes(), digest_size=16).digest())
        kept = _EM_SIGMA.get(digest)
        if kept is None:
            res = effective_medium(contact, squeeze_pressure=p, pressure_difference=1.0,
                                   viscosity=case.fluid.viscosity, aspect_ratio=1.0,
                                   gap_quadrature=CONDUCTIVITY_QUADRATURE)
            kept = _EM_SIGMA.put(digest, (np.where(res.percolates, res.leak_rate, 0.0),))
        return kept[0].copy()
    return sigma


def chebyshev_lobatto_interpolate(nodes: FloatArray, values: FloatArray, x: FloatArray) -> FloatArray:
    """The polynomial through ``values`` at the Chebyshev–Lobatto ``nodes`` (s_k = m − h cos(πk/(n−1))), at ``x``.

    The barycentric formula of the second kind with the weights of these nodes, w_k = (−1)^k, halved
    at both ends (Berrut & Trefethen, SIAM Review 46 (2004) 501, eq. 5.4): p(x) = Σ w_k f_k/(x − s_k) /
    Σ w_k/(x − s_k), exact at a node. The sums are running sums over k (``np.cumsum``, an accumulation from the
    left by definition, not a pairwise or BLAS sum whose grouping may depend on the length or alignment), so
    equal inputs give equal bits; the terms are formed for up to :data:`_INTERPOLATE_ROWS` points at a time.
    """
    x = np.asarray(x, dtype=float)
    weights = (-1.0) ** np.arange(nodes.size)
    weights[[0, -1]] *= 0.5
    flat = x.ravel()
    out = np.empty(flat.size)
    for lo in range(0, flat.size, _INTERPOLATE_ROWS):
        d = flat[lo:lo + _INTERPOLATE_ROWS, None] - nodes[None, :]
        at = d == 0
        c = weights / np.where(at, 1.0, d)
        part = np.cumsum(c * values, axis=1)[:, -1] / np.cumsum(c, axis=1)[:, -1]
        hit = at.any(axis=1)
        part[hit] = values[np.argmax(at[hit], axis=1)]
        out[lo:lo + _INTERPOLATE_ROWS] = part
    return out.reshape(x.shape)


class _Table:
    """σ(p) interpolated in ln σ against ln p through exact values at Chebyshev points (second kind)."""

    def __init__(self, exact: Callable[[FloatArray], FloatArray], p_max: float, n: int, floor: float = TABLE_FLOOR) -> None:
        self.lo, self.hi = np.log(p_max * floor), np.log(p_max)
        s = self._nodes(n)
        self.s = s
        p = np.exp(s)
        p[-1] = p_max  # (exp(ln p_max) may be an ulp off: the top is p_max itself, whose σ a caller may have asked for)
        self.values = exact(p)
        self.ok = bool(np.all(self.values > 0))
        self.log_values = np.log(np.where(self.values > 0, self.values, 1.0))

    def refine(self, exact: Callable[[FloatArray], FloatArray]) -> _Table:
        """The table on twice the intervals (the old points are reused)."""
        return self._finer(exact(np.exp(self._nodes(2 * (self.s.size - 1) + 1)[1::2])))

    def checked(self, exact: Callable[[FloatArray], FloatArray], rtol: float, grow: bool = True) -> tuple[_Table, bool]:
        """(this table, True) where it agrees with ``exact`` within ``rtol`` (relative, in σ) at a quarter of the points
        the table on twice the intervals adds (all 8 for a table of 9 points, every other one for 17, every fourth and
        the last from 33 on): the middles of its intervals, where the interpolation errs most and the error varies
        smoothly along the table. Otherwise (that finer table, False), the points checked being reused, or with
        ``grow`` False (this table, False). Where σ vanishes at a point checked, the finer table is not ``ok`` (σ is
        not tabulated in ln σ) and its other points are not evaluated."""
        n = 2 * (self.s.size - 1) + 1
        added = self._nodes(n)[1::2]
        pick = _checked_points(added.size)
        values = np.empty(added.size)
        values[pick] = exact(np.exp(added[pick]))
        positive = bool(np.all(values[pick] > 0))
        if positive and np.all(np.abs(self(np.exp(added[pick])) / values[pick] - 1.0) < rtol):
            return self, True
        if not grow:
            return self, False
        if not positive:
            values[~pick] = np.nan  # (a table that is not ok: its callers take σ itself)
        elif not pick.all():
            values[~pick] = exact(np.exp(added[~pick]))
        return self._finer(values), False

    def _finer(self, added: FloatArray) -> _Table:
        """The table on twice the intervals, from its ``added`` values (the old ones are reused)."""
        n = 2 * (self.s.size - 1) + 1
        new = _Table.__new__(_Table)
        new.lo, new.hi = self.lo, self.hi
        values = np.empty(n)
        values[::2] = self.values
        values[1::2] = added
        new.s, new.values = new._nodes(n), values
        new.ok = bool(np.all(values > 0))
        new.log_values = np.log(np.where(values > 0, values, 1.0))
        return new

    def _nodes(self, n: int) -> FloatArray:
        """The ``n`` Chebyshev–Lobatto points of [lo, hi] (ln p), the ends exact."""
        return _lobatto(self.lo, self.hi, n)

    def __call__(self, p: FloatArray) -> FloatArray:
        return np.exp(self.log_at(p))

    def log_at(self, p: FloatArray) -> FloatArray:
        """ln σ interpolated at the pressures ``p`` (Pa; clipped to the table's range)."""
        s = np.clip(np.log(p), self.lo, self.hi)
        return chebyshev_lobatto_interpolate(self.s, self.log_values, s)


def effective_medium_sigma_table(case: Case, contact: PerssonContact, p_max: float, floor: float,
                                 exact: Callable[[FloatArray], FloatArray] | None = None,
                                 ) -> Callable[[FloatArray], FloatArray]:
    """σ_eff(p) (m³/(Pa·s)) over [floor·p_max, p_max] (Pa): exact at Chebyshev points in ln p, interpolated in ln σ
    between them, refined until it agrees with σ within :data:`TABLE_RTOL` at the points checked
    (:meth:`_Table.checked`), at most to
    2·``TABLE_POINTS[1]`` − 1 points (the exact σ where it vanishes somewhere in the range). ``exact``: σ_eff of
    this contact (default the effective medium itself; a sweep passes its :class:`_SweepSurface`)."""
    exact = _em_exact(case, contact) if exact is None else exact
    table = _Table(exact, p_max, TABLE_POINTS[0], floor)
    while table.ok and table.s.size < 2 * TABLE_POINTS[1] - 1:
        table, good = table.checked(exact, TABLE_RTOL)
        if good:
            return table
    return table if table.ok else exact


class _SweepSurface:
    """σ_eff(p; q0) (m³/(Pa·s)) shared by the loads of a sweep: the effective medium's P(u) costs ~5 ms per pressure,
    and every load has its own q0 = 2π/w, so without it no exact value serves two loads.

    q0 enters Persson's contact only as the lower limit of G(ζ) = (π/4)E*² ∫_{q0}^{q} q³C dq (everything else is a
    function of q = ζq0 itself), so σ_eff changes smoothly and little with it: σ_eff is interpolated in ln q0
    (barycentric, Chebyshev–Lobatto points over the loads' range) and in ln p. At the middle q0 point a :class:`_Table`
    of ln σ against ln p over [``low``, ``high``] Pa is doubled until it agrees with the exact σ_eff to
    :data:`SURFACE_RTOL`/2 at a quarter of the points the next doubling would add (:meth:`_Table.checked`); at the other
    q0 points only the difference ln σ − ln σ_mid is tabulated (:meth:`_difference`), on every 2^k-th point of that
    table, doubled until it agrees with exact values at middles of its intervals to :data:`SURFACE_RTOL`/2: it is
    small (a few per cent at most) and smooth, so it needs a fraction of the points. Where a difference does not get
    there before it would need the middle table's own points, every q0 point takes a full table (as the middle one).
    The q0 points are doubled until the surface agrees with exact values of the load farthest from them, at pressures
    off the tables' points, to :data:`SURFACE_RTOL`. ``high`` stays a factor :data:`SURFACE_TOP` below every load's
    Bruggeman threshold (A(ζ1)/A0 = 1/2, closed form), where ln σ is smooth; pressures outside [``low``, ``high``] take
    the exact σ_eff. :meth:`build` returns None where the surface does not reach its tolerance within
    :data:`SURFACE_P_POINTS` and :data:`SURFACE_Q0_POINTS`.
    """

    def __init__(self, case: Case, nodes: FloatArray, base: _Table | None,
                 parts: list[tuple[FloatArray, FloatArray] | None], low: float, high: float, span: tuple[float, float]) -> None:
        """``parts``: per q0 point (``nodes``, ln q0) its values on Chebyshev–Lobatto points in ln p — ln σ itself where
        ``base`` is None, else the difference from ``base`` (None for the point of ``base``); ``span``: the table's
        ends in ln p."""
        self.case, self.nodes, self.base, self.parts, self.low, self.high = case, nodes, base, parts, low, high
        self.span = span

    @classmethod
    def build(cls, case: Case, q0: FloatArray, low: float, high: float) -> _SweepSurface | None:
        """The surface over the loads' ``q0`` (1/m) and pressures [``low``, ``high``] (Pa), or None."""
        q0 = np.unique(np.asarray(q0, dtype=float))
        threshold = 2.0 * special.erfinv(0.5) * min(
            math.sqrt(float(c.G(c.zeta_max))) for c in (persson_contact(case, float(q)) for q in q0))
        high = min(high, SURFACE_TOP * threshold)
        if not high > low:
            return None
        m = np.log(q0)
        n = 1 if q0.size == 1 else SURFACE_Q0_POINTS[0]
        middles: dict[float, _Table | None] = {}  # the middle table, checked to SURFACE_RTOL/2
        tables: dict[float, _Table | None] = {}  # full tables, where a difference does not do
        differences: dict[tuple[float, float], tuple[FloatArray, FloatArray]] = {}  # by (middle, point)
        full_tables = False
        while True:
            nodes = np.array([float(m[0])]) if n == 1 else _lobatto(float(m[0]), float(m[-1]), n)
            middle = float(nodes[nodes.size // 2])  # (the middle of 5 points is the middle of 9, bit for bit)
            if middle not in middles:
                middles[middle] = cls._table(case, cls._q0_at(middle, q0, m), low, high, 0.5 * SURFACE_RTOL)
            base = middles[middle]
            if base is None:
                return None
            for node in nodes.tolist():
                if full_tables:
                    break
                if node != middle and (middle, node) not in differences:
                    difference = cls._difference(case, cls._q0_at(node, q0, m), base)
                    if difference is None:  # a difference too rough for a coarser table: full tables from now on
                        full_tables = True
                    else:
                        differences[middle, node] = difference
            span = (float(base.lo), float(base.hi))
            if not full_tables:
                parts: list[tuple[FloatArray, FloatArray] | None] = [
                    None if node == middle else differences[middle, node] for node in nodes.tolist()]
                surface = cls(case, nodes, base, parts, low, high, span)
            else:
                for node in nodes.tolist():
                    if node not in tables:
                        tables[node] = base if node == middle else cls._table(case, cls._q0_at(node, q0, m), low, high,
                                                                              SURFACE_RTOL)
                full = [tables[node] for node in nodes.tolist()]
                if any(t is None for t in full):
                    return None
                surface = cls(case, nodes, None, [(t.s, t.log_values) for t in full if t is not None], low, high, span)
            far = int(np.argmax(np.min(np.abs(m[:, None] - nodes[None, :]), axis=1)))
            if n == 1 or np.min(np.abs(m[far] - nodes)) == 0:
                return surface
            check = np.exp(np.linspace(math.log(low), math.log(high), 10)[:-1] + 0.5 * math.log(high / low) / 9)
            exact = _em_exact(case, persson_contact(case, float(q0[far])))(check)
            if np.all(exact > 0) and np.all(np.abs(surface.sigma(float(q0[far]), check) / exact - 1.0) < SURFACE_RTOL):
                return surface
            if 2 * n - 1 > SURFACE_Q0_POINTS[1]:
                return None
            n = 2 * n - 1

    @staticmethod
    def _q0_at(node: float, q0: FloatArray, m: FloatArray) -> float:
        """The q0 (1/m) with ln q0 = ``node``: a load's own q0 at the ends of the range."""
        at = np.flatnonzero(m == node)
        return float(q0[at[0]]) if at.size else math.exp(node)

    @staticmethod
    def _table(case: Case, q0: float, low: float, high: float, rtol: float) -> _Table | None:
        """The table of ln σ_eff at ``q0`` over [``low``, ``high``] (Pa), checked to ``rtol`` (:meth:`_Table.checked`)."""
        exact = _em_exact(case, persson_contact(case, q0))
        table = _Table(exact, high, SURFACE_P_POINTS[0], low / high)
        while table.ok:
            grow = table.s.size < SURFACE_P_POINTS[1]
            table, good = table.checked(exact, rtol, grow=grow)
            if good:
                return table
            if not grow:
                return None
        return None

    @staticmethod
    def _difference(case: Case, q0: float, base: _Table) -> tuple[FloatArray, FloatArray] | None:
        """(points, values): ln σ_eff of the contact at ``q0`` less ``base``'s exact ln σ, at every 2^k-th point of
        ``base`` (from 9 points on), doubled until the interpolated difference agrees with exact values at the middles
        of its intervals (points of ``base`` too: all 8 of 9 points, every other one of 17, every fourth and the last
        from 33 points on) within :data:`SURFACE_RTOL`/2 in ln σ; with ``base`` checked to :data:`SURFACE_RTOL`/2 as
        well, the surface is within :data:`SURFACE_RTOL` at its q0 points (and checked between them by :meth:`build`).
        None where the difference needs the points of ``base`` itself, or σ_eff vanishes."""
        exact = _em_exact(case, persson_contact(case, q0))
        size = base.s.size
        step = (size - 1) // 8
        known: dict[int, float] = {}  # ln σ_eff at base's point i

        def log_sigma(index: NDArray[np.intp]) -> FloatArray | None:
            new = [i for i in index.tolist() if i not in known]
            if new:
                values = exact(np.exp(base.s[new]))
                if not np.all(values > 0):
                    return None
                known.update(zip(new, np.log(values).tolist()))
            return np.array([known[i] for i in index.tolist()])

        while step >= 2:
            points = np.arange(0, size, step)
            middles = np.arange(step // 2, size, step)
            pick = _checked_points(middles.size)
            both = log_sigma(np.concatenate([points, middles[pick]]))  # (one call: P(u) is vectorised over pressures)
            if both is None:
                return None
            at_points, at_middles = both[:points.size], both[points.size:]
            difference = at_points - base.log_values[points]
            interpolated = chebyshev_lobatto_interpolate(base.s[points], difference, base.s[middles[pick]])
            if np.all(np.abs(interpolated - (at_middles - base.log_values[middles[pick]])) < 0.5 * SURFACE_RTOL):
                return base.s[points], difference
            step //= 2
        return None

    def sigma(self, q0: float, p: FloatArray) -> FloatArray:
        """σ_eff (m³/(Pa·s)) of the load with ``q0`` (1/m) at pressures ``p`` inside [low, high] (Pa)."""
        return self._at(q0)(p)

    def _at(self, q0: float) -> Callable[[FloatArray], FloatArray]:
        """σ_eff(p) of the load with ``q0`` inside [low, high]: the interpolation in ln q0 is linear in the values,
        so ln σ = base + Σ_j w_j part_j (the weights sum to 1: the base once), and the parts on the same points combine
        into one before ln p is interpolated, once per size of table."""
        weights = [1.0] if self.nodes.size == 1 else [
            float(chebyshev_lobatto_interpolate(self.nodes, e, np.full(1, math.log(q0)))[0]) for e in np.eye(self.nodes.size)]
        combined: dict[int, tuple[FloatArray, FloatArray]] = {}
        if self.base is not None:
            combined[self.base.s.size] = (self.base.s, self.base.log_values)
        for w, part in zip(weights, self.parts, strict=True):
            if part is not None:
                s, values = combined.get(part[0].size, (part[0], np.zeros(part[0].size)))
                combined[part[0].size] = (s, values + w * part[1])
        lo, hi = self.span

        def sigma(p: FloatArray) -> FloatArray:
            x = np.clip(np.log(p), lo, hi)
            return np.exp(np.sum([chebyshev_lobatto_interpolate(s, v, x) for s, v in combined.values()], axis=0))
        return sigma

    def for_load(self, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
        """σ_eff(p) of one load's contact: the surface inside [low, high], the exact effective medium outside."""
        exact = _em_exact(self.case, contact)
        surface = self._at(contact.q0)

        def sigma(p: FloatArray) -> FloatArray:
            p = np.asarray(p, dtype=float)
            return piecewise(p, (p >= self.low) & (p <= self.high), surface, exact)
        return sigma


def _checked_points(n: int) -> NDArray[np.bool_]:
    """Which of ``n`` middles of a table's intervals a check evaluates: all of up to 15, every other one of 16 to 31,
    every fourth from 32 on, and always the last (:meth:`_Table.checked`, :meth:`_SweepSurface._difference`)."""
    pick = np.zeros(n, dtype=bool)
    pick[::min(4, max(1, n // 8))] = True
    pick[-1] = True
    return pick


def piecewise(p: FloatArray, first: NDArray[np.bool_], f: Callable[[FloatArray], FloatArray],
              g: Callable[[FloatArray], FloatArray]) -> FloatArray:
    """``f`` at the pressures ``p`` where ``first``, ``g`` at the others, each called on its own share only (and not
    at all where that is empty)."""
    out = np.empty(p.shape)
    if first.any():
        out[first] = f(p[first])
    if not first.all():
        out[~first] = g(p[~first])
    return out


def _lobatto(lo: float, hi: float, n: int) -> FloatArray:
    """The ``n`` Chebyshev–Lobatto points of [lo, hi], ascending, the ends exact."""
    s = (lo + hi) / 2.0 - (hi - lo) / 2.0 * np.cos(np.pi * np.arange(n) / (n - 1))
    s[0], s[-1] = lo, hi
    return np.asarray(s, dtype=float)


def _em_integral(case: Case, contact: PerssonContact, profile: PressureProfile,
                 exact: Callable[[FloatArray], FloatArray] | None = None) -> tuple[BandIntegral, float, bool]:
    """R of the effective medium through the σ(p) table, refined until R changes by < RTOL; (integral, change, converged).
    ``exact`` as for :func:`effective_medium_sigma_table`."""
    exact = _em_exact(case, contact) if exact is None else exact
    p_max = profile.max_pressure
    if float(exact(np.array([p_max]))[0]) <= 0:
        return series_resistance(profile, lambda p: np.zeros_like(p)), 0.0, True
    # plateaus (constant pieces) and p_max are evaluated exactly; the table serves the rest
    table = _Table(exact, p_max, TABLE_POINTS[0])
    plateaus: dict[float, float] = {}
    if profile.shape == "table":
        flat = (np.diff(profile.pressure) == 0) & (np.diff(profile.x) > 0) & (profile.pressure[:-1] > 0)
        levels = np.unique(profile.pressure[:-1][flat])
        if levels.size:
            plateaus = dict(zip(levels.tolist(), exact(levels).tolist()))

    def sigma_of(tab: _Table) -> Callable[[FloatArray], FloatArray]:
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


def _surface(case: Case, band: BandSeal) -> _SweepSurface | None:
    """The σ_eff surface of a sweep of at least :data:`SURFACE_MIN_LOADS` loads over every pressure its tables ask for
    (down to :data:`LIFT_OFF_FLOOR` × the lowest mean pressure with the fluid pressure coupled, else
    :data:`TABLE_FLOOR` × the lowest peak), or None."""
    if band.loads.size < SURFACE_MIN_LOADS:
        return None
    profiles = band.profiles
    low = (LIFT_OFF_FLOOR * min(p.mean_pressure for p in profiles) if case.coupled
           else TABLE_FLOOR * min(p.max_pressure for p in profiles))
    if not (np.isfinite(low) and low > 0):
        return None
    try:
        return _SweepSurface.build(case, np.asarray(band.q0, dtype=float), low, max(p.max_pressure for p in profiles))
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
        for i, (profile, q0) in enumerate(zip(band.profiles, band.q0, strict=True)):
            try:
                contact = persson_contact(case, float(q0))
                em_unit_exact = surface.for_load(contact) if surface is not None else None
                em_exact = _em_exact(case, contact) if em_unit_exact is None else _scaled(em_unit_exact, 1.0 / eta)
                sigma = junction_sigma(case, contact)
                g = series_resistance(profile, sigma)
                cj_int.append(g)
                cj_change.append(g.change)
                cj_ok.append(g.converged)
                cj_mean.append(_mean_sigma(case, sigma, profile.mean_pressure))
                if case.coupled:  # a band sealed at its peak stays sealed (coupled_band_flow's answer, without its table)
                    cj_flow.append(CoupledBand(0.0, dp >= profile.max_pressure, True, 0) if g.sealed
                                   else _per_viscosity(coupled_band_flow(profile, junction_sigma(unit, contact), dp), eta))
                uc, lc = _junction_at_peak(case, contact, profile.max_pressure, sigma)
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
