"""Running a case: the one place where a front end asks for numbers.

:func:`run_case` takes a :class:`~sealeak.cases.model.Case` and returns a :class:`CaseResult` that
holds everything the command line, the report, the figures and the JSON/CSV files show: both
theories' predictions, the spectrum statistics, the notes, and the SI unit of every field.
Front ends (``sealeak.render``, ``sealeak.cli``) format it; they compute nothing themselves.

The other entry points of this layer:

* :func:`predict`, :func:`predict_effective_medium`: one theory at the case's (or given) pressures;
* :func:`conductance`: K = Q/ΔP of a model at squeeze pressures, or at the loads of an O-ring or
  pressure-profile seal (both theories are linear in ΔP, docs/theory.md §3, §5 and §10.1), used by
  the rig, the linearity check and the fit;
* :func:`fit_models`, :func:`linearity`, :func:`rig_prediction`, :func:`rig_readings`: the
  laboratory workflows (docs/theory.md §4 and §8) applied to a case, a uniform seal or a band seal
  (docs/theory.md §10.5: the band's leak rate at each measured compression or profile scale);

The curves of the prediction figures are computed in :mod:`sealeak.cases.curves`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import FileFormatError, InputError, SealeakError
from ..io.units import molar_flow_factor
from ..lab.data import LeakData
from ..lab.fitting import LinearFit, ScaleFit, fit_line, fit_scale
from ..lab.rig import DecayRigSetup, ReadingsAnalysis, WaterColumn, drain_time, leak_rate_from_readings, water_column
from ..physics.critical_junction import CriticalJunctionResult, critical_junction, pressure_difference_not_small
from ..physics.effective_medium import EffectiveMediumResult, effective_medium
from ..physics.gas import MOLAR_GAS_CONSTANT, Gas, GasLeak, gas_leak, pressure_integral
from ..physics.properties import fluid_state
from ..physics.seal import Seal
from ..physics.validity import assumption_warnings, continuum_verdict, strain_warning
from .band import BAND_EFFECTIVE_MEDIUM_UNITS, BAND_UNITS, BandResult, BandTheory, run_band
from .leak_tests import DecayPrediction, decay_prediction
from .model import Case
from .schema import case_keys
from .seals import with_loads

__all__ = [
    "CaseResult", "run_case", "case_warnings", "predict", "predict_effective_medium", "conductance", "Model",
    "RESULT_UNITS", "EFFECTIVE_MEDIUM_UNITS", "MODEL_NAMES",
    "fit_models", "FitResult", "run_fit", "LinearityCheck", "linearity", "run_linearity", "RigPrediction", "rig_prediction",
    "rig_readings", "seal_description", "GasRows", "gas_rows", "GAS_UNITS", "HELIUM_UNITS", "HELIUM_TEST",
    "helium_test_gas", "gas_throughput",
]

FloatArray = NDArray[np.float64]

#: A leak-rate model: the critical-junction theory (docs/theory.md §3) or the effective medium (§5).
Model = Literal["critical-junction", "effective-medium"]

#: Points of a band seal's critical-junction curve in the fit figure (about 30 ms each).
BAND_CURVE_POINTS = 30

#: How front ends name the models.
MODEL_NAMES: dict[str, str] = {"critical-junction": "critical junction", "effective-medium": "effective medium"}

#: SI unit of every field of a critical-junction result record (JSON ``units``, CSV headers).
RESULT_UNITS: dict[str, str] = {
    "squeeze_pressure": "Pa",
    "pressure_difference": "Pa",
    "percolates": "1",
    "critical_magnification": "1",
    "critical_gap": "m",
    "critical_wavelength": "m",
    "leak_rate": "m^3/s",
    "contact_area_at_cutoff": "1",
    "valid": "1",
    "validity": "",
}

#: SI unit of the effective-medium fields (added to a record when the case asks for that model).
EFFECTIVE_MEDIUM_UNITS: dict[str, str] = {
    "percolates_effective_medium": "1",
    "effective_conductivity": "m^3/(Pa*s)",
    "effective_gap": "m",
    "leak_rate_effective_medium": "m^3/s",
    "mean_gap": "m",
    "gap_distribution_mean": "m",
    "valid_effective_medium": "1",
    "validity_effective_medium": "",
}
_EM_ATTR = {"percolates_effective_medium": "percolates", "effective_conductivity": "effective_conductivity",
            "effective_gap": "effective_gap", "leak_rate_effective_medium": "leak_rate", "mean_gap": "mean_gap",
            "gap_distribution_mean": "gap_distribution_mean"}

#: SI unit of the gas fields of a record (a gas case); the effective medium's carry the suffix ``_effective_medium``.
GAS_UNITS: dict[str, str] = {
    "knudsen_number": "1",
    "flow_regime": "",
    "leak_rate_pv": "Pa*m^3/s",
    "leak_rate_mbar_l_s": "mbar*l/s",
    "leak_rate_mass": "kg/s",
    "leak_rate_molar": "mol/s",
    "leak_rate_sccm": "sccm",
}

#: SI unit of the helium-equivalent fields (a gas case, or a liquid with ``conditions.helium_equivalent``).
HELIUM_UNITS: dict[str, str] = {"leak_rate_helium_pv": "Pa*m^3/s", "leak_rate_helium_mbar_l_s": "mbar*l/s"}

#: The standard helium leak test: helium at 1 bar (absolute) against vacuum, 20 °C (docs/theory.md §11.9).
HELIUM_TEST = {"upstream_pressure": 1e5, "downstream_pressure": 0.0, "temperature": 293.15}

#: 1 mbar·l/s in Pa·m³/s.
MBAR_LITRE_PER_SECOND = 0.1


# ---------------------------------------------------------------------- the theories for a case
def predict(case: Case, squeeze_pressure: ArrayLike | None = None,
            pressure_difference: ArrayLike | None = None) -> CriticalJunctionResult:
    """Critical-junction leak rate of ``case`` at its squeeze pressures (or the ones given), in SI units.

    Lorenz & Persson (2009) eq. 2 (docs/theory.md §3).
    """
    with case_keys():
        return critical_junction(
            case.contact(),
            squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
            pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
            viscosity=case.fluid.viscosity,
            aspect_ratio=case.seal.aspect_ratio,
            alpha=case.alpha,
            percolation_threshold=case.percolation_threshold,
        )


def predict_effective_medium(case: Case, squeeze_pressure: ArrayLike | None = None,
                             pressure_difference: ArrayLike | None = None) -> EffectiveMediumResult:
    """Bruggeman effective-medium leak rate Q = (Ly/Lx) σ_eff ΔP of ``case`` in m³/s (Bruggeman (1935); docs/theory.md §5.3)."""
    with case_keys():
        return effective_medium(
            case.contact(),
            squeeze_pressure=case.squeeze_pressure if squeeze_pressure is None else squeeze_pressure,
            pressure_difference=case.pressure_difference if pressure_difference is None else pressure_difference,
            viscosity=case.fluid.viscosity,
            aspect_ratio=case.seal.aspect_ratio,
        )


def conductance(case: Case, squeeze_pressure: ArrayLike, model: Model = "critical-junction") -> FloatArray:
    """K = Q/ΔP of the seal (m³/(Pa·s)) at each squeeze pressure P0 (Pa), for one model.

    Both theories are linear in ΔP at fixed P0, so K is the leak rate at ΔP = 1 Pa: for the
    critical junction K = α (Ly/Lx) u_c³/(12η) (Lorenz & Persson (2009) eq. 2), for the effective
    medium K = (Ly/Lx) σ_eff (docs/theory.md §5). K = 0 where the model predicts no leak channel.

    For an O-ring or pressure-profile seal (``case.band``) ``squeeze_pressure`` holds the loads
    instead, compressions ε (1) or profile scales (1), and K = faces · Ly / ∫₀^w dx/σ(p(x)) of the
    band at each (docs/theory.md §10.1); the effective medium costs 1–2 s per load.
    """
    return _conductance(case, squeeze_pressure, model)[0]


def _conductance(case: Case, squeeze_pressure: ArrayLike, model: Model) -> tuple[FloatArray, tuple[str, ...]]:
    """:func:`conductance` and the model's notes (why there is no leak channel, where there is none)."""
    if model not in ("critical-junction", "effective-medium"):
        raise InputError("model", model, "allowed: 'critical-junction', 'effective-medium'")
    if case.band is not None:
        ks, _ = _band_conductance(case, squeeze_pressure, (model,))
        return ks[model]
    p0 = np.atleast_1d(np.asarray(squeeze_pressure, dtype=float))
    res: CriticalJunctionResult | EffectiveMediumResult
    if model == "critical-junction":
        res = predict(case, squeeze_pressure=p0, pressure_difference=1.0)
    else:
        res = predict_effective_medium(case, squeeze_pressure=p0, pressure_difference=1.0)
    return np.where(res.percolates, res.leak_rate, 0.0), res.messages


