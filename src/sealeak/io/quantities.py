"""Result fields that carry their unit: declared once on the dataclass, read by every writer.

A result dataclass declares each field that JSON/CSV records show with :func:`quantity`::

    @dataclass(frozen=True, kw_only=True)
    class Result:
        leak_rate: FloatArray = quantity("m^3/s", "leak rate through the seal")
        percolates: BoolArray = quantity("1", "the non-contact area percolates", key="percolates_em")

The record key is the field's name unless ``key`` renames it. :func:`units_of` derives the
``{record key: SI unit}`` table (JSON ``units``, CSV headers) and :func:`record_fields` the
``{record key: value}`` columns of an instance, both in the dataclass's field order; fields without
a unit (settings, notes, arrays for figures) are not record fields.
"""

from __future__ import annotations

import dataclasses
from typing import Any

__all__ = ["quantity", "units_of", "descriptions_of", "record_fields"]


def quantity(unit: str, description: str, *, key: str | None = None, **options: Any) -> Any:
    """A dataclass field shown in records: its SI ``unit`` ("1" dimensionless, "" text), what it is, its record key.

    ``options`` go to :func:`dataclasses.field` (``default``, ``default_factory``, ``repr``, ...).
    """
    metadata = {"unit": unit, "description": description} | ({"key": key} if key is not None else {})
    return dataclasses.field(metadata=metadata, **options)


def _quantities(cls: Any) -> list[tuple[str, dataclasses.Field[Any]]]:
    """(record key, field) of every field of ``cls`` (a dataclass or an instance) declared with :func:`quantity`."""
    return [(f.metadata.get("key", f.name), f) for f in dataclasses.fields(cls) if "unit" in f.metadata]


def units_of(cls: Any) -> dict[str, str]:
    """``{record key: SI unit}`` of the :func:`quantity` fields of a dataclass (or an instance), in field order."""
    return {key: f.metadata["unit"] for key, f in _quantities(cls)}


def descriptions_of(cls: Any) -> dict[str, str]:
    """``{record key: description}`` of the :func:`quantity` fields of a dataclass (or an instance), in field order."""
    return {key: f.metadata["description"] for key, f in _quantities(cls)}


def record_fields(obj: Any) -> dict[str, Any]:
    """``{record key: value}`` of the :func:`quantity` fields of a dataclass instance, in field order."""
    return {key: getattr(obj, f.name) for key, f in _quantities(obj)}
