"""Helpers shared by the native readers and the SurfaceTopography bridge (private).

The unit options a file without units needs (:func:`require_units`, :func:`lateral_size`), the
notes for options a file overrides, and resampling of non-uniform line scans.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, InputError
from ..io.units import SI_RANGE
from ._types import NO_DATA_MAGNITUDE, LineScans, Topography
from ._units import MissingUnitsError, option_name, parse_length

__all__ = ["MAX_POINTS", "check_points", "check_lengths",
           "npy_header", "Surface", "LengthLike", "INSTALL_HINT", "require_units", "lateral_size", "ignored_notes",
           "resample_nonuniform", "mark_no_data"]

Surface = Topography | LineScans
LengthLike = float | str
INSTALL_HINT = "pip install 'sealeak[formats]'"

#: The most heights a map or profile may hold (8192 × 8192; 512 MB as float64): checked on the shape a
#: file declares, before its data are read or decompressed, so a small compressed file cannot expand
#: into all of memory.
MAX_POINTS = 8192 * 8192


def npy_header(stream: IO[bytes]) -> tuple[tuple[int, ...], np.dtype[Any]]:
    """The shape and type an ``.npy`` stream declares in its header, read without its data (numpy's format
    functions; ValueError for a damaged header)."""
    version = np.lib.format.read_magic(stream)
    read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    shape, _fortran, dtype = read(stream)
    return tuple(int(n) for n in shape), dtype


def check_points(path: Path | str, shape: Sequence[int]) -> None:
    """Refuse a declared ``shape`` of more than :data:`MAX_POINTS` heights (FileFormatError), before reading."""
    n = math.prod(int(k) for k in shape)
    if n > MAX_POINTS:
        raise FileFormatError(Path(path), f"declares {' × '.join(str(int(k)) for k in shape)} = {n:,} heights; "
                                          f"at most {MAX_POINTS:,} (8192 × 8192) are read: crop or resample the map")


def check_lengths(path: Path | str, what: str, lengths: Sequence[float]) -> None:
    """Refuse lengths in m read from (or derived from) a file outside :data:`~sealeak.io.units.SI_RANGE`
    (1e-100 m to 1e100 m, as the ``size`` option): FileFormatError naming the file and ``what`` (the entry)."""
    for i, v in enumerate(lengths):
        if not (math.isfinite(v) and SI_RANGE[0] <= v <= SI_RANGE[1]):
            name = what if len(lengths) == 1 else f"{what} ({'xy'[i] if i < 2 else i})"
            raise FileFormatError(Path(path), f"{name} = {v:.6g} m: a length between {SI_RANGE[0]:g} m and "
                                              f"{SI_RANGE[1]:g} m is allowed")


# ---------------------------------------------------------------------------- unit helpers
def _pair(value: Any, field: str) -> tuple[float, float]:
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise InputError(field, value, "one length or a pair (x, y)")
        return (parse_length(value[0], f"{field}[0]"), parse_length(value[1], f"{field}[1]"))
    v = parse_length(value, field)
    return (v, v)


def require_units(path: Path, *, height: bool = False, size: bool = False, lateral: bool = False,
                  how: str = "") -> None:
    """Raise one :class:`MissingUnitsError` naming every missing unit option (none missing: return)."""
    missing, what = [], []
    if height:
        missing.append("height_unit")
        what.append("height unit")
    if lateral:
        missing.append("lateral_unit")
        what.append("unit of its x, y positions")
    if size:
        missing.append("size")
        what.append("lateral size")
    if missing:
        raise MissingUnitsError(f"{path}{how}", missing, what)


def lateral_size(path: Path, shape: tuple[int, ...], pixel_size: Any, size: Any) -> tuple[float, ...]:
    """Physical size (m) per axis from the user's ``pixel_size`` or ``size`` for a file without one."""
    require_units(path, size=pixel_size is None and size is None)
    if pixel_size is not None and size is not None:
        raise InputError(f"{option_name('pixel_size')}/{option_name('size')}", (pixel_size, size),
                         f"give one of {option_name('pixel_size')} and {option_name('size')}, not both")
    if len(shape) == 1:
        if isinstance(pixel_size if size is None else size, (list, tuple)):
            key = "size" if pixel_size is None else "pixel_size"
            raise InputError(option_name(key), pixel_size if size is None else size,
                             f"{path} is a line scan: give one length")
        if size is not None:
            return (parse_length(size, option_name("size")),)
        return (parse_length(pixel_size, option_name("pixel_size")) * shape[0],)
    if size is not None:
        return _pair(size, option_name("size"))
    dx, dy = _pair(pixel_size, option_name("pixel_size"))
    return (dx * shape[0], dy * shape[1])


def ignored_notes(**given: Any) -> list[str]:
    """Notes for the unit options a file overrides because it states them itself."""
    return [f"{option_name(k)} {v!r} ignored: the file states it" for k, v in given.items() if v is not None]


def resample_nonuniform(x: NDArray[np.float64], h: NDArray[np.float64]) -> tuple[NDArray[np.float64], float, str | None]:
    """Heights on a uniform grid of as many points over [x0, x_last]; (h, length, note or None).

    Uniform within 0.1 % counts as uniform. The grid's pixel is (x_last - x0)/(n - 1) and its length
    n times that (the FFT period convention).
    """
    good = np.isfinite(h)
    x, h = x[good], h[good]
    n = x.size
    span = float(x[-1] - x[0])
    if not span > 0:
        raise InputError("x positions", span, "must span a positive length")
    d = np.diff(x)
    dx = span / (n - 1)
    note = None
    if np.abs(d - dx).max() > 1e-3 * dx or not good.all():
        h = np.interp(x[0] + dx * np.arange(n), x, h)
        note = (f"non-uniform x (spacing {d.min():.4g}..{d.max():.4g} in file units"
                f"{', ' + str(int((~good).sum())) + ' undefined heights dropped' if not good.all() else ''}): "
                f"linearly interpolated onto {n} uniform points")
    return h, dx * n, note


# ---------------------------------------------------------------------------- no-data markers
def mark_no_data(path: Path | str, h: NDArray[np.float64]) -> tuple[NDArray[np.float64], str | None]:
    """Heights in file units with no-data markers set to NaN, and a warning saying so (or None).

    A marker is ±inf or a value of magnitude >= ``NO_DATA_MAGNITUDE`` (1e30): no height in any length
    unit is that large; instruments write such values (1e300, -1e38, the float32 maximum 3.4e38)
    where they measured nothing. Marked points count as undefined, like NaN: left out of the
    statistics and filled by interpolation for C(q). All heights markers: FileFormatError.
    """
    h = np.asarray(h, dtype=float)
    with np.errstate(invalid="ignore"):
        bad = ~np.isnan(h) & ~(np.abs(h) < NO_DATA_MAGNITUDE)
    n = int(bad.sum())
    if n == 0:
        return h, None
    values = np.unique(h[bad])
    shown = ", ".join(f"{v:.4g}" for v in values[:3]) + (f" and {values.size - 3} other values" if values.size > 3 else "")
    if n == int((~np.isnan(h)).sum()):
        raise FileFormatError(path, f"all {n} heights are no-data markers ({shown}): the file holds no measured point")
    h = np.where(bad, np.nan, h)
    share = 100.0 * n / h.size
    return h, (f"{n} of {h.size} points ({share:.2g} %) hold values no height can have ({shown}; magnitude "
               f">= {NO_DATA_MAGNITUDE:g} in any unit): the instrument's no-data marker; they are treated as undefined "
               f"points (left out of the statistics, filled by interpolation for C(q)); export undefined points as "
               f"NaN to read the file without this warning")
