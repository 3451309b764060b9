"""Uncertain inputs carried through the prediction: quasi-Monte Carlo samples, percentiles, the probability of passing.

A case file's spreads (:mod:`sealeak.cases.spreads`) span a unit hypercube of one dimension per uncertain
input. :func:`propagate` draws ``samples`` points of it (scrambled Sobol' or Latin hypercube,
:mod:`scipy.stats.qmc`, reproducible for a seed), builds each point's case(s) from the case document with
the sampled values written in, runs every one (:func:`~sealeak.cases.run.run_case`) and returns per result
row the 5th, 50th and 95th percentiles of the leak rate (and of the gas's leak-test units), the fraction of
samples that seal, and with ``conditions.max_leak_rate`` the probability that the leak rate exceeds it and
per case the load at which the seal passes with 95 % probability (docs/theory.md §14).

A sample whose row has no leak channel counts as Q = 0 (it seals). Samples that write the same values
(a spread of zero, a choice between theories) are run once. Samples of a uniform liquid seal that vary only
h_rms, E, ν, ΔP, α and η are computed together from the nominal contact at scaled pressures
(:mod:`sealeak.cases.scaling`, docs/theory.md §14.5).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.stats import qmc

from ..errors import InputError, show_value
from ..io.leak_units import LEAK_RATE_KINDS, leak_rate_unit, pv_throughput
from ..io.quantities import quantity, record_fields, units_of
from ..io.units import SI_RANGE, outside_si_range, quantity_parts
from .band import ScaledJunctions, scaled_junctions
from .cancel import check as check_cancelled
from .gas import HELIUM_TEST, helium_test_gas
from .limits import MAX_EVALUATIONS, whole_number
from .loader import CaseFile, build_cases, parse_case_file, read_case_file
from .model import Case
from .run import CaseResult, run_case
from .scaling import band_junction_tables, scaled_leak_rate, scaled_validity
from .spreads import UncertainInput

__all__ = ["record_values", "UncertainInput", "UncertainStudy", "ResultRow", "UncertaintyResult", "UncertaintyColumns", "PassingLoad",
           "SAMPLERS", "SAMPLER_NAMES", "DEFAULT_SAMPLES", "MAX_SAMPLES", "PASS_PROBABILITY", "SPREAD_KEYS", "UNCERTAINTY_UNITS",
           "read_uncertain_case", "parse_uncertain_case", "uncertain_study", "check_sampling", "unit_points", "sample_values",
           "leak_rates", "propagate"]

#: The samplers of the unit hypercube: scrambled Sobol' points, or a Latin hypercube.
#: The samplers of ``--sampler`` and how outputs name them.
SAMPLER_NAMES = {"sobol": "scrambled Sobol' points", "lhs": "Latin hypercube"}
SAMPLERS = tuple(SAMPLER_NAMES)
#: Samples of ``predict`` when the case file has uncertain inputs and ``--samples`` is not given.
DEFAULT_SAMPLES = 256
#: The most samples one propagation may ask for (each a full prediction).
MAX_SAMPLES = 8192
#: The probability of passing at which :class:`PassingLoad` places a case's passing load.
PASS_PROBABILITY = 0.95
#: The leak-rate fields of a record whose spread is computed (those the case's records hold).
SPREAD_KEYS = ("leak_rate", "leak_rate_pv", "leak_rate_mbar_l_s", "leak_rate_helium_pv", "leak_rate_helium_mbar_l_s",
               "leak_rate_total_pv", "leak_rate_total_mbar_l_s")


@dataclass(frozen=True)
class ResultRow:
    """One result row of an uncertain study: its case (index and variant label) and its load."""

    case: int
    variant: str
    load_name: str  # "squeeze_pressure", or a band seal's "compression" / "profile_scale"
    load: float  # SI (Pa, or 1)


@dataclass(frozen=True)
class UncertainStudy:
    """A case file with uncertain inputs: the nominal cases, the inputs, and the rows every sample fills."""

    case_file: CaseFile
    inputs: tuple[UncertainInput, ...]
    rows: tuple[ResultRow, ...]

    @property
    def cases(self) -> list[Case]:
        """The nominal (deterministic) cases."""
        return self.case_file.cases

    @property
    def max_leak_rate(self) -> Any:
        """``conditions.max_leak_rate`` as written, or None."""
        return self.case_file.spreads.max_leak_rate


def _rows(cases: list[Case]) -> tuple[ResultRow, ...]:
    out: list[ResultRow] = []
    for i, case in enumerate(cases):
        name, loads = ((case.band.load_name, case.band.loads) if case.band is not None
                       else ("squeeze_pressure", case.squeeze_pressure))
        out += [ResultRow(i, case.label, name, float(v)) for v in loads]
    return tuple(out)


def uncertain_study(case_file: CaseFile) -> UncertainStudy:
    """The :class:`UncertainStudy` of a case file as read (inputs and specification checked)."""
    study = UncertainStudy(case_file, case_file.spreads.inputs, _rows(case_file.cases))
    if study.max_leak_rate is not None:
        _limits(study, case_file.cases)  # checked now: one line before any sample runs
    for inp in study.inputs:  # each value of a choice builds (a sample may not draw it), and so do both ends of every
        # other spread (the normal and lognormal ones truncated at ±TRUNCATION sd): whether a case file is accepted does
        # not depend on how many samples are drawn, nor on a sample taking a path that builds no case (α, η: scaled)
        choice = inp.distribution == "choice"
        ends = inp.choices if choice else () if inp.is_zero else inp.written(np.array([_END, 1.0 - _END]))
        for value in ends:
            _sample_cases(replace(study, inputs=(inp,)), [value], "a value of its choice" if choice else "the end of its spread")
    return study


#: Where a spread's ends are checked, as points of the unit interval: a hair inside, where the samples can fall (a
#: uniform's low = 0 is an end no sample reaches, on an open bound such as h_rms > 0).
_END = 1e-9


def read_uncertain_case(path: str | Path) -> UncertainStudy:
    """Read a case file with uncertain inputs (:func:`~sealeak.cases.loader.read_case_file`)."""
    return uncertain_study(read_case_file(path))


def parse_uncertain_case(text: str, case_dir: Path | str = ".", source: str = "<text>") -> UncertainStudy:
    """A case file's text with uncertain inputs (:func:`~sealeak.cases.loader.parse_case_file`)."""
    return uncertain_study(parse_case_file(text, case_dir, source))


