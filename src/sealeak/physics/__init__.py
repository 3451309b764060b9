"""The physics: the theory of the leak rate, in plain SI floats and NumPy arrays.

* :mod:`~sealeak.physics.spectrum`: the roughness power spectrum C(q) (docs/theory.md §1);
* :mod:`~sealeak.physics.contact`: Persson's contact mechanics, A(ζ), ū(ζ), u1(ζ) (§2);
* :mod:`~sealeak.physics.critical_junction`: the critical-junction leak rate (§3; Lorenz & Persson (2009));
* :mod:`~sealeak.physics.gaps`: the distribution of interfacial separations P(u) (§5);
* :mod:`~sealeak.physics.effective_medium`: the Bruggeman effective-medium leak rate (§5);
* :mod:`~sealeak.physics.seal`, :mod:`~sealeak.physics.fluid`: the seal's geometry and the fluid;
* :mod:`~sealeak.physics.profile`: a non-uniform contact pressure p(x) and the series resistance ∫dx/σ (§10.1);
* :mod:`~sealeak.physics.oring`: an O-ring's contact force, width and pressure, and E from Shore A (§10.2);
* :mod:`~sealeak.physics.viscoelastic`: relaxation, creep, time–temperature shift, thermal contraction and
  compression set: the seal over its life (§16).

Nothing here reads files with units or prints; errors name the functions' own parameters.
"""

from .contact import PerssonContact, contact_modulus
from .critical_junction import CriticalJunctionResult, critical_junction, poiseuille_leak_rate
from .effective_medium import EffectiveMediumResult, effective_medium
from .fluid import Fluid
from .gaps import GapDistribution, gap_distribution
from .oring import ORingContact, compression_from_groove_depth, oring_contact, shore_a_warnings, youngs_modulus_from_shore_a
from .profile import PressureProfile, series_resistance
from .seal import Seal
from .spectrum import PowerSpectrum, area_ratio_from_slope

__all__ = [
    "PowerSpectrum", "area_ratio_from_slope", "PerssonContact", "contact_modulus", "CriticalJunctionResult",
    "critical_junction", "poiseuille_leak_rate", "GapDistribution", "gap_distribution", "EffectiveMediumResult",
    "effective_medium", "Seal", "Fluid", "PressureProfile", "series_resistance", "ORingContact", "oring_contact",
    "compression_from_groove_depth", "youngs_modulus_from_shore_a", "shore_a_warnings",
]
