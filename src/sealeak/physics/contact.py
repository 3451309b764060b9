"""Persson contact mechanics: contact area and interfacial separation against magnification.

Rubber (contact modulus E* = E/(1-ν²)) squeezed with nominal pressure P0 against a rigid, randomly
rough substrate with power spectrum C(q). Magnification ζ = q/q0, q0 = 2π/L. Equations from
docs/theory.md §2.3–§2.10 (Persson, J. Chem. Phys. 115 (2001) 3840; Yang & Persson, J. Phys.: Condens.
Matter 20 (2008) 215214; Lorenz & Persson, EPL 86 (2009) 44006, unnumbered)::

    G(ζ)    = (π/4) E*² ∫_{q0}^{ζq0} q³ C(q) dq
    A(ζ)/A0 = erf(P0 / (2√G(ζ)))
    p(ζ)    = P0 A0/A(ζ)
    w(q,ζ)  = (π ∫_{ζq0}^{q} q'³ C(q') dq')^(-1/2)
    ū(ζ)    = √π ∫_{ζq0}^{q1} dq q² C(q) w(q,ζ) F(w(q,ζ) p(ζ)/E*)
    u1(ζ)   = ū(ζ) + ū'(ζ) A(ζ)/A'(ζ)

with F(y) = γ E1(y²)/2 + 3(1-γ) K(y) the closed form of the inner pressure integral (see
:mod:`sealeak.physics._kernels`, docs/theory.md §2.8); γ = 1 is the formula as printed in the reference paper.

How the ζ-integrals are computed (docs/theory.md §2.9; exact to ~1e-9 relative, far below the 1e-5 asked for):

* Every band moment ∫ qⁿ C dq is a closed form, because :class:`~sealeak.physics.spectrum.PowerSpectrum` is
  a piecewise power law; so G(ζ), A(ζ) and the critical magnification need no quadrature at all.
* ū and ū' are integrated in the variable s = ln t, t(q) = ∫_{ζq0}^{q} q'³ C dq' (so w = (πt)^(-1/2)),
  which turns ū into ∫ ds √t F(y)/q(t), y = p/(E*√(πt)). q(t) is the closed-form inverse of the
  cumulative moment. The lower limit q = ζq0 (t → 0, w → ∞) is where the integrand vanishes like
  exp(-y²); the s-range starts where y² exceeds y_T² + 40 (y_T: y at q1), which drops less than
  e^(-40) of the integrand; the upper end is q1 exactly.
* The range is cut into panels at every spectrum node above ζq0 (the kinks of C, e.g. at the
  roll-off q_r, become panel edges so each panel is smooth), at fixed values of y between 5 and
  0.75 (exp(-y²) is double-exponential in s, so its flank needs narrower panels) and into panels no wider than
  ``panel_width`` in s (default 2); each panel uses ``order``-point Gauss–Legendre (default 6:
  ~1e-9 relative against a much finer rule, see tests/unit/test_contact.py). All panels of all evaluation
  points (pressures × ζ) are listed flat and evaluated in cache-sized blocks: no Python loop over pressures or ζ.
* The cost is the integrand (docs/theory.md §2.9): each panel lies within one segment of the power law, so q(t)
  takes that segment's constants once per panel; ln y² = ln κ² - s needs no logarithm; F(y) = E1(y²)/2 comes
  from a table of eˣE1(x) (:func:`sealeak.physics._kernels.exp1`, 5e-15 relative) and shares e^(-y²) with
  F'(y). The result equals the point-by-point evaluation with scipy.special.exp1 to ~1e-15
  (tests/unit/test_effective_medium_fast_vs_plain.py).
* ū'(ζ) is the analytic ζ-derivative under the integral (the boundary term at q = ζq0 vanishes):
  ū' = ∫ ds [ D (F(y) + y F'(y)) / (2 q √t) + p'(ζ) F'(y) / (√π E* q) ],  D = q0 (ζq0)³ C(ζq0).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ..errors import InputError
from . import _kernels
from .spectrum import PowerSpectrum

__all__ = ["PerssonContact", "contact_modulus", "MIN_SQUEEZE_PRESSURE", "SOFTEST_MODULUS", "STIFFEST_MODULUS"]

FloatArray = NDArray[np.float64]

_TAIL = 40.0  # the s-range starts where y² = y_T² + _TAIL
_Y_EDGES = np.array([5.0, 4.0, 3.2, 2.6, 2.1, 1.7, 1.35, 1.05, 0.75])  # panel edges at these y
_BLOCK = 2048  # panels evaluated together: order × _BLOCK points per array, below 128 kB (cache, and no fresh pages per array)


def _row_sums(values: FloatArray, count: NDArray[np.intp]) -> FloatArray:
    """Sums of consecutive runs of ``values``, ``count[i]`` of them for row i (0 for an empty run)."""
    out = np.zeros(count.size)
    filled = count > 0
    if filled.any():
        out[filled] = np.add.reduceat(values, (np.cumsum(count) - count)[filled])
    return out


def _positive_band(g: FloatArray) -> FloatArray:
    """G(ζ) (Pa²) from the difference M3(ζq0) − M3(q0), which is >= 0: at ζ = 1 the two moments may differ in their
    last bit (M3 of an array and of a scalar take different SIMD paths on some CPUs), and −3·10⁻⁹ Pa² made √G NaN;
    such round-off is taken as 0."""
    return np.maximum(g, 0.0)


def _area(g: FloatArray, p0: FloatArray) -> FloatArray:
    """A(ζ)/A0 = erf(P0/(2√G)) from G(ζ) (Pa²) and P0 (Pa) (docs/theory.md eq. 2.4)."""
    with np.errstate(divide="ignore"):
        x = p0 / (2.0 * np.sqrt(g))
    return cast(FloatArray, special.erf(x))  # G = 0 (ζ = 1): x = inf, A/A0 = 1


def _area_derivative(g: FloatArray, gp: FloatArray, p0: FloatArray) -> FloatArray:
    """d(A/A0)/dζ from G (Pa²), dG/dζ (Pa²) and P0 (Pa) (docs/theory.md eq. 2.5)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        x = p0 / (2.0 * np.sqrt(g))
        out = (2.0 / np.sqrt(np.pi)) * np.exp(-x * x) * (-x * gp / (2.0 * g))
    return np.where(g > 0, out, 0.0)  # at ζ = 1 every derivative of erf(∞) vanishes


