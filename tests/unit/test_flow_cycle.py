"""The flow's device back-end (``solve_flow(device="cuda")``: the AMG hierarchy cycled with l1-Jacobi smoothing in
a device's array namespace), run here on NumPy and on the strict array-API namespace so that CI, which has no GPU,
covers its code.

On a GPU the same code runs on CuPy (tests/unit/test_gpu.py, skipped without one).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy import sparse
from scipy.special import erfinv

from sealeak.errors import ConvergenceError, InputError
from sealeak.numerics import _amg, _flow, solve_contact, solve_flow, solve_gas_flow
from sealeak.numerics._xp import namespace
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.gas import Gas
from sealeak.physics.spectrum import PowerSpectrum

ETA, DP, L = 1e-3, 1e5, 1e-3


@pytest.fixture(params=["numpy", "array_api_strict"])
def host_device(request, monkeypatch):
    """``device="cuda"`` runs the device back-end on NumPy or array_api_strict (no GPU, no memory check)."""
    xp = namespace(np.empty(0)) if request.param == "numpy" else pytest.importorskip("array_api_strict")
    monkeypatch.setattr(_amg, "_device_arrays", lambda device: xp)
    monkeypatch.setattr(_flow, "require_device_memory", lambda *a, **k: None)


def _contact(n: int, fraction: float):
    q0 = 2 * np.pi / L
    sp = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=4 * q0, q_cutoff=n / 16 * q0, q_lowest=q0, h_rms=1e-6)
    h = synthesize(sp, n, L, seed=3)
    return solve_contact(h, L, 1e6, 2 * math.sqrt(1e12 * sp.slope_rms**2 / 8) * erfinv(fraction) * 0.8, tol=1e-8)


@pytest.fixture(scope="module")
def fields():
    return {f: _contact(256, f) for f in (0.1, 0.4)}


@pytest.mark.parametrize("fraction", [0.1, 0.4])
def test_device_back_end_gives_the_direct_flux_within_the_bounds(fields, fraction, host_device):
    res = fields[fraction]
    d = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="direct")
    c = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg", device="cuda")
    assert d.percolates and c.percolates and c.device == "cuda" and d.device == "cpu"
    assert c.residual <= 1e-6 and c.conservation_error <= 1e-8
    # each residual bounds its relative flux error: the two fluxes lie within the sum of the bounds
    assert abs(c.flux - d.flux) <= (c.residual + d.residual) * d.flux
    # the hierarchy does the work: CG on the scaled matrix alone needs thousands of iterations here
    assert 5 <= c.iterations <= 40


def test_a_gas_flow_runs_its_linear_solves_on_the_device_and_agrees(fields, host_device):
    res = fields[0.1]
    helium = Gas("helium", 293.15, 19.6e-6, 4.0026e-3)
    args = (res.gap, L, helium, 2e5, 1e5)
    cpu = solve_gas_flow(*args, contact=res.contact, method="amg")
    dev = solve_gas_flow(*args, contact=res.contact, method="amg", device="cuda")
    assert cpu.device == "cpu" and dev.device == "cuda" and dev.iterations > 1  # the slip fixed point ran there
    # each is within the fixed point's tolerance (1e-6) of the exact slip flow of this field
    assert dev.mass_flow == pytest.approx(cpu.mass_flow, rel=2e-6, abs=0)
    assert dev.throughput_no_slip == pytest.approx(cpu.throughput_no_slip, rel=2e-7, abs=0)


def test_jacobi_alone_converges_but_needs_far_more_iterations(fields, host_device, monkeypatch):
    res = fields[0.1]
    amg = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg", device="cuda")
    monkeypatch.setattr(_amg, "DEVICE_PRECONDITIONER", "jacobi")
    jac = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg", device="cuda", max_iter=20000)
    assert jac.flux == pytest.approx(amg.flux, rel=2e-6, abs=0)
    assert jac.iterations > 20 * amg.iterations
    with pytest.raises(ConvergenceError, match="on the device"):
        solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="amg", device="cuda", max_iter=50)


def test_the_cycle_is_a_symmetric_positive_definite_preconditioner(fields):
    """CG needs M⁻¹ symmetric positive definite: xᵀ M⁻¹ y = yᵀ M⁻¹ x and xᵀ M⁻¹ x > 0 for random x, y."""
    res = fields[0.4]
    s = np.where(res.contact, 0.0, (res.gap / res.gap.max()) ** 3)
    fluid = _flow.spanning_mask(s > 0)
    A, _b, _ = _flow._assemble(*_flow._faces(s, fluid), fluid)
    solver = _amg._CycleSolver(A, 100, namespace(np.empty(0)))
    assert len(solver.levels) >= 2
    rng = np.random.default_rng(0)
    for sweeps in (1, 2):
        solver.SWEEPS = sweeps
        x, y = rng.standard_normal((2, A.shape[0]))
        mx, my = solver._cycle(x), solver._cycle(y)
        assert x @ my == pytest.approx(y @ mx, rel=1e-10)
        assert x @ mx > 0


def test_padded_rows_multiply_as_the_csr_matrix():
    rng = np.random.default_rng(3)
    M = sparse.random(300, 200, density=0.03, random_state=4, format="lil")
    M[5, :] = 0.0  # an empty row
    M = M.tocsr()
    M.eliminate_zeros()
    rows = _amg._Rows(M, namespace(np.empty(0)))
    x = rng.standard_normal(200)
    assert rows.width == np.diff(M.indptr).max()
    assert np.allclose(rows @ x, M @ x, rtol=1e-14, atol=1e-14) and (rows @ x)[5] == 0.0


def test_direct_stays_on_the_host_and_a_small_field_needs_no_gpu(fields, monkeypatch):
    res = fields[0.1]
    monkeypatch.setattr(_amg, "_device_arrays", lambda device: pytest.fail("the direct back-end touched the device"))
    monkeypatch.setattr(_flow, "require_device_memory", lambda *a, **k: pytest.fail("a device memory check"))
    d = solve_flow(res.gap, L, ETA, DP, contact=res.contact, method="direct", device="cuda")
    assert d.device == "cpu" and d.method == "direct"


def test_an_unknown_device_is_refused_before_any_work():
    with pytest.raises(InputError, match="device"):
        solve_flow(np.ones((4, 4)), L, ETA, DP, device="tpu")


def test_the_device_path_gives_the_same_digits_with_one_and_two_blas_threads(tmp_path):
    """As the CPU path (test_numerics_flow.py): a one-thread Dask worker and the plain loop give the same bits."""
    code = (
        "import numpy as np; from sealeak.numerics import _amg, solve_flow; from sealeak.numerics import _flow; "
        "from sealeak.numerics._xp import namespace; "
        "_amg._device_arrays = lambda d: namespace(np.empty(0)); _flow.require_device_memory = lambda *a, **k: None; "
        f"z = np.load({str(tmp_path / 'f.npz')!r}); "
        "r = solve_flow(z['gap'], 1e-3, 1e-3, 1e5, contact=z['contact'], method='amg', device='cuda'); "
        "print(r.flux.hex(), r.iterations)")
    res = _contact(256, 0.3)
    np.savez(tmp_path / "f.npz", gap=res.gap, contact=res.contact)
    outs = []
    for threads in ("1", "2"):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS=threads, MKL_NUM_THREADS=threads)
        outs.append(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env).stdout)
    assert outs[0] == outs[1] and outs[0].strip()
