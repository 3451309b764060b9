"""Fitting α of both models to measured leak rates (docs/theory.md §8, §10.5, §11.9).

:func:`run_fit` of a data file → :class:`FitResult`, in three variants: a uniform seal (Q against
P0), an O-ring or pressure-profile seal (Q at each measured compression or profile scale), and a gas
case (pV throughputs, the gas law row by row). :func:`fit_models` fits arrays. The checks of a data
file against the case's seal (its load column and loads) live here too and are shared with
:mod:`sealeak.cases.linearity_check`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import FileFormatError, InputError, SealeakError
from ..io.leak_units import pv_throughput
from ..lab.data import LeakData
from ..lab.fitting import ScaleFit, fit_scale
from ..physics.critical_junction import pressure_difference_large
from ..physics.properties import ATMOSPHERE, fluid_state
from ..physics.validity import ALPHA_RANGE as PLAUSIBLE_ALPHA
from .band import BandResult, load_value
from .capillarity import CapillaryRows, band_capillarity, uniform_capillarity
from .gas import CoupledGasSeal, band_gas_seal, gas_throughput, uniform_gas_seals
from .model import Case
from .notes import Note, NoteLike
from .prediction import FloatArray, Model, _band_at, _band_conductance, _band_effective_gap, _band_k, leak_curve, predict, predict_effective_medium
from .verdicts import Verdicts, _band_verdicts, _uniform_verdicts

__all__ = ["fit_models", "FitResult", "run_fit", "seal_description", "volume_flows"]

#: Points of a band seal's critical-junction curve in the fit figure (about 30 ms each).
BAND_CURVE_POINTS = 30


# ---------------------------------------------------------------------- a data file against the case's seal
def seal_description(case: Case) -> str:
    """The case's seal in a few words, for messages about a data file that does not fit it."""
    band = case.band
    if band is None:
        return f"a {case.seal.shape} pressed by a uniform squeeze pressure"
    if band.kind == "o-ring":
        d = f" of {band.cross_section_diameter * 1e3:.4g} mm cross-section" if band.cross_section_diameter else ""
        return f"an O-ring{d}, whose contact follows from its compression"
    return "a pressure-profile seal, whose load is a scale factor on the profile file's pressures"


def _check_load_column(case: Case, data: LeakData, required: bool = True) -> None:
    """The data file's load column must be the one the case's seal takes; one line naming both if not."""
    want = case.band.load_name if case.band is not None else "squeeze_pressure"
    if data.load_name == want or (not required and not data.load_name):
        return
    example = {"squeeze_pressure": "'squeeze_pressure (kPa)'", "compression": "'compression (%)'",
               "profile_scale": "'profile_scale'"}[want]
    if not data.load_name:
        raise FileFormatError(data.path, f"no {want} column: the case's seal is {seal_description(case)}; give a column {example}")
    raise FileFormatError(data.path, f"column '{data.columns.get(data.load_name, data.load_name)}' does not fit the case's "
                                     f"seal, {seal_description(case)}: give a column {example} instead")


# ---------------------------------------------------------------------- fitting α
def fit_models(case: Case, squeeze_pressure: ArrayLike, pressure_difference: ArrayLike,
               leak_rate: ArrayLike) -> dict[str, ScaleFit]:
    """α of the critical-junction and of the effective-medium model for measured (P0, ΔP, Q) (SI).

    Rows without a pressure difference (NaN) use the case's. Least squares in ln Q
    (docs/theory.md §8); keys "critical_junction" and "effective_medium". For an O-ring or
    pressure-profile seal (``case.band``) ``squeeze_pressure`` holds each row's load instead, a
    compression ε (1) or a profile scale (1), and the model is the band's leak rate there
    (docs/theory.md §10.5); the effective medium costs 1–2 s per distinct load.
    """
    dp = np.asarray(pressure_difference, dtype=float)
    dp = np.where(np.isfinite(dp), dp, case.pressure_difference)
    q = np.asarray(leak_rate, dtype=float)
    if case.band is not None:
        return _band_fit(case, squeeze_pressure, dp, q)[0]
    return _uniform_fit(case, np.asarray(squeeze_pressure, dtype=float), dp, q)[0]


