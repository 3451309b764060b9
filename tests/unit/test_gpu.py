"""On a GPU: synthesis, the contact solvers and the flows on CuPy arrays give the NumPy results, and ``simulate --device cuda``
gives the CPU's numbers. Skipped unless CuPy imports and sees a GPU (CI has none; docs/performance.md#gpu)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, simulate
from sealeak.errors import InputError
from sealeak.numerics import array_namespace_for, solve_band_contact, solve_contact, solve_flow, solve_gas_flow, synthesize, to_numpy
from sealeak.physics.gas import Gas
from sealeak.physics.spectrum import PowerSpectrum

pytest.importorskip("cupy")
try:
    xp = array_namespace_for("cuda")
except InputError as err:  # CuPy without a GPU it can use
    pytest.skip(str(err), allow_module_level=True)

#: Relative tolerance between the GPU and the CPU (cuFFT's round-off against pocketfft's over the iterations).
REL = 1e-12
MODEL = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e5, q_cutoff=1e7, q_lowest=1e4, h_rms=1e-6)
L = 2 * np.pi / 1e4


def _close(a, b, rel=REL):
    return np.abs(to_numpy(a) - b).max() <= rel * np.abs(b).max()


@pytest.mark.parametrize("amplitudes", ["gaussian", "phases"])
def test_synthesis_on_the_gpu_is_the_cpu_surface(amplitudes):
    ref = synthesize(MODEL, 256, L, seed=5, amplitudes=amplitudes)
    h = synthesize(MODEL, 256, L, seed=5, amplitudes=amplitudes, xp=xp)
    assert type(h).__module__.startswith("cupy") and _close(h, ref)


@pytest.mark.parametrize("fraction", [0.02, 0.1])
def test_contact_on_the_gpu_is_the_cpu_solution(fraction):
    h = synthesize(MODEL, 256, L, seed=2)
    p0 = fraction * 1e7 * MODEL.slope_rms / 2.0
    ref = solve_contact(h, L, 1e7, p0)
    res = solve_contact(xp.asarray(h), L, 1e7, p0)
    # cuFFT and pocketfft differ in the last bits: the same contact set and iterations within a cell and an iteration
    assert abs(res.contact_area - ref.contact_area) * h.size <= 2 and abs(res.iterations - ref.iterations) <= 1
    assert _close(res.pressure, ref.pressure) and _close(res.gap, ref.gap)
    assert res.on_host().pressure.__class__ is np.ndarray


def test_band_contact_on_the_gpu_is_the_cpu_solution():
    h = 50.0 * synthesize(MODEL, 128, L, seed=4)
    args = (L, L, 3e6, 1.31e-3, 50.0)
    ref = solve_band_contact(h, *args)
    res = solve_band_contact(xp.asarray(h), *args)
    assert abs(res.contact_area - ref.contact_area) * h.size <= 2 and _close(res.pressure, ref.pressure)


def test_simulate_on_the_gpu_gives_the_cpu_numbers():
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=np.array([3e4, 1e5]))
    cpu = simulate(case, grid=128, realizations=2, seed=1, device="cpu")
    gpu = simulate(case, grid=128, realizations=2, seed=1, device="cuda")
    # the same contact within two cells of 128² (cuFFT and pocketfft differ in the last bits), the same percolation
    assert np.abs(gpu.relative_contact_area - cpu.relative_contact_area).max() <= 2 / 128**2
    assert np.array_equal(gpu.per_realization["percolates"], cpu.per_realization["percolates"])
    # the gaps differ by FFT round-off (~1e-15 relative); the flow solve's own tolerance bounds what that becomes
    assert np.allclose(gpu.leak_rate, cpu.leak_rate, rtol=1e-6, atol=0)
    assert np.allclose(gpu.mean_gap, cpu.mean_gap, rtol=1e-12, atol=0)
    assert gpu.percolation_threshold == pytest.approx(cpu.percolation_threshold, abs=2 / 128**2)


def test_flow_on_the_gpu_gives_the_cpu_flux_within_the_bounds_and_the_same_bits_twice():
    h = synthesize(MODEL, 512, L, seed=2)
    res = solve_contact(xp.asarray(h), L, 1e7, 0.1 * 1e7 * MODEL.slope_rms / 2.0).on_host()
    args = (res.gap, L, 1e-3, 1e5)
    cpu = solve_flow(*args, contact=res.contact, method="amg")
    gpu = solve_flow(*args, contact=res.contact, method="amg", device="cuda")
    again = solve_flow(*args, contact=res.contact, method="amg", device="cuda")
    assert gpu.device == "cuda" and cpu.device == "cpu" and gpu.residual <= 1e-6 and gpu.conservation_error <= 1e-8
    # each residual bounds its relative flux error (the check on the host, unchanged)
    assert abs(gpu.flux - cpu.flux) <= (gpu.residual + cpu.residual) * cpu.flux
    assert 5 <= gpu.iterations <= 40
    # on one machine a GPU run repeats itself bit for bit (padded-row products and CuPy's reductions, no atomics)
    assert again.flux == gpu.flux and again.iterations == gpu.iterations


def test_a_gas_flow_on_the_gpu_gives_the_cpu_mass_flow():
    h = synthesize(MODEL, 512, L, seed=2)
    res = solve_contact(xp.asarray(h), L, 1e7, 0.1 * 1e7 * MODEL.slope_rms / 2.0).on_host()
    helium = Gas("helium", 293.15, 19.6e-6, 4.0026e-3)
    cpu = solve_gas_flow(res.gap, L, helium, 2e5, 1e5, contact=res.contact, method="amg")
    gpu = solve_gas_flow(res.gap, L, helium, 2e5, 1e5, contact=res.contact, method="amg", device="cuda")
    assert gpu.device == "cuda" and gpu.iterations > 1
    assert gpu.mass_flow == pytest.approx(cpu.mass_flow, rel=2e-6, abs=0)  # each within 1e-6 of the exact one
