"""Numerically exact leak rate of a case: random surfaces, BEM contact, Reynolds flow, α.

The reference paper could only fit α; this pipeline computes it (docs/theory.md §6):

1. R periodic random surfaces of side L = 2π/q0 (= Lx by default) on an N×N grid with the case's
   C(q) (:func:`sealeak.numerics.synthesize`, seeded: realisation r uses the seed sequence
   (seed, r), so results are reproducible and realisations independent);
2. frictionless elastic contact with each surface at every squeeze pressure
   (:func:`sealeak.numerics.solve_contact_sweep`, warm-started along increasing pressure);
3. steady Reynolds flow through each gap field (:func:`sealeak.numerics.solve_flow`, contact taken
   from pressure > 0), giving the leak rate of the square Q_sq; the seal's is (Ly/Lx) Q_sq;
4. the critical-junction prediction for the same (grid-resolved) spectrum with α = 1,
   Q_cj = (Ly/Lx) u_c³ ΔP/(12η), and α = Q_sq (Ly/Lx) / Q_cj for every percolating realisation;
5. optionally, per realisation, the relative contact area at which the non-contact area stops
   percolating (bisection on pressure, :func:`sealeak.numerics.percolation_threshold`);
6. for a gas case, also the isothermal gas flow through each gap field between the case's absolute
   pressures with its rarefaction model (:func:`sealeak.numerics.solve_gas_flow`: the p² problem,
   with slip a checked fixed point), the critical-junction gas leak of the same spectrum with α = 1
   and the same rarefaction model (:func:`sealeak.cases.gas.gas_rows`, as ``predict``), and
   α_gas = Q_pV,sim/Q_pV,cj (docs/theory.md §11.10). The liquid columns stay:
   for a gas they are the incompressible formula with the gas's viscosity.

Resolution: the grid resolves wavelengths of at least 4 cells, q <= 2π N/(4L). When the
spectrum's cut-off q1 lies above that, the spectrum is cut there, the result says so, and the
critical-junction theory it is compared with uses the same cut spectrum.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import numerics
from ..io.quantities import quantity
from ..physics.effective_medium import bruggeman_threshold
from ..physics.spectrum import PowerSpectrum
from .model import Case
from .notes import Note, NoteLike
from .pipeline import (
    JUNCTION_CELLS,
    POINTS_PER_WAVELENGTH,
    TASK_BASE_BYTES,
    FlowLog,
    FlowMethod,
    FlowRecord,
    Flows,
    GasSimulation,
    Records,
    RunSettings,
    SimulationCapillarity,
    TaskRecord,
    TaskSpec,
    capillary_part,
    cut_spectrum,
    gas_identity,
    gas_part,
    junction_resolved,
    keep_load,
    mean_std,
    pack_mask,
    resolved_spectrum_cut,
    run_ensemble,
    spectrum_text,
    task_memory_bytes,
    unpack_mask,
    with_fields,
)
from .prediction import predict

__all__ = ["SimulationResult", "SimulationCapillarity", "GasSimulation", "simulate", "resolved_spectrum_cut", "POINTS_PER_WAVELENGTH",
           "JUNCTION_CELLS", "EnsembleSpec", "EnsembleTask", "SweepRecord", "ThresholdRecord", "ensemble_tasks", "run_task", "task_memory_bytes",
           "TASK_BASE_BYTES", "PeriodicSquare", "gas_identity", "pack_mask", "unpack_mask", "FlowMethod"]

FloatArray = NDArray[np.float64]

@dataclass(frozen=True, kw_only=True)
class SimulationResult:
    """Per-pressure statistics over realisations (SI units). Arrays have one entry per pressure.

    ``*_std`` are standard deviations over realisations (ddof = 1; NaN with fewer than two values).
    ``leak_rate`` averages all realisations (a blocked one leaks 0); ``alpha`` averages the
    percolating ones only (NaN where none percolates). ``leak_rate_critical_junction`` is the
    critical-junction prediction with α = 1 for the same (possibly cut) spectrum.
    ``junction_cells`` is N/ζc, the grid cells across the theory's critical wavelength λc (NaN where
    there is no junction); below :data:`JUNCTION_CELLS` the α of that pressure is flagged.
    ``gas`` holds the gas leak and α_gas of a gas case (None for a liquid); the other fields are then
    the incompressible formula with the gas's viscosity. ``capillarity``: a liquid with a contact angle's entry
    pressures and held realisations (None without a contact angle).
    """

    squeeze_pressure: FloatArray = quantity("Pa", "nominal squeeze pressure P0")
    relative_contact_area: FloatArray = quantity("1", "relative contact area A/A0, mean over realisations")
    relative_contact_area_std: FloatArray = quantity("1", "standard deviation of A/A0")
    relative_contact_area_theory: FloatArray = quantity("1", "A/A0 of Persson's theory")
    mean_gap: FloatArray = quantity("m", "mean gap ū")
    mean_gap_std: FloatArray = quantity("m", "standard deviation of ū")
    percolating_fraction: FloatArray = quantity("1", "fraction of realisations in which fluid crosses the square")
    leak_rate: FloatArray = quantity("m^3/s", "simulated leak rate Q of the seal")
    leak_rate_std: FloatArray = quantity("m^3/s", "standard deviation of Q")
    leak_rate_critical_junction: FloatArray = quantity("m^3/s", "critical-junction leak rate with α = 1")
    alpha: FloatArray = quantity("1", "α = Q over the critical-junction Q, over the percolating realisations")
    alpha_std: FloatArray = quantity("1", "standard deviation of α")
    junction_cells: FloatArray = quantity("1", "grid cells across the theory's critical wavelength λc",
                                          default_factory=lambda: np.empty(0))
    junction_resolved: tuple[bool | None, ...] = quantity("1", "λc spans enough grid cells for α", init=False)
    percolation_threshold: float = quantity("1", "A/A0 at which the non-contact area stops percolating")
    percolation_threshold_std: float = quantity("1", "standard deviation of the percolation threshold")
    pressure_difference: float = quantity("Pa", "pressure difference across the seal")
    size: float = quantity("m", "side of the simulated square")
    grid: int
    realizations: int
    seed: int
    q_cut: float | None
    notes: tuple[NoteLike, ...] = ()
    spectrum_note: str = ""
    per_realization: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    contact_maps: dict[int, NDArray[np.bool_]] = field(default_factory=dict, repr=False)  # realisation 0
    gas: GasSimulation | None = None
    capillarity: SimulationCapillarity | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "junction_resolved", junction_resolved(self.junction_cells))


def simulate(
    case: Case,
    *,
    grid: int,
    realizations: int,
    seed: int,
    threshold: bool = True,
    fields_dir: str | Path | None = None,
    contact_tol: float = 1e-8,
    flow_method: FlowMethod = "auto",
    progress: Callable[[int], None] | None = None,
    memory_limit: float | None = None,
    grid_name: str = "grid",
    runner: Callable[[list[EnsembleTask]], Iterable[TaskRecord]] | None = None,
    device: str = "cpu",
) -> SimulationResult:
    """Numerically exact leak rate and α for ``case`` at its squeeze pressures.

    α = Q_num/Q_cj(α = 1) = Q_sq/(u_c³ ΔP/(12η)) per percolating realisation; leak rates in m³/s
    (docs/theory.md §6.5; Q_cj: Lorenz & Persson (2009) eq. 2). The ensemble pipeline
    (:func:`sealeak.cases.pipeline.run_ensemble`) with the :class:`PeriodicSquare` geometry.

    Parameters
    ----------
    case:
        The seal case (its spectrum, E*, seal, fluid, pressures, q0).
    grid:
        N, grid points per side of the square (even, >= 16).
    realizations:
        R, number of random surfaces (>= 1).
    seed:
        Random seed; realisation r uses ``numpy.random.default_rng([seed, r])``.
    threshold:
        Also find each realisation's percolation threshold (extra contact solves).
    fields_dir:
        If given, write ``r<r>-p<i>.npz`` (height, gap, pressure [x, y] in m, m, Pa; size in m).
    progress:
        Called with the number of finished (realisation, pressure) steps since the last call (only
        without ``runner``).
    grid_name:
        How messages name the grid (``--grid`` or ``simulation.grid`` from the command line).
    runner:
        Runs the independent tasks (:func:`ensemble_tasks`: each realisation's pressure sweep and its
        threshold search) and returns their results (:func:`run_task`) in the order given; None runs
        them one after the other in this process. :func:`sealeak.cases.ensemble.make_runner` runs them
        on a Dask cluster and keeps them in a store. Results are aggregated in realisation order, so
        they do not depend on the runner.
    device:
        ``"cpu"`` (NumPy, the default) or ``"cuda"``: surface synthesis and contact on an NVIDIA GPU with CuPy
        (the ``gpu`` extra), and the flows' AMG iterations there too (their set-up and small fields' direct
        solves stay on the CPU). The same surfaces; the numbers agree with the CPU's to FFT
        round-off, the leak rates within the flow solver's tolerance (docs/performance.md).
    """
    return run_ensemble(PeriodicSquare(threshold), case, grid=grid, realizations=realizations, seed=seed,
                        grid_field=grid_name, fields_dir=fields_dir, contact_tol=contact_tol, flow_method=flow_method,
                        progress=progress, memory_limit=memory_limit, runner=runner, device=device)


@dataclass(frozen=True, kw_only=True)
class _SquarePlan:
    """What :class:`PeriodicSquare` prepares: the case with the cut spectrum, pressures (Pa), theory (SI units)."""

    case: Case
    spectrum: PowerSpectrum
    size: float
    cut_at: float | None
    pressures: FloatArray
    q_cj: FloatArray
    junction_cells: FloatArray
    u_c: FloatArray
    critical_wavelength: FloatArray
    contact_theory: FloatArray
    threshold_anchor: float


@dataclass(frozen=True)
class PeriodicSquare:
    """The geometry of a uniform seal: a periodic square of side L = 2π/q0 pressed flat at each squeeze pressure.

    Its tasks are each realisation's pressure sweep and, with ``threshold``, its percolation-threshold search;
    the theory is the critical-junction leak rate (α = 1) of the same cut spectrum.
    """

    threshold: bool = True

    def check_memory(self, grid: int, memory_limit: float | None) -> None:
        """The periodic contact problem of an N × N grid must fit in memory."""
        numerics.check_memory(grid, "contact", available=memory_limit)

    def prepare(self, case: Case, grid: int, grid_field: str, notes: list[NoteLike],
                progress: Callable[[int], None] | None) -> _SquarePlan:
        """The cut spectrum, the sorted pressures, the critical-junction theory and the threshold's anchor."""
        size = case.square_side
        spectrum, cut_at, cut_notes = cut_spectrum(case.spectrum, grid, size, grid_field, "critical-junction")
        notes.extend(cut_notes)
        sim_case = replace(case, spectrum=spectrum)
        pressures = np.sort(np.asarray(case.squeeze_pressure, dtype=float))
        if not np.array_equal(pressures, case.squeeze_pressure):
            notes.append(Note("pressures_sorted"))
        q_cj, junction_cells, u_c, lam_c = _theory_leak_rate(sim_case, pressures, grid, cut_at, notes)
        contact_theory = sim_case.contact().area(sim_case.spectrum.q_max / sim_case.q0, pressures)
        return _SquarePlan(case=sim_case, spectrum=spectrum, size=size, cut_at=cut_at, pressures=pressures, q_cj=q_cj,
                           junction_cells=junction_cells, u_c=u_c, critical_wavelength=lam_c, contact_theory=contact_theory,
                           threshold_anchor=_threshold_anchor(sim_case))

    def tasks(self, plan: _SquarePlan, common: RunSettings, realizations: int) -> list[EnsembleTask]:
        """Each realisation's sweep, then (if asked) its threshold search."""
        spec = common.spec(EnsembleSpec, spectrum=plan.spectrum, size=plan.size, pressures=plan.pressures,
                           aspect=plan.case.seal.aspect_ratio, threshold_anchor=plan.threshold_anchor,
                           capillary=plan.case.capillarity is not None)
        return ensemble_tasks(spec, realizations, self.threshold)

    def aggregate(self, plan: _SquarePlan, records: Records, notes: list[NoteLike]) -> SimulationResult:
        """Means over realisations, α = Q/Q_cj over the percolating ones, the thresholds, a gas case's gas leak."""
        case, pressures, q_cj = plan.case, plan.pressures, plan.q_cj
        n_p = pressures.size
        flows = Flows.of(records, SweepRecord, n_p)
        gap = records.stack(SweepRecord, lambda rec: rec.mean_gap, n_p)
        thresholds = np.full(records.realizations, np.nan)
        for rec in records.of(ThresholdRecord):
            thresholds[rec.realization] = rec.threshold
            notes.extend(map(Note.of, rec.notes))
        perc, q_seal = flows.percolates, flows.leak_rate
        area_m, area_s = mean_std(flows.area)
        gap_m, gap_s = mean_std(gap)
        q_m, q_s = mean_std(q_seal)
        with np.errstate(invalid="ignore", divide="ignore"):
            alpha_r = np.where(perc & np.isfinite(q_cj)[None, :], q_seal / q_cj[None, :], np.nan)
        alpha_m, alpha_s = mean_std(alpha_r)
        thr_m, thr_s = mean_std(thresholds[:, None])
        if self.threshold and np.isnan(thresholds).all():
            notes.append(Note("no_threshold_found"))
        gas_result, per_gas = gas_part(case, q_cj, plan.u_c, plan.critical_wavelength, flows)
        capillarity, per_capillary = capillary_part(case, records, SweepRecord, plan.u_c, perc)
        return SimulationResult(
            squeeze_pressure=pressures, pressure_difference=float(case.pressure_difference), relative_contact_area=area_m,
            relative_contact_area_std=area_s, relative_contact_area_theory=plan.contact_theory, mean_gap=gap_m,
            mean_gap_std=gap_s, percolating_fraction=perc.mean(axis=0), leak_rate=q_m, leak_rate_std=q_s,
            leak_rate_critical_junction=q_cj, alpha=alpha_m, alpha_std=alpha_s,
            percolation_threshold=float(thr_m[0]), percolation_threshold_std=float(thr_s[0]), grid=records.grid,
            realizations=records.realizations, seed=records.seed, size=plan.size, q_cut=plan.cut_at,
            notes=tuple(notes), spectrum_note=spectrum_text(plan.spectrum, case), contact_maps=flows.contact_maps,
            junction_cells=plan.junction_cells,
            per_realization={"relative_contact_area": flows.area, "mean_gap": gap, "percolates": perc,
                             "leak_rate": q_seal, "alpha": alpha_r, "percolation_threshold": thresholds} | per_gas
                            | per_capillary,
            gas=gas_result, capillarity=capillarity,
        )