# ---------------------------------------------------------------------- band seals at other loads
def _q0_fixed(case: Case) -> float | None:
    """The q0 (1/m) a band case's file fixed (``theory.lowest_wavevector``/``square_side``), or None: 2π/w per load."""
    assert case.band is not None
    return case.band.q0_fixed


def _band_at(case: Case, loads: ArrayLike) -> Case:
    """The band case at other loads (compressions ε or profile scales, 1): its profiles, q0, seal and mean pressures.

    :func:`~sealeak.cases.seals.with_loads` builds the same seal at ``loads``; q0 stays fixed if the
    case file fixed it, else it is 2π/w of each load's contact width (docs/theory.md §10.1).
    """
    band = case.band
    assert band is not None
    values = np.atleast_1d(np.asarray(loads, dtype=float))
    if np.array_equal(values, band.loads):
        return case
    new = with_loads(band, values, case.youngs_modulus, case.poisson_ratio, _q0_fixed(case))
    widths = np.array([p.width for p in new.profiles])
    with case_keys():
        seal = Seal(width=float(widths.max()), length=new.length, shape=new.kind)
    return replace(case, band=new, seal=seal, squeeze_pressure=np.array([p.mean_pressure for p in new.profiles]))


def _band_k(band_result: BandResult, theory: BandTheory) -> FloatArray:
    """K = faces · Ly / R (m³/(Pa·s)) of each load, 0 where the band holds no leak channel (docs/theory.md §10.1)."""
    band = band_result.band
    with np.errstate(divide="ignore"):
        return np.where(theory.percolates, band.faces * band.length / theory.resistance, 0.0)


def _band_conductance(case: Case, loads: ArrayLike | None,
                      models: tuple[str, ...]) -> tuple[dict[str, tuple[FloatArray, tuple[str, ...]]], BandResult]:
    """K of a band seal per model at ``loads`` (None: the case's), with each theory's notes, and the band result.

    One :func:`~sealeak.cases.band.run_band` serves both models (the effective medium only when asked:
    it costs 1–2 s per load).
    """
    at = case if loads is None else _band_at(case, loads)
    res = run_band(at, effective="effective-medium" in models)
    out: dict[str, tuple[FloatArray, tuple[str, ...]]] = {}
    for model in models:
        theory = res.critical_junction if model == "critical-junction" else res.effective_medium
        assert theory is not None
        out[model] = (_band_k(res, theory), theory.messages)
    return out, res


def _load_text(load_name: str, value: float) -> str:
    """"compression 20 %", "profile scale 1.5" or "P0 = 30000 Pa" for one load."""
    if load_name == "compression":
        return f"compression {100 * value:.4g} %"
    if load_name == "profile_scale":
        return f"profile scale {value:.4g}"
    return f"P0 = {value:.6g} Pa"


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


def _model_name(case: Case, model: Model) -> str:
    """How the rig and the linearity check name a model (with α for the critical junction)."""
    return f"critical junction (α = {case.alpha:g})" if model == "critical-junction" else "effective medium (Bruggeman)"


# ---------------------------------------------------------------------- gases
def helium_test_gas() -> Gas:
    """Helium at 20 °C and 1 bar from the property library: the gas of the helium-equivalent leak rate."""
    t, p = HELIUM_TEST["temperature"], HELIUM_TEST["upstream_pressure"]
    return fluid_state("helium", t, p).gas()


@dataclass(frozen=True)
class GasRows:
    """One theory's gas leak per row (squeeze pressure or load), SI units (docs/theory.md §11.5, §11.9).

    Attributes
    ----------
    conductance
        K = Q/ΔP of the seal with the case's viscosity (m³/(Pa·s)); 0 where no leak channel.
    gap
        h, the gap of the narrowest constriction (m): u_c (critical junction), u_e (effective
        medium), or u_c at the peak contact pressure of a band seal; NaN where no leak channel.
    leaks
        The :class:`~sealeak.physics.gas.GasLeak` of the case's gas per row (None: a liquid case,
        or no leak channel).
    helium
        Q_pV of helium in the standard test (1 bar against vacuum, 20 °C) through the same seal,
        Pa·m³/s (None: not asked for).

    Rows without a leak channel hold NaN leak rates (``null`` in JSON), as the liquid's ``leak_rate``.
    """

    conductance: FloatArray
    gap: FloatArray
    leaks: tuple[GasLeak | None, ...] | None
    helium: FloatArray | None

    def fields(self, suffix: str = "") -> dict[str, Any]:
        """The record fields (:data:`GAS_UNITS`, :data:`HELIUM_UNITS`, with ``suffix``) as arrays per row."""
        out: dict[str, Any] = {}
        if self.leaks is not None:
            def pick(attr: str) -> FloatArray:
                return np.array([getattr(g, attr) if g is not None else np.nan for g in self.leaks or ()])

            pv = pick("throughput")
            molar = pick("molar_flow")
            sccm = molar / molar_flow_factor("leak_rate", "sccm", temperature=1.0, molar_mass=1.0)
            out |= {"knudsen_number": np.array([g.knudsen_mean if g is not None else np.nan for g in self.leaks]),
                    "flow_regime": [g.regime if g is not None else "" for g in self.leaks],
                    "leak_rate_pv": pv, "leak_rate_mbar_l_s": pv / MBAR_LITRE_PER_SECOND, "leak_rate_mass": pick("mass_flow"),
                    "leak_rate_molar": molar, "leak_rate_sccm": sccm}
        if self.helium is not None:
            out |= {"leak_rate_helium_pv": self.helium, "leak_rate_helium_mbar_l_s": self.helium / MBAR_LITRE_PER_SECOND}
        return {k + suffix: v for k, v in out.items()}


