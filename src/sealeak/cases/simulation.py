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

import base64
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray
from scipy import special

from .. import numerics
from .._version import __version__
from ..errors import InputError
from ..io.fieldstore import TaskFields
from ..io.files import OutputWriteError, check_replaceable
from ..io.leak_units import MOLAR_GAS_CONSTANT
from ..numerics.synthesis import synthesize
from .gas import gas_rows
from .limits import MAX_REALIZATIONS, whole_number
from .model import Case, GasConditions
from .prediction import predict

__all__ = ["SimulationResult", "GasSimulation", "simulate", "resolved_spectrum_cut", "POINTS_PER_WAVELENGTH",
           "JUNCTION_CELLS", "EnsembleSpec", "EnsembleTask", "ensemble_tasks", "run_task", "task_memory_bytes",
           "TASK_BASE_BYTES"]

POINTS_PER_WAVELENGTH = 4
#: Grid cells the critical wavelength λc must span for α to describe the seal rather than the grid.
JUNCTION_CELLS = 8
FloatArray = NDArray[np.float64]
#: The Reynolds solver's method (:func:`sealeak.numerics.solve_flow`).
FlowMethod = Literal["auto", "direct", "amg"]


def resolved_spectrum_cut(grid: int, size: float) -> float:
    """Highest wavevector an N-point grid of side ``size`` resolves with 4 points per wavelength (1/m)."""
    return 2.0 * np.pi * grid / (POINTS_PER_WAVELENGTH * size)


@dataclass(frozen=True)
class GasSimulation:
    """The gas leak of a gas case, per squeeze pressure (SI units; docs/theory.md §11.10).

    Leak rates are the seal's, (Ly/Lx) times the square's, averaged over all realisations (a blocked
    one leaks 0), ``*_std`` their standard deviations (ddof = 1; NaN with fewer than two values).

    Attributes
    ----------
    gas_name, temperature, upstream_pressure, downstream_pressure, rarefaction
        The gas, T (K), P_a and P_b (Pa, absolute) and the slip model.
    throughput, throughput_std
        pV throughput Q_pV (Pa·m³/s), counted at T.
    mass_flow, mass_flow_std
        ṁ = Q_pV/(R_s T) (kg/s).
    molar_flow
        ṅ = Q_pV/(R T) (mol/s).
    slip_gain
        Q_pV/Q_pV(no slip) of the same gap fields, mean over percolating realisations: how much the
        rarefaction adds (1 without slip).
    throughput_critical_junction
        The critical-junction gas leak with α = 1, the same (possibly cut) spectrum and rarefaction model
        (Pa·m³/s; NaN where the theory has no junction).
    knudsen_critical_junction, regime_critical_junction
        Kn = λ/u_c at the mean pressure (P_a + P_b)/2 and its flow regime (as ``predict`` reports them).
    alpha, alpha_std
        α_gas = Q_pV/Q_pV,cj(α = 1) over the percolating realisations (NaN where none percolates).
    iterations
        The most fixed-point iterations any realisation needed (0 without slip).
    """

    gas_name: str
    temperature: float
    upstream_pressure: float
    downstream_pressure: float
    rarefaction: str
    throughput: FloatArray
    throughput_std: FloatArray
    mass_flow: FloatArray
    mass_flow_std: FloatArray
    molar_flow: FloatArray
    slip_gain: FloatArray
    throughput_critical_junction: FloatArray
    knudsen_critical_junction: FloatArray
    regime_critical_junction: tuple[str, ...]
    alpha: FloatArray
    alpha_std: FloatArray
    iterations: NDArray[np.int64]


