"""The one ensemble pipeline of every simulated geometry: options, spectrum, tasks, runner, aggregation.

A numerically exact simulation (docs/theory.md §6, §10.4) is the same pipeline whatever the body pressed on
the rough surface; :func:`run_ensemble` runs it and a :class:`Geometry` (a strategy object) supplies the
steps that differ:

1. the options are checked by the rules of :mod:`sealeak.cases.options` (grid, realisations, seed) and,
   unless the runner checks each task where it runs, the memory of one grid's contact (the geometry's),
   flow and gas-flow problems;
2. :meth:`Geometry.prepare`: the domain, the spectrum cut to what the grid resolves (:func:`cut_spectrum`),
   the theory the simulation is compared with, notes;
3. :meth:`Geometry.tasks`: independent tasks, each holding a :class:`TaskSpec` (what every geometry's tasks
   share: the spectrum, grid, seed, material, fluid, solver settings and where fields go) and knowing how to
   run itself (``task.run()``, :func:`compute_task`, which returns its :class:`TaskRecord`); they run one
   after the other in this process, or through a runner of :func:`sealeak.cases.ensemble.make_runner`
   (Dask, a store);
4. :meth:`Geometry.aggregate`: the tasks' records in realisation order (:class:`Records` of
   :class:`TaskRecord`, the flow scalars every geometry records, :class:`FlowRecord`, as :class:`Flows`),
   means and standard deviations over realisations (:func:`mean_std`), α and, for a gas,
   :class:`GasSimulation` (:func:`gas_part`).

The geometries: :class:`sealeak.cases.simulation.PeriodicSquare` (a uniform seal) and
:class:`sealeak.cases.simulation_band.OringBand` (a cylinder on the rough surface).
"""

from __future__ import annotations

import base64
import os
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any, ClassVar, Literal, Protocol, TypeVar

import numpy as np
from numpy.typing import NDArray

from .. import numerics
from .._version import __version__
from ..errors import InputError
from ..io.fieldstore import TaskFields
from ..io.files import OutputWriteError, check_replaceable
from ..io.leak_units import to_mbar_l_per_s
from ..io.quantities import quantity
from ..physics.gas import MOLAR_GAS_CONSTANT
from ..physics.spectrum import PowerSpectrum
from .gas import gas_rows
from .limits import MAX_REALIZATIONS, whole_number
from .model import Case, GasConditions
from .notes import Note, NoteLike
from .options import grid_number, seed_number

__all__ = ["Geometry", "junction_resolved", "run_ensemble", "RunSettings", "TaskSpec", "Records", "Flows", "TaskRecord", "FlowRecord",
           "FlowLog", "GasSimulation", "SimulationCapillarity", "capillary_part", "compute_task", "cut_spectrum",
           "resolved_spectrum_cut", "mean_std", "ratio", "gas_part", "gas_identity", "pack_mask", "unpack_mask",
           "task_memory_bytes", "TASK_BASE_BYTES", "POINTS_PER_WAVELENGTH", "JUNCTION_CELLS", "FlowMethod",
           "StagedFolder"]

POINTS_PER_WAVELENGTH = 4
#: Grid cells the critical wavelength λc must span for α to describe the seal rather than the grid.
JUNCTION_CELLS = 8


def junction_resolved(junction_cells: FloatArray) -> tuple[bool | None, ...]:
    """Per row: the theory's λc spans at least :data:`JUNCTION_CELLS` grid cells (None where it has no junction)."""
    return tuple(bool(c >= JUNCTION_CELLS) if np.isfinite(c) else None for c in junction_cells)
FloatArray = NDArray[np.float64]
#: The Reynolds solver's method (:func:`sealeak.numerics.solve_flow`).
FlowMethod = Literal["auto", "direct", "amg"]
#: Memory of a worker process before its task (Python, NumPy, SciPy, PyAMG, Dask and sealeak imported):
#: about 200 MB resident were measured on Linux; rounded up.
TASK_BASE_BYTES = 256 * 2**20

PlanT = TypeVar("PlanT")
ResultT = TypeVar("ResultT", covariant=True)


class Geometry(Protocol[PlanT, ResultT]):
    """The geometry-specific steps of :func:`run_ensemble` (a periodic square, an O-ring's band, ...)."""

    def check_memory(self, grid: int, memory_limit: float | None) -> None:
        """Refuse a grid whose contact problem does not fit in memory (before any work)."""

    def prepare(self, case: Case, grid: int, grid_field: str, notes: list[NoteLike],
                progress: Callable[[int], None] | None) -> PlanT:
        """The domain, the cut spectrum, the theory and everything the tasks and the aggregation need."""

    def tasks(self, plan: PlanT, common: RunSettings, realizations: int) -> list[Any]:
        """The independent tasks in realisation order; ``common`` holds :class:`TaskSpec`'s fields but
        the spectrum and the domain's size, which the plan gives (:meth:`RunSettings.spec`)."""

    def aggregate(self, plan: PlanT, records: Records, notes: list[NoteLike]) -> ResultT:
        """The result from the tasks' records (realisation order)."""


