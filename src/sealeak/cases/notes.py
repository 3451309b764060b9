"""Structured notes: what the cases layer has to say about a result, as a code and its values.

The cases layer does not word them: :mod:`sealeak.render.notes` turns each :class:`Note` into the sentence the
user reads (one place for each sentence, and for the way a load or a pressure is written in one). Notes not yet
converted are still plain sentences, so a result's ``notes`` hold :data:`NoteLike` values.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Note", "NoteLike"]


@dataclass(frozen=True)
class Note:
    """One note about a result: ``code`` names what it says, ``values`` its numbers (SI units: Pa, m; loads in the
    case's units, a compression as a fraction) and names, as plain Python values (float, int, str, tuples)."""

    code: str
    values: Mapping[str, Any] = field(default_factory=dict)

    def to_mapping(self) -> dict[str, Any]:
        """The note as plain JSON values (what a task record keeps): ``{"code": ..., "values": {...}}``."""
        return {"code": self.code, "values": dict(self.values)}

    @staticmethod
    def of(mapping: Mapping[str, Any] | str) -> NoteLike:
        """The note :meth:`to_mapping` wrote (a sentence, as an older record kept it, passes unchanged)."""
        if isinstance(mapping, str):
            return mapping
        return Note(str(mapping["code"]), dict(mapping.get("values", {})))


#: A result's note: structured, or a sentence the cases layer still words itself.
NoteLike = Note | str