@dataclass(frozen=True)
class SimulationResult:
    """Per-pressure statistics over realisations (SI units). Arrays have one entry per pressure.

    ``*_std`` are standard deviations over realisations (ddof = 1; NaN with fewer than two values).
    ``leak_rate`` averages all realisations (a blocked one leaks 0); ``alpha`` averages the
    percolating ones only (NaN where none percolates). ``leak_rate_critical_junction`` is the
    critical-junction prediction with α = 1 for the same (possibly cut) spectrum.
    ``junction_cells`` is N/ζc, the grid cells across the theory's critical wavelength λc (NaN where
    there is no junction); below :data:`JUNCTION_CELLS` the α of that pressure is flagged.
    ``gas`` holds the gas leak and α_gas of a gas case (None for a liquid); the other fields are then
    the incompressible formula with the gas's viscosity.
    """

    squeeze_pressure: FloatArray
    pressure_difference: float
    relative_contact_area: FloatArray
    relative_contact_area_std: FloatArray
    relative_contact_area_theory: FloatArray
    mean_gap: FloatArray
    mean_gap_std: FloatArray
    percolating_fraction: FloatArray
    leak_rate: FloatArray
    leak_rate_std: FloatArray
    leak_rate_critical_junction: FloatArray
    alpha: FloatArray
    alpha_std: FloatArray
    percolation_threshold: float
    percolation_threshold_std: float
    grid: int
    realizations: int
    seed: int
    size: float
    q_cut: float | None
    notes: tuple[str, ...] = ()
    spectrum_note: str = ""
    per_realization: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    contact_maps: dict[int, NDArray[np.bool_]] = field(default_factory=dict, repr=False)  # realisation 0
    junction_cells: FloatArray = field(default_factory=lambda: np.empty(0))
    gas: GasSimulation | None = None


