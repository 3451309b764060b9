"""The linearity check: Q against ΔP at one load, a straight line and the models' slopes (docs/theory.md §8.2).

:func:`linearity` of arrays and :func:`run_linearity` of a data file → :class:`LinearityCheck`, for
a uniform seal at one squeeze pressure or a band seal at one compression or profile scale
(docs/theory.md §10.5). A gas case has none (its throughput is not linear in ΔP).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, SealeakError
from ..io.quantities import quantity
from ..lab.data import LeakData
from ..lab.fitting import LinearFit, fit_line
from .fitting import _check_file_loads, _check_load_column
from .model import Case
from .notes import Note, NoteLike
from .prediction import FloatArray, Model, _band_conductance, _conductance, _model_name

__all__ = ["LinearityCheck", "linearity", "run_linearity"]

@dataclass(frozen=True, kw_only=True)
class LinearityCheck:
    """Q against ΔP at one squeeze pressure: the straight-line fit and the models' slopes.

    Attributes
    ----------
    line
        The least-squares line Q = slope ΔP + intercept (docs/theory.md §8.2).
    squeeze_pressure
        P0 of the data (Pa), or None when unknown (then no model slopes).
    squeeze_pressure_source
        Where P0 came from (an option, the data file, the case, the rig).
    model_slopes
        K = Q/ΔP (m³/(Pa·s)) of each model that percolates at P0, by display name.
    alpha_from_slope
        The measured slope over the critical junction's slope at α = 1.
    messages
        Notes (a model without a leak channel, no P0 known).
    load_name, load
        For an O-ring or pressure-profile seal: "compression" or "profile_scale" and its value
        (1), or None when unknown; ``squeeze_pressure`` is then the band's mean contact pressure
        there (Pa) and ``squeeze_pressure_source`` says where the load came from.
    """

    line: LinearFit
    squeeze_pressure: float | None = quantity("Pa", "P0 of the data (a band seal: its mean contact pressure)")
    squeeze_pressure_source: str
    model_slopes: dict[str, float] = quantity("m^3/(s*Pa)", "K = Q/ΔP of each model that percolates at P0")
    alpha_from_slope: float | None = quantity("1", "the measured slope over the critical junction's at α = 1")
    messages: tuple[NoteLike, ...]
    load_name: str = "squeeze_pressure"
    load: float | None = quantity("1", "a band seal's load, keyed by its name: compression ε or profile scale",
                                  default=None, key="<load>")

    @property
    def intercept_z(self) -> float:
        """|intercept| in standard errors (NaN when the error is unknown)."""
        ln = self.line
        return abs(ln.intercept / ln.intercept_std) if ln.intercept_std > 0 else float("nan")


#: Why a gas case has no linearity check (docs/theory.md §11.3-11.5).
_GAS_LINEARITY = ("is for a liquid: it checks Q = K ΔP; the case's fluid is a gas, whose pV throughput between two absolute pressures is "
                  "Q_pV = K ∫ p f(Kn) dp from P_b to P_a (K (P_a² − P_b²)/2 without rarefaction, docs/theory.md §11.3, "
                  "§11.5), not linear in ΔP, so a straight line through the readings tests nothing: fit α without "
                  "--linearity, which applies the gas law row by row (P_a = downstream_pressure + ΔP of each row)")


def linearity(case: Case, pressure_difference: ArrayLike, leak_rate: ArrayLike,
              squeeze_pressure: float | None = None, squeeze_pressure_source: str = "") -> LinearityCheck:
    """Fit Q = slope ΔP + intercept and compare the slope with both models at P0 (docs/theory.md §8).

    ``squeeze_pressure`` None: the case's single P0, else its ``[rig]`` load, else none. For an
    O-ring or pressure-profile seal ``squeeze_pressure`` is the load instead (a compression ε or a
    profile scale, 1; None: the case's single load) and the models' slopes are the band's
    K = faces · Ly / ∫dx/σ there (docs/theory.md §10.5).
    """
    if case.gas is not None:
        raise InputError("--linearity", None, _GAS_LINEARITY)
    line = fit_line(pressure_difference, leak_rate)
    if case.band is not None:
        return _band_linearity(case, line, squeeze_pressure, squeeze_pressure_source)
    p0, source = squeeze_pressure, squeeze_pressure_source
    if p0 is None and case.squeeze_pressure.size == 1:
        p0, source = float(case.squeeze_pressure[0]), "the case file"
    elif p0 is None and case.rig is not None:
        p0, source = case.rig.squeeze_pressure(case.seal), "the [rig] load"
    slopes: dict[str, float] = {}
    messages: list[NoteLike] = []
    alpha_from_slope = None
    if p0 is not None:
        slopes, alpha_from_slope, messages = _model_slopes(case, line, {m: _conductance(case, [p0], m) for m in _MODELS})
    else:
        messages.append(Note("linearity_no_squeeze_pressure"))
    return LinearityCheck(line=line, squeeze_pressure=p0, squeeze_pressure_source=source, model_slopes=slopes,
                          alpha_from_slope=alpha_from_slope, messages=tuple(messages))


def run_linearity(case: Case, data: LeakData, squeeze_pressure: float | None = None,
                  squeeze_pressure_source: str = "") -> LinearityCheck:
    """:func:`linearity` of a data file (columns pressure_difference, leak_rate, optionally the load).

    The load is ``squeeze_pressure`` if given (a uniform seal only), else the data file's load
    column if it has one (one value: the check is at one load), else the case's single load (or its
    [rig] load). A load column that does not fit the case's seal is a FileFormatError.
    """
    if case.gas is not None:
        raise InputError("--linearity", None, _GAS_LINEARITY)
    _check_load_column(case, data, required=False)
    if squeeze_pressure is None and data.load_name:
        load = data.load
        if not np.allclose(load, load[0], rtol=1e-6):
            what = {"squeeze_pressure": "squeeze pressure", "compression": "compression", "profile_scale": "profile scale"}
            raise SealeakError(f"{data.path}: a linearity check is at one {what[data.load_name]}; the file has several")
        if case.band is not None:
            _check_file_loads(case, data, load[:1])
        squeeze_pressure, squeeze_pressure_source = float(load[0]), "the data file"
    return linearity(case, data.pressure_difference, data.leak_rate, squeeze_pressure, squeeze_pressure_source)


#: The models a linearity check compares with, in the order their slopes are reported.
_MODELS: tuple[Model, ...] = ("critical-junction", "effective-medium")


def _model_slopes(case: Case, line: LinearFit, conductances: dict[Model, tuple[FloatArray, tuple[NoteLike, ...]]]
                  ) -> tuple[dict[str, float], float | None, list[NoteLike]]:
    """Each model's slope K = Q/ΔP (m³/(s·Pa)) at the load, from ``conductances`` ({model: (K per load, notes)});
    the α the data's slope implies (slope / K_cj at α = 1); the notes of a model that has no leak there."""
    slopes: dict[str, float] = {}
    messages: list[NoteLike] = []
    alpha_from_slope = None
    for model, (k, notes) in conductances.items():
        if k[0] > 0:
            slopes[_model_name(case, model)] = float(k[0])
            if model == "critical-junction":
                alpha_from_slope = line.slope / (float(k[0]) / case.alpha)
        else:
            messages.extend(notes)
    return slopes, alpha_from_slope, messages


def _band_linearity(case: Case, line: LinearFit, load: float | None, source: str) -> LinearityCheck:
    """:func:`linearity` of a band seal: the models' slopes at one compression or profile scale."""
    band = case.band
    assert band is not None
    if load is None and band.loads.size == 1:
        load, source = float(band.loads[0]), "the case file"
    slopes: dict[str, float] = {}
    messages: list[NoteLike] = []
    alpha_from_slope = None
    p_mean = None
    if load is not None:
        ks, res = _band_conductance(case, [load], _MODELS)
        p_mean = float(res.mean_contact_pressure[0])
        slopes, alpha_from_slope, messages = _model_slopes(case, line, {m: ks[m] for m in _MODELS})
    else:
        messages.append(Note("linearity_one_load_needed", {"loads": int(band.loads.size), "load_name": band.load_name}))
    return LinearityCheck(line=line, squeeze_pressure=p_mean, squeeze_pressure_source=source, model_slopes=slopes,
                          alpha_from_slope=alpha_from_slope, messages=tuple(messages), load_name=band.load_name, load=load)
