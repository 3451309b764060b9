"""read_topography: instrument files (through SurfaceTopography) and plain formats (native).

Native formats: plain numeric text (see :mod:`._text`), NumPy ``.npy`` (a 2D height matrix [x, y]
or a 1D profile) and ``.npz`` (array ``heights``, optionally ``size`` in m, ``height_unit``,
``periodic``). Units and size come from the file where it states them: header comments of text
files (``# size: 1 mm``, ``# height_unit: um``, see :mod:`._text`), the arrays of a ``.npz``, or a
sidecar ``NAME.npy.json`` next to a ``.npy`` (``{"size": [sx, sy], "height_unit": "m",
"periodic": true, "shape": [nx, ny]}``), as ``sealeak surface synthesize`` writes them.
Otherwise the caller must give them (``height_unit`` and the lateral scale: ``pixel_size`` or
``size`` for matrices and profiles, ``lateral_unit`` for x/y columns); one error names all that
is missing. Everything else goes to SurfaceTopography (optional extra ``sealeak[formats]``),
which reads the physical size and unit from the file's metadata.
"""

from __future__ import annotations

import importlib.util
import json
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypedDict

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, InputError
from ..io.files import input_file
from ._common import (
    INSTALL_HINT,
    LengthLike,
    Surface,
    check_lengths,
    check_points,
    ignored_notes,
    lateral_size,
    mark_no_data,
    npy_header,
    require_units,
    resample_nonuniform,
)
from ._external import read_external
from ._text import MAX_TEXT_BYTES, NotPlainText, RawTable, looks_binary, parse_text
from ._types import LineScans, Topography
from ._units import length_unit_factor, option_name, parse_length

__all__ = ["read_topography", "ReadOptions", "Surface", "LengthLike", "sidecar_path"]


TEXT_SUFFIXES = {".txt", ".csv", ".asc", ".xyz", ".dat", ".tsv", ""}


