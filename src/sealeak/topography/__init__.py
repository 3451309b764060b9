"""Measured surfaces (work in progress): reading."""

from ._readers import read_topography
from ._types import LineScans, Topography

__all__ = ["read_topography", "Topography", "LineScans"]
