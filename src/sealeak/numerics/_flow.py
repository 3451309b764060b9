"""Steady Reynolds flow through the gap field of a periodic contact cell.

Equation (docs/theory.md §6.3; thin film, incompressible Newtonian fluid, no-slip walls; Reynolds 1886;
Patir & Cheng, J. Lubr. Technol. 100 (1978) 12):

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
of AᵀA+A) with up to seven steps of iterative refinement; ``"amg"`` — conjugate gradients on the
symmetrically diagonally scaled matrix D^-1/2 A D^-1/2, preconditioned by a smoothed-aggregation
AMG V-cycle (built from pyamg's kernels; near-null-space vector D^1/2·1 — the constant of the
unscaled matrix — and *classical* strength of connection θ = 0.7, i.e. relative to each cell's
strongest face, so aggregates do not straddle constrictions: on a 512² field at 40 % contact
θ = 0.5 takes 16 CG iterations where pyamg's default symmetric strength needs > 300; details in
:class:`_AmgSolver`; deterministic: the same gap field gives the same digits every run), stopped
on the flux-error bound above (not on pyamg's ||r||_2/||b||, which near the percolation threshold accepts
4 %-wrong fluxes because ||b|| is dominated by large inlet conductances). ``"auto"`` picks
``"direct"`` up to 250 000 unknowns, else ``"amg"``, and records the choice. With
``device="cuda"`` the AMG back-end's CG iterations run on a GPU (:class:`_CycleSolver`: the same
hierarchy, cycled with l1-Jacobi smoothing); everything else, the check included, stays on the host.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyamg.aggregation import standard_aggregation
from pyamg.relaxation.relaxation import gauss_seidel
from scipy import sparse
from scipy.linalg import pinvh
from scipy.sparse import linalg as spla

from ..errors import ConvergenceError, InputError, SolutionCheckError, positive_values
from ._device import array_namespace_for, check_device, require_device_memory
from ._linalg import dot
from ._memory import require_memory
from ._percolation import spanning_mask
from ._xp import to_numpy

FloatArray = NDArray[np.float64]
Method = Literal["auto", "direct", "amg"]

AUTO_DIRECT_MAX_UNKNOWNS = 250_000
#: The preconditioner of the AMG back-end's CG on a device (:class:`_CycleSolver`); "jacobi" is there to be measured.
DEVICE_PRECONDITIONER: Literal["amg", "jacobi"] = "amg"
CONSERVATION_TOL = 1e-8
DEFAULT_RTOL = 1e-6


@dataclass(frozen=True, eq=False, kw_only=True)
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
    phase_seconds:
        Wall time of each step (s): "clusters" (validation, conductances, the spanning cluster),
        "assembly" (faces, matrix), "setup" (LU factorisation or AMG hierarchy), "iterations"
        (back-end solves), "check" (extended-precision residuals); empty when nothing was solved.
    device:
        Where the CG iterations ran: "cpu", or "cuda" (the AMG back-end on a GPU, ``solve_flow(device=...)``).
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
    phase_seconds: dict[str, float] = field(default_factory=dict)
    device: str = "cpu"


def flow_memory_bytes(n: int, method: Method = "auto") -> int:
    """Peak memory of :func:`solve_flow` on an n×n grid in bytes (estimate, an upper bound of what was measured).

    ``"amg"``: the 5-point matrix (CSR, scaled in place), the AMG hierarchy (operator complexity
    ~1.7), the double-precision face conductances, the long-double solution, the CG vectors, plus a
    fixed 64 MiB: 400 B/cell. Measured (peak resident set of a fresh process minus the one before the
    solve, 10 % and 25 % contact): 335 B/cell at 1024², 314 at 2048², 291 at 4096² (4.9 GB).
    ``"direct"``: the LU factors grow like n² log n; 7.6 GB were measured at 2048² and 10 %
    contact, i.e. ~1800 B/unknown there, used as ~150 log2(n) B/unknown.
    ``"auto"``: the estimate of the back-end ``"auto"`` would choose for a fully open n×n cell.
    """
    n = int(n)
    cells = n * n
    if method == "auto":
        method = "direct" if cells <= AUTO_DIRECT_MAX_UNKNOWNS else "amg"
    if method == "amg":
        return int(400 * cells + 64 * 2**20)
    return int(150 * max(math.log2(max(n, 2)), 1.0) * cells + 200 * cells)


def _validate(gap: ArrayLike, size: float, viscosity: float, dp: float) -> FloatArray:
    g = np.asarray(gap, dtype=np.float64)
    if g.ndim != 2 or g.shape[0] != g.shape[1] or g.shape[0] < 1:
        raise InputError("gap", f"array of shape {g.shape}", "must be a square N×N array")
    if np.isnan(g).any() or np.isinf(g).any():
        raise InputError("gap", "non-finite values", "gaps must be finite (no NaN or inf)")
    positive_values(("size", size, "a length > 0 (m)"), ("viscosity", viscosity, "a viscosity > 0 (Pa s)"),
                    ("pressure_difference", dp, "a pressure difference > 0 (Pa)"))
    return g


def _faces(s: FloatArray, fluid: NDArray[np.bool_]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Face conductances (harmonic means; 0 where either side is closed) and the cell values.

    ``cx[i, j]`` couples cells (i, j) and (i+1, j) (not periodic); ``cy[i, j]`` couples (i, j) and
    (i, j+1 mod n1) (periodic; none if n1 == 1); ``sf`` is σ in fluid cells and 0 elsewhere.
    """
    sf = np.where(fluid, s, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        a, b = sf[:-1, :], sf[1:, :]
        cx = np.where((a > 0) & (b > 0), 2.0 * a * b / (a + b), 0.0)
        bb = np.roll(sf, -1, axis=1)
        cy = np.where((sf > 0) & (bb > 0), 2.0 * sf * bb / (sf + bb), 0.0)
    if sf.shape[1] == 1:
        cy[...] = 0.0
    return cx, cy, sf


def _assemble(cx: FloatArray, cy: FloatArray, sf: FloatArray, fluid: NDArray[np.bool_]
              ) -> tuple[sparse.csr_matrix, FloatArray, FloatArray]:
    """Matrix A (CSR, rows in raster order of the fluid cells) and the boundary conductances.

    Built row by row without a sort: each fluid cell's row holds, in this order, its neighbours
    at i-1, j-1, itself, j+1 and i+1 (those with a non-zero face), so the CSR arrays come from
    one boolean selection of a (cells × 5) table.
    """
    n0, n1 = fluid.shape
    m = int(np.count_nonzero(fluid))
    itype = np.int32 if 5 * m < np.iinfo(np.int32).max else np.int64  # what scipy would convert to
    idx = np.full(fluid.shape, -1, dtype=itype)
    idx[fluid] = np.arange(m, dtype=itype)
    zrow = np.zeros((1, n1))
    c_up = np.concatenate([zrow, cx])[fluid]  # face to (i-1, j)
    c_down = np.concatenate([cx, zrow])[fluid]  # face to (i+1, j)
    c_right = cy[fluid]  # face to (i, j+1)
    c_left = np.roll(cy, 1, axis=1)[fluid]  # face to (i, j-1)
    b_in = np.zeros(m)
    b_out = np.zeros(m)
    b_in[idx[0, fluid[0, :]]] = 2.0 * sf[0, fluid[0, :]]
    b_out[idx[-1, fluid[-1, :]]] += 2.0 * sf[-1, fluid[-1, :]]
    diag = c_up + c_down + c_left + c_right + b_in + b_out
    vals = np.empty((m, 5))
    for k, v in enumerate((-c_up, -c_left, diag, -c_right, -c_down)):
        vals[:, k] = v
    cols = np.empty((m, 5), dtype=itype)
    for k, (shift, axis) in enumerate(((1, 0), (1, 1), (0, 0), (-1, 1), (-1, 0))):
        cols[:, k] = (np.roll(idx, shift, axis=axis) if shift else idx)[fluid]
    keep = vals != 0.0
    keep[:, 2] = True
    indptr = np.zeros(m + 1, dtype=itype)
    count = keep[:, 0].astype(itype)  # entries per row (column by column: count_nonzero(axis=1) is slow)
    for k in range(1, 5):
        count += keep[:, k]
    np.cumsum(count, out=indptr[1:])
    del count
    A = sparse.csr_matrix((vals[keep], cols[keep], indptr), shape=(m, m))
    if n1 == 2:  # the neighbours j-1 and j+1 are the same cell: sum them
        A.sum_duplicates()
    return A, b_in, b_out


class _Grid:
    """Face conductances on the structured grid, for residuals in extended precision.

    The conductances are kept in double precision (the values the matrix was built from, exact in
    long double) and the residual is formed block by block of rows, in long double, so only a block's
    extended-precision temporaries are alive at once (memory ~ 8 B per cell per field, not 16).
    """

    ROWS_PER_BLOCK = 256

    def __init__(self, cx: FloatArray, cy: FloatArray, sf: FloatArray, fluid: NDArray[np.bool_]) -> None:
        self.cx = cx
        self.cy = cy
        self.bin = 2.0 * sf[0, :]
        self.bout = 2.0 * sf[-1, :]
        self.fluid = fluid

    def residual(self, phi: NDArray[np.longdouble]) -> tuple[FloatArray, float, float, float, float, float]:
        """Net volume inflow of every cell, b - A φ, formed in long double and returned rounded to
        double, with the inflow, the outflow, Σ|r|, |Σ φ r| and Σ r (sums in long double)."""
        ld = np.longdouble
        n0 = phi.shape[0]
        r_out = np.empty(phi.shape)
        l1 = ld(0.0)
        phir = ld(0.0)
        qin = (self.bin.astype(ld) * (1.0 - phi[0, :])).sum()
        qout = (self.bout.astype(ld) * phi[-1, :]).sum()
        for a in range(0, n0, self.ROWS_PER_BLOCK):
            b = min(a + self.ROWS_PER_BLOCK, n0)
            lo, hi = max(a - 1, 0), min(b, n0 - 1)  # faces i -> i+1 for i in [lo, hi) touch the block
            fx = self.cx[lo:hi, :].astype(ld) * (phi[lo:hi, :] - phi[lo + 1:hi + 1, :])  # flux i -> i+1
            blk = phi[a:b, :]
            fy = self.cy[a:b, :].astype(ld) * (blk - np.roll(blk, -1, axis=1))  # flux j -> j+1 (periodic)
            r = np.zeros_like(blk)
            # the same operations, in the same order, as on the whole grid: r[:-1] -= fx; r[1:] += fx
            r[: hi - a, :] -= fx[a - lo:, :]  # out through the face below (rows a .. hi-1)
            r[lo + 1 - a:, :] += fx[: b - lo - 1, :]  # in through the face above (rows lo+1 .. b-1)
            r -= fy
            r += np.roll(fy, 1, axis=1)
            if a == 0:
                r[0, :] += self.bin.astype(ld) * (1.0 - phi[0, :])
            if b == n0:
                r[-1, :] -= self.bout.astype(ld) * phi[-1, :]
            r[~self.fluid[a:b, :]] = 0.0
            l1 += np.abs(r).sum()
            phir += (blk * r).sum()
            r_out[a:b, :] = r
        return r_out, float(qin), float(qout), float(l1), abs(float(phir)), float(r_out.sum())


def _checks(grid: _Grid, phi: NDArray[np.longdouble]) -> tuple[FloatArray, float, float, float, float, float]:
    """residual field (double), inflow, outflow, estimate |φᵀr|/Q, bound ||r||_1/Q, conservation error."""
    r, qin, qout, l1, phir, _net = grid.residual(phi)
    q = max(abs(qin), abs(qout))
    if not q > 0:
        return r, qin, qout, math.inf, math.inf, math.inf
    return r, qin, qout, phir / q, l1 / q, abs(qin - qout) / q


@dataclass(frozen=True)
class _Flux:
    """Inflow Q = Σ w_k (1 - φ_k) over the inlet cells of φ = base + x (dimensionless units)."""

    cells: NDArray[np.int64]  # inlet cells (indices into the unknowns)
    weights: FloatArray  # their inlet face conductances
    base: FloatArray  # φ of the current total solution at those cells

    def __call__(self, x_inlet: FloatArray) -> float:
        return dot(self.weights, 1.0 - self.base - x_inlet)


class _DirectSolver:
    def __init__(self, A: sparse.csr_matrix) -> None:
        self.lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})

    def __call__(self, rhs: FloatArray, l1_tol: float, sum_tol: float, flux: _Flux) -> tuple[FloatArray, int]:
        return self.lu.solve(rhs), 0  # tolerances: the caller's refinement loop checks


