"""sealeak: leak rate of rubber seals from surface roughness.

Inside the library every quantity is a plain float or NumPy array in SI units (m, Pa, Pa·s, m³/s);
units are parsed and printed only at the edges (case files, CLI, reports).
"""

from .errors import (
    ConvergenceError,
    FileFormatError,
    InputError,
    ResourceError,
    SealeakError,
    SolutionCheckError,
    UnitError,
)
from .roughness import PowerSpectrum

__version__ = "0.1.0"

__all__ = [
    "PowerSpectrum",
    "SealeakError",
    "InputError",
    "UnitError",
    "FileFormatError",
    "ConvergenceError",
    "SolutionCheckError",
    "ResourceError",
]
