"""Running a case: the one place where a front end asks for numbers.

:func:`run_case` takes a :class:`~sealeak.cases.model.Case` and returns a :class:`CaseResult` that
holds everything the command line, the report, the figures and the JSON/CSV files show: both
theories' predictions, the spectrum statistics, the notes, and the SI unit of every field.
Front ends (``sealeak.render``, ``sealeak.cli``) format it; they compute nothing themselves.

The pieces it is made of live beside it: the theories in :mod:`sealeak.cases.prediction`, the verdicts
in :mod:`sealeak.cases.verdicts`, the gas rows in :mod:`sealeak.cases.gas` and the rig in
:mod:`sealeak.cases.rig`; the laboratory workflows are :mod:`sealeak.cases.fitting` and
:mod:`sealeak.cases.linearity_check`, the curves of the prediction figures
:mod:`sealeak.cases.curves`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..io.quantities import quantity, record_fields, units_of
from ..physics.critical_junction import CriticalJunctionResult
from ..physics.effective_medium import EffectiveMediumResult
from ..physics.validity import assumption_warnings
from .band import BandColumns, BandEffectiveMediumColumns, BandResult, run_band
from .capillarity import CAPILLARY_UNITS, SUFFIX, CapillaryRows, band_capillarity, uniform_capillarity
from .gas import GAS_UNITS, HELIUM_TEST, HELIUM_UNITS, PERMEATION_UNITS, GasRows, _band_gas, _uniform_gas
from .leak_tests import DecayPrediction
from .model import Case, LifePoint
from .notes import Note, NoteLike
from .prediction import predict, predict_effective_medium
from .rig import RigPrediction, rig_prediction
from .verdicts import _band_verdicts, _uniform_verdicts, case_warnings

__all__ = ["CaseResult", "run_case", "LIFE_UNITS", "RESULT_UNITS", "EFFECTIVE_MEDIUM_UNITS"]

_VERDICTS = ("valid", "validity")
_VERDICTS_EFFECTIVE_MEDIUM = ("valid_effective_medium", "validity_effective_medium")
_LIFT_OFF = ("lift_off_pressure_difference",)


@dataclass(frozen=True, kw_only=True)
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
    lift_off_pressure_difference
        With ``theory.fluid_pressure = "coupled"``: the ΔP (Pa) at which the fluid pressure reaches the peak
        contact pressure and opens the seal, per row: P0 of a uniform seal, p_max of a band (docs/theory.md §13.4);
        None when the fluid pressure is ignored.
    gas
        For a gas case, or a liquid with ``conditions.helium_equivalent``: the gas leak and the
        helium equivalent of each theory ("critical_junction", "effective_medium"), per row; the
        rows are the band's loads for a band seal (docs/theory.md §11.9).
    capillary
        For a liquid with a contact angle (``case.capillarity``): each theory's entry pressure and the
        rows the meniscus holds ("critical_junction", "effective_medium"; docs/theory.md §12); the leak
        rates of the held rows are 0.
    """

    case: Case
    critical_junction: CriticalJunctionResult
    effective_medium: EffectiveMediumResult | None = None
    rig: RigPrediction | DecayPrediction | None = None
    messages: tuple[NoteLike, ...] = ()
    valid: NDArray[np.bool_] = quantity("1", "the critical gap is above the fluid's molecular size (continuum flow)",
                                        default_factory=lambda: np.ones(0, dtype=bool))
    validity: tuple[str, ...] = quantity("", "why the result is not valid ('' where valid)", default=())
    valid_effective_medium: NDArray[np.bool_] | None = quantity(
        "1", "the effective gap is above the fluid's molecular size", default=None)
    validity_effective_medium: tuple[str, ...] | None = quantity(
        "", "why the effective-medium result is not valid ('' where valid)", default=None)
    lift_off_pressure_difference: NDArray[np.float64] | None = quantity(
        "Pa", "ΔP at which the fluid pressure reaches the peak contact pressure and opens the seal", default=None)
    warnings: tuple[str, ...] = ()
    band: BandResult | None = None
    gas: dict[str, GasRows] | None = None
    capillary: dict[str, CapillaryRows] | None = None

    @property
    def shows_critical_junction(self) -> bool:
        """Whether front ends show the critical-junction numbers (not for model = "effective-medium")."""
        if self.band is not None:
            return self.case.model != "effective-medium"
        return self.case.model != "effective-medium" or self.effective_medium is None

    @property
    def units(self) -> dict[str, str]:
        """SI unit of every field of :meth:`records`: a life case's time, temperature and modulus lead."""
        return {k: LIFE_UNITS[k] for k in _life_fields(self.case.life)} | self._result_units

    @property
    def _result_units(self) -> dict[str, str]:
        if self.band is not None:
            em = BAND_EFFECTIVE_MEDIUM_UNITS if self.band.effective_medium is not None else {}
            regime = {"regime": ""} if self.band.band.oring is not None else {}
            return ({self.band.band.load_name: "1"} | regime | BAND_UNITS | self._lift_off_units | em | self._gas_units
                    | self._capillary_units)
        return (RESULT_UNITS | self._lift_off_units | (EFFECTIVE_MEDIUM_UNITS if self.effective_medium is not None else {})
                | self._gas_units | self._capillary_units)

    @property
    def _lift_off_units(self) -> dict[str, str]:
        return _verdict_units(_LIFT_OFF) if self.lift_off_pressure_difference is not None else {}

    @property
    def _capillary_units(self) -> dict[str, str]:
        return {k + SUFFIX[name]: u for name in (self.capillary or {}) for k, u in CAPILLARY_UNITS.items()}

    def _capillary_fields(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for name, rows in (self.capillary or {}).items():
            out |= rows.fields(SUFFIX[name])
        return out

    @property
    def _gas_units(self) -> dict[str, str]:
        out: dict[str, str] = {}
        for name, rows in (self.gas or {}).items():
            suffix = "_effective_medium" if name == "effective_medium" else ""
            units = ((GAS_UNITS if rows.leaks is not None else {}) | (HELIUM_UNITS if rows.helium is not None else {})
                     | (PERMEATION_UNITS if rows.permeation is not None else {}))
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

    def _verdicts(self, names: tuple[str, ...]) -> dict[str, Any]:
        """The verdict columns ``names`` (:data:`RESULT_UNITS`' or :data:`EFFECTIVE_MEDIUM_UNITS`' last two)."""
        return {k: v for k, v in record_fields(self).items() if k in names and v is not None}

    def records(self) -> list[dict[str, Any]]:
        """One dict per squeeze pressure with the fields of :attr:`units` (SI values; NaN kept)."""
        if self.band is not None:
            return self._band_records(self.band)
        columns = record_fields(self.critical_junction) | self._verdicts(_VERDICTS + _LIFT_OFF)
        if self.effective_medium is not None and self.valid_effective_medium is not None:
            columns |= record_fields(self.effective_medium) | self._verdicts(_VERDICTS_EFFECTIVE_MEDIUM)
        columns |= self._gas_fields() | self._capillary_fields()
        return self._rows(columns, len(self.critical_junction))

    def _rows(self, columns: dict[str, Any], n: int) -> list[dict[str, Any]]:
        """One record per row from ``columns`` (record key: values per row), led by the variant's label."""
        label = {"variant": self.case.label} if self.case.label else {}
        life = _life_fields(self.case.life)
        return [label | life | {k: _plain(v[i]) for k, v in columns.items()} for i in range(n)]

    def _band_records(self, b: BandResult) -> list[dict[str, Any]]:
        columns: dict[str, Any] = {b.band.load_name: b.band.loads}
        if b.band.oring is not None:
            columns["regime"] = b.band.oring.regime
        columns |= record_fields(b.columns()) | self._verdicts(_VERDICTS + _LIFT_OFF)
        em = b.effective_medium_columns()
        if em is not None:
            columns |= record_fields(em) | self._verdicts(_VERDICTS_EFFECTIVE_MEDIUM)
        return self._rows(columns | self._gas_fields() | self._capillary_fields(), len(b))


def _life_fields(life: LifePoint | None) -> dict[str, Any]:
    """The record fields of a life case (none for another case): time, temperature, modulus, and the compression set
    where the case file gives one."""
    return {} if life is None else {k: v for k, v in record_fields(life).items() if v is not None}


def _verdict_units(names: tuple[str, ...]) -> dict[str, str]:
    """The units of :class:`CaseResult`'s verdict fields ``names``."""
    return {k: u for k, u in units_of(CaseResult).items() if k in names}


#: SI unit of the fields that lead each record of a case of the seal over its life (time, temperature, modulus).
LIFE_UNITS: dict[str, str] = units_of(LifePoint)
#: SI unit of every field of a critical-junction result record (JSON ``units``, CSV headers), from the fields' declarations.
RESULT_UNITS: dict[str, str] = units_of(CriticalJunctionResult) | _verdict_units(_VERDICTS)
#: SI unit of the effective-medium fields (added to a record when the case asks for that model).
EFFECTIVE_MEDIUM_UNITS: dict[str, str] = units_of(EffectiveMediumResult) | _verdict_units(_VERDICTS_EFFECTIVE_MEDIUM)


#: SI unit of every field of a band record (JSON ``units``, CSV headers); the load's key (and an O-ring's regime) lead.
BAND_UNITS: dict[str, str] = units_of(BandColumns) | _verdict_units(_VERDICTS)
#: SI unit of a band record's effective-medium fields (added when the case asks for that model).
BAND_EFFECTIVE_MEDIUM_UNITS: dict[str, str] = units_of(BandEffectiveMediumColumns) | _verdict_units(_VERDICTS_EFFECTIVE_MEDIUM)


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
    valid, validity, valid_em, validity_em = _uniform_verdicts(case, res, em)
    gas = _uniform_gas(case, res, em) if case.gas is not None or case.helium_equivalent else None
    capillary = None
    if case.capillarity is not None:  # after the gas rows: helium passes where the liquid is held
        res, em, capillary = uniform_capillarity(case, res, em)
    lifts = _helium_test_lifts(case, gas, "squeeze_pressure", res.squeeze_pressure, res.squeeze_pressure)
    if lifts and em is not None and case.model == "effective-medium":  # (the notes of the theory the tables show,
        em = _noted(em, lifts)                                            # which the text and report print under it)
    elif lifts:
        res = _noted(res, lifts)
    messages: list[NoteLike] = list(res.messages)
    if em is not None:
        messages += [_of_effective_medium(m) for m in em.messages]
    return CaseResult(case=case, critical_junction=res, effective_medium=em, rig=rig_result, messages=tuple(messages),
                      valid=valid, validity=validity, valid_effective_medium=valid_em,
                      validity_effective_medium=validity_em,
                      lift_off_pressure_difference=res.squeeze_pressure.copy() if case.coupled else None,
                      warnings=case.input_warnings + tuple(case_warnings(case, res)), gas=gas, capillary=capillary)


def _noted(result: Any, notes: list[NoteLike]) -> Any:
    """``result`` (a theory's result, whose physics-layer ``messages`` are typed as sentences) with ``notes`` added, as
    :func:`sealeak.cases.capillarity` adds its own."""
    return replace(result, messages=(*result.messages, *notes))


def _helium_test_lifts(case: Case, gas: dict[str, GasRows] | None, load_name: str, loads: NDArray[np.float64],
                       lift_off: NDArray[np.float64]) -> list[NoteLike]:
    """A note on the rows whose helium-equivalent leak rate comes from a helium test that opens the seal: the test's
    pressure difference (1 bar against vacuum) reaches the contact pressure that holds the seal shut, P0 or a band's
    peak (docs/theory.md §13.4), at rows where either theory has a helium leak."""
    if gas is None or not case.helium_equivalent:
        return []
    dp = HELIUM_TEST["upstream_pressure"] - HELIUM_TEST["downstream_pressure"]
    leaking = np.zeros(loads.size, dtype=bool)
    for rows in gas.values():
        if rows.helium is not None:
            leaking |= np.isfinite(rows.helium) & (rows.helium > 0)
    opens = leaking & (dp >= lift_off)
    if not opens.any():
        return []
    return [Note("helium_test_lifts", {"load_name": load_name, "loads": tuple(float(v) for v in loads[opens]),
                                       "pressure_difference": dp, "coupled": case.coupled,
                                       "band": load_name != "squeeze_pressure"})]


def _of_effective_medium(message: NoteLike) -> NoteLike:
    """The effective medium's own note as the case's notes carry it, beside the critical junction's: a sentence
    prefixed "effective medium: ", a note that names its theory (``theory``, "" under the theory's own heading) naming it."""
    if isinstance(message, Note):
        return replace(message, values={**message.values, "theory": "effective medium"}) if "theory" in message.values else message
    return "effective medium: " + message


def _run_band_case(case: Case, *, rig: bool = False) -> CaseResult:
    """run_case for an O-ring or profile seal: the band's leak rates, judged where the pressure is highest."""
    band = run_band(case)
    res = predict(case)  # uniform, at each load's mean pressure over the widest band (kept for old front ends)
    valid, validity, valid_em, validity_em = _band_verdicts(case, band)
    # the rig runs at one load (rig_prediction refuses several): a sweep's report shows no rig
    rig_result = rig_prediction(case) if rig and case.rig is not None and band.band.loads.size == 1 else None
    warnings = assumption_warnings(
        slope_rms=case.spectrum.slope_rms, h_rms=case.spectrum.h_rms, seal_width=float(band.contact_width.min()),
        cutoff_wavevector=case.spectrum.q_max, squeeze_pressure=band.max_contact_pressure,
        youngs_modulus=case.youngs_modulus, contact_area_at_cutoff=res.contact_area_at_cutoff, alpha=case.alpha)
    gas = _band_gas(case, band) if case.gas is not None or case.helium_equivalent else None
    capillary = None
    if case.capillarity is not None:  # after the gas rows: helium passes where the liquid is held
        band, capillary = band_capillarity(case, band)
    messages: list[NoteLike] = list(band.critical_junction.messages)
    if band.effective_medium is not None:
        messages += list(band.effective_medium.messages)
    messages += _helium_test_lifts(case, gas, band.band.load_name, band.band.loads, band.max_contact_pressure)
    return CaseResult(case=case, critical_junction=res, rig=rig_result, messages=tuple(messages), valid=valid,
                      validity=validity, valid_effective_medium=valid_em, validity_effective_medium=validity_em,
                      lift_off_pressure_difference=band.max_contact_pressure.copy() if case.coupled else None,
                      warnings=case.input_warnings + tuple(band.band.notes[1:]) + tuple(warnings), band=band, gas=gas,
                      capillary=capillary)
