"""The array namespace of the FFT solvers: one code path for NumPy, CuPy and any array-API namespace (private).

Surface synthesis and the contact solvers take their namespace from the arrays they are given
(``array_api_compat.array_namespace``): NumPy arrays run on the CPU, CuPy arrays on a GPU, and the
tests run the same code on ``array_api_strict`` arrays. On NumPy the helpers here keep what the
solvers did before there was a choice, operation for operation: ``scipy.fft`` with ``workers``
threads and ufuncs writing into preallocated arrays (``out=``), so the results are bit for bit
those of the NumPy-only code. Elsewhere they use only the array API standard: ``xp.fft.rfftn`` /
``irfftn`` over both axes and operators that allocate.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from array_api_compat import array_namespace, device, is_cupy_array, is_numpy_array, is_numpy_namespace
from scipy import fft as sfft

__all__ = ["namespace", "is_numpy", "is_numpy_array", "to_namespace", "to_numpy", "rfft2", "irfft2", "multiply_into", "maximum_into", "minimum_into",
           "contiguous"]

Array = Any  # an array of the namespace at hand (NumPy, CuPy, array_api_strict, ...)


def namespace(*arrays: Any) -> Any:
    """The array namespace of ``arrays`` (array-api-compat's wrapper of NumPy for NumPy arrays); NumPy for
    anything that is no array (lists, scalars)."""
    try:
        return array_namespace(*arrays)
    except TypeError:
        return array_namespace(np.empty(0))


def is_numpy(xp: Any) -> bool:
    """Whether ``xp`` is NumPy (itself or array-api-compat's wrapper)."""
    return bool(is_numpy_namespace(xp))


def to_namespace(a: Any, like: Array) -> Array:
    """The host (NumPy) array ``a`` in the namespace and on the device of ``like`` (no copy for NumPy)."""
    if is_numpy_array(like):
        return a
    return namespace(like).asarray(a, device=device(like))


def to_numpy(a: Any) -> np.ndarray:
    """``a`` as a NumPy array on the host: itself for NumPy, copied from the GPU for CuPy, through DLPack for another
    array namespace, ``np.asarray`` for anything else (lists)."""
    if is_numpy_array(a):
        return a
    if is_cupy_array(a):
        return a.get()
    if hasattr(a, "__dlpack__"):
        return np.from_dlpack(a)
    return np.asarray(a)


def rfft2(x: Array, xp: Any, workers: int, s: tuple[int, int] | None = None) -> Array:
    """2-D real FFT over both axes (zero-padded to ``s``): ``scipy.fft.rfft2`` with ``workers`` threads on NumPy."""
    if is_numpy(xp):
        return sfft.rfft2(x, s=s, workers=workers)
    return xp.fft.rfftn(x, s=s or tuple(x.shape), axes=(0, 1))


def irfft2(spec: Array, xp: Any, workers: int, s: tuple[int, int]) -> Array:
    """Inverse of :func:`rfft2` to the real shape ``s``; on NumPy ``scipy.fft.irfft2`` overwriting ``spec``."""
    if is_numpy(xp):
        return sfft.irfft2(spec, s=s, workers=workers, overwrite_x=True)
    return xp.fft.irfftn(spec, s=s, axes=(0, 1))


def multiply_into(a: Array, b: Array, out: Array, xp: Any) -> Array:
    """``out[...] = a * b`` and ``out``; ``b`` may be a boolean mask (1/0). On NumPy one ufunc call into ``out``."""
    if is_numpy(xp):
        return np.multiply(a, b, out=out)
    if b.dtype == xp.bool:
        b = xp.astype(b, a.dtype)
    out[...] = a * b
    return out


def maximum_into(a: Array, low: float, out: Array, xp: Any) -> Array:
    """``out[...] = max(a, low)`` and ``out``: one ``np.maximum`` into ``out`` on NumPy."""
    if is_numpy(xp):
        return np.maximum(a, low, out=out)
    out[...] = xp.maximum(a, low)
    return out


def minimum_into(a: Array, high: float, out: Array, xp: Any) -> Array:
    """``out[...] = min(a, high)`` and ``out``: one ``np.minimum`` into ``out`` on NumPy."""
    if is_numpy(xp):
        return np.minimum(a, high, out=out)
    out[...] = xp.minimum(a, high)
    return out


def contiguous(a: Array, xp: Any) -> Array:
    """``a`` laid out contiguously in memory (``np.ascontiguousarray`` on NumPy, a copy elsewhere)."""
    if is_numpy(xp):
        return np.ascontiguousarray(a)
    return xp.asarray(a, copy=True)
