"""sealeak: leak rate of rubber seals from surface roughness.

Inside the library every quantity is a plain float or NumPy array in SI units (m, Pa, Pa·s, m³/s);
units are parsed and printed only at the edges (case files, CLI, reports).

The package is layered (``docs/architecture.md``): :mod:`sealeak.physics` at the bottom,
:mod:`sealeak.numerics` and :mod:`sealeak.topography` beside each other above it, then
:mod:`sealeak.lab`, :mod:`sealeak.cases` (one way to run a case), :mod:`sealeak.render` and the
command line :mod:`sealeak.cli` on top. The names below are the public API, re-exported here::

    from sealeak import load_cases, run_case
    result = run_case(load_cases("ring.toml")[0])
    result.critical_junction.leak_rate      # m³/s, one per squeeze pressure
"""

from ._version import __version__
from .cases import (
    Case,
    CaseFile,
    CaseResult,
    conductance,
    fit_models,
    load_case,
    load_cases,
    parse_cases,
    predict,
    predict_effective_medium,
    read_case_file,
    rig_prediction,
    run_case,
    simulate,
)
from .errors import (
    ConvergenceError,
    FileFormatError,
    InputError,
    ResourceError,
    SealeakError,
    SolutionCheckError,
    UnitError,
)
from .lab import water_column
from .numerics import synthesize
from .physics import (
    PerssonContact,
    PowerSpectrum,
    Seal,
    contact_modulus,
    critical_junction,
    effective_medium,
    gap_distribution,
)

__all__ = [
    "__version__",
    "PowerSpectrum",
    "PerssonContact",
    "contact_modulus",
    "critical_junction",
    "effective_medium",
    "gap_distribution",
    "Seal",
    "Case",
    "CaseFile",
    "CaseResult",
    "load_cases",
    "load_case",
    "parse_cases",
    "read_case_file",
    "run_case",
    "predict",
    "predict_effective_medium",
    "conductance",
    "fit_models",
    "rig_prediction",
    "simulate",
    "synthesize",
    "water_column",
    "SealeakError",
    "InputError",
    "UnitError",
    "FileFormatError",
    "ConvergenceError",
    "SolutionCheckError",
    "ResourceError",
]