def contact_modulus(youngs_modulus: float, poisson_ratio: float,
                    youngs_modulus_2: float | None = None, poisson_ratio_2: float = 0.0) -> float:
    """E* in Pa: E/(1-ν²), or 1/E* = (1-ν1²)/E1 + (1-ν2²)/E2 when the substrate is elastic too.

    Moduli in Pa, Poisson ratios in (-1, 0.5]; the substrate's ν defaults to 0. Johnson, *Contact
    Mechanics* (1985); docs/theory.md §2.1 (eq. 2.1).
    """
    _check_modulus("youngs_modulus", youngs_modulus)
    _check_poisson("poisson_ratio", poisson_ratio)
    inv = (1.0 - poisson_ratio**2) / youngs_modulus
    if youngs_modulus_2 is not None:
        _check_modulus("youngs_modulus_2", youngs_modulus_2)
        _check_poisson("poisson_ratio_2", poisson_ratio_2)
        inv += (1.0 - poisson_ratio_2**2) / youngs_modulus_2
    return 1.0 / inv


#: The softest modulus (Pa) a contact takes: the softest gels are about 10 Pa; below 1 Pa a value is a unit slip, and far
#: below it E*² underflows in G(ζ) (the same floor as a Prony series' moduli).
SOFTEST_MODULUS = 1.0
#: The stiffest modulus (Pa) a contact takes: diamond's is about 1.2·10¹² Pa; far above it E*² overflows in G(ζ).
STIFFEST_MODULUS = 1e13
#: The smallest squeeze pressure, or peak contact pressure of a band, a case or a data file may give (Pa): far below
#: any seal's (kPa to MPa), and well above the pressures whose P0/E* (~10⁻⁹ and less) leave this theory nothing to
#: compute (refused by :func:`~sealeak.physics.critical_junction.critical_junction`: the surfaces barely touch); near
#: the smallest doubles the separation integrals overflowed.
MIN_SQUEEZE_PRESSURE = 1e-3