def compute_task(task: Any) -> TaskRecord:
    """Compute one task of any geometry (``task.run()``): the default task function of a runner."""
    return task.run()  # type: ignore[no-any-return]


def run_ensemble(geometry: Geometry[PlanT, ResultT], case: Case, *, grid: int, realizations: int, seed: int,
                 grid_field: str = "grid", fields_dir: str | Path | None = None, contact_tol: float = 1e-8,
                 flow_method: FlowMethod = "auto", progress: Callable[[int], None] | None = None,
                 memory_limit: float | None = None,
                 runner: Callable[[list[Any]], Iterable[TaskRecord]] | None = None, device: str = "cpu") -> ResultT:
    """Run ``geometry``'s simulation of ``case`` (module docstring): check, prepare, run the tasks, aggregate.

    ``grid`` N (even, >= 16; ``grid_field`` names it in messages), ``realizations`` R, ``seed``: realisation r
    draws its surface from ``numpy.random.default_rng([seed, r])``. ``fields_dir``: the tasks write their
    field files (npz) there, staged until all are written. ``progress`` is called with the number of finished
    solves (without a runner). ``runner`` runs the tasks and returns their records in the order given (None:
    one after the other in this process); the records are aggregated in realisation order, so the numbers
    do not depend on the runner. ``device``: where the tasks synthesize their surfaces and solve the contact,
    ``"cpu"`` (NumPy) or ``"cuda"`` (CuPy on a GPU, :mod:`sealeak.numerics._device`; its free memory is checked
    here, before any work, against the larger of the contact's and the flow's needs), and where the flows' AMG
    iterations run (:func:`sealeak.numerics.solve_flow`, ``device``); the rest of the flow runs on the host.
    """
    grid = grid_number(grid_field, grid)
    realizations = whole_number("realizations", realizations, 1, MAX_REALIZATIONS)
    seed = seed_number("seed", seed)
    # the flow's CG runs on the device too, after the contact: the larger of the two needs, before any work
    numerics.require_device_memory(max(numerics.device_memory_bytes(grid), numerics.flow_memory_bytes(grid, "amg")),
                                   f"the {grid}x{grid} synthesis, contact and flow", device)
    if not getattr(runner, "checks_memory", False):  # a runner of make_runner checks each task where it runs
        geometry.check_memory(grid, memory_limit)
        numerics.check_memory(grid, "flow", available=memory_limit)
        if case.gas is not None:
            numerics.require_memory(numerics.gas_flow_memory_bytes(grid), f"the {grid}x{grid} gas flow problem",
                                    memory_limit)
    notes: list[NoteLike] = []
    if case.coupled:  # the simulated contact is pressed by P0 alone: compare with the theory without fluid pressure
        case = replace(case, fluid_pressure="ignored")
        notes.append(Note("fluid_pressure_not_simulated"))
    plan = geometry.prepare(case, grid, grid_field, notes, progress)
    with StagedFolder(fields_dir) as fields:
        common = RunSettings(grid=grid, seed=seed, e_star=case.e_star, viscosity=case.fluid.viscosity,
                             pressure_difference=float(case.pressure_difference), gas=case.gas, flow_method=flow_method,
                             contact_tol=contact_tol, memory_limit=memory_limit, device=device,
                             fields_stage=None if fields.stage is None else str(fields.stage),
                             fields_target=None if fields.target is None else str(fields.target))
        tasks = geometry.tasks(plan, common, realizations)
        done = [t.run(progress=progress) for t in tasks] if runner is None else list(runner(tasks))
    return geometry.aggregate(plan, Records(done, realizations, grid, seed), notes)


# ---------------------------------------------------------------- the spectrum
def resolved_spectrum_cut(grid: int, size: float) -> float:
    """Highest wavevector an N-point grid of side ``size`` resolves with 4 points per wavelength (1/m)."""
    return 2.0 * np.pi * grid / (POINTS_PER_WAVELENGTH * size)


