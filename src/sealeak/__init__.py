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

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from . import errors
from ._version import __version__
from .errors import (  # noqa: F401 (public through _ERRORS)
    ConvergenceError,
    FileFormatError,
    InputError,
    ResourceError,
    SealeakError,
    SolutionCheckError,
    UnitError,
)

#: The exception classes of :mod:`sealeak.errors`, public here as well.
_ERRORS = tuple(name for name in errors.__all__ if name.endswith("Error"))

#: The public names of the layers below, and the sub-package each comes from. They are imported on
#: first use (PEP 562), so that ``import sealeak`` and ``sealeak --help`` load neither pint, SciPy's
#: integrators, matplotlib nor Dask.
_LAZY: dict[str, str] = {
    **dict.fromkeys(("Case", "CaseFile", "CaseResult", "conductance", "fit_models", "load_case", "load_cases",
                     "parse_cases", "predict", "predict_effective_medium", "read_case_file", "rig_prediction",
                     "run_case", "simulate", "simulate_map"), "cases"),
    "water_column": "lab",
    "synthesize": "numerics",
    **dict.fromkeys(("PerssonContact", "PowerSpectrum", "Seal", "contact_modulus", "critical_junction",
                     "effective_medium", "gap_distribution"), "physics"),
}

if TYPE_CHECKING:  # the names as the type checker and the API pages see them
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
        simulate_map,
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


#: The sub-packages, also imported on first use (``sealeak.physics`` after a bare ``import sealeak``).
_SUBPACKAGES = frozenset({"cases", "cli", "io", "lab", "numerics", "physics", "render", "topography", "web"})


def __getattr__(name: str) -> Any:
    """A public name of a lower layer, or a sub-package, imported on first use (PEP 562)."""
    if name in _SUBPACKAGES:
        return importlib.import_module(f"{__name__}.{name}")
    package = _LAZY.get(name)
    if package is None:
        raise AttributeError(f"module 'sealeak' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{package}"), name)
    globals()[name] = value  # later look-ups are plain attribute reads
    return value


def __dir__() -> list[str]:
    """The module's names and the lazily imported public ones."""
    return sorted(set(globals()) | set(__all__))


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
    "simulate_map",
    "synthesize",
    "water_column",
    *_ERRORS,
]