class ReadOptions(TypedDict, total=False):
    """The keyword options of :func:`read_topography` (each optional; what they mean is said there)."""

    pixel_size: LengthLike | Sequence[LengthLike] | None
    size: LengthLike | Sequence[LengthLike] | None
    height_unit: str | None
    lateral_unit: str | None
    periodic: bool
    channel: int | str | None


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

    Values the file states itself win (instrument metadata, text header lines, ``.npz`` arrays, a
    ``.npy.json`` sidecar); a user value the file overrides is recorded in ``notes``. Missing units
    are never guessed: one :class:`~sealeak.topography.MissingUnitsError` (a
    :class:`~sealeak.errors.UnitError`) names the file and every option to pass (keyword arguments,
    or command-line flags inside :func:`~sealeak.topography.cli_option_names`). Unreadable files
    raise :class:`~sealeak.errors.FileFormatError`.

    Parameters
    ----------
    path:
        The file. ``.npy``, ``.npz`` and plain numeric text are read natively; instrument formats
        (Alicona, Bruker/Veeco, Zygo, Sensofar, Digital Surf, x3p, Dektak csv, ...) through
        SurfaceTopography.
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

    Returns
    -------
    Topography or LineScans
        Heights in m: a map h[x, y] with size (sx, sy), or line scans with their length. Profiles
        with non-uniform x are linearly interpolated onto a uniform grid of as many points (noted).
        NaN marks undefined points; so do instruments' no-data markers (±inf, or values of magnitude
        1e30 or more in the file's unit, such as 1e300 or -1e38), with a sentence in ``warnings``.
    """
    p = Path(path)
    if not p.exists():
        raise FileFormatError(p, "no such file")
    if p.is_dir():
        raise FileFormatError(p, "is a directory, not a file")
    p = input_file(p, "topography file")  # a FIFO or device would block or never end
    try:
        with open(p, "rb") as fh:
            data = fh.read(4096)
    except OSError as exc:
        raise FileFormatError(p, f"cannot be read ({exc.strerror})") from None
    if not data:
        raise FileFormatError(p, "empty file (0 bytes)")
    if p.suffix.lower() == ".npy":
        return _read_npy(p, pixel_size=pixel_size, size=size, height_unit=height_unit, periodic=periodic)
    if p.suffix.lower() == ".npz":
        return _read_npz(p, pixel_size=pixel_size, size=size, height_unit=height_unit, periodic=periodic)
    if p.suffix.lower() in TEXT_SUFFIXES and not looks_binary(data):
        if p.stat().st_size > MAX_TEXT_BYTES:  # refused before it is read into memory
            raise FileFormatError(p, f"text file of {p.stat().st_size / 2**20:.0f} MiB is larger than the "
                                     f"{MAX_TEXT_BYTES / 2**20:.0f} MiB the text reader accepts; save it as .npy")
        full = p.read_bytes()
        try:
            raw = parse_text(p, full)
        except NotPlainText as native_error:
            if not _have_surfacetopography():
                raise FileFormatError(p, f"{native_error.problem}; if this is an instrument export "
                                         f"(e.g. Dektak csv), install the reader extra: {INSTALL_HINT}") from None
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
    return read_external(p, pixel_size=pixel_size, size=size, height_unit=height_unit,
                         lateral_unit=lateral_unit, periodic=periodic, channel=channel)


def _have_surfacetopography() -> bool:
    return importlib.util.find_spec("SurfaceTopography") is not None


@dataclass
class _Stated:
    """Units and size a native file states (header comments, .npz arrays, .npy sidecar)."""

    origin: str = ""
    size: Any = None
    pixel_size: Any = None
    height_unit: str | None = None
    lateral_unit: str | None = None
    periodic: bool | None = None


def _lengths_text(value: str) -> Any:
    parts = [v.strip() for v in value.split(",") if v.strip()]
    if not 1 <= len(parts) <= 2:
        raise ValueError("one length or two separated by a comma, e.g. '1 mm, 0.5 mm'")
    return parts[0] if len(parts) == 1 else (parts[0], parts[1])


def _bool_text(value: Any) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    text = str(value).strip().lower()
    if text in ("true", "yes", "1"):
        return True
    if text in ("false", "no", "0"):
        return False
    raise ValueError("true or false")


def _stated(path: Path, origin: str, items: dict[str, tuple[str, Any]]) -> _Stated:
    """Validate stated values; ``items``: key -> (where, value). Problems name the file and where."""
    out = _Stated(origin=origin)
    for key, (where, value) in items.items():
        try:
            if key in ("size", "pixel_size"):
                v = _lengths_text(value) if isinstance(value, str) else value
                if isinstance(v, (list, tuple, np.ndarray)):
                    if not 1 <= len(v if not isinstance(v, np.ndarray) else v.ravel()) <= 2:
                        raise ValueError("one length or two (x, y)")
                    v = tuple(np.asarray(v).ravel().tolist()) if not isinstance(v, tuple) else v
                    v = tuple(parse_length(x, key) for x in v)
                    v = v[0] if len(v) == 1 else v
                else:
                    v = parse_length(v, key)
                setattr(out, key, v)
            elif key in ("height_unit", "lateral_unit"):
                if not isinstance(value, str):
                    raise ValueError("a unit name such as 'um'")
                length_unit_factor(value, key)
                setattr(out, key, value.strip())
            elif key == "periodic":
                out.periodic = _bool_text(value)
        except (ValueError, InputError) as exc:
            raise FileFormatError(path, f"{where}: {key} = {_shown(value)} cannot be used ({_one_line(str(exc))})") from None
    if out.size is not None and out.pixel_size is not None:
        raise FileFormatError(path, f"{origin} states both size and pixel_size; keep one")
    return out


def _shown(value: Any) -> str:
    """A value a file states, in one short line: an array of more than two values by its shape and type."""
    if isinstance(value, np.ndarray) and value.size > 2:
        return f"an array of shape {value.shape} ({value.dtype})"
    if isinstance(value, np.ndarray):
        value = value.tolist()
    return _one_line(repr(value))


def _one_line(text: str, limit: int = 120) -> str:
    """``text`` as one line of at most ``limit`` characters (escapes for what does not print)."""
    if not text.isprintable():
        text = text.encode("unicode_escape").decode("ascii")
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _merge(stated: _Stated, *, pixel_size: Any, size: Any, height_unit: str | None, lateral_unit: str | None,
           periodic: bool) -> tuple[Any, Any, str | None, str | None, bool, list[str]]:
    """The user's options with what the file states taking precedence (noted)."""
    notes: list[str] = []
    said = [k for k in ("size", "pixel_size", "height_unit", "lateral_unit", "periodic")
            if getattr(stated, k) is not None]
    if said:
        notes.append(f"{', '.join(said)} from {stated.origin}")
    if stated.size is not None or stated.pixel_size is not None:
        notes += ignored_notes(size=size, pixel_size=pixel_size)
        size, pixel_size = stated.size, stated.pixel_size
    if stated.height_unit is not None:
        notes += ignored_notes(height_unit=height_unit)
        height_unit = stated.height_unit
    if stated.lateral_unit is not None:
        notes += ignored_notes(lateral_unit=lateral_unit)
        lateral_unit = stated.lateral_unit
    if stated.periodic is not None:
        if periodic and not stated.periodic:
            notes.append(f"{option_name('periodic')} ignored: the file states the map is not periodic")
        periodic = stated.periodic
    return pixel_size, size, height_unit, lateral_unit, periodic, notes


def sidecar_path(path: str | Path) -> Path:
    """``map.npy`` -> ``map.npy.json``: the units and size of a ``.npy`` height map."""
    p = Path(path)
    return p.with_name(p.name + ".json")