@dataclass(frozen=True, kw_only=True)
class EnsembleSpec(TaskSpec):
    """Everything one task of a uniform seal's ensemble needs, in SI units (shared by all tasks of a run).

    :class:`~sealeak.cases.pipeline.TaskSpec`'s fields, and ``pressures`` the sorted squeeze pressures (Pa),
    ``aspect`` Ly/Lx, ``threshold_anchor`` the threshold search's first pressure (Pa).
    """

    pressures: FloatArray
    aspect: float
    threshold_anchor: float

    def geometry_identity(self) -> dict[str, Any]:
        """The square's own inputs: the squeeze pressures, Ly/Lx and the threshold search's anchor."""
        return {"squeeze_pressure": [float(x) for x in self.pressures], "aspect": float(self.aspect),
                "threshold_anchor": float(self.threshold_anchor)}


@dataclass(frozen=True)
class EnsembleTask:
    """One independent task: realisation ``realization``'s pressure sweep (``kind = "sweep"``) or threshold search."""

    kind: str
    realization: int
    spec: EnsembleSpec

    @property
    def name(self) -> str:
        """``sweep-r<r>`` or ``threshold-r<r>``: the task's name in the store and in progress lines."""
        return f"{self.kind}-r{self.realization}"

    @property
    def writes_fields(self) -> bool:
        """Whether the task writes its fields into a store (a sweep, with ``spec.fields_store`` set)."""
        return self.kind == "sweep" and self.spec.fields_store is not None

    def memory_bytes(self) -> int:
        """Peak memory of this task in bytes (estimate; docs/theory.md §6.7).

        A sweep holds the heights (8N² B) and the gap and pressure maps of every squeeze pressure
        (n_p · 16N² B), and on top of them at one time either a contact solve
        (:func:`sealeak.numerics.contact_memory_bytes`), or a flow solve
        (:func:`sealeak.numerics.flow_memory_bytes`, for a gas :func:`sealeak.numerics.gas_flow_memory_bytes`),
        or the writing of one map into the store (16N² B: the map and its compressed copy). A threshold
        search holds one contact solve and, beside it, the heights, the previous solution (gap and
        pressure, a warm start), cluster labels and masks: 48N² B in all. Both add :data:`TASK_BASE_BYTES`
        for the worker process itself.
        """
        return task_memory_bytes(self.kind, self.spec.grid, self.spec.grid, int(np.size(self.spec.pressures)),
                                 contact="periodic", gas=self.spec.gas is not None, fields=self.spec.fields_store is not None,
                                 flow_method=self.spec.flow_method)

    def run(self, progress: Callable[[int], None] | None = None) -> SweepRecord | ThresholdRecord:
        """Compute this task (:func:`run_task`)."""
        return run_task(self, progress)


