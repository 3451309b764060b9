"""Periodic random rough surfaces with a prescribed power spectrum C(q).

For a periodic N×N map of side L the Fourier amplitudes h_q of h(x) = Σ_q h_q exp(i q·x) satisfy
<|h_q|²> = C(q) (2π/L)² (Persson's convention, docs/theory.md §1.1; the method is §6.1), so that
h_rms² = Σ_q C(q) (2π/L)² ≈ ∫ d²q C(q). With NumPy's unnormalised FFT, fft2(h)(q) = N² h_q.

Two kinds of randomness:

* ``"gaussian"`` (default): h is a Gaussian random field: the FFT of real white noise, filtered by
  √C(q). The spectrum of one realisation scatters around C(q) (exponentially distributed |h_q|²).
* ``"phases"``: fixed amplitudes |h_q| = √(C(q)) 2π/L with random phases (Hermitian symmetry kept by
  taking the phases from the FFT of real white noise). The discrete spectrum equals C(q) exactly
  except at the Nyquist and zero modes, which must be real.

Work is O(N² log N) with float64 arrays of N² and (N/2+1)N complex values; no mode loop.

A map holds the modes 2π/L ≤ |q| ≤ √2·πN/L (wavelengths from about two pixels to its side L) and
nothing of C(q) outside them: :func:`map_variance` is the mean square height the map has on
average, :func:`band_problem` says why a map would be flat (no mode of the grid inside the
spectrum's band), which :func:`synthesize` refuses.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sfft

from ..errors import InputError
from ..physics.spectrum import PowerSpectrum
from ._memory import require_memory
from ._xp import irfft2, is_numpy, namespace, rfft2, to_namespace

__all__ = ["synthesize", "wavevector_grid", "synthesis_memory_bytes", "map_variance", "band_problem"]

Amplitudes = Literal["gaussian", "phases"]


def wavevector_grid(n: int, size: float, *, half: bool = True) -> NDArray[np.float64]:
    """|q| (1/m) on the FFT grid of an n×n periodic map of side ``size`` (m).

    ``half=True`` gives the (n, n//2+1) layout of ``scipy.fft.rfft2``; otherwise the full (n, n) one.
    """
    k = 2.0 * np.pi * sfft.fftfreq(n, d=size / n)
    ky = 2.0 * np.pi * sfft.rfftfreq(n, d=size / n) if half else k
    return np.sqrt(k[:, None] ** 2 + ky[None, :] ** 2)


_BLOCK_ELEMENTS = 1 << 16  # wavevectors per block when filtering (bounds the temporaries)
_BLOCK_TEMPORARIES = 12  # float64 block-sized temporaries alive at once (C(q) evaluation, amplitudes, phases)


def synthesis_memory_bytes(n: int) -> int:
    """Peak memory of :func:`synthesize` for an n×n map, in bytes.

    The peak is two full arrays at once: the real white noise (8 n² bytes) with its half-plane
    spectrum (16 n (n/2+1) bytes) during the forward FFT, and that spectrum with the real output
    map during the inverse FFT. The filter works on blocks of rows, so its temporaries are bounded
    (at most ``_BLOCK_TEMPORARIES`` float64 blocks of ``_BLOCK_ELEMENTS`` values).
    """
    n = int(n)
    half = 16 * n * (n // 2 + 1)
    block = 8 * _BLOCK_TEMPORARIES * min(_BLOCK_ELEMENTS, n * (n // 2 + 1))
    return int(1.05 * (8 * n * n + half + block))  # 5 %: the FFT library's own work space


def map_variance(spectrum: PowerSpectrum, n: int, size: float) -> float:
    """Expected mean square height (m²) of an n×n periodic map of side ``size`` (m) synthesized from C(q).

    <h²> = Σ_q C(|q|) (2π/size)² over the grid's modes q ≠ 0 (docs/theory.md §6.1; exact for
    ``"phases"`` amplitudes, the mean over realisations for ``"gaussian"``). Compare with
    ``spectrum.h_rms**2`` for the share of the roughness the map captures. Evaluated in blocks of
    rows (temporaries bounded as in :func:`synthesize`).
    """
    n = int(n)
    k2 = (2.0 * np.pi * sfft.fftfreq(n, d=size / n)) ** 2
    rows = max(1, _BLOCK_ELEMENTS // n)
    total = 0.0
    for r0 in range(0, n, rows):
        q = np.sqrt(k2[r0:r0 + rows, None] + k2[None, :])
        total += float(np.sum(spectrum(q)))  # C(0) = 0: the zero mode lies below every band
    return total * (2.0 * np.pi / size) ** 2


def _length(value: float) -> str:
    """A length (m) as text with a readable unit."""
    for factor, unit in ((1e3, "km"), (1.0, "m"), (1e-3, "mm"), (1e-6, "µm")):
        if abs(value) >= factor * 0.9999:
            return f"{value / factor:.4g} {unit}"
    return f"{value / 1e-9:.4g} nm"


def band_problem(spectrum: PowerSpectrum, n: int, size: float, *, size_name: str = "size",
                 grid_name: str = "n") -> str | None:
    """Why an n×n map of side ``size`` (m) would hold nothing of C(q), naming the input to change; or None.

    The map holds wavevectors 2π/size ≤ |q| ≤ √2·πn/size on a grid of spacing 2π/size; C(q) is zero
    outside [q_min, q_max]. ``size_name``/``grid_name``: how to name the two inputs (e.g. CLI flags).
    """
    if map_variance(spectrum, n, size) > 0.0:
        return None
    lam_short, lam_long = 2.0 * np.pi / spectrum.q_max, 2.0 * np.pi / spectrum.q_min
    span = f"C(q) spans wavelengths {_length(lam_short)} .. {_length(lam_long)}"
    if size < lam_short * (1 + 1e-12):
        return (f"the map (side {_length(size)}) is smaller than the shortest wavelength of C(q): {span}, so the map "
                f"would be flat; give a {size_name} above {_length(lam_short)}")
    shortest = np.sqrt(2.0) * size / n  # the grid's corner mode, √2·πn/size
    if shortest > lam_long * (1 - 1e-12):
        return (f"the pixel ({_length(size / n)}) is too coarse: the shortest wavelength of the {n}×{n} map "
                f"({_length(shortest)}) is longer than the longest of C(q): {span}, so the map would be flat; give a "
                f"larger {grid_name} (above {int(np.ceil(np.sqrt(2.0) * size / lam_long))}) or a smaller {size_name}")
    return (f"no wavevector of the {n}×{n} grid (spacing 2π/{_length(size)}) falls inside the band of C(q): {span}, so "
            f"the map would be flat; give a larger {size_name} (a finer grid of wavevectors)")


def _check_seed(seed: object) -> None:
    if isinstance(seed, (bool, np.bool_)):
        raise InputError("seed", seed, "a non-negative integer (or a numpy Generator)")
    if isinstance(seed, (int, np.integer)) and seed < 0:
        raise InputError("seed", int(seed), "must be a non-negative integer (0, 1, 2, ...)")


def synthesize(
    spectrum: PowerSpectrum,
    n: int,
    size: float,
    *,
    seed: int | np.random.Generator | None,
    amplitudes: Amplitudes = "gaussian",
    workers: int = -1,
    memory_limit: float | None = None,
    xp: Any = None,
) -> NDArray[np.float64]:
    """A periodic random height map (m) of n×n points and side ``size`` (m) with spectrum C(q).

    Fourier amplitudes with <|h_q|²> = C(q) (2π/size)² (docs/theory.md §6.1, eq. 6.1).

    Parameters
    ----------
    spectrum:
        C(q) in Persson's convention; modes outside its band get zero amplitude.
    n:
        Grid points per side (even, >= 4).
    size:
        Side of the square map in m; the lowest non-zero mode is 2π/size.
    seed:
        Seed (a non-negative integer) or NumPy Generator; the same seed gives the same surface
        (``None`` only on purpose).
    amplitudes:
        ``"gaussian"`` or ``"phases"`` (see the module docstring).
    workers:
        Threads for scipy.fft (-1: all cores).
    memory_limit:
        Bytes the job may use; default: the memory the OS reports as available. A job whose
        peak (:func:`synthesis_memory_bytes`) exceeds it is refused with ResourceError before
        anything is allocated.
    xp:
        Array namespace to build the map in (default NumPy): e.g. array-api-compat's CuPy namespace for a
        GPU (:func:`sealeak.numerics.array_namespace_for`). The white noise is always drawn on the host
        by NumPy's generator and then moved to the device, so a seed gives the same surface on every
        device (to the FFT's round-off, ~1e-15 relative); the filter C(q) is evaluated on the host
        block by block and moved likewise. On NumPy the FFTs are scipy.fft's with ``workers`` threads.

    Raises
    ------
    InputError
        When no mode of the map lies inside the band of C(q): the map would be flat
        (:func:`band_problem` says why).

    Returns
    -------
    ndarray
        Heights h[i, j] in m at x_i = i·size/n, y_j = j·size/n, float64, mean zero; an array of ``xp``.
    """
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or n < 4 or n % 2:
        raise InputError("grid", n, "must be an even integer >= 4")
    if not (np.isfinite(size) and size > 0):
        raise InputError("size", size, "must be a finite length > 0 (m)")
    if amplitudes not in ("gaussian", "phases"):
        raise InputError("amplitudes", amplitudes, "allowed: 'gaussian', 'phases'")
    _check_seed(seed)
    n = int(n)
    require_memory(synthesis_memory_bytes(n), f"synthesizing a {n}x{n} map", memory_limit)
    try:
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    except (TypeError, ValueError) as exc:
        raise InputError("seed", seed, f"a non-negative integer or a numpy Generator ({exc})") from None
    xp = namespace(np.empty(0)) if xp is None else xp
    noise = rng.standard_normal((n, n))  # on the host, whatever the device: the same surface everywhere
    spec = rfft2(noise if is_numpy(xp) else xp.asarray(noise), xp, workers)  # <|spec|²> = n²
    del noise
    k = 2.0 * np.pi * sfft.fftfreq(n, d=size / n)
    ky2 = (2.0 * np.pi * sfft.rfftfreq(n, d=size / n)) ** 2
    scale = (2.0 * np.pi / size) * n  # n² |h_q| / n
    rows = max(1, _BLOCK_ELEMENTS // ky2.size)
    content = False
    for r0 in range(0, n, rows):  # blocks of rows: vectorised, temporaries bounded
        q = np.sqrt(k[r0:r0 + rows, None] ** 2 + ky2[None, :])
        amp = np.sqrt(spectrum(q)) * scale
        content = content or bool(amp.any())
        _filter(spec, r0, rows, to_namespace(amp, spec), amplitudes == "gaussian", n, xp)
    spec[0, 0] = 0.0
    if not content:
        del spec
        raise InputError("size", size, band_problem(spectrum, n, size) or "no mode of the map lies in the band of C(q)")
    h = irfft2(spec, xp, workers, (n, n))
    return np.ascontiguousarray(h, dtype=np.float64) if is_numpy(xp) else h


def _filter(spec: Any, r0: int, rows: int, amp: Any, gaussian: bool, n: int, xp: Any) -> None:
    """Rows r0 .. r0+rows of the noise's half-spectrum filtered by the amplitudes ``amp``, in place (module docstring)."""
    if is_numpy(xp):  # in place on the rows' view: the NumPy-only code's operations, bit for bit
        blk = spec[r0:r0 + rows]
        if gaussian:
            blk *= amp
        else:
            mag = np.abs(blk)
            np.divide(blk, mag, out=blk, where=mag > 0)
            blk *= amp * n
        return
    rows = min(rows, n - r0)  # the standard leaves slices past the end unspecified
    blk = spec[r0:r0 + rows, ...]
    if not gaussian:
        mag = xp.abs(blk)
        blk = blk / xp.where(mag > 0, mag, 1.0)
        amp = amp * n
    spec[r0:r0 + rows, ...] = blk * amp
