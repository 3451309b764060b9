"""Result fields that carry their unit: declared once on the dataclass, read by every writer.

A result dataclass declares each field that JSON/CSV records show with :func:`quantity`::

    @dataclass(frozen=True, kw_only=True)
    class Result:
        leak_rate: FloatArray = quantity("m^3/s", "leak rate through the seal")
        percolates: BoolArray = quantity("1", "the non-contact area percolates", key="percolates_em")

The record key is the field's name unless ``key`` renames it. :func:`units_of` derives the
``{record key: SI unit}`` table (JSON ``units``, CSV headers) and :func:`record_fields` the
``{record key: value}`` columns of an instance, both in the dataclass's field order; fields without
a unit (settings, notes, arrays for figures) are not record fields. A document that gathers keys of several
dataclasses in an order of its own takes their units with :func:`units_for`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import Any

__all__ = ["quantity", "units_of", "descriptions_of", "record_fields", "units_for", "expand_keys"]


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


def units_for(keys: Iterable[str], *classes: Any) -> dict[str, str]:
    """``{key: SI unit}`` of ``keys`` in that order, each from the first of ``classes`` that declares it.

    Raises KeyError naming a key that none of ``classes`` declares with :func:`quantity`.
    """
    declared: dict[str, str] = {}
    for cls in reversed(classes):
        declared |= units_of(cls)
    missing = [k for k in keys if k not in declared]
    if missing:
        raise KeyError(f"no unit declared for {', '.join(missing)}")
    return {k: declared[k] for k in keys}


def expand_keys(units: dict[str, str], **values: Iterable[str]) -> dict[str, str]:
    """``units`` with its template keys (holding ``<name>``, e.g. ``fitted_<model>``) written for each value of
    ``values[name]`` (left out where none is given): the template keys of one value together, in the place of the
    first template key."""
    plain = {k: u for k, u in units.items() if "<" not in k}
    templates = {k: u for k, u in units.items() if "<" in k}
    out: dict[str, str] = {}
    for key, unit in units.items():
        if key in plain:
            out[key] = unit
        elif key == next(iter(templates)):
            for name, names in values.items():
                for v in names:
                    out |= {k.replace(f"<{name}>", v): u for k, u in templates.items() if f"<{name}>" in k}
    return out