def ensemble_tasks(spec: EnsembleSpec, realizations: int, threshold: bool) -> list[EnsembleTask]:
    """The tasks of a run in realisation order: each realisation's sweep, then (if asked) its threshold search."""
    kinds = ("sweep", "threshold") if threshold else ("sweep",)
    return [EnsembleTask(k, r, spec) for r in range(int(realizations)) for k in kinds]


@dataclass(frozen=True, kw_only=True)
class SweepRecord(FlowRecord):
    """A realisation's pressure sweep (:func:`run_task`): :class:`~sealeak.cases.pipeline.FlowRecord`'s
    columns per squeeze pressure, and the mean gap."""

    KIND = "sweep"

    mean_gap: list[float] = quantity("m", "mean gap")


@dataclass(frozen=True, kw_only=True)
class ThresholdRecord(TaskRecord):
    """A realisation's percolation-threshold search (:func:`run_task`) and its notes."""

    KIND = "threshold"

    threshold: float = quantity("1", "relative contact area at which the fluid stops crossing (NaN: not found)")
    notes: list[dict[str, Any]] = field(default_factory=list)  # each a Note as plain JSON (:meth:`Note.to_mapping`)


def run_task(task: EnsembleTask, progress: Callable[[int], None] | None = None) -> SweepRecord | ThresholdRecord:
    """Compute one task; return its record, plain JSON values (lists of floats, bools, ints, strings).

    Realisation r's surface is ``synthesize`` with the seed sequence (seed, r) (docs/theory.md §6.1), drawn
    again by each task that needs it, so every task depends on its inputs only. A sweep solves the contact
    at every squeeze pressure (warm-started upwards) and the flow through each gap field (§6.2–6.3); it
    returns per pressure the relative contact area, mean gap (m), whether the fluid percolates and the
    seal's leak rate (Ly/Lx)·Q_sq (m³/s), for a gas also the pV throughputs (Pa·m³/s, §11.10), and for
    realisation 0 the contact maps (packed). Synthesis, contact and the flows' AMG iterations run on ``spec.device``, the rest of the flow on the host.
    Field files, if asked, are written by the task itself: npz files
    into ``spec.fields_stage``, or, with ``spec.fields_store``, the Zarr group ``r<r>`` of the store
    (:class:`sealeak.io.fieldstore.TaskFields`, renamed in when complete; its name and the SHA-256 of each
    array are its record's ``fields``). A threshold task returns the relative contact area at the
    percolation threshold (§6.4) and its notes.
    """
    spec, r = task.spec, task.realization
    h = spec.on_device(spec.surface(r))
    if task.kind == "threshold":
        notes: list[dict[str, Any]] = []
        th = _threshold(h, spec.size, spec.e_star, spec.threshold_anchor, spec.contact_tol, notes, r, spec.fft_workers)
        return ThresholdRecord(realization=r, threshold=float(th), notes=notes)
    log = FlowLog(gas=spec.gas is not None, capillary=spec.capillary)
    gaps: list[float] = []
    results = numerics.solve_contact_sweep(h, spec.size, spec.e_star, spec.pressures, tol=spec.contact_tol,
                                           workers=spec.fft_workers, host=True)
    h = numerics.to_numpy(h)  # the flow and the fields on the host

    def sweep(kept: Any) -> None:
        for i, res in enumerate(results):
            gaps.append(float(res.mean_gap))
            log.add(spec, r, res, spec.aspect, res.contact_area)
            keep_load(spec, kept, r, i, h, res, progress)

    kept = with_fields(spec, r, h, sweep, load_name="squeeze_pressure", loads=spec.pressures, load_unit="Pa",
                       attributes=spec.field_attributes(f"sweep-r{r}", r))
    return log.record(SweepRecord, r, kept, mean_gap=gaps)


