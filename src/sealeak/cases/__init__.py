"""Cases: the case model, the case-file schema and its builders, and running a case.

* :mod:`~sealeak.cases.model`: :class:`Case`, one seal case in SI units;
* :mod:`~sealeak.cases.schema`: every section and key of a case file, typed getters that validate;
* :mod:`~sealeak.cases.builders`: sections → spectrum, seal, fluid, rig, ... (errors name ``section.key``);
* :mod:`~sealeak.cases.loader`: :func:`load_cases`, :func:`read_case_file`, the bundled examples;
* :mod:`~sealeak.cases.run`: :func:`run_case` → :class:`CaseResult`, the one way every front end
  runs a case, made of :mod:`~sealeak.cases.prediction` (:func:`predict`, :func:`conductance`),
  :mod:`~sealeak.cases.verdicts` (validity per row), :mod:`~sealeak.cases.gas` (a gas's leak and the
  helium equivalent) and :mod:`~sealeak.cases.rig` (:func:`rig_prediction`, :func:`rig_readings`);
* the laboratory workflows on a case: :mod:`~sealeak.cases.fitting` (:func:`run_fit`, :func:`fit_models`) and
  :mod:`~sealeak.cases.linearity_check` (:func:`linearity`);
* :mod:`~sealeak.cases.options`: :func:`simulation_options` → :class:`SimulationOptions`, the one check of a
  simulation's grid, realisations, seed and workers (command line, case files, web app);
* :mod:`~sealeak.cases.pipeline`: :func:`~sealeak.cases.pipeline.run_ensemble`, the one ensemble pipeline of
  every simulated geometry (the geometry a strategy object);
* :mod:`~sealeak.cases.simulation`: :func:`simulate`, the numerically exact leak rate and α of a uniform seal
  (:mod:`~sealeak.cases.simulation_band`: of an O-ring).
* :mod:`~sealeak.cases.simulation_map`: :func:`simulate_map`, :func:`simulate_maps`, the same on measured or
  given height maps (the map itself is the surface, one realisation per map);
* :mod:`~sealeak.cases.convergence`: the convergence and validation study of :func:`simulate` over
  several grids (standard errors, extrapolation to the continuum, the published percolation threshold).
"""

from .builders import register_surface_model
from .curves import CurveSet, PredictionCurves, PressureDifferenceSweep, prediction_curves, representative_pressures
from .fitting import FitResult, fit_models, run_fit
from .linearity_check import LinearityCheck, linearity
from .loader import (
    CaseFile,
    example_names,
    example_path,
    example_text,
    load_case,
    load_cases,
    parse_case_bytes,
    parse_case_file,
    parse_cases,
    read_case_file,
)
from .model import MODELS, Case
from .options import SimulationOptions, simulation_options
from .prediction import conductance, predict, predict_effective_medium
from .rig import RigPrediction, rig_prediction, rig_readings
from .run import EFFECTIVE_MEDIUM_UNITS, RESULT_UNITS, CaseResult, run_case
from .simulation import SimulationResult, simulate
from .simulation_map import MapSimulationResult, simulate_map, simulate_maps

__all__ = [
    "Case", "MODELS", "CaseFile", "read_case_file", "parse_case_file", "parse_case_bytes", "load_cases", "load_case", "parse_cases",
    "example_names", "example_text", "example_path", "register_surface_model",
    "CaseResult", "run_case", "predict", "predict_effective_medium", "conductance", "RESULT_UNITS",
    "EFFECTIVE_MEDIUM_UNITS", "fit_models", "LinearityCheck", "linearity", "RigPrediction", "rig_prediction",
    "rig_readings", "PredictionCurves", "prediction_curves", "FitResult", "run_fit", "CurveSet",
    "PressureDifferenceSweep", "representative_pressures", "SimulationResult", "simulate", "SimulationOptions",
    "simulation_options", "MapSimulationResult", "simulate_map", "simulate_maps",
]
