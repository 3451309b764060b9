"""Steady isothermal gas flow through the gap field of a periodic contact cell, with rarefaction.

Equation (docs/theory.md §11.10; thin film, ideal gas ρ = p/(R_s T), isothermal,
slow viscous flow with the slip model of §11.4):

    ∇·( ρ σ(g, p) ∇p ) = 0   ⇔   ∇·( σ(g, p) ∇(p²) ) = 0,    σ(g, p) = g³ f(Kn(g, p)) / (12 μ)

with p = P_a on the inlet edge x = 0, p = P_b on the outlet edge x = L, periodic along y, no flow into
contact. The mass flux is ρ σ ∇p = σ ∇(p²)/(2 R_s T), so the mass flow is ṁ = (flux of φ = p²)/(2 R_s T)
and the pV throughput Q_pV = ṁ R_s T (counted at the gas temperature T).

* Without rarefaction (f = 1, ``model="no-slip"``) the problem in φ = p² is *exactly* the liquid
  problem of :func:`solve_flow` (§6.3) with a different right-hand side: one linear solve at unit
  Δφ gives the no-slip conductance K0 (m³/(Pa·s)) of the square and ṁ = K0 (P_a² − P_b²)/(2 R_s T),
  p = √(P_b² + (P_a² − P_b²) φ̂) with φ̂ the liquid solution at unit drop.
* With slip, σ depends on p. The fixed point: from the current pressures, set the face
  conductances; solve the (linear) φ problem with the same finite-volume matrix and back-ends as
  :func:`solve_flow` (sparse LU or AMG-CG with iterative refinement and the same flux-error bound
  and conservation checks); take p = √φ; repeat. It starts from the no-slip solution.

Face conductances with slip (the secant rule). The half cell of cell i on the face towards j carries
σ0_i F_i, σ0_i = g_i³/(12 μ) and F_i the mean of f over the face's pressure interval weighted as the
flux of φ is:

    F_i = ∫_{p_j}^{p_i} 2 p f(c_i/p) dp / (p_i² − p_j²),   c_i = μ √(π R_s T/2)/g_i   (Kn = c_i/p)

(F_i = f(c_i/p_i) when p_i = p_j); the face has the harmonic mean of the two half cells, the inlet
and outlet faces 2 σ0_i F_i with p_j = P_a or P_b. The flux σ0 F (p_i² − p_j²) = σ0 (Ψ(p_i) − Ψ(p_j))
with Ψ(p) = ∫ 2p f dp (the Kirchhoff transform of a cell of constant gap), so in a channel of
constant gap the discrete fixed point is exact: Ψ falls linearly and ∫ p f dp between the inlet and
any point is proportional to its distance (the closed form of §11.5). F is integrated by
Gauss–Legendre quadrature: 12 nodes in p when p_lo ≥ p_hi/4, else 24 nodes in u = p^(1/5), which
removes the p^0.4 cusp of the slip factor at p = 0 (a face to vacuum); both within 1e-11 of adaptive
quadrature for 1e-8 ≤ Kn ≤ 1e8 (Beskok–Karniadakis). The kinetic model's F is in closed form (the exact
integral of its tabulated G_P, :func:`sealeak.physics.gas.kinetic_pressure_integral`), with the 12-node
rule only on intervals narrower than 1e-3 p_hi, where the difference of the integrals would cancel.

Convergence of the fixed point (checked, never assumed). G maps the pressures x = p/P_a of the fluid
cells to those of the linear solve with the faces set from x; the iteration is accelerated by Anderson
mixing of the last four evaluations (Walker & Ni, SIAM J. Numer. Anal. 49 (2011) 1715), with a plain
step x = G(x) whenever a proposal leaves [P_b/P_a, 1] (the maximum principle). After evaluation k,
d_k is the larger of the relative change of ṁ and max |G(x_k) − x_k|; L, the largest of the last
three ratios |G(x_k) − G(x_(k−1))|/|x_k − x_(k−1)| (maximum norms), estimates G's contraction, and
e_k = d_k L/(1 − L) the error left in G(x_k). The result (ṁ and p of the last linear solve) is
accepted when d_k ≤ ``tol`` and e_k ≤ ``tol``; where no contraction L < 1 can be measured, only when
d_k ≤ min(``tol``, 10 ``rtol``), the accuracy of the linear solves themselves. Otherwise, after
``max_iter`` evaluations, a :class:`ConvergenceError` is raised: no number is returned.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ConvergenceError, InputError, SolutionCheckError, positive_values
from ..physics.gas import DEFAULT_RAREFACTION, Gas, check_pressures, check_rarefaction_model, kinetic_pressure_integral, slip_factor
from ._amg import _back_end
from ._checks import square_grid
from ._flow import (
    CONSERVATION_TOL,
    Method,
    _assemble,
    _Grid,
    _refine,
    flow_memory_bytes,
    solve_flow,
)
from ._memory import require_memory

__all__ = ["GasFlowResult", "solve_gas_flow", "secant_slip_factor", "gas_flow_memory_bytes", "DEFAULT_GAS_TOL"]

FloatArray = NDArray[np.float64]

#: Default tolerance of the fixed point on the relative change of the mass flow and of p/P_a.
DEFAULT_GAS_TOL = 1e-6
#: Default bound on the relative flux error of every linear solve (the ``rtol`` of :func:`solve_flow`).
DEFAULT_GAS_RTOL = 1e-7
#: Below this ratio p_lo/p_hi the secant factor is integrated in u = p^(1/5) (module docstring).
_SPLIT = 0.25
_NODES_P = np.polynomial.legendre.leggauss(12)
_NODES_U = np.polynomial.legendre.leggauss(24)
#: Faces per block of the quadrature (bounds its temporary arrays to a few tens of MB).
_BLOCK = 65536


@dataclass(frozen=True, eq=False, kw_only=True)
class GasFlowResult:
    """Steady isothermal gas flow through one square cell (docs/theory.md §11.10).

    Attributes
    ----------
    mass_flow:
        ṁ through the square (kg/s), the inflow.
    inflow, outflow:
        Mass flow through the inlet and the outlet edge (kg/s), computed independently.
    throughput:
        pV throughput Q_pV = ṁ R_s T (Pa·m³/s), counted at the gas temperature.
    throughput_no_slip:
        K0 (P_a² − P_b²)/2 (Pa·m³/s): the same gap field without rarefaction (the p² solve).
    conductance_no_slip:
        K0 (m³/(Pa·s)): the no-slip (liquid) conductance of the square, Q/ΔP of :func:`solve_flow`
        with the gas's viscosity.
    pressure:
        Absolute gas pressure p[x, y] (Pa); NaN in removed cells (contact, dead or blocked fluid).
    knudsen:
        Kn = λ(p)/g in every solved cell; NaN elsewhere.
    percolates:
        Whether a fluid cluster connects inlet and outlet (False: ṁ = 0, nothing solved).
    rarefaction_model:
        The slip model (:data:`sealeak.physics.gas.RAREFACTION_MODELS`).
    upstream_pressure, downstream_pressure:
        P_a and P_b (Pa).
    iterations:
        Fixed-point iterations (linear solves after the no-slip one; 0 for ``model="no-slip"``).
    mass_flow_change, pressure_change:
        Relative change of ṁ and largest change of p/P_a in the last iteration (0 without slip).
    error_estimate:
        e = d r/(1 − r) of the last iteration (module docstring; 0 without slip, NaN where no
        contraction could be measured and the change sat at the linear solves' accuracy).
    method:
        Linear back-end ("direct", "amg", or "none").
    residual, conservation_error:
        Flux-error bound ||r||_1/Q and |inflow − outflow|/Q of the last linear solve.
    unknowns:
        Cells solved for.
    seconds:
        Wall time (s).
    device:
        Where the linear solves' CG iterations ran: "cpu", or "cuda" (:func:`solve_flow`).
    """

    mass_flow: float
    inflow: float
    outflow: float
    throughput: float
    throughput_no_slip: float
    conductance_no_slip: float
    pressure: FloatArray
    knudsen: FloatArray
    percolates: bool
    rarefaction_model: str
    upstream_pressure: float
    downstream_pressure: float
    iterations: int
    mass_flow_change: float
    pressure_change: float
    error_estimate: float
    method: str
    residual: float
    conservation_error: float
    unknowns: int
    seconds: float
    device: str = "cpu"


def gas_flow_memory_bytes(n: int, method: Method = "auto") -> int:
    """Peak memory of :func:`solve_gas_flow` on an n×n grid in bytes (estimate): the flow solver's
    (:func:`flow_memory_bytes`) plus ~400 B per cell of face and pressure fields and quadrature blocks, plus
    300 B per cell that the liquid solver needed before its memory was cut (2026-11-24) and that are kept here
    as a margin: the gas solver's own peak has not been measured again since."""
    return flow_memory_bytes(n, method) + 700 * int(n) ** 2 + 60 * _BLOCK * 8 * 24


def secant_slip_factor(knudsen_scale: ArrayLike, p1: ArrayLike, p2: ArrayLike, model: str = DEFAULT_RAREFACTION) -> FloatArray:
    """F = ∫_{p2}^{p1} 2 p f(c/p) dp / (p1² − p2²): the slip factor f averaged over a pressure interval as
    the flux of p² weights it (F = f(c/p1) when p1 = p2); docs/theory.md §11.10, eq. 11.13.

    ``knudsen_scale`` c = μ √(π R_s T/2)/g (Pa) makes Kn = c/p; ``p1``, ``p2`` are absolute pressures
    (Pa, > 0 or one of them 0). Broadcasts. Gauss–Legendre quadrature (module docstring), relative
    error below 1e-11.
    """
    c, a, b = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (knudsen_scale, p1, p2)))
    check_rarefaction_model(model)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    if np.any(~(lo >= 0)) or np.any(~(hi > 0)) or np.any(~(c >= 0)) or np.any(~np.isfinite(hi)):
        raise InputError("pressure", "values <= 0 or not finite", "absolute pressures must be finite, the larger one > 0")
    if model == "no-slip":
        return np.ones(c.shape)
    out = np.empty(c.shape)
    flat = (c.ravel(), lo.ravel(), hi.ravel(), out.reshape(-1))
    for start in range(0, flat[0].size, _BLOCK):
        s = slice(start, start + _BLOCK)
        flat[3][s] = _secant_block(flat[0][s], flat[1][s], flat[2][s], model)
    return out


