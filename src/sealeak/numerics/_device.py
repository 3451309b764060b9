"""Where the FFT solvers run: ``"cpu"`` (NumPy) or ``"cuda"`` (CuPy on an NVIDIA GPU) (private).

CuPy is an optional extra (``pip install 'sealeak[gpu]'``). It is imported here only, through
:func:`importlib.import_module`, and only when ``"cuda"`` is asked for: the CPU path never imports it.
Asking for ``"cuda"`` without CuPy, or with CuPy but no GPU it can see, is one :class:`InputError`
naming the option, the value and what is missing. Before any work the GPU's free memory is checked
against :func:`device_memory_bytes` (:func:`require_device_memory`).
"""

from __future__ import annotations

import importlib
from typing import Any

import numpy as np

from ..errors import InputError, ResourceError
from ._band_contact import band_contact_memory_bytes
from ._contact import contact_memory_bytes
from ._xp import namespace
from .synthesis import synthesis_memory_bytes

__all__ = ["DEVICES", "array_namespace_for", "check_device", "device_count", "device_name", "device_memory_bytes",
           "require_device_memory"]

#: The devices a simulation may run on.
DEVICES = ("cpu", "cuda")
#: What the errors say about how to get a GPU run.
_GPU_HELP = "install the gpu extra (pip install 'sealeak[gpu]') on a machine with an NVIDIA GPU, or use cpu"


def check_device(device: Any, field: str = "device") -> str:
    """``device`` itself when it is one of :data:`DEVICES`, else an InputError naming ``field`` (nothing is imported)."""
    if not isinstance(device, str) or device not in DEVICES:
        raise InputError(field, device, "allowed: 'cpu', 'cuda'")
    return device


def _cupy(field: str) -> Any:
    """CuPy, imported now; an InputError naming ``field`` if it is missing or sees no GPU."""
    try:
        cupy = importlib.import_module("cupy")
    except (ImportError, OSError, RuntimeError) as exc:  # not installed, or its CUDA libraries fail to load
        raise InputError(field, "cuda", f"needs CuPy, which cannot be imported ({exc}): {_GPU_HELP}") from None
    if _count(cupy) < 1:
        raise InputError(field, "cuda", f"needs an NVIDIA GPU, and CuPy sees none: {_GPU_HELP}")
    return cupy


def _count(cupy: Any) -> int:
    try:
        return int(cupy.cuda.runtime.getDeviceCount())
    except Exception:  # CUDARuntimeError (no driver, no device): no GPU to use
        return 0


def array_namespace_for(device: str, field: str = "device") -> Any:
    """The array namespace of ``device``: array-api-compat's NumPy for ``"cpu"``, its CuPy for ``"cuda"``.

    ``field`` names the option in errors (``--device``, ``simulation.device``).
    """
    if check_device(device, field) == "cpu":
        return namespace(np.empty(0))
    _cupy(field)
    return importlib.import_module("array_api_compat.cupy")


def device_count(device: str, field: str = "device") -> int:
    """GPUs CuPy sees for ``"cuda"`` (>= 1, else an InputError); 0 for ``"cpu"``."""
    if check_device(device, field) == "cpu":
        return 0
    return _count(_cupy(field))


def device_name(device: str, field: str = "device") -> str:
    """The name of the card (``"cuda"``: CuPy's current device), or ``"cpu"``."""
    if check_device(device, field) == "cpu":
        return "cpu"
    cupy = _cupy(field)
    name = cupy.cuda.runtime.getDeviceProperties(cupy.cuda.Device().id)["name"]
    return name.decode() if isinstance(name, bytes) else str(name)


def device_memory_bytes(n: int) -> int:
    """Peak GPU memory of one task's synthesis and contact solves on an n×n grid, in bytes (estimate).

    The larger of the synthesis (:func:`~sealeak.numerics.synthesis_memory_bytes`) and a contact solve
    (periodic or band, :func:`~sealeak.numerics.contact_memory_bytes`,
    :func:`~sealeak.numerics.band_contact_memory_bytes`) with the heights and three more gap-and-pressure
    pairs (16 n² bytes each: a warm start and the bracket of a threshold search), plus 10 % for CuPy's
    FFT plans and its memory pool's rounding. The flow's own need is :func:`~sealeak.numerics.flow_memory_bytes`
    (``run_ensemble`` checks the larger of the two, :func:`~sealeak.numerics.solve_flow` its own).
    """
    n = int(n)
    solve = max(contact_memory_bytes(n), band_contact_memory_bytes(n, n)) + 8 * n * n + 3 * 16 * n * n
    return int(1.1 * max(synthesis_memory_bytes(n), solve))


def require_device_memory(need: int, what: str, device: str, field: str = "device") -> None:
    """Raise :class:`ResourceError` when ``need`` bytes exceed the GPU's free memory (``"cuda"``; nothing for ``"cpu"``).

    Free is what the driver reports plus the blocks CuPy's memory pool holds unused (a finished contact solve's
    arrays stay in the pool for reuse, and the flow after it reuses them).
    """
    if check_device(device, field) == "cpu":
        return
    cupy = _cupy(field)
    free, total = (int(v) for v in cupy.cuda.runtime.memGetInfo())
    pool = getattr(cupy, "get_default_memory_pool", None)
    if pool is not None:
        free += int(pool().free_bytes())
    if need > free:
        raise ResourceError(f"{what} needs about {need / 2**30:.2f} GiB of GPU memory (estimate), more than the "
                            f"{free / 2**30:.2f} GiB free of {total / 2**30:.2f} GiB; use a smaller grid or {field} cpu")