def _check_modulus(name: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
        raise InputError(name, value, "must be a finite modulus > 0 (Pa)")
    if value < SOFTEST_MODULUS:
        raise InputError(name, value, f"must be at least {SOFTEST_MODULUS:g} Pa: no solid is softer (the softest gels are "
                                      "about 10 Pa); check the value and its unit")
    if value > STIFFEST_MODULUS:
        raise InputError(name, value, f"must be at most {STIFFEST_MODULUS:g} Pa: no solid is stiffer (diamond's is about "
                                      "1.2e12 Pa); check the value and its unit")


def _check_poisson(name: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and np.isfinite(value) and -1.0 < value <= 0.5):
        raise InputError(name, value, "Poisson ratio must lie in (-1, 0.5]")


@dataclass(frozen=True)
class PerssonContact:
    """Persson contact mechanics of one rough interface.

    All methods broadcast ζ against P0 (nominal squeeze pressure, Pa). Persson, J. Chem. Phys. 115
    (2001) 3840 (G, A/A0); Yang & Persson, J. Phys.: Condens. Matter 20 (2008) 215214 (ū, u1);
    docs/theory.md §2.

    Parameters
    ----------
    spectrum:
        Substrate roughness C(q) (Persson convention, m⁴ against 1/m).
    e_star:
        Contact modulus E* in Pa.
    q0:
        Magnification reference wavevector 2π/L in 1/m (L: side of the nominal square).
    gamma:
        γ in (0, 1] of the separation integral (1: formula as printed in the reference paper;
        0.42: Yang & Persson's recommended value).
    panel_width, order:
        Quadrature controls of ū and ū' (panel width in ln t, Gauss–Legendre points per panel).
    """

    spectrum: PowerSpectrum
    e_star: float
    q0: float
    gamma: float = 1.0
    panel_width: float = 2.0
    order: int = 6

    def __post_init__(self) -> None:
        _check_modulus("contact modulus E*", self.e_star)
        if not (np.isfinite(self.q0) and self.q0 > 0):
            raise InputError("q0", self.q0, "must be a finite wavevector > 0 (1/m)")
        if not self.q0 < self.spectrum.q_max:
            raise InputError("q0", self.q0,
                             f"must be below the roughness cut-off q1 = {self.spectrum.q_max:.6g} 1/m")
        if not (0.0 < self.gamma <= 1.0):
            raise InputError("gamma", self.gamma, "must lie in (0, 1]")
        if not (self.panel_width > 0 and self.order >= 2):
            raise InputError("quadrature", (self.panel_width, self.order), "panel_width > 0 and order >= 2")

    # ------------------------------------------------------------------ closed forms
    @property
    def zeta_max(self) -> float:
        """ζ1 = q1/q0, the highest magnification (roughness cut-off)."""
        return self.spectrum.q_max / self.q0

    def _m3(self, q: ArrayLike) -> FloatArray:
        return self.spectrum.cumulative_moment(3, q)

    @cached_property
    def _m3_fixed(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """M3 at q0, at q1 and at every node of the spectrum (the same numbers on every call, computed once)."""
        return self._m3(self.q0), self._m3(self.spectrum.q_max), self._m3(self.spectrum.q[None, :])

    def G(self, zeta: ArrayLike) -> FloatArray:
        """G(ζ) = (π/4) E*² ∫_{q0}^{ζq0} q³C dq in Pa² (Persson (2001); docs/theory.md §2.3, eq. 2.3)."""
        z = np.asarray(zeta, dtype=float)
        return _positive_band(0.25 * np.pi * self.e_star**2 * (self._m3(z * self.q0) - self._m3_fixed[0]))

    def dG_dzeta(self, zeta: ArrayLike) -> FloatArray:
        """dG/dζ = (π/4) E*² q0 (ζq0)³ C(ζq0) in Pa² (docs/theory.md §2.3, eq. 2.3)."""
        q = np.asarray(zeta, dtype=float) * self.q0
        return 0.25 * np.pi * self.e_star**2 * self.q0 * q**3 * self.spectrum(q)

    def area(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """Relative apparent contact area A(ζ)/A0 = erf(P0/(2√G(ζ))) (dimensionless; P0 in Pa).

        Persson, J. Chem. Phys. 115 (2001) 3840; Lorenz & Persson (2009), unnumbered; docs/theory.md §2.4 (eq. 2.4).
        """
        return _area(self.G(zeta), np.asarray(squeeze_pressure, dtype=float))

    def area_derivative(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """d(A/A0)/dζ = (2/√π) e^(-x²) dx/dζ with x = P0/(2√G), dx/dζ = -x G'/(2G); <= 0 (docs/theory.md §2.4, eq. 2.5)."""
        return _area_derivative(self.G(zeta), self.dG_dzeta(zeta), np.asarray(squeeze_pressure, dtype=float))

    def mean_pressure(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """p(ζ) = P0 A0/A(ζ) in Pa, the mean pressure in the apparent contact (Lorenz & Persson (2009), unnumbered; docs/theory.md §2.5, eq. 2.6)."""
        return np.asarray(squeeze_pressure, dtype=float) / self.area(zeta, squeeze_pressure)

    def zeta_at_area(self, relative_area: float, squeeze_pressure: ArrayLike) -> tuple[FloatArray, NDArray[np.bool_]]:
        """ζ at which A(ζ)/A0 = relative_area, in closed form, and a mask of where it exists.

        G(ζ) = (P0/(2 erfinv(a)))² is inverted through the cumulative moment of q³C. Where that G
        exceeds G(ζ1) (the area never falls that low within the resolved roughness) the ζ returned
        is ζ1 and the mask is False. ``relative_area`` a in (0, 1), P0 in Pa (docs/theory.md §3.3, eq. 3.3).
        """
        if not 0.0 < relative_area < 1.0:
            raise InputError("relative contact area", relative_area, "must lie in (0, 1)")
        p0 = np.asarray(squeeze_pressure, dtype=float)
        g_target = (p0 / (2.0 * special.erfinv(relative_area))) ** 2
        m_target = g_target / (0.25 * np.pi * self.e_star**2) + self._m3(self.q0)
        exists = m_target <= self._m3(self.spectrum.q_max)
        q = self.spectrum.inverse_cumulative_moment(3, m_target)
        zeta = np.maximum(q / self.q0, 1.0)
        return np.where(exists, zeta, self.zeta_max), exists

    # ------------------------------------------------------------------ separation integrals
    def _integrals(self, zeta: ArrayLike, p0: ArrayLike, derivative: bool,
                   ) -> tuple[FloatArray, FloatArray | None, FloatArray, FloatArray | None]:
        """(ū, ū' or None, A/A0, d(A/A0)/dζ or None), each of the shape of ζ and P0 broadcast."""
        spec = self.spectrum
        m3_q0, m3_top, m3_nodes = self._m3_fixed
        z, p0 = np.broadcast_arrays(np.asarray(zeta, dtype=float), np.asarray(p0, dtype=float))
        shape = z.shape
        z = z.ravel()
        p0 = p0.ravel()
        qz = np.maximum(z * self.q0, spec.q_min)
        m_lo = self._m3(qz)
        big_t = m3_top - m_lo  # t at q1
        g = _positive_band(0.25 * np.pi * self.e_star**2 * (self._m3(z * self.q0) - m3_q0))  # G(ζ)
        area = _area(g, p0)
        p = p0 / area
        kappa = p / (self.e_star * np.sqrt(np.pi))  # y = kappa / sqrt(t)
        active = (big_t > 0) & (z * self.q0 < spec.q_max)
        big_t_safe = np.where(active, big_t, 1.0)
        y_top2 = kappa**2 / big_t_safe
        s_hi = np.log(big_t_safe)
        s_lo = s_hi - np.log1p(_TAIL / y_top2)
        # Panel edges: uniform split plus the spectrum's nodes (kinks of C) inside the range.
        width = s_hi - s_lo
        per_row = np.maximum(np.ceil(width / self.panel_width), 1.0)  # uniform panels of each row
        step = width / per_row
        k = np.arange(int(np.max(per_row[active], initial=1.0)) + 1)
        uniform = np.minimum(s_lo[:, None] + step[:, None] * k[None, :], s_hi[:, None])
        node_t = m3_nodes - m_lo[:, None]
        with np.errstate(divide="ignore"):
            node_s = np.log(np.where(node_t > 0, node_t, 0.0))
        node_s = np.clip(node_s, s_lo[:, None], s_hi[:, None])
        # exp(-y²) is double-exponential in s: extra edges at fixed y resolve its steep flank.
        y_edges = np.log(kappa**2)[:, None] - 2.0 * np.log(_Y_EDGES)[None, :]
        y_s = np.clip(y_edges, s_lo[:, None], s_hi[:, None])
        parts = np.concatenate([uniform, node_s, y_s], axis=1)
        order = np.argsort(parts, axis=1, kind="stable")
        edges = np.take_along_axis(parts, order, axis=1)
        # the segment of C each panel lies in (spectrum nodes at or before its left edge, less one), and which panels
        # run from one y-edge to the next (neither clipped): there the nodes sit at fixed y
        tags = np.full(parts.shape, -1, dtype=np.intp)
        n_uniform, n_nodes = uniform.shape[1], node_s.shape[1]
        tags[:, n_uniform:n_uniform + n_nodes] = -2
        tags[:, n_uniform + n_nodes:] = np.where(y_s == y_edges, np.arange(_Y_EDGES.size), -1)
        tags = np.take_along_axis(tags, order, axis=1)
        segment = np.clip(np.cumsum(tags == -2, axis=1)[:, :-1] - 1, 0, spec.q.size - 2)
        y_panel = np.where((tags[:, :-1] >= 0) & (tags[:, 1:] == tags[:, :-1] + 1), tags[:, :-1], -1)
        d = pz = da = None
        if derivative:
            d = self.q0 * qz**3 * spec(qz)
            da = _area_derivative(g, self.dG_dzeta(z), p0)
            pz = -p0 * da / area**2 / (np.sqrt(np.pi) * self.e_star)
        ubar_flat, dubar_flat = self._panel_sums(edges, active, m_lo, kappa, d, pz, segment, y_panel)
        ubar = cast(FloatArray, np.where(active, ubar_flat, 0.0).reshape(shape))
        if dubar_flat is None or da is None:
            return ubar, None, area.reshape(shape), None
        return ubar, cast(FloatArray, np.where(active, dubar_flat, 0.0).reshape(shape)), area.reshape(shape), da.reshape(shape)

    def _panel_sums(self, edges: FloatArray, active: NDArray[np.bool_], m_lo: FloatArray, kappa: FloatArray,
                    d: FloatArray | None, pz: FloatArray | None, segment: NDArray[np.intp],
                    y_panel: NDArray[np.intp]) -> tuple[FloatArray, FloatArray | None]:
        """ū (and ū' when ``d``, ``pz`` are given) per row: ``order``-point Gauss–Legendre on every non-empty panel.

        Rows are ragged (spectrum nodes outside a row's range give empty panels, which get no points; inactive rows
        get none), so the panels are listed flat with the row each belongs to, and evaluated in blocks of
        ``_BLOCK`` panels (the arrays stay in cache). Each panel lies within one segment k of the piecewise power
        law (the spectrum's nodes are panel edges), so the closed-form inverse q(t) (docs/theory.md §1.3)
        takes that segment's constants once per panel: q = q_k (1 + e r)^(1/e), r = (t + m_lo - M3(q_k))/(C_k q_k⁴).
        With y² = κ²/t, ln y² = ln κ² - s (no logarithm per point), P = -y F'(y) and F'(y) = -P √t/κ, the integrands
        of the module docstring read  ū: √t F/q,  ū': [D (F - P)/(2√t) - p'(ζ)/(√π E*) P √t/κ]/q
        (``d`` = D, ``pz`` = p'(ζ)/(√π E*)).
        """
        spec = self.spectrum
        a = edges[:, :-1]
        width = edges[:, 1:] - a
        live = (width > 0) & active[:, None]
        count = live.sum(axis=1)  # panels per row; they are listed row after row

        def per_panel(values: FloatArray) -> FloatArray:
            return np.repeat(values, count)

        half = 0.5 * width[live]
        mid = a[live] + half
        xg, wg = _kernels.gauss_legendre(self.order)
        m_lo_p = per_panel(m_lo)
        seg = segment[live]
        cum_k, scale_k, e_k = spec._segment_constants(3, np.arange(spec.q.size - 1))  # per segment, then per panel
        linear_k = e_k == 0.0  # ((q/q_k)^e - 1)/e at e = 0 is ln(q/q_k): q = q_k e^r
        linear = linear_k[seg]
        neg_inv_e = (-1.0 / np.where(linear_k, 1.0, e_k))[seg]
        slope = (np.where(linear_k, 1.0, e_k) / scale_k)[seg]  # z = e r = slope (t + m_lo - M3(q_k))
        offset = m_lo_p - cum_k[seg]
        floor = (spec.q[:-1] / spec.q_max)[seg]  # q <= q1: q_k/q >= q_k/q1
        # per panel: Σ_j w_j f_j = half Σ_j wg_j f_j, and 1/q = (q_k/q)/q_k
        factor = half / spec.q[:-1][seg]
        kappa2 = per_panel(kappa * kappa)
        log_kappa2 = per_panel(2.0 * np.log(kappa))
        ubar = np.empty(half.size)  # per panel, summed per row at the end
        dubar = np.empty(half.size) if d is not None else None
        d_half = per_panel(0.5 * d) if d is not None else None
        pz_kappa = per_panel(pz / kappa) if pz is not None else None
        xg = xg[:, None]
        # A panel between two neighbouring y-edges (``y_panel`` >= 0: its index among y = 5, 4, ..., 0.75) has its
        # nodes at the same y in every row: there t = κ²/y², √t = κ/y, F and P are the same numbers for all rows.
        v_edges = 2.0 * np.log(_Y_EDGES)  # ln y² at the edges
        v_nodes = 0.5 * (v_edges[:-1] + v_edges[1:]) - 0.5 * (v_edges[:-1] - v_edges[1:]) * xg  # (order, y-panels)
        f_tab, p_tab = _kernels.f_and_slope(np.exp(v_nodes), v_nodes, self.gamma)
        inv_y2_tab, inv_y_tab = np.exp(-v_nodes), np.exp(-0.5 * v_nodes)
        y_panel = y_panel[live]
        shared = y_panel >= 0
        kappa_p = per_panel(kappa)
        # A flat segment of C (β = 0, e = 4: the roll-off plateau) has q_k/q = (1 + z)^(-1/4), two square roots.
        flat = e_k[seg] == 4.0
        kind = flat + 2 * shared
        for k in range(4):
            panels = np.flatnonzero(kind == k)
            plateau, same_y = bool(k & 1), bool(k & 2)
            for lo in range(0, panels.size, _BLOCK):
                # arrays (order, panels): the per-panel constants broadcast along the long last axis; few temporaries
                blk = panels[lo:lo + _BLOCK]
                if same_y:
                    j = y_panel[blk]
                    t = kappa2[blk] * inv_y2_tab[:, j]
                else:
                    s = half[blk] * xg
                    s += mid[blk]
                    t = np.exp(s)
                ratio = t + offset[blk]  # z = e r, then q_k/q = (1 + z)^(-1/e)
                ratio *= slope[blk]
                if plateau:
                    ratio += 1.0
                    np.sqrt(ratio, out=ratio)
                    np.sqrt(ratio, out=ratio)
                    np.reciprocal(ratio, out=ratio)
                else:
                    lin = linear[blk]
                    z_lin = ratio[:, lin] if lin.any() else None
                    np.log1p(ratio, out=ratio)
                    ratio *= neg_inv_e[blk]
                    if z_lin is not None:
                        ratio[:, lin] = -z_lin
                    np.exp(ratio, out=ratio)
                np.maximum(ratio, floor[blk], out=ratio)
                if same_y:
                    f, p = f_tab[:, j], p_tab[:, j]
                    ratio *= kappa_p[blk] * inv_y_tab[:, j]  # √t q_k/q
                else:
                    y2 = kappa2[blk] / t
                    np.subtract(log_kappa2[blk], s, out=s)  # ln y²
                    f, p = _kernels.f_and_slope(y2, s, self.gamma)
                    ratio *= np.sqrt(t, out=y2)  # √t q_k/q
                factor_b = factor[blk]
                ubar[blk] = _kernels.weighted_sum(f * ratio, wg, axis=0) * factor_b
                if dubar is not None:
                    two = _kernels.weighted_sum(p * ratio, wg, axis=0)
                    f = f - p
                    ratio /= t  # q_k/(q √t)
                    f *= ratio
                    dubar[blk] = (d_half[blk] * _kernels.weighted_sum(f, wg, axis=0) - pz_kappa[blk] * two) * factor_b  # type: ignore[arg-type, operator, index]
        return _row_sums(ubar, count), None if dubar is None else _row_sums(dubar, count)

    def mean_gap(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """ū(ζ) in m: mean separation in the apparent contact area seen at magnification ζ.

        ū(ζ) = √π ∫_{ζq0}^{q1} dq q² C(q) w(q,ζ) F(w(q,ζ) p(ζ)/E*) (Yang & Persson, J. Phys.: Condens.
        Matter 20 (2008) 215214; docs/theory.md §2.7–§2.9, eqs. 2.8, 2.10). ū(ζ1) = 0; ū(1) is the mean separation of
        the whole interface.
        """
        return self._integrals(zeta, squeeze_pressure, derivative=False)[0]

    def mean_gap_derivative(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """dū/dζ in m (negative), the ζ-derivative under the integral (docs/theory.md §2.9, eq. 2.11)."""
        return self._integrals(zeta, squeeze_pressure, derivative=True)[1]  # type: ignore[return-value]

    def u1(self, zeta: ArrayLike, squeeze_pressure: ArrayLike) -> FloatArray:
        """u1(ζ) = ū(ζ) + ū'(ζ) A(ζ)/A'(ζ) in m: separation at the patches where contact is lost at ζ.

        Yang & Persson, J. Phys.: Condens. Matter 20 (2008) 215214; Lorenz & Persson (2009), unnumbered;
        docs/theory.md §2.10 (eq. 2.12).
        """
        ubar, dubar, a, da = self._integrals(zeta, squeeze_pressure, derivative=True)
        # where A'(ζ) is tiny (ζ -> 1, or a steep spectrum) u1 -> +inf: the quotient overflows to inf, as it should
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return ubar + dubar * a / da  # type: ignore[operator]