def _held(rows: dict[str, CapillaryRows], name: str, dp: FloatArray, at: NDArray[np.int_] | None = None
          ) -> NDArray[np.bool_] | None:
    """The data rows at which model ``name`` holds the liquid by capillarity: ΔP (Pa) below the entry pressure of the
    row's load (``at``: each row's index into ``rows``; docs/theory.md eq. 12.3); None without capillarity."""
    if name not in rows:
        return None
    entry = rows[name].entry_pressure if at is None else rows[name].entry_pressure[at]
    return np.asarray(np.isfinite(entry) & (dp < entry), dtype=bool)


def _uniform_fit(case: Case, p0: FloatArray, dp: FloatArray, q: FloatArray) -> tuple[dict[str, ScaleFit], Verdicts]:
    """:func:`fit_models` of a uniform seal, with each row's validity verdicts (without the ΔP one); rows held by
    capillarity (a case with a contact angle) are excluded, naming whether they leaked."""
    cj = predict(replace(case, alpha=1.0), squeeze_pressure=p0, pressure_difference=dp)
    em = predict_effective_medium(case, squeeze_pressure=p0, pressure_difference=dp)
    rows = uniform_capillarity(case, cj, em)[2] if case.capillarity is not None else {}
    return ({"critical_junction": fit_scale(q, cj.leak_rate, "critical_junction", _held(rows, "critical_junction", dp)),
             "effective_medium": fit_scale(q, em.leak_rate, "effective_medium", _held(rows, "effective_medium", dp))},
            _uniform_verdicts(case, cj, em, pressure_difference=False))


def _band_fit(case: Case, loads: ArrayLike, dp: FloatArray, q: FloatArray
              ) -> tuple[dict[str, ScaleFit], BandResult, NDArray[np.int_]]:
    """:func:`fit_models` of a band seal: Q_i = α q(load_i, ΔP_i) with q at α = 1 (docs/theory.md §10.5, §13.5).

    The band is run once per distinct load at the case's ΔP; as printed it is linear in ΔP, q = K ΔP_i, and with the
    fluid pressure coupled a row at another ΔP takes the band's coupled flow there (eq. 13.3). Rows held by
    capillarity are excluded. Returns the fits, the band result at the distinct loads and each row's index into them.
    """
    distinct, inverse = np.unique(np.asarray(loads, dtype=float), return_inverse=True)
    at_one = replace(case, alpha=1.0)
    ks, res = _band_conductance(at_one, distinct, ("critical-junction", "effective-medium"))
    rows = band_capillarity(case, res)[1] if case.capillarity is not None else {}
    fits = {}
    models: tuple[tuple[Model, str], ...] = (("critical-junction", "critical_junction"), ("effective-medium", "effective_medium"))
    for model, name in models:
        k = ks[model][0]
        prediction = np.where(k > 0, k, np.nan)[inverse] * dp  # NaN: no leak channel at that load
        other = np.isfinite(prediction) & (dp != case.pressure_difference) & (dp > 0)
        if case.coupled and other.any():  # K is the band's at the case's ΔP: the flow at each other ΔP, per load
            for j in np.unique(inverse[other]):
                mine = other & (inverse == j)
                values, back = np.unique(dp[mine], return_inverse=True)
                prediction[mine] = leak_curve(at_one, model, float(distinct[j]), values)[back]
        fits[name] = fit_scale(q, prediction, name, _held(rows, name, dp, inverse))
    return fits, res, inverse


