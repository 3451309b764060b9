"""Instrument formats through SurfaceTopography (optional extra ``sealeak[formats]``).

SurfaceTopography (ContactEngineering, MIT licence) knows dozens of instrument formats; sealeak
uses only its readers, never its spectra (which follow another convention, see docs/theory.md §1.6).
Its exceptions are turned into :class:`~sealeak.errors.FileFormatError` here, at the boundary, and
its (and its dependencies') warnings and log output are kept from the user's terminal: a damaged
file gives one clear message, not megabytes of a foreign library's debugging output.

Format detection by content alone can mistake a damaged file for another format; SRTM ``.hgt``
elevation tiles in particular are recognised by their size alone (2n² bytes), so that reader is
accepted only for files named ``.hgt``. When detection fails, the reader the file's suffix names
is asked directly, for its own explanation (e.g. "probably truncated").
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FileFormatError, InputError, UnitError
from ._common import INSTALL_HINT, Surface, check_lengths, check_points, ignored_notes, lateral_size, mark_no_data, require_units, resample_nonuniform
from ._types import LineScans, Topography
from ._units import length_unit_factor, option_name

__all__ = ["read_external"]

# packages SurfaceTopography uses to read files; their loggers are silenced while it reads
_FOREIGN_LOGGERS = ("SurfaceTopography", "igor2", "NuMPI", "muFFT", "netCDF4", "h5py", "PIL", "tifffile",
                    "openpyxl", "xarray", "zarr")
_CONTENT_ONLY_FORMATS = {"hgt": ".hgt"}  # readers that recognise a file by its size: only with their suffix


@contextmanager
def _quiet() -> Iterator[None]:
    """Silence warnings and the log output of the foreign packages for the duration of a read."""
    loggers = [logging.getLogger(name) for name in _FOREIGN_LOGGERS]
    saved = [(lg.level, lg.disabled) for lg in loggers]
    try:
        for lg in loggers:
            lg.setLevel(logging.CRITICAL + 1)
            lg.disabled = True
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        for lg, (level, disabled) in zip(loggers, saved):
            lg.setLevel(level)
            lg.disabled = disabled


def _suffix_readers(path: Path) -> list[Any]:
    try:
        from SurfaceTopography.IO import readers
    except ImportError:  # pragma: no cover - checked by the caller
        return []
    suffix = path.suffix.lower().lstrip(".")
    out = []
    for r in readers:
        try:
            if suffix and suffix in [e.lower() for e in r.file_extensions()]:
                out.append(r)
        except Exception:
            continue
    return out


def _format_name(reader_class: Any) -> str:
    try:
        return str(reader_class.name())
    except Exception:
        return type(reader_class).__name__ if not isinstance(reader_class, type) else reader_class.__name__


def _open(path: Path) -> Any:
    """SurfaceTopography's reader for ``path`` or a FileFormatError with the most specific reason."""
    from SurfaceTopography import open_topography

    problem = None
    with _quiet():
        try:
            reader = open_topography(str(path))
        except Exception as exc:  # foreign library: many exception types for unknown or damaged files
            reader, problem = None, _why(exc)
        if reader is not None:
            fmt = _reader_format(reader)
            wanted = _CONTENT_ONLY_FORMATS.get(fmt)
            if wanted is None or path.suffix.lower() == wanted:
                return reader
            _close(reader)
            problem = f"its content matches only the {fmt!r} format, which needs the suffix {wanted}"
        # ask the reader(s) the suffix names for their own explanation
        reasons = []
        for r in _suffix_readers(path):
            fmt_r = _reader_format(r)
            if fmt_r in _CONTENT_ONLY_FORMATS:
                continue
            try:
                reader = open_topography(str(path), format=fmt_r)
            except Exception as exc:
                reasons.append(f"as {_format_name(r)}: {_why(exc, with_type=False)}")
                continue
            return reader
    if reasons:
        text = "; ".join(reasons)
        hint = "" if any(w in text.lower() for w in ("truncated", "damaged", "corrupt")) else \
            " (the file may be truncated or damaged)"
        raise FileFormatError(path, f"cannot be read {text}{hint}")
    raise FileFormatError(path, f"not a recognised topography file ({problem})")


