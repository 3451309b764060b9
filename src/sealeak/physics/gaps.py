"""Distribution of interfacial separations P(u) from Persson contact mechanics.

docs/theory.md §5.1 (Persson; Almqvist et al., J. Mech. Phys. Solids 59 (2011) 2355); u in m, P(u) in 1/m::

    P(u) = ∫_1^{ζ1} dζ [-A'(ζ)/A0] (2π h(ζ)²)^(-1/2) [e^(-(u-u1(ζ))²/(2h(ζ)²)) + e^(-(u+u1(ζ))²/(2h(ζ)²))]
           + (A(ζ1)/A0) δ(u),          h(ζ)² = 2π ∫_{ζq0}^{q1} q C(q) dq,   ζ1 = q1/q0

Each magnification contributes the patches that lose contact there (weight -A'(ζ)dζ): their
separation is u1(ζ) (:meth:`PerssonContact.u1`), broadened by the roughness h(ζ) not yet resolved at
ζ; the mirror Gaussian folds the part below u = 0 back onto u >= 0, so every component integrates
to one over u >= 0 and P(u) integrates to 1 exactly.

How the ζ-integral is computed
------------------------------
-A'(ζ) is sharply peaked in ζ, so the integral is taken in the contact area itself: with
a = A(ζ)/A0 the weight -A'(ζ)dζ is just da, and in the complement b = 1 - a (kept as b for
precision near a = 1) ζ(b) is a closed form: G(ζ) = (P0/(2 erfcinv(b)))², inverted through the
closed-form cumulative moment of q³C. The b-range [ε, b1], b1 = 1 - A(ζ1)/A0, is cut into panels
whose edges are the union of (i) a uniform split of [0, b1] (the bulk of the weight), (ii) a
geometric split of [ε, b1] (near a = 1, i.e. ζ → 1, u1(ζ) grows without bound while its weight
vanishes), (iii) a geometric grading towards b1 by factors of 4 down to 4^-20 ≈ 1e-12 of b1 (ζ → ζ1, where
h(ζ) ∝ √(ζ1 - ζ) makes the density at u ≈ 0 an integrable 1/√ end-point singularity; the ungraded
remainder shifts P(u) only at u below ~1e-6 h_rms, by ~1e-6 relative); each panel gets ``order``-point Gauss–Legendre. The result is a mixture of
folded Gaussians (weight w_i, centre u1_i, width h_i) plus the contact weight A(ζ1)/A0 at u = 0,
all arrays over (squeeze pressure × node): nothing loops over pressures.

The part b < ε (ε = 1e-14 by default: patches appearing at ζ so close to 1 that A = 1 - ε) is not
resolved; its weight ε is reported (``unresolved_weight``). Its contribution to the mean is known in
closed form, because ∫(-A')u1 dζ = -[A ū] (u1 = ū + ū'A/A'), so it is added to :attr:`mean` exactly.

The mean of P(u) and ū(1)
-------------------------
The same identity gives ∫_1^{ζ1} (-A') u1 dζ = ū(1) exactly (ū(ζ1) = 0). The mean of a folded
Gaussian is u1 + h√(2/π) e^(-u1²/2h²) - u1 erfc(u1/(√2 h)) >= u1, so::

    mean of P(u) = ū(1) + ∫ da [h√(2/π) e^(-u1²/2h²) - u1 erfc(u1/(√2 h))]  >=  ū(1)

i.e. the mean of P(u) exceeds ū(1) by the folding term alone; it is close to ū(1) where u1 >> h(ζ)
for the patches that matter (large separations, low squeeze pressure) and can be several times
ū(1) at high squeeze pressure, where the separations are smaller than the unresolved roughness.
:attr:`GapDistribution.mean` and :attr:`GapDistribution.mean_gap` (ū(1)) are reported side by side.

Reuse
-----
Each row (squeeze pressure) is computed on its own, so a row is the same, bit for bit, alone or among others.
:func:`gap_distribution` keeps the rows it computes, keyed on the contact (spectrum nodes, E*, q0, γ, quadrature)
and P0, and takes them from there when asked again (up to :data:`GAP_CACHE_BYTES`, the least recently used
dropped first): P(u) does not depend on the fluid, so the fluids of a study, an effective-medium σ table
evaluated again at the same pressures, and a web update that changes only η, ΔP or α cost no new P(u).
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Mapping
from dataclasses import dataclass, fields
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ..errors import InputError, SolutionCheckError
from ._kernels import gauss_legendre
from .contact import PerssonContact

__all__ = ["GapDistribution", "gap_distribution", "folded_normal_mean", "GAP_CACHE_BYTES", "CONDUCTIVITY_QUADRATURE",
           "clear_caches", "contact_key", "ArrayCache"]

FloatArray = NDArray[np.float64]

_SQRT2 = np.sqrt(2.0)
_SQRT2PI = np.sqrt(2.0 * np.pi)

#: A lighter ζ-rule of :func:`gap_distribution` (its keywords) for σ_eff tables: 12 uniform, 16 geometric and 10 graded
#: panels of 6 points instead of 32, 64 and 20 of 8, a quarter of the nodes. σ_eff, an integral over P(u) (the panels of
#: :func:`~sealeak.physics.effective_medium.discretise` are rescaled to the exact CDF), stays within 2e-7 of a 4× finer
#: rule up to 0.8 of the percolation threshold and within 6e-7 up to 0.99 (a sweep's σ surface reaches 0.95), where it errs
#: most (tests/unit/test_effective_medium.py; 8 graded panels leave 2e-6 there, 4 leave 3e-3); P(u) itself, a sum of
#: Gaussians at the nodes, is ~2e-3 bumpier pointwise at low pressure, so the figures and the uniform seal keep the default.
CONDUCTIVITY_QUADRATURE: Mapping[str, int] = MappingProxyType(
    {"uniform_panels": 12, "log_panels": 16, "graded_panels": 10, "order": 6})

#: Bytes of P(u) rows kept for reuse (least recently used dropped first): ~30 kB per squeeze pressure.
GAP_CACHE_BYTES = 128 * 2**20
#: Squeeze pressures whose P(u) is computed together: the separation integrals of one pressure's nodes take ~3 MB of
#: intermediate arrays (a fit of 5 000 measured pressures took 16 GB at once); each row is computed on its own, so
#: the blocks change no bit.
ROWS_AT_ONCE = 64


def folded_normal_mean(centre: ArrayLike, width: ArrayLike) -> FloatArray:
    """E|X| for X ~ N(centre, width²): width √(2/π) e^(-c²/2w²) + c erf(c/(√2 w)) (width 0: |c|)."""
    c = np.asarray(centre, dtype=float)
    w = np.asarray(width, dtype=float)
    safe = np.where(w > 0, w, 1.0)
    z = c / (_SQRT2 * safe)
    out = safe * np.sqrt(2.0 / np.pi) * np.exp(-z * z) + c * special.erf(z)
    return np.where(w > 0, out, np.abs(c))


def folded_normal_cdf(u: ArrayLike, centre: ArrayLike, width: ArrayLike) -> FloatArray:
    """P(|X| <= u) for X ~ N(centre, width²), u >= 0 (width 0: a step at |centre|)."""
    u = np.asarray(u, dtype=float)
    c = np.asarray(centre, dtype=float)
    w = np.asarray(width, dtype=float)
    safe = np.where(w > 0, w, 1.0)
    out = special.ndtr((u - c) / safe) - special.ndtr((-u - c) / safe)
    return np.where(w > 0, out, (u >= np.abs(c)).astype(float))


@dataclass(frozen=True, kw_only=True)
class GapDistribution:
    """P(u) over a sweep of squeeze pressures, as a mixture of folded Gaussians plus δ(u).

    Arrays have shape (pressures,) or (pressures, nodes); SI units (m, Pa).

    Attributes
    ----------
    squeeze_pressure
        P0 (Pa).
    contact_fraction
        A(ζ1)/A0, the weight of δ(u) (surfaces in contact at the finest resolution).
    weights, centres, widths, magnification
        The components: weight -A'(ζ)dζ/A0, centre u1(ζ) (m), width h(ζ) (m) and ζ of every
        quadrature node.
    unresolved_weight
        Weight of the components left out (b < ε: ζ so close to 1 that A = 1 - ε).
    unresolved_mean
        Their (closed-form) contribution to the mean (m).
    mean_gap
        ū(1), the mean separation of Persson theory (m), for comparison with :attr:`mean`.
    """

    squeeze_pressure: FloatArray
    contact_fraction: FloatArray
    weights: FloatArray
    centres: FloatArray
    widths: FloatArray
    magnification: FloatArray
    unresolved_weight: FloatArray
    unresolved_mean: FloatArray
    mean_gap: FloatArray

    def __len__(self) -> int:
        return int(self.squeeze_pressure.size)

    @property
    def mean(self) -> FloatArray:
        """∫ u P(u) du in m (mixture means plus the closed-form unresolved part)."""
        return np.sum(self.weights * folded_normal_mean(self.centres, self.widths), axis=-1) + self.unresolved_mean

    @property
    def total_weight(self) -> FloatArray:
        """Contact weight + component weights + unresolved weight (1 up to rounding)."""
        return self.contact_fraction + self.weights.sum(axis=-1) + self.unresolved_weight

    def density(self, u: ArrayLike) -> FloatArray:
        """The continuous part of P(u) in 1/m at separations u >= 0, shape (pressures, len(u)).

        The δ(u) part (weight :attr:`contact_fraction`) is not included.
        """
        ua = np.atleast_1d(np.asarray(u, dtype=float))
        if (ua < 0).any() or not np.isfinite(ua).all():
            raise InputError("separation u", ua[(ua < 0) | ~np.isfinite(ua)][0], "must be finite and >= 0 (m)")
        out = np.zeros((len(self), ua.size))
        for k in range(0, ua.size, 256):  # bounded memory: (pressures, nodes, 256)
            uk = ua[None, None, k:k + 256]
            w = self.widths[:, :, None]
            c = self.centres[:, :, None]
            live = (self.weights > 0)[:, :, None] & (w > 0)
            safe = np.where(live, w, 1.0)
            g = (np.exp(-0.5 * ((uk - c) / safe) ** 2) + np.exp(-0.5 * ((uk + c) / safe) ** 2)) / (_SQRT2PI * safe)
            out[:, k:k + 256] = np.sum(np.where(live, self.weights[:, :, None] * g, 0.0), axis=1)
        return out

    def cdf(self, u: ArrayLike) -> FloatArray:
        """∫_0^u P(u') du' including the δ(u) weight, shape (pressures, len(u))."""
        ua = np.atleast_1d(np.asarray(u, dtype=float))
        out = np.empty((len(self), ua.size))
        for k in range(0, ua.size, 256):
            part = folded_normal_cdf(ua[None, None, k:k + 256], self.centres[:, :, None], self.widths[:, :, None])
            out[:, k:k + 256] = self.contact_fraction[:, None] + np.sum(self.weights[:, :, None] * part, axis=1)
        return out


def _zeta_of_complement(contact: PerssonContact, b: FloatArray, p0: FloatArray) -> FloatArray:
    """ζ at which 1 - A(ζ)/A0 = b (closed form; b in (0, 1 - A(ζ1)/A0])."""
    spec = contact.spectrum
    x = special.erfcinv(b)
    g = (p0 / (2.0 * x)) ** 2
    m = g / (0.25 * np.pi * contact.e_star**2) + spec.cumulative_moment(3, contact.q0)
    q = spec.inverse_cumulative_moment(3, m)
    return np.clip(q / contact.q0, 1.0, contact.zeta_max)


def gap_distribution(
    contact: PerssonContact,
    squeeze_pressure: ArrayLike,
    *,
    uniform_panels: int = 32,
    log_panels: int = 64,
    graded_panels: int = 20,
    order: int = 8,
    unresolved: float = 1e-14,
) -> GapDistribution:
    """P(u) of Persson theory at every squeeze pressure (see the module docstring for the method).

    Almqvist et al., J. Mech. Phys. Solids 59 (2011) 2355; docs/theory.md §5.1 (eq. 5.1). Separations u in m,
    P(u) in 1/m.

    Parameters
    ----------
    contact:
        Persson contact mechanics of the interface.
    squeeze_pressure:
        Nominal squeeze pressures P0 in Pa (scalar or 1-D).
    uniform_panels, log_panels, graded_panels, order:
        Quadrature of the ζ-integral in b = 1 - A/A0: the panel counts of the uniform split, the
        geometric split towards a = 1 and the grading towards A(ζ1); Gauss–Legendre points per panel.
    unresolved:
        ε: components with 1 - A(ζ)/A0 < ε are not resolved (their weight and mean are reported).
    """
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float)).ravel()
    if p0.size == 0 or not (np.isfinite(p0) & (p0 > 0)).all():
        raise InputError("squeeze_pressure", p0.tolist(), "needs finite values > 0 (Pa)")
    if not (0.0 < unresolved < 1e-3):
        raise InputError("unresolved weight", unresolved, "must lie in (0, 1e-3)")
    for name, n in (("uniform_panels", uniform_panels), ("log_panels", log_panels),
                    ("graded_panels", graded_panels), ("order", order)):
        if int(n) != n or n < 1:
            raise InputError(name, n, "must be a whole number >= 1")

    key = contact_key(contact, uniform_panels, log_panels, graded_panels, order, unresolved)
    kept = {p: row for p in p0.tolist() if (row := _ROWS.get((key, p))) is not None}
    missing = np.array(sorted({p for p in p0.tolist() if p not in kept}))
    for start in range(0, missing.size, ROWS_AT_ONCE):  # (rows are independent: in blocks, the memory stays bounded)
        block = missing[start:start + ROWS_AT_ONCE]
        new = _compute(contact, block, uniform_panels, log_panels, graded_panels, order, unresolved)
        for i, p in enumerate(block.tolist()):
            kept[p] = _ROWS.put((key, p), tuple(np.array(getattr(new, name)[i]) for name in _FIELDS))
    rows = [kept[p] for p in p0.tolist()]
    return GapDistribution(**{name: np.array([row[k] for row in rows]) for k, name in enumerate(_FIELDS)})


def _compute(contact: PerssonContact, p0: FloatArray, uniform_panels: int, log_panels: int, graded_panels: int,
             order: int, unresolved: float) -> GapDistribution:
    """:func:`gap_distribution` at the valid pressures ``p0`` (Pa), computed (each row on its own: no row depends on another)."""
    a1 = contact.area(contact.zeta_max, p0)
    g1 = contact.G(contact.zeta_max)
    b1 = special.erfc(p0 / (2.0 * np.sqrt(g1)))  # 1 - A(ζ1)/A0 without cancellation
    eps = np.full_like(p0, unresolved)
    lo = np.minimum(eps, b1)
    # panel edges in b (rows: pressures)
    k = np.arange(uniform_panels + 1) / uniform_panels
    uniform = b1[:, None] * k[None, :]
    logk = np.arange(log_panels + 1) / log_panels
    safe_lo = np.where(lo > 0, lo, 1.0)  # b1 = 0 (complete contact): every panel has zero width
    safe_b1 = np.where(b1 > 0, b1, 1.0)
    logs = np.exp(np.log(safe_lo)[:, None] + (np.log(safe_b1) - np.log(safe_lo))[:, None] * logk[None, :])
    graded = b1[:, None] * (1.0 - 4.0 ** -np.arange(1, graded_panels + 1, dtype=float))[None, :]
    edges = np.sort(np.clip(np.concatenate([uniform, logs, graded], axis=1), lo[:, None], b1[:, None]), axis=1)
    x, w = gauss_legendre(order)
    left, right = edges[:, :-1], edges[:, 1:]
    half = 0.5 * (right - left)
    b = ((left + right) * 0.5)[:, :, None] + half[:, :, None] * x[None, None, :]
    weights = (half[:, :, None] * w[None, None, :]).reshape(p0.size, -1)
    b = b.reshape(p0.size, -1)
    live = weights > 0
    b = np.where(live, b, np.maximum(b1, lo)[:, None])  # dead nodes: any valid b
    zeta = _zeta_of_complement(contact, b, p0[:, None])
    pp = np.broadcast_to(p0[:, None], zeta.shape)
    u1 = np.zeros_like(zeta)
    inside = live & (zeta < contact.zeta_max)
    if inside.any():
        u1[inside] = contact.u1(zeta[inside], pp[inside])
    spec = contact.spectrum
    h2 = 2.0 * np.pi * (spec.cumulative_moment(1, spec.q_max) - spec.cumulative_moment(1, zeta * contact.q0))
    h = np.sqrt(np.maximum(h2, 0.0))
    weights = np.where(live, weights, 0.0)
    u1 = np.where(live, np.maximum(u1, 0.0), 0.0)
    # the unresolved part b < ε: ∫_1^{ζm} (-A') u1 dζ = ū(1) - A(ζm) ū(ζm), ζm = ζ(ε)
    ubar1 = contact.mean_gap(np.ones_like(p0), p0)
    zeta_m = _zeta_of_complement(contact, np.maximum(lo, 1e-300), p0)
    ubar_m = contact.mean_gap(zeta_m, p0)
    unresolved_mean = np.where(b1 > lo, ubar1 - (1.0 - lo) * ubar_m, ubar1)
    unresolved_weight = np.where(b1 > lo, lo, b1)
    if not (np.isfinite(u1).all() and np.isfinite(h).all()):
        raise SolutionCheckError("gap distribution: non-finite separation u1(ζ) at a quadrature node")
    return GapDistribution(
        squeeze_pressure=p0, contact_fraction=a1, weights=weights, centres=u1, widths=h, magnification=zeta,
        unresolved_weight=unresolved_weight, unresolved_mean=np.maximum(unresolved_mean, 0.0), mean_gap=ubar1,
    )


_FIELDS = tuple(f.name for f in fields(GapDistribution))


def contact_key(contact: PerssonContact, *quadrature: float) -> bytes:
    """A digest of everything a row of P(u) depends on besides P0: the spectrum's nodes, E*, q0, γ and both quadratures."""
    spec = contact.spectrum
    numbers = np.array([contact.e_star, contact.q0, contact.gamma, contact.panel_width, contact.order, *quadrature], dtype=float)
    digest = hashlib.blake2b(digest_size=16)
    for part in (spec.q, spec.C, numbers):
        digest.update(np.ascontiguousarray(part, dtype=float).tobytes())
    return digest.digest()


class ArrayCache:
    """Tuples of arrays by key, least recently used dropped first beyond ``limit()`` bytes; thread-safe (the web
    app's requests share it). What is kept must be a function of the key alone, bit for bit."""

    def __init__(self, limit: Callable[[], int]) -> None:
        self._items: OrderedDict[Hashable, tuple[FloatArray, ...]] = OrderedDict()
        self._bytes = 0
        self._limit = limit
        self._lock = threading.Lock()
        _CACHES.append(self)

    def get(self, key: Hashable) -> tuple[FloatArray, ...] | None:
        """The item kept under ``key`` (now the most recently used), or None."""
        with self._lock:
            item = self._items.get(key)
            if item is not None:
                self._items.move_to_end(key)
            return item

    def put(self, key: Hashable, item: tuple[FloatArray, ...]) -> tuple[FloatArray, ...]:
        """Keep ``item`` (read-only from now on) under ``key``; returns it."""
        for a in item:
            a.setflags(write=False)
        with self._lock:
            if key not in self._items:
                self._items[key] = item
                self._bytes += _nbytes(item)
            while self._bytes > self._limit() and self._items:
                _, old = self._items.popitem(last=False)
                self._bytes -= _nbytes(old)
        return item

    def clear(self) -> None:
        """Forget everything kept."""
        with self._lock:
            self._items.clear()
            self._bytes = 0

    def __len__(self) -> int:
        return len(self._items)

    @property
    def nbytes(self) -> int:
        """The bytes kept (arrays, and 200 per entry for the keys and tuples)."""
        return self._bytes


def _nbytes(item: tuple[FloatArray, ...]) -> int:
    return sum(a.nbytes for a in item) + 200


_CACHES: list[ArrayCache] = []

#: Rows of P(u) by (contact, P0): a row depends only on the contact, the quadrature and its own P0 (the rows are
#: computed independently, bit for bit the same alone or among others), not on the fluid.
_ROWS = ArrayCache(lambda: GAP_CACHE_BYTES)


def clear_caches() -> None:
    """Forget every P(u) row (and the effective medium's discretisations) kept for reuse, for timings that start cold."""
    for cache in _CACHES:
        cache.clear()
