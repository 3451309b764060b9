"""The field maps of a task store in Zarr (v3): each task writes its own group, atomically, and a checksum of it.

A store folder ``DIR`` (:class:`sealeak.cases.ensemble.TaskStore`) that keeps fields holds one Zarr
hierarchy ``DIR/fields.zarr``. Its root group is made once by the client; every task that writes fields
makes its own group in it, ``DIR/fields.zarr/<group>`` (``r0``, ``r1``, ...), with

- ``height`` [x, y] (m), the random surface;
- ``gap`` [load, x, y] (m) and ``pressure`` [load, x, y] (Pa, the contact pressure), one map per load
  (squeeze pressure, or an O-ring's compression);
- the coordinates ``x``, ``y`` (m, cell centres (i + 1/2) L/N) and the load (its unit in the array's
  attributes), and the group's attributes (grid, size, seed, realisation, ...).

Arrays carry ``dimension_names``, so ``xarray.open_zarr(DIR/"fields.zarr", group="r0", consolidated=False)``
gives a labelled Dataset; ``zarr.open_group`` reads it without xarray. Chunks are one load's map, cut into
squares of at most :data:`CHUNK` cells a side; each chunk is compressed with zstd (Zarr's default codec).

A task writes its group under a temporary name in ``DIR/.partial`` (the same file system) and renames it
into ``fields.zarr`` only when every array is complete: no reader ever sees a half-written group, and no
task touches another's files or any shared metadata, so tasks on many machines write at once without
locks (the store folder must be on a file system every worker reaches). :meth:`TaskFields.commit` returns
the SHA-256 of every array's float64 little-endian bytes (C order); the task store keeps them in the
task's record, written after the fields, and :func:`fields_intact` checks a group against them.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import uuid
from pathlib import Path
from typing import Any

import numpy as np

from .files import OutputWriteError

__all__ = ["FIELDS_FOLDER", "PARTIAL_FOLDER", "CHUNK", "TaskFields", "create_field_store", "fields_intact",
           "clear_partial"]

#: The Zarr hierarchy inside a store folder.
FIELDS_FOLDER = "fields.zarr"
#: Where tasks write their groups before renaming them into :data:`FIELDS_FOLDER`.
PARTIAL_FOLDER = ".partial"
#: Largest chunk side (cells): 1024² float64 values are 8 MiB before compression.
CHUNK = 1024
#: The arrays of a task's group and their units.
FIELD_UNITS = {"height": "m", "gap": "m", "pressure": "Pa"}


def create_field_store(folder: str | Path) -> Path:
    """Make ``folder/fields.zarr`` (the root group) if missing; return its path."""
    import zarr

    root = Path(folder) / FIELDS_FOLDER
    try:
        if not (root / "zarr.json").exists():
            zarr.open_group(str(root), mode="a", zarr_format=3,
                            attributes={"description": "sealeak task fields: one group per task (height, gap, pressure)"})
        (Path(folder) / PARTIAL_FOLDER).mkdir(exist_ok=True)
    except OSError as exc:
        raise OutputWriteError(root, exc) from None
    return root


def clear_partial(folder: str | Path) -> None:
    """Remove what interrupted tasks left in ``folder/.partial`` (groups that were never renamed in)."""
    partial = Path(folder) / PARTIAL_FOLDER
    if partial.is_dir():
        for entry in partial.iterdir():
            shutil.rmtree(entry, ignore_errors=True)


def _digest_update(h: Any, values: np.ndarray) -> None:
    h.update(np.ascontiguousarray(values, dtype="<f8").tobytes())


class TaskFields:
    """One task's group, written under a temporary name and renamed into the store by :meth:`commit`.

    Parameters
    ----------
    folder:
        The store folder (``fields.zarr`` and ``.partial`` inside it; see :func:`create_field_store`).
    group:
        The group's name (``r<r>``).
    grid, size, period:
        N, the side across x and the period along y (m).
    load_name, loads, load_unit:
        The load coordinate (``squeeze_pressure``, Pa; or ``compression``, 1) and its values.
    attributes:
        Stored as the group's attributes (JSON values).
    """

    def __init__(self, folder: str | Path, group: str, *, grid: int, size: float, period: float, load_name: str,
                 loads: np.ndarray, load_unit: str, attributes: dict[str, Any]) -> None:
        import zarr

        self.folder = Path(folder)
        self.group = group
        self.target = self.folder / FIELDS_FOLDER / group
        self.tmp = self.folder / PARTIAL_FOLDER / f"{group}-{uuid.uuid4().hex}"
        n = int(grid)
        loads = np.asarray(loads, dtype=np.float64)
        chunk = min(n, CHUNK)
        self.digests = {name: hashlib.sha256() for name in FIELD_UNITS}
        self.filled: set[tuple[str, int]] = set()
        self.n_loads = loads.size
        try:
            self.tmp.parent.mkdir(parents=True, exist_ok=True)
            g = zarr.open_group(str(self.tmp), mode="w", zarr_format=3, attributes=dict(attributes))
            for name, coord, unit in (("x", (np.arange(n) + 0.5) * (size / n), "m"),
                                      ("y", (np.arange(n) + 0.5) * (period / n), "m"), (load_name, loads, load_unit)):
                a = g.create_array(name, shape=coord.shape, dtype="float64", dimension_names=[name],
                                   attributes={"units": unit})
                a[:] = coord
            self.height = g.create_array("height", shape=(n, n), dtype="float64", chunks=(chunk, chunk),
                                         dimension_names=["x", "y"], attributes={"units": "m", "long_name": "surface height"})
            self.maps = {name: g.create_array(name, shape=(loads.size, n, n), dtype="float64", chunks=(1, chunk, chunk),
                                              dimension_names=[load_name, "x", "y"],
                                              attributes={"units": FIELD_UNITS[name], "long_name": what})
                         for name, what in (("gap", "interfacial gap"), ("pressure", "contact pressure"))}
        except OSError as exc:
            self.abort()
            raise OutputWriteError(self.target, exc) from None

    def put_height(self, height: np.ndarray) -> None:
        """Write the height map (m)."""
        self._write(self.height, ..., height, "height", 0)

    def put(self, i: int, gap: np.ndarray, pressure: np.ndarray) -> None:
        """Write load ``i``'s gap (m) and contact pressure (Pa); loads must come in order 0, 1, ..."""
        self._write(self.maps["gap"], i, gap, "gap", i)
        self._write(self.maps["pressure"], i, pressure, "pressure", i)

    def _write(self, array: Any, where: Any, values: np.ndarray, name: str, i: int) -> None:
        if (name, i) in self.filled or (name != "height" and i != sum(1 for k, _ in self.filled if k == name)):
            raise ValueError(f"{name}[{i}] written out of order")
        try:
            array[where] = values
        except OSError as exc:
            self.abort()
            raise OutputWriteError(self.target, exc) from None
        _digest_update(self.digests[name], values)
        self.filled.add((name, i))

    def commit(self) -> dict[str, Any]:
        """Rename the complete group into the store (replacing an older one); its name and checksums."""
        missing = [f"{k}[{i}]" for k in ("gap", "pressure") for i in range(self.n_loads) if (k, i) not in self.filled]
        if ("height", 0) not in self.filled or missing:
            raise ValueError(f"fields of {self.group} incomplete: {', '.join(missing) or 'height'} not written")
        try:
            try:
                os.rename(self.tmp, self.target)
            except OSError:
                if not self.target.exists():
                    raise
                # an older (damaged, or record-less) group: set it aside, put this one in, then remove the old one
                aside = self.folder / PARTIAL_FOLDER / f"{self.group}-old-{uuid.uuid4().hex}"
                os.rename(self.target, aside)
                os.rename(self.tmp, self.target)
                shutil.rmtree(aside, ignore_errors=True)
        except OSError as exc:
            self.abort()
            raise OutputWriteError(self.target, exc) from None
        return {"group": self.group, "sha256": {k: h.hexdigest() for k, h in self.digests.items()}}

    def abort(self) -> None:
        """Remove the temporary group (nothing reaches the store)."""
        shutil.rmtree(self.tmp, ignore_errors=True)


def fields_intact(folder: str | Path, record: Any) -> bool:
    """Whether the group a task's record names is in the store and every array matches its SHA-256."""
    import zarr

    if not isinstance(record, dict) or not isinstance(record.get("sha256"), dict) or not isinstance(record.get("group"), str):
        return False
    path = Path(folder) / FIELDS_FOLDER / record["group"]
    if not (path / "zarr.json").is_file():
        return False
    try:
        g = zarr.open_group(str(path), mode="r")
        for name in FIELD_UNITS:
            h = hashlib.sha256()
            a = g[name]
            if not isinstance(a, zarr.Array):
                return False
            if a.ndim == 2:
                _digest_update(h, np.asarray(a[...]))
            else:
                for i in range(a.shape[0]):
                    _digest_update(h, np.asarray(a[i]))
            if h.hexdigest() != record["sha256"].get(name):
                return False
    except Exception:  # noqa: BLE001 - anything unreadable (missing chunk folder, bad metadata, ...) is damaged
        return False
    return True