def _reader_format(reader: Any) -> str:
    try:
        return str(reader.format())
    except Exception:
        return type(reader).__name__


def _close(reader: Any) -> None:
    close = getattr(reader, "close", None)
    if close is not None:
        try:
            close()
        except Exception:
            pass


def read_external(path: Path, *, pixel_size: Any, size: Any, height_unit: str | None, lateral_unit: str | None,
                  periodic: bool, channel: int | str | None) -> Surface:
    try:
        with _quiet():  # its MPI layer warns on import when mpi4py is absent
            import SurfaceTopography  # noqa: F401
    except ImportError:
        raise FileFormatError(path, f"reading this format needs SurfaceTopography: {INSTALL_HINT}") from None
    reader = _open(path)
    try:
        return _read(path, reader, pixel_size=pixel_size, size=size, height_unit=height_unit,
                     lateral_unit=lateral_unit, periodic=periodic, channel=channel)
    finally:
        _close(reader)


def _read(path: Path, reader: Any, *, pixel_size: Any, size: Any, height_unit: str | None, lateral_unit: str | None,
          periodic: bool, channel: int | str | None) -> Surface:
    names = _channel_names(path, reader)
    if not names:
        raise FileFormatError(path, "the file holds no data channels (it may be truncated or damaged)")
    index = _channel_index(path, reader, names, channel)
    ch = _channel(path, reader, index)
    notes = [f"read {path.name} with SurfaceTopography ({type(reader).__name__}), channel {index} {ch.name!r}"]
    unit = ch.unit
    if unit is not None and not isinstance(unit, str):
        raise UnitError(option_name("channel"), channel, f"{path}: channel {index} {ch.name!r} does not hold heights "
                                                         f"(unit {_short(unit)}); choose a height channel: {_list(names)}")
    file_sizes = ch.physical_sizes
    check_points(path, ch.nb_grid_pts)  # before the data are read (a compressed file can expand)
    is_profile = len(ch.nb_grid_pts) == 1
    # everything the user must give, in one message
    require_units(path, height=unit is None and height_unit is None,
                  size=file_sizes is None and pixel_size is None and size is None,
                  lateral=file_sizes is not None and unit is None and lateral_unit is None,
                  how=f" (read by SurfaceTopography as {_reader_name(reader)}{', a line scan' if is_profile else ''})")
    kwargs: dict[str, Any] = {"channel_index": index, "periodic": False}
    if file_sizes is None:
        kwargs["physical_sizes"] = tuple(float(n) for n in ch.nb_grid_pts)  # placeholder: replaced below
    if unit is None:
        kwargs["unit"] = "m"  # placeholder: SurfaceTopography wants one; the user's units are applied below
    try:  # everything SurfaceTopography computes, and the conversion of what it returns
        with _quiet():
            topo = reader.topography(**kwargs)
            heights = topo.heights()
            positions = None if topo.is_uniform else np.asarray(topo.positions(), dtype=float)
            h: np.ndarray = np.asarray(np.ma.filled(np.ma.asarray(heights, dtype=float), np.nan), dtype=float)
            info = getattr(topo, "info", {}) or {}
            instrument = info.get("instrument", {}) if isinstance(info, dict) else {}
            instrument_name = str(instrument["name"]) if isinstance(instrument, dict) and instrument.get("name") else None
    except Exception as exc:  # noqa: BLE001 - a damaged file makes the foreign reader raise anything
        raise FileFormatError(path, f"channel {index} cannot be read ({_why(exc)})") from None
    if h.size == 0:
        raise FileFormatError(path, "channel holds no data points")
    if np.isnan(h).all():
        raise FileFormatError(path, "all heights are undefined")
    if np.isnan(h).any():
        notes.append(f"{int(np.isnan(h).sum())} of {h.size} points undefined in the file")
    h, warning = mark_no_data(path, h)
    warned = (warning,) if warning else ()

    if unit is None:
        hf = length_unit_factor(height_unit, option_name("height_unit"))  # type: ignore[arg-type]
        notes.append(f"heights in {height_unit} (given by the user; the file states no unit)")
    else:
        hf = length_unit_factor(unit, f"{path.name} unit")
        notes.append(f"unit {unit!r} from the file")
        notes += ignored_notes(height_unit=height_unit)
    if file_sizes is None:
        sizes = lateral_size(path, h.shape if positions is None else (h.size,), pixel_size, size)
        notes.append("lateral size given by the user (the file states none)")
    else:
        if unit is None:
            lf = length_unit_factor(lateral_unit, option_name("lateral_unit"))  # type: ignore[arg-type]
        else:
            lf = hf
            notes += ignored_notes(pixel_size=pixel_size, size=size, lateral_unit=lateral_unit)
        sizes = tuple(s * lf for s in file_sizes)
        check_lengths(path, "physical size", sizes)
    if instrument_name:
        notes.append(f"instrument: {_printable(instrument_name)}")
    source = f"{path} [channel {index}: {ch.name}]" if len(names) > 1 else str(path)
    resolution = _resolution(topo, hf if unit is not None else None, notes)  # ST states it in the file unit
    try:
        if h.ndim == 1:
            if positions is not None:
                x = positions.ravel()
                order = np.argsort(x, kind="stable")
                x, h = x[order], h[order]
                if (np.diff(x) <= 0).any():
                    raise FileFormatError(path, "line scan with repeated x positions")
                lf_x = sizes[0] / float(x[-1] - x[0]) if file_sizes is None else (hf if unit else lf)
                h, length, note = resample_nonuniform(x, h)
                check_lengths(path, "line scan length (from its x positions)", (length * lf_x,))
                if note:
                    notes.append(note)
                return LineScans(heights=h * hf, length=length * lf_x, periodic=periodic, source=source,
                                 notes=tuple(notes),
                                 resolution=resolution, warnings=warned)
            return LineScans(heights=h * hf, length=sizes[0], periodic=periodic, source=source, notes=tuple(notes),
                             resolution=resolution, warnings=warned)
        if h.ndim != 2:
            raise FileFormatError(path, f"{h.ndim}D data; expected a map or a line scan")
        return Topography(heights=h * hf, size=(sizes[0], sizes[1]), periodic=periodic, source=source,
                          notes=tuple(notes),
                          resolution=resolution, warnings=warned)
    except InputError as exc:
        raise FileFormatError(path, str(exc)) from None