def _row_of_entries(M: sparse.csr_matrix) -> NDArray[np.intp]:
    """Row index of every stored entry of a CSR matrix."""
    return np.repeat(np.arange(M.shape[0]), np.diff(M.indptr))


def _upper(A: sparse.csr_matrix, rows: NDArray[np.intp]) -> sparse.csr_matrix:
    """Strictly upper triangle of a CSR matrix (``rows``: :func:`_row_of_entries`), by one mask over
    its entries (no COO round trip)."""
    n = A.shape[0]
    keep = A.indices > rows
    indptr = np.zeros(n + 1, dtype=A.indptr.dtype)
    np.cumsum(np.bincount(rows[keep], minlength=n), out=indptr[1:])
    return sparse.csr_matrix((A.data[keep], A.indices[keep], indptr), shape=A.shape)


def _strong_pattern(M: sparse.csr_matrix, rows: NDArray[np.intp], theta: float) -> sparse.csr_matrix:
    """Pattern of the classical strength of connection (Ruge & Stüben; pyamg's
    ``classical_strength_of_connection`` with its default 'abs' norm): entry (i, j), j ≠ i, is strong
    when |a_ij| >= θ max_{k≠i} |a_ik| and a_ij ≠ 0; the diagonal is always kept. Vectorised over the
    entries (``rows``: :func:`_row_of_entries`); the data are ones (aggregation uses the pattern)."""
    off = M.indices != rows
    mag = np.abs(M.data)
    mag[~off] = 0.0
    nonempty = np.diff(M.indptr) > 0
    rowmax = np.zeros(M.shape[0])
    rowmax[nonempty] = np.maximum.reduceat(mag, M.indptr[:-1][nonempty])
    keep = (mag >= theta * rowmax[rows]) & (mag != 0.0)
    keep |= ~off
    del mag, off
    indptr = np.zeros(M.shape[0] + 1, dtype=M.indptr.dtype)
    np.cumsum(np.bincount(rows[keep], minlength=M.shape[0]), out=indptr[1:])
    return sparse.csr_matrix((np.ones(int(indptr[-1])), M.indices[keep], indptr), shape=M.shape)