def check_sampling(samples: int, seed: int, sampler: str) -> None:
    """Refuse a number of samples, a seed or a sampler :func:`unit_points` cannot use (one line naming the option)."""
    if sampler not in SAMPLERS:
        raise InputError("--sampler", sampler, f"allowed: {', '.join(SAMPLERS)}")
    whole_number("--samples", samples, 2, MAX_SAMPLES, " (each sample is a full prediction)")
    whole_number("--seed", seed, 0, 2**63 - 1)
    if sampler == "sobol" and samples & (samples - 1):
        raise InputError("--samples", samples, "Sobol' points come in powers of two: give e.g. "
                                               f"{1 << (samples - 1).bit_length()} (or --sampler lhs for any number)")


def unit_points(dimensions: int, samples: int, seed: int, sampler: str = "sobol") -> NDArray[np.float64]:
    """``samples`` points of the unit hypercube of ``dimensions`` (an array [samples, dimensions]), reproducible for a
    ``seed``: scrambled Sobol' points (``samples`` a power of two) or a Latin hypercube."""
    check_sampling(samples, seed, sampler)
    if dimensions == 0:
        return np.zeros((samples, 0))
    rng = np.random.default_rng(seed)
    if sampler == "lhs":
        return qmc.LatinHypercube(dimensions, rng=rng).random(samples)
    return qmc.Sobol(dimensions, scramble=True, rng=rng).random(samples)


def _shown(result: CaseResult, key: str) -> str:
    """The record key of ``key`` in the theory ``result`` shows (the effective medium's with its suffix)."""
    return key if result.shows_critical_junction else key + "_effective_medium"


def record_values(results: list[CaseResult]) -> dict[str, NDArray[np.float64]]:
    """The :data:`SPREAD_KEYS` the records hold, one value per row (NaN → 0: no leak channel, it seals)."""
    records = [(r, rec) for r in results for rec in r.records()]
    out: dict[str, NDArray[np.float64]] = {}
    for key in SPREAD_KEYS:
        if all(_shown(r, key) in rec for r, rec in records):
            v = np.array([rec[_shown(r, key)] for r, rec in records], dtype=float)
            out[key] = np.where(np.isnan(v), 0.0, v)
    return out


def record_validity(results: list[CaseResult]) -> NDArray[np.bool_]:
    """Per row, whether the theory it shows is within its validity (docs/theory.md §9.11: ``valid``, or
    ``valid_effective_medium``); a row without a leak channel counts as valid."""
    return np.array([bool(rec.get(_shown(r, "valid"), True)) for r in results for rec in r.records()], dtype=bool)


def sample_values(study: UncertainStudy, points: NDArray[np.float64],
                  nominal: list[CaseResult] | None = None) -> dict[str, NDArray[np.float64]]:
    """The leak rates of every :data:`SPREAD_KEYS` the records hold at each point of the unit hypercube
    ([samples, inputs]), as arrays [samples, rows] in the records' SI units; a row without a leak channel holds 0.

    Points that write the same values (a spread of zero) are run once. When only α and the viscosity of a liquid are
    uncertain, the samples share the nominal contact: Q ∝ α/η (critical junction), ∝ 1/η (effective medium), with
    ``nominal`` the nominal cases' results (run here when not given); when h_rms, E, ν and ΔP vary too (a uniform
    liquid seal on the critical junction), the nominal contact at the scaled pressures P0/(k s) (:func:`_by_scaling`).
    """
    return _sample(study, points, nominal, validity=False)[0]


