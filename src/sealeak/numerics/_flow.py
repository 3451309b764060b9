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
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import sparse

from ..errors import InputError, SolutionCheckError, positive_values
from ._amg import _AmgSolver, _back_end, _CycleSolver, _DirectSolver, _Flux
from ._device import check_device, require_device_memory
from ._memory import require_memory
from ._percolation import spanning_mask

FloatArray = NDArray[np.float64]
Method = Literal["auto", "direct", "amg"]

AUTO_DIRECT_MAX_UNKNOWNS = 250_000
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
        either way. When the AMG back-end is chosen: without CuPy or a GPU, an InputError; too little free GPU
        memory, a ResourceError (a direct solve needs neither).

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
