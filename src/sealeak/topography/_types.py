"""Measured surfaces: 2D height maps and 1D line scans, always in metres."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.quantities import quantity

__all__ = ["Topography", "LineScans", "NO_DATA_MAGNITUDE"]

FloatArray = NDArray[np.float64]

#: Heights of this magnitude or more (in any length unit) are not heights but an instrument's
#: no-data marker (1e300, -1e38, the float32 maximum 3.4e38, ...): the readers mark them undefined.
NO_DATA_MAGNITUDE = 1e30


def _freeze(a: FloatArray) -> FloatArray:
    a = np.array(a, dtype=float, copy=True)
    a.setflags(write=False)
    return a


def _check_heights(h: FloatArray, field: str) -> None:
    """Heights must be finite where defined (NaN marks missing points) and below no-data magnitude."""
    if np.isnan(h).all():
        raise InputError(field, "all NaN", "at least some heights must be defined")
    with np.errstate(invalid="ignore"):
        bad = ~np.isnan(h) & ~(np.abs(h) < NO_DATA_MAGNITUDE)
    if bad.any():
        example = h[bad].flat[0]
        raise InputError(field, f"{int(bad.sum())} value(s) such as {example:.4g}",
                         f"heights must be finite and below {NO_DATA_MAGNITUDE:g} m; values like these are "
                         f"no-data markers: set them to NaN (NaN marks missing points)")


def _resolution(value: float | None, name: str) -> float | None:
    if value is None:
        return None
    v = float(value)
    if not (np.isfinite(v) and v > 0):
        raise InputError(name, value, "a finite length > 0 (m), or None")
    return v


@dataclass(frozen=True, eq=False, kw_only=True)
class _Measured:
    """What a map and line scans share (heights in m, NaN where undefined; the rest as for :class:`Topography`)."""

    heights: FloatArray
    periodic: bool = False
    source: str = ""
    notes: tuple[str, ...] = field(default=())
    resolution: float | None = None
    warnings: tuple[str, ...] = field(default=())

    def _settle(self, heights: FloatArray, kind: str) -> None:
        """Keep the checked ``heights`` and the notes, warnings and ``resolution`` (checked, naming ``kind``)."""
        object.__setattr__(self, "heights", heights)
        object.__setattr__(self, "notes", tuple(self.notes))
        object.__setattr__(self, "warnings", tuple(self.warnings))
        object.__setattr__(self, "resolution", _resolution(self.resolution, f"{kind}.resolution"))

    @property
    def has_missing(self) -> bool:
        """True when some heights are NaN (undefined points of optical instruments)."""
        return bool(np.isnan(self.heights).any())


@dataclass(frozen=True, eq=False, kw_only=True)
class Topography(_Measured):
    """A 2D height map on a uniform grid.

    Attributes
    ----------
    heights:
        h[i, j] in m at x_i = i·sx/nx, y_j = j·sy/ny (first index x). NaN marks missing points.
    size:
        Physical size (sx, sy) in m; the pixel size is (sx/nx, sy/ny) (the FFT period convention:
        size = number of points × pixel size).
    periodic:
        True when the map is one period of a periodic surface (synthesized maps); measured maps are
        not periodic.
    source:
        Where the data came from (file path and channel, or free text).
    notes:
        What was done on reading (unit conversions, interpolation), in order.
    resolution:
        Shortest reliable wavelength in m stated by the instrument file (lateral resolution, or the
        tip-radius limit of a stylus/AFM scan), or None. The reliable range of the spectrum ends at
        q = 2π/resolution (or earlier, at the pixel limit).
    warnings:
        What the user should know about the data, as sentences (e.g. no-data markers that were
        marked undefined on reading); shown as warnings by ``sealeak surface analyze``.
    """

    size: tuple[float, float] = quantity("m", "physical size of a map (or length of line scans)")

    def __post_init__(self) -> None:
        h = _freeze(self.heights)
        if h.ndim != 2 or min(h.shape) < 2:
            raise InputError("topography.heights", f"shape {h.shape}", "a 2D array with at least 2×2 points")
        _check_heights(h, "topography.heights")
        sx, sy = (float(v) for v in self.size)
        for name, v in (("size[0]", sx), ("size[1]", sy)):
            if not (np.isfinite(v) and v > 0):
                raise InputError(f"topography.{name}", v, "a finite length > 0 (m)")
        object.__setattr__(self, "size", (sx, sy))
        self._settle(h, "topography")

    @property
    def nb_grid_pts(self) -> tuple[int, int]:
        """(nx, ny)."""
        return (int(self.heights.shape[0]), int(self.heights.shape[1]))

    @property
    def pixel_size(self) -> tuple[float, float]:
        """(dx, dy) in m."""
        return (self.size[0] / self.heights.shape[0], self.size[1] / self.heights.shape[1])

    def __repr__(self) -> str:
        nx, ny = self.nb_grid_pts
        return (f"Topography({nx}×{ny}, size {self.size[0]:.4g} m × {self.size[1]:.4g} m, "
                f"periodic={self.periodic}, source={self.source!r})")


@dataclass(frozen=True, eq=False, kw_only=True)
class LineScans(_Measured):
    """One or more parallel 1D profiles on a common uniform grid.

    Non-uniformly sampled profiles are interpolated onto a uniform grid on reading (and a note says so).

    Attributes
    ----------
    heights:
        h[k, i] in m for scan k at x_i = i·length/n. NaN marks missing points.
    length:
        Physical length in m (= n × pixel size).
    periodic, source, notes, resolution, warnings:
        As for :class:`Topography`.
    """

    length: float

    def __post_init__(self) -> None:
        h = _freeze(self.heights)
        if h.ndim == 1:
            h = _freeze(h[None, :])
        if h.ndim != 2 or h.shape[1] < 4 or h.shape[0] < 1:
            raise InputError("line_scans.heights", f"shape {h.shape}", "1D profiles with at least 4 points")
        _check_heights(h, "line_scans.heights")
        length = float(self.length)
        if not (np.isfinite(length) and length > 0):
            raise InputError("line_scans.length", length, "a finite length > 0 (m)")
        object.__setattr__(self, "length", length)
        self._settle(h, "line_scans")

    @classmethod
    def from_topography(cls, topography: Topography, axis: int = 0) -> LineScans:
        """All rows (``axis=0``: profiles along x) or columns (``axis=1``: along y) of a map."""
        if axis not in (0, 1):
            raise InputError("axis", axis, "0 (profiles along x) or 1 (along y)")
        h = topography.heights.T if axis == 0 else topography.heights
        return cls(heights=h, length=topography.size[axis], periodic=topography.periodic,
                   source=f"{topography.source} ({'x' if axis == 0 else 'y'} profiles)",
                   notes=topography.notes, resolution=topography.resolution, warnings=topography.warnings)

    @property
    def nb_points(self) -> int:
        return int(self.heights.shape[1])

    @property
    def nb_scans(self) -> int:
        return int(self.heights.shape[0])

    @property
    def pixel_size(self) -> float:
        return self.length / self.heights.shape[1]

    def __repr__(self) -> str:
        return (f"LineScans({self.nb_scans} × {self.nb_points} points, length {self.length:.4g} m, "
                f"periodic={self.periodic}, source={self.source!r})")