def _mean_std(x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Mean and standard deviation (ddof = 1) over axis 0, ignoring NaN; std NaN for fewer than two values."""
    x = np.asarray(x, dtype=float)
    ok = np.isfinite(x)
    n = ok.sum(axis=0)
    mean = np.where(n > 0, np.where(ok, x, 0.0).sum(axis=0) / np.maximum(n, 1), np.nan)
    dev = np.where(ok, x - mean, 0.0)
    var = np.where(n > 1, (dev**2).sum(axis=0) / np.maximum(n - 1, 1), 0.0)
    return mean, np.where(n > 1, np.sqrt(var), np.nan)


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
    runner: Callable[[list[EnsembleTask]], Iterable[dict[str, Any]]] | None = None,
) -> SimulationResult:
    """Numerically exact leak rate and α for ``case`` at its squeeze pressures.

    α = Q_num/Q_cj(α = 1) = Q_sq/(u_c³ ΔP/(12η)) per percolating realisation; leak rates in m³/s
    (docs/theory.md §6.5; Q_cj: Lorenz & Persson (2009) eq. 2).

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
    runner:
        Runs the independent tasks (:func:`ensemble_tasks`: each realisation's pressure sweep and its
        threshold search) and returns their results (:func:`run_task`) in the order given; None runs
        them one after the other in this process. :func:`sealeak.cases.ensemble.make_runner` runs them
        on a Dask cluster and keeps them in a store. Results are aggregated in realisation order, so
        they do not depend on the runner.
    """

    if not isinstance(grid, (int, np.integer)) or grid < 16 or grid % 2:
        raise InputError("grid", grid, "must be an even integer >= 16")
    whole_number("realizations", realizations, 1, MAX_REALIZATIONS)
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "must be a whole number >= 0")
    gas = case.gas
    if not getattr(runner, "checks_memory", False):  # a runner of make_runner checks each task where it runs
        numerics.check_memory(grid, "contact", available=memory_limit)
        numerics.check_memory(grid, "flow", available=memory_limit)
        if gas is not None:
            numerics.require_memory(numerics.gas_flow_memory_bytes(grid), f"the {grid}x{grid} gas flow problem",
                                    memory_limit)

    size = case.square_side
    notes: list[str] = []
    q_cut = resolved_spectrum_cut(grid, size)
    spectrum = case.spectrum
    cut_at: float | None = None
    if spectrum.q_max > q_cut:
        if q_cut <= spectrum.q_min:
            raise InputError("grid", grid, f"resolves q only up to {q_cut:.4g} 1/m, below the spectrum's band "
                                           f"({spectrum.q_min:.4g} .. {spectrum.q_max:.4g} 1/m): use a larger grid")
        spectrum = spectrum.truncated(None, q_cut)
        cut_at = q_cut
        notes.append(f"the {grid}x{grid} grid resolves q up to {q_cut:.4g} 1/m ({POINTS_PER_WAVELENGTH} points per "
                     f"wavelength), below the spectrum's cut-off q1 = {case.spectrum.q_max:.4g} 1/m: the spectrum was "
                     f"cut there for the simulation AND for the critical-junction theory it is compared with "
                     f"(h_rms {case.spectrum.h_rms * 1e6:.4g} -> {spectrum.h_rms * 1e6:.4g} µm)")
    sim_case = replace(case, spectrum=spectrum)
    pressures = np.sort(np.asarray(case.squeeze_pressure, dtype=float))
    if not np.array_equal(pressures, case.squeeze_pressure):
        notes.append("squeeze pressures were sorted in increasing order")
    dp = float(case.pressure_difference)
    eta = case.fluid.viscosity
    aspect = case.seal.aspect_ratio

    q_cj, junction_cells, u_c = _theory_leak_rate(sim_case, pressures, grid, cut_at, notes)
    contact_theory = sim_case.contact().area(sim_case.spectrum.q_max / sim_case.q0, pressures)
    p_anchor = _threshold_anchor(sim_case)

    n_p = pressures.size
    with _StagedFolder(fields_dir) as fields:
        spec = EnsembleSpec(spectrum=spectrum, grid=int(grid), size=size, seed=int(seed), e_star=case.e_star,
                            pressures=pressures, viscosity=eta, pressure_difference=dp, aspect=aspect, gas=gas,
                            flow_method=flow_method, contact_tol=contact_tol, threshold_anchor=p_anchor,
                            memory_limit=memory_limit, fields_stage=None if fields.stage is None else str(fields.stage),
                            fields_target=None if fields.target is None else str(fields.target))
        tasks = ensemble_tasks(spec, realizations, threshold)
        if runner is None:
            done = [run_task(t, progress=progress) for t in tasks]
        else:
            done = list(runner(tasks))
    area = np.zeros((realizations, n_p))
    gap = np.zeros((realizations, n_p))
    perc = np.zeros((realizations, n_p), dtype=bool)
    q_seal = np.zeros((realizations, n_p))
    thresholds = np.full(realizations, np.nan)
    contact_maps: dict[int, NDArray[np.bool_]] = {}
    gas_pv = np.zeros((realizations, n_p))  # the seal's pV throughput (Pa·m³/s)
    gas_pv_no_slip = np.zeros((realizations, n_p))
    gas_iterations = np.zeros((realizations, n_p), dtype=np.int64)
    for task, out in zip(tasks, done, strict=True):  # in realisation order, whatever order they finished in
        r = task.realization
        if task.kind == "threshold":
            thresholds[r] = out["threshold"]
            notes.extend(out["notes"])
            continue
        area[r] = out["relative_contact_area"]
        gap[r] = out["mean_gap"]
        perc[r] = out["percolates"]
        q_seal[r] = out["leak_rate"]
        if gas is not None:
            gas_pv[r] = out["leak_rate_pv"]
            gas_pv_no_slip[r] = out["leak_rate_pv_no_slip"]
            gas_iterations[r] = out["gas_iterations"]
        if r == 0:
            contact_maps = {i: unpack_mask(m) for i, m in enumerate(out["contact_maps"])}

    area_m, area_s = _mean_std(area)
    gap_m, gap_s = _mean_std(gap)
    q_m, q_s = _mean_std(q_seal)
    with np.errstate(invalid="ignore", divide="ignore"):
        alpha_r = np.where(perc & np.isfinite(q_cj)[None, :], q_seal / q_cj[None, :], np.nan)
    alpha_m, alpha_s = _mean_std(alpha_r)
    thr_m, thr_s = _mean_std(thresholds[:, None])
    spectrum_note = (f"{spectrum.label or case.spectrum_note}: h_rms = {spectrum.h_rms * 1e6:.4g} µm over "
                     f"q = {spectrum.q_min:.4g} .. {spectrum.q_max:.4g} 1/m")
    if threshold and np.isnan(thresholds).all():
        notes.append("no percolation threshold found (see the notes above)")
    gas_result = None
    if gas is not None:
        gas_result = _gas_statistics(sim_case, q_cj, u_c, perc, gas_pv, gas_pv_no_slip, gas_iterations)
        per_gas = {"leak_rate_pv": gas_pv, "leak_rate_pv_no_slip": gas_pv_no_slip, "gas_iterations": gas_iterations,
                   "alpha_gas": _ratio(perc, gas_pv, gas_result.throughput_critical_junction)}
    else:
        per_gas = {}
    return SimulationResult(
        squeeze_pressure=pressures, pressure_difference=dp, relative_contact_area=area_m,
        relative_contact_area_std=area_s, relative_contact_area_theory=contact_theory, mean_gap=gap_m,
        mean_gap_std=gap_s, percolating_fraction=perc.mean(axis=0), leak_rate=q_m, leak_rate_std=q_s,
        leak_rate_critical_junction=q_cj, alpha=alpha_m, alpha_std=alpha_s,
        percolation_threshold=float(thr_m[0]), percolation_threshold_std=float(thr_s[0]), grid=int(grid),
        realizations=int(realizations), seed=int(seed), size=size, q_cut=cut_at, notes=tuple(notes),
        spectrum_note=spectrum_note, contact_maps=contact_maps, junction_cells=junction_cells,
        per_realization={"relative_contact_area": area, "mean_gap": gap, "percolates": perc,
                         "leak_rate": q_seal, "alpha": alpha_r, "percolation_threshold": thresholds} | per_gas,
        gas=gas_result,
    )


def gas_identity(gas: GasConditions | None) -> dict[str, Any] | None:
    """A gas case's conditions as plain JSON values for a store's manifest (None for a liquid)."""
    if gas is None:
        return None
    return {"name": gas.gas.name, "temperature": float(gas.temperature), "upstream_pressure": float(gas.upstream_pressure),
            "downstream_pressure": float(gas.downstream_pressure), "rarefaction": gas.rarefaction}


@dataclass(frozen=True)
class EnsembleSpec:
    """Everything one task of an ensemble needs, in SI units (shared by all tasks of a run).

    ``spectrum`` is the (possibly cut) C(q) the surfaces are drawn from; ``size`` L (m), ``e_star`` E* (Pa),
    ``pressures`` the sorted squeeze pressures (Pa), ``viscosity`` η (Pa·s), ``pressure_difference`` ΔP (Pa),
    ``aspect`` Ly/Lx, ``threshold_anchor`` the threshold search's first pressure (Pa). ``fields_stage`` is the
    folder the sweep tasks write their field files into (None: none), ``fields_store`` the task store folder
    whose ``fields.zarr`` the sweep tasks write their fields into (:mod:`sealeak.io.fieldstore`; None: none),
    ``fft_workers`` the FFT threads of each task (-1: all cores; 1 on a cluster, whose worker processes share
    the cores). None of these changes a number.
    """

    spectrum: Any
    grid: int
    size: float
    seed: int
    e_star: float
    pressures: FloatArray
    viscosity: float
    pressure_difference: float
    aspect: float
    gas: Any
    flow_method: FlowMethod
    contact_tol: float
    threshold_anchor: float
    memory_limit: float | None = None
    fields_stage: str | None = None
    fields_target: str | None = None
    fft_workers: int = -1
    fields_store: str | None = None

    def identity(self) -> dict[str, Any]:
        """The inputs the tasks' numbers depend on, as plain JSON values (floats exact by ``repr``).

        The store's manifest keeps a hash of it (:mod:`sealeak.cases.ensemble`): ``spectrum`` (the nodes of
        C(q)), ``grid``, ``seed`` and ``case`` (everything else that enters a task).
        """
        gas = self.gas
        return {
            "spectrum": {"q": [float(x) for x in self.spectrum.q], "C": [float(x) for x in self.spectrum.C]},
            "grid": int(self.grid),
            "seed": int(self.seed),
            "case": {"size": float(self.size), "e_star": float(self.e_star),
                     "squeeze_pressure": [float(x) for x in self.pressures], "viscosity": float(self.viscosity),
                     "pressure_difference": float(self.pressure_difference), "aspect": float(self.aspect),
                     "flow_method": self.flow_method, "contact_tol": float(self.contact_tol),
                     "threshold_anchor": float(self.threshold_anchor),
                     "gas": gas_identity(gas)},
        }


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


#: Memory of a worker process before its task (Python, NumPy, SciPy, PyAMG, Dask and sealeak imported):
#: about 200 MB resident were measured on Linux; rounded up.
TASK_BASE_BYTES = 256 * 2**20


def task_memory_bytes(kind: str, nx: int, ny: int, loads: int, *, contact: str, gas: bool, fields: bool,
                      flow_method: str = "auto") -> int:
    """Peak memory in bytes of one ensemble task on an nx × ny grid with ``loads`` loads (estimate, §6.7).

    ``kind`` is ``"sweep"`` (contact and flow at every load) or ``"threshold"``; ``contact`` is
    ``"periodic"`` (:func:`sealeak.numerics.contact_memory_bytes`) or ``"band"``
    (:func:`sealeak.numerics.band_contact_memory_bytes`).
    """
    cells = int(nx) * int(ny)
    solve = (numerics.contact_memory_bytes(int(nx)) if contact == "periodic"
             else numerics.band_contact_memory_bytes(int(nx), int(ny)))
    if kind != "sweep":
        return TASK_BASE_BYTES + 48 * cells + solve
    flow = (numerics.gas_flow_memory_bytes(int(nx), flow_method) if gas  # type: ignore[arg-type]
            else numerics.flow_memory_bytes(int(nx), flow_method))  # type: ignore[arg-type]
    write = 16 * cells if fields else 0
    return TASK_BASE_BYTES + 8 * cells + 16 * cells * int(loads) + max(solve, flow, write)


def ensemble_tasks(spec: EnsembleSpec, realizations: int, threshold: bool) -> list[EnsembleTask]:
    """The tasks of a run in realisation order: each realisation's sweep, then (if asked) its threshold search."""
    kinds = ("sweep", "threshold") if threshold else ("sweep",)
    return [EnsembleTask(k, r, spec) for r in range(int(realizations)) for k in kinds]