@dataclass(frozen=True, kw_only=True)
class FitResult:
    """α of both models fitted to measured leak rates, with what the fit figure draws (SI units).

    Attributes
    ----------
    case, data
        The case and the measured (P0, ΔP, Q) rows.
    fits
        The :class:`~sealeak.lab.fitting.ScaleFit` of "critical_junction" and "effective_medium"
        (docs/theory.md §8.1).
    reference_pressure_difference
        ΔP of the figure (Pa; the data's, if all rows share one; else the case's).
    same_pressure_difference
        Whether all rows share one ΔP.
    measured
        The measured Q scaled to the reference ΔP (Q ∝ ΔP), m³/s.
    grid
        Squeeze pressures of the model curves (Pa).
    curves
        Each model at α = 1 on ``grid`` (m³/s), or on its own grid in ``curve_grids``.
    messages
        Excluded rows, a single usable point, ΔP not small against P0.
    load_name
        What the x axis is: "squeeze_pressure" (P0, Pa), or for a band seal "compression" (ε, 1)
        or "profile_scale" (1); ``grid`` and the data's :attr:`~sealeak.lab.data.LeakData.load` hold it.
    curve_grids
        A model's own grid, where it is not ``grid``: a band seal's effective medium is drawn
        through its values at the measured loads only (1–2 s each).
    leak_rate_unit
        The unit of ``measured`` and ``curves``: "m^3/s" (a volume flow; liquids), or for a gas
        case "Pa*m^3/s" (the pV throughput the data and the models are compared in, docs/theory.md §11.9).
    outside_validity
        Per model, the data rows (from 0) in its fit at which ``sealeak predict`` would mark that theory
        outside its validity (valid = NO: the gap below the fluid's molecular size, or not a thin film;
        docs/theory.md §9.11). They stay in the fit, named in ``messages``.
    """

    case: Case
    data: LeakData
    fits: dict[str, ScaleFit]
    reference_pressure_difference: float
    same_pressure_difference: bool
    measured: FloatArray
    grid: FloatArray
    curves: dict[str, FloatArray]
    messages: tuple[NoteLike, ...]
    load_name: str = "squeeze_pressure"
    curve_grids: dict[str, FloatArray] = field(default_factory=dict)
    leak_rate_unit: str = "m^3/s"
    outside_validity: dict[str, tuple[int, ...]] = field(default_factory=dict)


def _outside_validity(data: LeakData, fits: dict[str, ScaleFit], verdicts: Verdicts, rows: NDArray[np.int_] | None,
                      load_name: str, loads: FloatArray) -> tuple[list[NoteLike], dict[str, tuple[int, ...]]]:
    """The rows in each model's fit that ``predict`` marks outside the theory's validity: a note per model naming their
    lines, loads and the first reason, and the rows (from 0) per model.

    ``verdicts`` are per row, or per distinct load with ``rows`` each row's index into them. The rows stay in the
    fit (the measurement is real; the theory's number there is the formula's, not a prediction): the note says so.
    """
    valid_cj, why_cj, valid_em, why_em = verdicts
    judged = {"critical_junction": (valid_cj, why_cj)}
    if valid_em is not None and why_em is not None:
        judged["effective_medium"] = (valid_em, why_em)
    at = np.arange(len(data)) if rows is None else rows
    notes: list[NoteLike] = []
    out = {}
    for name, (valid, why) in judged.items():
        bad = tuple(int(i) for i in np.flatnonzero(~np.asarray(valid)[at] & fits[name].used))
        out[name] = bad
        if not bad:
            continue
        notes.append(Note("fit_outside_validity", {
            "theory": name.replace("_", " "), "lines": tuple(data.line_of(i) for i in bad), "load_name": load_name,
            "loads": tuple(float(loads[i]) for i in bad), "reason": why[int(at[bad[0]])]}))
    return notes, out


def _fit_messages(data: LeakData, fits: dict[str, ScaleFit], load_name: str, loads: FloatArray) -> list[NoteLike]:
    """Refuse a fit of no point at all; else the notes on excluded rows (each with its load) and a lone point."""
    if not any(f.fitted for f in fits.values()):
        reasons = "; ".join(f"line {data.line_of(i)}: {r}" for i, r in fits["effective_medium"].excluded[:3])
        raise SealeakError(f"{data.path}: no data point can be fitted by either model ({reasons})")
    messages: list[NoteLike] = [
        Note("fit_excluded", {"theory": name.replace("_", " "), "line": data.line_of(i), "load_name": load_name,
                              "load": float(loads[i]), "reason": reason})
        for name, f in fits.items() for i, reason in f.excluded]
    if not any(f.n_used > 1 for f in fits.values()):
        messages.append(Note("fit_single_point"))
    elif not any(f.n_used > 1 and np.isfinite(f.alpha_std) for f in fits.values()):
        messages.append(Note("fit_repeated_point", {"rows": max(f.n_used for f in fits.values())}))
    low, high = PLAUSIBLE_ALPHA  # a fitted α far from order one (predict warns at the same values): computed, and flagged
    messages += [Note("fit_alpha_far", {"theory": name.replace("_", " "), "alpha": f.alpha, "low": low, "high": high})
                 for name, f in fits.items() if f.fitted and not low <= f.alpha <= high]
    return messages


