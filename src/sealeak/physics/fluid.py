"""Fluid properties and the Poiseuille conductance of a thin gap.

Incompressible Newtonian fluid with viscosity η (Pa·s), laminar flow, no slip. Between parallel
plates a distance g apart the flow per unit width is q = -σ ∇p with σ(g) = g³/(12 η)
(plane Poiseuille flow; docs/theory.md §3.5 and §5.2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .validity import molecular_size

__all__ = ["Fluid", "gap_conductance"]


@dataclass(frozen=True)
class Fluid:
    """A Newtonian fluid: ``viscosity`` η in Pa·s, optional ``density`` ρ in kg/m³.

    ``molecular_size`` d (m) is the narrowest gap the fluid can flow through as a continuum
    (docs/theory.md §9.11); when not given it is looked up by ``name`` in
    :data:`~sealeak.physics.validity.MOLECULAR_SIZES`, else
    :data:`~sealeak.physics.validity.DEFAULT_MOLECULAR_SIZE`.
    """

    viscosity: float
    density: float | None = None
    name: str = ""
    molecular_size: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.viscosity, (int, float)) and np.isfinite(self.viscosity) and self.viscosity > 0):
            raise InputError("viscosity", self.viscosity, "must be a finite viscosity > 0 (Pa s)")
        if self.density is not None and not (np.isfinite(self.density) and self.density > 0):
            raise InputError("density", self.density, "must be a finite density > 0 (kg/m^3)")
        if self.molecular_size is not None and not (np.isfinite(self.molecular_size) and 0 < self.molecular_size < 1e-6):
            raise InputError("molecular_size", self.molecular_size, "must be a length in (0, 1 µm) (m)")

    @property
    def molecular_length(self) -> float:
        """d in m: ``molecular_size`` if given, else the tabulated or default value for ``name``."""
        return self.molecular_size if self.molecular_size is not None else molecular_size(self.name)[0]

    @property
    def molecular_length_note(self) -> str:
        """Where d comes from: "given", "water", or "default (fluid not in the table)"."""
        if self.molecular_size is not None:
            return "given in the case"
        known = molecular_size(self.name)[1]
        return self.name.lower() if known else "default for a fluid not in the table"


def gap_conductance(gap: ArrayLike, viscosity: float) -> NDArray[np.float64]:
    """σ(g) = g³/(12 η) in m³/(Pa·s): flow per unit width per unit pressure gradient (gap g in m, η in Pa·s; docs/theory.md §5.2)."""
    g = np.asarray(gap, dtype=float)
    return g**3 / (12.0 * viscosity)
