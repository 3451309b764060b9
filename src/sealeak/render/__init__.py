"""Rendering: every text table, JSON/CSV document, figure and report sealeak produces.

Renderers take result objects of the layers below (:class:`~sealeak.cases.CaseResult`,
:class:`~sealeak.cases.FitResult`, :class:`~sealeak.cases.SimulationResult`,
:class:`~sealeak.topography.Analysis`, ...) in SI units and turn them into readable units; they
compute no physics. Figures are :class:`matplotlib.figure.Figure` objects built without pyplot, so
importing sealeak leaves matplotlib's backend alone.

* :mod:`~sealeak.render.text`: the prediction table; :mod:`~sealeak.render.records`: JSON and CSV;
* :mod:`~sealeak.render.figures`: the prediction figures (:mod:`~sealeak.render.band`: those of O-ring and
  pressure-profile seals; :mod:`~sealeak.render.plotstyle`: the shared axes, units and legends); :mod:`~sealeak.render.lab_figures`: fit,
  linearity and rig figures; :mod:`~sealeak.render.spectra`: measured spectra;
* :mod:`~sealeak.render.lab`, :mod:`~sealeak.render.simulation`, :mod:`~sealeak.render.surface`:
  text and JSON of the other commands (:mod:`~sealeak.render.convergence`: the convergence study of
  ``simulate``); :mod:`~sealeak.render.report`: the HTML report.
"""

from .figures import PREDICTION_FIGURE_NAMES, prediction_figures, render_figures, save_figures
from .lab import fit_json, fit_text, linearity_json, linearity_text, rig_json, rig_text
from .lab_figures import figure_fit, figure_linearity, figure_readings, figure_rig
from .records import case_summary, json_document, json_value, prediction_csv, prediction_json
from .report import html_report
from .simulation import SIMULATION_FIGURE_NAMES, simulation_figures, simulation_json, simulation_table
from .spectra import plot_spectra
from .surface import analysis_json, analysis_text, spectrum_csv
from .text import prediction_table

__all__ = [
    "prediction_table", "prediction_json", "prediction_csv", "case_summary", "json_value", "json_document",
    "prediction_figures", "render_figures", "save_figures", "PREDICTION_FIGURE_NAMES",
    "fit_text", "fit_json", "linearity_text", "linearity_json", "rig_text", "rig_json",
    "figure_fit", "figure_linearity", "figure_rig", "figure_readings",
    "simulation_table", "simulation_json", "simulation_figures", "SIMULATION_FIGURE_NAMES",
    "analysis_text", "analysis_json", "spectrum_csv", "plot_spectra", "html_report",
]
