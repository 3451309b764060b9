"""synthesize(): memory check before any allocation, seeds, and the statistics of what it makes."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from sealeak.errors import InputError, ResourceError
from sealeak.numerics.synthesis import synthesis_memory_bytes, synthesize
from sealeak.physics.spectrum import PowerSpectrum

L = 1e-3
MODEL = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e5, q_cutoff=1e7, q_lowest=1e4, h_rms=1e-6)


@pytest.mark.parametrize("amplitudes, n", [("gaussian", 1024), ("phases", 1024), ("gaussian", 2048)])
def test_memory_estimate_bounds_the_measured_peak(amplitudes, n):
    # independent measurement: tracemalloc sees every NumPy/SciPy array allocation
    synthesize(MODEL, 16, L, seed=0)  # imports and caches outside the measurement
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        synthesize(MODEL, n, L, seed=1, amplitudes=amplitudes)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    need = synthesis_memory_bytes(n)
    assert peak <= need <= 1.5 * peak
    # the peak is two full arrays: n² float64 heights (or noise) and the n(n/2+1) complex spectrum
    assert peak >= 8 * n * n + 16 * n * (n // 2 + 1)


def test_memory_limit_refuses_before_allocating():
    need = synthesis_memory_bytes(256)
    with pytest.raises(ResourceError, match=r"256x256.*GiB"):
        synthesize(MODEL, 256, L, seed=0, memory_limit=need - 1)
    assert synthesize(MODEL, 256, L, seed=0, memory_limit=need).shape == (256, 256)


def test_default_limit_is_the_available_memory(monkeypatch):
    import sealeak.numerics._memory as memory

    monkeypatch.setattr(memory, "available_memory_bytes", lambda: 10**6)
    with pytest.raises(ResourceError, match="available"):
        synthesize(MODEL, 256, L, seed=0)
    # a grid far beyond any machine is refused without touching memory
    monkeypatch.undo()
    with pytest.raises(ResourceError):
        synthesize(MODEL, 2_000_000, L, seed=0)  # ~48 TiB


@pytest.mark.parametrize("seed", [-1, True])
def test_bad_seeds_are_input_errors(seed):
    with pytest.raises(InputError) as err:
        synthesize(MODEL, 16, L, seed=seed)
    assert err.value.field == "seed"


def test_same_seed_same_surface_and_exact_amplitudes():
    a = synthesize(MODEL, 128, L, seed=3, amplitudes="phases")
    assert np.array_equal(a, synthesize(MODEL, 128, L, seed=3, amplitudes="phases"))
    assert not np.array_equal(a, synthesize(MODEL, 128, L, seed=4, amplitudes="phases"))
    # fixed amplitudes: |fft2(h)|² = n⁴ C(q) (2π/L)² on every mode inside the band (docs/theory.md §1)
    F = np.fft.fft2(a)
    k = 2 * np.pi * np.fft.fftfreq(128, d=L / 128)
    q = np.hypot(k[:, None], k[None, :])
    nyq = np.abs(k).max()
    inside = (q >= 1e4) & (q <= 1e7) & (np.abs(k[:, None]) < nyq) & (np.abs(k[None, :]) < nyq)
    expected = 128**4 * MODEL(q[inside]) * (2 * np.pi / L) ** 2
    np.testing.assert_allclose(np.abs(F[inside]) ** 2, expected, rtol=1e-9)


def test_text_maps_too_thin_to_read_back_are_refused(tmp_path):
    from sealeak.errors import InputError
    from sealeak.topography import read_topography, write_height_map

    with pytest.raises(InputError, match="at least 4 x 2 points; write .npz instead"):
        write_height_map(tmp_path / "thin.txt", np.zeros((3, 8)), (1e-3, 1e-3))
    write_height_map(tmp_path / "ok.txt", np.arange(8.0).reshape(4, 2), (1e-3, 5e-4))
    t = read_topography(tmp_path / "ok.txt")
    assert t.heights.shape == (4, 2) and t.size == pytest.approx((1e-3, 5e-4))


# ---------------------------------------------------------------------------- what a map of a given size holds
def test_map_variance_is_the_mean_square_of_the_map():
    from sealeak.numerics.synthesis import map_variance

    for n, size in ((64, L), (128, L / 20), (32, 2 * L)):
        h = synthesize(MODEL, n, size, seed=3, amplitudes="phases")  # exact amplitudes: no scatter
        # the Nyquist modes (stored real) carry a little less than their share; < 1 % here
        assert np.mean(h**2) == pytest.approx(map_variance(MODEL, n, size), rel=0.01, abs=0)
    # a map much larger than the longest wavelength and fine enough for the shortest holds all of C(q)
    assert map_variance(MODEL, 2048, 20 * 2 * np.pi / 1e4) == pytest.approx(MODEL.h_rms**2, rel=0.05, abs=0)  # (3.4 %)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("n,size,said", [
    (64, 2 * np.pi / 1e7 / 2, "smaller than the shortest wavelength"),  # side half the shortest wavelength
    (8, 100.0, "too coarse"),  # shortest wavelength on the map ~ 18 m, C(q) ends at 0.6 mm
])
def test_a_map_that_would_be_flat_is_refused(n, size, said):
    from sealeak.numerics.synthesis import band_problem

    assert said in band_problem(MODEL, n, size)
    with pytest.raises(InputError, match=said):
        synthesize(MODEL, n, size, seed=0)
    assert band_problem(MODEL, 64, L) is None
    # a narrow band between two wavevectors of the grid: no mode inside it either
    narrow = PowerSpectrum.from_arrays([3.2 * 2 * np.pi / L, 3.5 * 2 * np.pi / L], [1e-30, 1e-30])  # |q| L/2π = √(i²+j²)
    assert "no wavevector" in band_problem(narrow, 8, L)
    with pytest.raises(InputError, match="flat"):
        synthesize(narrow, 8, L, seed=0)
