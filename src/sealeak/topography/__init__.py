"""Measured surfaces: instrument files → height maps / line scans → C(q), statistics, fits.

Everything is in SI units (m, 1/m, m⁴) and Persson's convention for C(q) (docs/theory.md §1)::

    C(q) = 1/(2π)² ∫ d²x <h(x)h(0)> e^(-iq·x),   h_rms² = 2π ∫ q C(q) dq

(SurfaceTopography's isotropic PSD is (2π)² times this C(q); sealeak uses SurfaceTopography only
to read instrument files, never for spectra.)

Typical use::

    from sealeak.topography import analyze
    from sealeak.render import plot_spectra
    result = analyze(["wide.plu", "afm.di"])
    result.spectrum          # PowerSpectrum over the union of reliable ranges
    result.statistics        # SurfaceStatistics
    result.fit               # SelfAffineFit (H, q_r, C0 with standard errors)
    plot_spectra(result, "spectra.png")

Height maps are written with their size by :func:`write_height_map` (``.npz``, ``.npy`` with a
``.npy.json`` sidecar, or text with ``# size:`` header lines), which :func:`read_topography`
reads back without unit options.

Pipeline pieces: :func:`read_topography` → :func:`prepare` → :func:`spectrum_2d` /
:func:`spectrum_1d` (+ :func:`spectrum_2d_from_1d`) → :func:`stitch` → :func:`fit_self_affine`,
and :func:`surface_statistics`.
"""

from . import _spectrum
from ._analysis import Analysis, AnalysisOptions, SourceAnalysis, analyze
from ._common import npy_header
from ._fit import SelfAffineFit, fit_self_affine
from ._options import analysis_options, lengths_option
from ._preprocess import Prepared, hann_window, prepare
from ._readers import ReadOptions, read_topography
from ._spectrum import (  # noqa: F401 (public through _spectrum.__all__)
    BinnedSpectrum,
    RangeBasis,
    SpectrumOptions,
    abel_forward,
    abel_inverse,
    length_text,
    power_spectrum_map,
    spectrum_1d,
    spectrum_1d_from_2d,
    spectrum_2d,
    spectrum_2d_from_1d,
)
from ._statistics import SurfaceStatistics, surface_statistics
from ._stitch import stitch
from ._types import LineScans, Topography
from ._units import MissingUnitsError, case_option_names, cli_option_names, length_unit_factor, parse_length
from ._writers import HEIGHT_MAP_SUFFIXES, height_map_outputs, write_height_map

__all__ = [
    "npy_header",
    "analysis_options",
    "lengths_option",
    "Topography",
    "LineScans",
    "read_topography",
    "ReadOptions",
    "Prepared",
    "prepare",
    "hann_window",
    *_spectrum.__all__,
    "stitch",
    "SurfaceStatistics",
    "surface_statistics",
    "SelfAffineFit",
    "fit_self_affine",
    "Analysis",
    "AnalysisOptions",
    "SourceAnalysis",
    "analyze",
    "length_unit_factor",
    "parse_length",
    "write_height_map",
    "height_map_outputs",
    "HEIGHT_MAP_SUFFIXES",
    "MissingUnitsError",
    "cli_option_names",
    "case_option_names",
]