def cut_spectrum(spectrum: PowerSpectrum, grid: int, size: float, grid_field: str, theory: str,
                 q_low: float | None = None) -> tuple[PowerSpectrum, float | None, list[Note]]:
    """The spectrum a ``grid`` × ``grid`` domain of side ``size`` (m) resolves, where it was cut, and notes.

    Wavevectors above :func:`resolved_spectrum_cut` are cut, and, with ``q_low`` (1/m), those below it (the
    band's waviness); ``theory`` names what the simulation is compared with (it uses the same cut spectrum).
    A grid that resolves nothing of the band is refused (an InputError naming ``grid_field``).
    """
    q_cut = resolved_spectrum_cut(grid, size)
    lowest = spectrum.q_min if q_low is None else max(spectrum.q_min, q_low)
    if q_cut <= lowest:
        raise InputError(grid_field, grid, f"resolves q only up to {q_cut:.4g} 1/m, below the spectrum's band "
                                           f"({lowest:.4g} .. {spectrum.q_max:.4g} 1/m): use a larger grid")
    notes = []
    cut_at = q_cut if spectrum.q_max > q_cut else None
    if cut_at is not None:
        notes.append(Note("spectrum_cut_by_grid", {"grid": grid, "q_cut": float(q_cut), "q1": float(spectrum.q_max),
                                                   "points_per_wavelength": POINTS_PER_WAVELENGTH, "theory": theory}))
    low_cut = q_low if q_low is not None and spectrum.q_min < q_low else None
    if low_cut is not None:
        notes.append(Note("waviness_left_out", {"q0": float(low_cut)}))
    if not notes:
        return spectrum, None, notes
    cut = spectrum.truncated(low_cut, cut_at)
    # the last note also says how much of h_rms (m) the cut leaves
    notes[-1] = Note(notes[-1].code, {**notes[-1].values, "h_rms": (float(spectrum.h_rms), float(cut.h_rms))})
    return cut, cut_at, notes


def spectrum_text(spectrum: PowerSpectrum, case: Case) -> str:
    """The simulated spectrum for the result: its label, h_rms and band."""
    return (f"{spectrum.label or case.spectrum_note}: h_rms = {spectrum.h_rms * 1e6:.4g} µm over "
            f"q = {spectrum.q_min:.4g} .. {spectrum.q_max:.4g} 1/m")


# ---------------------------------------------------------------- the tasks
def gas_identity(gas: GasConditions | None) -> dict[str, Any] | None:
    """A gas case's conditions as plain JSON values for a store's manifest (None for a liquid)."""
    if gas is None:
        return None
    return {"name": gas.gas.name, "temperature": float(gas.temperature), "upstream_pressure": float(gas.upstream_pressure),
            "downstream_pressure": float(gas.downstream_pressure), "rarefaction": gas.rarefaction}


S = TypeVar("S", bound="TaskSpec")


@dataclass(frozen=True, kw_only=True)
class RunSettings:
    """What :func:`run_ensemble` gives every task of a run: :class:`TaskSpec`'s fields but the spectrum and the
    domain's size, which the geometry's plan gives (SI units)."""

    grid: int
    seed: int
    e_star: float
    viscosity: float
    pressure_difference: float
    gas: Any
    flow_method: FlowMethod
    contact_tol: float
    memory_limit: float | None = None
    fields_stage: str | None = None
    fields_target: str | None = None
    device: str = "cpu"

    def spec(self, cls: type[S], **own: Any) -> S:
        """A task spec of type ``cls`` with these settings and the geometry's ``own`` fields."""
        return cls(**{f.name: getattr(self, f.name) for f in fields(RunSettings)}, **own)