def _from_raw(path: Path, raw: RawTable, *, pixel_size: Any, size: Any, height_unit: str | None,
              lateral_unit: str | None, periodic: bool) -> Surface:
    notes = [f"read {path.name} as plain text ({raw.kind} layout)"]
    if raw.meta:
        stated = _stated(path, "the file's header", {k: (f"line {n}", v) for k, (n, v) in raw.meta.items()})
        pixel_size, size, height_unit, lateral_unit, periodic, more = _merge(
            stated, pixel_size=pixel_size, size=size, height_unit=height_unit, lateral_unit=lateral_unit,
            periodic=periodic)
        notes += more
    if raw.kind in ("xh", "xyz"):
        require_units(path, height=height_unit is None, lateral=lateral_unit is None)
        hf = length_unit_factor(height_unit, option_name("height_unit"))  # type: ignore[arg-type]
        lf = length_unit_factor(lateral_unit, option_name("lateral_unit"))  # type: ignore[arg-type]
        notes += [f"x, y in {lateral_unit}, heights in {height_unit}"]
        notes += [f"{option_name(k)} {v!r} ignored: the positions give the lateral scale"
                  for k, v in (("pixel_size", pixel_size), ("size", size)) if v is not None]
        heights, warning = mark_no_data(path, raw.heights)
        warned = (warning,) if warning else ()
        if raw.kind == "xh":
            if int(np.isfinite(heights).sum()) < 4:
                raise FileFormatError(path, "x h columns: fewer than 4 defined heights")
            h, length, note = resample_nonuniform(raw.x, heights)  # type: ignore[arg-type]
            check_lengths(path, f"profile length (x column × {option_name('lateral_unit')})", (length * lf,))
            if note:
                notes.append(note)
            return LineScans(heights=h * hf, length=length * lf, periodic=periodic, source=str(path),
                             notes=tuple(notes),
                             warnings=warned)
        assert raw.x is not None and raw.y is not None  # an x y h table
        dx = float(np.diff(raw.x).mean())
        dy = float(np.diff(raw.y).mean())
        nx, ny = heights.shape
        check_lengths(path, f"map size (x, y columns × {option_name('lateral_unit')})", (nx * dx * lf, ny * dy * lf))
        return Topography(heights=heights * hf, size=(nx * dx * lf, ny * dy * lf), periodic=periodic,
                          source=str(path), notes=tuple(notes), warnings=warned)
    return _from_matrix(path, raw.heights, notes, pixel_size=pixel_size, size=size,
                        height_unit=height_unit, periodic=periodic)


def _from_matrix(path: Path, h: NDArray[np.float64], notes: list[str], *, pixel_size: Any, size: Any,
                 height_unit: str | None, periodic: bool) -> Surface:
    if np.isnan(h).all():
        raise FileFormatError(path, "all heights are undefined (NaN)")
    h, warning = mark_no_data(path, h)
    warned = (warning,) if warning else ()
    require_units(path, height=height_unit is None, size=pixel_size is None and size is None)
    hf = length_unit_factor(height_unit, option_name("height_unit"))  # type: ignore[arg-type]
    sizes = lateral_size(path, h.shape, pixel_size, size)
    check_lengths(path, "size (pixel size × points)" if pixel_size is not None else "size", sizes)
    notes.append(f"heights in {height_unit}, size {' × '.join(f'{s:.6g}' for s in sizes)} m")
    try:
        if h.ndim == 1:
            return LineScans(heights=h * hf, length=sizes[0], periodic=periodic, source=str(path), notes=tuple(notes),
                             warnings=warned)
        return Topography(heights=h * hf, size=(sizes[0], sizes[1]), periodic=periodic, source=str(path),
                          notes=tuple(notes),
                          warnings=warned)
    except InputError as exc:
        raise FileFormatError(path, str(exc)) from None


def _check_array(path: Path, a: Any, what: str) -> NDArray[np.float64]:
    if not isinstance(a, np.ndarray) or a.dtype.kind not in "iuf":
        raise FileFormatError(path, f"{what} holds {getattr(a, 'dtype', type(a))}, not real numbers")
    a = np.asarray(a, dtype=float)
    if a.ndim == 1 and a.size < 4:
        raise FileFormatError(path, f"only {a.size} heights; a profile needs at least 4")
    if a.ndim == 2 and min(a.shape) < 2:
        raise FileFormatError(path, f"array of shape {a.shape}; a map needs at least 2×2 points")
    if a.ndim not in (1, 2):
        raise FileFormatError(path, f"array of shape {a.shape}; expected a 2D height map [x, y] or a 1D profile")
    return a


