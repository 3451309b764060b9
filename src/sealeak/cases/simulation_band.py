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

This is the ensemble pipeline (:func:`sealeak.cases.pipeline.run_ensemble`) with the :class:`OringBand`
geometry. Steps 2–4 and 7 of each realisation form one independent task (:func:`band_tasks`,
:func:`run_band_task`: ``band-r<r>`` draws surface r, presses the cylinder at every load and solves the
flows), returning its scalars only; a runner (:func:`sealeak.cases.ensemble.make_runner`) runs them in this
process or on Dask, keeps them in a store and, if asked, has each write its fields there. The statistics
are formed in realisation order afterwards, so the numbers do not depend on the runner (docs/theory.md §6.7).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import numerics
from ..errors import InputError
from ..io.quantities import quantity
from ..physics.profile import PressureProfile
from ..physics.spectrum import PowerSpectrum
from . import pipeline
from .band import BandResult, run_band
from .model import BandSeal, Case
from .notes import Note, NoteLike

__all__ = ["BandSimulationResult", "simulate_band", "DOMAIN_WIDTHS", "HERTZ_TOL", "BandSpec", "BandTask", "BandRecord", "band_tasks",
           "run_band_task", "OringBand"]

FloatArray = NDArray[np.float64]

#: Width of the domain across the band, in contact widths of the widest band (free edges beyond).
DOMAIN_WIDTHS = 2.5
#: λc at most this many cells: the junction sits at the end of the resolved spectrum (4 cells per wavelength).
AT_END_CELLS = 1.05 * pipeline.POINTS_PER_WAVELENGTH
#: Relative agreement with Hertz the smooth-cylinder check must reach (width and peak pressure).
HERTZ_TOL = 0.01