def _secant_block(c: FloatArray, lo: FloatArray, hi: FloatArray, model: str) -> FloatArray:
    out = np.empty(c.size)
    if model == "kinetic":  # in closed form (∫ G_P dδ of the table's interpolant), but on a tiny interval
        wide = hi - lo > 1e-3 * hi
        out[wide] = 2.0 * kinetic_pressure_integral(c[wide], hi[wide], lo[wide]) / ((hi - lo) * (hi + lo))[wide]
        near = ~wide
    else:
        near = lo >= _SPLIT * hi
    if near.any():  # Gauss–Legendre in p on [lo, hi]: Σ w_k p_k f(p_k)/(lo + hi), the weights summing to 2
        x, w = _NODES_P
        cn, a, b = c[near, None], lo[near, None], hi[near, None]
        p = 0.5 * (b + a) + 0.5 * (b - a) * x
        out[near] = (w * p * slip_factor(cn / p, model)).sum(axis=1) / (a + b)[:, 0]
    far = ~near if model != "kinetic" else np.zeros(c.size, dtype=bool)
    if far.any():  # in u = p^(1/5): ∫ 2p f dp = ∫ 10 u⁹ f du, no cusp at p = 0
        x, w = _NODES_U
        cf, a, b = c[far, None], lo[far, None], hi[far, None]
        ul, uh = a**0.2, b**0.2
        u = 0.5 * (uh + ul) + 0.5 * (uh - ul) * x
        p = u**5
        integral = 0.5 * (uh - ul)[:, 0] * (w * 10.0 * u**4 * p * slip_factor(cf / p, model)).sum(axis=1)
        out[far] = integral / ((b - a) * (b + a))[:, 0]
    return out


