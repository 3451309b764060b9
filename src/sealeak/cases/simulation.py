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
   percolating (bisection on pressure, :func:`sealeak.numerics.percolation_threshold`).

Resolution: the grid resolves wavelengths of at least 4 cells, q <= 2π N/(4L). When the
spectrum's cut-off q1 lies above that, the spectrum is cut there, the result says so, and the
critical-junction theory it is compared with uses the same cut spectrum.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .. import numerics
from ..errors import InputError
from ..io.files import atomic_write
from ..numerics.synthesis import synthesize
from .model import Case
from .run import predict

__all__ = ["SimulationResult", "simulate", "resolved_spectrum_cut", "POINTS_PER_WAVELENGTH"]

POINTS_PER_WAVELENGTH = 4
FloatArray = NDArray[np.float64]


def resolved_spectrum_cut(grid: int, size: float) -> float:
    """Highest wavevector an N-point grid of side ``size`` resolves with 4 points per wavelength (1/m)."""
    return 2.0 * np.pi * grid / (POINTS_PER_WAVELENGTH * size)


@dataclass(frozen=True)
class SimulationResult:
    """Per-pressure statistics over realisations (SI units). Arrays have one entry per pressure.

    ``*_std`` are standard deviations over realisations (ddof = 1; NaN with fewer than two values).
    ``leak_rate`` averages all realisations (a blocked one leaks 0); ``alpha`` averages the
    percolating ones only (NaN where none percolates). ``leak_rate_critical_junction`` is the
    critical-junction prediction with α = 1 for the same (possibly cut) spectrum.
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
    flow_method: str = "auto",
    progress: Callable[[int], None] | None = None,
    memory_limit: float | None = None,
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
        Called with the number of finished (realisation, pressure) steps since the last call.
    """

    if not isinstance(grid, (int, np.integer)) or grid < 16 or grid % 2:
        raise InputError("grid", grid, "must be an even integer >= 16")
    if not isinstance(realizations, (int, np.integer)) or realizations < 1:
        raise InputError("realizations", realizations, "must be a whole number >= 1")
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "must be a whole number >= 0")
    numerics.check_memory(grid, "contact", available=memory_limit)
    numerics.check_memory(grid, "flow", available=memory_limit)

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

    theory = predict(replace(sim_case, alpha=1.0), squeeze_pressure=pressures)
    contact_theory = sim_case.contact().area(sim_case.spectrum.q_max / sim_case.q0, pressures)

    n_p = pressures.size
    area = np.zeros((realizations, n_p))
    gap = np.zeros((realizations, n_p))
    perc = np.zeros((realizations, n_p), dtype=bool)
    q_seal = np.zeros((realizations, n_p))
    thresholds = np.full(realizations, np.nan)
    contact_maps: dict[int, NDArray[np.bool_]] = {}
    fields = Path(fields_dir) if fields_dir is not None else None

    for r in range(realizations):
        h = synthesize(spectrum, int(grid), size, seed=np.random.default_rng([int(seed), r]))
        results = numerics.solve_contact_sweep(h, size, case.e_star, pressures, tol=contact_tol)
        for i, res in enumerate(results):
            flow = numerics.solve_flow(res.gap, size, eta, dp, contact=res.contact, method=flow_method)
            area[r, i] = res.contact_area
            gap[r, i] = res.mean_gap
            perc[r, i] = flow.percolates
            q_seal[r, i] = aspect * flow.flux
            if r == 0:
                contact_maps[i] = res.contact.copy()
            if fields is not None:
                with atomic_write(fields / f"r{r}-p{i}.npz") as tmp:
                    with open(tmp, "wb") as fh:
                        np.savez_compressed(fh, height=h, gap=res.gap, pressure=res.pressure, size=np.float64(size))
            if progress is not None:
                progress(1)
        if threshold:
            thresholds[r] = _threshold(numerics, h, size, case.e_star, pressures, perc[r], area[r], notes, r)

    area_m, area_s = _mean_std(area)
    gap_m, gap_s = _mean_std(gap)
    q_m, q_s = _mean_std(q_seal)
    q_cj = theory.leak_rate
    with np.errstate(invalid="ignore", divide="ignore"):
        alpha_r = np.where(perc & np.isfinite(q_cj)[None, :], q_seal / q_cj[None, :], np.nan)
    alpha_m, alpha_s = _mean_std(alpha_r)
    thr_m, thr_s = _mean_std(thresholds[:, None])
    spectrum_note = (f"{spectrum.label or case.spectrum_note}: h_rms = {spectrum.h_rms * 1e6:.4g} µm over "
                     f"q = {spectrum.q_min:.4g} .. {spectrum.q_max:.4g} 1/m")
    if threshold and np.isnan(thresholds).all():
        notes.append("no percolation threshold found (see the notes above)")
    return SimulationResult(
        squeeze_pressure=pressures, pressure_difference=dp, relative_contact_area=area_m,
        relative_contact_area_std=area_s, relative_contact_area_theory=contact_theory, mean_gap=gap_m,
        mean_gap_std=gap_s, percolating_fraction=perc.mean(axis=0), leak_rate=q_m, leak_rate_std=q_s,
        leak_rate_critical_junction=q_cj, alpha=alpha_m, alpha_std=alpha_s,
        percolation_threshold=float(thr_m[0]), percolation_threshold_std=float(thr_s[0]), grid=int(grid),
        realizations=int(realizations), seed=int(seed), size=size, q_cut=cut_at, notes=tuple(notes),
        spectrum_note=spectrum_note, contact_maps=contact_maps,
        per_realization={"relative_contact_area": area, "mean_gap": gap, "percolates": perc,
                         "leak_rate": q_seal, "alpha": alpha_r, "percolation_threshold": thresholds},
    )


def _threshold(numerics, h, size, e_star, pressures, perc, area, notes, r) -> float:
    """Contact area where the fluid stops spanning, bracketed from the sweep (expanded if needed)."""
    spanning = pressures[perc]
    blocked = pressures[~perc]
    p_lo = spanning.max() if spanning.size else pressures[0] / 4.0
    later_blocked = blocked[blocked > p_lo]
    p_hi = later_blocked.min() if later_blocked.size else None
    # expand the bracket upwards (at most 6 steps of 3x) when the sweep never blocked
    tries = 0
    while p_hi is None and tries < 6:
        candidate = p_lo * 3.0 ** (tries + 1)
        res = numerics.solve_contact(h, size, e_star, candidate)
        if not numerics.spans(~res.contact):
            p_hi = candidate
        tries += 1
    if p_hi is None:
        notes.append(f"realisation {r}: the fluid still spans at {p_lo * 3 ** 6:.4g} Pa; no threshold found")
        return float("nan")
    if not spanning.size:
        res = numerics.solve_contact(h, size, e_star, p_lo)
        if not numerics.spans(~res.contact):
            notes.append(f"realisation {r}: the fluid does not span even at {p_lo:.4g} Pa; no threshold found")
            return float("nan")
    th = numerics.percolation_threshold(h, size, e_star, p_lo=float(p_lo), p_hi=float(p_hi), rel_tol=1e-2)
    return th.contact_area