@dataclass(frozen=True, kw_only=True)
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
    capillarity
        A liquid with a contact angle: per load the entry pressure of each realisation's critical constriction
        across the band, p_e at u_c of the peak contact pressure, and the realisations held (docs/theory.md §12.4);
        None without a contact angle.
    """

    load_name: str
    loads: FloatArray
    force_per_length: FloatArray = quantity("N/m", "force per length of seal line")
    model_contact_width: FloatArray = quantity("m", "contact width of the case's O-ring relation")
    model_max_pressure: FloatArray = quantity("Pa", "peak pressure of the case's O-ring relation")
    hertz_contact_width: FloatArray = quantity("m", "Hertz line contact width 2b")
    hertz_max_pressure: FloatArray = quantity("Pa", "Hertz peak pressure")
    smooth_contact_width: FloatArray = quantity("m", "contact width of the solver without roughness")
    smooth_max_pressure: FloatArray = quantity("Pa", "peak pressure of the solver without roughness")
    smooth_width_error: FloatArray = quantity("1", "smooth contact width over Hertz's, minus 1")
    smooth_pressure_error: FloatArray = quantity("1", "smooth peak pressure over Hertz's, minus 1")
    contact_width: FloatArray = quantity("m", "extent across the band of the rough contact")
    contact_width_std: FloatArray = quantity("m", "standard deviation of the rough contact width")
    relative_contact_area: FloatArray = quantity("1", "fraction of the Hertz band in contact")
    relative_contact_area_std: FloatArray = quantity("1", "standard deviation of that fraction")
    percolating_fraction: FloatArray = quantity("1", "fraction of realisations in which fluid crosses the band")
    leak_rate: FloatArray = quantity("m^3/s", "simulated leak rate Q_num of the seal")
    leak_rate_std: FloatArray = quantity("m^3/s", "standard deviation of Q_num")
    leak_rate_series_resistance: FloatArray = quantity("m^3/s", "series-resistance leak rate Q_sr with α = 1")
    alpha: FloatArray = quantity("1", "α = Q_num/Q_sr over the percolating realisations")
    alpha_std: FloatArray = quantity("1", "standard deviation of α")
    junction_cells: FloatArray = quantity("1", "grid cells across λc where the pressure is highest")
    junction_resolved: tuple[bool | None, ...] = quantity("1", "λc spans enough grid cells for α", init=False)
    pressure_difference: float = quantity("Pa", "pressure difference across the seal")
    size: float = quantity("m", "domain across the band W")
    period: float = quantity("m", "domain along the seal line Ly")
    seal_length: float = quantity("m", "seal line length")
    radius: float = quantity("m", "cylinder radius d/2")
    q_cut: float | None = quantity("1/m", "wavevector where the spectrum is cut", key="spectrum_cut_wavevector")
    q_low: float = quantity("1/m", "lowest wavevector of the spectrum", key="spectrum_low_wavevector")
    grid: int
    realizations: int
    seed: int
    faces: int
    notes: tuple[NoteLike, ...] = ()
    spectrum_note: str = ""
    per_realization: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    #: realisation 0: contact mask [x, y] and the pressure averaged along the seal line p̄(x) (Pa) per load
    contact_maps: dict[int, NDArray[np.bool_]] = field(default_factory=dict, repr=False)
    line_pressure: dict[int, FloatArray] = field(default_factory=dict, repr=False)
    smooth_line_pressure: dict[int, FloatArray] = field(default_factory=dict, repr=False)
    gas: pipeline.GasSimulation | None = None
    capillarity: pipeline.SimulationCapillarity | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "junction_resolved", pipeline.junction_resolved(self.junction_cells))

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
    flow_method: pipeline.FlowMethod = "auto",
    progress: Callable[[int], None] | None = None,
    memory_limit: float | None = None,
    grid_name: str = "grid",
    runner: Callable[[list[BandTask]], Iterable[pipeline.TaskRecord]] | None = None,
    device: str = "cpu",
) -> BandSimulationResult:
    """Numerically exact leak rate of an O-ring case and the α of its series-resistance theory.

    α = Q_num / Q_sr(α = 1) per percolating realisation (module docstring; docs/theory.md §10.4). Leak
    rates in m³/s, widths in m, pressures in Pa. The ensemble pipeline
    (:func:`sealeak.cases.pipeline.run_ensemble`) with the :class:`OringBand` geometry.

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
        :func:`sealeak.cases.ensemble.make_runner` runs them on Dask and keeps them in a store.
    device:
        ``"cpu"`` or ``"cuda"``: where the surfaces are synthesized and the band contact solved, as for
        :func:`sealeak.cases.simulate`.
    """
    return pipeline.run_ensemble(OringBand.of(case, contact_tol), case, grid=grid, realizations=realizations, seed=seed,
                        grid_field=grid_name, fields_dir=fields_dir, contact_tol=contact_tol, flow_method=flow_method,
                        progress=progress, memory_limit=memory_limit, runner=runner, device=device)


@dataclass(frozen=True)
class _Smooth:
    """The smooth-cylinder check per load: width (m), peak pressure (Pa), p̄(x) (Pa), deviations from Hertz (1)."""

    width: FloatArray
    max_pressure: FloatArray
    lines: dict[int, FloatArray]
    width_error: FloatArray
    pressure_error: FloatArray


@dataclass(frozen=True, kw_only=True)
class _BandPlan:
    """What :class:`OringBand` prepares (SI units; loads in increasing order of force)."""

    case: Case
    band: BandSeal
    radius: float
    loads: FloatArray
    force: FloatArray
    model_width: FloatArray
    model_pmax: FloatArray
    half_width: FloatArray
    hertz_pmax: FloatArray
    size: float
    spectrum: PowerSpectrum
    cut_at: float | None
    q_low: float
    theory: BandResult
    theory_case: Case
    q_sr: FloatArray
    junction_cells: FloatArray
    smooth: _Smooth


@dataclass(frozen=True)
class OringBand:
    """The geometry of an O-ring: a cylinder of radius d/2 pressed on a rough square domain across its band.

    One task per realisation presses the cylinder at every load and solves the flows across the band; the
    theory is the series-resistance leak rate (α = 1) of the Hertz profile of the same force per length.
    """

    diameter: float
    loads: FloatArray
    profiles: tuple[PressureProfile, ...]
    contact_tol: float = 1e-8

    @classmethod
    def of(cls, case: Case, contact_tol: float = 1e-8) -> OringBand:
        """The geometry of ``case`` (``contact_tol``: the smooth check's); refused unless it is an O-ring with its
        cross-section diameter."""
        d, loads, profiles = _oring_check(case)
        return cls(d, loads, profiles, contact_tol)

    def check_memory(self, grid: int, memory_limit: float | None) -> None:
        """The band contact problem of an N × N grid (free edges) must fit in memory."""
        numerics.require_memory(numerics.band_contact_memory_bytes(grid, grid), f"the {grid}x{grid} band contact problem",
                                memory_limit)

    def prepare(self, case: Case, grid: int, grid_field: str, notes: list[NoteLike],
                progress: Callable[[int], None] | None) -> _BandPlan:
        """The loads by force, Hertz, the domain, the cut spectrum, the series-resistance theory, the smooth check."""
        band = case.band
        assert band is not None
        radius = self.diameter / 2.0
        force = np.array([p.force_per_length for p in self.profiles])
        order = np.argsort(force, kind="stable")
        if not np.array_equal(order, np.arange(force.size)):
            notes.append(Note("loads_sorted_by_force", {"load_name": band.load_name}))
        loads, force = self.loads[order], force[order]
        profiles = tuple(self.profiles[i] for i in order)
        model_q0 = np.asarray(band.q0, dtype=float)[order]
        model_width = np.array([p.width for p in profiles])
        hertz = [numerics.hertz_line_contact(float(f), radius, case.e_star) for f in force]
        b_h = np.array([b for b, _ in hertz])
        p_h = np.array([p for _, p in hertz])
        size = DOMAIN_WIDTHS * float(max(model_width.max(), 2.0 * b_h.max()))
        # the spectrum: resolved wavelengths only, and nothing longer than the theory's longest q0 reference
        default_q0 = np.isclose(model_q0, 2.0 * np.pi / model_width, rtol=1e-9)
        q0_theory = np.where(default_q0, 2.0 * np.pi / (2.0 * b_h), model_q0)  # q0 = 2π/w of the simulated band
        q_low = float(q0_theory.min())
        cut, cut_at, cut_notes = pipeline.cut_spectrum(case.spectrum, grid, size, grid_field, "series-resistance", q_low)
        notes.extend(cut_notes)
        if not np.allclose(2.0 * b_h, model_width, rtol=1e-3):
            worst = int(np.argmax(np.abs(2.0 * b_h / model_width - 1.0)))
            notes.append(Note("hertz_width_differs", {
                "load_name": band.load_name, "load": float(loads[worst]), "hertz_width": float(2.0 * b_h[worst]),
                "model_width": float(model_width[worst])}))
        # the theory: the series resistance of the Hertz profile of each force, critical junction, α = 1
        hertz_profiles = tuple(PressureProfile.semi_elliptic(2.0 * b, p) for b, p in zip(b_h, p_h))
        theory_case = replace(case, alpha=1.0, spectrum=cut,
                              band=replace(band, loads=loads, profiles=hertz_profiles, q0=q0_theory))
        theory = run_band(theory_case, effective=False)
        q_sr, junction_cells = _theory_at_grid(theory, band.load_name, loads, size / grid, grid_field, notes)
        smooth = self._smooth_check(grid, size, case.e_star, force, b_h, p_h, band.load_name, loads, grid_field,
                                    notes, progress)
        return _BandPlan(case=case, band=band, radius=radius, loads=loads, force=force, model_width=model_width,
                         model_pmax=np.array([p.max_pressure for p in profiles]), half_width=b_h, hertz_pmax=p_h,
                         size=size, spectrum=cut, cut_at=cut_at, q_low=q_low, theory=theory, theory_case=theory_case,
                         q_sr=q_sr, junction_cells=junction_cells, smooth=smooth)

    def _smooth_check(self, n: int, size: float, e_star: float, force: FloatArray, b_h: FloatArray, p_h: FloatArray,
                      load_name: str, loads: FloatArray, grid_field: str, notes: list[NoteLike],
                      progress: Callable[[int], None] | None) -> _Smooth:
        """The same solver without roughness (y-uniform, one column along y suffices) against Hertz."""
        sm_width = np.full(loads.size, np.nan)
        sm_pmax = np.full(loads.size, np.nan)
        lines: dict[int, FloatArray] = {}
        prev = None
        for i, f in enumerate(force):
            prev = numerics.solve_band_contact(np.zeros((n, 1)), size, size, e_star, self.diameter / 2.0, float(f),
                                               tol=self.contact_tol, initial=prev)
            lo, hi = numerics.contact_edges(prev.x, prev.line_pressure)
            sm_width[i] = hi - lo
            sm_pmax[i] = prev.max_pressure
            lines[i] = prev.line_pressure.copy()
            if progress is not None:
                progress(1)
        w_err = sm_width / (2.0 * b_h) - 1.0
        p_err = sm_pmax / p_h - 1.0
        bad = ~((np.abs(w_err) <= HERTZ_TOL) & (np.abs(p_err) <= HERTZ_TOL))
        if bad.any():
            i = int(np.argmax(np.where(bad, np.maximum(np.abs(w_err), np.abs(p_err)), -1.0)))
            notes.append(Note("smooth_check_off", {
                "load_name": load_name, "load": float(loads[i]), "width_error": float(w_err[i]),
                "pressure_error": float(p_err[i]), "tolerance": HERTZ_TOL, "cells": float(2 * b_h[i] / (size / n)),
                "grid_field": grid_field}))
        return _Smooth(sm_width, sm_pmax, lines, w_err, p_err)

    def tasks(self, plan: _BandPlan, common: pipeline.RunSettings, realizations: int) -> list[BandTask]:
        """One task per realisation."""
        band = plan.band
        spec = common.spec(BandSpec, spectrum=plan.spectrum, size=plan.size, radius=plan.radius, forces=plan.force,
                           half_widths=plan.half_width, loads=plan.loads, load_name=band.load_name,
                           scale=float(band.faces * band.length / plan.size),  # Q of the seal per Q of the W-wide strip
                           capillary=plan.case.capillarity is not None)
        return band_tasks(spec, realizations)

    def aggregate(self, plan: _BandPlan, records: pipeline.Records, notes: list[NoteLike]) -> BandSimulationResult:
        """Means over realisations, α = Q/Q_sr over the percolating ones, a gas case's gas leak."""
        band, loads, q_sr, sm = plan.band, plan.loads, plan.q_sr, plan.smooth
        n_l = loads.size
        flows = pipeline.Flows.of(records, BandRecord, n_l)
        width = records.stack(BandRecord, lambda rec: rec.contact_width, n_l)
        touched = [float(loads[i]) for rec in records.of(BandRecord) for i in rec.touched_edge]
        first = records.first(BandRecord)
        lines = {} if first is None else {i: np.asarray(v, dtype=float) for i, v in enumerate(first.line_pressure)}
        if touched:
            notes.append(Note("band_touches_edge", {"load_name": band.load_name,
                                                    "loads": tuple(float(v) for v in np.unique(touched))}))
        perc, q_num = flows.percolates, flows.leak_rate
        width_m, width_s = pipeline.mean_std(width)
        area_m, area_s = pipeline.mean_std(flows.area)
        q_m, q_s = pipeline.mean_std(q_num)
        with np.errstate(invalid="ignore", divide="ignore"):
            alpha_r = np.where(perc & (np.isfinite(q_sr) & (q_sr > 0))[None, :], q_num / q_sr[None, :], np.nan)
        alpha_m, alpha_s = pipeline.mean_std(alpha_r)
        # the series-resistance gas leak: K = Q_sr/ΔP (α = 1, the gas's viscosity), gap u_c at the peak pressure (§11.9)
        u_c = np.where(np.isfinite(q_sr), np.asarray(plan.theory.critical_gap_at_max_pressure, dtype=float), np.nan)
        gas_result, per_gas = pipeline.gas_part(plan.theory_case, q_sr, u_c,
                                                np.asarray(plan.theory.critical_wavelength_at_max_pressure, dtype=float), flows)
        capillarity, per_capillary = pipeline.capillary_part(plan.case, records, BandRecord,
                                                             np.asarray(plan.theory.critical_gap_at_max_pressure, float), perc)
        return BandSimulationResult(
            load_name=band.load_name, loads=loads, force_per_length=plan.force, model_contact_width=plan.model_width,
            model_max_pressure=plan.model_pmax, hertz_contact_width=2.0 * plan.half_width, hertz_max_pressure=plan.hertz_pmax,
            smooth_contact_width=sm.width, smooth_max_pressure=sm.max_pressure, smooth_width_error=sm.width_error,
            smooth_pressure_error=sm.pressure_error, contact_width=width_m, contact_width_std=width_s,
            relative_contact_area=area_m, relative_contact_area_std=area_s, percolating_fraction=perc.mean(axis=0),
            leak_rate=q_m, leak_rate_std=q_s, leak_rate_series_resistance=q_sr, alpha=alpha_m, alpha_std=alpha_s,
            junction_cells=plan.junction_cells, pressure_difference=float(plan.case.pressure_difference),
            grid=records.grid, realizations=records.realizations, seed=records.seed, size=plan.size,
            period=plan.size, seal_length=float(band.length), faces=int(band.faces), radius=plan.radius,
            q_cut=plan.cut_at, q_low=plan.q_low, notes=tuple(notes), spectrum_note=pipeline.spectrum_text(plan.spectrum, plan.case),
            per_realization={"contact_width": width, "relative_contact_area": flows.area, "percolates": perc,
                             "leak_rate": q_num, "alpha": alpha_r} | per_gas | per_capillary,
            contact_maps=flows.contact_maps, line_pressure=lines, smooth_line_pressure=sm.lines, gas=gas_result,
            capillarity=capillarity,
        )


def _theory_at_grid(theory: BandResult, load_name: str, loads: FloatArray, dx: float, grid_field: str,
                    notes: list[NoteLike]) -> tuple[FloatArray, FloatArray]:
    """Q_sr (m³/s; NaN where the junction sits at the end of the resolved spectrum) and the cells across λc.

    A junction at the end of the resolved band (λc at the cut, 4 cells) has u_c -> 0: no prediction to compare
    with; one of fewer than :data:`JUNCTION_CELLS` cells is resolved poorly (noted).
    """
    q_sr = np.asarray(theory.critical_junction.leak_rate, dtype=float)
    junction_cells = np.asarray(theory.critical_wavelength_at_max_pressure, dtype=float) / dx
    at_end = np.isfinite(junction_cells) & (junction_cells <= AT_END_CELLS)
    q_sr = np.where(at_end, np.nan, q_sr)
    coarse = np.isfinite(junction_cells) & (junction_cells < pipeline.JUNCTION_CELLS) & ~at_end
    if coarse.any() or at_end.any():
        notes.append(Note("band_junction_unresolved", {
            "load_name": load_name, "min_cells": pipeline.JUNCTION_CELLS, "grid_field": grid_field,
            "coarse": tuple(float(v) for v in loads[coarse]), "at_end": tuple(float(v) for v in loads[at_end])}))
    notes.extend(theory.critical_junction.messages)
    return q_sr, junction_cells


@dataclass(frozen=True, kw_only=True)
class BandSpec(pipeline.TaskSpec):
    """Everything one realisation's task of an O-ring simulation needs, in SI units (shared by all its tasks).

    :class:`~sealeak.cases.pipeline.TaskSpec`'s fields (``spectrum`` the cut C(q), ``grid`` N and ``size`` W (m)
    the square domain), and ``radius`` the cylinder's d/2 (m); ``forces`` f (N/m) at the ``loads`` (named
    ``load_name``, in increasing order of force); ``half_widths`` the Hertz half-widths b (m) whose band
    |x - W/2| < b the relative contact area counts; ``scale`` faces · L_seal/W, the seal's Q per Q of the strip.
    """

    radius: float
    forces: FloatArray
    half_widths: FloatArray
    loads: FloatArray
    load_name: str
    scale: float

    def geometry_identity(self) -> dict[str, Any]:
        """The band's own inputs: the route, the cylinder, its forces, the Hertz half-widths, the scale."""
        return {"route": "o-ring", "radius": float(self.radius), "force_per_length": [float(x) for x in self.forces],
                "half_widths": [float(x) for x in self.half_widths], "scale": float(self.scale)}


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
        """Peak memory in bytes (estimate): as a uniform sweep (``EnsembleTask.memory_bytes``) with the band
        contact's solver (:func:`sealeak.numerics.band_contact_memory_bytes`) in place of the periodic one."""
        return pipeline.task_memory_bytes("sweep", self.spec.grid, self.spec.grid, int(np.size(self.spec.forces)), contact="band",
                                 gas=self.spec.gas is not None, fields=self.spec.fields_store is not None,
                                 flow_method=self.spec.flow_method)

    def run(self, progress: Callable[[int], None] | None = None) -> BandRecord:
        """Compute this task (:func:`run_band_task`)."""
        return run_band_task(self, progress)


def band_tasks(spec: BandSpec, realizations: int) -> list[BandTask]:
    """One task per realisation, in realisation order."""
    return [BandTask(r, spec) for r in range(int(realizations))]


@dataclass(frozen=True, kw_only=True)
class BandRecord(pipeline.FlowRecord):
    """A realisation of an O-ring simulation (:func:`run_band_task`): :class:`~sealeak.cases.pipeline.FlowRecord`'s
    columns per load (the relative contact area that of the Hertz band), and the band's own."""

    KIND = "band"

    contact_width: list[float] = quantity("m", "extent across the band of the rough contact")
    touched_edge: list[int] = quantity("1", "indices of the loads whose contact reached the domain's edge")
    line_pressure: list[list[float]] = quantity("Pa", "realisation 0: pressure averaged along the seal line, per load",
                                                default_factory=list)


def run_band_task(task: BandTask, progress: Callable[[int], None] | None = None) -> BandRecord:
    """Compute one realisation of an O-ring simulation; return its record, plain JSON values.

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
    h_dev = spec.on_device(spec.surface(r))  # synthesis and contact on the run's device, the flow and fields on the host
    h = numerics.to_numpy(h_dev)
    x = (np.arange(n) + 0.5) * (size / n)
    in_band = np.abs(x - size / 2.0)[:, None] < np.asarray(spec.half_widths)[None, :]  # [x, load]
    log = pipeline.FlowLog(gas=spec.gas is not None, capillary=spec.capillary)
    widths: list[float] = []
    touched: list[int] = []
    lines: list[list[float]] = []

    def sweep(kept: Any) -> None:
        prev = None
        for i, f in enumerate(spec.forces):
            prev = numerics.solve_band_contact(h_dev, size, size, spec.e_star, spec.radius, float(f), tol=spec.contact_tol,
                                               initial=prev, workers=spec.fft_workers)
            res = prev.on_host()
            widths.append(float(res.contact_width))
            log.add(spec, r, res, spec.scale, res.contact[in_band[:, i]].mean() if in_band[:, i].any() else np.nan)
            if res.touches_edge:
                touched.append(i)
            if r == 0:
                lines.append([float(v) for v in res.line_pressure])
            pipeline.keep_load(spec, kept, r, i, h, res, progress, period=np.float64(size))

    attributes = spec.field_attributes(task.name, r) | {
        "radius": float(spec.radius), "force_per_length": [float(f) for f in spec.forces],
        "force_per_length_units": "N/m"}
    kept = pipeline.with_fields(spec, r, h, sweep, load_name=spec.load_name, loads=spec.loads, load_unit="1",
                       attributes=attributes)
    return log.record(BandRecord, r, kept, contact_width=widths, touched_edge=touched, line_pressure=lines)