def _large_pressure_difference(data: LeakData, dp: FloatArray, pressure: FloatArray, load_name: str,
                               loads: FloatArray, coupled: bool) -> list[NoteLike]:
    """A note on the first row whose ΔP (Pa) is large against ``pressure`` (Pa: P0, or a band's peak contact
    pressure at the row's load), with how many rows are like it; none if no row is. Large: ΔP reaches the
    pressure and opens the seal (``coupled``, the fluid pressure in the band; docs/theory.md §13.4), or
    ΔP > pressure/2 (the fluid pressure ignored; §3.6)."""
    large = pressure_difference_large(pressure, dp, coupled)
    if not large.any():
        return []
    i = int(np.argmax(large))
    return [Note("fit_pressure_difference_large", {
        "line": data.line_of(i), "pressure_difference": float(dp[i]), "pressure": float(pressure[i]),
        "load_name": load_name, "load": float(loads[i]), "rows": int(large.sum()), "coupled": coupled})]


def run_fit(case: Case, data: LeakData) -> FitResult:
    """Fit α of both models to measured leak rates (docs/theory.md §8); raises if no row can be used.

    The data file's load column must be the case's (squeeze_pressure for a uniform seal,
    compression for an O-ring, profile_scale for a pressure profile); a mismatch is a
    :class:`~sealeak.errors.FileFormatError` naming the column and the seal.
    """
    _check_load_column(case, data)
    if case.gas is not None:
        return _run_gas_fit(case, data)
    column = data.columns.get("leak_rate", "leak_rate")
    data, weighed = volume_flows(case, data)
    if weighed is not None:
        fitted = run_fit(case, data)
        return replace(fitted, messages=(weighed, *fitted.messages))
    if data.leak_rate_kind in _GAS_ONLY_KINDS:
        raise FileFormatError(data.path, f"column '{column}': a {data.leak_rate_kind.replace('_', ' ')} "
                                         "is a gas's leak rate, and the case's fluid is a liquid: give a volume flow (e.g. "
                                         "'ml/min') or a mass flow (e.g. 'g/h'), or name the gas in the case ([fluid] "
                                         "name, absolute pressures)")
    if case.band is not None:
        return _run_band_fit(case, data)
    dp_used = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    fits, verdicts = _uniform_fit(case, data.squeeze_pressure, dp_used, data.leak_rate)
    messages = _fit_messages(data, fits, "squeeze_pressure", data.squeeze_pressure)
    notes, outside = _outside_validity(data, fits, verdicts, None, "squeeze_pressure", data.squeeze_pressure)
    messages += notes
    messages += _large_pressure_difference(data, dp_used, data.squeeze_pressure, "squeeze_pressure", data.squeeze_pressure,
                                           case.coupled)
    p0 = data.squeeze_pressure
    same = bool(np.allclose(dp_used, dp_used[0]))
    ref_dp = float(dp_used[0]) if same else case.pressure_difference
    measured = data.leak_rate * (1.0 if same else ref_dp / np.where(dp_used > 0, dp_used, np.nan))
    grid = np.geomspace(p0.min(), p0.max(), 40) if p0.max() > p0.min() else np.array([p0.min()])
    curves = {
        "critical_junction": predict(replace(case, alpha=1.0), squeeze_pressure=grid,
                                     pressure_difference=ref_dp).leak_rate,
        "effective_medium": predict_effective_medium(case, squeeze_pressure=grid, pressure_difference=ref_dp).leak_rate,
    }
    return FitResult(case=case, data=data, fits=fits, reference_pressure_difference=ref_dp,
                     same_pressure_difference=same, measured=measured, grid=grid, curves=curves,
                     messages=tuple(messages), outside_validity=outside)


