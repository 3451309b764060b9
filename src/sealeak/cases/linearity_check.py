"""The linearity check: Q against ΔP at one load, a straight line and the models' predictions (docs/theory.md §8.2).

:func:`linearity` of arrays and :func:`run_linearity` of a data file → :class:`LinearityCheck`, for
a uniform seal at one squeeze pressure or a band seal at one compression or profile scale
(docs/theory.md §10.5). Each model's Q(ΔP) at the load is its coupled leak rate (eq. 13.2, 13.3: not linear
in ΔP with the fluid pressure acting on the contact) and, with a contact angle, 0 below the capillary entry
pressure (eq. 12.3); the straight line through it at the measured ΔP gives the model's slope and intercept
(docs/theory.md §8.2). A gas case has none (its throughput is not linear in ΔP).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, SealeakError
from ..io.quantities import quantity
from ..lab.data import LeakData
from ..lab.fitting import LinearFit, fit_line
from .capillarity import entry_pressures
from .fitting import _check_file_loads, _check_load_column, _large_pressure_difference, volume_flows
from .model import Case
from .notes import Note, NoteLike
from .prediction import FloatArray, Model, _band_conductance, _conductance, _model_name, leak_curve

__all__ = ["LinearityCheck", "linearity", "run_linearity"]

#: Points of each model's Q(ΔP) curve in the figure, from 0 to 1.1 × the largest measured ΔP (a band seal with the
#: fluid pressure coupled: one shooting solve of eq. 13.3 each, about 50 ms).
CURVE_POINTS = 24


@dataclass(frozen=True, kw_only=True)
class LinearityCheck:
    """Q against ΔP at one squeeze pressure: the straight-line fit and the models' predictions.

    Attributes
    ----------
    line
        The least-squares line Q = slope ΔP + intercept (docs/theory.md §8.2).
    squeeze_pressure
        P0 of the data (Pa), or None when unknown (then no model slopes).
    squeeze_pressure_source
        Where P0 came from (an option, the data file, the case, the rig).
    model_slopes, model_intercepts
        The least-squares line through each model's Q at the measured ΔP (with the fluid pressure coupled and
        capillarity, docs/theory.md §13.5, §12.1), slope (m³/(Pa·s)) and intercept (m³/s), by display name, for each
        model that percolates at the load. A leak linear in ΔP has slope K = Q/ΔP and intercept 0.
    model_nonlinearity
        (Q/ΔP at the largest measured ΔP)/(Q/ΔP at the smallest) − 1 of each model without capillarity (1): 0 for
        the printed theory, > 0 where the fluid pressure opens the contact (docs/theory.md §13.2).
    capillary_entry_pressure
        With a contact angle, each model's entry pressure p_e (Pa; Q = 0 below it, docs/theory.md eq. 12.3).
    alpha_from_slope
        The measured slope over the critical junction's slope at α = 1.
    messages
        Notes (a model without a leak channel, no P0 known, measured points the model holds by capillarity).
    load_name, load
        For an O-ring or pressure-profile seal: "compression" or "profile_scale" and its value
        (1), or None when unknown; ``squeeze_pressure`` is then the band's mean contact pressure
        there (Pa) and ``squeeze_pressure_source`` says where the load came from.
    curve_pressure_difference, model_curves
        ΔP (Pa) from 0 past the largest measured one, and each model's Q there (m³/s), for the figure.
    model_keys
        Each display name's model as a record key (``critical_junction``, ``effective_medium``): what the JSON keys
        the models by (a display name holds α, "critical junction (α = 0.2)").
    """

    line: LinearFit
    squeeze_pressure: float | None = quantity("Pa", "P0 of the data (a band seal: its mean contact pressure)")
    squeeze_pressure_source: str
    model_slopes: dict[str, float] = quantity("m^3/(s*Pa)", "slope of the line through each model's Q at the measured ΔP")
    model_intercepts: dict[str, float] = quantity("m^3/s", "intercept of that line (0 for a model linear in ΔP)",
                                                  default_factory=dict)
    model_nonlinearity: dict[str, float] = quantity(
        "1", "each model's Q/ΔP at the largest measured ΔP over that at the smallest, minus 1 (0: linear)",
        default_factory=dict)
    capillary_entry_pressure: dict[str, float] = quantity(
        "Pa", "each model's capillary entry pressure (with a contact angle; Q = 0 below it)", default_factory=dict)
    alpha_from_slope: float | None = quantity("1", "the measured slope over the critical junction's at α = 1")
    messages: tuple[NoteLike, ...]
    load_name: str = "squeeze_pressure"
    load: float | None = quantity("1", "a band seal's load, keyed by its name: compression ε or profile scale",
                                  default=None, key="<load>")
    curve_pressure_difference: FloatArray = field(default_factory=lambda: np.zeros(0))
    model_curves: dict[str, FloatArray] = field(default_factory=dict)
    model_keys: dict[str, str] = field(default_factory=dict)

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
    dp = np.asarray(pressure_difference, dtype=float)
    q = np.asarray(leak_rate, dtype=float)
    line = fit_line(dp, q)
    if case.band is not None:
        return _band_linearity(case, line, dp, q, squeeze_pressure, squeeze_pressure_source)
    p0, source = squeeze_pressure, squeeze_pressure_source
    if p0 is None and case.squeeze_pressure.size == 1:
        p0, source = float(case.squeeze_pressure[0]), "the case file"
    elif p0 is None and case.rig is not None:
        p0, source = case.rig.squeeze_pressure(case.seal), "the [rig] load"
    if p0 is None:
        return LinearityCheck(line=line, squeeze_pressure=None, squeeze_pressure_source=source, model_slopes={},
                              alpha_from_slope=None, messages=(Note("linearity_no_squeeze_pressure"),))
    compared = _compare(case, line, dp, q, p0, {m: _conductance(case, [p0], m) for m in _MODELS},
                        entry_pressures(case, _MODELS, p0))
    return LinearityCheck(line=line, squeeze_pressure=p0, squeeze_pressure_source=source, **compared)


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
    data, weighed = volume_flows(case, data)  # a liquid's leak weighed: ṁ/ρ, as fit does (it read 'NaN or inf')
    check = linearity(case, data.pressure_difference, data.leak_rate, squeeze_pressure, squeeze_pressure_source)
    notes: list[NoteLike] = [] if weighed is None else [weighed]
    if case.band is None and check.squeeze_pressure is not None:  # ΔP not small against P0: as fit says (it said nothing)
        p0 = np.full(len(data), check.squeeze_pressure)
        notes += _large_pressure_difference(data, data.pressure_difference, p0, "squeeze_pressure", p0, case.coupled)
    return replace(check, messages=(*notes, *check.messages)) if notes else check


#: The models a linearity check compares with, in the order their slopes are reported.
_MODELS: tuple[Model, ...] = ("critical-junction", "effective-medium")


def _compare(case: Case, line: LinearFit, dp: FloatArray, q: FloatArray, load: float,
             conductances: dict[Model, tuple[FloatArray, tuple[NoteLike, ...]]],
             entry: dict[Model, float]) -> dict[str, Any]:
    """The :class:`LinearityCheck` fields that compare the models with the data at ``load`` (P0 in Pa, or a band
    seal's compression or profile scale): each model's Q(ΔP) (m³/s) at the measured ΔP (Pa) and on the figure's
    grid, coupled (:func:`~sealeak.cases.prediction.leak_curve`) and 0 below its entry pressure ``entry`` (Pa),
    the line through it, its nonlinearity, the α the measured slope implies; notes of a model without a leak channel
    and of measured points the model holds by capillarity. ``conductances``: {model: (K per load, notes)}."""
    grid = np.linspace(0.0, 1.1 * float(dp.max()), CURVE_POINTS + 1)
    # each entry pressure and the float below it: the figure draws the step of eq. 12.3 upright
    steps = [x for p in entry.values() if 0.0 < p < grid[-1] for x in (float(np.nextafter(p, 0.0)), p)]
    grid = np.unique(np.concatenate([grid, steps]))
    x = np.unique(np.concatenate([grid[1:], dp[dp > 0]]))
    out: dict[str, dict[str, float]] = {"model_slopes": {}, "model_intercepts": {}, "model_nonlinearity": {},
                                        "capillary_entry_pressure": {}}
    curves: dict[str, FloatArray] = {}
    messages: list[NoteLike] = []
    alpha_from_slope = None
    keys: dict[str, str] = {}
    for model, (k, notes) in conductances.items():
        name = _model_name(case, model)
        keys[name] = model.replace("-", "_")
        if model in entry:
            out["capillary_entry_pressure"][name] = entry[model]
        if not k[0] > 0:
            messages.extend(notes)
            continue
        free = leak_curve(case, model, load, x) if case.coupled else float(k[0]) * x
        p_e = entry.get(model, float("nan"))
        modelled = np.where(x < p_e, 0.0, free)  # eq. 12.3 (NaN p_e: no capillarity)
        at = np.searchsorted(x, np.maximum(dp, x[0]))
        fitted = fit_line(dp, np.where(dp > 0, modelled[at], 0.0))
        out["model_slopes"][name], out["model_intercepts"][name] = fitted.slope, fitted.intercept
        lo, hi = int(np.argmin(dp)), int(np.argmax(dp))
        out["model_nonlinearity"][name] = (free[at[hi]] / dp[hi]) / (free[at[lo]] / dp[lo]) - 1.0 if dp[lo] > 0 else 0.0
        curves[name] = np.concatenate([[0.0], modelled[np.searchsorted(x, grid[1:])]])
        if model == "critical-junction" and fitted.slope > 0:
            alpha_from_slope = line.slope / (fitted.slope / case.alpha)
        held = dp < p_e
        if held.any():
            messages.append(Note("linearity_held_by_capillarity", {
                "model": name, "entry_pressure": p_e, "points": int(held.sum()), "leaking": int((q[held] > 0).sum())}))
    return {**out, "alpha_from_slope": alpha_from_slope, "messages": tuple(messages), "curve_pressure_difference": grid,
            "model_curves": curves, "model_keys": keys}


def _band_linearity(case: Case, line: LinearFit, dp: FloatArray, q: FloatArray, load: float | None,
                    source: str) -> LinearityCheck:
    """:func:`linearity` of a band seal: the models at one compression or profile scale."""
    band = case.band
    assert band is not None
    if load is None and band.loads.size == 1:
        load, source = float(band.loads[0]), "the case file"
    if load is None:
        return LinearityCheck(line=line, squeeze_pressure=None, squeeze_pressure_source=source, model_slopes={},
                              alpha_from_slope=None, load_name=band.load_name, load=load, messages=(
                                  Note("linearity_one_load_needed", {"loads": int(band.loads.size),
                                                                     "load_name": band.load_name}),))
    ks, res = _band_conductance(case, [load], _MODELS)
    compared = _compare(case, line, dp, q, load, {m: ks[m] for m in _MODELS},
                        entry_pressures(case, _MODELS, float(res.mean_contact_pressure[0]), res))
    return LinearityCheck(line=line, squeeze_pressure=float(res.mean_contact_pressure[0]), squeeze_pressure_source=source,
                          load_name=band.load_name, load=load, **compared)

