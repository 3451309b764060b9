"""Checks of the Reynolds flow solver against answers derived independently."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erfinv

from sealeak.errors import ConvergenceError, InputError, ResourceError, SolutionCheckError
from sealeak.numerics import check_memory, solve_contact, solve_flow
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.spectrum import PowerSpectrum

ETA, DP = 1.0e-3, 1.0e4


@pytest.mark.parametrize("method", ["direct", "amg"])
def test_parallel_plates_exact(method: str) -> None:
    n, L, g = 24, 2e-3, 3e-6
    res = solve_flow(np.full((n, n), g), L, ETA, DP, method=method)
    exact = g**3 * L * DP / (12 * ETA * L)  # W = L
    # (abs=0: pytest.approx's default absolute tolerance of 1e-12 exceeds Q ~ 2e-11 m³/s itself)
    assert res.flux == pytest.approx(exact, rel=1e-12, abs=0)
    # the outflow, summed independently at the outlet: exact for the direct solve, within the conservation
    # tolerance (1e-8) for AMG's iterate (4e-11 here)
    assert res.outflow == pytest.approx(exact, rel=1e-12 if method == "direct" else 1e-8, abs=0)
    assert res.method == method and res.percolates
    # linear pressure: p = ΔP (1 - x/L) at cell centres x = (i + 1/2) L/n
    x = (np.arange(n) + 0.5) / n
    assert np.allclose(res.pressure[:, 3], DP * (1 - x), rtol=1e-12, atol=1e-9 * DP)


def test_series_gap_varying_along_flow() -> None:
    """g = g(x): every row is a chain of resistances 1/σ_i, Q = (W/L) ΔP / mean_x(1/σ)."""
    n, L = 40, 1e-3
    gx = 1e-6 * (1.5 + np.sin(2 * np.pi * np.arange(n) / n) + 0.3 * np.cos(6 * np.pi * np.arange(n) / n))
    sigma = gx**3 / (12 * ETA)
    exact = DP / np.mean(1.0 / sigma)
    res = solve_flow(np.repeat(gx[:, None], n, axis=1), L, ETA, DP, method="direct")
    # (abs=0: Q ~ 2.5e-13 m³/s is below pytest.approx's default absolute tolerance; σ spans 3 decades along the
    # chain, so the direct solve's round-off reaches ~2e-12)
    assert res.flux == pytest.approx(exact, rel=1e-10, abs=0)


def _lognormal_field(n: int, seed: int) -> np.ndarray:
    L = 1.0
    q0 = 2 * np.pi / L
    spec = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=6 * q0, q_cutoff=40 * q0, q_lowest=q0, h_rms=1.0)
    return synthesize(spec, n, L, seed=seed)  # log σ, variance 1


def test_matheron_lognormal_geometric_mean() -> None:
    """2D isotropic log-normal σ: σ_eff = exp(<log σ>) (Matheron 1967), within 3 % at 512²."""
    n = 512
    f = _lognormal_field(n, seed=11)
    assert float(f.std()) == pytest.approx(1.0, rel=0.2)
    gap = np.exp(f / 3.0)  # σ = g³/(12η) = exp(f) with η = 1/12
    geo = math.exp(float(f.mean()))
    sx = solve_flow(gap, 1.0, 1.0 / 12.0, 1.0).flux  # W = L: σ_eff = Q/ΔP
    sy = solve_flow(np.ascontiguousarray(gap.T), 1.0, 1.0 / 12.0, 1.0).flux
    assert math.sqrt(sx * sy) == pytest.approx(geo, rel=0.03)
    # the arithmetic and harmonic means differ from the geometric mean by e^{±1/2}: the test can fail
    assert abs(math.log(math.sqrt(sx * sy) / float(np.exp(f).mean()))) > 0.3


def _near_threshold_contact(n: int = 512, tol: float = 1e-8):
    L, e_star = 1e-3, 1e6
    q0 = 2 * np.pi / L
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * q0, q_cutoff=n / 16 * q0, q_lowest=q0, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=1)
    p0 = 2 * math.sqrt(e_star**2 * sp.slope_rms**2 / 8) * erfinv(0.4) * 0.8
    return solve_contact(h, L, e_star, p0, tol=tol), L


@pytest.fixture(scope="module")
def hard_field():
    return _near_threshold_contact()


def test_direct_and_amg_agree_near_threshold(hard_field) -> None:
    res, L = hard_field
    assert 0.35 < res.contact_area < 0.45
    d = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="direct")
    a = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg")
    assert d.percolates and a.percolates
    for r in (d, a):
        assert r.conservation_error <= 1e-8
        assert abs(r.inflow - r.outflow) <= 1e-8 * r.inflow
        assert r.residual <= 1e-6
    # each residual is a rigorous bound on its relative flux error
    assert abs(a.flux - d.flux) <= (a.residual + d.residual) * d.flux
    assert a.flux == pytest.approx(d.flux, rel=1e-6, abs=0)
    # the flux is far below the parallel-plate value of the mean gap: a constricted, hard case
    assert d.flux < 0.1 * res.mean_gap**3 * DP / (12 * ETA)


def test_amg_is_deterministic(hard_field) -> None:
    """The AMG set-up uses no random numbers: the same field gives the same digits, whatever the RNG state."""
    res, L = hard_field
    np.random.seed(1)
    a = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg")
    np.random.seed(2)
    b = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg")
    assert a.flux == b.flux and a.iterations == b.iterations and a.residual == b.residual


def test_contact_tolerance_barely_changes_the_leak_rate(hard_field) -> None:
    res, L = hard_field
    tight, _ = _near_threshold_contact(tol=1e-9)
    q1 = solve_flow(res.gap, L, ETA, DP, contact=res.contact).flux
    q2 = solve_flow(tight.gap, L, ETA, DP, contact=tight.contact).flux
    assert tight.residual <= 1e-9 < res.residual or tight.iterations > res.iterations
    assert q2 == pytest.approx(q1, rel=1e-5, abs=0)  # measured: 1.1e-8


def test_contact_mask_not_gap_zero() -> None:
    """Contact cells keep ~1e-12 gaps; with the mask they carry nothing."""
    n, L = 16, 1e-3
    g = np.full((n, n), 2e-6)
    mask = np.zeros((n, n), dtype=bool)
    mask[:, 5] = True
    mask[3:, 5] = True
    mask[4, :] = True
    mask[4, 9] = False  # one opening in a wall across the flow
    g[mask] = 1e-12
    with_mask = solve_flow(g, L, ETA, DP, contact=mask, method="direct")
    g0 = g.copy()
    g0[mask] = 0.0
    by_gap = solve_flow(g0, L, ETA, DP, method="direct")
    assert with_mask.flux == pytest.approx(by_gap.flux, rel=1e-12, abs=0)
    assert np.isnan(with_mask.pressure[mask]).all()
    ignoring_mask = solve_flow(g, L, ETA, DP, method="direct")  # 1e-12 gaps would leak a little
    assert ignoring_mask.flux > with_mask.flux


def test_dead_ends_and_islands_removed_and_no_spanning_gives_zero() -> None:
    n, L = 12, 1e-3
    g = np.full((n, n), 1e-6)
    contact = np.zeros((n, n), dtype=bool)
    contact[:, 4] = True  # two closed columns along x (periodic in y): lanes 0-3 and 5-10
    contact[:, 11] = True
    contact[6, :] = True  # a wall across both lanes
    lane = solve_flow(g, L, ETA, DP, contact=contact, method="direct")
    assert not lane.percolates and lane.flux == 0.0 and lane.method == "none"
    assert np.isnan(lane.pressure).all()
    contact[6, 2] = False  # open one cell: lane 1 (columns 0-3) now spans, lane 2 is dead
    open1 = solve_flow(g, L, ETA, DP, contact=contact, method="direct")
    assert open1.percolates and open1.flux > 0
    assert np.isnan(open1.pressure[:, 4:]).all() and np.isfinite(open1.pressure[:, :4][~contact[:, :4]]).all()
    assert open1.unknowns == 4 * n - 3


def test_failed_checks_raise_never_return() -> None:
    n, L = 64, 1.0
    gap = np.exp(_lognormal_field(n, seed=2)[:64, :64] / 3)
    with pytest.raises(SolutionCheckError, match="failed its check"):
        solve_flow(gap, L, ETA, DP, method="direct", rtol=1e-300)
    with pytest.raises(ConvergenceError, match="CG iterations"):
        solve_flow(gap, L, ETA, DP, method="amg", max_iter=1)
    with pytest.raises(InputError, match="method"):
        solve_flow(gap, L, ETA, DP, method="cholesky")  # type: ignore[arg-type]
    with pytest.raises(ResourceError, match="GiB"):
        solve_flow(gap, L, ETA, DP, memory_limit=1000)
    with pytest.raises(ResourceError, match="GiB"):
        check_memory(1 << 17, "flow")
    auto = solve_flow(gap, L, ETA, DP)
    assert auto.method == "direct"


def test_grid_refinement_of_the_leak_rate() -> None:
    """Same band-limited surface sampled at N and 2N (exact subsampling): leak rates within 5 %."""
    L, e_star = 1e-3, 1e6
    q0 = 2 * np.pi / L
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * q0, q_cutoff=12 * q0, q_lowest=q0, h_rms=1e-6)
    fine = synthesize(sp, 256, L, seed=5)
    coarse = fine[::2, ::2]  # the same continuous surface: all modes are below the coarse Nyquist
    p0 = 0.08 * e_star * sp.slope_rms
    out = []
    for h in (coarse, fine):
        c = solve_contact(h, L, e_star, p0)
        out.append((c.contact_area, solve_flow(c.gap, L, ETA, DP, contact=c.contact).flux))
    # measured: contact area 0.188 -> 0.182, leak rate +2.0 %
    assert out[1][0] == pytest.approx(out[0][0], rel=0.05)
    assert out[1][1] == pytest.approx(out[0][1], rel=0.05, abs=0)


@pytest.mark.parametrize("shape", [(5, 1), (5, 2), (4, 3), (6, 7)])
def test_matrix_against_a_loop_assembly(shape) -> None:
    """The vectorised finite-volume matrix equals one assembled face by face with plain loops."""
    from sealeak.numerics._flow import _assemble, _faces

    rng = np.random.default_rng(sum(shape))
    n0, n1 = shape
    s = rng.uniform(0.1, 1.0, shape)
    fluid = rng.uniform(size=shape) < 0.8
    cx, cy, sf = _faces(s, fluid)
    A, b_in, b_out = _assemble(cx, cy, sf, fluid)
    cells = [(i, j) for i in range(n0) for j in range(n1) if fluid[i, j]]
    number = {c: k for k, c in enumerate(cells)}
    ref = np.zeros((len(cells), len(cells)))
    ref_in, ref_out = np.zeros(len(cells)), np.zeros(len(cells))
    for (i, j), k in number.items():
        neighbours = [(i + 1, j)] + ([(i, (j + 1) % n1)] if n1 > 1 else [])
        for nb in neighbours:
            if nb in number:
                c = 2 * s[i, j] * s[nb] / (s[i, j] + s[nb])  # harmonic mean of the two half cells
                ref[k, k] += c
                ref[number[nb], number[nb]] += c
                ref[k, number[nb]] -= c
                ref[number[nb], k] -= c
        if i == 0:
            ref_in[k] = 2 * s[i, j]
        if i == n0 - 1:
            ref_out[k] = 2 * s[i, j]
    ref += np.diag(ref_in + ref_out)
    assert np.allclose(A.toarray(), ref, rtol=1e-14, atol=0)
    assert np.array_equal(b_in, ref_in) and np.array_equal(b_out, ref_out)


@pytest.mark.parametrize("shape", [(1, 5), (5, 1), (7, 6), (9, 4)])
def test_blockwise_residual_equals_the_whole_grid_formula(shape, monkeypatch) -> None:
    """The extended-precision residual formed in blocks of rows (here 2 or 3 rows, so blocks meet
    everywhere) equals, digit for digit, b - A φ written out on the whole grid in long double, and
    the flux sums match; it also equals b - A φ from the sparse matrix to double precision."""
    from sealeak.numerics import _flow

    rng = np.random.default_rng(shape[0] * 10 + shape[1])
    s = rng.uniform(0.1, 1.0, shape)
    fluid = rng.uniform(size=shape) < 0.85
    cx, cy, sf = _flow._faces(s, fluid)
    phi = np.where(fluid, rng.uniform(size=shape), 0.0).astype(np.longdouble)
    ld = np.longdouble
    fx = cx.astype(ld) * (phi[:-1, :] - phi[1:, :])
    fy = cy.astype(ld) * (phi - np.roll(phi, -1, axis=1))
    ref = np.zeros_like(phi)
    ref[:-1, :] -= fx
    ref[1:, :] += fx
    ref -= fy
    ref += np.roll(fy, 1, axis=1)
    qin = (2.0 * sf[0, :]).astype(ld) * (1.0 - phi[0, :])
    qout = (2.0 * sf[-1, :]).astype(ld) * phi[-1, :]
    ref[0, :] += qin
    ref[-1, :] -= qout
    ref[~fluid] = 0.0
    A, b_in, _ = _flow._assemble(cx, cy, sf, fluid)
    for rows in (2, 3):
        monkeypatch.setattr(_flow._Grid, "ROWS_PER_BLOCK", rows)
        r, q_in, q_out, l1, phir, net = _flow._Grid(cx, cy, sf, fluid).residual(phi)
        assert np.array_equal(r, ref.astype(np.float64))
        assert q_in == float(qin.sum()) and q_out == float(qout.sum())
        assert l1 == pytest.approx(float(np.abs(ref).sum()), rel=1e-15, abs=0)
        assert phir == pytest.approx(abs(float((phi * ref).sum())), rel=1e-12, abs=1e-300)
        assert net == pytest.approx(float(ref.sum()), rel=1e-12, abs=1e-15)
        sparse_r = b_in - A @ phi[fluid].astype(np.float64)
        assert np.allclose(r[fluid], sparse_r, rtol=0, atol=1e-14)


def test_strength_pattern_equals_pyamg_classical_strength(hard_field) -> None:
    """The vectorised strength of connection gives, on the fine level and on a coarse level of a
    contact gap field near the percolation threshold, exactly the pattern of pyamg's classical
    strength of connection (θ = 0.7), so the aggregates are the same."""
    from pyamg.strength import classical_strength_of_connection

    from sealeak.numerics import _amg, _flow
    from sealeak.numerics._percolation import spanning_mask

    c, _L = hard_field
    g = np.where(c.contact, 0.0, c.gap) / c.gap.max()
    fluid = spanning_mask(g > 0)
    A, _, _ = _flow._assemble(*_flow._faces(g**3, fluid), fluid)
    solver = _amg._AmgSolver(A, 10)
    assert len(solver.levels) >= 3
    for level in (solver.levels[0][0], solver.levels[2][0]):
        ours = _amg._strong_pattern(level, _amg._row_of_entries(level), _amg._AmgSolver.THETA)
        theirs = classical_strength_of_connection(level, theta=_amg._AmgSolver.THETA)
        assert np.array_equal(ours.indptr, theirs.indptr) and np.array_equal(ours.indices, theirs.indices)


def test_phase_times_add_up_to_the_wall_time() -> None:
    gap = np.exp(_lognormal_field(64, seed=3) / 3)
    res = solve_flow(gap, 1.0, ETA, DP, method="amg")
    assert set(res.phase_seconds) == {"clusters", "assembly", "setup", "iterations", "check"}
    assert all(v >= 0 for v in res.phase_seconds.values())
    assert sum(res.phase_seconds.values()) <= res.seconds


def test_memory_estimate_bounds_the_measured_peak_and_blas_threads_change_no_digit() -> None:
    """flow_memory_bytes (AMG) is above the peak resident set the solve adds, measured in a fresh process
    (ru_maxrss after the solve minus before it) on a 512² log-normal conductance field; and the AMG
    solution has the same digits with one BLAS thread (as in a Dask worker) and with two (the plain loop)."""
    import json
    import os
    import subprocess
    import sys

    code = (
        "import json, resource, numpy as np\n"
        "from sealeak.numerics import solve_flow, flow_memory_bytes\n"
        "from sealeak.numerics.synthesis import synthesize\n"
        "from sealeak.physics.spectrum import PowerSpectrum\n"
        "q0 = 2 * np.pi\n"
        "spec = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=6 * q0, q_cutoff=40 * q0, q_lowest=q0, h_rms=1.0)\n"
        "gap = np.exp(synthesize(spec, 512, 1.0, seed=4) / 3)\n"
        "gap[synthesize(spec, 512, 1.0, seed=5) > 1.2] = 0.0\n"
        "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024\n"
        "res = solve_flow(gap, 1.0, 1e-3, 1e4, method='amg')\n"
        "after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024\n"
        "print(json.dumps([after - before, flow_memory_bytes(512, 'amg'), res.unknowns, res.flux.hex(),\n"
        "                  float(np.nansum(res.pressure)).hex()]))\n"
    )
    runs = []
    for threads in ("1", "2"):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS=threads, MKL_NUM_THREADS=threads)
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    used, estimate, unknowns, _flux, _psum = runs[0]
    assert unknowns > 0.5 * 512**2
    assert used < estimate
    assert runs[0][2:] == runs[1][2:]