def _smooth_prolongator(T: sparse.csr_matrix, AT: sparse.csr_matrix, weight: FloatArray) -> sparse.csr_matrix:
    """P = T - diag(weight) (A T) (``AT`` is consumed): p_ij = t_ij - w_i (AT)_ij, with the row scaling
    done on ``AT``'s entries in place instead of a sparse product with the diagonal matrix (the same
    digits; (AT)_ij can vanish where T has an entry, so the sum is a sparse addition)."""
    AT.data *= -weight[_row_of_entries(AT)]
    return (T + AT).tocsr()


def _hierarchy(A: sparse.csr_matrix) -> tuple[FloatArray, list[tuple[sparse.csr_matrix, ...]], sparse.csr_matrix]:
    """The smoothed-aggregation hierarchy of :class:`_AmgSolver` (its docstring), for any back-end that cycles on it.

    ``A`` (CSR, float64) is scaled in place to D^-1/2 A D^-1/2 and becomes the finest level's matrix.
    Returns √diag(A), the levels (A_l, P_l, R_l) from the finest down, and the coarsest matrix (<=
    ``_AmgSolver.MAX_COARSE`` unknowns; ``A`` itself when it is that small already). A coarsening that stalls
    is a :class:`ConvergenceError`.
    """
    rows = _row_of_entries(A)
    sq = _scaled(A, rows)
    levels: list[tuple[sparse.csr_matrix, ...]] = []
    level_a, cand, row_of = A, sq.copy(), rows
    while level_a.shape[0] > _AmgSolver.MAX_COARSE and len(levels) < _AmgSolver.MAX_LEVELS - 1:
        agg = standard_aggregation(_strong_pattern(level_a, row_of, _AmgSolver.THETA))[0].tocsr()
        n, nc = agg.shape
        if nc == 0 or nc >= n:  # nothing left to coarsen
            break
        cols = agg.indices
        c_agg = cand[_row_of_entries(agg)]
        norm = np.sqrt(np.bincount(cols, weights=c_agg**2, minlength=nc))
        T = sparse.csr_matrix((c_agg / norm[cols], cols, agg.indptr), shape=(n, nc))
        del c_agg
        weight = _AmgSolver.OMEGA / np.bincount(row_of, weights=np.abs(level_a.data), minlength=n)
        P = _smooth_prolongator(T, level_a @ T, weight)
        del T, agg
        R = P.T.tocsr()
        AP = level_a @ P
        coarse = (R @ AP).tocsr()
        del AP
        coarse.sum_duplicates()
        levels.append((level_a, P, R))
        level_a, cand = coarse, norm
        row_of = _row_of_entries(level_a)
    if level_a.shape[0] > 20 * _AmgSolver.MAX_COARSE:  # a dense coarse solve would not fit: say so
        raise ConvergenceError(f"flow solver (amg): coarsening stalled at {level_a.shape[0]} unknowns "
                               f"after {len(levels)} levels; use method='direct'")
    return sq, levels, level_a