def volume_flows(case: Case, data: LeakData) -> tuple[LeakData, Note | None]:
    """A liquid's data with its leak rates weighed (g/h, kg/s) as the volume flows ṁ/ρ at the liquid's density, and the
    note saying so (``data`` and None when they are not mass flows); a mass flow without a density known is a
    FileFormatError naming the column."""
    if data.leak_rate_kind != "mass_flow":
        return data, None
    column = data.columns.get("leak_rate", "leak_rate")
    density = _liquid_density(case)
    if density is None:
        raise FileFormatError(data.path, f"column '{column}': a mass flow of a liquid needs its density: give "
                                         "fluid.density in the case (or name a liquid the property library knows), or "
                                         "give a volume flow (e.g. 'ml/min')")
    assert data.leak_rate_si is not None
    return (replace(data, leak_rate=data.leak_rate_si / density, leak_rate_kind="volume_flow"),
            Note("fit_mass_flow", {"column": column, "density": density}))


def _liquid_density(case: Case) -> float | None:
    """ρ (kg/m³) of a liquid case: ``fluid.density``, else the property library's for a named liquid at the case's
    temperature and 1 atm (a case that gives the viscosity of water looks nothing up until a mass flow needs it); None
    for an unnamed liquid, or one the library does not know."""
    if case.fluid.density is not None:
        return case.fluid.density
    if case.fluid.name is None:
        return None
    try:
        state = fluid_state(case.fluid.name, case.temperature, ATMOSPHERE)
    except InputError:  # (an oil, or a name the library does not know)
        return None
    return None if state.is_gas else state.density


#: One theory of a gas fit at its loads: K at α = 1 (m³/(Pa·s)), the narrowest gap (m), the constriction's length λ_c
#: (m), and with the fluid pressure coupled the :class:`~sealeak.cases.gas.CoupledGasSeal` at α = 1 of each load (else None).
_GasModel = tuple[FloatArray, FloatArray, FloatArray, list[CoupledGasSeal] | None]

#: Leak-rate kinds only a gas case can convert (:mod:`sealeak.io.leak_units`).
_GAS_ONLY_KINDS = ("standard_volume_flow", "molar_flow", "mass_flow")