def _validate(gap: ArrayLike, size: float, gas: Gas) -> FloatArray:
    if not isinstance(gas, Gas):
        raise InputError("gas", gas, "must be a sealeak.physics.gas.Gas (name, temperature, viscosity, molar mass)")
    g = square_grid(gap, "gap", "gaps")
    positive_values(("size", size, "a length > 0 (m)"))
    return g


def solve_gas_flow(
    gap: ArrayLike,
    size: float,
    gas: Gas,
    upstream_pressure: float,
    downstream_pressure: float,
    *,
    contact: ArrayLike | None = None,
    model: str = DEFAULT_RAREFACTION,
    method: Method = "auto",
    tol: float = DEFAULT_GAS_TOL,
    rtol: float = DEFAULT_GAS_RTOL,
    max_iter: int = 100,
    cg_max_iter: int = 2000,
    memory_limit: float | None = None,
    device: str = "cpu",
) -> GasFlowResult:
    """Gas leak through an N×N gap field from the inlet edge x = 0 (P_a) to the outlet edge x = L (P_b).

    Solves ∇·(g³ f(Kn) ∇(p²)) = 0 (docs/theory.md §11.10, eqs. 11.11, 11.13): without slip one
    linear solve of the liquid problem in p² (:func:`solve_flow`), with slip a checked fixed point
    over the same linear solver (module docstring).

    Parameters
    ----------
    gap:
        Interfacial gap g[x, y] (m); flow along axis 0, periodic along axis 1; N >= 2.
    size:
        Side L of the square (m).
    gas:
        The gas (:class:`sealeak.physics.gas.Gas`: temperature, viscosity, molar mass).
    upstream_pressure, downstream_pressure:
        Absolute pressures P_a > P_b >= 0 (Pa; P_b = 0 is vacuum).
    contact:
        Boolean contact mask, as for :func:`solve_flow`.
    model:
        Slip model: "kinetic" (default; an infinite slit), "beskok-karniadakis" or "no-slip" (docs/theory.md §11.4).
    method:
        Linear back-end: "auto", "direct" or "amg" (:func:`solve_flow`).
    tol:
        Fixed-point tolerance on the relative change of ṁ and of p/P_a and on the error estimate.
    rtol:
        Bound on the relative flux error of each linear solve (should lie below ``tol``).
    max_iter:
        Fixed-point iteration limit (ConvergenceError beyond).
    cg_max_iter:
        CG iteration limit of the AMG back-end.
    memory_limit:
        Bytes allowed (default: what the OS reports available); ResourceError up front.
    device:
        Where the AMG back-end's CG iterations run, "cpu" or "cuda" (:func:`solve_flow`); every check on the host.

    Returns
    -------
    GasFlowResult
        ``mass_flow`` in kg/s, ``throughput`` in Pa·m³/s, the pressure and Knudsen fields.
    """
    t0 = time.perf_counter()
    g = _validate(gap, size, gas)
    pa, pb = check_pressures(upstream_pressure, downstream_pressure)
    if not pa > pb:
        raise InputError("upstream_pressure", upstream_pressure,
                         f"must be above the downstream pressure {pb:.6g} Pa (no pressure drop, no flow to solve)")
    check_rarefaction_model(model)
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and 1e-13 <= tol <= 1e-2):
        raise InputError("tol", tol, "must be in [1e-13, 0.01]")
    if not (isinstance(rtol, (int, float)) and math.isfinite(rtol) and 0 < rtol < 1e-2):
        raise InputError("rtol", rtol, "must be in (0, 0.01)")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise InputError("max_iter", max_iter, "must be a whole number >= 1")
    n = g.shape[0]
    require_memory(gas_flow_memory_bytes(n, method), f"the {n}x{n} gas flow problem", memory_limit)
    rst = gas.specific_gas_constant * gas.temperature
    d_phi = (pa - pb) * (pa + pb)
    # the no-slip problem in φ = p²: the liquid solve at unit drop (φ̂ = (φ − P_b²)/(P_a² − P_b²) in [0, 1])
    base = solve_flow(g, size, gas.viscosity, 1.0, contact=contact, method=method, rtol=rtol,
                      max_iter=cg_max_iter, memory_limit=memory_limit, device=device)
    k0 = base.conductance
    nan = np.full(g.shape, np.nan)
    if not base.percolates:
        return GasFlowResult(mass_flow=0.0, inflow=0.0, outflow=0.0, throughput=0.0, throughput_no_slip=0.0,
                             conductance_no_slip=0.0, pressure=nan, knudsen=nan.copy(), percolates=False,
                             rarefaction_model=model, upstream_pressure=pa, downstream_pressure=pb, iterations=0,
                             mass_flow_change=0.0, pressure_change=0.0, error_estimate=0.0,
                             method="none", residual=0.0, conservation_error=0.0, unknowns=0,
                             seconds=time.perf_counter() - t0)
    fluid = np.isfinite(base.pressure)
    phi_hat = np.where(fluid, base.pressure, np.nan)
    pressure = np.sqrt(pb * pb + d_phi * phi_hat)
    scale = gas.rarefaction_pressure_scale
    kn_field = np.where(fluid, scale / np.where(fluid, g, 1.0) / np.where(fluid, pressure, 1.0), np.nan)
    no_slip_q = 0.5 * k0 * d_phi
    if model == "no-slip":
        m = no_slip_q / rst
        return GasFlowResult(mass_flow=m, inflow=base.inflow / base.flux * m, outflow=base.outflow / base.flux * m,
                             throughput=no_slip_q, throughput_no_slip=no_slip_q, conductance_no_slip=k0,
                             pressure=pressure, knudsen=kn_field, percolates=True, rarefaction_model=model,
                             upstream_pressure=pa, downstream_pressure=pb, iterations=0, mass_flow_change=0.0,
                             pressure_change=0.0, error_estimate=0.0, method=base.method, residual=base.residual,
                             conservation_error=base.conservation_error, unknowns=base.unknowns,
                             seconds=time.perf_counter() - t0, device=base.device)
    return _fixed_point(g, fluid, phi_hat, gas, pa, pb, model, base.method, tol, rtol, max_iter, cg_max_iter,
                        k0, t0, base.device)