def _theory_leak_rate(case: Case, pressures: FloatArray, grid: int, cut_at: float | None,
                      notes: list[NoteLike]) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Critical-junction Q (α = 1, m³/s) of the (cut) spectrum, the grid cells across each junction, u_c and λc.

    Returns ``(q_cj, cells, u_c, λc)``: u_c and λc are ``predict``'s critical gap and wavelength (m; NaN where Q_cj
    is not computed);
    cells = N/ζc, the grid cells across the critical wavelength
    λc = L/ζc (NaN where the theory has no junction). The critical gap u_c = u1(ζc) falls to zero as
    ζc approaches the end of the spectrum ζ1 (u1(ζ1) = 0, docs/theory.md §2.10); on a coarse grid
    the spectrum is cut at ζ1 = N/4, so at the higher pressures the junction can sit in the last
    octave of the band (fewer than :data:`JUNCTION_CELLS` cells), where α reflects the grid more
    than the seal (flagged, with a note naming the grid), or at its very end, where u_c vanishes
    and neither Q_cj nor α exists (NaN, with the same note).
    """
    contact = case.contact()
    zeta_c, percolates = contact.zeta_at_area(1.0 - case.percolation_threshold, pressures)
    with np.errstate(all="ignore"):
        u_c = np.where(percolates, contact.u1(np.where(percolates, zeta_c, 1.0), pressures), np.nan)
    zeta_1 = contact.zeta_max
    at_end = percolates & ~(np.isfinite(u_c) & (u_c > 0)) & (zeta_c - 1.0 > 0.5 * (zeta_1 - 1.0))
    q_cj = np.full(pressures.size, np.nan)
    gap_c = np.full(pressures.size, np.nan)
    lam_c = np.full(pressures.size, np.nan)
    keep = ~at_end
    if keep.any():
        cj = predict(replace(case, alpha=1.0), squeeze_pressure=pressures[keep])
        q_cj[keep] = cj.leak_rate
        gap_c[keep] = np.where(cj.percolates, cj.critical_gap, np.nan)
        lam_c[keep] = np.where(cj.percolates, cj.critical_wavelength, np.nan)
    cells = np.where(percolates, grid / zeta_c, np.nan)
    coarse = percolates & (cells < JUNCTION_CELLS)
    if coarse.any():
        notes.append(Note("junction_unresolved", {
            "grid": grid, "cut_at": cut_at, "zeta_1": float(zeta_1), "min_cells": JUNCTION_CELLS,
            "coarse": tuple(float(p) for p in pressures[coarse & ~at_end]),
            "at_end": tuple(float(p) for p in pressures[at_end])}))
    return q_cj, cells, gap_c, lam_c


def _threshold_anchor(case: Case) -> float:
    """Where the threshold search starts (Pa): the P0 at which Persson's A(ζ1)/A0 = 1/2 on the (cut) spectrum.

    A(ζ1)/A0 = erf(P0/(2√G(ζ1))) (docs/theory.md §2.4), so P0 = 2√G(ζ1) erf⁻¹(1/2). It depends on
    the surface and the rubber only, never on the squeeze pressures listed in the case.
    """
    return bruggeman_threshold(case.contact())


#: Ladder of the threshold search: pressures p_anchor·2^k, k = 0, ±1, ... up to this many steps.
THRESHOLD_LADDER_STEPS = 12
#: Relative width of the final pressure bracket of the threshold bisection.
THRESHOLD_REL_TOL = 1e-3


def _threshold(h: FloatArray, size: float, e_star: float, p_anchor: float, tol: float, notes: list[dict[str, Any]],
               r: int, workers: int = -1) -> float:
    """Relative contact area at which realisation ``r``'s non-contact area stops spanning inlet to outlet.

    The bracket comes from a ladder p_anchor·2^k (k = 0, then up while the fluid spans or down while
    it does not), the threshold from bisection to a relative pressure width of 1e-3
    (:func:`sealeak.numerics.percolation_threshold`; docs/theory.md §6.4). Nothing depends on the
    squeeze pressures listed in the case, so neither does the threshold.
    """
    def spanning(p: float) -> bool:
        return numerics.spans(~numerics.solve_contact(h, size, e_star, p, tol=tol, workers=workers).contact)

    first = spanning(p_anchor)
    step = 1 if first else -1
    for k in range(step, step * (THRESHOLD_LADDER_STEPS + 1), step):
        if spanning(p_anchor * 2.0**k) != first:
            break
    else:
        notes.append(Note("threshold_not_found", {
            "realization": int(r), "still_spans": bool(first),
            "squeeze_pressure": float(p_anchor * 2.0 ** (step * THRESHOLD_LADDER_STEPS))}).to_mapping())
        return float("nan")
    p_a, p_b = sorted((p_anchor * 2.0 ** (k - step), p_anchor * 2.0**k))
    th = numerics.percolation_threshold(h, size, e_star, p_lo=p_a, p_hi=p_b, rel_tol=THRESHOLD_REL_TOL, tol=tol,
                                            workers=workers)
    return th.contact_area

