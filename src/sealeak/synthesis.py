"""Periodic random rough surfaces with a prescribed power spectrum C(q).

For a periodic N×N map of side L the Fourier amplitudes h_q of h(x) = Σ_q h_q exp(i q·x) satisfy
<|h_q|²> = C(q) (2π/L)² (Persson's convention, THEORY.md section 1), so that
h_rms² = Σ_q C(q) (2π/L)² ≈ ∫ d²q C(q). With NumPy's unnormalised FFT, fft2(h)(q) = N² h_q.

Two kinds of randomness:

* ``"gaussian"`` (default): h is a Gaussian random field: the FFT of real white noise, filtered by
  √C(q). The spectrum of one realisation scatters around C(q) (exponentially distributed |h_q|²).
* ``"phases"``: fixed amplitudes |h_q| = √(C(q)) 2π/L with random phases (Hermitian symmetry kept by
  taking the phases from the FFT of real white noise). The discrete spectrum equals C(q) exactly
  except at the Nyquist and zero modes, which must be real.

Work is O(N² log N) with float64 arrays of N² and (N/2+1)N complex values; no mode loop.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sfft

from .errors import InputError, ResourceError
from .roughness import PowerSpectrum

__all__ = ["synthesize", "wavevector_grid", "synthesis_memory_bytes"]

Amplitudes = Literal["gaussian", "phases"]


def wavevector_grid(n: int, size: float, *, half: bool = True) -> NDArray[np.float64]:
    """|q| (1/m) on the FFT grid of an n×n periodic map of side ``size`` (m).

    ``half=True`` gives the (n, n//2+1) layout of ``scipy.fft.rfft2``; otherwise the full (n, n) one.
    """
    k = 2.0 * np.pi * sfft.fftfreq(n, d=size / n)
    ky = 2.0 * np.pi * sfft.rfftfreq(n, d=size / n) if half else k
    return np.sqrt(k[:, None] ** 2 + ky[None, :] ** 2)


def synthesis_memory_bytes(n: int) -> int:
    """Peak memory of :func:`synthesize` for an n×n map, in bytes (estimate)."""
    return int(8 * n * n * 2 + 16 * n * (n // 2 + 1) * 2)


def synthesize(
    spectrum: PowerSpectrum,
    n: int,
    size: float,
    *,
    seed: int | np.random.Generator | None,
    amplitudes: Amplitudes = "gaussian",
    workers: int = -1,
    memory_limit: float | None = None,
) -> NDArray[np.float64]:
    """A periodic random height map (m) of n×n points and side ``size`` (m) with spectrum C(q).

    Parameters
    ----------
    spectrum:
        C(q) in Persson's convention; modes outside its band get zero amplitude.
    n:
        Grid points per side (even, >= 4).
    size:
        Side of the square map in m; the lowest non-zero mode is 2π/size.
    seed:
        Seed or NumPy Generator; the same seed gives the same surface (``None`` only on purpose).
    amplitudes:
        ``"gaussian"`` or ``"phases"`` (see the module docstring).
    workers:
        Threads for scipy.fft (-1: all cores).
    memory_limit:
        Refuse (ResourceError) when the estimate exceeds this many bytes.

    Returns
    -------
    Heights h[i, j] at x_i = i·size/n, y_j = j·size/n, float64, mean zero.
    """
    if not isinstance(n, (int, np.integer)) or n < 4 or n % 2:
        raise InputError("grid", n, "must be an even integer >= 4")
    if not (np.isfinite(size) and size > 0):
        raise InputError("size", size, "must be a finite length > 0 (m)")
    if amplitudes not in ("gaussian", "phases"):
        raise InputError("amplitudes", amplitudes, "allowed: 'gaussian', 'phases'")
    need = synthesis_memory_bytes(int(n))
    if memory_limit is not None and need > memory_limit:
        raise ResourceError(f"synthesizing a {n}x{n} map needs about {need / 2**30:.2f} GiB, "
                            f"more than the {memory_limit / 2**30:.2f} GiB allowed")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    n = int(n)
    noise = rng.standard_normal((n, n))
    spec = sfft.rfft2(noise, workers=workers)  # <|spec|²> = n²
    del noise
    q = wavevector_grid(n, size, half=True)
    amp = np.sqrt(spectrum(q)) * (2.0 * np.pi / size) * n  # n² |h_q| / n
    del q
    if amplitudes == "gaussian":
        spec *= amp
    else:
        mag = np.abs(spec)
        np.divide(spec, mag, out=spec, where=mag > 0)
        spec *= amp * n
    spec[0, 0] = 0.0
    h = sfft.irfft2(spec, s=(n, n), workers=workers)
    return np.ascontiguousarray(h, dtype=np.float64)