def _fixed_point(g: FloatArray, fluid: NDArray[np.bool_], phi_hat: FloatArray, gas: Gas, pa: float, pb: float,
                 model: str, chosen: str, tol: float, rtol: float, max_iter: int, cg_max_iter: int, k0: float,
                 t0: float, device: str = "cpu") -> GasFlowResult:
    """The slip fixed point (module docstring), started from the no-slip solution φ̂.

    The map G takes the pressures x = p/P_a of the fluid cells to the pressures of the linear solve
    with the faces set from x. Anderson acceleration (Walker & Ni 2011, depth :data:`ANDERSON_DEPTH`)
    proposes the next x from the last G evaluations; a proposal outside [P_b/P_a, 1] (the maximum
    principle) is replaced by the plain step x = G(x) and the history is cleared.
    """
    rst = gas.specific_gas_constant * gas.temperature
    d_phi = (pa - pb) * (pa + pb)
    gmax = float(g[fluid].max())
    sigma0 = np.where(fluid, (np.where(fluid, g, 0.0) / gmax) ** 3, 0.0)  # σ0/(gmax³/(12 μ))
    c = np.where(fluid, gas.rarefaction_pressure_scale / np.where(fluid, g, 1.0), 0.0)  # Kn = c/p
    unit = gmax**3 / (12.0 * gas.viscosity) * d_phi / (2.0 * rst)  # kg/s per unit dimensionless flux
    phi = np.zeros(g.shape, dtype=np.longdouble)
    phi[fluid] = phi_hat[fluid]
    m_old = k0 * d_phi / (2.0 * rst)
    x = np.sqrt(pb * pb + d_phi * phi_hat[fluid]) / pa
    p_field = np.full(g.shape, pa)
    g_hist: list[FloatArray] = []  # the last G(x) and residuals G(x) − x, for Anderson
    f_hist: list[FloatArray] = []
    x_prev: FloatArray | None = None
    lips: list[float] = []
    history: list[float] = []
    for it in range(1, max_iter + 1):
        p_field[fluid] = pa * x
        cx, cy, sb = _faces(sigma0, c, p_field, fluid, pa, pb, model)
        phi, inflow, outflow, bound, cons = _solve_linear(cx, cy, sb, fluid, phi, chosen, rtol, cg_max_iter, device)
        m = inflow * unit
        gx = np.sqrt(pb * pb + d_phi * np.maximum(phi[fluid].astype(np.float64), 0.0)) / pa
        f = gx - x
        dm = abs(m - m_old) / m
        dp = float(np.abs(f).max())
        d = max(dm, dp)
        history.append(d)
        if x_prev is not None:  # a lower estimate of G's Lipschitz constant along the last step
            step = float(np.abs(x - x_prev).max())
            if step > 0:
                lips.append(float(np.abs(gx - g_hist[-1]).max()) / step)
        lip = max(lips[-3:]) if lips else math.nan
        estimate = d * lip / (1.0 - lip) if lip < 1.0 else math.nan
        m_old = m
        if d <= tol and (estimate <= tol if lip < 1.0 else d <= 10.0 * rtol):
            p = np.full(g.shape, np.nan)
            p[fluid] = pa * gx
            with np.errstate(divide="ignore"):
                kn = np.where(fluid, c / np.where(fluid, p, 1.0), np.nan)
            return GasFlowResult(mass_flow=m, inflow=m, outflow=outflow * unit, throughput=m * rst,
                                 throughput_no_slip=0.5 * k0 * d_phi, conductance_no_slip=k0, pressure=p, knudsen=kn,
                                 percolates=True, rarefaction_model=model, upstream_pressure=pa, downstream_pressure=pb,
                                 iterations=it, mass_flow_change=dm, pressure_change=dp, error_estimate=estimate,
                                 method=chosen, residual=bound, conservation_error=cons,
                                 unknowns=int(np.count_nonzero(fluid)),
                                 seconds=time.perf_counter() - t0, device=device)
        x_prev = x
        g_hist.append(gx)
        f_hist.append(f)
        proposal = _anderson(g_hist, f_hist, pb / pa)
        if proposal is None:  # the proposal left the physical range: a plain step, history cleared
            proposal = gx
            del g_hist[:-1], f_hist[:-1]
        x = proposal
    raise ConvergenceError(
        f"gas flow ({model}, {int(np.count_nonzero(fluid))} unknowns): the slip fixed point did not converge in {max_iter} "
        f"iterations: last relative changes {', '.join(f'{v:.2g}' for v in history[-4:])}, needed {tol:.1e}")


