"""Instrument formats through SurfaceTopography (optional extra ``sealeak[formats]``).

SurfaceTopography (ContactEngineering, MIT licence) knows dozens of instrument formats; sealeak
uses only its readers, never its spectra (which follow another convention, see THEORY.md §1).
Its exceptions are turned into :class:`~sealeak.errors.FileFormatError` here, at the boundary.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FileFormatError, InputError, UnitError
from ._readers import INSTALL_HINT, Surface, ignored_notes, lateral_size, need_height_unit, resample_nonuniform
from ._types import LineScans, Topography
from ._units import length_unit_factor

__all__ = ["read_external"]


def read_external(path: Path, *, pixel_size: Any, size: Any, height_unit: str | None, lateral_unit: str | None,
                  periodic: bool, channel: int | str | None) -> Surface:
    try:
        from SurfaceTopography import open_topography
    except ImportError:
        raise FileFormatError(path, f"reading this format needs SurfaceTopography: {INSTALL_HINT}") from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            reader = open_topography(str(path))
    except Exception as exc:  # foreign library: many exception types for unknown or damaged files
        raise FileFormatError(path, f"not a recognised topography file ({_why(exc)})") from None
    channels = list(reader.channels)
    if not channels:
        raise FileFormatError(path, "the file holds no data channels")
    index = _channel_index(path, reader, channels, channel)
    ch = channels[index]
    notes = [f"read {path.name} with SurfaceTopography ({type(reader).__name__}), channel {index} {ch.name!r}"]
    unit = ch.unit
    if unit is not None and not isinstance(unit, str):
        raise UnitError("channel", channel, f"{path}: channel {index} {ch.name!r} does not hold heights "
                                            f"(unit {unit!r}); choose a height channel: {_list(channels)}")
    file_sizes = ch.physical_sizes
    kwargs: dict[str, Any] = {"channel_index": index, "periodic": False}
    if file_sizes is None:
        kwargs["physical_sizes"] = tuple(float(n) for n in ch.nb_grid_pts)  # placeholder: replaced below
    if unit is None:
        kwargs["unit"] = "m"  # placeholder: SurfaceTopography wants one; the user's units are applied below
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            topo = reader.topography(**kwargs)
        heights = topo.heights()
        positions = None if topo.is_uniform else topo.positions()
    except Exception as exc:
        raise FileFormatError(path, f"channel {index} cannot be read ({_why(exc)})") from None
    finally:
        close = getattr(reader, "close", None)
        if close is not None:
            try:
                close()
            except Exception:
                pass
    h = np.ma.filled(np.ma.asarray(heights, dtype=float), np.nan)
    if h.size == 0:
        raise FileFormatError(path, "channel holds no data points")
    if np.isinf(h).any():
        raise FileFormatError(path, "channel holds infinite heights")
    if np.isnan(h).all():
        raise FileFormatError(path, "all heights are undefined")
    if np.isnan(h).any():
        notes.append(f"{int(np.isnan(h).sum())} of {h.size} points undefined in the file")

    if unit is None:
        hf = need_height_unit(path, height_unit, f" (read by SurfaceTopography as {_reader_name(reader)})")
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
            if lateral_unit is None:
                raise UnitError("lateral_unit", None, f"{path} states its lateral size without a unit; "
                                                      f"pass lateral_unit (e.g. lateral_unit='um')")
            lf = length_unit_factor(lateral_unit, "lateral_unit")
        else:
            lf = hf
            notes += ignored_notes(pixel_size=pixel_size, size=size, lateral_unit=lateral_unit)
        sizes = tuple(float(s) * lf for s in np.atleast_1d(file_sizes))
    info = getattr(topo, "info", {}) or {}
    instrument = info.get("instrument", {}) if isinstance(info, dict) else {}
    if isinstance(instrument, dict) and instrument.get("name"):
        notes.append(f"instrument: {instrument['name']}")
    source = f"{path} [channel {index}: {ch.name}]" if len(channels) > 1 else str(path)
    try:
        if h.ndim == 1:
            if positions is not None:
                x = np.asarray(positions, dtype=float).ravel()
                order = np.argsort(x, kind="stable")
                x, h = x[order], h[order]
                if (np.diff(x) <= 0).any():
                    raise FileFormatError(path, "line scan with repeated x positions")
                lf_x = sizes[0] / float(x[-1] - x[0]) if file_sizes is None else (hf if unit else lf)
                h, length, note = resample_nonuniform(x, h)
                if note:
                    notes.append(note)
                return LineScans(h * hf, length * lf_x, periodic=periodic, source=source, notes=tuple(notes))
            return LineScans(h * hf, sizes[0], periodic=periodic, source=source, notes=tuple(notes))
        if h.ndim != 2:
            raise FileFormatError(path, f"{h.ndim}D data; expected a map or a line scan")
        return Topography(h * hf, (sizes[0], sizes[1]), periodic=periodic, source=source, notes=tuple(notes))
    except InputError as exc:
        raise FileFormatError(path, str(exc)) from None


def _channel_index(path: Path, reader: Any, channels: list, channel: int | str | None) -> int:
    if channel is None:
        try:
            return int(reader.default_channel.index)
        except Exception:
            return 0
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, bool):
        if 0 <= int(channel) < len(channels):
            return int(channel)
    elif isinstance(channel, str):
        for i, ch in enumerate(channels):
            if str(ch.name).lower() == channel.lower():
                return i
        if channel.isdigit() and int(channel) < len(channels):
            return int(channel)
    raise InputError("channel", channel, f"{path} has channels {_list(channels)}")


def _reader_name(reader: Any) -> str:
    name = type(reader).__name__
    return getattr(reader, "_format", None) or getattr(reader, "name", None) or name


def _list(channels: list) -> str:
    return ", ".join(f"{i}: {ch.name!r}" for i, ch in enumerate(channels))


def _why(exc: Exception) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}: {text[:200]}" if text else type(exc).__name__
