"""A seal case in SI units, and the prediction for it.

:class:`Case` holds everything one prediction needs as plain SI floats (the case-file reader,
:mod:`sealeak.casefile`, builds it from TOML with units). :func:`predict` runs the
critical-junction theory for every squeeze pressure of the case.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .contact import PerssonContact
from .fluid import Fluid
from .leakage import CriticalJunctionResult, critical_junction
from .roughness import PowerSpectrum
from .seal import Seal

__all__ = ["Case", "predict", "predict_effective_medium"]


@dataclass(frozen=True)
class Case:
    """One seal case (SI units).

    ``q0`` is 2π/L with L the side of the squares the nominal contact is divided into (L = Lx
    unless overridden). ``label`` names the variant within a parameter study ('' otherwise).
    ``model`` is the leak-rate theory the case asks for: "critical-junction", "effective-medium"
    or "both".
    """

    title: str
    spectrum: PowerSpectrum
    spectrum_note: str
    youngs_modulus: float
    poisson_ratio: float
    e_star: float
    seal: Seal
    fluid: Fluid
    squeeze_pressure: NDArray[np.float64]
    pressure_difference: float
    alpha: float = 1.0
    percolation_threshold: float = 0.6
    gamma: float = 1.0
    q0: float = 0.0
    q0_note: str = ""
    model: str = "critical-junction"
    rig: Any = None  # sealeak.rig.RigSetup from the case file's [rig] section, or None
    simulation: dict[str, int] = field(default_factory=dict)  # [simulation] grid/realizations/seed given
    label: str = ""
    source: str = ""
    inputs: dict[str, Any] = field(default_factory=dict, compare=False)

    @property
    def square_side(self) -> float:
        """L = 2π/q0 in m."""
        return 2.0 * np.pi / self.q0

    def contact(self) -> PerssonContact:
        """Persson contact mechanics of this case's interface."""
        return PerssonContact(self.spectrum, self.e_star, self.q0, self.gamma)


def predict(case: Case, squeeze_pressure: NDArray[np.float64] | None = None,
            pressure_difference: float | NDArray[np.float64] | None = None) -> CriticalJunctionResult:
    """Critical-junction leak rate of ``case`` at its squeeze pressures (or the ones given)."""
    return critical_junction(
        case.contact(),
        squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
        pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
        viscosity=case.fluid.viscosity,
        aspect_ratio=case.seal.aspect_ratio,
        alpha=case.alpha,
        percolation_threshold=case.percolation_threshold,
    )


def predict_effective_medium(case: Case, squeeze_pressure: NDArray[np.float64] | None = None,
                             pressure_difference: float | NDArray[np.float64] | None = None):
    """Bruggeman effective-medium leak rate of ``case`` (:func:`sealeak.effective_medium.effective_medium`)."""
    from .effective_medium import effective_medium

    return effective_medium(
        case.contact(),
        squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
        pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
        viscosity=case.fluid.viscosity,
        aspect_ratio=case.seal.aspect_ratio,
    )
