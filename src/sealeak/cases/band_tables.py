"""The σ(p) tables of a band seal (docs/theory.md §10.1): Chebyshev tables in ln p and the surfaces a sweep's loads share.

The effective medium costs ~5 ms per pressure (its P(u)), so a band takes σ_eff(p) from a table of ln σ against ln p
through exact values at Chebyshev–Lobatto points (:class:`SigmaTable`, :func:`effective_medium_sigma_table`), and
the loads of a sweep, each with its own q0, from one surface interpolated in ln q0 as well (:class:`SweepSurface`).
Exact values are kept by contact, viscosity and list of pressures (:func:`effective_medium_exact`). The critical
junction costs little per pressure but ~1 ms per call, and a band calls it some ten times (its quadrature's rounds, the
coupled band's table, the peak): a sweep's loads take its u_c from one surface too (:class:`JunctionSurface`).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..physics.contact import PerssonContact
from ..physics.critical_junction import critical_junction, percolation_limit
from ..physics.effective_medium import bruggeman_threshold, effective_medium
from ..physics.gaps import CONDUCTIVITY_QUADRATURE, ArrayCache, contact_key
from .model import Case

__all__ = ["SigmaTable", "SweepSurface", "JunctionSurface", "chebyshev_lobatto_interpolate", "effective_medium_exact",
           "effective_medium_sigma_table", "junction_exact", "lobatto_points", "persson_contact", "piecewise"]

FloatArray = NDArray[np.float64]

#: The effective medium's σ(p) table: lowest pressure relative to p_max, Chebyshev points (first, most), and
#: the relative change of R between two tables at which it stops (far below the ~10 % of the Bruggeman model itself).
TABLE_FLOOR = 1e-3
TABLE_POINTS = (9, 65)
TABLE_RTOL = 1e-5
#: Bytes of effective-medium σ_eff values kept by :func:`effective_medium_exact` (by contact, viscosity and list of pressures).
KEPT_SIGMA_BYTES = 16 * 2**20

#: The σ_eff surface the loads of a sweep share (:class:`SweepSurface`): its relative
#: error against the exact σ_eff, checked off its points as it is built; its Chebyshev points in ln p (first, most) and
#: in ln q0 (first, most); its top as a fraction of the lowest Bruggeman threshold pressure of the loads. It tabulates
#: σ_eff/(1 − p/P0_B)^:data:`THRESHOLD_EXPONENT` (docs/theory.md eq. 5.5): σ_eff vanishes as (P0_B − p)³ at the threshold P0_B,
#: which in ln σ is a logarithmic singularity the Chebyshev points of ln σ alone resolve only up to ~0.8 P0_B.
SURFACE_RTOL = 1e-6
SURFACE_P_POINTS = (33, 129)
SURFACE_Q0_POINTS = (5, 9)
SURFACE_TOP = 0.95
THRESHOLD_EXPONENT = 3.0

#: The critical junction's u_c(p; q0) surface a sweep's loads share (:class:`JunctionSurface`): its relative error in
#: σ = α u_c³/(12η) against the exact junction, checked off its points as it is built; its Chebyshev points in ln p
#: (first, most) and in ln q0 (first, most); its top as a fraction of the lowest percolation limit of the loads (towards
#: the limit u_c falls to 0 faster than any power, and the exact junction is taken above it).
JUNCTION_RTOL = 1e-7
JUNCTION_P_POINTS = (129, 1025)
JUNCTION_Q0_POINTS = (5, 17)
JUNCTION_TOP = 0.97
#: Beyond the load's percolation limit by this much (relative) σ is 0 without a call of the junction, which says the same
#: (the limit is closed-form; the margin keeps the rounding of the two apart).
CLOSED_MARGIN = 1e-9

#: Bytes of built junction surfaces kept (by contact, threshold, the loads' q0 and the range; ~40 kB each): a web update
#: of ΔP, η or α builds the surface of the same loads again.
KEPT_JUNCTION_SURFACE_BYTES = 4 * 2**20

_EM_SIGMA = ArrayCache(lambda: KEPT_SIGMA_BYTES)
_JUNCTION_SURFACES = ArrayCache(lambda: KEPT_JUNCTION_SURFACE_BYTES)
_INTERPOLATE_ROWS = 512  # points per block of chebyshev_lobatto_interpolate: 512 × 129 terms, ~0.5 MB an array


def persson_contact(case: Case, q0: float) -> PerssonContact:
    """Persson's contact of the case's surface and rubber at q0 (1/m): one load of a band, a sample's table."""
    return PerssonContact(case.spectrum, case.e_star, q0, case.gamma)