def _run_gas_fit(case: Case, data: LeakData) -> FitResult:
    """:func:`run_fit` of a gas case: measured and predicted pV throughputs (Pa·m³/s), α scaling K (docs/theory.md §11.9).

    Each theory's prediction at a row is K(α = 1) ∫ p f(Kn(p)) dp from P_b to P_b + ΔP_row with the
    gap of :func:`gas_rows` (u_c, u_e, or u_c at the band's peak pressure), or with the fluid pressure coupled the
    exact gas coupling at α = 1 of the row's load at its P_a (:class:`~sealeak.cases.gas.CoupledGasSeal`, docs/theory.md
    §13.5). α scales σ(s) and not the critical junction's gap u_c(s), so Kn and f do not depend on α: the throughput is
    proportional to α, and :func:`~sealeak.lab.fitting.fit_scale` applies (the effective medium's α is a factor on
    its prediction).
    """
    gas = case.gas
    assert gas is not None
    assert data.leak_rate_si is not None
    # the data's leak rates as pV throughputs of the case's gas at its temperature (docs/theory.md §11.6)
    q = pv_throughput(data.leak_rate_si, data.leak_rate_kind, temperature=gas.temperature, molar_mass=gas.gas.molar_mass,
                      pressure=data.reference_pressure)
    dp = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)

    def models(at: Case, loads: FloatArray) -> tuple[dict[str, _GasModel], Verdicts, FloatArray]:
        """(K at α = 1, gap, length λ_c, coupled seals at α = 1 or None) of both theories at ``loads`` (those of
        :func:`gas_rows`), their verdicts there, and the pressure that holds the seal shut at each (Pa: P0, or the
        band's peak contact pressure)."""
        one = replace(at, alpha=1.0)
        if at.band is not None:
            ks, res = _band_conductance(one, loads, ("critical-junction", "effective-medium"))
            assert res.effective_medium is not None
            lam = res.critical_wavelength_at_max_pressure
            at_loads = _band_at(one, loads)

            def band_seals(model: Model, percolates: NDArray[np.bool_]) -> list[CoupledGasSeal] | None:
                return ([band_gas_seal(at_loads, model, i, bool(ok)) for i, ok in enumerate(percolates)]
                        if at.coupled else None)
            return ({"critical_junction": (ks["critical-junction"][0], res.critical_gap_at_max_pressure, lam,
                                           band_seals("critical-junction", res.critical_junction.percolates)),
                     "effective_medium": (ks["effective-medium"][0], _band_effective_gap(at, res.effective_medium), lam,
                                          band_seals("effective-medium", res.effective_medium.percolates))},
                    _band_verdicts(at, res, pressure_difference=False), res.max_contact_pressure)
        # K = Q/ΔP: at ΔP → 0 as printed; with the fluid pressure coupled at the case's ΔP, as predict (theory §13.5)
        dp_k = at.pressure_difference if at.coupled else 1.0
        cj = predict(one, squeeze_pressure=loads, pressure_difference=dp_k)
        em = predict_effective_medium(at, squeeze_pressure=loads, pressure_difference=dp_k)

        def seals(model: Model, percolates: NDArray[np.bool_]) -> list[CoupledGasSeal] | None:
            return uniform_gas_seals(one, model, loads, percolates) if at.coupled else None
        return ({"critical_junction": (np.where(cj.percolates, cj.leak_rate / dp_k, 0.0), cj.critical_gap, cj.critical_wavelength,
                                       seals("critical-junction", cj.percolates)),
                 "effective_medium": (np.where(em.percolates, em.leak_rate / dp_k, 0.0),
                                      np.where(em.percolates, em.effective_gap, np.nan), cj.critical_wavelength,
                                      seals("effective-medium", em.percolates))},
                _uniform_verdicts(at, cj, em, pressure_difference=False), loads)

    loads = data.band_load if case.band is not None and data.band_load is not None else data.squeeze_pressure
    distinct, inverse = np.unique(loads, return_inverse=True)
    at_distinct, verdicts, holding = models(case, distinct)
    fits = {name: fit_scale(q, gas_throughput(case, k[inverse], gap[inverse], dp, lam[inverse],
                                              None if seals is None else [seals[j] for j in inverse]), name)
            for name, (k, gap, lam, seals) in at_distinct.items()}
    load_name = case.band.load_name if case.band is not None else "squeeze_pressure"
    messages = _fit_messages(data, fits, load_name, loads)
    notes, outside = _outside_validity(data, fits, verdicts, inverse, load_name, loads)
    messages += notes
    # ΔP large against P0 or the band's peak, as a liquid's fit says (1000 bar against 200 kPa said nothing)
    messages += _large_pressure_difference(data, dp, holding[inverse], load_name, loads, case.coupled)
    messages.append(Note("fit_pv_throughputs", {"gas": gas.gas.name, "temperature": float(gas.temperature),
                                                "downstream_pressure": float(gas.downstream_pressure)}))
    same = bool(np.allclose(dp, dp[0]))
    ref_dp = float(dp[0]) if same else case.pressure_difference
    pb = gas.downstream_pressure
    # the figure's points at the reference ΔP: scaled with the no-slip law (P_a² − P_b²), approximate with slip
    measured = q if same else q * ((pb + ref_dp) ** 2 - pb**2) / ((pb + dp) ** 2 - pb**2)
    if case.band is not None:
        grid = distinct
        at_grid = at_distinct
    else:
        grid = np.geomspace(loads.min(), loads.max(), 40) if loads.max() > loads.min() else loads[:1].copy()
        at_grid = models(case, grid)[0]
    curves = {name: gas_throughput(case, k, gap, np.full(grid.size, ref_dp), lam, seals)
              for name, (k, gap, lam, seals) in at_grid.items()}
    return FitResult(case=case, data=data, fits=fits, reference_pressure_difference=ref_dp, same_pressure_difference=same,
                     measured=measured, grid=grid, curves=curves, messages=tuple(messages), load_name=load_name,
                     leak_rate_unit="Pa*m^3/s", outside_validity=outside)


