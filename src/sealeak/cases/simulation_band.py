"""Numerically exact leak rate of an O-ring: a smooth cylinder on a rough surface, then the flow across its band.

The series-resistance theory of a band seal (docs/theory.md §10.1) assumes that every strip dx of
the band conducts like a uniform seal at its nominal pressure p(x). This pipeline checks that
assumption for an O-ring (docs/theory.md §10.4):

1. the domain: W = :data:`DOMAIN_WIDTHS` × the widest contact band across x (free edges, zero-padded
   Green's function), one period Ly = W along the seal line, N × N square cells;
2. R random surfaces on that square with the case's C(q) (:func:`sealeak.numerics.synthesize`,
   realisation r seeded with (seed, r) as in :mod:`.simulation`), cut to the wavevectors the grid
   resolves (4 cells per wavelength) and to q >= q0 of the widest band (longer wavelengths are the
   band's waviness, not its roughness, in the theory it is compared with);
3. at each compression, the contact of the cylinder of radius d/2 carrying the case's force per
   unit length f (:func:`sealeak.numerics.solve_band_contact`, warm-started along increasing f);
4. the Reynolds flow across the domain from x = 0 to x = W (:func:`sealeak.numerics.solve_flow`), so
   Q_num = faces · (Ly_seal / W) · Q_W, with Ly_seal = π × the mean diameter;
5. the series-resistance prediction Q_sr of the critical-junction theory with α = 1
   (:func:`sealeak.cases.band.run_band`) for the same cut spectrum and the nominal profile the
   simulation has: the Hertz semi-ellipse of the same f (half-width b = √(4fR/(πE*)),
   p_max = 2f/(πb)); α = Q_num / Q_sr is the α of a real O-ring;
6. a smooth-cylinder check: the same solver without roughness, its contact width and peak
   pressure against Hertz (reported; off by more than :data:`HERTZ_TOL` is flagged);
7. for a gas case, also the isothermal gas flow across the band through each gap field, P_a at
   x = 0 and P_b at x = W, with the case's rarefaction model (:func:`sealeak.numerics.solve_gas_flow`:
   the p² problem, with slip a checked fixed point), scaled to the seal line as Q_num; beside it the
   series-resistance gas leak of the same theory (K = Q_sr/ΔP with α = 1 and the gas's viscosity,
   the gap u_c at the peak pressure, the same rarefaction model, as ``predict`` computes a band
   seal's gas leak, docs/theory.md §11.9) and α_gas = Q_pV,num/Q_pV,sr (docs/theory.md §11.10).
   The liquid columns stay: for a gas they are the incompressible formula with the gas's viscosity.

Steps 2–4 and 7 of each realisation form one independent task (:func:`band_tasks`, :func:`run_band_task`:
``band-r<r>`` draws surface r, presses the cylinder at every load and solves the flows), returning its
scalars only; a runner (:func:`sealeak.cases.ensemble.make_runner`) runs them in this process or on Dask,
keeps them in a store and, if asked, has each write its fields there. The statistics are formed in
realisation order afterwards, so the numbers do not depend on the runner (docs/theory.md §6.7).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import numerics
from .._version import __version__
from ..errors import InputError
from ..io.fieldstore import TaskFields
from ..numerics.synthesis import synthesize
from ..physics.profile import PressureProfile
from .band import run_band
from .limits import MAX_REALIZATIONS, whole_number
from .model import Case
from .simulation import (
    JUNCTION_CELLS,
    POINTS_PER_WAVELENGTH,
    FlowMethod,
    GasSimulation,
    _gas_statistics,
    _mean_std,
    _ratio,
    _StagedFolder,
    _write_fields,
    gas_identity,
    pack_mask,
    resolved_spectrum_cut,
    task_memory_bytes,
    unpack_mask,
)

__all__ = ["BandSimulationResult", "simulate_band", "DOMAIN_WIDTHS", "HERTZ_TOL", "BandSpec", "BandTask", "band_tasks",
           "run_band_task"]

FloatArray = NDArray[np.float64]

#: Width of the domain across the band, in contact widths of the widest band (free edges beyond).
DOMAIN_WIDTHS = 2.5
#: λc at most this many cells: the junction sits at the end of the resolved spectrum (4 cells per wavelength).
AT_END_CELLS = 1.05 * POINTS_PER_WAVELENGTH
#: Relative agreement with Hertz the smooth-cylinder check must reach (width and peak pressure).
HERTZ_TOL = 0.01


@dataclass(frozen=True)
class BandSimulationResult:
    """An O-ring's numerically exact leak rate per compression (SI units; arrays have one entry per load).

    Attributes
    ----------
    load_name, loads
        "compression" and the compressions ε (1), in increasing order of force.
    force_per_length
        f (N per m of seal line) at each compression, from the case's O-ring contact.
    model_contact_width, model_max_pressure
        Contact width (m) and peak pressure (Pa) of the case's O-ring relation (Hertz or Lindley).
    hertz_contact_width, hertz_max_pressure
        2b and p_max of Hertz line contact with the same f, R = d/2 and E* (m, Pa).
    smooth_contact_width, smooth_max_pressure
        The same from the solver without roughness (m, Pa; width from the p² edges, to a fraction of a cell).
    smooth_width_error, smooth_pressure_error
        Their relative deviation from Hertz (1).
    contact_width, contact_width_std
        Extent across x of the rough contact, first to last column with contact (m), over realisations.
    relative_contact_area, relative_contact_area_std
        Fraction of the Hertz band |x - x_c| < b in contact (1).
    percolating_fraction
        Fraction of realisations in which fluid crosses the band.
    leak_rate, leak_rate_std
        Q_num (m³/s): mean and standard deviation (ddof = 1) over realisations, blocked ones as 0.
    leak_rate_series_resistance
        Q_sr: the critical-junction series-resistance prediction with α = 1 for the same spectrum
        and the Hertz profile of the same f (m³/s; NaN where the band has no channel).
    alpha, alpha_std
        α = Q_num/Q_sr over the percolating realisations (NaN where none percolates or Q_sr is missing).
    junction_cells
        Grid cells across the theory's critical wavelength λc where the pressure is highest.
    size, period
        Domain across the band W and along the seal line Ly (m; Ly = W).
    seal_length, faces, radius
        Seal line length (m), contact faces in parallel, cylinder radius d/2 (m).
    gas
        A gas case's leak across the band (None for a liquid): pV throughput Q_pV (Pa·m³/s), mass and
        molar flow of the seal, the series-resistance gas leak with α = 1 (``throughput_critical_junction``:
        gap u_c at the peak pressure, the case's rarefaction model), Kn and regime at that gap and the
        mean pressure, and α_gas = Q_pV/Q_pV,sr (docs/theory.md §11.9, §11.10). The other leak rates
        are then the incompressible formula with the gas's viscosity.
    """

    load_name: str
    loads: FloatArray
    force_per_length: FloatArray
    model_contact_width: FloatArray
    model_max_pressure: FloatArray
    hertz_contact_width: FloatArray
    hertz_max_pressure: FloatArray
    smooth_contact_width: FloatArray
    smooth_max_pressure: FloatArray
    smooth_width_error: FloatArray
    smooth_pressure_error: FloatArray
    contact_width: FloatArray
    contact_width_std: FloatArray
    relative_contact_area: FloatArray
    relative_contact_area_std: FloatArray
    percolating_fraction: FloatArray
    leak_rate: FloatArray
    leak_rate_std: FloatArray
    leak_rate_series_resistance: FloatArray
    alpha: FloatArray
    alpha_std: FloatArray
    junction_cells: FloatArray
    pressure_difference: float
    grid: int
    realizations: int
    seed: int
    size: float
    period: float
    seal_length: float
    faces: int
    radius: float
    q_cut: float | None
    q_low: float
    notes: tuple[str, ...] = ()
    spectrum_note: str = ""
    per_realization: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    #: realisation 0: contact mask [x, y] and the pressure averaged along the seal line p̄(x) (Pa) per load
    contact_maps: dict[int, NDArray[np.bool_]] = field(default_factory=dict, repr=False)
    line_pressure: dict[int, FloatArray] = field(default_factory=dict, repr=False)
    smooth_line_pressure: dict[int, FloatArray] = field(default_factory=dict, repr=False)
    gas: GasSimulation | None = None

    @property
    def x(self) -> FloatArray:
        """Cell centres across the band (m), 0 at the inlet edge of the domain."""
        return (np.arange(self.grid, dtype=np.float64) + 0.5) * (self.size / self.grid)

    @property
    def smooth_check_passed(self) -> bool:
        """Whether the smooth cylinder met Hertz to :data:`HERTZ_TOL` at every load."""
        return bool(np.all(np.abs(self.smooth_width_error) <= HERTZ_TOL)
                    and np.all(np.abs(self.smooth_pressure_error) <= HERTZ_TOL))


def _oring_check(case: Case) -> tuple[float, FloatArray, tuple[PressureProfile, ...]]:
    band = case.band
    if band is None or band.kind != "o-ring":
        what = "a seal with a pressure_profile" if band is not None else "a uniform seal"
        raise InputError("seal.shape", band.kind if band is not None else case.seal.shape,
                         f"the O-ring simulation needs [seal] shape = \"o-ring\" ({what} has no cylinder to press)")
    d = band.cross_section_diameter
    if d is None and band.oring is not None:
        d = float(band.oring.cross_section_diameter)
    if d is None or not d > 0:
        raise InputError("seal.cross_section_diameter", d, "an O-ring needs its cross-section diameter")
    return float(d), np.asarray(band.loads, dtype=float), band.profiles


def simulate_band(
    case: Case,
    *,
    grid: int,
    realizations: int,
    seed: int,
    fields_dir: str | Path | None = None,
    contact_tol: float = 1e-8,
    flow_method: FlowMethod = "auto",
    progress: Callable[[int], None] | None = None,
    memory_limit: float | None = None,
    grid_name: str = "grid",
    runner: Callable[[list[BandTask]], Iterable[dict[str, Any]]] | None = None,
) -> BandSimulationResult:
    """Numerically exact leak rate of an O-ring case and the α of its series-resistance theory.

    α = Q_num / Q_sr(α = 1) per percolating realisation (module docstring; docs/theory.md §10.4). Leak
    rates in m³/s, widths in m, pressures in Pa.

    Parameters
    ----------
    case:
        An O-ring case (``case.band.kind == "o-ring"``).
    grid:
        N, cells per side of the square domain (even, >= 16).
    realizations:
        R, random surfaces (>= 1).
    seed:
        Realisation r uses ``numpy.random.default_rng([seed, r])``.
    fields_dir:
        If given, write ``r<r>-p<i>.npz`` (height, gap, pressure [x, y] in m, m, Pa; size, period in m).
    progress:
        Called with the number of finished solves (one smooth check per load, then one per
        realisation and load; with ``runner``, the smooth checks only).
    grid_name:
        How messages name the grid (``--grid`` or ``simulation.grid`` from the command line).
    runner:
        Runs the realisations' tasks (:func:`band_tasks`, :func:`run_band_task`) and returns their results
        in the order given; None runs them one after the other in this process.
        :func:`sealeak.cases.ensemble.make_runner` (with ``task_function=run_band_task``) runs them on Dask
        and keeps them in a store.
    """
    d, loads, profiles = _oring_check(case)
    if not isinstance(grid, (int, np.integer)) or isinstance(grid, bool) or grid < 16 or grid % 2:
        raise InputError(grid_name, grid, "must be an even integer >= 16")
    whole_number("realizations", realizations, 1, MAX_REALIZATIONS)
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
        raise InputError("seed", seed, "must be a whole number >= 0")
    n = int(grid)
    gas = case.gas
    if not getattr(runner, "checks_memory", False):  # a runner of make_runner checks each task where it runs
        numerics.require_memory(numerics.band_contact_memory_bytes(n, n), f"the {n}x{n} band contact problem",
                                memory_limit)
        numerics.check_memory(n, "flow", available=memory_limit)
        if gas is not None:
            numerics.require_memory(numerics.gas_flow_memory_bytes(n), f"the {n}x{n} gas flow problem", memory_limit)
    band = case.band
    assert band is not None
    radius = d / 2.0
    e_star = case.e_star
    notes: list[str] = []

    force = np.array([p.force_per_length for p in profiles])
    order = np.argsort(force, kind="stable")
    if not np.array_equal(order, np.arange(force.size)):
        notes.append(f"{band.load_name.replace('_', ' ')}s were sorted in increasing order of force")
    loads, force = loads[order], force[order]
    profiles = tuple(profiles[i] for i in order)
    model_q0 = np.asarray(band.q0, dtype=float)[order]
    model_width = np.array([p.width for p in profiles])
    model_pmax = np.array([p.max_pressure for p in profiles])
    hertz = [numerics.hertz_line_contact(float(f), radius, e_star) for f in force]
    b_h = np.array([b for b, _ in hertz])
    p_h = np.array([p for _, p in hertz])
    widest = float(max(model_width.max(), 2.0 * b_h.max()))
    size = DOMAIN_WIDTHS * widest
    dx = size / n

    # the spectrum: resolved wavelengths only, and nothing longer than the theory's longest q0 reference
    default_q0 = np.isclose(model_q0, 2.0 * np.pi / model_width, rtol=1e-9)
    q0_theory = np.where(default_q0, 2.0 * np.pi / (2.0 * b_h), model_q0)  # q0 = 2π/w of the simulated band
    q_low = float(q0_theory.min())
    q_cut = resolved_spectrum_cut(n, size)
    spectrum = case.spectrum
    cut_at: float | None = None
    if q_cut <= max(spectrum.q_min, q_low):
        raise InputError(grid_name, grid, f"resolves q only up to {q_cut:.4g} 1/m, below the spectrum's band "
                                       f"({max(spectrum.q_min, q_low):.4g} .. {spectrum.q_max:.4g} 1/m): use a larger grid")
    if spectrum.q_max > q_cut:
        cut_at = q_cut
        notes.append(f"the {n}x{n} grid resolves q up to {q_cut:.4g} 1/m ({POINTS_PER_WAVELENGTH} points per "
                     f"wavelength), below the spectrum's cut-off q1 = {spectrum.q_max:.4g} 1/m: the spectrum was cut "
                     "there for the simulation AND for the series-resistance theory it is compared with")
    if spectrum.q_min < q_low:
        notes.append(f"wavelengths longer than the widest band (q < q0 = {q_low:.4g} 1/m) are left out of the surface: "
                     "the theory treats them as waviness of the band, not roughness")
    low_cut = q_low if spectrum.q_min < q_low else None
    cut = spectrum.truncated(low_cut, cut_at) if (low_cut is not None or cut_at is not None) else spectrum
    if cut is not spectrum:
        notes[-1] += f" (h_rms {case.spectrum.h_rms * 1e6:.4g} -> {cut.h_rms * 1e6:.4g} µm)"
    if not np.allclose(2.0 * b_h, model_width, rtol=1e-3):
        worst = int(np.argmax(np.abs(2.0 * b_h / model_width - 1.0)))
        notes.append(f"the simulation presses a cylinder on a half-space (Hertz): its contact width at "
                     f"{_load_text(band.load_name, loads[worst])} is {2e3 * b_h[worst]:.4g} mm where the case's O-ring "
                     f"relation gives {1e3 * model_width[worst]:.4g} mm; the series-resistance prediction below uses the "
                     "Hertz profile of the same force, so α measures the series assumption only")

    # the theory: the series resistance of the Hertz profile of each force, critical junction, α = 1
    hertz_profiles = tuple(PressureProfile.semi_elliptic(2.0 * b, p) for b, p in zip(b_h, p_h))
    theory_band = replace(band, loads=loads, profiles=hertz_profiles, q0=q0_theory)
    theory_case = replace(case, alpha=1.0, spectrum=cut, band=theory_band)
    theory = run_band(theory_case, effective=False)
    q_sr = np.asarray(theory.critical_junction.leak_rate, dtype=float)
    lam_c = np.asarray(theory.critical_wavelength_at_max_pressure, dtype=float)
    junction_cells = lam_c / dx
    # a junction at the end of the resolved band (λc at the cut, 4 cells) has u_c -> 0: no prediction to compare with
    at_end = np.isfinite(junction_cells) & (junction_cells <= AT_END_CELLS)
    q_sr = np.where(at_end, np.nan, q_sr)
    coarse = np.isfinite(junction_cells) & (junction_cells < JUNCTION_CELLS) & ~at_end
    parts = []
    if coarse.any():
        parts.append(f"at {_loads_text(band.load_name, loads[coarse])} the theory's critical junction where the pressure "
                     f"is highest spans fewer than {JUNCTION_CELLS} cells: the grid resolves it poorly, and α there "
                     "(marked *) reflects the grid more than the seal")
    if at_end.any():
        parts.append(f"at {_loads_text(band.load_name, loads[at_end])} the theory's critical junction where the pressure is highest "
                     "sits at the very end of the resolved "
                     "spectrum, where u_c vanishes: no series-resistance leak rate and no α")
    if parts:
        notes.append("; ".join(parts) + f". A finer grid (a larger {grid_name}) resolves it.")
    notes.extend(theory.critical_junction.messages)

    # the smooth check: the same solver, no roughness (y-uniform, one column along y suffices)
    sm_width = np.full(loads.size, np.nan)
    sm_pmax = np.full(loads.size, np.nan)
    smooth_lines: dict[int, FloatArray] = {}
    prev = None
    for i, f in enumerate(force):
        prev = numerics.solve_band_contact(np.zeros((n, 1)), size, size, e_star, radius, float(f), tol=contact_tol,
                                           initial=prev)
        lo, hi = numerics.contact_edges(prev.x, prev.line_pressure)
        sm_width[i] = hi - lo
        sm_pmax[i] = prev.max_pressure
        smooth_lines[i] = prev.line_pressure.copy()
        if progress is not None:
            progress(1)
    w_err = sm_width / (2.0 * b_h) - 1.0
    p_err = sm_pmax / p_h - 1.0
    bad = ~((np.abs(w_err) <= HERTZ_TOL) & (np.abs(p_err) <= HERTZ_TOL))
    if bad.any():
        i = int(np.argmax(np.where(bad, np.maximum(np.abs(w_err), np.abs(p_err)), -1.0)))
        notes.append(f"smooth check: at {_load_text(band.load_name, loads[i])} the smooth cylinder is off Hertz by "
                     f"{100 * w_err[i]:+.2g} % in width and {100 * p_err[i]:+.2g} % in peak pressure (allowed "
                     f"{100 * HERTZ_TOL:g} %): the band spans only {2 * b_h[i] / dx:.0f} cells; use a larger {grid_name}")

    # the rough contacts and the flow: one task per realisation
    n_l = loads.size
    width = np.zeros((realizations, n_l))
    area = np.zeros((realizations, n_l))
    perc = np.zeros((realizations, n_l), dtype=bool)
    q_num = np.zeros((realizations, n_l))
    pv = np.zeros((realizations, n_l))  # the seal's pV throughput (Pa·m³/s), a gas case only
    pv_no_slip = np.zeros((realizations, n_l))
    iterations = np.zeros((realizations, n_l), dtype=np.int64)
    contact_maps: dict[int, NDArray[np.bool_]] = {}
    lines: dict[int, FloatArray] = {}
    touched: list[float] = []
    scale = band.faces * band.length / size  # Q of the seal per Q of the W-wide strip
    dp = float(case.pressure_difference)
    with _StagedFolder(fields_dir) as fields:
        spec = BandSpec(spectrum=cut, grid=n, size=size, seed=int(seed), e_star=e_star, radius=radius, forces=force,
                        half_widths=b_h, loads=loads, load_name=band.load_name, scale=float(scale),
                        viscosity=case.fluid.viscosity, pressure_difference=dp, gas=gas,
                        flow_method=flow_method, contact_tol=contact_tol, memory_limit=memory_limit,
                        fields_stage=None if fields.stage is None else str(fields.stage),
                        fields_target=None if fields.target is None else str(fields.target))
        tasks = band_tasks(spec, realizations)
        done = [run_band_task(t, progress=progress) for t in tasks] if runner is None else list(runner(tasks))
    for task, out in zip(tasks, done, strict=True):  # in realisation order, whatever order they finished in
        r = task.realization
        width[r] = out["contact_width"]
        area[r] = out["relative_contact_area"]
        perc[r] = out["percolates"]
        q_num[r] = out["leak_rate"]
        if gas is not None:
            pv[r] = out["leak_rate_pv"]
            pv_no_slip[r] = out["leak_rate_pv_no_slip"]
            iterations[r] = out["gas_iterations"]
        touched.extend(float(loads[i]) for i in out["touched_edge"])
        if r == 0:
            contact_maps = {i: unpack_mask(m) for i, m in enumerate(out["contact_maps"])}
            lines = {i: np.asarray(line, dtype=float) for i, line in enumerate(out["line_pressure"])}
    if touched:
        notes.append(f"the rough contact reached the edge of the domain at {_loads_text(band.load_name, np.unique(touched))}: "
                     "the band there is wider than the domain holds and its leak rate is not that of an isolated band")

    width_m, width_s = _mean_std(width)
    area_m, area_s = _mean_std(area)
    q_m, q_s = _mean_std(q_num)
    with np.errstate(invalid="ignore", divide="ignore"):
        alpha_r = np.where(perc & (np.isfinite(q_sr) & (q_sr > 0))[None, :], q_num / q_sr[None, :], np.nan)
    alpha_m, alpha_s = _mean_std(alpha_r)
    gas_result = None
    per_gas: dict[str, Any] = {}
    if gas is not None:
        # the series-resistance gas leak: K = Q_sr/ΔP (α = 1, the gas's viscosity), gap u_c at the peak pressure (§11.9)
        u_c = np.where(np.isfinite(q_sr), np.asarray(theory.critical_gap_at_max_pressure, dtype=float), np.nan)
        gas_result = _gas_statistics(theory_case, q_sr, u_c, perc, pv, pv_no_slip, iterations)
        per_gas = {"leak_rate_pv": pv, "leak_rate_pv_no_slip": pv_no_slip, "gas_iterations": iterations,
                   "alpha_gas": _ratio(perc, pv, gas_result.throughput_critical_junction)}
    spectrum_note = (f"{cut.label or case.spectrum_note}: h_rms = {cut.h_rms * 1e6:.4g} µm over "
                     f"q = {cut.q_min:.4g} .. {cut.q_max:.4g} 1/m")
    return BandSimulationResult(
        load_name=band.load_name, loads=loads, force_per_length=force, model_contact_width=model_width,
        model_max_pressure=model_pmax, hertz_contact_width=2.0 * b_h, hertz_max_pressure=p_h,
        smooth_contact_width=sm_width, smooth_max_pressure=sm_pmax, smooth_width_error=w_err, smooth_pressure_error=p_err,
        contact_width=width_m, contact_width_std=width_s, relative_contact_area=area_m, relative_contact_area_std=area_s,
        percolating_fraction=perc.mean(axis=0), leak_rate=q_m, leak_rate_std=q_s, leak_rate_series_resistance=q_sr,
        alpha=alpha_m, alpha_std=alpha_s, junction_cells=junction_cells, pressure_difference=dp, grid=n,
        realizations=int(realizations), seed=int(seed), size=size, period=size, seal_length=float(band.length),
        faces=int(band.faces), radius=radius, q_cut=cut_at, q_low=q_low, notes=tuple(notes), spectrum_note=spectrum_note,
        per_realization={"contact_width": width, "relative_contact_area": area, "percolates": perc, "leak_rate": q_num,
                         "alpha": alpha_r} | per_gas,
        contact_maps=contact_maps, line_pressure=lines, smooth_line_pressure=smooth_lines, gas=gas_result,
    )


@dataclass(frozen=True)
class BandSpec:
    """Everything one realisation's task of an O-ring simulation needs, in SI units (shared by all its tasks).

    ``spectrum`` is the cut C(q) the surfaces are drawn from; ``grid`` N and ``size`` W (m) the square
    domain; ``radius`` the cylinder's d/2 (m); ``forces`` f (N/m) at the ``loads`` (named ``load_name``, in
    increasing order of force); ``half_widths`` the Hertz half-widths b (m) whose band |x - W/2| < b the
    relative contact area counts; ``scale`` faces · L_seal/W, the seal's Q per Q of the strip. ``fields_stage``,
    ``fields_target``, ``fields_store`` and ``fft_workers`` as in :class:`sealeak.cases.simulation.EnsembleSpec`.
    """

    spectrum: Any
    grid: int
    size: float
    seed: int
    e_star: float
    radius: float
    forces: FloatArray
    half_widths: FloatArray
    loads: FloatArray
    load_name: str
    scale: float
    viscosity: float
    pressure_difference: float
    gas: Any
    flow_method: FlowMethod
    contact_tol: float
    memory_limit: float | None = None
    fields_stage: str | None = None
    fields_target: str | None = None
    fft_workers: int = -1
    fields_store: str | None = None

    def identity(self) -> dict[str, Any]:
        """The inputs the tasks' numbers depend on, as plain JSON values (the store's manifest hashes them)."""
        gas = self.gas
        return {
            "spectrum": {"q": [float(x) for x in self.spectrum.q], "C": [float(x) for x in self.spectrum.C]},
            "grid": int(self.grid),
            "seed": int(self.seed),
            "case": {"route": "o-ring", "size": float(self.size), "e_star": float(self.e_star),
                     "radius": float(self.radius), "force_per_length": [float(x) for x in self.forces],
                     "half_widths": [float(x) for x in self.half_widths], "scale": float(self.scale),
                     "viscosity": float(self.viscosity), "pressure_difference": float(self.pressure_difference),
                     "flow_method": self.flow_method, "contact_tol": float(self.contact_tol),
                     "gas": gas_identity(gas)},
        }


@dataclass(frozen=True)
class BandTask:
    """Realisation ``realization`` of an O-ring simulation: its surface pressed at every load, and the flows."""

    realization: int
    spec: BandSpec
    kind: str = "band"

    @property
    def name(self) -> str:
        """``band-r<r>``: the task's name in the store and in progress lines."""
        return f"band-r{self.realization}"

    @property
    def writes_fields(self) -> bool:
        """Whether the task writes its fields into a store."""
        return self.spec.fields_store is not None

    def memory_bytes(self) -> int:
        """Peak memory in bytes (estimate): as a uniform sweep (:meth:`EnsembleTask.memory_bytes`) with the band
        contact's solver (:func:`sealeak.numerics.band_contact_memory_bytes`) in place of the periodic one."""
        return task_memory_bytes("sweep", self.spec.grid, self.spec.grid, int(np.size(self.spec.forces)), contact="band",
                                 gas=self.spec.gas is not None, fields=self.spec.fields_store is not None,
                                 flow_method=self.spec.flow_method)