def _sample(study: UncertainStudy, points: NDArray[np.float64], nominal: list[CaseResult] | None = None,
            validity: bool = True, progress: Callable[[int], object] | None = None,
            ) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.bool_] | None]:
    """(:func:`sample_values`, and per sample and row whether the theory shown is within its validity: the verdict of
    the sample's own prediction, or of the nominal contact scaled as its leak rate is). With ``validity`` False (the
    Sobol' indices, which need the leak rates alone) the scaled samples' verdicts, a critical junction per sample and
    row, are not computed (None). ``progress`` is called with 1 after each sample that takes a prediction of its own
    (not on the fast paths, which take all samples at once)."""
    points = np.atleast_2d(np.asarray(points, dtype=float))
    if points.shape[1] != len(study.inputs):
        raise ValueError(f"points have {points.shape[1]} coordinates; the study has {len(study.inputs)} inputs")
    if _shares_contact(study):  # α and η change neither the gaps nor the pressures: the nominal verdicts
        nominal = nominal if nominal is not None else [run_case(c) for c in study.cases]
        return _scaled(study, points, nominal), np.tile(record_validity(nominal), (points.shape[0], 1))
    if _scales(study):
        nominal = nominal if nominal is not None else [run_case(c) for c in study.cases]
        fast = _by_scaling(study, points, nominal, validity)
        if fast is not None:
            return fast
    factors = _factors(study, points) if _scales_band(study) else None
    tables = _band_tables(study, points, factors["length"]) if factors is not None else None
    written = [inp.written(points[:, j]) for j, inp in enumerate(study.inputs)]
    done: dict[str, dict[str, NDArray[np.float64]]] = {}
    done_valid: dict[str, NDArray[np.bool_]] = {}
    out: dict[str, list[NDArray[np.float64]]] = {}
    valid: list[NDArray[np.bool_]] = []
    for i in range(points.shape[0]):
        values = [w[i] for w in written]
        tag = repr(values)
        if tag not in done:
            check_cancelled()  # (a client that has gone stops the samples between predictions)
            cases = [_shown_theory(c) for c in _sample_cases(study, values)]
            if tables is None or factors is None or factors["nominal"][i]:
                results = [run_case(c) for c in cases]
            else:  # the nominal contact's σ at the scaled pressures (docs/theory.md §14.5)
                results = []
                for case, table in zip(cases, tables, strict=True):
                    with scaled_junctions(ScaledJunctions(table, float(factors["length"][i]),
                                                          float(factors["modulus"][i]))):
                        results.append(run_case(case))
            done[tag], done_valid[tag] = record_values(results), record_validity(results)
        if progress is not None:
            progress(1)
        for key, v in done[tag].items():
            out.setdefault(key, []).append(v)
        valid.append(done_valid[tag])
    return {k: np.array(v) for k, v in out.items() if len(v) == points.shape[0]}, np.array(valid, dtype=bool)


#: The inputs that scale a liquid's leak rate without changing the contact (docs/theory.md §14).
_SCALING = ("theory.alpha", "fluid.viscosity")


def _shares_contact(study: UncertainStudy) -> bool:
    """Whether every uncertain input is α or the viscosity, and every case a liquid without gas rows or capillarity."""
    return bool(study.inputs) and all(i.key in _SCALING and i.distribution != "choice" for i in study.inputs) and all(
        c.gas is None and not c.helium_equivalent and c.capillarity is None for c in study.cases)


def _scaled(study: UncertainStudy, points: NDArray[np.float64], nominal: list[CaseResult]) -> dict[str, NDArray[np.float64]]:
    """:func:`sample_values` of α and viscosity samples: the nominal Q times α/α₀ (critical junction) and η₀/η."""
    ratio = {key: np.ones(points.shape[0]) for key in _SCALING}
    for j, inp in enumerate(study.inputs):
        v = inp.values(points[:, j])
        if not np.all(v > 0):
            raise InputError(f"{inp.key} (uncertainty sample)", float(v[~(v > 0)][0]), "must be > 0; narrow the spread")
        ratio[inp.key] = v / quantity_parts(inp.key, inp.nominal)[0]
    base = record_values(nominal)["leak_rate"]
    alpha = np.concatenate([np.tile(ratio["theory.alpha"][:, None] if r.shows_critical_junction else np.ones((points.shape[0], 1)),
                                    len(r.records())) for r in nominal], axis=1)
    return {"leak_rate": base * alpha / ratio["fluid.viscosity"][:, None]}


#: The inputs the scaling of the contact carries (docs/theory.md eq. 14.6): h_rms, the modulus, ΔP, α and η.
_SCALED = ("surface.h_rms", "rubber.youngs_modulus", "rubber.poisson_ratio", "conditions.pressure_difference", *_SCALING)


def _scales(study: UncertainStudy) -> bool:
    """Whether every uncertain input is one :data:`_SCALED` names (no choice) and every case a uniform liquid seal
    without gas rows or capillarity whose rows show the critical junction, its rubber on a rigid counterface."""
    keys = {i.key for i in study.inputs}
    return bool(keys) and keys <= set(_SCALED) and all(i.distribution != "choice" for i in study.inputs) and all(
        c.band is None and c.gas is None and not c.helium_equivalent and c.capillarity is None
        and c.model != "effective-medium" for c in study.cases) and (
        "substrate" not in (study.case_file.document or {}) or not keys & {"rubber.youngs_modulus", "rubber.poisson_ratio"})