def _resolution(topo: Any, lateral_factor: float | None, notes: list[str]) -> float | None:
    """Shortest reliable wavelength (m) the file's instrument parameters give (tip radius, resolution)."""
    if lateral_factor is None:
        return None
    try:
        with _quiet():
            cutoff = topo.short_reliability_cutoff()
    except Exception as exc:
        notes.append(f"the instrument's reliability cutoff could not be evaluated ({_why(exc)})")
        return None
    if cutoff is None:
        return None
    value = float(cutoff) * lateral_factor
    if not (np.isfinite(value) and value > 0):
        return None
    params: dict[str, Any] = {}
    try:
        params = (topo.info.get("instrument", {}) or {}).get("parameters", {}) or {}
    except Exception:
        pass
    why = ("tip radius " + _quantity(params["tip_radius"]) if "tip_radius" in params
           else "resolution " + _quantity(params["resolution"]) if "resolution" in params else "instrument")
    notes.append(f"shortest reliable wavelength {value:.4g} m from the file's {why}")
    return value


def _quantity(d: Any) -> str:
    try:
        return f"{d['value']} {d['unit']}"
    except Exception:
        return str(d)


def _channel_index(path: Path, reader: Any, names: list[str], channel: int | str | None) -> int:
    if channel is None:
        try:
            with _quiet():
                return int(reader.default_channel.index)
        except Exception:
            return 0
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, bool):
        if 0 <= int(channel) < len(names):
            return int(channel)
    elif isinstance(channel, str):
        for i, name in enumerate(names):
            if name.lower() == channel.lower():
                return i
        if channel.isdigit() and int(channel) < len(names):
            return int(channel)
    raise InputError(option_name("channel"), channel, f"{path} has channels {_list(names)}")