@dataclass(frozen=True, kw_only=True)
class TaskSpec(RunSettings):
    """What every task of a run needs whatever the geometry, in SI units (shared by all tasks of the run).

    ``spectrum`` is the (possibly cut) C(q) the surfaces are drawn from, ``grid`` N and ``size`` (m) the
    square domain, ``seed`` the run's seed, ``e_star`` E* (Pa), ``viscosity`` η (Pa·s), ``pressure_difference``
    ΔP (Pa), ``gas`` a gas case's conditions (None: a liquid). ``fields_stage`` is the folder the tasks write
    their field files into (None: none), ``fields_store`` the task store folder whose ``fields.zarr`` they
    write their fields into (:mod:`sealeak.io.fieldstore`; None: none), ``fft_workers`` the FFT threads of
    each task (-1: all cores; 1 on a cluster, whose worker processes share the cores). None of these
    changes a number; nor does ``device`` (``"cpu"`` or ``"cuda"``: where the surfaces are synthesized, the
    contact solved, :meth:`on_device`, and the flows' CG iterations run) beyond FFT round-off and the flow's
    tolerance. ``capillary``: each sweep also finds its gap fields' critical constrictions (a liquid with a
    contact angle, docs/theory.md §12.4). A geometry's spec adds its own fields and :meth:`geometry_identity`.
    """

    spectrum: Any
    size: float
    fft_workers: int = -1
    fields_store: str | None = None
    capillary: bool = False

    def geometry_identity(self) -> dict[str, Any]:
        """The geometry's own inputs of the tasks, as plain JSON values."""
        return {}

    def identity(self) -> dict[str, Any]:
        """The inputs the tasks' numbers depend on, as plain JSON values (floats exact by ``repr``).

        The store's manifest keeps a hash of it (:mod:`sealeak.cases.ensemble`): ``spectrum`` (the nodes of
        C(q)), ``grid``, ``seed`` and ``case`` (everything else that enters a task).
        """
        return {
            "spectrum": {"q": [float(x) for x in self.spectrum.q], "C": [float(x) for x in self.spectrum.C]},
            "grid": int(self.grid),
            "seed": int(self.seed),
            "case": {"size": float(self.size), "e_star": float(self.e_star), "viscosity": float(self.viscosity),
                     "pressure_difference": float(self.pressure_difference), "flow_method": self.flow_method,
                     "contact_tol": float(self.contact_tol), "gas": gas_identity(self.gas)} | self.geometry_identity()
                    | ({"capillary": True} if self.capillary else {}),
        }

    def surface(self, r: int) -> FloatArray:
        """Realisation ``r``'s heights (m): ``synthesize`` with the seed sequence (seed, r) (docs/theory.md §6.1),
        on the run's device (drawn on the host, so the same on every device)."""
        return numerics.synthesize(self.spectrum, self.grid, self.size, seed=np.random.default_rng([int(self.seed), r]),
                                   workers=self.fft_workers, xp=numerics.array_namespace_for(self.device))

    def on_device(self, heights: Any) -> Any:
        """``heights`` as an array of the run's device (NumPy for ``"cpu"``: itself, no copy)."""
        return numerics.array_namespace_for(self.device).asarray(heights)

    def field_attributes(self, task: str, r: int) -> dict[str, Any]:
        """The attributes of a task's group of fields (JSON values; lengths in m, E* in Pa)."""
        return {"task": task, "realization": int(r), "seed": int(self.seed), "grid": int(self.grid),
                "size": float(self.size), "period": float(self.size), "length_units": "m", "e_star": float(self.e_star),
                "e_star_units": "Pa", "software": f"sealeak {__version__}"}


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


def pack_mask(mask: NDArray[np.bool_]) -> dict[str, Any]:
    """A boolean map as plain JSON values: its shape and its bits (``numpy.packbits``) in base64."""
    return {"shape": list(mask.shape), "bits": base64.b64encode(np.packbits(mask, axis=None).tobytes()).decode("ascii")}


def unpack_mask(packed: dict[str, Any]) -> NDArray[np.bool_]:
    """The boolean map :func:`pack_mask` packed."""
    shape = tuple(int(n) for n in packed["shape"])
    bits = np.frombuffer(base64.b64decode(packed["bits"]), dtype=np.uint8)
    return np.unpackbits(bits, count=int(np.prod(shape))).astype(bool).reshape(shape)


#: A realisation-0 contact map as plain JSON values (:func:`pack_mask`).
PackedMask = dict[str, Any]