def gas_rows(case: Case, conductance: ArrayLike, gap: ArrayLike) -> GasRows:
    """The case's gas leak (if a gas case) and the helium equivalent (if asked for) per row.

    ``conductance`` K (m³/(Pa·s)) was computed with ``case.fluid.viscosity``, the gas's own
    viscosity for a gas case (K ∝ 1/μ: Poiseuille flow). The helium equivalent is the helium leak
    of the same seal: K μ_case/μ_He, the same gap, helium's rarefaction, 1 bar against vacuum at
    20 °C (docs/theory.md §11.9).
    """
    k = np.atleast_1d(np.asarray(conductance, dtype=float))
    h = np.atleast_1d(np.asarray(gap, dtype=float))
    channel = (k > 0) & np.isfinite(h) & (h > 0)
    leaks = None
    gas = case.gas
    if gas is not None:
        with case_keys():
            leaks = tuple(gas_leak(float(k[i]), float(h[i]), gas.gas, gas.upstream_pressure, gas.downstream_pressure,
                                   gas.rarefaction) if channel[i] else None for i in range(k.size))
    helium = None
    if case.helium_equivalent:
        he = helium_test_gas()
        scale = case.fluid.viscosity / he.viscosity
        pa, pb = HELIUM_TEST["upstream_pressure"], HELIUM_TEST["downstream_pressure"]
        helium = np.array([gas_leak(float(k[i]) * scale, float(h[i]), he, pa, pb, case.rarefaction).throughput
                           if channel[i] else np.nan for i in range(k.size)])
    return GasRows(np.where(channel, k, 0.0), np.where(channel, h, np.nan), leaks, helium)


def _uniform_gas(case: Case, res: CriticalJunctionResult, em: EffectiveMediumResult | None) -> dict[str, GasRows]:
    """Gas rows of a uniform seal: K = Q/ΔP of each theory; the gap u_c, or u_e for the effective medium."""
    out = {"critical_junction": gas_rows(case, np.where(res.percolates, res.leak_rate / res.pressure_difference, 0.0),
                                         res.critical_gap)}
    if em is not None:
        out["effective_medium"] = gas_rows(case, np.where(em.percolates, em.leak_rate / em.pressure_difference, 0.0),
                                           np.where(em.percolates, em.effective_gap, np.nan))
    return out


def _band_gas(case: Case, band: BandResult) -> dict[str, GasRows]:
    """Gas rows of a band seal: K = Q/ΔP of the band; the gap of the narrowest constriction, u_c at the peak
    contact pressure (critical junction) or u_e = (12 μ σ_min)^(1/3) of the smallest σ along the band (effective
    medium), docs/theory.md §11.9."""
    out = {}
    for name, theory in (("critical_junction", band.critical_junction), ("effective_medium", band.effective_medium)):
        if theory is None or theory.leak_rate is None:
            continue
        k = np.where(theory.percolates, np.nan_to_num(theory.leak_rate) / band.pressure_difference, 0.0)
        gap = band.critical_gap_at_max_pressure if name == "critical_junction" else _band_effective_gap(case, theory)
        out[name] = gas_rows(case, k, gap)
    return out


def _band_effective_gap(case: Case, theory: BandTheory) -> FloatArray:
    """u_e = (12 μ σ_min)^(1/3) (m) per load: the effective medium's narrowest constriction along the band, σ_min the
    smallest sheet conductance of its quadrature; NaN where the band holds no leak channel (docs/theory.md §11.9)."""
    return np.array([float(np.cbrt(12.0 * case.fluid.viscosity * np.min(g.conductance[g.conductance > 0])))
                     if ok and np.any(g.conductance > 0) else np.nan
                     for g, ok in zip(theory.integrals, theory.percolates)])