def _read_sidecar(path: Path, shape: tuple[int, ...]) -> _Stated | None:
    side = sidecar_path(path)
    if not side.is_file():
        return None
    try:
        doc = json.loads(side.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise FileFormatError(side, f"not a readable JSON description of {path.name} ({exc})") from None
    if not isinstance(doc, dict):
        raise FileFormatError(side, f"expected a JSON object describing {path.name}")
    if "shape" in doc:
        stated_shape = doc["shape"]
        if not (isinstance(stated_shape, list) and all(isinstance(k, int) for k in stated_shape)):
            raise FileFormatError(side, f"shape = {stated_shape!r}: a list of whole numbers such as {list(shape)}")
        if stated_shape != list(shape):
            raise FileFormatError(side, f"describes a map of shape {stated_shape} but {path.name} holds "
                                        f"{list(shape)}; it belongs to another file: delete or fix it")
    keys = ("size", "pixel_size", "height_unit", "periodic")
    return _stated(side, side.name, {k: ("sidecar", doc[k]) for k in keys if k in doc})


#: The arrays of a height-map ``.npz`` besides ``heights``; a file with many more is refused before reading.
_NPZ_KEYS = ("size", "pixel_size", "height_unit", "periodic")
_NPZ_KEYS_MAX = 16


def _check_declared(path: Path, members: bool) -> None:
    """Refuse an ``.npy`` (or each array of an ``.npz``: ``members``) that declares more than MAX_POINTS heights,
    before its data are read or decompressed. A header that cannot be read is left to :func:`numpy.load`."""
    try:
        if not members:
            with open(path, "rb") as fh:
                shapes = [npy_header(fh)[0]]
        else:
            with zipfile.ZipFile(path) as z:
                names = z.namelist()
                if len(names) > _NPZ_KEYS_MAX:
                    raise FileFormatError(path, f".npz holds {len(names)} arrays; a height map file holds 'heights' "
                                                f"and at most {', '.join(_NPZ_KEYS)}")
                shapes = []
                for name in names:
                    with z.open(name) as fh:
                        shapes.append(npy_header(fh)[0])
    except FileFormatError:
        raise
    except Exception:  # noqa: BLE001 - damaged headers are reported by numpy.load below, in its words
        return
    for shape in shapes:
        check_points(path, shape)


def _read_npy(path: Path, *, pixel_size: Any, size: Any, height_unit: str | None, periodic: bool) -> Surface:
    _check_declared(path, members=False)
    try:
        a = np.load(path, allow_pickle=False)
    except Exception as exc:  # numpy raises ValueError/OSError/EOFError/... for damaged files
        raise FileFormatError(path, f"not a readable .npy file ({type(exc).__name__}: {exc})") from None
    a = _check_array(path, a, ".npy")
    notes = [f"read {path.name} as .npy array {a.shape}"]
    stated = _read_sidecar(path, a.shape)
    if stated is not None:
        pixel_size, size, height_unit, _, periodic, more = _merge(
            stated, pixel_size=pixel_size, size=size, height_unit=height_unit, lateral_unit=None, periodic=periodic)
        notes += more
    return _from_matrix(path, a, notes, pixel_size=pixel_size, size=size, height_unit=height_unit, periodic=periodic)


def _read_npz(path: Path, *, pixel_size: Any, size: Any, height_unit: str | None, periodic: bool) -> Surface:
    _check_declared(path, members=True)
    try:
        with np.load(path, allow_pickle=False) as z:  # the height map and its description only
            names = list(z.files)
            wanted = set(z.files) if len(z.files) == 1 else {"heights", *_NPZ_KEYS}
            arrays = {k: z[k] for k in z.files if k in wanted}
    except Exception as exc:  # zipfile.BadZipFile, ValueError, OSError, EOFError, ...
        raise FileFormatError(path, f"not a readable .npz file ({type(exc).__name__}: {exc})") from None
    if "heights" in arrays:
        a = arrays["heights"]
    elif len(arrays) == 1 and not set(arrays) & set(_NPZ_KEYS):
        a = next(iter(arrays.values()))
    else:
        raise FileFormatError(path, f".npz holds arrays {sorted(names)}; the height map must be named 'heights'")
    a = _check_array(path, a, ".npz array 'heights'")
    items: dict[str, tuple[str, Any]] = {}
    for key in _NPZ_KEYS:
        if key in arrays:
            v = arrays[key]
            items[key] = (f"array {key!r}", v.item() if v.ndim == 0 else v)
    notes = [f"read {path.name} as .npz array 'heights' {a.shape}"]
    if items:
        stated = _stated(path, f"the arrays of {path.name}", items)
        pixel_size, size, height_unit, _, periodic, more = _merge(
            stated, pixel_size=pixel_size, size=size, height_unit=height_unit, lateral_unit=None, periodic=periodic)
        notes += more
    return _from_matrix(path, a, notes, pixel_size=pixel_size, size=size, height_unit=height_unit, periodic=periodic)