def _stop(l1: float, net: float, q: float, it: int, l1_tol: float, sum_tol: float, max_iter: int, who: str) -> bool:
    """Whether CG's iterate meets the flux-error test (||r||_1 <= l1_tol·Q and |Σ r| <= sum_tol·Q); a
    :class:`ConvergenceError` naming the back-end ``who`` once ``max_iter`` iterations have not."""
    if q > 0 and l1 <= l1_tol * q and net <= sum_tol * q:
        return True
    if it >= max_iter:
        raise ConvergenceError(f"flow solver ({who}): residual bound ||r||_1/Q = {l1 / q if q > 0 else math.inf:.3g} "
                               f"after {it} CG iterations, needed {l1_tol:.1e}")
    return False


class _AmgSolver:
    """CG on D^-1/2 A D^-1/2 preconditioned by a smoothed-aggregation V-cycle (module docstring).

    The hierarchy is built here from pyamg's kernels (standard aggregation, Gauss–Seidel sweeps) and
    scipy's sparse products, in CSR throughout, deterministically:

    * strength: classical, θ = 0.7 (relative to each cell's strongest face), so aggregates do not
      straddle constrictions (:func:`_strong_pattern`, vectorised: the pattern of pyamg's
      ``classical_strength_of_connection``);
    * tentative prolongator T: one candidate, B = D^1/2·1 on the finest level (the constant of the
      unscaled matrix), normalised per aggregate; the coarse candidate is the aggregate norm;
    * prolongator P = (I - ω W A) T with ω = 4/3 and W the local Gershgorin weight
      1 / Σ_j |a_ij| of each row (no spectral-radius estimate, which in pyamg is a randomly
      started Arnoldi iteration: its results, and the CG iteration count, varied from run to run);
      R = Pᵀ, A_c = R (A P);
    * coarsening stops at <= 500 unknowns, solved by a sparse LU (SuperLU; digits independent of the
      number of BLAS threads), or with the pseudo-inverse (pinvh) if that matrix is singular;
    * V(1,1) cycle: one forward Gauss–Seidel sweep before, one backward sweep after the coarse
      correction (a symmetric preconditioner, as CG needs); the residual after the forward sweep
      from x = 0 is -U x (U the strictly upper triangle of A), half the work of b - A x.

    Measured on 2048² contact gap fields (10 % and 25 % contact): 17 and 23 CG iterations, against
    21–25 and 33 with pyamg's ``smoothed_aggregation_solver`` at the same θ (Jacobi prolongation
    smoothing with Arnoldi ρ estimates), and a set-up ~30 % shorter.
    """

    THETA = 0.7
    OMEGA = 4.0 / 3.0
    MAX_COARSE = 500
    MAX_LEVELS = 16

    def __init__(self, A: sparse.csr_matrix, max_iter: int) -> None:
        """Build the hierarchy of ``A`` (CSR, float64), which is scaled in place to D^-1/2 A D^-1/2:
        the caller must not use ``A`` afterwards (it is the fine-level matrix, no copy is kept)."""
        self.sq, levels, level_a = _hierarchy(A)
        self.As = A
        # per level: A, its strictly upper triangle U (for the residual after a forward sweep), P, R
        self.levels: list[tuple[sparse.csr_matrix, ...]] = [
            (a, _upper(a, _row_of_entries(a)), p, r) for a, p, r in levels]
        # the coarsest level by a sparse LU: SuperLU's digits do not depend on the number of BLAS threads
        # (LAPACK's eigh behind a pseudo-inverse, and a threaded dgemv, do), so a task gives the same
        # numbers in a one-thread Dask worker as in the plain loop (docs/theory.md §6.7); the
        # pseudo-inverse only if the coarse matrix is singular
        try:
            lu = spla.splu(level_a.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
            self._coarse_solve = lu.solve
        except RuntimeError:  # exactly singular
            inverse = pinvh(level_a.toarray())
            self._coarse_solve = lambda b: np.einsum("ij,j->i", inverse, b)
        self.max_iter = max_iter
        self._gauss_seidel = gauss_seidel

    def _vcycle(self, b: FloatArray, lvl: int = 0, out: FloatArray | None = None) -> FloatArray:
        """One V-cycle for A_lvl x = b from x = 0 (the preconditioner M⁻¹ b), into ``out`` if given
        (a reused buffer: a fresh array of the fine size costs page faults at every cycle)."""
        gauss_seidel = self._gauss_seidel
        if lvl == len(self.levels):
            return self._coarse_solve(b)
        A, U, P, R = self.levels[lvl]
        if out is None:
            x = np.zeros_like(b)
        else:
            x = out
            x.fill(0.0)
        gauss_seidel(A, x, b, sweep="forward")
        # a forward sweep from x = 0 solves (D + L) x = b exactly, so b - A x = -U x (half a matvec)
        x += P @ self._vcycle(-(R @ (U @ x)), lvl + 1)
        gauss_seidel(A, x, b, sweep="backward")
        return x

    def __call__(self, rhs: FloatArray, l1_tol: float, sum_tol: float, flux: _Flux) -> tuple[FloatArray, int]:
        """Solve A x = rhs until ||rhs - A x||_1 <= l1_tol·Q and |Σ(rhs - A x)| <= sum_tol·Q.

        ``flux`` gives the inflow Q of the total solution the correction x belongs to. The
        residual is CG's recursively updated one, in the unscaled variables (cell flux
        imbalances). Near the percolation threshold Q is tiny against the conductances and the
        true residual of x, even computed exactly, lies far above the recursive one (1e-4 against
        5e-7 of Q at 1024², 40 % contact), and in double precision it has a floor near 1e-6 of
        Q; so the caller re-checks the true residual in extended precision and solves for a
        correction (a second pass of 5–7 iterations) when needed.
        """
        sq = self.sq
        bs = rhs / sq
        x = np.zeros_like(bs)
        r = bs.copy()
        zbuf = np.empty_like(r)  # z of each cycle (not needed past the update of pdir)
        z = self._vcycle(r, 0, zbuf)
        pdir = z.copy()
        rz = dot(r, z)
        work = np.empty_like(r)
        sq_in = sq[flux.cells]
        it = 0
        while True:
            np.multiply(r, sq, out=work)  # unscaled residual: net flux out of each cell
            net = abs(float(work.sum()))
            l1 = float(np.abs(work, out=work).sum())
            q = flux(x[flux.cells] / sq_in)
            if _stop(l1, net, q, it, l1_tol, sum_tol, self.max_iter, "amg"):
                return x / sq, it
            it += 1
            Ap = self.As @ pdir
            alpha = rz / dot(pdir, Ap)
            np.multiply(pdir, alpha, out=work)  # x += alpha pdir, r -= alpha Ap without temporaries
            x += work
            np.multiply(Ap, alpha, out=Ap)
            r -= Ap
            del Ap
            z = self._vcycle(r, 0, zbuf)
            rz_new = dot(r, z)
            pdir *= rz_new / rz
            pdir += z
            rz = rz_new


class _Rows:
    """A sparse matrix as padded rows (ELLPACK) in an array namespace: ``vals`` and ``cols`` (m × w), the
    entries of each row in CSR order, then zeros. ``self @ x`` is y_i = Σ_k vals[i,k] x[cols[i,k]]: one gather
    and one sum along the rows, with no atomic additions, so it gives the same bits at every call (cuSPARSE's
    default CSR product on a GPU does not: two runs of the same flow differed at 1e-14).
    """

    def __init__(self, M: sparse.csr_matrix, xp: Any) -> None:
        m = M.shape[0]
        counts = np.diff(M.indptr)
        width = max(int(counts.max()) if m else 1, 1)
        rows = _row_of_entries(M)
        pos = np.arange(M.nnz) - M.indptr[rows]
        vals = np.zeros((m, width))
        cols = np.zeros((m, width), dtype=np.int32 if M.shape[1] < 2**31 else np.int64)  # padding: column 0, value 0
        vals[rows, pos] = M.data
        cols[rows, pos] = M.indices
        self.xp, self.shape, self.width = xp, (m, width), width
        self.vals, self.cols = xp.asarray(vals), xp.asarray(cols.reshape(-1))

    def __matmul__(self, x: Any) -> Any:
        xp = self.xp
        return xp.sum(self.vals * xp.reshape(xp.take(x, self.cols), self.shape), axis=1)


class _CycleSolver:
    """CG on D^-1/2 A D^-1/2 preconditioned by the hierarchy of :func:`_hierarchy` with l1-Jacobi smoothing, in
    the array namespace of a device: CuPy on a GPU; NumPy and array_api_strict in the tests.

    The hierarchy is built on the host, as for :class:`_AmgSolver`, and moved to the device as padded rows
    (:class:`_Rows`, array-API operations only); what runs there are the CG iterations, each a V(k,k) cycle of
    matrix-vector products and elementwise updates: Gauss–Seidel, the host's smoother, is sequential and has
    no fast GPU form. The smoother is the l1-Jacobi sweep x ← x + (b - A x)/Σ_j|a_ij| (Baker, Falgout, Kolev &
    Yang, SIAM J. Sci. Comput. 33 (2011) 2864, which shows it convergent for any symmetric positive definite A
    without a damping factor or a spectral estimate; symmetric, so the cycle
    with ``SWEEPS`` sweeps before and after the coarse correction is a symmetric preconditioner, as CG
    needs). The coarsest level (<= 500 unknowns) is solved with its inverse (the pseudo-inverse if it is
    singular), computed on the host and applied as a dense product. ``preconditioner="jacobi"`` drops the
    hierarchy: CG on the diagonally scaled matrix (no set-up, thousands of iterations; kept for the
    measurement that chose the hierarchy, docs/performance.md#gpu).

    The stopping test is the host's (:meth:`_AmgSolver.__call__`): the l1 norm and the sum of the
    unscaled residual against the inflow of the total solution; the caller checks the result in
    extended precision on the host, as for every back-end. Every operation is elementwise, a gather or a
    reduction, so a run repeats its bits on one machine.
    """

    SWEEPS = 1

    def __init__(self, A: sparse.csr_matrix, max_iter: int, xp: Any,
                 preconditioner: Literal["amg", "jacobi"] = "amg") -> None:
        """``A`` is scaled in place (as for :class:`_AmgSolver`); ``xp`` is the device's array namespace."""
        self.xp = xp
        if preconditioner == "amg":
            sq, levels, coarse = _hierarchy(A)
        else:
            sq, levels, coarse = _scaled(A, _row_of_entries(A)), [], None
        self.sq = xp.asarray(sq)
        self.As = _Rows(A, xp)
        self.levels = [(self.As if k == 0 else _Rows(a, xp), _Rows(p, xp), _Rows(r, xp), xp.asarray(_l1_weight(a)))
                       for k, (a, p, r) in enumerate(levels)]
        self.coarse = None if coarse is None else xp.asarray(_coarse_inverse(coarse))
        self.max_iter = max_iter

    def _cycle(self, b: Any, lvl: int = 0) -> Any:
        """One V(k,k) cycle for A_lvl x = b from x = 0 (the preconditioner M⁻¹ b); b itself without a hierarchy."""
        if self.coarse is None:
            return b
        if lvl == len(self.levels):
            return self.coarse @ b
        A, P, R, w = self.levels[lvl]
        x = w * b
        for _ in range(self.SWEEPS - 1):
            x = x + w * (b - A @ x)
        x = x + P @ self._cycle(R @ (b - A @ x), lvl + 1)
        for _ in range(self.SWEEPS):
            x = x + w * (b - A @ x)
        return x

    def __call__(self, rhs: FloatArray, l1_tol: float, sum_tol: float, flux: _Flux) -> tuple[FloatArray, int]:
        """Solve A x = rhs until ||rhs - A x||_1 <= l1_tol·Q and |Σ(rhs - A x)| <= sum_tol·Q (as
        :meth:`_AmgSolver.__call__`); ``rhs`` and the returned correction are host arrays."""
        xp, sq = self.xp, self.sq
        cells = xp.asarray(flux.cells)
        inflow_w, base, sq_in = xp.asarray(flux.weights), xp.asarray(flux.base), xp.take(sq, cells)
        r = xp.asarray(rhs) / sq
        x = xp.zeros_like(r)
        z = self._cycle(r)
        pdir = z
        rz = float(xp.sum(r * z))
        it = 0
        while True:
            unscaled = r * sq  # net flux out of each cell
            net = abs(float(xp.sum(unscaled)))
            l1 = float(xp.sum(xp.abs(unscaled)))
            q = float(xp.sum(inflow_w * (1.0 - base - xp.take(x, cells) / sq_in)))
            if _stop(l1, net, q, it, l1_tol, sum_tol, self.max_iter, "amg, on the device"):
                return to_numpy(x / sq), it
            it += 1
            Ap = self.As @ pdir
            alpha = rz / float(xp.sum(pdir * Ap))
            x = x + alpha * pdir
            r = r - alpha * Ap
            z = self._cycle(r)
            rz_new = float(xp.sum(r * z))
            pdir = z + (rz_new / rz) * pdir
            rz = rz_new


def _scaled(A: sparse.csr_matrix, rows: NDArray[np.intp]) -> FloatArray:
    """Scale ``A`` in place to D^-1/2 A D^-1/2 and return √diag(A) (``rows``: :func:`_row_of_entries`)."""
    sq = np.sqrt(A.diagonal())
    inv = 1.0 / sq
    A.data *= inv[rows]  # (a_ij / √d_i) / √d_j: the digits of Dm @ A @ Dm; unit diagonal
    A.data *= inv[A.indices]
    return sq


def _l1_weight(A: sparse.csr_matrix) -> FloatArray:
    """1 / Σ_j |a_ij| of each row: the l1-Jacobi smoother's weights."""
    return 1.0 / np.bincount(_row_of_entries(A), weights=np.abs(A.data), minlength=A.shape[0])


def _coarse_inverse(A: sparse.csr_matrix) -> FloatArray:
    """The inverse of the (small) coarsest matrix, or its pseudo-inverse if it is singular."""
    dense = A.toarray()
    try:
        return np.asarray(np.linalg.inv(dense))
    except np.linalg.LinAlgError:
        return np.asarray(pinvh(dense))


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
    device: str = "cpu",
) -> FlowResult:
    """Leak flow through an N×N gap field from the inlet edge x = 0 to the outlet edge x = L.

    Solves the Reynolds equation ∇·(σ ∇p) = 0, σ = g³/(12η), by finite volumes, with a rigorous
    bound on the flux error (docs/theory.md §6.3, eqs. 6.4, 6.5; Patir & Cheng, J. Lubr. Technol. 100 (1978) 12).

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
    device:
        Where the AMG back-end's CG iterations run: ``"cpu"`` (default), or ``"cuda"``, an NVIDIA GPU
        through CuPy (:class:`_CycleSolver`: the same hierarchy, built on the host, cycled on the GPU with
        l1-Jacobi instead of Gauss–Seidel smoothing; within ``rtol`` of the CPU's flux, as every result).
        The direct back-end, the clusters, the assembly and the extended-precision check run on the host
        either way. Without CuPy or a GPU, an InputError; too little free GPU memory, a ResourceError.

    Returns
    -------
    FlowResult
        ``flux`` is Q = (conductance of the square) × ΔP in m³/s.
    """
    t0 = time.perf_counter()
    clock: dict[str, float] = {}
    g = _validate(gap, size, viscosity, pressure_difference)
    check_device(device)
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
        return _result(0.0, 0.0, 0.0, pressure, False, "none", 0.0, 0.0, 0, 0, t0, 0.0, {})
    chosen = method if method != "auto" else ("direct" if m <= AUTO_DIRECT_MAX_UNKNOWNS else "amg")
    require_memory(flow_memory_bytes(n, chosen), f"the {n}x{n} flow problem ({chosen})", memory_limit)
    on_device = chosen == "amg" and device != "cpu"
    if on_device:
        require_device_memory(flow_memory_bytes(n, "amg"), f"the {n}x{n} flow problem (amg)", device)
    clock["clusters"] = time.perf_counter() - t0
    t = time.perf_counter()
    cx, cy, sf = _faces(s, fluid)
    del s
    A, b_in, _b_out = _assemble(cx, cy, sf, fluid)
    grid = _Grid(cx, cy, sf, fluid)
    del cx, cy, sf, _b_out
    clock["assembly"] = time.perf_counter() - t
    t = time.perf_counter()
    solver = _back_end(A, chosen, max_iter, device)
    del A
    clock["setup"] = time.perf_counter() - t
    phi = np.zeros(g.shape, dtype=np.longdouble)
    its, (r, inflow, outflow, res, bound, cons) = _refine(solver, grid, phi, b_in, rtol, clock, rhs=b_in)
    if not (np.isfinite(phi[fluid]).all() and bound <= rtol and cons <= CONSERVATION_TOL and inflow > 0):
        raise SolutionCheckError(
            f"flow solution ({chosen}, {m} unknowns) failed its check: flux-error bound ||r||_1/Q = "
            f"{bound:.3g} (allowed {rtol:.3g}), |inflow - outflow|/Q = {cons:.3g} (allowed {CONSERVATION_TOL:.0e})"
            f"; estimate |φᵀr|/Q = {res:.3g}")
    del r, grid, solver
    unit = gmax**3 / (12.0 * viscosity) * pressure_difference  # m³/s per unit dimensionless flux
    pressure[fluid] = outlet_pressure + pressure_difference * phi[fluid].astype(np.float64)
    cond = inflow * gmax**3 / (12.0 * viscosity)
    return _result(inflow * unit, inflow * unit, outflow * unit, pressure, True, chosen, bound, cons, its, m, t0, cond,
                   clock, device if on_device else "cpu")