def _factors(study: UncertainStudy, points: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """Per sample, s = h_rms/h_rms,nom, k = E*/E*_nom, f = (α/η)/(α/η)_nom and d = ΔP/ΔP_nom (docs/theory.md
    eq. 14.6), and ``nominal``: whether the sample is the nominal case (every input at its nominal value)."""
    ones = np.ones(points.shape[0])
    value = {key: ones for key in _SCALED}
    nominal = {key: 1.0 for key in _SCALED}
    same = np.ones(points.shape[0], dtype=bool)
    for j, inp in enumerate(study.inputs):
        value[inp.key], nominal[inp.key] = inp.values(points[:, j]), quantity_parts(inp.key, inp.nominal)[0]
        same &= value[inp.key] == nominal[inp.key]
    # (a sample far outside its input's range overflows here: its case is refused, naming the sample, when it is built)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        ratio = {key: value[key] / nominal[key] for key in _SCALED}
        nu, nu0 = value["rubber.poisson_ratio"], nominal["rubber.poisson_ratio"]
        modulus = ratio["rubber.youngs_modulus"] * ((1.0 - nu0**2) / (1.0 - nu**2) if "rubber.poisson_ratio" in
                                                     {i.key for i in study.inputs} else 1.0)
    return {"length": ratio["surface.h_rms"], "modulus": modulus,
            "flow": ratio["theory.alpha"] / ratio["fluid.viscosity"],
            "pressure_difference": ratio["conditions.pressure_difference"], "nominal": same}


def _extreme_samples(study: UncertainStudy, points: NDArray[np.float64],
                     ) -> list[tuple[list[Case], dict[str, NDArray[np.float64]]]] | None:
    """The cases built at the lowest and at the highest sampled values (every input at once), each with its
    :func:`_factors`; None where a builder refuses one (the full path then names the sample)."""
    out = []
    for pick in (np.argmin, np.argmax):
        rows = [int(pick(inp.values(points[:, j]))) for j, inp in enumerate(study.inputs)]
        point = np.array([[points[i, j] for j, i in enumerate(rows)]])
        values = [inp.written(point[:, j])[0] for j, inp in enumerate(study.inputs)]
        try:
            out.append((_sample_cases(study, values), _factors(study, point)))
        except InputError:
            return None
    return out


def _scaling_holds(study: UncertainStudy, points: NDArray[np.float64]) -> bool:
    """Whether the cases built at the lowest and the highest sampled values (every input at once) are the nominal
    cases scaled by their :func:`_factors` (the spectrum's shape, q0, γ, p_c, the pressures and the seal unchanged); False also
    where such a case is refused (the full path then names the sample)."""
    extremes = _extreme_samples(study, points)
    if extremes is None:
        return False
    for built, f in extremes:
        s, k, flow, d = (float(f[key][0]) for key in ("length", "modulus", "flow", "pressure_difference"))
        for b, c in zip(built, study.cases, strict=True):
            if not (b.band is None and b.gas is None and b.capillarity is None and b.coupled == c.coupled
                    and b.model == c.model and b.q0 == c.q0 and b.gamma == c.gamma
                    and b.percolation_threshold == c.percolation_threshold
                    and b.seal.aspect_ratio == c.seal.aspect_ratio
                    and np.array_equal(b.squeeze_pressure, c.squeeze_pressure)
                    and np.array_equal(b.spectrum.q, c.spectrum.q)
                    and np.allclose(b.spectrum.C, s * s * c.spectrum.C, rtol=1e-12, atol=0.0)
                    and math.isclose(b.e_star, k * c.e_star, rel_tol=1e-12)
                    and math.isclose(b.alpha / b.fluid.viscosity, flow * c.alpha / c.fluid.viscosity, rel_tol=1e-12)
                    and np.allclose(b.pressure_difference, d * np.asarray(c.pressure_difference), rtol=1e-12, atol=0.0)):
                return False
    return True


def _by_scaling(study: UncertainStudy, points: NDArray[np.float64], nominal: list[CaseResult], validity: bool = True,
                ) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.bool_] | None] | None:
    """:func:`sample_values` by the scaling of the nominal contact (:mod:`sealeak.cases.scaling`), with the samples'
    verdicts where ``validity``; None where the cases do not scale (then every sample is a full prediction); the nominal
    samples hold the nominal rows bit for bit."""
    if not _scaling_holds(study, points):
        return None
    factors = _factors(study, points)
    columns: list[NDArray[np.float64]] = []
    verdicts: list[NDArray[np.bool_]] = []
    try:
        for case, result in zip(study.cases, nominal, strict=True):
            q = scaled_leak_rate(case, result.critical_junction, factors["length"], factors["modulus"], factors["flow"],
                                 factors["pressure_difference"])
            columns.append(np.where(np.isnan(q), 0.0, q))
            if validity:
                verdicts.append(scaled_validity(case, result.critical_junction, factors["length"], factors["modulus"],
                                                factors["pressure_difference"]))
    except InputError:
        return None
    out = np.concatenate(columns, axis=1)
    valid = np.concatenate(verdicts, axis=1) if validity else None
    base = record_values(nominal)["leak_rate"]
    if base.shape != out.shape[1:]:  # records that are not one per squeeze pressure: not what the scaling computes
        return None
    out[factors["nominal"]] = base
    if valid is not None:
        valid[factors["nominal"]] = record_validity(nominal)
    return {"leak_rate": out}, valid


def _scales_band(study: UncertainStudy) -> bool:
    """Whether every uncertain input is one :data:`_SCALED` names (no choice) and every case a band liquid seal whose
    rows show the critical junction (its samples compute it alone, :func:`_shown_theory`), without gas rows or
    capillarity, its rubber on a rigid counterface."""
    keys = {i.key for i in study.inputs}
    return bool(keys) and keys <= set(_SCALED) and all(i.distribution != "choice" for i in study.inputs) and all(
        c.band is not None and c.gas is None and not c.helium_equivalent and c.capillarity is None
        and c.model != "effective-medium" for c in study.cases) and (
        "substrate" not in (study.case_file.document or {}) or not keys & {"rubber.youngs_modulus", "rubber.poisson_ratio"})