@dataclass(frozen=True)
class _Channel:
    """What SurfaceTopography says of a channel before its data are read, as plain values."""

    name: str
    unit: Any  # a length unit (str), None (not stated), or something else (not heights)
    nb_grid_pts: tuple[int, ...]
    physical_sizes: tuple[float, ...] | None  # in the channel's (lateral) unit; None: not stated


def _unreadable(path: Path, exc: Exception) -> FileFormatError:
    """The error for a file SurfaceTopography fails on while parsing it (damaged header or data)."""
    return FileFormatError(path, f"cannot be read: SurfaceTopography failed to parse it ({_why(exc)}); the file may be "
                                 f"truncated or damaged")


def _channel_names(path: Path, reader: Any) -> list[str]:
    """The names of the file's channels: parsing its header, SurfaceTopography may fail on a damaged file."""
    try:
        with _quiet():
            return [_printable(str(ch.name)) for ch in reader.channels]
    except Exception as exc:  # noqa: BLE001 - a foreign reader on a damaged file raises anything
        raise _unreadable(path, exc) from None


def _channel(path: Path, reader: Any, index: int) -> _Channel:
    """Channel ``index`` as plain values, checked: a damaged header fails here, before any data are read."""
    try:
        with _quiet():
            ch = list(reader.channels)[index]
            name, unit, grid, sizes = _printable(str(ch.name)), ch.unit, ch.nb_grid_pts, ch.physical_sizes
            nb_grid_pts = tuple(int(n) for n in np.ravel(grid))
            physical_sizes = None if sizes is None else tuple(float(v) for v in np.ravel(sizes))
    except Exception as exc:  # noqa: BLE001 - a foreign reader on a damaged file raises anything
        raise _unreadable(path, exc) from None
    shown = " × ".join(str(n) for n in nb_grid_pts)
    if len(nb_grid_pts) not in (1, 2) or min(nb_grid_pts) < 1:
        raise FileFormatError(path, f"channel {index} declares a grid of {shown or 'no'} points; expected a map "
                                    f"(nx × ny) or a line scan (n), at least 1 each (the file may be damaged)")
    if physical_sizes is not None and len(physical_sizes) != len(nb_grid_pts):
        raise FileFormatError(path, f"channel {index} states {len(physical_sizes)} physical size(s) for a grid of "
                                    f"{shown} points (the file may be damaged)")
    return _Channel(name=name, unit=unit, nb_grid_pts=nb_grid_pts, physical_sizes=physical_sizes)


def _reader_name(reader: Any) -> str:
    name = type(reader).__name__
    return getattr(reader, "_format", None) or getattr(reader, "name", None) or name


def _list(names: list[str]) -> str:
    return ", ".join(f"{i}: {name!r}" for i, name in enumerate(names))


def _printable(text: str, limit: int = 200) -> str:
    """``text`` of a foreign file as one line of at most ``limit`` characters ('?' for what does not print)."""
    return "".join(c if c.isprintable() else "?" for c in text[:limit])


def _short(value: Any) -> str:
    """A foreign value in one short line."""
    return _printable(repr(value), 80)


def _why(exc: Exception, with_type: bool = True) -> str:
    lines = [ln.strip() for ln in str(exc).strip().splitlines() if ln.strip()]
    text = lines[0] if lines else ""
    if text.endswith(":") and len(lines) > 1:  # "tried XReader:" followed by the reason
        text = f"{text} {lines[1]}"
    text = _printable(text)
    if not with_type:
        return text or type(exc).__name__
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__
