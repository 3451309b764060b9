"""Writing height maps in the formats :func:`read_topography` reads back with their size and units.

* ``.npz``: arrays ``heights`` (m, [x, y]), ``size`` (m, (sx, sy)), ``height_unit`` ("m") and
  ``periodic``: one self-describing file.
* ``.npy``: the bare array h[x, y] in m (readable by any NumPy program) and a sidecar
  ``NAME.npy.json`` with ``size``, ``height_unit``, ``periodic`` and ``shape``.
* ``.txt`` / ``.csv``: a matrix with one row per y and one column per x (the layout the text
  reader and SurfaceTopography use), after header comments ``# size: ...``,
  ``# height_unit: m``, ``# periodic: true``.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..io.files import atomic_write
from ._readers import sidecar_path

__all__ = ["write_height_map", "HEIGHT_MAP_SUFFIXES", "height_map_outputs"]

HEIGHT_MAP_SUFFIXES = (".npy", ".npz", ".txt", ".csv")


def height_map_outputs(path: str | Path) -> list[Path]:
    """The files :func:`write_height_map` writes for ``path`` (the map, and the sidecar of a .npy)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in HEIGHT_MAP_SUFFIXES:
        raise InputError("output", str(p), f"must end in {', '.join(HEIGHT_MAP_SUFFIXES)}")
    return [p, sidecar_path(p)] if suffix == ".npy" else [p]


def write_height_map(path: str | Path, heights: NDArray[np.float64], size: tuple[float, float], *,
                     periodic: bool = False, comments: Sequence[str] = ()) -> list[Path]:
    """Write h[x, y] (m) of physical size (sx, sy) (m); returns the files written.

    ``comments``: extra lines (provenance) for the header of text files and the sidecar of .npy.
    Each file is written atomically (a temporary file renamed into place).
    """
    outputs = height_map_outputs(path)
    p = outputs[0]
    h = np.asarray(heights, dtype=float)
    if h.ndim != 2:
        raise InputError("heights", f"shape {h.shape}", "a 2D map")
    sx, sy = (float(v) for v in size)
    suffix = p.suffix.lower()

    if suffix == ".npz":
        with atomic_write(p) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, heights=h, size=np.array([sx, sy]), height_unit=np.array("m"),
                     periodic=np.array(bool(periodic)))
    elif suffix == ".npy":
        with atomic_write(p) as tmp, open(tmp, "wb") as fh:
            np.save(fh, h)
        doc = {"description": f"height map {p.name}: h[i, j] in m at x_i = i·size[0]/shape[0], "
                              f"y_j = j·size[1]/shape[1]",
               "size": [sx, sy], "height_unit": "m", "periodic": bool(periodic), "shape": list(h.shape),
               "notes": list(comments)}
        with atomic_write(outputs[1]) as tmp:
            Path(tmp).write_text(json.dumps(doc, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    else:
        nx, ny = h.shape
        if nx < 4 or ny < 2:  # fewer columns read back as x h / x y h columns or a line scan
            raise InputError("heights", f"a {nx} x {ny} map",
                             f"too small for a text height map ({p.name}): at least 4 x 2 points; write .npz instead")
        header = [f"height map: {nx} x {ny} points; one row per y, one column per x; heights in m",
                  *comments,
                  f"size: {sx:.17g} m, {sy:.17g} m",
                  "height_unit: m",
                  f"periodic: {'true' if periodic else 'false'}"]
        with atomic_write(p) as tmp:
            np.savetxt(tmp, h.T, fmt="%.17g", header="\n".join(header), comments="# ",
                       delimiter="," if suffix == ".csv" else " ", encoding="utf-8")
    return outputs