def _check_file_loads(case: Case, data: LeakData, loads: NDArray[np.float64]) -> None:
    """The band seal at a data file's loads; a load its relations refuse raises a FileFormatError naming the line and column."""
    band = case.band
    assert band is not None
    column = data.columns.get(band.load_name, band.load_name)
    distinct = np.unique(loads)
    try:
        _band_at(case, distinct)
    except InputError:  # a load the seal's relations refuse: name its line in the data file
        for v in distinct:
            try:
                _band_at(case, [v])
            except InputError as exc:
                row = int(np.argmax(loads == v))
                raise FileFormatError(data.path, f"line {data.line_of(row)}, column '{column}': "
                                                 f"{band.load_name.replace('_', ' ')} {load_value(band.load_name, v)}: "
                                                 f"{exc.allowed}") from None
        raise


def _row_error(data: LeakData, loads: FloatArray, exc: InputError) -> SealeakError:
    """``exc`` about a band's load (``conditions.compression[i] = '0.0001 %': ...``, the data file's loads run as the
    case's) as the data file's line and column that gave it; ``exc`` itself where it names no load of the file."""
    name = data.load_name
    if not name or not str(exc.field).startswith(f"conditions.{name}"):
        return exc
    rows = [i for i, v in enumerate(loads.tolist()) if load_value(name, v) == exc.value]
    if not rows:
        return exc
    column = data.columns.get(name, name)
    return FileFormatError(data.path, f"line {data.line_of(rows[0])}, column '{column}': {name.replace('_', ' ')} "
                                      f"{exc.value}: {exc.allowed}")


def _run_band_fit(case: Case, data: LeakData) -> FitResult:
    """:func:`run_fit` of an O-ring or pressure-profile seal: the band's leak rate at each row's load (docs/theory.md §10.5)."""
    band = case.band
    assert band is not None and data.band_load is not None
    loads = data.band_load
    dp_used = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    _check_file_loads(case, data, loads)
    distinct = np.unique(loads)
    try:
        fits, res, inverse = _band_fit(case, loads, dp_used, data.leak_rate)
    except InputError as exc:  # a row's load the contact theory cannot use: its line, not conditions.compression[0]
        raise _row_error(data, loads, exc) from None
    messages = _fit_messages(data, fits, band.load_name, loads)
    notes, outside = _outside_validity(data, fits, _band_verdicts(case, res, pressure_difference=False), inverse,
                                       band.load_name, loads)
    messages += notes
    if res.band.oring is not None:
        messages += list(res.band.oring.warnings)
    # ΔP against the peak contact pressure of each row's load (the band's verdict, docs/theory.md §10.1)
    messages += _large_pressure_difference(data, dp_used, res.max_contact_pressure[inverse], band.load_name, loads, case.coupled)
    same = bool(np.allclose(dp_used, dp_used[0]))
    ref_dp = float(dp_used[0]) if same else case.pressure_difference
    measured = data.leak_rate * (1.0 if same else ref_dp / np.where(dp_used > 0, dp_used, np.nan))
    grid = np.linspace(loads.min(), loads.max(), BAND_CURVE_POINTS) if loads.max() > loads.min() else loads[:1].copy()
    ks_grid, _ = _band_conductance(replace(case, alpha=1.0), grid, ("critical-junction",))
    k_em = _band_k(res, res.effective_medium) if res.effective_medium is not None else np.zeros(distinct.size)
    curves = {"critical_junction": np.where(ks_grid["critical-junction"][0] > 0, ks_grid["critical-junction"][0], np.nan) * ref_dp,
              "effective_medium": np.where(k_em > 0, k_em, np.nan) * ref_dp}
    return FitResult(case=case, data=data, fits=fits, reference_pressure_difference=ref_dp, same_pressure_difference=same,
                     measured=measured, grid=grid, curves=curves, messages=tuple(messages), load_name=band.load_name,
                     curve_grids={"effective_medium": distinct}, outside_validity=outside)