def _band_tables(study: UncertainStudy, points: NDArray[np.float64], length: NDArray[np.float64],
                 ) -> list[dict[float, Callable[[NDArray[np.float64]], NDArray[np.float64]]]] | None:
    """Per case, the nominal σ̃(τ) tables of its loads by q0 (:func:`sealeak.cases.scaling.band_junction_tables`) over
    the scaled pressures the samples (their h_rms ratios ``length``) reach, or None where the samples' band cases are not the nominal ones scaled:
    the cases built at the lowest and the highest sampled values keep the loads, each load's q0 and profile widths,
    and have the nominal profile pressures × k, the spectrum × s², E* × k (:func:`_factors`)."""
    extremes = _extreme_samples(study, points)
    if extremes is None:
        return None
    for built, f in extremes:
        si, ki = float(f["length"][0]), float(f["modulus"][0])
        for b, c in zip(built, study.cases, strict=True):
            if b.band is None or c.band is None or not (
                    b.model == c.model and b.coupled == c.coupled and b.gamma == c.gamma
                    and b.percolation_threshold == c.percolation_threshold
                    and np.array_equal(b.band.loads, c.band.loads) and np.array_equal(b.band.q0, c.band.q0)
                    and np.array_equal(b.spectrum.q, c.spectrum.q)
                    and np.allclose(b.spectrum.C, si * si * c.spectrum.C, rtol=1e-12, atol=0.0)
                    and math.isclose(b.e_star, ki * c.e_star, rel_tol=1e-12)
                    and all(np.array_equal(pb.x, pc.x) and pb.shape == pc.shape
                            and np.allclose(pb.pressure, ki * pc.pressure, rtol=1e-12, atol=0.0)
                            and math.isclose(pb.width, pc.width, rel_tol=1e-12)
                            and math.isclose(pb.peak, ki * pc.peak, rel_tol=1e-12)
                            for pb, pc in zip(b.band.profiles, c.band.profiles, strict=True))):
                return None
    return [band_junction_tables(c, float(length.min()), float(length.max())) for c in study.cases]


def _shown_theory(case: Case) -> Case:
    """A sample's case computing the theory its rows show alone: with ``theory.model = "both"`` the critical junction
    (the samples' leak rates are that theory's, docs/cli.md), whose numbers do not depend on the effective medium
    computed beside it: the same bits at a fraction of the cost (a band's effective medium needs σ tables per sample)."""
    return replace(case, model="critical-junction") if case.model == "both" else case


def _sample_cases(study: UncertainStudy, values: list[Any], what: str = "uncertainty sample") -> list[Case]:
    """The cases of one sample: the nominal document with ``values`` written in (one per input); ``what`` names the
    values in a refusal."""
    cf = study.case_file
    doc = copy.deepcopy(cf.document or {})
    for inp, value in zip(study.inputs, values):
        section, key = inp.key.split(".", 1)
        doc.setdefault(section, {})[key] = value
    try:
        return build_cases(doc, cf.case_dir, cf.source)[0]
    except InputError as exc:
        sample = ", ".join(f"{inp.key} = {show_value(v)}" for inp, v in zip(study.inputs, values))
        raise InputError(f"{exc.field} ({what} {sample})", exc.value,
                         exc.allowed + "; narrow the spread or use a distribution that stays in range "
                                       "(docs/case-files.md, Uncertain inputs)") from None


def leak_rates(study: UncertainStudy, points: NDArray[np.float64],
               nominal: list[CaseResult] | None = None) -> NDArray[np.float64]:
    """The leak rate of the theory each row shows at each point of the unit hypercube, an array [samples, rows]: the
    gas's pV throughput Q_pV (Pa·m³/s) where every row is a gas's (what its band shows), else Q (m³/s); a row without a
    leak channel (it seals) holds 0. ``nominal`` as for :func:`sample_values`."""
    values = sample_values(study, points, nominal)
    return values.get("leak_rate_pv", values["leak_rate"])


def _limits(study: UncertainStudy, cases: list[Case]) -> tuple[list[str], NDArray[np.float64]]:
    """Per row, the record key and the threshold that ``conditions.max_leak_rate`` compares: a volume flow with Q
    (m³/s); a gas leak-test unit with the gas's pV throughput (Pa·m³/s; with permeation through the rubber, the
    interface leak plus permeation, what the test measures), or a liquid's helium equivalent."""
    field, value = "conditions.max_leak_rate", study.max_leak_rate
    if isinstance(value, bool) or not isinstance(value, str):
        raise InputError(field, value, "must be a leak rate with its unit, e.g. '1e-6 mbar*l/s' or '0.1 ml/min'")
    number, unit = _leak_parts(field, value)
    try:
        kind, factor = leak_rate_unit(field, unit)
    except InputError as exc:  # named with the whole value as written, not its unit alone
        raise InputError(field, value, exc.allowed + "; for a liquid a volume flow ('ml/min', 'm^3/s')") from None
    if not number > 0:
        raise InputError(field, value, "must be > 0")
    if outside_si_range(np.array([number * factor])).any():  # (1e300 ml/min overflowed in the figures)
        raise InputError(field, value, f"must lie within {SI_RANGE[0]:g} .. {SI_RANGE[1]:g} in SI units, as every "
                                       "quantity of a case file")
    keys: list[str] = []
    limits: list[float] = []
    for row in study.rows:
        case = cases[row.case]
        if kind == "volume_flow" and case.gas is not None:  # (its Q column is the incompressible K ΔP, for comparison)
            raise InputError(field, value, "is a plain volume flow, which for a gas depends on the pressure it is counted "
                                           "at: give the gas's limit as a pV throughput ('1e-6 mbar*l/s'), a standard "
                                           "flow ('2 sccm'), a mass flow ('5 g/a') or a molar flow")
        if kind == "volume_flow":
            keys.append("leak_rate")
            limits.append(number * factor)
            continue
        if case.gas is not None:  # with permeation what a leak test measures: the interface leak plus permeation
            key = "leak_rate_total_pv" if case.permeation is not None else "leak_rate_pv"
            gas, pressure = case.gas.gas, case.gas.upstream_pressure
        elif case.helium_equivalent:
            key, gas, pressure = "leak_rate_helium_pv", helium_test_gas(), HELIUM_TEST["upstream_pressure"]
        else:
            raise InputError(field, value, f"is a {kind.replace('_', ' ')} ({LEAK_RATE_KINDS[kind][0]}): it needs a gas, or "
                                           "conditions.helium_equivalent = true for a liquid; for a liquid's own "
                                           "leak give a volume flow such as '0.1 ml/min'")
        keys.append(key)
        limits.append(float(pv_throughput(number * factor, kind, temperature=gas.temperature,
                                          molar_mass=gas.molar_mass, pressure=pressure)))
    return keys, np.array(limits)


