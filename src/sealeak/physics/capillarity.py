"""Capillarity of a liquid in the seal's narrowest constriction: the Laplace pressure of a slit.

A liquid meniscus in a slit of height u between two walls with contact angles θ_r (rubber) and θ_s
(the rough counter-surface) has the curvature (cos θ_r + cos θ_s)/u across the slit (the other
curvature, along the slit, is negligible for a wide channel), so the pressure jump across it is the
Young–Laplace pressure (docs/theory.md §12.1, eq. 12.1)::

    p_cap = γ (cos θ_r + cos θ_s) / u

with γ the liquid's surface tension (N/m). p_cap > 0: the liquid wets the walls and is drawn in;
p_cap < 0: it does not, and enters only when the pressure difference across the seal exceeds the
entry pressure p_e = −p_cap (eq. 12.2) of the narrowest constriction on the leak path
(Huon et al., Tribology Letters 70 (2022) 35). Units: SI (Pa, m, N/m), angles in degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = ["Wetting", "capillary_pressure", "check_contact_angle", "check_surface_tension"]


def check_contact_angle(name: str, value: object) -> float:
    """A contact angle θ in degrees, 0 ≤ θ ≤ 180; an :class:`InputError` naming ``name`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not 0.0 <= value <= 180.0:
        raise InputError(name, value, "must be a contact angle in degrees, a number from 0 to 180 (e.g. 110)")
    return float(value)


def check_surface_tension(name: str, value: float) -> float:
    """A surface tension γ in N/m, finite and > 0 (below 1 N/m: mercury's is 0.49 N/m); an :class:`InputError` otherwise."""
    if not (math.isfinite(value) and 0.0 < value < 1.0):
        raise InputError(name, value, "must be a surface tension > 0 and below 1 N/m (water: 0.0728 N/m at 20 °C)")
    return float(value)


def _cosines(contact_angle_rubber: float, contact_angle_surface: float) -> float:
    """cos θ_r + cos θ_s (1), 0 where it is within rounding of 0 (90° on both walls: cos 90° is 6e-17 in floating point)."""
    total = math.cos(math.radians(contact_angle_rubber)) + math.cos(math.radians(contact_angle_surface))
    return total if abs(total) > 1e-12 else 0.0


def capillary_pressure(gap: ArrayLike, surface_tension: float, contact_angle_rubber: float,
                       contact_angle_surface: float) -> NDArray[np.float64]:
    """p_cap = γ (cos θ_r + cos θ_s)/u (Pa) of a slit of height ``gap`` u (m): > 0 draws the liquid in, < 0 opposes it.

    ``surface_tension`` γ in N/m, the contact angles θ in degrees (docs/theory.md §12.1, eq. 12.1).
    NaN where the gap is NaN (no leak channel).
    """
    u = np.asarray(gap, dtype=float)
    cosines = _cosines(contact_angle_rubber, contact_angle_surface)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(surface_tension * cosines / u, dtype=float)


@dataclass(frozen=True)
class Wetting:
    """A liquid's surface tension and its contact angles on the two walls of the leak path.

    Attributes
    ----------
    surface_tension
        γ (N/m).
    contact_angle_rubber, contact_angle_surface
        θ_r on the rubber and θ_s on the rough counter-surface (degrees, 0 to 180).
    surface_tension_source
        Where γ comes from: "given in the case", or the property library and its correlation.
    """

    surface_tension: float
    contact_angle_rubber: float
    contact_angle_surface: float
    surface_tension_source: str = "given in the case"

    def __post_init__(self) -> None:
        check_surface_tension("surface_tension", self.surface_tension)
        check_contact_angle("contact_angle_rubber", self.contact_angle_rubber)
        check_contact_angle("contact_angle_surface", self.contact_angle_surface)

    @property
    def cosines(self) -> float:
        """cos θ_r + cos θ_s (1): < 0 for a liquid that does not wet the walls on balance."""
        return _cosines(self.contact_angle_rubber, self.contact_angle_surface)

    @property
    def wets(self) -> bool:
        """Whether the liquid is drawn into the gap (cos θ_r + cos θ_s > 0)."""
        return self.cosines > 0

    def entry_pressure(self, gap: ArrayLike) -> NDArray[np.float64]:
        """p_e = −γ (cos θ_r + cos θ_s)/u (Pa) at the narrowest gap u (m): the ΔP the liquid must exceed to enter
        (negative for a wetting liquid: the suction that draws it in; docs/theory.md §12.1, eq. 12.2)."""
        return -capillary_pressure(gap, self.surface_tension, self.contact_angle_rubber, self.contact_angle_surface)

    def held(self, gap: ArrayLike, pressure_difference: float) -> NDArray[np.bool_]:
        """Where the meniscus holds the liquid: ΔP (Pa) below a positive entry pressure at the gap u (m) (eq. 12.3)."""
        p_e = self.entry_pressure(gap)
        return np.asarray(np.isfinite(p_e) & (p_e > 0) & (pressure_difference < p_e), dtype=bool)