#: Depth of the Anderson acceleration of the slip fixed point (last G evaluations used).
ANDERSON_DEPTH = 4


def _anderson(g_hist: list[FloatArray], f_hist: list[FloatArray], lower: float) -> FloatArray | None:
    """Next iterate by Anderson mixing of the last :data:`ANDERSON_DEPTH` + 1 evaluations (Walker & Ni 2011,
    SIAM J. Numer. Anal. 49, 1715, type II, no damping): x = g_k − ΔG γ with γ minimising ||f_k − ΔF γ||₂.
    None if the proposal leaves [lower, 1]."""
    del g_hist[:-(ANDERSON_DEPTH + 1)], f_hist[:-(ANDERSON_DEPTH + 1)]
    if len(f_hist) < 2:
        return g_hist[-1]
    dF = np.stack([f_hist[i + 1] - f_hist[i] for i in range(len(f_hist) - 1)], axis=1)
    dG = np.stack([g_hist[i + 1] - g_hist[i] for i in range(len(g_hist) - 1)], axis=1)
    gamma = np.linalg.lstsq(dF, f_hist[-1], rcond=1e-12)[0]
    x = g_hist[-1] - dG @ gamma
    if not (np.isfinite(x).all() and x.min() >= lower and x.max() <= 1.0):
        return None
    return x


