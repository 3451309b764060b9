"""The linear back-ends of the Reynolds flow solver (private): sparse LU, and CG preconditioned by a smoothed-aggregation
AMG hierarchy, on the CPU (Gauss–Seidel cycles) or on a device (l1-Jacobi cycles in its array namespace).

Each back-end solves A x = rhs for the caller's refinement loop (:func:`sealeak.numerics._flow._refine`), which
checks every result in extended precision; docs/theory.md §6.3, docs/architecture.md (contact and flow solvers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray
from pyamg.aggregation import standard_aggregation
from pyamg.relaxation.relaxation import gauss_seidel
from scipy import sparse
from scipy.linalg import pinvh
from scipy.sparse import linalg as spla

from ..errors import ConvergenceError
from ._device import array_namespace_for
from ._linalg import dot
from ._xp import to_numpy

FloatArray = NDArray[np.float64]

#: The preconditioner of the AMG back-end's CG on a device (:class:`_CycleSolver`); "jacobi" is there to be measured.
DEVICE_PRECONDITIONER: Literal["amg", "jacobi"] = "amg"


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
        lu = _coarse_lu(level_a)
        if lu is not None:
            self._coarse_solve = lu.solve
        else:  # exactly singular
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
    singular), computed on the host by SuperLU one column at a time and applied as products and row sums (no
    BLAS call, whose digits would follow its number of threads). ``preconditioner="jacobi"`` drops the
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
            return self.xp.sum(self.coarse * b, axis=1)  # not a BLAS product, whose digits follow its threads
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


def _coarse_lu(A: sparse.csr_matrix) -> Any:
    """SuperLU of the (small) coarsest matrix, whose digits do not depend on the number of BLAS threads; None if it is
    exactly singular."""
    try:
        return spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    except RuntimeError:
        return None


def _coarse_inverse(A: sparse.csr_matrix) -> FloatArray:
    """The inverse of the (small) coarsest matrix, by its SuperLU (as the CPU's cycles solve it, so a device run's
    digits do not depend on the BLAS threads either) and symmetrised; its pseudo-inverse if it is singular."""
    lu = _coarse_lu(A)
    if lu is None:
        return np.asarray(pinvh(A.toarray()))
    unit = np.eye(A.shape[0])
    # one column at a time: a solve of the whole identity calls a matrix product whose digits follow the BLAS threads
    inverse = np.stack([lu.solve(unit[k]) for k in range(A.shape[0])], axis=1)
    return np.asarray(0.5 * (inverse + inverse.T))


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