def _leak_parts(field: str, value: str) -> tuple[float, str]:
    """(number, unit text) of a leak rate as written; standard-flow names (sccm) pint does not know pass as text."""
    head, _, unit = value.strip().partition(" ")
    try:
        return quantity_parts(field, value)
    except InputError:
        try:
            number, _ = quantity_parts(field, head)
        except InputError as exc:  # named as written, not by its number alone
            raise InputError(field, value, exc.allowed) from None
        return number, unit.strip()


@dataclass(frozen=True, kw_only=True)
class UncertaintyColumns:
    """The uncertainty fields of the result rows (one value per row; a field the case has no leak rate for is None)."""

    leak_rate_p05: NDArray[np.float64] = quantity("m^3/s", "5th percentile of the leak rate over the samples (0: sealed)")
    leak_rate_p50: NDArray[np.float64] = quantity("m^3/s", "median of the leak rate over the samples")
    leak_rate_p95: NDArray[np.float64] = quantity("m^3/s", "95th percentile of the leak rate over the samples")
    leak_rate_pv_p05: NDArray[np.float64] | None = quantity("Pa*m^3/s", "5th percentile of the gas's pV throughput", default=None)
    leak_rate_pv_p50: NDArray[np.float64] | None = quantity("Pa*m^3/s", "median of the gas's pV throughput", default=None)
    leak_rate_pv_p95: NDArray[np.float64] | None = quantity("Pa*m^3/s", "95th percentile of the gas's pV throughput", default=None)
    leak_rate_mbar_l_s_p05: NDArray[np.float64] | None = quantity("mbar*l/s", "5th percentile of the gas leak in mbar·l/s",
                                                                  default=None)
    leak_rate_mbar_l_s_p50: NDArray[np.float64] | None = quantity("mbar*l/s", "median of the gas leak in mbar·l/s", default=None)
    leak_rate_mbar_l_s_p95: NDArray[np.float64] | None = quantity("mbar*l/s", "95th percentile of the gas leak in mbar·l/s",
                                                                  default=None)
    leak_rate_helium_pv_p05: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "5th percentile of the helium leak in the standard test", default=None)
    leak_rate_helium_pv_p50: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "median of the helium leak in the standard test", default=None)
    leak_rate_helium_pv_p95: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "95th percentile of the helium leak in the standard test", default=None)
    leak_rate_helium_mbar_l_s_p05: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "5th percentile of the helium leak in mbar·l/s", default=None)
    leak_rate_helium_mbar_l_s_p50: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "median of the helium leak in mbar·l/s", default=None)
    leak_rate_helium_mbar_l_s_p95: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "95th percentile of the helium leak in mbar·l/s", default=None)
    leak_rate_total_pv_p05: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "5th percentile of the gas's interface leak plus permeation (what a leak test measures)", default=None)
    leak_rate_total_pv_p50: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "median of the gas's interface leak plus permeation", default=None)
    leak_rate_total_pv_p95: NDArray[np.float64] | None = quantity(
        "Pa*m^3/s", "95th percentile of the gas's interface leak plus permeation", default=None)
    leak_rate_total_mbar_l_s_p05: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "5th percentile of the interface leak plus permeation in mbar·l/s", default=None)
    leak_rate_total_mbar_l_s_p50: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "median of the interface leak plus permeation in mbar·l/s", default=None)
    leak_rate_total_mbar_l_s_p95: NDArray[np.float64] | None = quantity(
        "mbar*l/s", "95th percentile of the interface leak plus permeation in mbar·l/s", default=None)
    sealed_fraction: NDArray[np.float64] = quantity("1", "fraction of the samples without a leak channel (the seal seals)")
    outside_fraction: NDArray[np.float64] | None = quantity(
        "1", "fraction of the samples that leak outside the theory's validity (a gap narrower than the fluid's molecules, "
             "a seal the fluid pressure opens, ...; docs/theory.md §9.11)", default=None)
    exceed_probability: NDArray[np.float64] | None = quantity(
        "1", "fraction of the samples whose leak rate exceeds conditions.max_leak_rate", default=None)


#: SI unit of every uncertainty field of a record (those a result holds are a subset).
UNCERTAINTY_UNITS: dict[str, str] = units_of(UncertaintyColumns)


