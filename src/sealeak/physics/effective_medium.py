"""Leak rate by effective-medium theory: 2D Bruggeman flow conductivity of the gap distribution P(u).

docs/theory.md §5.2–§5.5 (Bruggeman, Ann. Phys. (Leipzig) 416 (1935) 636; Lorenz & Persson, Eur. Phys. J. E 31
(2010) 159). Where the surfaces are apart by u the fluid flows as between parallel plates,
with local conductivity σ(u) = u³/(12η) (flow per unit width per unit pressure gradient); where they
touch, σ = 0. The isotropic 2D Bruggeman effective conductivity σ_eff of that random mixture solves::

    1/σ_eff = ∫ du P(u) 2/(σ_eff + σ(u))        (the δ(u) contact part contributes 2 A(ζ1)/(A0 σ_eff))

and the leak rate of the seal (Ly/Lx squares in parallel) is Q = (Ly/Lx) σ_eff ΔP. No fit factor
enters (α of the critical-junction theory has no counterpart here; :mod:`sealeak.lab.fitting` can still
fit a factor that multiplies this prediction).

Percolation. Multiplying by σ_eff, the equation reads g(σ_eff) = 1 with
g(σ) = ∫ P(u) 2σ/(σ + σ(u)) du, which rises monotonically from 2 A(ζ1)/A0 (σ → 0) to 2 (σ → ∞): a
positive root exists if and only if A(ζ1)/A0 < 1/2. So plain 2D Bruggeman puts the percolation
threshold of the non-contact area at A/A0 = 0.5, while numerically exact studies of self-affine
contacts find that the non-contact area stops percolating near A/A0 ≈ 0.42 (Wang & Müser, Tribol.
Lett. 2020: 0.415; Dapp et al., PRL 108 (2012) 244301); the critical-junction theory uses
A/A0 = 1 - p_c (0.4 by default). Between these thresholds the two theories disagree on whether
the seal leaks at all.

A single gap value u with contact fraction a gives σ_eff = σ(u)(1 - 2a) for a < 1/2 and 0 beyond.

How it is solved
----------------
The continuous part of P(u) (a mixture of folded Gaussians, :mod:`sealeak.physics.gaps`) is discretised on
Gauss–Legendre nodes in ln u, on panels between the 1e-10 and 1 - 1e-13 quantiles; each panel's
weights are rescaled so the panel holds exactly its mass from the closed-form mixture CDF (so
the discrete distribution integrates to one to rounding), the mass below (above) the range sits
at its lower (upper) end. On that discrete distribution, with x = ln u and s = ln u_e where
σ(u_e) = σ_eff, g(s) = 2A(ζ1)/A0 + Σ_j W_j 2/(1 + e^(3(x_j - s))), monotone in s; a vectorised
Newton iteration with a bisection bracket (all pressures at once) solves g(s) = 1 until the
relative residual |1 - g| is below 1e-12 (σ_eff to ~1e-12 relative).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ConvergenceError, InputError
from .contact import PerssonContact
from .critical_junction import _pressures
from .gaps import GapDistribution, folded_normal_cdf, gap_distribution
from .validity import no_channel_note

__all__ = ["EffectiveMediumResult", "effective_medium", "bruggeman_conductivity", "bruggeman_residual",
           "discretise", "BRUGGEMAN_THRESHOLD"]

FloatArray = NDArray[np.float64]

#: Contact-area fraction at which plain 2D Bruggeman stops conducting.
BRUGGEMAN_THRESHOLD = 0.5


def _g_and_slope(x: FloatArray, w: FloatArray, contact: FloatArray, s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """g(s) = 2c + Σ w 2/(1+e^(3(x-s))) and dg/ds (rows: pressures)."""
    z = np.clip(3.0 * (x - s[:, None]), -700.0, 700.0)
    r = np.exp(z)
    g = 2.0 * contact + np.sum(w * 2.0 / (1.0 + r), axis=1)
    dg = np.sum(w * 6.0 * r / (1.0 + r) ** 2, axis=1)
    return g, dg


def bruggeman_conductivity(gaps: ArrayLike, weights: ArrayLike, contact_fraction: ArrayLike, viscosity: float,
                           *, rtol: float = 1e-12, max_iter: int = 200) -> tuple[FloatArray, FloatArray]:
    """2D Bruggeman σ_eff (m³/(Pa·s)) of discrete gap distributions, one per row.

    Solves 1/σ_eff = Σ_j W_j 2/(σ_eff + σ(u_j)) + 2c/σ_eff (docs/theory.md §5.3, §5.5).

    Parameters
    ----------
    gaps, weights:
        Shape (rows, n) (or (n,) for one distribution): gap values u_j > 0 in m and their weights.
    contact_fraction:
        Weight of u = 0 (σ = 0) per row; contact + Σ weights should be 1.
    viscosity:
        η in Pa·s; σ(u) = u³/(12η).

    Returns
    -------
    sigma_eff : ndarray
        σ_eff per row (m³/(Pa·s)); 0 where the contact fraction is >= 1/2 (no percolation in
        Bruggeman's theory).
    residual : ndarray
        Relative residual 1 - g(σ_eff) per row; NaN where σ_eff = 0.
    """
    u = np.atleast_2d(np.asarray(gaps, dtype=float))
    w = np.atleast_2d(np.asarray(weights, dtype=float))
    c = np.atleast_1d(np.asarray(contact_fraction, dtype=float)).astype(float)
    if u.shape != w.shape or c.size != u.shape[0]:
        raise InputError("gap distribution", (u.shape, w.shape, c.shape), "gaps, weights (rows × n) and one contact fraction per row")
    if not (np.isfinite(u).all() and (u > 0).all()):
        raise InputError("gaps", u[~(np.isfinite(u) & (u > 0))][0], "must be finite and > 0 (m); put contact in contact_fraction")
    if not (np.isfinite(w).all() and (w >= 0).all() and np.isfinite(c).all() and (c >= 0).all()):
        raise InputError("weights", w.tolist() if w.size < 10 else "...", "must be finite and >= 0")
    if not (np.isfinite(viscosity) and viscosity > 0):
        raise InputError("viscosity", viscosity, "must be finite and > 0")
    x = np.log(u)
    total = c + w.sum(axis=1)
    flows = (2.0 * c < total) & (w.sum(axis=1) > 0)
    rows = np.flatnonzero(flows)
    sigma = np.zeros(c.size)
    resid = np.full(c.size, np.nan)
    if rows.size:
        xr, wr, cr = x[rows], w[rows] / total[rows, None], c[rows] / total[rows]
        lo = xr.min(axis=1) - 30.0  # g(lo) ≈ 2c + 2·Σw·e^(-90·...) < 1
        hi = xr.max(axis=1) + 30.0  # g(hi) ≈ 2(1 - c) + 2c > 1
        s = np.log(np.sum(wr * np.exp(3.0 * xr), axis=1)) / 3.0  # start: u_e from <u³>
        s = np.clip(s, lo, hi)
        for _ in range(max_iter):
            g, dg = _g_and_slope(xr, wr, cr, s)
            f = g - 1.0
            lo = np.where(f < 0, s, lo)
            hi = np.where(f > 0, s, hi)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(dg > 0, f / dg, np.inf)
            new = s - step
            bad = ~np.isfinite(new) | (new <= lo) | (new >= hi)
            new = np.where(bad, 0.5 * (lo + hi), new)
            done = (np.abs(f) < rtol) | (hi - lo < 1e-14 * np.maximum(1.0, np.abs(s)))
            if done.all():
                break
            s = np.where(done, s, new)
        else:
            raise ConvergenceError(f"Bruggeman equation: no convergence in {max_iter} iterations "
                                   f"(largest residual {np.max(np.abs(f)):.3g})")
        g, _ = _g_and_slope(xr, wr, cr, s)
        sigma[rows] = np.exp(3.0 * s) / (12.0 * viscosity)
        resid[rows] = 1.0 - g
    return sigma, resid


def bruggeman_residual(gaps: ArrayLike, weights: ArrayLike, contact_fraction: ArrayLike, viscosity: float,
                       sigma: ArrayLike) -> FloatArray:
    """σ_eff [1/σ_eff - Σ_j W_j 2/(σ_eff + σ(u_j)) - 2c/σ_eff] per row (0 at the solution; dimensionless), written out directly.

    The Bruggeman equation of docs/theory.md §5.3; gaps in m, η in Pa·s, σ_eff in m³/(Pa·s).
    """
    u = np.atleast_2d(np.asarray(gaps, dtype=float))
    w = np.atleast_2d(np.asarray(weights, dtype=float))
    c = np.atleast_1d(np.asarray(contact_fraction, dtype=float))
    s = np.atleast_1d(np.asarray(sigma, dtype=float))
    local = u**3 / (12.0 * viscosity)
    return s * (1.0 / s - np.sum(w * 2.0 / (s[:, None] + local), axis=1) - 2.0 * c / s)


def _quantile(dist: GapDistribution, level: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
    """The u (per pressure) where the continuous part's CDF reaches ``level`` (bisection in ln u)."""
    a, b = np.log(lo), np.log(hi)
    for _ in range(80):
        mid = 0.5 * (a + b)
        cdf = np.sum(dist.weights * folded_normal_cdf(np.exp(mid)[:, None], dist.centres, dist.widths), axis=1)
        below = cdf < level
        a = np.where(below, mid, a)
        b = np.where(below, b, mid)
    return np.exp(0.5 * (a + b))


def discretise(dist: GapDistribution, *, panel_width: float = 0.5, order: int = 8) -> tuple[FloatArray, FloatArray]:
    """The continuous part of P(u) as discrete (gaps, weights), shape (pressures, n), see the module docstring.

    Gaps in m, weights dimensionless (docs/theory.md §5.5). Rows whose continuous part is empty get a
    single node of weight 0.
    """
    mass = dist.weights.sum(axis=1)
    scale = np.maximum(dist.mean, 1e-200)  # (rows in complete contact have no continuous part)
    top = np.maximum(np.max(np.where(dist.weights > 0, dist.centres + 12.0 * dist.widths, 0.0), axis=1), scale)
    u_lo = _quantile(dist, 1e-10 * mass, scale * 1e-30, top)
    u_hi = _quantile(dist, mass - 1e-13 * np.maximum(mass, 1e-300), scale * 1e-30, top * 10.0)
    u_hi = np.maximum(u_hi, u_lo * 1.0001)
    span = np.log(u_hi / u_lo)
    n_pan = int(np.clip(np.ceil(np.max(span) / panel_width), 1, 2000))
    edges = np.log(u_lo)[:, None] + span[:, None] * (np.arange(n_pan + 1) / n_pan)[None, :]
    xg, wg = np.polynomial.legendre.leggauss(order)
    left, right = edges[:, :-1], edges[:, 1:]
    half = 0.5 * (right - left)
    x = (0.5 * (left + right))[:, :, None] + half[:, :, None] * xg
    u = np.exp(x).reshape(len(dist), -1)
    dens = _density_rows(dist, u)
    w = (half[:, :, None] * wg).reshape(len(dist), -1) * u * dens
    # rescale each panel to its exact mass from the closed-form CDF
    cdf_edges = np.sum(dist.weights[:, None, :] * folded_normal_cdf(np.exp(edges)[:, :, None], dist.centres[:, None, :],
                                                                     dist.widths[:, None, :]), axis=2)
    exact = np.diff(cdf_edges, axis=1)
    approx = w.reshape(len(dist), n_pan, order).sum(axis=2)
    # a panel whose Gauss points badly miss its mass (a feature narrower than the panel) gets its
    # exact mass at the panel's middle node instead
    resolved = (approx > 0.5 * exact) & (approx < 2.0 * exact)
    ratio = np.where(resolved, exact / np.where(resolved, approx, 1.0), 0.0)
    w = w.reshape(len(dist), n_pan, order) * ratio[:, :, None]
    fallback = ~resolved & (exact > 0)
    if fallback.any():
        w[fallback, order // 2] = exact[fallback]
    w = w.reshape(len(dist), -1)
    below = cdf_edges[:, 0]
    above = mass - cdf_edges[:, -1]
    gaps = np.concatenate([u_lo[:, None], u, u_hi[:, None]], axis=1)
    weights = np.concatenate([below[:, None], w, np.maximum(above, 0.0)[:, None]], axis=1)
    return gaps, weights


def _density_rows(dist: GapDistribution, u: FloatArray) -> FloatArray:
    """The continuous density at per-row separations u (pressures × n).

    Terms with |u ∓ u1|/h > √80 (< e^-40 of the peak) are skipped; the mirror term only for
    components with u1 < 9h.
    """
    out = np.empty_like(u)
    sq = np.sqrt(2.0 * np.pi)
    for i in range(len(dist)):
        live = (dist.weights[i] > 0) & (dist.widths[i] > 0)
        if not live.any():
            out[i] = 0.0
            continue
        wv, c, h = dist.weights[i, live], dist.centres[i, live], dist.widths[i, live]
        amp = wv / (sq * h)
        mirror = c < 9.0 * h
        for k in range(0, u.shape[1], 512):
            uk = u[i, k:k + 512, None]
            z = ((uk - c) / h) ** 2
            e = np.exp(-0.5 * z, where=z < 80.0, out=np.zeros_like(z))
            dens = e @ amp
            if mirror.any():
                zm = ((uk + c[mirror]) / h[mirror]) ** 2
                em = np.exp(-0.5 * zm, where=zm < 80.0, out=np.zeros_like(zm))
                dens += em @ amp[mirror]
            out[i, k:k + 512] = dens
    return out


@dataclass(frozen=True)
class EffectiveMediumResult:
    """Effective-medium prediction over a sweep of squeeze pressures (arrays of equal length, SI units).

    Attributes
    ----------
    squeeze_pressure, pressure_difference
        P0 and ΔP (Pa).
    percolates
        σ_eff > 0 (A(ζ1)/A0 < 1/2, Bruggeman's threshold; docs/theory.md §5.4).
    effective_conductivity
        σ_eff in m³/(Pa·s) (0 where it does not percolate).
    effective_gap
        u_e = (12 η σ_eff)^(1/3), the gap with the local conductivity σ_eff (m).
    leak_rate
        Q = (Ly/Lx) σ_eff ΔP in m³/s (NaN where it does not percolate).
    contact_area_at_cutoff
        A(ζ1)/A0, the δ(u) weight.
    mean_gap
        ū(1) (m).
    gap_distribution_mean
        ∫ u P(u) du (m).
    residual
        Relative residual 1 - g(σ_eff) of the solved Bruggeman equation.
    viscosity
        η (Pa·s).
    aspect_ratio
        Ly/Lx (dimensionless).
    distribution
        The :class:`~sealeak.physics.gaps.GapDistribution` P(u) at the distinct squeeze pressures.
    messages
        Human-readable notes (one per non-percolating pressure).
    """

    squeeze_pressure: FloatArray
    pressure_difference: FloatArray
    percolates: NDArray[np.bool_]
    effective_conductivity: FloatArray
    effective_gap: FloatArray
    leak_rate: FloatArray
    contact_area_at_cutoff: FloatArray
    mean_gap: FloatArray
    gap_distribution_mean: FloatArray
    residual: FloatArray
    viscosity: float
    aspect_ratio: float
    distribution: GapDistribution = field(repr=False, compare=False)
    messages: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.squeeze_pressure.size)


def effective_medium(
    contact: PerssonContact,
    *,
    squeeze_pressure: ArrayLike,
    pressure_difference: ArrayLike,
    viscosity: float,
    aspect_ratio: float,
    distribution: GapDistribution | None = None,
) -> EffectiveMediumResult:
    """Bruggeman effective-medium leak rate Q = (Ly/Lx) σ_eff ΔP at every squeeze pressure (vectorised).

    Q in m³/s; σ_eff in m³/(Pa·s) solves 1/σ_eff = ∫ du P(u) 2/(σ_eff + σ(u)), σ(u) = u³/(12η)
    (Bruggeman (1935); docs/theory.md §5.3). No leak rate (NaN) where A(ζ1)/A0 >= 1/2 (§5.4).

    Parameters
    ----------
    contact
        Persson contact mechanics of the interface.
    squeeze_pressure
        Nominal squeeze pressures P0 in Pa (scalar or 1-D array).
    pressure_difference
        ΔP in Pa, scalar or broadcastable against ``squeeze_pressure``.
    viscosity
        η in Pa·s.
    aspect_ratio
        Ly/Lx (number of squares of side L across the seal).
    distribution
        A :class:`GapDistribution` already computed for these pressures (else it is computed).
    """
    p0, dp = _pressures(squeeze_pressure, pressure_difference)
    for name, v in (("viscosity", viscosity), ("aspect_ratio", aspect_ratio)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(name, v, "must be finite and > 0")
    # one distribution per distinct pressure
    uniq, inverse = np.unique(p0, return_inverse=True)
    if distribution is None or distribution.squeeze_pressure.shape != uniq.shape or \
            not np.array_equal(distribution.squeeze_pressure, uniq):
        distribution = gap_distribution(contact, uniq)
    dist = distribution
    gaps, weights = discretise(dist)
    sigma, resid = bruggeman_conductivity(gaps, weights, dist.contact_fraction, viscosity)
    percolates = sigma > 0
    sigma, resid, percolates = sigma[inverse], resid[inverse], percolates[inverse]
    area = dist.contact_fraction[inverse]
    q = np.where(percolates, aspect_ratio * sigma * dp, np.nan)
    u_e = np.cbrt(12.0 * viscosity * sigma)
    note = no_channel_note(p0, percolates, area,
                           " >= 0.5, the 2D Bruggeman percolation threshold: the effective-medium theory predicts no flow "
                           "(no leak-rate number; numerically exact studies put the threshold near A/A0 = 0.42).")
    messages = [note] if note else []
    return EffectiveMediumResult(
        squeeze_pressure=p0, pressure_difference=dp, percolates=percolates, effective_conductivity=sigma,
        effective_gap=u_e, leak_rate=q, contact_area_at_cutoff=area, mean_gap=dist.mean_gap[inverse],
        gap_distribution_mean=dist.mean[inverse], residual=resid, viscosity=float(viscosity),
        aspect_ratio=float(aspect_ratio), distribution=dist, messages=tuple(messages),
    )