@dataclass(frozen=True, kw_only=True)
class TaskRecord:
    """What one task returns: plain JSON values (lists of floats, bools, ints, strings), in SI units.

    Each geometry's record type names its ``KIND`` (the task's kind) and is found by it when a store's record
    is read back (:meth:`from_mapping`); :meth:`to_mapping` is what a store keeps (fields that are None, a
    liquid's gas columns or a record without fields, are left out).
    """

    KIND: ClassVar[str] = ""
    _TYPES: ClassVar[dict[str, type[TaskRecord]]] = {}

    realization: int

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.KIND:
            TaskRecord._TYPES[cls.KIND] = cls

    def to_mapping(self) -> dict[str, Any]:
        """The record as plain JSON values (its kind, then its fields but those that are None)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        return {"kind": self.KIND} | {k: v for k, v in values.items() if v is not None}

    @staticmethod
    def from_mapping(mapping: Any) -> TaskRecord:
        """The record :meth:`to_mapping` wrote (its type from ``"kind"``); ValueError if it is not one."""
        kind = TaskRecord._TYPES.get(str(mapping.get("kind"))) if isinstance(mapping, dict) else None
        if kind is None:
            raise ValueError(f"not a task record: {type(mapping).__name__}")
        names = {f.name for f in fields(kind)}
        try:
            return kind(**{k: v for k, v in mapping.items() if k in names})
        except TypeError as exc:  # a field is missing
            raise ValueError(str(exc)) from None


@dataclass(frozen=True, kw_only=True)
class FlowRecord(TaskRecord):
    """The scalars every geometry's sweep records per load (:class:`FlowLog`), and where its fields went.

    ``fields``: the store group's name and the SHA-256 of each array (:meth:`sealeak.io.fieldstore.TaskFields.commit`;
    None without a store).
    """

    relative_contact_area: list[float] = quantity("1", "relative contact area")
    percolates: list[bool] = quantity("1", "the fluid crosses the domain")
    leak_rate: list[float] = quantity("m^3/s", "leak rate of the seal")
    contact_maps: list[PackedMask] = field(default_factory=list)  # realisation 0's, by load
    leak_rate_pv: list[float] | None = quantity("Pa*m^3/s", "pV throughput of the seal (a gas)", default=None)
    leak_rate_pv_no_slip: list[float] | None = quantity("Pa*m^3/s", "pV throughput without rarefaction (a gas)",
                                                        default=None)
    gas_iterations: list[int] | None = quantity("1", "fixed-point iterations of the gas flow (a gas)", default=None)
    critical_gap: list[float] | None = quantity(
        "m", "gap of the narrowest constriction on the widest path across (a liquid with a contact angle)", default=None)
    fields: dict[str, Any] | None = None


R = TypeVar("R", bound=TaskRecord)
F = TypeVar("F", bound=FlowRecord)


@dataclass(kw_only=True)
class FlowLog:
    """A task's flow scalars as its loads are solved (:meth:`add`), made into its record by :meth:`record`."""

    gas: bool
    capillary: bool = False
    area: list[float] = field(default_factory=list)
    percolates: list[bool] = field(default_factory=list)
    leak_rate: list[float] = field(default_factory=list)
    pv: list[float] = field(default_factory=list)
    pv_no_slip: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    contact_maps: list[PackedMask] = field(default_factory=list)
    critical: list[float] = field(default_factory=list)

    def add(self, spec: TaskSpec, r: int, res: Any, scale: float, area: float) -> None:
        """The flow through one contact solution's gap field (and a gas's), and its relative contact ``area``.

        Leak rates are ``scale`` times the domain's (m³/s; Pa·m³/s for the gas); realisation 0 also keeps its
        contact map (packed).
        """
        self.area.append(float(area))
        flow = numerics.solve_flow(res.gap, spec.size, spec.viscosity, spec.pressure_difference, contact=res.contact,
                                   method=spec.flow_method, device=spec.device)
        self.percolates.append(bool(flow.percolates))
        self.leak_rate.append(float(scale * flow.flux))
        gas = spec.gas
        if gas is not None:
            gflow = numerics.solve_gas_flow(res.gap, spec.size, gas.gas, gas.upstream_pressure, gas.downstream_pressure,
                                            contact=res.contact, model=gas.rarefaction, method=spec.flow_method,
                                            memory_limit=spec.memory_limit, device=spec.device)
            self.pv.append(float(scale * gflow.throughput))
            self.pv_no_slip.append(float(scale * gflow.throughput_no_slip))
            self.iterations.append(int(gflow.iterations))
        if self.capillary:  # the narrowest gap of the widest path across (docs/theory.md eq. 12.5)
            self.critical.append(numerics.critical_constriction(res.gap, ~np.asarray(res.contact, dtype=bool)))
        if r == 0:
            self.contact_maps.append(pack_mask(np.asarray(res.contact, dtype=bool)))

    def record(self, cls: type[F], r: int, kept: dict[str, Any] | None, **own: Any) -> F:
        """Realisation ``r``'s record of type ``cls``: these flows, the committed fields ``kept`` and ``own`` fields."""
        return cls(realization=r, relative_contact_area=self.area, percolates=self.percolates, leak_rate=self.leak_rate,
                   contact_maps=self.contact_maps, leak_rate_pv=self.pv if self.gas else None,
                   leak_rate_pv_no_slip=self.pv_no_slip if self.gas else None,
                   gas_iterations=self.iterations if self.gas else None,
                   critical_gap=self.critical if self.capillary else None, fields=kept, **own)


def keep_load(spec: TaskSpec, kept: TaskFields | None, r: int, i: int, h: FloatArray, res: Any,
              progress: Callable[[int], None] | None, **extra: Any) -> None:
    """Load ``i``'s fields (a field file, the store) of realisation ``r``, and one step of progress (``h`` and
    ``res`` on the host)."""
    if spec.fields_stage is not None:
        _write_fields(spec, f"r{r}-p{i}.npz", height=h, gap=res.gap, pressure=res.pressure, size=np.float64(spec.size),
                      **extra)
    if kept is not None:
        kept.put(i, res.gap, res.pressure)
    if progress is not None:
        progress(1)