def band_tasks(spec: BandSpec, realizations: int) -> list[BandTask]:
    """One task per realisation, in realisation order."""
    return [BandTask(r, spec) for r in range(int(realizations))]


def run_band_task(task: BandTask, progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Compute one realisation of an O-ring simulation; return its scalars as plain JSON values.

    Realisation r's surface is ``synthesize`` with the seed sequence (seed, r); at each load (increasing f) the
    cylinder's contact (:func:`sealeak.numerics.solve_band_contact`, warm-started from the previous load) and the
    flow across the band (:func:`sealeak.numerics.solve_flow`; for a gas also
    :func:`sealeak.numerics.solve_gas_flow`, P_a at x = 0, P_b at x = W). Per load: the contact width (m), the
    fraction of the Hertz band in contact, whether fluid crosses, the seal's leak rate scale · Q_W (m³/s), for a
    gas the pV throughputs (Pa·m³/s) and iterations; the indices of the loads whose contact reached the domain's
    edge; for realisation 0 the contact maps (packed) and the pressure averaged along the seal line p̄(x) (Pa).
    Fields, if asked, are written by the task itself (npz files, or the store's Zarr group ``r<r>``).
    """
    spec, r = task.spec, task.realization
    n, size = spec.grid, spec.size
    h = synthesize(spec.spectrum, n, size, seed=np.random.default_rng([int(spec.seed), r]), workers=spec.fft_workers)
    x = (np.arange(n) + 0.5) * (size / n)
    in_band = np.abs(x - size / 2.0)[:, None] < np.asarray(spec.half_widths)[None, :]  # [x, load]
    gas = spec.gas
    out: dict[str, Any] = {"kind": "band", "realization": r, "contact_width": [], "relative_contact_area": [],
                           "percolates": [], "leak_rate": [], "touched_edge": [], "contact_maps": [], "line_pressure": []}
    if gas is not None:
        out |= {"leak_rate_pv": [], "leak_rate_pv_no_slip": [], "gas_iterations": []}
    kept = None
    if spec.fields_store is not None:
        kept = TaskFields(spec.fields_store, f"r{r}", grid=n, size=size, period=size, load_name=spec.load_name,
                          loads=spec.loads, load_unit="1",
                          attributes={"task": task.name, "realization": int(r), "seed": int(spec.seed), "grid": int(n),
                                      "size": float(size), "period": float(size), "length_units": "m",
                                      "e_star": float(spec.e_star), "e_star_units": "Pa", "radius": float(spec.radius),
                                      "force_per_length": [float(f) for f in spec.forces],
                                      "force_per_length_units": "N/m", "software": f"sealeak {__version__}"})
    try:
        if kept is not None:
            kept.put_height(h)
        prev = None
        for i, f in enumerate(spec.forces):
            res = numerics.solve_band_contact(h, size, size, spec.e_star, spec.radius, float(f), tol=spec.contact_tol,
                                              initial=prev, workers=spec.fft_workers)
            prev = res
            flow = numerics.solve_flow(res.gap, size, spec.viscosity, spec.pressure_difference, contact=res.contact,
                                       method=spec.flow_method)
            out["contact_width"].append(float(res.contact_width))
            out["relative_contact_area"].append(float(res.contact[in_band[:, i]].mean()) if in_band[:, i].any()
                                                else float("nan"))
            out["percolates"].append(bool(flow.percolates))
            out["leak_rate"].append(float(spec.scale * flow.flux))
            if gas is not None:
                gflow = numerics.solve_gas_flow(res.gap, size, gas.gas, gas.upstream_pressure, gas.downstream_pressure,
                                                contact=res.contact, model=gas.rarefaction, method=spec.flow_method,
                                                memory_limit=spec.memory_limit)
                out["leak_rate_pv"].append(float(spec.scale * gflow.throughput))
                out["leak_rate_pv_no_slip"].append(float(spec.scale * gflow.throughput_no_slip))
                out["gas_iterations"].append(int(gflow.iterations))
            if res.touches_edge:
                out["touched_edge"].append(i)
            if r == 0:
                out["contact_maps"].append(pack_mask(np.asarray(res.contact, dtype=bool)))
                out["line_pressure"].append([float(v) for v in res.line_pressure])
            if spec.fields_stage is not None:
                _write_fields(spec, f"r{r}-p{i}.npz", height=h, gap=res.gap, pressure=res.pressure,  # type: ignore[arg-type]
                              size=np.float64(size), period=np.float64(size))
            if kept is not None:
                kept.put(i, res.gap, res.pressure)
            if progress is not None:
                progress(1)
        if kept is not None:
            out["fields"] = kept.commit()
    except BaseException:
        if kept is not None:
            kept.abort()
        raise
    return out


def _load_text(name: str, value: float) -> str:
    """One load for a note: "compression 20 %" or "profile scale 1.5"."""
    if name == "compression":
        return f"compression {100 * value:.4g} %"
    return f"{name.replace('_', ' ')} {value:.4g}"


def _loads_text(name: str, values: FloatArray) -> str:
    """Several loads for a note (all of a few, else the range)."""
    vals = np.asarray(values, dtype=float)
    if name == "compression":
        shown = [f"{100 * v:.4g}" for v in vals]
        unit, label = " %", "compression"
    else:
        shown = [f"{v:.4g}" for v in vals]
        unit, label = "", name.replace("_", " ")
    if len(shown) <= 4:
        return f"{label} {', '.join(shown)}{unit}"
    return f"{label} {shown[0]} .. {shown[-1]}{unit} ({len(shown)} values)"