# ---------------------------------------------------------------------- one result for every front end
@dataclass(frozen=True)
class CaseResult:
    """Everything a front end shows for one case (SI units throughout).

    Attributes
    ----------
    case
        The case that was run.
    critical_junction
        The critical-junction prediction at the case's squeeze pressures (always computed: it is
        the reference paper's theory; Lorenz & Persson (2009) eq. 2, docs/theory.md §3).
    effective_medium
        The effective-medium prediction (docs/theory.md §5), when ``case.model`` asks for it.
    rig
        The virtual water-column rig (docs/theory.md §4), when the case has a ``[rig]`` section.
    messages
        The notes of both theories (and the rig), each prefixed with its theory.
    valid, validity
        Verdict per squeeze pressure on the critical-junction result: False where the critical
        gap u_c is below the fluid's molecular size (no continuum flow; docs/theory.md §9.11), and
        the reason ('' where valid; a pressure without leak channel is valid: nothing flows).
    valid_effective_medium, validity_effective_medium
        The same for the effective medium's gap u_e (None when that model was not run).
    warnings
        Inputs far outside what the theory assumes, in plain words (docs/theory.md §9.11); the
        numbers are computed all the same.
    band
        For an O-ring or pressure-profile seal (``case.band``): the leak rates per load through the
        non-uniform band (docs/theory.md §10), which front ends show instead of the uniform table;
        ``critical_junction`` then holds the uniform prediction at each load's mean pressure and the
        verdicts judge the band at its highest pressure.
    gas
        For a gas case, or a liquid with ``conditions.helium_equivalent``: the gas leak and the
        helium equivalent of each theory ("critical_junction", "effective_medium"), per row; the
        rows are the band's loads for a band seal (docs/theory.md §11.9).
    """

    case: Case
    critical_junction: CriticalJunctionResult
    effective_medium: EffectiveMediumResult | None = None
    rig: RigPrediction | DecayPrediction | None = None
    messages: tuple[str, ...] = ()
    valid: NDArray[np.bool_] = field(default_factory=lambda: np.ones(0, dtype=bool))
    validity: tuple[str, ...] = ()
    valid_effective_medium: NDArray[np.bool_] | None = None
    validity_effective_medium: tuple[str, ...] | None = None
    warnings: tuple[str, ...] = ()
    band: BandResult | None = None
    gas: dict[str, GasRows] | None = None

    @property
    def shows_critical_junction(self) -> bool:
        """Whether front ends show the critical-junction numbers (not for model = "effective-medium")."""
        if self.band is not None:
            return self.case.model != "effective-medium"
        return self.case.model != "effective-medium" or self.effective_medium is None

    @property
    def units(self) -> dict[str, str]:
        """SI unit of every field of :meth:`records`."""
        if self.band is not None:
            em = BAND_EFFECTIVE_MEDIUM_UNITS if self.band.effective_medium is not None else {}
            regime = {"regime": ""} if self.band.band.oring is not None else {}
            return {self.band.band.load_name: "1"} | regime | BAND_UNITS | em | self._gas_units
        return RESULT_UNITS | (EFFECTIVE_MEDIUM_UNITS if self.effective_medium is not None else {}) | self._gas_units

    @property
    def _gas_units(self) -> dict[str, str]:
        out: dict[str, str] = {}
        for name, rows in (self.gas or {}).items():
            suffix = "_effective_medium" if name == "effective_medium" else ""
            units = (GAS_UNITS if rows.leaks is not None else {}) | (HELIUM_UNITS if rows.helium is not None else {})
            out |= {k + suffix: u for k, u in units.items()}
        return out

    def _gas_fields(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for name, rows in (self.gas or {}).items():
            out |= rows.fields("_effective_medium" if name == "effective_medium" else "")
        return out

    @property
    def shown_valid(self) -> NDArray[np.bool_]:
        """The verdict of the model front ends show (critical junction, or the effective medium alone)."""
        if not self.shows_critical_junction and self.valid_effective_medium is not None:
            return self.valid_effective_medium
        return self.valid

    def records(self) -> list[dict[str, Any]]:
        """One dict per squeeze pressure with the fields of :attr:`units` (SI values; NaN kept)."""
        if self.band is not None:
            return self._band_records(self.band)
        res, em = self.critical_junction, self.effective_medium
        gas = self._gas_fields()
        out = []
        for i in range(len(res)):
            rec: dict[str, Any] = {"variant": self.case.label} if self.case.label else {}
            for key in RESULT_UNITS:
                rec[key] = bool(self.valid[i]) if key == "valid" else self.validity[i] if key == "validity" else getattr(res, key)[i]
            if em is not None and self.valid_effective_medium is not None and self.validity_effective_medium is not None:
                for key, attr in _EM_ATTR.items():
                    rec[key] = getattr(em, attr)[i]
                rec["valid_effective_medium"] = bool(self.valid_effective_medium[i])
                rec["validity_effective_medium"] = self.validity_effective_medium[i]
            rec |= {k: _plain(v[i]) for k, v in gas.items()}
            out.append(rec)
        return out


    def _band_records(self, b: BandResult) -> list[dict[str, Any]]:
        cj, em = b.critical_junction, b.effective_medium
        values: dict[str, Any] = {
            b.band.load_name: b.band.loads, "contact_width": b.contact_width, "force_per_length": b.force_per_length,
            "mean_contact_pressure": b.mean_contact_pressure, "max_contact_pressure": b.max_contact_pressure,
            "pressure_difference": np.full(len(b), b.pressure_difference), "percolates": cj.percolates,
            "leak_rate": cj.leak_rate, "leak_rate_uniform_mean_pressure": cj.uniform_mean_pressure,
            "critical_gap_at_max_pressure": b.critical_gap_at_max_pressure,
            "resistance_band_width": cj.resistance_band_width, "resistance_peak_position": cj.resistance_peak_position,
            "lowest_wavevector": b.q0, "integral_relative_change": cj.change,
        }
        if b.band.oring is not None:
            values["regime"] = b.band.oring.regime
        if em is not None:
            values |= {"percolates_effective_medium": em.percolates, "leak_rate_effective_medium": em.leak_rate,
                       "leak_rate_effective_medium_uniform_mean_pressure": em.uniform_mean_pressure,
                       "resistance_band_width_effective_medium": em.resistance_band_width,
                       "integral_relative_change_effective_medium": em.change}
        values |= self._gas_fields()
        out = []
        for i in range(len(b)):
            rec: dict[str, Any] = {"variant": self.case.label} if self.case.label else {}
            for key in self.units:
                if key == "valid":
                    rec[key] = bool(self.valid[i])
                elif key == "validity":
                    rec[key] = self.validity[i]
                elif key == "valid_effective_medium" and self.valid_effective_medium is not None:
                    rec[key] = bool(self.valid_effective_medium[i])
                elif key == "validity_effective_medium" and self.validity_effective_medium is not None:
                    rec[key] = self.validity_effective_medium[i]
                else:
                    v = values[key][i]
                    rec[key] = bool(v) if isinstance(v, np.bool_) else v if isinstance(v, str) else float(v)
            out.append(rec)
        return out


def _plain(v: Any) -> Any:
    """A record value as a plain Python bool, str or float."""
    return bool(v) if isinstance(v, (bool, np.bool_)) else v if isinstance(v, str) else float(v)


def run_case(case: Case, *, rig: bool = False) -> CaseResult:
    """Run a case: both theories as ``case.model`` asks, all notes collected, every result judged.

    ``rig``: also simulate the case's ``[rig]`` (if it has one); it takes an ODE solve per model
    (~0.2 s), so only front ends that show the rig (the report) ask for it.
    """
    if case.band is not None:
        return _run_band_case(case, rig=rig)
    res = predict(case)
    em = predict_effective_medium(case) if case.model != "critical-junction" else None
    rig_result = rig_prediction(case) if rig and case.rig is not None else None
    messages = list(res.messages)
    if em is not None:
        messages += ["effective medium: " + m for m in em.messages]
    valid, validity, valid_em, validity_em = _uniform_verdicts(case, res, em)
    gas = _uniform_gas(case, res, em) if case.gas is not None or case.helium_equivalent else None
    return CaseResult(case, res, em, rig_result, tuple(messages), valid, validity, valid_em, validity_em,
                      case.input_warnings + tuple(case_warnings(case, res)), gas=gas)


#: Verdicts per row: (valid, reasons) of the critical junction, and of the effective medium (None, None if not run).
Verdicts = tuple[NDArray[np.bool_], tuple[str, ...], NDArray[np.bool_] | None, tuple[str, ...] | None]


def _uniform_verdicts(case: Case, res: CriticalJunctionResult, em: EffectiveMediumResult | None,
                      pressure_difference: bool = True) -> Verdicts:
    """The validity verdicts of a uniform seal per squeeze pressure (docs/theory.md §9.11): u_c against the fluid's
    molecular size and λc, u_e against the molecular size and the seal width Lx; with ``pressure_difference`` also
    ΔP against P0/2 (the fit notes that one on its own)."""
    d = case.fluid.molecular_length
    valid, validity = continuum_verdict(res.critical_gap, d, "u_c", res.critical_wavelength, "λc")
    valid_em = validity_em = None
    if em is not None:
        valid_em, validity_em = continuum_verdict(np.where(em.percolates, em.effective_gap, np.nan), d, "u_e",
                                                  case.seal.width, "Lx (seal width)")
    if not pressure_difference:
        return valid, validity, valid_em, validity_em
    # ΔP not small against P0: the fluid pressure would change the contact (docs/theory.md §3.6, §9.2)
    lifted = pressure_difference_not_small(res.squeeze_pressure, res.pressure_difference)
    valid, validity = _lifted(valid, validity, lifted, res.percolates, res)
    if em is not None and valid_em is not None and validity_em is not None:
        valid_em, validity_em = _lifted(valid_em, validity_em, lifted, em.percolates, res)
    return valid, validity, valid_em, validity_em


def _run_band_case(case: Case, *, rig: bool = False) -> CaseResult:
    """run_case for an O-ring or profile seal: the band's leak rates, judged where the pressure is highest."""
    band = run_band(case)
    res = predict(case)  # uniform, at each load's mean pressure over the widest band (kept for old front ends)
    messages = list(band.critical_junction.messages)
    if band.effective_medium is not None:
        messages += list(band.effective_medium.messages)
    valid, validity, valid_em, validity_em = _band_verdicts(case, band)
    # the rig runs at one load (rig_prediction refuses several): a sweep's report shows no rig
    rig_result = rig_prediction(case) if rig and case.rig is not None and band.band.loads.size == 1 else None
    warnings = assumption_warnings(
        slope_rms=case.spectrum.slope_rms, h_rms=case.spectrum.h_rms, seal_width=float(band.contact_width.min()),
        cutoff_wavevector=case.spectrum.q_max, squeeze_pressure=band.max_contact_pressure,
        youngs_modulus=case.youngs_modulus, contact_area_at_cutoff=res.contact_area_at_cutoff, alpha=case.alpha)
    gas = _band_gas(case, band) if case.gas is not None or case.helium_equivalent else None
    return CaseResult(case, res, None, rig_result, tuple(messages), valid, validity, valid_em, validity_em,
                      case.input_warnings + tuple(band.band.notes[1:]) + tuple(warnings), band, gas)


def _band_verdicts(case: Case, band: BandResult, pressure_difference: bool = True) -> Verdicts:
    """The validity verdicts of a band seal per load (docs/theory.md §9.11, §10.1): (valid, reasons) of the critical
    junction, and of the effective medium (None, None when it was not run).

    Each judges the band's narrowest constriction: u_c and λc at the peak contact pressure (critical junction),
    or u_e = (12 μ σ_min)^(1/3) against the contact width w (effective medium), against the fluid's molecular
    size; and, with ``pressure_difference``, ΔP against the peak contact pressure p_max/2 (the fit notes that one
    on its own). A load without a leak channel is valid.
    """
    d = case.fluid.molecular_length
    lifted = pressure_difference_not_small(band.max_contact_pressure, case.pressure_difference) & pressure_difference

    def judged(valid: NDArray[np.bool_], reasons: tuple[str, ...], percolates: NDArray[np.bool_]
               ) -> tuple[NDArray[np.bool_], tuple[str, ...]]:
        flag = lifted & percolates & valid
        reasons = tuple(f"ΔP = {case.pressure_difference:.4g} Pa is not small against the peak contact pressure "
                        f"{band.max_contact_pressure[i]:.4g} Pa: the fluid pressure would open the seal, which the theory "
                        "(p >> ΔP) does not model" if flag[i] else r for i, r in enumerate(reasons))
        return valid & ~flag, reasons

    cj = band.critical_junction
    valid, validity = judged(*continuum_verdict(band.critical_gap_at_max_pressure, d, "u_c at the peak pressure",
                                                band.critical_wavelength_at_max_pressure, "λc"), cj.percolates)
    em = band.effective_medium
    if em is None:
        return valid, validity, None, None
    valid_em, validity_em = judged(*continuum_verdict(_band_effective_gap(case, em), d, "u_e at the peak pressure",
                                                      band.contact_width, "w (contact width)"), em.percolates)
    return valid, validity, valid_em, validity_em


def _lifted(valid: NDArray[np.bool_], reasons: tuple[str, ...], lifted: NDArray[np.bool_], percolates: NDArray[np.bool_],
            res: CriticalJunctionResult) -> tuple[NDArray[np.bool_], tuple[str, ...]]:
    """Add the verdict "ΔP not small against P0" to rows that have a leak channel and no other reason."""
    flag = lifted & percolates & valid
    out = tuple(f"ΔP = {res.pressure_difference[i]:.4g} Pa is not small against P0 = {res.squeeze_pressure[i]:.4g} Pa: "
                "the fluid pressure would lift the seal, which the theory (P0 >> ΔP) does not model" if flag[i] else r
                for i, r in enumerate(reasons))
    return valid & ~flag, out


def case_warnings(case: Case, result: CriticalJunctionResult) -> list[str]:
    """Warnings about the case's inputs (docs/theory.md §9.11): slopes, sizes, cut-off, strain, full contact."""
    spectrum = case.spectrum
    return assumption_warnings(
        slope_rms=spectrum.slope_rms, h_rms=spectrum.h_rms, seal_width=case.seal.width, cutoff_wavevector=spectrum.q_max,
        squeeze_pressure=result.squeeze_pressure, youngs_modulus=case.youngs_modulus,
        contact_area_at_cutoff=result.contact_area_at_cutoff, alpha=case.alpha,
    )


# ---------------------------------------------------------------------- fit and linearity
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


def _uniform_fit(case: Case, p0: FloatArray, dp: FloatArray, q: FloatArray) -> tuple[dict[str, ScaleFit], Verdicts]:
    """:func:`fit_models` of a uniform seal, with each row's validity verdicts (without the ΔP one)."""
    cj = predict(replace(case, alpha=1.0), squeeze_pressure=p0, pressure_difference=dp)
    em = predict_effective_medium(case, squeeze_pressure=p0, pressure_difference=dp)
    return ({"critical_junction": fit_scale(q, cj.leak_rate, "critical_junction"),
             "effective_medium": fit_scale(q, em.leak_rate, "effective_medium")},
            _uniform_verdicts(case, cj, em, pressure_difference=False))


def _band_fit(case: Case, loads: ArrayLike, dp: FloatArray, q: FloatArray
              ) -> tuple[dict[str, ScaleFit], BandResult, NDArray[np.int_]]:
    """:func:`fit_models` of a band seal: Q_i = α K(load_i) ΔP_i with K at α = 1 (docs/theory.md §10.5).

    Both theories are linear in ΔP (and the critical junction in α), so the band is run once per
    distinct load at the case's ΔP and scaled to each row's. Returns the fits, the band result at the
    distinct loads and each row's index into them.
    """
    distinct, inverse = np.unique(np.asarray(loads, dtype=float), return_inverse=True)
    ks, res = _band_conductance(replace(case, alpha=1.0), distinct, ("critical-junction", "effective-medium"))
    fits = {}
    for model, name in (("critical-junction", "critical_junction"), ("effective-medium", "effective_medium")):
        k = ks[model][0]
        prediction = np.where(k > 0, k, np.nan)[inverse] * dp  # NaN: no leak channel at that load
        fits[name] = fit_scale(q, prediction, name)
    return fits, res, inverse


@dataclass(frozen=True)
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
    messages: tuple[str, ...]
    load_name: str = "squeeze_pressure"
    curve_grids: dict[str, FloatArray] = field(default_factory=dict)
    leak_rate_unit: str = "m^3/s"
    outside_validity: dict[str, tuple[int, ...]] = field(default_factory=dict)


def _outside_validity(data: LeakData, fits: dict[str, ScaleFit], verdicts: Verdicts, rows: NDArray[np.int_] | None,
                      where: Callable[[int], str]) -> tuple[list[str], dict[str, tuple[int, ...]]]:
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
    notes, out = [], {}
    for name, (valid, why) in judged.items():
        bad = tuple(int(i) for i in np.flatnonzero(~np.asarray(valid)[at] & fits[name].used))
        out[name] = bad
        if not bad:
            continue
        lines = ", ".join(f"{data.line_of(i)} ({where(i)})" for i in bad)
        notes.append(f"{name.replace('_', ' ')}: line{'s' if len(bad) > 1 else ''} {lines} outside the theory's validity "
                     f"(predict's valid = NO: {why[int(at[bad[0]])]}); kept in the fit, though the theory's value there "
                     f"is the formula's, not a prediction (remove the line{'s' if len(bad) > 1 else ''} from the data file "
                     f"to fit without {'them' if len(bad) > 1 else 'it'})")
    return notes, out


def _fit_messages(data: LeakData, fits: dict[str, ScaleFit], where: Callable[[int], str]) -> list[str]:
    """Refuse a fit of no point at all; else the notes on excluded rows (each with ``where(row)``) and a lone point."""
    if not any(f.fitted for f in fits.values()):
        reasons = "; ".join(f"line {data.line_of(i)}: {r}" for i, r in fits["effective_medium"].excluded[:3])
        raise SealeakError(f"{data.path}: no data point can be fitted by either model ({reasons})")
    messages = [f"{name.replace('_', ' ')}: line {data.line_of(i)} ({where(i)}) excluded: {reason}"
                for name, f in fits.items() for i, reason in f.excluded]
    if not any(f.n_used > 1 for f in fits.values()):
        messages.append("with one usable point α has no standard error")
    return messages


def run_fit(case: Case, data: LeakData) -> FitResult:
    """Fit α of both models to measured leak rates (docs/theory.md §8); raises if no row can be used.

    The data file's load column must be the case's (squeeze_pressure for a uniform seal,
    compression for an O-ring, profile_scale for a pressure profile); a mismatch is a
    :class:`~sealeak.errors.FileFormatError` naming the column and the seal.
    """
    _check_load_column(case, data)
    if case.gas is not None:
        return _run_gas_fit(case, data)
    if data.leak_rate_kind in _GAS_ONLY_KINDS:
        raise FileFormatError(data.path, f"column '{data.columns.get('leak_rate', 'leak_rate')}': a {data.leak_rate_kind.replace('_', ' ')} "
                                         "is a gas's leak rate, and the case's fluid is a liquid: give a volume flow (e.g. "
                                         "'ml/min'), or name the gas in the case ([fluid] name, absolute pressures)")
    if case.band is not None:
        return _run_band_fit(case, data)
    dp_used = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    fits, verdicts = _uniform_fit(case, data.squeeze_pressure, dp_used, data.leak_rate)

    def where(i: int) -> str:
        return f"P0 = {data.squeeze_pressure[i]:.6g} Pa"

    messages = _fit_messages(data, fits, where)
    notes, outside = _outside_validity(data, fits, verdicts, None, where)
    messages += notes
    large = pressure_difference_not_small(data.squeeze_pressure, dp_used)
    if large.any():
        i = int(np.argmax(large))
        messages.append(f"line {data.line_of(i)}: ΔP = {dp_used[i]:.6g} Pa is not small against P0 = "
                        f"{data.squeeze_pressure[i]:.6g} Pa ({int(large.sum())} row(s) like it): both theories "
                        "assume P0 >> ΔP")
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
    return FitResult(case, data, fits, ref_dp, same, measured, grid, curves, tuple(messages), outside_validity=outside)


#: Leak-rate kinds only a gas case can convert (:mod:`sealeak.io.units`).
_GAS_ONLY_KINDS = ("standard_volume_flow", "molar_flow", "mass_flow")


def _measured_throughput(case: Case, data: LeakData) -> FloatArray:
    """The data's leak rates as pV throughputs (Pa·m³/s) of the case's gas at its temperature (docs/theory.md §11.6).

    Throughput as is; molar flow ṅ R T; mass flow ṁ R T/M; standard volume flow ṅ = P0 V̇/(R T0)
    first; a plain volume flow p V̇ with p the data's reference pressure (``--at-pressure``).
    """
    gas = case.gas
    assert gas is not None and data.leak_rate_si is not None
    rt = MOLAR_GAS_CONSTANT * gas.temperature
    q = data.leak_rate_si
    kind = data.leak_rate_kind
    if kind == "throughput":
        return q
    if kind == "molar_flow":
        return q * rt
    if kind == "mass_flow":
        return q / gas.gas.molar_mass * rt
    if kind == "standard_volume_flow":
        return q * molar_flow_factor("leak_rate", "m^3/s", temperature=273.15, molar_mass=1.0, pressure=101325.0) * rt
    return q * data.reference_pressure


def gas_throughput(case: Case, k: FloatArray, gap: FloatArray, dp: FloatArray) -> FloatArray:
    """Q_pV = K ∫ p f dp (Pa·m³/s) per row: P_b the case's, P_a = P_b + ΔP of the row (docs/theory.md §11.5, §11.9).

    ``k`` the no-slip conductance K (m³/(Pa·s)), ``gap`` the narrowest gap h (m) and ``dp`` ΔP (Pa) per
    row; NaN where K = 0 or there is no gap, 0 where ΔP = 0.
    """
    gas = case.gas
    assert gas is not None
    pb = gas.downstream_pressure
    out = np.full(k.size, np.nan)
    for i in range(k.size):
        if k[i] > 0 and np.isfinite(gap[i]) and gap[i] > 0 and dp[i] == 0:
            out[i] = 0.0
        elif k[i] > 0 and np.isfinite(gap[i]) and gap[i] > 0 and dp[i] > 0:
            with case_keys():
                out[i] = k[i] * pressure_integral(float(gap[i]), gas.gas, pb + float(dp[i]), pb, gas.rarefaction)
    return out


def _run_gas_fit(case: Case, data: LeakData) -> FitResult:
    """:func:`run_fit` of a gas case: measured and predicted pV throughputs (Pa·m³/s), α scaling K (docs/theory.md §11.9).

    Each theory's prediction at a row is K(α = 1) ∫ p f(Kn(p)) dp from P_b to P_b + ΔP_row with the
    gap of :func:`gas_rows` (u_c, u_e, or u_c at the band's peak pressure), which does not depend on
    α: the throughput is proportional to α, and :func:`~sealeak.lab.fitting.fit_scale` applies.
    """
    gas = case.gas
    assert gas is not None
    q = _measured_throughput(case, data)
    dp = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    unit = ("load", "") if case.band is not None else ("P0", " Pa")

    def models(at: Case, loads: FloatArray) -> tuple[dict[str, tuple[FloatArray, FloatArray]], Verdicts]:
        """(K at α = 1, gap) of both theories at ``loads`` (the gaps of :func:`gas_rows`), and their verdicts there."""
        if at.band is not None:
            ks, res = _band_conductance(replace(at, alpha=1.0), loads, ("critical-junction", "effective-medium"))
            assert res.effective_medium is not None
            return ({"critical_junction": (ks["critical-junction"][0], res.critical_gap_at_max_pressure),
                     "effective_medium": (ks["effective-medium"][0], _band_effective_gap(at, res.effective_medium))},
                    _band_verdicts(at, res, pressure_difference=False))
        cj = predict(replace(at, alpha=1.0), squeeze_pressure=loads, pressure_difference=1.0)
        em = predict_effective_medium(at, squeeze_pressure=loads, pressure_difference=1.0)
        return ({"critical_junction": (np.where(cj.percolates, cj.leak_rate, 0.0), cj.critical_gap),
                 "effective_medium": (np.where(em.percolates, em.leak_rate, 0.0),
                                      np.where(em.percolates, em.effective_gap, np.nan))},
                _uniform_verdicts(at, cj, em, pressure_difference=False))

    loads = data.band_load if case.band is not None and data.band_load is not None else data.squeeze_pressure
    distinct, inverse = np.unique(loads, return_inverse=True)
    at_distinct, verdicts = models(case, distinct)
    fits = {name: fit_scale(q, gas_throughput(case, k[inverse], gap[inverse], dp), name)
            for name, (k, gap) in at_distinct.items()}
    if not any(f.fitted for f in fits.values()):
        reasons = "; ".join(f"line {data.line_of(i)}: {r}" for i, r in fits["effective_medium"].excluded[:3])
        raise SealeakError(f"{data.path}: no data point can be fitted by either model ({reasons})")

    def where(i: int) -> str:
        return _load_text(case.band.load_name, loads[i]) if case.band is not None else f"P0 = {loads[i]:.6g} Pa"

    messages = [f"{name.replace('_', ' ')}: line {data.line_of(i)} ({unit[0]} = {loads[i]:.6g}{unit[1]}) excluded: {reason}"
                for name, f in fits.items() for i, reason in f.excluded]
    notes, outside = _outside_validity(data, fits, verdicts, inverse, where)
    messages += notes
    messages.append(f"leak rates compared as pV throughputs of {gas.gas.name} at {gas.temperature - 273.15:.4g} °C "
                    f"(Pa·m³/s), P_b = {gas.downstream_pressure:.6g} Pa and P_a = P_b + ΔP of each row")
    if not any(f.n_used > 1 for f in fits.values()):
        messages.append("with one usable point α has no standard error")
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
    curves = {name: gas_throughput(case, k, gap, np.full(grid.size, ref_dp)) for name, (k, gap) in at_grid.items()}
    load_name = case.band.load_name if case.band is not None else "squeeze_pressure"
    return FitResult(case, data, fits, ref_dp, same, measured, grid, curves, tuple(messages), load_name,
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
                                                 f"{_load_text(band.load_name, v)}: {exc.allowed}") from None
        raise


def _run_band_fit(case: Case, data: LeakData) -> FitResult:
    """:func:`run_fit` of an O-ring or pressure-profile seal: the band's leak rate at each row's load (docs/theory.md §10.5)."""
    band = case.band
    assert band is not None and data.band_load is not None
    loads = data.band_load
    dp_used = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    _check_file_loads(case, data, loads)
    distinct = np.unique(loads)
    fits, res, inverse = _band_fit(case, loads, dp_used, data.leak_rate)

    def where(i: int) -> str:
        return _load_text(band.load_name, loads[i])

    messages = _fit_messages(data, fits, where)
    notes, outside = _outside_validity(data, fits, _band_verdicts(case, res, pressure_difference=False), inverse, where)
    messages += notes
    if res.band.oring is not None:
        messages += list(res.band.oring.warnings)
    # ΔP against the peak contact pressure of each row's load (the band's verdict, docs/theory.md §10.1)
    p_max = res.max_contact_pressure[inverse]
    large = pressure_difference_not_small(p_max, dp_used)
    if large.any():
        i = int(np.argmax(large))
        messages.append(f"line {data.line_of(i)}: ΔP = {dp_used[i]:.6g} Pa is not small against the peak contact pressure "
                        f"{p_max[i]:.6g} Pa at {_load_text(band.load_name, loads[i])} ({int(large.sum())} row(s) like it): "
                        "both theories assume p >> ΔP")
    same = bool(np.allclose(dp_used, dp_used[0]))
    ref_dp = float(dp_used[0]) if same else case.pressure_difference
    measured = data.leak_rate * (1.0 if same else ref_dp / np.where(dp_used > 0, dp_used, np.nan))
    grid = np.linspace(loads.min(), loads.max(), BAND_CURVE_POINTS) if loads.max() > loads.min() else loads[:1].copy()
    ks_grid, _ = _band_conductance(replace(case, alpha=1.0), grid, ("critical-junction",))
    k_em = _band_k(res, res.effective_medium) if res.effective_medium is not None else np.zeros(distinct.size)
    curves = {"critical_junction": np.where(ks_grid["critical-junction"][0] > 0, ks_grid["critical-junction"][0], np.nan) * ref_dp,
              "effective_medium": np.where(k_em > 0, k_em, np.nan) * ref_dp}
    return FitResult(case, data, fits, ref_dp, same, measured, grid, curves, tuple(messages), band.load_name,
                     {"effective_medium": distinct}, outside_validity=outside)


@dataclass(frozen=True)
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
    squeeze_pressure: float | None
    squeeze_pressure_source: str
    model_slopes: dict[str, float]
    alpha_from_slope: float | None
    messages: tuple[str, ...]
    load_name: str = "squeeze_pressure"
    load: float | None = None

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
    messages: list[str] = []
    alpha_from_slope = None
    if p0 is not None:
        for model in ("critical-junction", "effective-medium"):
            k, notes = _conductance(case, [p0], model)
            if k[0] > 0:
                slopes[_model_name(case, model)] = float(k[0])
                if model == "critical-junction":
                    alpha_from_slope = line.slope / (float(k[0]) / case.alpha)
            else:
                messages.extend(notes)
    else:
        messages.append("no squeeze pressure known (give --squeeze-pressure): no comparison with the models")
    return LinearityCheck(line, p0, source, slopes, alpha_from_slope, tuple(messages))


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


def _band_linearity(case: Case, line: LinearFit, load: float | None, source: str) -> LinearityCheck:
    """:func:`linearity` of a band seal: the models' slopes at one compression or profile scale."""
    band = case.band
    assert band is not None
    if load is None and band.loads.size == 1:
        load, source = float(band.loads[0]), "the case file"
    slopes: dict[str, float] = {}
    messages: list[str] = []
    alpha_from_slope = None
    p_mean = None
    if load is not None:
        ks, res = _band_conductance(case, [load], ("critical-junction", "effective-medium"))
        p_mean = float(res.mean_contact_pressure[0])
        for model in ("critical-junction", "effective-medium"):
            k, notes = ks[model]
            if k[0] > 0:
                slopes[_model_name(case, model)] = float(k[0])
                if model == "critical-junction":
                    alpha_from_slope = line.slope / (float(k[0]) / case.alpha)
            else:
                messages.extend(notes)
    else:
        word = "compression" if band.load_name == "compression" else "profile scale"
        messages.append(f"the case has {band.loads.size} values of conditions.{band.load_name} and the data file no "
                        f"{band.load_name} column: give one {word} (in the case, or as a column with one value) to "
                        "compare with the models")
    return LinearityCheck(line, p_mean, source, slopes, alpha_from_slope, tuple(messages), band.load_name, load)


# ---------------------------------------------------------------------- the virtual rig
@dataclass(frozen=True)
class RigPrediction:
    """The rig simulated for a case (docs/theory.md §4).

    Attributes
    ----------
    squeeze_pressure
        P0 from the load (Pa).
    conductance
        K = Q/ΔP of each model the case asks for (m³/(s·Pa); 0: no leak), by display name.
    columns
        The water column H(t) of each model.
    time_constant
        τ = A_cyl/(K ρ g) of each model (s; inf without leak).
    drain_time
        Closed-form time to fall to the final height, each model (s).
    messages
        Notes (no leak, ΔP not small against P0).
    band
        For an O-ring or pressure-profile seal, the band at the case's one load (contact width,
        mean and peak pressure; docs/theory.md §10); ``squeeze_pressure`` is then its mean
        contact pressure.
    """

    squeeze_pressure: float
    conductance: dict[str, float]
    columns: dict[str, WaterColumn]
    time_constant: dict[str, float] = field(default_factory=dict)
    drain_time: dict[str, float] = field(default_factory=dict)
    messages: tuple[str, ...] = ()
    band: BandResult | None = None


def _linear_leak(k: float) -> Callable[[ArrayLike], FloatArray]:
    """Q(ΔP) = K ΔP (m³/s) of a seal of conductance ``k`` (m³/(Pa·s))."""
    def leak(dp: ArrayLike) -> FloatArray:
        return k * np.asarray(dp, dtype=float)
    return leak


def rig_prediction(case: Case) -> RigPrediction | DecayPrediction:
    """Simulate the case's [rig]: P0 = load/(seal area), ΔP = ρgH, H(t) for each model of ``case.model`` (docs/theory.md §4.2).

    A ``[rig] kind = "pressure-decay"`` goes to :func:`~sealeak.cases.leak_tests.decay_prediction`
    (P(t) of the test volume, docs/theory.md §11.7).

    Both theories are linear in ΔP at fixed P0, so Q(ΔP) = K ΔP with K from :func:`conductance`;
    the ODE is still solved in general (:func:`~sealeak.lab.rig.water_column`) and the closed-form
    exponential gives the same curve.

    An O-ring or pressure-profile seal runs at the case's one load (its compression or profile
    scale sets the contact; the [rig] has no load): K = faces · Ly / ∫dx/σ of the band
    (docs/theory.md §10.5). Several loads raise an InputError naming conditions.compression or
    conditions.profile_scale.
    """
    rig = case.rig
    if rig is None:
        raise InputError("rig", None, "the case file has no [rig] section (cylinder_diameter, initial_height, load, ...)")
    if isinstance(rig, DecayRigSetup):
        return decay_prediction(case)
    models: list[Model] = [m for m in ("critical-junction", "effective-medium") if case.model in (m, "both")]
    k_of: dict[str, float] = {}
    messages: list[str] = []
    band = None
    if case.band is not None:
        if case.band.loads.size != 1:
            raise InputError(f"conditions.{case.band.load_name}", None, _one_load_needed(case))
        by_model, band = _band_conductance(case, None, tuple(models))
        for model in models:
            k_of[_model_name(case, model)] = float(by_model[model][0][0])
            messages.extend(by_model[model][1])
        p0 = float(band.mean_contact_pressure[0])
    else:
        p0 = rig.squeeze_pressure(case.seal)
        strained = strain_warning(p0, case.youngs_modulus, "the pressure of the rig's load")
        messages += [strained + "; check [rig] load"] if strained else []
        for model in models:
            ks, notes = _conductance(case, [p0], model)
            k_of[_model_name(case, model)] = float(ks[0])
            messages.extend(notes)
    columns, tau, t_final = {}, {}, {}
    area = rig.cylinder_area
    for name, k in k_of.items():
        if k == 0:
            messages.append(f"{name}: no leak at P0 = {p0:.6g} Pa, the level stays at {rig.initial_height:g} m")
        columns[name] = water_column(rig, _linear_leak(k))
        tau[name] = area / (k * rig.density * rig.gravity) if k > 0 else float("inf")
        t_final[name] = drain_time(rig, k, columns[name].final_height)
    dp0 = float(rig.pressure_difference(rig.initial_height))
    if band is not None:
        p_max = float(band.max_contact_pressure[0])
        if pressure_difference_not_small(p_max, dp0):
            messages.append(f"ΔP = ρgH0 = {dp0:.4g} Pa is not small against the peak contact pressure {p_max:.4g} Pa: "
                            "the theory assumes p >> ΔP")
    elif pressure_difference_not_small(p0, dp0):
        messages.append(f"ΔP = ρgH0 = {dp0:.4g} Pa is not small against P0 = {p0:.4g} Pa: the theory assumes P0 >> ΔP")
    return RigPrediction(p0, k_of, columns, tau, t_final, tuple(messages), band)


def _one_load_needed(case: Case) -> str:
    """Why a band case with several loads has no rig, and what to do."""
    band = case.band
    assert band is not None
    shown = [f"{100 * v:.4g} %" if band.load_name == "compression" else f"{v:.4g}" for v in band.loads[:4]]
    values = ", ".join(shown) + (", ..." if band.loads.size > 4 else "")
    what = "compression (or groove_depth)" if band.kind == "o-ring" else "profile_scale"
    return (f"the rig runs at one {what}, which sets the contact; this case has {band.loads.size} ({values}): "
            "give one value for the rig (predict sweeps several)")


def rig_readings(case: Case, time: ArrayLike, height: ArrayLike, source: str = "readings") -> ReadingsAnalysis:
    """The leak rate read from measured (t, H) readings of the case's rig (docs/theory.md §4)."""
    if case.rig is None:
        raise InputError("rig", None, "the case file has no [rig] section")
    if isinstance(case.rig, DecayRigSetup):
        raise InputError("rig.kind", case.rig.kind, "(t, P) readings of a pressure-decay test go to "
                                                    "sealeak.cases.leak_tests.decay_readings")
    return leak_rate_from_readings(case.rig, time, height, source=source)
