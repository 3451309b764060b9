"""read_topography: instrument files (through SurfaceTopography) and plain formats (native).

Native formats: plain numeric text (see :mod:`._text`) and NumPy ``.npy`` (a 2D height matrix
[x, y] or a 1D profile). These carry no units: the caller must give them (``height_unit`` and the
lateral scale: ``pixel_size`` or ``size`` for matrices and profiles, ``lateral_unit`` for x/y
columns). Everything else goes to SurfaceTopography (optional extra ``sealeak[formats]``), which
reads the physical size and unit from the file's metadata.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence, Union

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, InputError, UnitError
from ._text import NotPlainText, RawTable, looks_binary, parse_text
from ._types import LineScans, Topography
from ._units import length_unit_factor, parse_length

__all__ = ["read_topography", "Surface", "LengthLike"]

Surface = Union[Topography, LineScans]
LengthLike = Union[float, str]

TEXT_SUFFIXES = {".txt", ".csv", ".asc", ".xyz", ".dat", ".tsv", ""}
INSTALL_HINT = "pip install 'sealeak[formats]'"


def read_topography(
    path: str | Path,
    *,
    pixel_size: LengthLike | Sequence[LengthLike] | None = None,
    size: LengthLike | Sequence[LengthLike] | None = None,
    height_unit: str | None = None,
    lateral_unit: str | None = None,
    periodic: bool = False,
    channel: int | str | None = None,
) -> Surface:
    """Read a measured surface: a :class:`Topography` (map) or :class:`LineScans` (profile).

    Parameters
    ----------
    path:
        The file. ``.npy`` and plain numeric text are read natively; instrument formats (Alicona,
        Bruker/Veeco, Zygo, Sensofar, Digital Surf, x3p, Dektak csv, ...) through SurfaceTopography.
    pixel_size, size:
        Lateral scale for files without one (matrix text, ``.npy``): pixel size or total size, a
        number in m or a string with unit (``"0.5 um"``), or a pair for (x, y). Give one, not both.
    height_unit:
        Unit of the stored heights for files without one (``"nm"``, ``"um"``, ``"µm"``, ``"mm"``, ``"m"``).
    lateral_unit:
        Unit of the x (and y) positions of column files (``x h``, ``x y h``).
    periodic:
        Declare the map periodic (only for synthesized data; measurements are not).
    channel:
        Channel index or name for multi-channel instrument files (default: the file's default channel).

    Values the file states itself win; a user value the file overrides is recorded in ``notes``.
    Missing units are never guessed: a :class:`~sealeak.errors.UnitError` names the file and the
    option to pass. Unreadable files raise :class:`~sealeak.errors.FileFormatError`.

    Returns heights in m: a map h[x, y] with size (sx, sy), or line scans with their length. Profiles
    with non-uniform x are linearly interpolated onto a uniform grid of as many points (noted).
    """
    p = Path(path)
    if not p.exists():
        raise FileFormatError(p, "no such file")
    if p.is_dir():
        raise FileFormatError(p, "is a directory, not a file")
    try:
        with open(p, "rb") as fh:
            data = fh.read(4096)
    except OSError as exc:
        raise FileFormatError(p, f"cannot be read ({exc.strerror})") from None
    if not data:
        raise FileFormatError(p, "empty file (0 bytes)")
    if p.suffix.lower() == ".npy":
        return _read_npy(p, pixel_size=pixel_size, size=size, height_unit=height_unit, periodic=periodic)
    if p.suffix.lower() in TEXT_SUFFIXES and not looks_binary(data):
        full = p.read_bytes()
        try:
            raw = parse_text(p, full)
        except NotPlainText as native_error:
            if not _have_surfacetopography():
                raise FileFormatError(p, f"{native_error.problem}; if this is an instrument export "
                                         f"(e.g. Dektak csv), install the reader extra: {INSTALL_HINT}") from None
            from ._external import read_external

            try:
                return read_external(p, pixel_size=pixel_size, size=size, height_unit=height_unit,
                                     lateral_unit=lateral_unit, periodic=periodic, channel=channel)
            except FileFormatError:
                raise FileFormatError(p, native_error.problem) from None
        return _from_raw(p, raw, pixel_size=pixel_size, size=size, height_unit=height_unit,
                         lateral_unit=lateral_unit, periodic=periodic)
    if not _have_surfacetopography():
        raise FileFormatError(p, f"{p.suffix or 'this'} files are instrument formats read through "
                                 f"SurfaceTopography, which is not installed: {INSTALL_HINT}")
    from ._external import read_external

    return read_external(p, pixel_size=pixel_size, size=size, height_unit=height_unit,
                         lateral_unit=lateral_unit, periodic=periodic, channel=channel)


def _have_surfacetopography() -> bool:
    import importlib.util

    return importlib.util.find_spec("SurfaceTopography") is not None


# ---------------------------------------------------------------------------- unit helpers
def _pair(value: Any, field: str) -> tuple[float, float]:
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise InputError(field, value, "one length or a pair (x, y)")
        return (parse_length(value[0], f"{field}[0]"), parse_length(value[1], f"{field}[1]"))
    v = parse_length(value, field)
    return (v, v)


def need_height_unit(path: Path, height_unit: str | None, how: str = "") -> float:
    if height_unit is None:
        raise UnitError("height_unit", None, f"{path}{how} stores no height unit; pass height_unit "
                                             f"(e.g. height_unit='um'; CLI: --height-unit um)")
    return length_unit_factor(height_unit, "height_unit")


def lateral_size(path: Path, shape: tuple[int, ...], pixel_size: Any, size: Any) -> tuple[float, ...]:
    """Physical size (m) per axis from the user's ``pixel_size`` or ``size`` for a file without one."""
    if pixel_size is None and size is None:
        raise UnitError("size", None, f"{path} stores no lateral size; pass size (whole scan, e.g. "
                                      f"size='100 um') or pixel_size (e.g. pixel_size='0.5 um')")
    if pixel_size is not None and size is not None:
        raise InputError("pixel_size/size", (pixel_size, size), "give one of pixel_size and size, not both")
    if len(shape) == 1:
        if isinstance(pixel_size if size is None else size, (list, tuple)):
            raise InputError("size" if pixel_size is None else "pixel_size", pixel_size if size is None else size,
                             f"{path} is a line scan: give one length")
        if size is not None:
            return (parse_length(size, "size"),)
        return (parse_length(pixel_size, "pixel_size") * shape[0],)
    if size is not None:
        return _pair(size, "size")
    dx, dy = _pair(pixel_size, "pixel_size")
    return (dx * shape[0], dy * shape[1])


def ignored_notes(**given: Any) -> list[str]:
    return [f"{k}={v!r} ignored: the file states it" for k, v in given.items() if v is not None]


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


# ---------------------------------------------------------------------------- native formats
def _from_raw(path: Path, raw: RawTable, *, pixel_size: Any, size: Any, height_unit: str | None,
              lateral_unit: str | None, periodic: bool) -> Surface:
    notes = [f"read {path.name} as plain text ({raw.kind} layout)"]
    if raw.kind in ("xh", "xyz"):
        if lateral_unit is None:
            raise UnitError("lateral_unit", None, f"{path} holds x{' y' if raw.kind == 'xyz' else ''} positions "
                                                  f"without a unit; pass lateral_unit (e.g. lateral_unit='um')")
        hf = need_height_unit(path, height_unit)
        lf = length_unit_factor(lateral_unit, "lateral_unit")
        notes += [f"x, y in {lateral_unit}, heights in {height_unit} (given by the user)"]
        notes += [f"{k}={v!r} ignored: the positions give the lateral scale"
                  for k, v in (("pixel_size", pixel_size), ("size", size)) if v is not None]
        if raw.kind == "xh":
            h, length, note = resample_nonuniform(raw.x, raw.heights)  # type: ignore[arg-type]
            if note:
                notes.append(note)
            return LineScans(h * hf, length * lf, periodic=periodic, source=str(path), notes=tuple(notes))
        dx = float(np.diff(raw.x).mean())  # type: ignore[arg-type]
        dy = float(np.diff(raw.y).mean())  # type: ignore[arg-type]
        nx, ny = raw.heights.shape
        return Topography(raw.heights * hf, (nx * dx * lf, ny * dy * lf), periodic=periodic,
                          source=str(path), notes=tuple(notes))
    return _from_matrix(path, raw.heights, notes, pixel_size=pixel_size, size=size,
                        height_unit=height_unit, periodic=periodic)


def _from_matrix(path: Path, h: NDArray[np.float64], notes: list[str], *, pixel_size: Any, size: Any,
                 height_unit: str | None, periodic: bool) -> Surface:
    if np.isinf(h).any():
        raise FileFormatError(path, "contains infinite heights")
    if np.isnan(h).all():
        raise FileFormatError(path, "all heights are undefined (NaN)")
    hf = need_height_unit(path, height_unit)
    sizes = lateral_size(path, h.shape, pixel_size, size)
    notes.append(f"heights in {height_unit}, size {' × '.join(f'{s:.6g}' for s in sizes)} m (given by the user)")
    try:
        if h.ndim == 1:
            return LineScans(h * hf, sizes[0], periodic=periodic, source=str(path), notes=tuple(notes))
        return Topography(h * hf, (sizes[0], sizes[1]), periodic=periodic, source=str(path), notes=tuple(notes))
    except InputError as exc:
        raise FileFormatError(path, str(exc)) from None


def _read_npy(path: Path, *, pixel_size: Any, size: Any, height_unit: str | None, periodic: bool) -> Surface:
    try:
        a = np.load(path, allow_pickle=False)
    except Exception as exc:  # numpy raises ValueError/OSError/EOFError/... for damaged files
        raise FileFormatError(path, f"not a readable .npy file ({type(exc).__name__}: {exc})") from None
    if not isinstance(a, np.ndarray) or a.dtype.kind not in "iuf":
        raise FileFormatError(path, f".npy holds {getattr(a, 'dtype', type(a))}, not real numbers")
    a = np.asarray(a, dtype=float)
    if a.ndim == 1 and a.size < 4:
        raise FileFormatError(path, f"only {a.size} heights; a profile needs at least 4")
    if a.ndim == 2 and min(a.shape) < 2:
        raise FileFormatError(path, f"array of shape {a.shape}; a map needs at least 2×2 points")
    if a.ndim not in (1, 2):
        raise FileFormatError(path, f"array of shape {a.shape}; expected a 2D height map [x, y] or a 1D profile")
    return _from_matrix(path, a, [f"read {path.name} as .npy array {a.shape}"], pixel_size=pixel_size, size=size,
                        height_unit=height_unit, periodic=periodic)