def _faces(sigma0: FloatArray, c: FloatArray, p: FloatArray, fluid: NDArray[np.bool_], pa: float, pb: float,
           model: str) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Face conductances of φ = p² by the secant rule (module docstring), in units of gmax³/(12 μ).

    ``cx[i, j]`` couples (i, j)–(i+1, j), ``cy[i, j]`` couples (i, j)–(i, j+1 mod n) (none if either
    side is not fluid); ``sb`` holds the inlet (row 0) and outlet (row −1) half-cell conductances σ0 F,
    which :func:`sealeak.numerics._flow._assemble` doubles for the half cell.
    """
    pf = np.where(fluid, p, pa)  # any positive pressure outside the fluid: those faces are zeroed below
    cx = np.zeros((fluid.shape[0] - 1, fluid.shape[1]))
    both = fluid[:-1, :] & fluid[1:, :]
    if both.any():
        a = sigma0[:-1, :][both] * secant_slip_factor(c[:-1, :][both], pf[:-1, :][both], pf[1:, :][both], model)
        b = sigma0[1:, :][both] * secant_slip_factor(c[1:, :][both], pf[:-1, :][both], pf[1:, :][both], model)
        cx[both] = 2.0 * a * b / (a + b)
    cy = np.zeros(fluid.shape)
    if fluid.shape[1] > 1:
        nb = np.roll(fluid, -1, axis=1)
        both = fluid & nb
        if both.any():
            pn, cn, sn = (np.roll(v, -1, axis=1)[both] for v in (pf, c, sigma0))
            a = sigma0[both] * secant_slip_factor(c[both], pf[both], pn, model)
            b = sn * secant_slip_factor(cn, pf[both], pn, model)
            cy[both] = 2.0 * a * b / (a + b)
    sb = np.zeros(fluid.shape)
    for row, p_edge in ((0, pa), (-1, pb)):
        cells = fluid[row, :]
        sb[row, cells] = sigma0[row, cells] * secant_slip_factor(c[row, cells], pf[row, cells], p_edge, model)
    if not (np.isfinite(cx).all() and np.isfinite(cy).all() and np.isfinite(sb).all()):
        raise SolutionCheckError("gas flow: a face conductance is not finite (a pressure fell to 0 inside the gap field)")
    return cx, cy, sb


def _solve_linear(cx: FloatArray, cy: FloatArray, sb: FloatArray, fluid: NDArray[np.bool_],
                  phi: NDArray[np.longdouble], chosen: str, rtol: float, cg_max_iter: int, device: str = "cpu"
                  ) -> tuple[NDArray[np.longdouble], float, float, float, float]:
    """φ̂ of the linear problem with the given faces (φ̂ = 1 at the inlet, 0 at the outlet), warm-started
    from ``phi``, by the back-end of :func:`solve_flow` with its refinement loop and checks (§6.3).

    Returns φ̂ (long double), the dimensionless inflow and outflow, the flux-error bound and the
    conservation error; raises :class:`SolutionCheckError` when the checks fail."""
    A, b_in, _b_out = _assemble(cx, cy, sb, fluid)
    grid = _Grid(cx, cy, sb, fluid)
    solver = _back_end(A, chosen, cg_max_iter, device)
    del A
    phi = phi.copy()
    _its, (_r, inflow, outflow, res, bound, cons) = _refine(solver, grid, phi, b_in, rtol, {})
    if not (np.isfinite(phi[fluid]).all() and bound <= rtol and cons <= CONSERVATION_TOL and inflow > 0):
        raise SolutionCheckError(
            f"gas flow solution ({chosen}, {int(np.count_nonzero(fluid))} unknowns) failed its check: flux-error bound "
            f"||r||_1/Q = {bound:.3g} (allowed {rtol:.3g}), |inflow - outflow|/Q = {cons:.3g} (allowed "
            f"{CONSERVATION_TOL:.0e}); estimate |φᵀr|/Q = {res:.3g}")
    return phi, inflow, outflow, bound, cons