@dataclass(frozen=True, kw_only=True)
class PassingLoad:
    """Where one case passes ``conditions.max_leak_rate`` with :data:`PASS_PROBABILITY`."""

    variant: str
    load_name: str
    passing_load: float = quantity("<load>", "the squeeze pressure (Pa) or compression (1) at which the probability of "
                                             "passing first reaches 95 %: between the two rows it separates, where the "
                                             "95th percentile of the leak rate reaches the limit (log-linear; null: see the note)")
    between: tuple[float, float] = quantity("<load>", "the loads of the two rows passing_load lies between: it is placed no "
                                                      "better than they are close (null where no two rows separate "
                                                      "failing from passing)",
                                            default=(math.nan, math.nan))
    between_passing_probability: tuple[float, float] = quantity("1", "the probability of passing at those two rows (null "
                                                                     "with between)", default=(math.nan, math.nan))
    note: str = ""
    #: The fraction of the samples at those two rows that leak outside the theory's validity.
    between_outside: tuple[float, float] = (0.0, 0.0)
    #: Whether it passes already at the lowest load computed (no load placed: ``note`` says why).
    passes_at_lowest: bool = False


@dataclass(frozen=True)
class UncertaintyResult:
    """The propagation of a study's uncertain inputs (:func:`propagate`).

    Attributes
    ----------
    study
        The study.
    points
        The points of the unit hypercube, [samples, inputs].
    values
        The leak rates per :data:`SPREAD_KEYS` key the records hold, [samples, rows] (SI; 0 where sealed).
    nominal
        The deterministic results of the nominal cases (what ``predict`` shows without spreads).
    sampler, seed
        How the points were drawn.
    limit_keys, limits
        Per row, the record key and the threshold ``conditions.max_leak_rate`` compares it with (SI), or None.
    """

    study: UncertainStudy
    points: NDArray[np.float64]
    values: dict[str, NDArray[np.float64]]
    nominal: list[CaseResult]
    sampler: str
    seed: int
    limit_keys: list[str] | None = None
    limits: NDArray[np.float64] | None = None
    notes: tuple[str, ...] = field(default=())
    #: Per sample and row whether the theory shown is within its validity (a sealed sample is), or None (not known).
    valid: NDArray[np.bool_] | None = None

    @property
    def samples(self) -> int:
        """The number of samples."""
        return int(self.points.shape[0])

    @property
    def sealed(self) -> NDArray[np.bool_]:
        """Whether each sample's row seals (no leak channel: Q = 0), [samples, rows]."""
        return ~(self.values["leak_rate"] > 0)

    @property
    def exceed_probability(self) -> NDArray[np.float64] | None:
        """Per row, the fraction of samples whose leak rate exceeds ``conditions.max_leak_rate`` (None without it)."""
        if self.limit_keys is None or self.limits is None:
            return None
        q = np.column_stack([self.values[k][:, j] for j, k in enumerate(self.limit_keys)])
        return np.mean(q > self.limits, axis=0)

    def percentiles(self, key: str = "leak_rate") -> NDArray[np.float64]:
        """The 5th, 50th and 95th percentiles of ``key`` per row, [3, rows] (linear interpolation between samples)."""
        return np.percentile(self.values[key], [5.0, 50.0, 95.0], axis=0)

    def outside(self, key: str = "leak_rate") -> NDArray[np.bool_]:
        """Per percentile of :meth:`percentiles` and row, [3, rows], whether it is taken from a sample outside the
        theory's validity (either of the two samples it interpolates between); all False where that is not known."""
        v = self.values[key]
        if self.valid is None:
            return np.zeros((3, v.shape[1]), dtype=bool)
        order = np.argsort(v, axis=0, kind="stable")
        bad = ~np.take_along_axis(self.valid, order, axis=0)
        at = (v.shape[0] - 1) * np.array([0.05, 0.50, 0.95])
        return bad[np.floor(at).astype(int)] | bad[np.ceil(at).astype(int)]

    @property
    def outside_fraction(self) -> NDArray[np.float64] | None:
        """Per row, the fraction of the samples that leak outside the theory's validity (None where not known)."""
        if self.valid is None:
            return None
        return np.mean(~self.valid & (self.values["leak_rate"] > 0), axis=0)

    def columns(self) -> UncertaintyColumns:
        """The record fields of every row."""
        fields: dict[str, Any] = {}
        for key in self.values:
            p = self.percentiles(key)
            fields |= {f"{key}_p05": p[0], f"{key}_p50": p[1], f"{key}_p95": p[2]}
        return UncertaintyColumns(**fields, sealed_fraction=np.mean(self.sealed, axis=0),
                                  outside_fraction=self.outside_fraction, exceed_probability=self.exceed_probability)

    def row_fields(self) -> list[dict[str, Any]]:
        """One dict per row of the fields :meth:`columns` holds (None fields left out), plain floats. Without uncertain
        inputs (``max_leak_rate`` alone: one sample, the nominal prediction) only ``exceed_probability`` (0 or 1): three
        equal "percentiles" and a sealed fraction of 0 or 1 would read as a sampled band."""
        cols = {k: v for k, v in record_fields(self.columns()).items() if v is not None}
        if not self.study.inputs:
            cols = {k: v for k, v in cols.items() if k == "exceed_probability"}
        return [{k: float(v[i]) for k, v in cols.items()} for i in range(len(self.study.rows))]

    @property
    def units(self) -> dict[str, str]:
        """SI unit of each field of :meth:`row_fields`."""
        return {k: UNCERTAINTY_UNITS[k] for k in (self.row_fields() or [{}])[0]}

    def passing_loads(self) -> list[PassingLoad]:
        """Per case, the load at which the probability of passing first reaches :data:`PASS_PROBABILITY` (None
        without ``conditions.max_leak_rate``)."""
        exceed = self.exceed_probability
        if exceed is None or self.limit_keys is None or self.limits is None:
            return []
        compared = np.column_stack([self.values[k][:, j] for j, k in enumerate(self.limit_keys)])
        q95 = np.percentile(compared, 100.0 * PASS_PROBABILITY, axis=0)
        out: list[PassingLoad] = []
        rows = self.study.rows
        outside = self.outside_fraction
        for i, case in enumerate(self.study.cases):
            idx = np.array([j for j, r in enumerate(rows) if r.case == i])
            idx = idx[np.argsort([rows[j].load for j in idx], kind="stable")]
            out.append(_passing(case.label, rows[idx[0]].load_name, np.array([rows[j].load for j in idx]),
                                1.0 - exceed[idx], q95[idx], self.limits[idx], None if outside is None else outside[idx]))
        return out


