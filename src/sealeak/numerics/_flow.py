"""Steady Reynolds flow through the gap field of a periodic contact cell.

Equation (thin film, incompressible Newtonian fluid, no-slip walls; Reynolds 1886; Patir & Cheng,
J. Lubr. Technol. 100 (1978) 12):

    ∇·( σ(x) ∇p ) = 0,     σ = g³ / (12 η)   [m³/(Pa·s)]

on the N×N square of side L (cells of side dx = L/N), with p = P_a on the inlet edge x = 0,
p = P_b on the outlet edge x = L, periodic along y, and no flow into contact cells.

Discretisation: cell-centred finite volumes. The conductance of the face between two cells is
the harmonic mean 2 σ_i σ_j / (σ_i + σ_j) (series resistance of two half cells); the flux across
it is σ_face (p_i - p_j) (face length dx over centre distance dx). The inlet/outlet faces use the
cell's own σ over half a cell: flux 2 σ_i (P_a - p_i). Parallel plates of gap g then give
exactly Q = g³ W ΔP / (12 η L).

Before solving, contact cells (the ``contact`` mask, else gap <= 0) and every fluid cluster not
connected to both the inlet and the outlet are removed: they carry no flow and would make the
matrix singular. The reduced matrix is symmetric positive definite (an M-matrix).

The unknown is φ = (p - P_b)/(P_a - P_b) with conductances scaled by their maximum; the flux is
linear in ΔP.

Solution check (every result): r = b - A φ is the net volume flux out of each cell. Because a
unit source injected in cell i leaves through the inlet with a probability w_i ∈ [0, 1]
(discrete harmonic measure), the error of the computed inflow is Σ w_i r_i, so

    |Q_computed - Q_exact| / Q <= ||r||_1 / Q  =: residual

is a rigorous bound on the relative flux error; it is the stopping test of the iterative
back-end and must be <= ``rtol``. In addition the inflow and outflow, computed independently
from the boundary faces, must agree to 1e-8 relative. A failed check raises
:class:`SolutionCheckError`; no number is returned.

Back-ends (never a silent fallback): ``"direct"`` — sparse LU (SuperLU, minimum-degree ordering
of AᵀA+A) with up to five steps of iterative refinement; ``"amg"`` — conjugate gradients on the
symmetrically diagonally scaled matrix D^-1/2 A D^-1/2, preconditioned by a smoothed-aggregation
AMG V-cycle (pyamg; near-null-space vector D^1/2·1 — the constant of the unscaled matrix —
and *classical* strength of connection θ = 0.5, i.e. relative to each cell's strongest face, so
aggregates do not straddle constrictions: on a 512² field at 40 % contact this takes 16 CG
iterations where pyamg's default symmetric strength needs > 300), stopped on the
flux-error bound above (not on pyamg's ||r||_2/||b||, which near the percolation threshold accepts
4 %-wrong fluxes because ||b|| is dominated by large inlet conductances). ``"auto"`` picks
``"direct"`` up to 250 000 unknowns, else ``"amg"``, and records the choice.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import sparse
from scipy.sparse import linalg as spla

from ..errors import ConvergenceError, InputError, SolutionCheckError
from ._memory import require_memory
from ._percolation import spanning_mask

FloatArray = NDArray[np.float64]
Method = Literal["auto", "direct", "amg"]

AUTO_DIRECT_MAX_UNKNOWNS = 250_000
CONSERVATION_TOL = 1e-8
DEFAULT_RTOL = 1e-6


@dataclass(frozen=True, eq=False)
class FlowResult:
    """Steady flow through one square cell.

    Attributes
    ----------
    flux:
        Volume flow rate Q through the square (m³/s) for the given ΔP (the inflow).
    inflow, outflow:
        Flow through the inlet and outlet edges (m³/s), computed independently.
    pressure:
        Fluid pressure p[x, y] (Pa, outlet pressure + ΔP φ); NaN in removed cells (contact,
        blocked or dead clusters).
    percolates:
        Whether a fluid cluster connects inlet and outlet (False: Q = 0, nothing solved).
    method:
        Back-end used: "direct", "amg" or "none" (no spanning cluster).
    residual:
        ||b - A φ||_1 / Q: bound on the relative flux error (module docstring).
    conservation_error:
        |inflow - outflow| / max(|inflow|, |outflow|).
    iterations:
        CG iterations (amg) or refinement steps (direct).
    unknowns:
        Number of cells in the spanning cluster(s) that were solved for.
    seconds:
        Wall time of the solve (assembly included).
    conductance:
        Q/ΔP of the square (m³/(Pa·s)).
    """

    flux: float
    inflow: float
    outflow: float
    pressure: FloatArray
    percolates: bool
    method: str
    residual: float
    conservation_error: float
    iterations: int
    unknowns: int
    seconds: float
    conductance: float


def flow_memory_bytes(n: int, method: Method = "auto") -> int:
    """Peak memory of :func:`solve_flow` on an n×n grid in bytes (estimate).

    ``"amg"``: the 5-point matrix (CSR), its scaled copy, the AMG hierarchy, long-double
    residual fields and CG vectors: ~700 B/unknown (tracemalloc peak 2.4 GiB at 2048², 10 %).
    ``"direct"``: the LU factors grow like n² log n; 7.6 GB were measured at 2048² and 10 %
    contact, i.e. ~1800 B/unknown there, used as ~150 log2(n) B/unknown.
    ``"auto"``: the estimate of the back-end ``"auto"`` would choose for a fully open n×n cell.
    """
    n = int(n)
    cells = n * n
    if method == "auto":
        method = "direct" if cells <= AUTO_DIRECT_MAX_UNKNOWNS else "amg"
    if method == "amg":
        return int(700 * cells)
    return int(150 * max(math.log2(max(n, 2)), 1.0) * cells + 200 * cells)


def _validate(gap: ArrayLike, size: float, viscosity: float, dp: float) -> FloatArray:
    g = np.asarray(gap, dtype=np.float64)
    if g.ndim != 2 or g.shape[0] != g.shape[1] or g.shape[0] < 1:
        raise InputError("gap", f"array of shape {g.shape}", "must be a square N×N array")
    if np.isnan(g).any() or np.isinf(g).any():
        raise InputError("gap", "non-finite values", "gaps must be finite (no NaN or inf)")
    for name, v, what in (("size", size, "a length > 0 (m)"), ("viscosity", viscosity, "a viscosity > 0 (Pa s)"),
                          ("pressure_difference", dp, "a pressure difference > 0 (Pa)")):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise InputError(name, v, f"must be finite, {what}")
    return g


def _assemble(s: FloatArray, fluid: NDArray[np.bool_]) -> tuple[sparse.csr_matrix, FloatArray, NDArray[np.int64],
                                                                    FloatArray, FloatArray]:
    """Matrix A, right-hand side b (φ = 1 inlet, 0 outlet), cell index map, boundary conductances."""
    n0, n1 = s.shape
    idx = np.full(s.shape, -1, dtype=np.int64)
    m = int(np.count_nonzero(fluid))
    idx[fluid] = np.arange(m, dtype=np.int64)
    sf = np.where(fluid, s, 0.0)
    # x faces (i, j)-(i+1, j), not periodic
    a, b = sf[:-1, :], sf[1:, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        cx = np.where((a > 0) & (b > 0), 2.0 * a * b / (a + b), 0.0)
    # y faces (i, j)-(i, j+1 mod n1), periodic (none if n1 == 1)
    if n1 > 1:
        bb = np.roll(sf, -1, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            cy = np.where((sf > 0) & (bb > 0), 2.0 * sf * bb / (sf + bb), 0.0)
    else:
        cy = np.zeros_like(sf)
    ix0 = idx[:-1, :][cx > 0]
    ix1 = idx[1:, :][cx > 0]
    vx = cx[cx > 0]
    iy0 = idx[cy > 0]
    iy1 = np.roll(idx, -1, axis=1)[cy > 0]
    vy = cy[cy > 0]
    diag = (np.bincount(ix0, vx, m) + np.bincount(ix1, vx, m)
            + np.bincount(iy0, vy, m) + np.bincount(iy1, vy, m))
    b_in = np.zeros(m)
    b_out = np.zeros(m)
    inl = fluid[0, :]
    outl = fluid[-1, :]
    b_in[idx[0, inl]] = 2.0 * sf[0, inl]
    b_out[idx[-1, outl]] += 2.0 * sf[-1, outl]
    diag += b_in + b_out
    rows = np.concatenate([ix0, ix1, iy0, iy1, np.arange(m)])
    cols = np.concatenate([ix1, ix0, iy1, iy0, np.arange(m)])
    vals = np.concatenate([-vx, -vx, -vy, -vy, diag])
    A = sparse.csr_matrix((vals, (rows, cols)), shape=(m, m))  # duplicates (n1 == 2) are summed
    A.sum_duplicates()
    return A, b_in.copy(), idx, b_in, b_out


class _Grid:
    """Face conductances on the structured grid, for residuals in extended precision."""

    def __init__(self, s: FloatArray, fluid: NDArray[np.bool_]) -> None:
        ld = np.longdouble
        sf = np.where(fluid, s, 0.0)
        a, b = sf[:-1, :], sf[1:, :]
        with np.errstate(invalid="ignore", divide="ignore"):
            self.cx = np.where((a > 0) & (b > 0), 2.0 * a * b / (a + b), 0.0).astype(ld)
            bb = np.roll(sf, -1, axis=1)
            cy = np.where((sf > 0) & (bb > 0), 2.0 * sf * bb / (sf + bb), 0.0)
        if sf.shape[1] == 1:
            cy[...] = 0.0
        self.cy = cy.astype(ld)
        self.bin = (2.0 * sf[0, :]).astype(ld)
        self.bout = (2.0 * sf[-1, :]).astype(ld)
        self.fluid = fluid

    def residual(self, phi: NDArray[np.longdouble]) -> tuple[NDArray[np.longdouble], float, float]:
        """Net volume inflow of every cell (b - A φ) and the inlet/outlet fluxes, in long double."""
        fx = self.cx * (phi[:-1, :] - phi[1:, :])  # flux i -> i+1
        fy = self.cy * (phi - np.roll(phi, -1, axis=1))  # flux j -> j+1 (periodic)
        r = np.zeros_like(phi)
        r[:-1, :] -= fx
        r[1:, :] += fx
        r -= fy
        r += np.roll(fy, 1, axis=1)
        qin = self.bin * (1.0 - phi[0, :])
        qout = self.bout * phi[-1, :]
        r[0, :] += qin
        r[-1, :] -= qout
        r[~self.fluid] = 0.0
        return r, float(qin.sum()), float(qout.sum())


def _checks(grid: _Grid, phi: NDArray[np.longdouble]) -> tuple[NDArray[np.longdouble], float, float, float, float, float]:
    """residual field, inflow, outflow, estimate |φᵀr|/Q, bound ||r||_1/Q, conservation error."""
    r, qin, qout = grid.residual(phi)
    q = max(abs(qin), abs(qout))
    if not q > 0:
        return r, qin, qout, math.inf, math.inf, math.inf
    est = abs(float(np.sum(phi * r))) / q
    bound = float(np.abs(r).sum()) / q
    return r, qin, qout, est, bound, abs(qin - qout) / q


class _DirectSolver:
    def __init__(self, A: sparse.csr_matrix) -> None:
        self.lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})

    def __call__(self, rhs: FloatArray) -> tuple[FloatArray, int]:
        return self.lu.solve(rhs), 0


class _AmgSolver:
    """CG on D^-1/2 A D^-1/2 preconditioned by a smoothed-aggregation V-cycle."""

    def __init__(self, A: sparse.csr_matrix, max_iter: int) -> None:
        import pyamg  # imported lazily: only this back-end needs it

        d = A.diagonal()
        self.sq = np.sqrt(d)
        Dm = sparse.diags(1.0 / self.sq)
        self.As = (Dm @ A @ Dm).tocsr()  # unit diagonal
        ml = pyamg.smoothed_aggregation_solver(
            self.As, B=self.sq.reshape(-1, 1), symmetry="symmetric",
            strength=("classical", {"theta": 0.5}), max_coarse=500)
        self.M = ml.aspreconditioner(cycle="V")
        self.max_iter = max_iter

    def __call__(self, rhs: FloatArray, reduction: float = 1e-11) -> tuple[FloatArray, int]:
        bs = rhs / self.sq
        x = np.zeros_like(bs)
        r = bs.copy()
        z = self.M @ r
        pdir = z.copy()
        rz = float(np.dot(r, z))
        rz0 = rz
        it = 0
        while rz > reduction**2 * rz0:  # preconditioned residual norm reduced by `reduction`
            if it >= self.max_iter:
                raise ConvergenceError(
                    f"flow solver (amg): preconditioned residual reduced only by "
                    f"{math.sqrt(rz / rz0):.3g} after {it} CG iterations, needed {reduction:.1e}")
            it += 1
            Ap = self.As @ pdir
            alpha = rz / float(np.dot(pdir, Ap))
            x += alpha * pdir
            r -= alpha * Ap
            z = self.M @ r
            rz_new = float(np.dot(r, z))
            pdir *= rz_new / rz
            pdir += z
            rz = rz_new
        return x / self.sq, it


def solve_flow(
    gap: ArrayLike,
    size: float,
    viscosity: float,
    pressure_difference: float,
    *,
    contact: ArrayLike | None = None,
    method: Method = "auto",
    rtol: float = DEFAULT_RTOL,
    outlet_pressure: float = 0.0,
    max_iter: int = 2000,
    memory_limit: float | None = None,
) -> FlowResult:
    """Leak flow through an N×N gap field from the inlet edge x = 0 to the outlet edge x = L.

    Parameters
    ----------
    gap:
        Interfacial gap g[x, y] (m); flow along axis 0, periodic along axis 1.
    size:
        Side L of the square (m).
    viscosity:
        Dynamic viscosity η (Pa·s).
    pressure_difference:
        ΔP = P_a - P_b > 0 (Pa).
    contact:
        Boolean contact mask (e.g. ``ContactResult.contact``, pressure > 0). If None, cells with
        gap <= 0 are contact. With a mask, cells outside it with gap <= 0 are also closed.
    method:
        "auto", "direct" or "amg" (module docstring). An explicit method that fails raises.
    rtol:
        Required bound on the relative flux error ||r||_1/Q (default 1e-6; the round-off floor of
        this rigorous but pessimistic bound is ~1e-8 at 512², higher on larger grids).
    outlet_pressure:
        P_b (Pa) for the returned pressure field.
    max_iter:
        CG iteration limit of the AMG back-end (ConvergenceError beyond).
    memory_limit:
        Bytes allowed (default: what the OS reports available); ResourceError up front.

    Returns
    -------
    FlowResult; ``flux`` is Q = (conductance of the square) × ΔP in m³/s.
    """
    t0 = time.perf_counter()
    g = _validate(gap, size, viscosity, pressure_difference)
    if method not in ("auto", "direct", "amg"):
        raise InputError("method", method, "allowed: 'auto', 'direct', 'amg'")
    if not (math.isfinite(rtol) and 0 < rtol < 1e-2):
        raise InputError("rtol", rtol, "must be in (0, 0.01)")
    n = g.shape[0]
    if contact is None:
        closed = g <= 0
    else:
        cm = np.asarray(contact)
        if cm.shape != g.shape:
            raise InputError("contact", f"mask of shape {cm.shape}", f"must match the gap shape {g.shape}")
        if cm.dtype != np.bool_:
            raise InputError("contact", f"array of dtype {cm.dtype}", "must be a boolean mask (pressure > 0)")
        closed = cm | (g <= 0)
    gmax = float(g[~closed].max()) if (~closed).any() else 0.0
    s = np.zeros_like(g)
    if gmax > 0:
        np.divide(g, gmax, out=s, where=~closed)
        s **= 3  # conductance / (gmax³/(12 η))
        closed |= s <= 0.0  # underflow: gap below 1e-103 gmax carries nothing
    fluid = spanning_mask(~closed)
    m = int(np.count_nonzero(fluid))
    pressure = np.full(g.shape, np.nan)
    if m == 0:
        return _result(0.0, 0.0, 0.0, pressure, False, "none", 0.0, 0.0, 0, 0, t0, 0.0)
    chosen = method if method != "auto" else ("direct" if m <= AUTO_DIRECT_MAX_UNKNOWNS else "amg")
    require_memory(flow_memory_bytes(n, chosen), f"the {n}x{n} flow problem ({chosen})", memory_limit)
    A, b, idx, b_in, b_out = _assemble(s, fluid)
    grid = _Grid(s, fluid)
    solver = _DirectSolver(A) if chosen == "direct" else _AmgSolver(A, max_iter)
    del A
    # mixed-precision iterative refinement: φ and the residual in long double, corrections in
    # double precision from the chosen back-end, until the flux checks hold
    phi = np.zeros(g.shape, dtype=np.longdouble)
    rhs = b
    its = 0
    for _ in range(8):
        delta, k = solver(rhs)
        its += k
        phi[fluid] += delta.astype(np.longdouble)
        r, inflow, outflow, res, bound, cons = _checks(grid, phi)
        if res <= rtol and cons <= 0.1 * CONSERVATION_TOL:
            break
        rhs = r[fluid].astype(np.float64)
    if not (np.isfinite(phi[fluid]).all() and res <= rtol and cons <= CONSERVATION_TOL and inflow > 0):
        raise SolutionCheckError(
            f"flow solution ({chosen}, {m} unknowns) failed its check: flux-error estimate |φᵀr|/Q = "
            f"{res:.3g} (allowed {rtol:.3g}), |inflow - outflow|/Q = {cons:.3g} (allowed {CONSERVATION_TOL:.0e})"
            f"; bound ||r||_1/Q = {bound:.3g}")
    unit = gmax**3 / (12.0 * viscosity) * pressure_difference  # m³/s per unit dimensionless flux
    pressure[fluid] = outlet_pressure + pressure_difference * phi[fluid].astype(np.float64)
    cond = inflow * gmax**3 / (12.0 * viscosity)
    return _result(inflow * unit, inflow * unit, outflow * unit, pressure, True, chosen, res, cons, its, m, t0, cond)


def _result(q: float, qin: float, qout: float, pressure: FloatArray, perc: bool, method: str, res: float,
            cons: float, its: int, m: int, t0: float, cond: float) -> FlowResult:
    return FlowResult(q, qin, qout, pressure, perc, method, res, cons, its, m, time.perf_counter() - t0, cond)