def with_fields(spec: TaskSpec, r: int, h: FloatArray, sweep: Callable[[TaskFields | None], None],
                *, load_name: str, loads: Any, load_unit: str, attributes: dict[str, Any]) -> dict[str, Any] | None:
    """Run ``sweep`` with the store's group ``r<r>`` of the task's fields open (None without a store).

    The heights go in first; the group is committed when the sweep has finished and removed if it fails.
    Returns the commit (the group's name and the SHA-256 of each array; None without a store).
    """
    kept = None
    if spec.fields_store is not None:
        kept = TaskFields(spec.fields_store, f"r{r}", grid=spec.grid, size=spec.size, period=spec.size,
                          load_name=load_name, loads=loads, load_unit=load_unit, attributes=attributes)
    try:
        if kept is not None:
            kept.put_height(h)
        sweep(kept)
        return kept.commit() if kept is not None else None
    except BaseException:
        if kept is not None:
            kept.abort()
        raise


def _write_fields(spec: TaskSpec, name: str, **arrays: Any) -> None:
    """One field file into the run's staging folder (moved into the target when the run has finished).

    A Ctrl-C during the write is held back until the file is complete (:func:`_interrupt_after`): an interrupted
    ``savez`` leaves NumPy's zip writer holding the closed file, and its clean-up later printed "Exception ignored
    ... seek of closed file" after the run's own message.
    """
    assert spec.fields_stage is not None
    try:
        with _interrupt_after(), open(Path(spec.fields_stage) / name, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    except OSError as exc:
        raise OutputWriteError(Path(spec.fields_target or spec.fields_stage) / name, exc) from None


@contextmanager
def _interrupt_after() -> Iterator[None]:
    """Hold a SIGINT (Ctrl-C) back while the block runs and raise it as KeyboardInterrupt when the block has
    finished. Only in the main thread with Python's own SIGINT handler in place (elsewhere no KeyboardInterrupt
    can arrive, or someone else handles it): there nothing changes."""
    if threading.current_thread() is not threading.main_thread() or \
            signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        yield
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, _frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if caught:  # also when the block failed: the user's Ctrl-C comes first
            raise KeyboardInterrupt


# ---------------------------------------------------------------- aggregation
class Records:
    """The tasks' records in the order of the tasks (realisation order), and the run's realisations R, grid N
    and seed."""

    def __init__(self, records: Iterable[TaskRecord], realizations: int, grid: int, seed: int) -> None:
        self.records = list(records)
        self.realizations = int(realizations)
        self.grid = int(grid)
        self.seed = int(seed)

    def of(self, cls: type[R]) -> list[R]:
        """The records of type ``cls`` (their tasks' kind)."""
        return [rec for rec in self.records if isinstance(rec, cls)]

    def stack(self, cls: type[R], value: Callable[[R], Any], n: int, dtype: Any = float) -> NDArray[Any]:
        """``value`` of the ``cls`` records as an [R, n] array (zeros where no task gave it)."""
        out = np.zeros((self.realizations, n), dtype=dtype)
        for rec in self.of(cls):
            out[rec.realization] = value(rec)
        return out

    def first(self, cls: type[R]) -> R | None:
        """Realisation 0's record of type ``cls`` (None if there is none)."""
        return next((rec for rec in self.of(cls) if rec.realization == 0), None)


@dataclass(frozen=True, kw_only=True)
class Flows:
    """What every geometry's sweep records, per realisation and load ([R, n] arrays; :class:`FlowLog`).

    ``area`` the relative contact area, ``percolates``, ``leak_rate`` the seal's (m³/s), for a gas ``pv`` and
    ``pv_no_slip`` its pV throughputs (Pa·m³/s, zeros for a liquid) and ``iterations``; ``contact_maps`` those
    of realisation 0 by load.
    """

    area: FloatArray
    percolates: NDArray[np.bool_]
    leak_rate: FloatArray
    pv: FloatArray
    pv_no_slip: FloatArray
    iterations: NDArray[np.int64]
    contact_maps: dict[int, NDArray[np.bool_]] = field(default_factory=dict)

    @classmethod
    def of(cls, records: Records, kind: type[FlowRecord], n: int) -> Flows:
        """The flows of the ``kind`` records of ``records`` at ``n`` loads (a liquid's gas columns zeros)."""
        first = records.first(kind)
        return cls(area=records.stack(kind, lambda rec: rec.relative_contact_area, n),
                   percolates=records.stack(kind, lambda rec: rec.percolates, n, bool),
                   leak_rate=records.stack(kind, lambda rec: rec.leak_rate, n),
                   pv=records.stack(kind, lambda rec: rec.leak_rate_pv or 0.0, n),
                   pv_no_slip=records.stack(kind, lambda rec: rec.leak_rate_pv_no_slip or 0.0, n),
                   iterations=records.stack(kind, lambda rec: rec.gas_iterations or 0, n, np.int64),
                   contact_maps={} if first is None else {i: unpack_mask(m) for i, m in enumerate(first.contact_maps)})


@dataclass(frozen=True, kw_only=True)
class SimulationCapillarity:
    """A liquid with a contact angle in ``simulate`` (docs/theory.md §12.4): per load, the capillary entry pressure of
    each realisation's critical constriction (the narrowest gap on the widest path across its gap field) and the
    realisations it holds. The simulated leak rates are the flow without capillarity (α compares flows)."""

    capillary_entry_pressure: FloatArray = quantity(
        "Pa", "entry pressure −γ(cos θ_r + cos θ_s)/u of each realisation's critical constriction u, mean over the "
              "realisations the fluid crosses")
    capillary_entry_pressure_std: FloatArray = quantity("Pa", "standard deviation of that entry pressure")
    capillary_entry_pressure_critical_junction: FloatArray = quantity(
        "Pa", "the entry pressure at the theory's critical gap u_c (an O-ring: at its peak contact pressure)")
    held_fraction: FloatArray = quantity("1", "fraction of realisations the fluid crosses but ΔP is below their entry "
                                              "pressure: held, Q = 0")
    held_by_capillarity: NDArray[np.bool_] = quantity(
        "1", "the fluid crosses some realisation, and capillarity holds it in every one it crosses")


def capillary_part(case: Case, records: Records, kind: type[FlowRecord], u_c: FloatArray, percolates: NDArray[np.bool_]
                   ) -> tuple[SimulationCapillarity | None, dict[str, Any]]:
    """Each realisation's entry pressure p_e = −γ(cos θ_r + cos θ_s)/u at its critical constriction u (Pa, [R, n]) from
    the ``kind`` records, where it holds the liquid (ΔP < p_e, docs/theory.md eq. 12.3), summed up per load beside
    p_e at the theory's gap ``u_c`` (m); (None, {}) without a contact angle."""
    wetting = case.capillarity
    if wetting is None:
        return None, {}
    n = u_c.size
    gap = records.stack(kind, lambda rec: rec.critical_gap if rec.critical_gap is not None else [np.nan] * n, n)
    entry = wetting.entry_pressure(np.where(percolates & (gap > 0), gap, np.nan))
    held = percolates & (case.pressure_difference < entry)
    entry_m, entry_s = mean_std(entry)
    return (SimulationCapillarity(
        capillary_entry_pressure=entry_m, capillary_entry_pressure_std=entry_s,
        capillary_entry_pressure_critical_junction=wetting.entry_pressure(u_c), held_fraction=held.mean(axis=0),
        held_by_capillarity=percolates.any(axis=0) & (held.sum(axis=0) == percolates.sum(axis=0))),
            {"capillary_entry_pressure": entry, "held_by_capillarity": held})


def mean_std(x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Mean and standard deviation (ddof = 1) over axis 0, ignoring NaN; std NaN for fewer than two values."""
    x = np.asarray(x, dtype=float)
    ok = np.isfinite(x)
    n = ok.sum(axis=0)
    mean = np.where(n > 0, np.where(ok, x, 0.0).sum(axis=0) / np.maximum(n, 1), np.nan)
    dev = np.where(ok, x - mean, 0.0)
    var = np.where(n > 1, (dev**2).sum(axis=0) / np.maximum(n - 1, 1), 0.0)
    return mean, np.where(n > 1, np.sqrt(var), np.nan)


def ratio(perc: NDArray[np.bool_], q: FloatArray, theory: FloatArray) -> FloatArray:
    """q/theory per realisation and pressure where the realisation percolates and the theory has a leak; else NaN."""
    ok = perc & (np.isfinite(theory) & (theory > 0))[None, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(ok, q / np.where(ok, theory[None, :], 1.0), np.nan)


@dataclass(frozen=True, kw_only=True)
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
    knudsen_critical_junction: FloatArray = quantity("1", "Knudsen number λ/u_c at the mean pressure",
                                                     key="knudsen_number")
    regime_critical_junction: tuple[str, ...] = quantity("", "flow regime at u_c", key="flow_regime")
    throughput: FloatArray = quantity("Pa*m^3/s", "pV throughput Q_pV, counted at T", key="leak_rate_pv")
    throughput_std: FloatArray = quantity("Pa*m^3/s", "standard deviation of Q_pV", key="leak_rate_pv_std")
    throughput_mbar_l_s: FloatArray = quantity("mbar*l/s", "Q_pV in mbar·l/s", key="leak_rate_mbar_l_s", init=False)
    mass_flow: FloatArray = quantity("kg/s", "mass flow Q_pV/(R_s T)", key="leak_rate_mass")
    mass_flow_std: FloatArray = quantity("kg/s", "standard deviation of the mass flow", key="leak_rate_mass_std")
    molar_flow: FloatArray = quantity("mol/s", "molar flow Q_pV/(R T)", key="leak_rate_molar")
    slip_gain: FloatArray = quantity("1", "Q_pV over the same flow without rarefaction")
    throughput_critical_junction: FloatArray = quantity("Pa*m^3/s", "the theory's gas leak with α = 1",
                                                        key="leak_rate_pv_critical_junction")
    alpha: FloatArray = quantity("1", "α_gas = Q_pV over the theory's", key="alpha_gas")
    alpha_std: FloatArray = quantity("1", "standard deviation of α_gas", key="alpha_gas_std")
    iterations: NDArray[np.int64] = quantity("1", "most fixed-point iterations of any realisation", key="gas_iterations")

    def __post_init__(self) -> None:
        object.__setattr__(self, "throughput_mbar_l_s", to_mbar_l_per_s(self.throughput))


def gas_part(case: Case, q_theory: FloatArray, u_c: FloatArray, length: FloatArray,
             flows: Flows) -> tuple[GasSimulation | None, dict[str, NDArray[Any]]]:
    """A gas case's :class:`GasSimulation` and its per-realisation arrays (None and {} for a liquid).

    The theory is ``predict``'s (:func:`sealeak.cases.gas.gas_rows`): the channel of conductance
    K = Q/ΔP of the liquid theory ``q_theory`` (α = 1, the gas's viscosity; m³/s) whose gap is ``u_c`` (m),
    a slit of length ``length`` λ_c (m; the kinetic model's free-molecular cap, NaN: an infinite slit), integrated
    along the pressure drop with the case's rarefaction model (docs/theory.md §11.4, §11.5).
    """
    gas = case.gas
    if gas is None:
        return None, {}
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(np.isfinite(q_theory) & (q_theory > 0), q_theory / case.pressure_difference, 0.0)
    leaks = gas_rows(case, k, np.where(np.isfinite(u_c), u_c, np.nan), length, helium=False).leaks or ()
    theory = np.array([g.throughput if g is not None else np.nan for g in leaks])
    perc, pv = flows.percolates, flows.pv
    pv_m, pv_s = mean_std(pv)
    rst = gas.gas.specific_gas_constant * gas.temperature
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = np.where(perc, pv / np.where(perc, flows.pv_no_slip, 1.0), np.nan)
    alpha_r = ratio(perc, pv, theory)
    alpha_m, alpha_s = mean_std(alpha_r)
    result = GasSimulation(
        gas_name=gas.gas.name, temperature=gas.temperature, upstream_pressure=gas.upstream_pressure,
        downstream_pressure=gas.downstream_pressure, rarefaction=gas.rarefaction, throughput=pv_m, throughput_std=pv_s,
        mass_flow=pv_m / rst, mass_flow_std=pv_s / rst, molar_flow=pv_m / (MOLAR_GAS_CONSTANT * gas.temperature),
        slip_gain=mean_std(gain)[0], throughput_critical_junction=theory,
        knudsen_critical_junction=np.array([g.knudsen_mean if g is not None else np.nan for g in leaks]),
        regime_critical_junction=tuple(g.regime if g is not None else "" for g in leaks), alpha=alpha_m,
        alpha_std=alpha_s, iterations=flows.iterations.max(axis=0))
    return result, {"leak_rate_pv": pv, "leak_rate_pv_no_slip": flows.pv_no_slip, "gas_iterations": flows.iterations,
                    "alpha_gas": alpha_r}


# ---------------------------------------------------------------- field files
class StagedFolder:
    """Field files written into a hidden folder inside the target and moved in only when all are written.

    An interrupted or failed run (Ctrl-C, an error) removes the staging folder, and the target
    folder itself if this run created it, so no field file of an unfinished run is left behind.
    ``folder=None`` writes nothing.
    """

    def __init__(self, folder: str | Path | None) -> None:
        self.target = Path(folder) if folder is not None else None
        self.created: list[Path] = []
        self.stage: Path | None = None

    def __enter__(self) -> StagedFolder:
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

    def __exit__(self, exc_type: object, exc: object, tb: object) -> None:
        if self.stage is None or self.target is None:
            return
        if exc_type is None:
            moved: list[Path] = []
            parts = sorted(self.stage.iterdir())
            try:
                for part in parts:  # only regular files (or nothing) may be replaced, checked before any move
                    check_replaceable(self.target / part.name)
            except BaseException:
                self._clean()
                raise
            try:
                for part in parts:
                    os.replace(part, self.target / part.name)
                    moved.append(self.target / part.name)
            except BaseException as err:
                for m in moved:
                    m.unlink(missing_ok=True)
                self._clean()
                if isinstance(err, OSError):
                    raise OutputWriteError(self.target, err) from None
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