def _passing(variant: str, load_name: str, loads: NDArray[np.float64], p_pass: NDArray[np.float64],
             q95: NDArray[np.float64], limits: NDArray[np.float64], outside: NDArray[np.float64] | None = None,
             ) -> PassingLoad:
    """The load (ascending ``loads``) where ``p_pass`` first reaches :data:`PASS_PROBABILITY` (docs/theory.md eq. 14.4):
    between the last row below it and the first at it, where the 95th percentile of the leak rate compared (``q95``)
    reaches its limit (``limits``), log Q95 linear in the load (not placed where the percentiles bracket the limit and
    the passing row's Q95 is 0: it seals there); linear in ``p_pass`` where the percentiles do not bracket the limit.
    ``outside``: per load the fraction of samples leaking outside the theory's validity, if known."""
    ok = np.flatnonzero(p_pass >= PASS_PROBABILITY)
    name = load_name.replace("_", " ")
    if ok.size == 0:
        return PassingLoad(variant=variant, load_name=load_name, passing_load=math.nan,
                           note=f"the probability of passing stays below {100 * PASS_PROBABILITY:.0f} % up to the highest "
                                f"{name} computed")
    i = int(ok[0])
    if i == 0:
        shown = f"; {100 * outside[0]:.0f} % of its samples leak outside the theory's validity (the table's 'outside')" \
            if outside is not None and outside[0] > 0 else ""
        return PassingLoad(variant=variant, load_name=load_name, passing_load=math.nan, passes_at_lowest=True,
                           note=f"passes with at least {100 * PASS_PROBABILITY:.0f} % already at the lowest "
                                f"{name} computed: compute lower loads to place it{shown}")
    x0, x1, a, b, limit = float(loads[i - 1]), float(loads[i]), float(q95[i - 1]), float(q95[i]), float(limits[i])
    if a > limit >= b and limits[i - 1] == limit and b == 0:
        passing, note = math.nan, (f"passes with at least {100 * PASS_PROBABILITY:.0f} % somewhere between the two rows "
                                   f"of 'between': at the higher {name} at least {100 * PASS_PROBABILITY:.0f} % of the "
                                   "samples seal, which leaves no leak rate to interpolate towards; compute loads between "
                                   "them to place it")
    else:
        f = (math.log(limit / a) / math.log(b / a) if a > limit >= b and limits[i - 1] == limit
             else (PASS_PROBABILITY - p_pass[i - 1]) / (p_pass[i] - p_pass[i - 1]))
        passing, note = x0 + f * (x1 - x0), ""
    return PassingLoad(variant=variant, load_name=load_name, passing_load=passing, between=(x0, x1),
                       between_passing_probability=(float(p_pass[i - 1]), float(p_pass[i])), note=note,
                       between_outside=(0.0, 0.0) if outside is None else (float(outside[i - 1]), float(outside[i])))


def propagate(study: UncertainStudy, samples: int = DEFAULT_SAMPLES, seed: int = 0, sampler: str = "sobol",
              progress: Callable[[int], object] | None = None) -> UncertaintyResult:
    """Carry the study's uncertain inputs through the prediction with ``samples`` quasi-random points (``sampler``,
    ``seed``): the same arguments give the same numbers bit for bit. Without uncertain inputs (``conditions.max_leak_rate``
    alone) every sample would be the nominal prediction: one sample is taken, and each probability is 0 or 1.
    ``progress`` (as a progress bar's ``update``) is called with 1 after each sample that runs a prediction of its own."""
    check_sampling(samples, seed, sampler)
    if study.inputs and samples * len(study.rows) > MAX_EVALUATIONS:  # (each leak rate's array is samples × rows)
        raise InputError("--samples", samples, f"× {len(study.rows)} rows is {samples * len(study.rows)} leak rates per "
                                               f"array; at most {MAX_EVALUATIONS}: give fewer samples or rows")
    points = unit_points(len(study.inputs), samples, seed, sampler) if study.inputs else np.zeros((1, 0))
    nominal = [run_case(c) for c in study.cases]
    values, valid = _sample(study, points, nominal, progress=progress)
    keys, limits = _limits(study, study.cases) if study.max_leak_rate is not None else (None, None)
    return UncertaintyResult(study, points, values, nominal, sampler, seed, keys, limits, valid=valid)