def _back_end(A: sparse.csr_matrix, chosen: str, max_iter: int, device: str) -> _DirectSolver | _AmgSolver | _CycleSolver:
    """The solver of ``chosen`` ("direct" or "amg") for ``A`` (consumed); the AMG one on ``device`` (:class:`_CycleSolver`
    unless it is "cpu")."""
    if chosen == "direct":
        return _DirectSolver(A)
    if device != "cpu":
        return _CycleSolver(A, max_iter, _device_arrays(device), preconditioner=DEVICE_PRECONDITIONER)
    return _AmgSolver(A, max_iter)


def _device_arrays(device: str) -> Any:
    """The array namespace of ``device`` (array-api-compat's CuPy for ``"cuda"``)."""
    return array_namespace_for(device)


def _refine(solver: _DirectSolver | _AmgSolver | _CycleSolver, grid: _Grid, phi: NDArray[np.longdouble], b_in: FloatArray,
            rtol: float, clock: dict[str, float], rhs: FloatArray | None = None
            ) -> tuple[int, tuple[FloatArray, float, float, float, float, float]]:
    """Mixed-precision iterative refinement (docs/theory.md §6.3), shared by the liquid and the gas solver.

    φ (long double, ``phi``, updated in place) and the residual b - A φ (extended precision,
    :meth:`_Grid.residual`) against corrections in double precision from the back-end, until the
    flux-error bound ||r||_1/Q <= ``rtol`` and the conservation error <= ``CONSERVATION_TOL`` hold, at
    most 8 corrections. ``rhs``: the residual of the starting φ when it is known (b for φ = 0),
    else it is computed first. Adds the seconds of the back-end's iterations and of the checks to
    ``clock`` ("iterations", "check"). Returns the iterations (CG, or 0 per direct solve) and the
    last :func:`_checks`; the caller judges them.
    """
    fluid = grid.fluid
    inlet = np.flatnonzero(b_in)
    w_in = b_in[inlet]
    its = 0
    clock.setdefault("iterations", 0.0)
    clock.setdefault("check", 0.0)
    checks = None
    if rhs is None:
        t = time.perf_counter()
        checks = _checks(grid, phi)
        clock["check"] += time.perf_counter() - t
    for _ in range(8):
        if checks is not None:
            r, _qin, _qout, _res, bound, cons = checks
            if bound <= rtol and cons <= CONSERVATION_TOL:
                break
            rhs = r[fluid]
            del r, checks
        assert rhs is not None  # given, or the residual of the last check
        t = time.perf_counter()
        flux = _Flux(inlet, w_in, phi[fluid][inlet].astype(np.float64))
        delta, k = solver(rhs, 0.5 * rtol, 0.1 * CONSERVATION_TOL, flux)
        its += k
        phi[fluid] += delta.astype(np.longdouble)
        del delta
        clock["iterations"] += time.perf_counter() - t
        t = time.perf_counter()
        checks = _checks(grid, phi)
        clock["check"] += time.perf_counter() - t
    assert checks is not None
    return its, checks


def _result(q: float, qin: float, qout: float, pressure: FloatArray, perc: bool, method: str, res: float,
            cons: float, its: int, m: int, t0: float, cond: float, clock: dict[str, float],
            device: str = "cpu") -> FlowResult:
    return FlowResult(flux=q, inflow=qin, outflow=qout, pressure=pressure, percolates=perc, method=method,
                      residual=res, conservation_error=cons, iterations=its, unknowns=m,
                      seconds=time.perf_counter() - t0, conductance=cond,
                      phase_seconds=dict(clock), device=device)
