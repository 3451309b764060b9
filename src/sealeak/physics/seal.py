"""Seal geometry: the nominal contact band the fluid crosses.

The nominal contact is Lx × Ly with the flow along x (width Lx, from the high-pressure side to the
low-pressure side) and Ly the length of the band across the flow. The critical-junction theory
divides it into N = Ly/Lx squares of side Lx (Lorenz & Persson, EPL 86 (2009) 44006, eq. (2)).

Ring seal with inner and outer diameters Di < Do (docs/theory.md §3.1):
Lx = (Do - Di)/2, Ly = π (Do + Di)/2, so Lx·Ly = π (Do² - Di²)/4 is the annulus area.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, positive_number

__all__ = ["Seal", "STANDARD_GRAVITY"]

STANDARD_GRAVITY = 9.80665  # m/s²


def _length(name: str, value: float) -> float:
    return positive_number(name, value, allowed="must be a finite length > 0")


@dataclass(frozen=True)
class Seal:
    """Nominal contact band of a seal: ``width`` Lx along the flow and ``length`` Ly across it (m)."""

    width: float
    length: float
    shape: str = "rectangle"
    inner_diameter: float | None = None
    outer_diameter: float | None = None

    def __post_init__(self) -> None:
        _length("width", self.width)
        _length("length", self.length)

    @classmethod
    def ring(cls, inner_diameter: float, outer_diameter: float) -> Seal:
        """Ring (O-ring footprint, gasket): Lx = (Do - Di)/2, Ly = π (Do + Di)/2 (diameters in m; docs/theory.md §3.1, eq. 3.1)."""
        di = _length("inner_diameter", inner_diameter)
        do = _length("outer_diameter", outer_diameter)
        if not di < do:
            raise InputError("outer_diameter", do,
                             f"must exceed the inner diameter {di:.6g} m")
        return cls(width=(do - di) / 2.0, length=np.pi * (do + di) / 2.0, shape="ring",
                   inner_diameter=di, outer_diameter=do)

    @classmethod
    def rectangle(cls, width: float, length: float) -> Seal:
        """Straight band of width Lx (along the flow) and length Ly (across it)."""
        return cls(width=_length("width", width), length=_length("length", length))

    @property
    def aspect_ratio(self) -> float:
        """Ly/Lx, the number of squares of side Lx in the band."""
        return self.length / self.width

    @property
    def nominal_area(self) -> float:
        """Lx·Ly in m² (the annulus area for a ring)."""
        return self.width * self.length

    def squeeze_pressure_from_load(self, force: float) -> float:
        """Nominal squeeze pressure P0 = F / (Lx Ly) in Pa for a normal force F in N (docs/theory.md §3.1, eq. 3.1)."""
        if not (np.isfinite(force) and force > 0):
            raise InputError("load", force, "must be a finite force > 0 (N)")
        return force / self.nominal_area