def effective_medium_exact(case: Case, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
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


def junction_exact(case: Case, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
    """σ(p) = α u_c³/(12η) (m³/(Pa·s)) of the critical junction, 0 where it does not percolate (docs/theory.md eq. 3.5)."""
    def sigma(p: FloatArray) -> FloatArray:
        res = critical_junction(contact, squeeze_pressure=p, pressure_difference=1.0, viscosity=case.fluid.viscosity,
                                aspect_ratio=1.0, alpha=case.alpha, percolation_threshold=case.percolation_threshold)
        return np.where(res.percolates, res.leak_rate, 0.0)
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


class SigmaTable:
    """σ(p) interpolated in ln σ against ln p through exact values at Chebyshev points (second kind).

    With ``threshold`` (P0_B > p_max, Pa: the effective medium's Bruggeman threshold, :func:`~sealeak.physics.effective_medium.bruggeman_threshold`) what is
    interpolated is ln r = ln σ − 3 ln(1 − p/P0_B), and σ = r (1 − p/P0_B)³: σ_eff vanishes as (1 − p/P0_B)³ (docs/theory.md
    eq. 5.5), a logarithmic singularity of ln σ that a polynomial in ln p follows only far below P0_B (on the `o-ring`
    sweep, tables of 33 points of ln σ up to peaks near P0_B left the band integral up to 20 % from converged).
    ``values`` are σ itself, ``log_values`` ln r."""

    def __init__(self, exact: Callable[[FloatArray], FloatArray], p_max: float, n: int, floor: float = TABLE_FLOOR,
                 threshold: float | None = None) -> None:
        self.lo, self.hi = np.log(p_max * floor), np.log(p_max)
        self.threshold = threshold if threshold is not None and threshold > p_max else None
        self.p_max = p_max
        self.s = self._nodes(n)
        self.values = exact(self.pressures())
        self.ok = bool(np.all(self.values > 0))
        self.log_values = self._log(self.values)

    def pressures(self) -> FloatArray:
        """The table's points (Pa): e^s, the top p_max itself (exp(ln p_max) may be an ulp off, and a caller may have
        asked for σ(p_max) already)."""
        p = np.exp(self.s)
        p[-1] = self.p_max
        return p

    def _log(self, values: FloatArray) -> FloatArray:
        """ln σ of the ``values`` at the table's points, or with a threshold ln r = ln σ − 3 ln(1 − p/P0_B)."""
        out = np.log(np.where(values > 0, values, 1.0))
        return out if self.threshold is None else out - _vanishing(self.pressures(), self.threshold)

    def refine(self, exact: Callable[[FloatArray], FloatArray]) -> SigmaTable:
        """The table on twice the intervals (the old points are reused)."""
        return self._finer(exact(np.exp(self._nodes(2 * (self.s.size - 1) + 1)[1::2])))

    def checked(self, exact: Callable[[FloatArray], FloatArray], rtol: float, grow: bool = True) -> tuple[SigmaTable, bool]:
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

    def _finer(self, added: FloatArray) -> SigmaTable:
        """The table on twice the intervals, from its ``added`` values (the old ones are reused)."""
        n = 2 * (self.s.size - 1) + 1
        new = SigmaTable.__new__(SigmaTable)
        new.lo, new.hi, new.threshold, new.p_max = self.lo, self.hi, self.threshold, self.p_max
        values = np.empty(n)
        values[::2] = self.values
        values[1::2] = added
        new.s, new.values = new._nodes(n), values
        new.ok = bool(np.all(values > 0))
        new.log_values = new._log(values)
        return new

    def _nodes(self, n: int) -> FloatArray:
        """The ``n`` Chebyshev–Lobatto points of [lo, hi] (ln p), the ends exact."""
        return lobatto_points(self.lo, self.hi, n)

    def __call__(self, p: FloatArray) -> FloatArray:
        """σ interpolated at the pressures ``p`` (Pa; clipped to the table's range)."""
        return np.exp(self.log_at(p))

    def log_at(self, p: FloatArray) -> FloatArray:
        """ln σ interpolated at the pressures ``p`` (Pa; clipped to the table's range)."""
        s = np.clip(np.log(p), self.lo, self.hi)
        out = chebyshev_lobatto_interpolate(self.s, self.log_values, s)
        if self.threshold is None:
            return out
        return out + _vanishing(np.minimum(np.exp(s), self.p_max), self.threshold)


def effective_medium_sigma_table(case: Case, contact: PerssonContact, p_max: float, floor: float,
                                 exact: Callable[[FloatArray], FloatArray] | None = None,
                                 ) -> Callable[[FloatArray], FloatArray]:
    """σ_eff(p) (m³/(Pa·s)) over [floor·p_max, p_max] (Pa): exact at Chebyshev points in ln p, interpolated in
    ln[σ/(1 − p/P0_B)³] between them (P0_B the contact's Bruggeman threshold, :class:`SigmaTable`), refined until it
    agrees with σ within :data:`TABLE_RTOL` at the points checked
    (:meth:`SigmaTable.checked`), at most to
    2·``TABLE_POINTS[1]`` − 1 points (the exact σ where it vanishes somewhere in the range). ``exact``: σ_eff of
    this contact (default the effective medium itself; a sweep passes its :class:`SweepSurface`)."""
    exact = effective_medium_exact(case, contact) if exact is None else exact
    table = SigmaTable(exact, p_max, TABLE_POINTS[0], floor, threshold=bruggeman_threshold(contact))
    while table.ok and table.s.size < 2 * TABLE_POINTS[1] - 1:
        table, good = table.checked(exact, TABLE_RTOL)
        if good:
            return table
    return table if table.ok else exact


class SweepSurface:
    """σ_eff(p; q0) (m³/(Pa·s)) shared by the loads of a sweep: the effective medium's P(u) costs ~5 ms per pressure,
    and every load has its own q0 = 2π/w, so without it no exact value serves two loads.

    q0 enters Persson's contact only as the lower limit of G(ζ) = (π/4)E*² ∫_{q0}^{q} q³C dq (everything else is a
    function of q = ζq0 itself), so σ_eff changes smoothly and little with it: σ_eff is interpolated in ln q0
    (barycentric, Chebyshev–Lobatto points over the loads' range) and in ln p. What is interpolated is the regular part
    ln r = ln[σ_eff/(1 − p/P0_B(q0))³] (below, "ln r"; :class:`SigmaTable` with its threshold). At the middle q0 point a :class:`SigmaTable`
    of ln r against ln p over [``low``, ``high``] Pa is doubled until it agrees with the exact values to
    :data:`SURFACE_RTOL`/2 at a quarter of the points the next doubling would add (:meth:`SigmaTable.checked`); at the other
    q0 points only the difference ln r − ln r_mid is tabulated (:meth:`_difference`), on every 2^k-th point of that
    table, doubled until it agrees with exact values at middles of its intervals to :data:`SURFACE_RTOL`/2: it is
    small (a few per cent at most) and smooth, so it needs a fraction of the points. Where a difference does not get
    there before it would need the middle table's own points, every q0 point takes a full table (as the middle one).
    The q0 points are doubled until the surface agrees with exact values of the load farthest from them, at pressures
    off the tables' points, to :data:`SURFACE_RTOL`. ``high`` stays a factor :data:`SURFACE_TOP` below every load's
    Bruggeman threshold P0_B (A(ζ1)/A0 = 1/2, closed form); ln r has no logarithmic singularity at P0_B, which ln σ has
    (σ vanishes as (1 − p/P0_B)³ at leading order, docs/theory.md eq. 5.5), so 0.95 P0_B costs no more points than 0.8 did
    in ln σ; pressures outside [``low``, ``high``] take
    the exact σ_eff. :meth:`build` returns None where the surface does not reach its tolerance within
    :data:`SURFACE_P_POINTS` and :data:`SURFACE_Q0_POINTS`.
    """

    def __init__(self, case: Case, nodes: FloatArray, base: SigmaTable | None,
                 parts: list[tuple[FloatArray, FloatArray] | None], low: float, high: float, span: tuple[float, float]) -> None:
        """``parts``: per q0 point (``nodes``, ln q0) its values on Chebyshev–Lobatto points in ln p — ln r itself where
        ``base`` is None, else the difference from ``base`` (None for the point of ``base``); ``span``: the table's
        ends in ln p."""
        self.case, self.nodes, self.base, self.parts, self.low, self.high = case, nodes, base, parts, low, high
        self.span = span

    @classmethod
    def build(cls, case: Case, q0: FloatArray, low: float, high: float) -> SweepSurface | None:
        """The surface over the loads' ``q0`` (1/m) and pressures [``low``, ``high``] (Pa), or None."""
        q0 = np.unique(np.asarray(q0, dtype=float))
        threshold = min(bruggeman_threshold(persson_contact(case, float(q))) for q in q0)
        high = min(high, SURFACE_TOP * threshold)
        if not high > low:
            return None
        m = np.log(q0)
        n = 1 if q0.size == 1 else SURFACE_Q0_POINTS[0]
        middles: dict[float, SigmaTable | None] = {}  # the middle table, checked to SURFACE_RTOL/2
        tables: dict[float, SigmaTable | None] = {}  # full tables, where a difference does not do
        differences: dict[tuple[float, float], tuple[FloatArray, FloatArray]] = {}  # by (middle, point)
        full_tables = False
        while True:
            nodes = np.array([float(m[0])]) if n == 1 else lobatto_points(float(m[0]), float(m[-1]), n)
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
            exact = effective_medium_exact(case, persson_contact(case, float(q0[far])))(check)
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
    def _table(case: Case, q0: float, low: float, high: float, rtol: float) -> SigmaTable | None:
        """The table of ln r at ``q0`` over [``low``, ``high``] (Pa), checked to ``rtol`` (:meth:`SigmaTable.checked`)."""
        contact = persson_contact(case, q0)
        exact = effective_medium_exact(case, contact)
        table = SigmaTable(exact, high, SURFACE_P_POINTS[0], low / high, threshold=bruggeman_threshold(contact))
        while table.ok:
            grow = table.s.size < SURFACE_P_POINTS[1]
            table, good = table.checked(exact, rtol, grow=grow)
            if good:
                return table
            if not grow:
                return None
        return None

    @staticmethod
    def _difference(case: Case, q0: float, base: SigmaTable) -> tuple[FloatArray, FloatArray] | None:
        """(points, values): ln r of the contact at ``q0`` less ``base``'s exact ln r, at every 2^k-th point of
        ``base`` (from 9 points on), doubled until the interpolated difference agrees with exact values at the middles
        of its intervals (points of ``base`` too: all 8 of 9 points, every other one of 17, every fourth and the last
        from 33 points on) within :data:`SURFACE_RTOL`/2 in ln r; with ``base`` checked to :data:`SURFACE_RTOL`/2 as
        well, the surface is within :data:`SURFACE_RTOL` at its q0 points (and checked between them by :meth:`build`).
        None where the difference needs the points of ``base`` itself, or σ_eff vanishes."""
        contact = persson_contact(case, q0)
        exact, top, at = effective_medium_exact(case, contact), bruggeman_threshold(contact), base.pressures()
        size = base.s.size
        step = (size - 1) // 8
        known: dict[int, float] = {}  # ln r at base's point i

        def log_sigma(index: NDArray[np.intp]) -> FloatArray | None:
            new = [i for i in index.tolist() if i not in known]
            if new:
                values = exact(at[new])
                if not np.all(values > 0):
                    return None
                known.update(zip(new, (np.log(values) - _vanishing(at[new], top)).tolist()))
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
        return self._at(persson_contact(self.case, q0))(p)

    def _at(self, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
        """σ_eff(p) of the load with ``contact`` (its q0) inside [low, high]: the interpolation in ln q0 is linear in the values,
        so ln r = base + Σ_j w_j part_j (the weights sum to 1: the base once), and the parts on the same points combine
        into one before ln p is interpolated, once per size of table; ln σ = ln r + 3 ln(1 − p/P0_B(q0))."""
        weights = lobatto_weights(self.nodes, math.log(contact.q0)).tolist()
        combined: dict[int, tuple[FloatArray, FloatArray]] = {}
        if self.base is not None:
            combined[self.base.s.size] = (self.base.s, self.base.log_values)
        for w, part in zip(weights, self.parts, strict=True):
            if part is not None:
                s, values = combined.get(part[0].size, (part[0], np.zeros(part[0].size)))
                combined[part[0].size] = (s, values + w * part[1])
        lo, hi = self.span
        top = bruggeman_threshold(contact)

        def sigma(p: FloatArray) -> FloatArray:
            x = np.clip(np.log(p), lo, hi)
            regular = np.sum([chebyshev_lobatto_interpolate(s, v, x) for s, v in combined.values()], axis=0)
            return np.exp(regular + _vanishing(np.clip(p, self.low, self.high), top))
        return sigma

    def for_load(self, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
        """σ_eff(p) of one load's contact: the surface inside [low, high], the exact effective medium outside."""
        exact = effective_medium_exact(self.case, contact)
        surface = self._at(contact)

        def sigma(p: FloatArray) -> FloatArray:
            p = np.asarray(p, dtype=float)
            return piecewise(p, (p >= self.low) & (p <= self.high), surface, exact)
        return sigma


class JunctionSurface:
    """ln u_c(p; q0) (u_c in m) of the critical junction, shared by the loads of a sweep: interpolated in ln q0 and in
    ln p (barycentric, Chebyshev–Lobatto points over the loads' q0 and over [``low``, ``high``] Pa), from exact values
    computed all at once (one call of the junction per q0 point, where a band without it calls the junction some ten
    times, ~1 ms a call).

    u_c(p) is smooth in ln p except where ζc crosses a node of the spectrum (the roll-off), where a higher derivative
    jumps: Chebyshev points converge there algebraically, 8–36 times per doubling. The points in ln p are doubled until
    the table agrees with the exact u_c at the middle q0 point, at middles of its intervals
    (:func:`_checked_points`), within :data:`JUNCTION_RTOL`/2 in σ ∝ u_c³; the q0 points until the surface agrees with
    the exact u_c of the load farthest from them, at points of the table, within :data:`JUNCTION_RTOL`/2. ``high`` stays
    a factor :data:`JUNCTION_TOP` below every load's percolation limit (closed form,
    :func:`~sealeak.physics.critical_junction.percolation_limit`), where u_c falls to 0 faster than any power; pressures
    outside [``low``, ``high``] take the exact junction. :meth:`build` returns None where the surface does not reach its
    tolerance within :data:`JUNCTION_P_POINTS` and :data:`JUNCTION_Q0_POINTS`, or the junction does not percolate
    everywhere in range. The surface does not depend on α or η.
    """

    def __init__(self, nodes: FloatArray, s: FloatArray, values: FloatArray, low: float, high: float) -> None:
        """``values``: ln u_c at (ln q0 ``nodes``) × (ln p points ``s``)."""
        self.nodes, self.s, self.values, self.low, self.high = nodes, s, values, low, high

    @classmethod
    def build(cls, case: Case, q0: FloatArray, low: float, high: float) -> JunctionSurface | None:
        """The surface over the loads' ``q0`` (1/m) and pressures [``low``, ``high``] (Pa), or None; kept
        (:data:`KEPT_JUNCTION_SURFACE_BYTES`) by everything it depends on."""
        q0 = np.unique(np.asarray(q0, dtype=float))
        key = (contact_key(persson_contact(case, float(q0[0])), case.percolation_threshold, low, high),
               hashlib.blake2b(q0.tobytes(), digest_size=16).digest())
        kept = _JUNCTION_SURFACES.get(key)
        if kept is None:
            built = cls._build(case, q0, low, high)
            kept = _JUNCTION_SURFACES.put(key, () if built is None else
                                          (built.nodes, built.s, built.values, np.array([built.low, built.high])))
        return cls(kept[0], kept[1], kept[2], float(kept[3][0]), float(kept[3][1])) if kept else None

    @classmethod
    def _build(cls, case: Case, q0: FloatArray, low: float, high: float) -> JunctionSurface | None:
        """:meth:`build` computed, over the sorted unique ``q0``."""
        limit = min(percolation_limit(persson_contact(case, float(q)), case.percolation_threshold) for q in q0)
        high = min(high, JUNCTION_TOP * limit)
        if not high > low:
            return None
        m = np.log(q0)
        nq, n = (1 if q0.size == 1 else JUNCTION_Q0_POINTS[0]), JUNCTION_P_POINTS[0]
        while True:
            nodes = np.array([float(m[0])]) if nq == 1 else lobatto_points(float(m[0]), float(m[-1]), nq)
            s = lobatto_points(math.log(low), math.log(high), n)
            rows = [cls._log_gap(case, SweepSurface._q0_at(node, q0, m), s) for node in nodes.tolist()]
            if any(row is None for row in rows):
                return None
            surface = cls(nodes, s, np.array(rows), low, high)
            middle = nodes.size // 2
            between = ((s[1:] + s[:-1]) / 2.0)[_checked_points(n - 1)]
            exact = cls._log_gap(case, SweepSurface._q0_at(float(nodes[middle]), q0, m), between)
            if exact is None:
                return None
            p_good = bool(np.all(3.0 * np.abs(chebyshev_lobatto_interpolate(s, surface.values[middle], between) - exact)
                                 < 0.5 * JUNCTION_RTOL))
            far = int(np.argmax(np.min(np.abs(m[:, None] - nodes[None, :]), axis=1)))
            q_good = True
            if nq > 1 and np.min(np.abs(m[far] - nodes)) > 0:
                at = s[::max(1, (n - 1) // 32)]
                exact = cls._log_gap(case, float(q0[far]), at)
                q_good = exact is not None and bool(np.all(
                    3.0 * np.abs(_weighted_rows(lobatto_weights(nodes, float(m[far])), surface.values[:, ::max(1, (n - 1) // 32)]) - exact)
                    < 0.5 * JUNCTION_RTOL))
            if p_good and q_good:
                return surface
            if (not p_good and 2 * n - 1 > JUNCTION_P_POINTS[1]) or (not q_good and 2 * nq - 1 > JUNCTION_Q0_POINTS[1]):
                return None
            n, nq = (n if p_good else 2 * n - 1), (nq if q_good else 2 * nq - 1)

    @staticmethod
    def _log_gap(case: Case, q0: float, s: FloatArray) -> FloatArray | None:
        """ln u_c (u_c in m) of the contact at ``q0`` (1/m) at the pressures e^``s`` (Pa), or None where it does not
        percolate (or u_c = 0) at one of them."""
        res = critical_junction(persson_contact(case, q0), squeeze_pressure=np.exp(s), pressure_difference=1.0,
                                viscosity=1.0, aspect_ratio=1.0, percolation_threshold=case.percolation_threshold)
        gap = res.critical_gap
        if not (res.percolates.all() and np.all(np.isfinite(gap) & (gap > 0))):
            return None
        return np.log(gap)

    def for_load(self, case: Case, contact: PerssonContact) -> Callable[[FloatArray], FloatArray]:
        """σ(p) = α u_c³/(12η) (m³/(Pa·s)) of one load's contact with the case's α and η: the surface inside
        [low, high], 0 beyond the load's percolation limit (by :data:`CLOSED_MARGIN`), the exact junction elsewhere
        (:func:`junction_exact`)."""
        row = _weighted_rows(lobatto_weights(self.nodes, math.log(contact.q0)), self.values)
        factor = case.alpha / (12.0 * case.fluid.viscosity)
        exact = junction_exact(case, contact)
        closed = percolation_limit(contact, case.percolation_threshold) * (1.0 + CLOSED_MARGIN)

        def surface(p: FloatArray) -> FloatArray:
            return factor * np.exp(3.0 * chebyshev_lobatto_interpolate(self.s, row, np.log(p)))

        def outside(p: FloatArray) -> FloatArray:
            return piecewise(p, p > closed, np.zeros_like, exact)

        def sigma(p: FloatArray) -> FloatArray:
            p = np.asarray(p, dtype=float)
            return piecewise(p, (p >= self.low) & (p <= self.high), surface, outside)
        return sigma


def _vanishing(p: FloatArray, threshold: float) -> FloatArray:
    """3 ln(1 − p/P0_B): the logarithm of the factor with which σ_eff vanishes at its threshold P0_B (Pa; docs/theory.md
    eq. 5.5), which the tables of ln σ leave out (:class:`SigmaTable`, :class:`SweepSurface`)."""
    return THRESHOLD_EXPONENT * np.log1p(-p / threshold)


def _checked_points(n: int) -> NDArray[np.bool_]:
    """Which of ``n`` middles of a table's intervals a check evaluates: all of up to 15, every other one of 16 to 31,
    every fourth from 32 on, and always the last (:meth:`SigmaTable.checked`, :meth:`SweepSurface._difference`,
    :meth:`JunctionSurface.build`)."""
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


def _weighted_rows(weights: FloatArray, rows: FloatArray) -> FloatArray:
    """Σ_k w_k rows[k], added row after row (a fixed order, not a BLAS product whose grouping may vary): equal inputs,
    equal bits."""
    return np.cumsum(weights[:, None] * rows, axis=0)[-1]


def lobatto_weights(nodes: FloatArray, x: float) -> FloatArray:
    """The weights l_k(x) with which the polynomial through values f_k at the Chebyshev–Lobatto ``nodes`` is
    Σ l_k f_k at ``x`` (:func:`chebyshev_lobatto_interpolate`'s barycentric formula; 1 at a node, they sum to 1)."""
    if nodes.size == 1:
        return np.ones(1)
    d = x - nodes
    at = np.flatnonzero(d == 0)
    if at.size:
        return np.eye(nodes.size)[at[0]]
    w = (-1.0) ** np.arange(nodes.size)
    w[[0, -1]] *= 0.5
    c = w / d
    return c / np.cumsum(c)[-1]


def lobatto_points(lo: float, hi: float, n: int) -> FloatArray:
    """The ``n`` Chebyshev–Lobatto points of [lo, hi], ascending, the ends exact."""
    s = (lo + hi) / 2.0 - (hi - lo) / 2.0 * np.cos(np.pi * np.arange(n) / (n - 1))
    s[0], s[-1] = lo, hi
    return np.asarray(s, dtype=float)