def pack_mask(mask: NDArray[np.bool_]) -> dict[str, Any]:
    """A boolean map as plain JSON values: its shape and its bits (``numpy.packbits``) in base64."""
    return {"shape": list(mask.shape), "bits": base64.b64encode(np.packbits(mask, axis=None).tobytes()).decode("ascii")}


def unpack_mask(packed: dict[str, Any]) -> NDArray[np.bool_]:
    """The boolean map :func:`pack_mask` packed."""
    shape = tuple(int(n) for n in packed["shape"])
    bits = np.frombuffer(base64.b64decode(packed["bits"]), dtype=np.uint8)
    return np.unpackbits(bits, count=int(np.prod(shape))).astype(bool).reshape(shape)


def run_task(task: EnsembleTask, progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Compute one task; return its scalars as plain JSON values (lists of floats, bools, ints, strings).

    Realisation r's surface is ``synthesize`` with the seed sequence (seed, r) (docs/theory.md §6.1), drawn
    again by each task that needs it, so every task depends on its inputs only. A sweep solves the contact
    at every squeeze pressure (warm-started upwards) and the flow through each gap field (§6.2–6.3); it
    returns per pressure the relative contact area, mean gap (m), whether the fluid percolates and the
    seal's leak rate (Ly/Lx)·Q_sq (m³/s), for a gas also the pV throughputs (Pa·m³/s, §11.10), and for
    realisation 0 the contact maps (packed). Field files, if asked, are written by the task itself: npz files
    into ``spec.fields_stage``, or, with ``spec.fields_store``, the Zarr group ``r<r>`` of the store
    (:class:`sealeak.io.fieldstore.TaskFields`, renamed in when complete; its name and the SHA-256 of each
    array are returned under ``"fields"``). A threshold task returns the relative contact area at the
    percolation threshold (§6.4) and its notes.
    """
    spec, r = task.spec, task.realization
    h = synthesize(spec.spectrum, spec.grid, spec.size, seed=np.random.default_rng([spec.seed, r]), workers=spec.fft_workers)
    if task.kind == "threshold":
        notes: list[str] = []
        th = _threshold(h, spec.size, spec.e_star, spec.threshold_anchor, spec.contact_tol, notes, r, spec.fft_workers)
        return {"kind": "threshold", "realization": r, "threshold": float(th), "notes": notes}
    gas = spec.gas
    out: dict[str, Any] = {"kind": "sweep", "realization": r, "relative_contact_area": [], "mean_gap": [],
                           "percolates": [], "leak_rate": [], "contact_maps": []}
    if gas is not None:
        out |= {"leak_rate_pv": [], "leak_rate_pv_no_slip": [], "gas_iterations": []}
    results = numerics.solve_contact_sweep(h, spec.size, spec.e_star, spec.pressures, tol=spec.contact_tol,
                                           workers=spec.fft_workers)
    kept = None
    if spec.fields_store is not None:
        kept = TaskFields(spec.fields_store, f"r{r}", grid=spec.grid, size=spec.size, period=spec.size,
                          load_name="squeeze_pressure", loads=spec.pressures, load_unit="Pa",
                          attributes=_field_attributes(spec, r, "sweep"))
    try:
        _sweep_flows(spec, r, h, results, out, kept, progress)
        if kept is not None:
            out["fields"] = kept.commit()
    except BaseException:
        if kept is not None:
            kept.abort()
        raise
    return out


def _field_attributes(spec: EnsembleSpec, r: int, kind: str) -> dict[str, Any]:
    """The attributes of a task's group of fields (JSON values; lengths in m, E* in Pa)."""
    return {"task": f"{kind}-r{r}", "realization": int(r), "seed": int(spec.seed), "grid": int(spec.grid),
            "size": float(spec.size), "period": float(spec.size), "length_units": "m", "e_star": float(spec.e_star),
            "e_star_units": "Pa", "software": f"sealeak {__version__}"}


def _sweep_flows(spec: EnsembleSpec, r: int, h: FloatArray, results: list[Any], out: dict[str, Any],
                 kept: TaskFields | None, progress: Callable[[int], None] | None) -> None:
    """The flow through each of a sweep's gap fields, its scalars into ``out``, its fields into ``kept``."""
    gas = spec.gas
    if kept is not None:
        kept.put_height(h)
    for i, res in enumerate(results):
        flow = numerics.solve_flow(res.gap, spec.size, spec.viscosity, spec.pressure_difference, contact=res.contact,
                                   method=spec.flow_method)
        out["relative_contact_area"].append(float(res.contact_area))
        out["mean_gap"].append(float(res.mean_gap))
        out["percolates"].append(bool(flow.percolates))
        out["leak_rate"].append(float(spec.aspect * flow.flux))
        if gas is not None:
            gflow = numerics.solve_gas_flow(res.gap, spec.size, gas.gas, gas.upstream_pressure, gas.downstream_pressure,
                                            contact=res.contact, model=gas.rarefaction, method=spec.flow_method,
                                            memory_limit=spec.memory_limit)
            out["leak_rate_pv"].append(float(spec.aspect * gflow.throughput))
            out["leak_rate_pv_no_slip"].append(float(spec.aspect * gflow.throughput_no_slip))
            out["gas_iterations"].append(int(gflow.iterations))
        if r == 0:
            out["contact_maps"].append(pack_mask(np.asarray(res.contact, dtype=bool)))
        if spec.fields_stage is not None:
            _write_fields(spec, f"r{r}-p{i}.npz", height=h, gap=res.gap, pressure=res.pressure, size=np.float64(spec.size))
        if kept is not None:
            kept.put(i, res.gap, res.pressure)
        if progress is not None:
            progress(1)


def _write_fields(spec: EnsembleSpec, name: str, **arrays: Any) -> None:
    """One field file into the run's staging folder (moved into the target when the run has finished)."""
    assert spec.fields_stage is not None
    try:
        with open(Path(spec.fields_stage) / name, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    except OSError as exc:
        raise OutputWriteError(Path(spec.fields_target or spec.fields_stage) / name, exc) from None


def _ratio(perc: NDArray[np.bool_], q: FloatArray, theory: FloatArray) -> FloatArray:
    """q/theory per realisation and pressure where the realisation percolates and the theory has a leak; else NaN."""
    ok = perc & (np.isfinite(theory) & (theory > 0))[None, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(ok, q / np.where(ok, theory[None, :], 1.0), np.nan)


def _gas_statistics(case: Case, q_cj: FloatArray, u_c: FloatArray, perc: NDArray[np.bool_], pv: FloatArray,
                    pv_no_slip: FloatArray, iterations: NDArray[np.int64]) -> GasSimulation:
    """Means over realisations of the gas leak, the critical-junction gas leak (α = 1) and α_gas.

    The theory is ``predict``'s (:func:`sealeak.cases.gas.gas_rows`): the channel of conductance
    K = Q_cj/ΔP (α = 1, the gas's viscosity) whose gap is u_c, integrated along the pressure drop with the
    case's rarefaction model (docs/theory.md §11.5).
    """
    gas = case.gas
    assert gas is not None
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(np.isfinite(q_cj) & (q_cj > 0), q_cj / case.pressure_difference, 0.0)
    rows = gas_rows(case, k, np.where(np.isfinite(u_c), u_c, np.nan))
    leaks = rows.leaks or ()
    theory = np.array([g.throughput if g is not None else np.nan for g in leaks])
    kn = np.array([g.knudsen_mean if g is not None else np.nan for g in leaks])
    regime = tuple(g.regime if g is not None else "" for g in leaks)
    pv_m, pv_s = _mean_std(pv)
    rst = gas.gas.specific_gas_constant * gas.temperature
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = np.where(perc, pv / np.where(perc, pv_no_slip, 1.0), np.nan)
    alpha_m, alpha_s = _mean_std(_ratio(perc, pv, theory))
    return GasSimulation(
        gas_name=gas.gas.name, temperature=gas.temperature, upstream_pressure=gas.upstream_pressure,
        downstream_pressure=gas.downstream_pressure, rarefaction=gas.rarefaction, throughput=pv_m, throughput_std=pv_s,
        mass_flow=pv_m / rst, mass_flow_std=pv_s / rst, molar_flow=pv_m / (MOLAR_GAS_CONSTANT * gas.temperature),
        slip_gain=_mean_std(gain)[0], throughput_critical_junction=theory, knudsen_critical_junction=kn,
        regime_critical_junction=regime, alpha=alpha_m, alpha_std=alpha_s, iterations=iterations.max(axis=0))


def _theory_leak_rate(case: Case, pressures: FloatArray, grid: int, cut_at: float | None,
                      notes: list[str]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Critical-junction Q (α = 1, m³/s) of the (cut) spectrum, the grid cells across each junction, and u_c.

    Returns ``(q_cj, cells, u_c)``: u_c is ``predict``'s critical gap (m; NaN where Q_cj is not computed);
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
    keep = ~at_end
    if keep.any():
        cj = predict(replace(case, alpha=1.0), squeeze_pressure=pressures[keep])
        q_cj[keep] = cj.leak_rate
        gap_c[keep] = np.where(cj.percolates, cj.critical_gap, np.nan)
    cells = np.where(percolates, grid / zeta_c, np.nan)
    coarse = percolates & (cells < JUNCTION_CELLS)
    if coarse.any():
        resolved = (f"resolves the spectrum only up to q = {cut_at:.4g} 1/m (ζ1 = {zeta_1:.4g})" if cut_at is not None
                    else f"has {grid} cells across the square")
        parts = []
        if (coarse & ~at_end).any():
            parts.append(f"at {_kpa(pressures[coarse & ~at_end])} the theory's critical junction "
                         f"λc = L/ζc spans fewer than {JUNCTION_CELLS} cells: the grid resolves it poorly and little "
                         "resolved roughness is left to hold the surfaces apart, so u_c falls steeply and α there "
                         "(marked *) reflects the grid more than the seal")
        if at_end.any():
            parts.append(f"at {_kpa(pressures[at_end])} the junction sits at the very end of the band, where "
                         "u_c vanishes: no critical-junction leak rate and no α")
        notes.append(f"grid = {grid}: the {grid}x{grid} grid {resolved}; " + "; ".join(parts)
                     + ". A finer grid (--grid, or grid in [simulation]) resolves the junction.")
    return q_cj, cells, gap_c


def _kpa(p: FloatArray) -> str:
    """Pressures for a note: all of a few, else the range ("P0 = 73 .. 234 kPa (19 pressures)")."""
    if p.size <= 4:
        return "P0 = " + ", ".join(f"{x / 1e3:.4g}" for x in p) + " kPa"
    return f"P0 = {p.min() / 1e3:.4g} .. {p.max() / 1e3:.4g} kPa ({p.size} pressures)"


def _threshold_anchor(case: Case) -> float:
    """Where the threshold search starts (Pa): the P0 at which Persson's A(ζ1)/A0 = 1/2 on the (cut) spectrum.

    A(ζ1)/A0 = erf(P0/(2√G(ζ1))) (docs/theory.md §2.4), so P0 = 2√G(ζ1) erf⁻¹(1/2). It depends on
    the surface and the rubber only, never on the squeeze pressures listed in the case.
    """
    contact = case.contact()
    return float(2.0 * np.sqrt(contact.G(contact.zeta_max)) * special.erfinv(0.5))


#: Ladder of the threshold search: pressures p_anchor·2^k, k = 0, ±1, ... up to this many steps.
THRESHOLD_LADDER_STEPS = 12
#: Relative width of the final pressure bracket of the threshold bisection.
THRESHOLD_REL_TOL = 1e-3


def _threshold(h: FloatArray, size: float, e_star: float, p_anchor: float, tol: float, notes: list[str],
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
        where = "still spans" if first else "does not span even"
        notes.append(f"realisation {r}: the fluid {where} at P0 = {p_anchor * 2.0 ** (step * THRESHOLD_LADDER_STEPS):.4g} "
                     "Pa; no percolation threshold found")
        return float("nan")
    p_a, p_b = sorted((p_anchor * 2.0 ** (k - step), p_anchor * 2.0**k))
    th = numerics.percolation_threshold(h, size, e_star, p_lo=p_a, p_hi=p_b, rel_tol=THRESHOLD_REL_TOL, tol=tol,
                                            workers=workers)
    return th.contact_area


class _StagedFolder:
    """Field files written into a hidden folder inside the target and moved in only when all are written.

    An interrupted or failed run (Ctrl-C, an error) removes the staging folder, and the target
    folder itself if this run created it, so no field file of an unfinished run is left behind.
    ``folder=None`` writes nothing.
    """

    def __init__(self, folder: str | Path | None) -> None:
        self.target = Path(folder) if folder is not None else None
        self.created: list[Path] = []
        self.stage: Path | None = None

    def __enter__(self) -> _StagedFolder:
        if self.target is None:
            return self
        if self.target.exists() and not self.target.is_dir():
            raise InputError("fields_dir", str(self.target), "is a file, not a folder: give a folder for the field files")
        missing = [d for d in (self.target, *self.target.parents) if not d.exists()]
        try:
            self.target.mkdir(parents=True, exist_ok=True)
            self.created = missing
            self.stage = Path(tempfile.mkdtemp(prefix=".sealeak-fields-", suffix=".part", dir=self.target))
        except OSError as exc:
            self._clean()
            raise OutputWriteError(self.target, exc) from None
        return self

    def write(self, name: str, **arrays: Any) -> None:
        if self.stage is None:
            return
        try:
            with open(self.stage / name, "wb") as fh:
                np.savez_compressed(fh, **arrays)
        except OSError as exc:
            raise OutputWriteError(self.target / name, exc) from None  # type: ignore[operator]

    def __exit__(self, exc_type: object, exc: object, tb: object) -> None:
        if self.stage is None:
            return
        if exc_type is None:
            moved: list[Path] = []
            parts = sorted(self.stage.iterdir())
            try:
                for part in parts:  # only regular files (or nothing) may be replaced, checked before any move
                    check_replaceable(self.target / part.name)  # type: ignore[operator]
            except BaseException:
                self._clean()
                raise
            try:
                for part in parts:
                    os.replace(part, self.target / part.name)  # type: ignore[operator]
                    moved.append(self.target / part.name)  # type: ignore[operator]
            except BaseException as err:
                for m in moved:
                    m.unlink(missing_ok=True)
                self._clean()
                if isinstance(err, OSError):
                    raise OutputWriteError(self.target, err) from None  # type: ignore[arg-type]
                raise
        self._clean()

    def _clean(self) -> None:
        if self.stage is not None:
            shutil.rmtree(self.stage, ignore_errors=True)
        for d in self.created:  # innermost first; only folders this run made, and only if empty
            try:
                d.rmdir()
            except OSError:
                break
