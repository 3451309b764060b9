"""Convergence and validation study of the numerically exact route: ``sealeak simulate --grid 64,128,256``.

The same case is simulated (:func:`sealeak.cases.simulation.simulate`) at several grids N on the same square
of side L and with the same seed, so the lattice spacing a = L/N shrinks from grid to grid (and, at a fixed
L, the finer grid also resolves finer roughness: the spectrum is cut at q = 2πN/(4L),
:func:`~sealeak.cases.simulation.resolved_spectrum_cut`). Per grid the study forms the mean of α (per
squeeze pressure), of the relative contact area A/A0 and of the percolation threshold, each with its
standard error sd/√n; it extrapolates α and the threshold to the continuum a → 0 by weighted least
squares in X(a) = X∞ + c·a^p (:func:`extrapolate`; docs/theory.md §6.8), compares the threshold with
the published values for self-affine surfaces (:data:`PUBLISHED_THRESHOLDS`), and says in plain sentences
where the numbers cannot carry what they seem to claim (too few realisations, a spread larger than the
difference, a system too small or too coarse, an extrapolation that rests on too little).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import optimize, stats

from ..errors import InputError
from ..io.quantities import quantity
from .model import Case
from .notes import Note, NoteLike
from .options import parse_grid_list
from .simulation import JUNCTION_CELLS, SimulationResult, simulate

__all__ = ["Extrapolation", "GridStatistics", "ThresholdComparison", "ConvergenceStudy", "standard_error",
           "extrapolate", "convergence_study", "analyse_convergence", "PUBLISHED_THRESHOLDS", "MIN_REALIZATIONS",
           "FIT_EXPONENT_FROM", "parse_grid_list"]

FloatArray = NDArray[np.float64]

#: Published relative contact area at which the non-contact (fluid) area stops percolating, for self-affine
#: surfaces (fine resolution, large systems, Hurst exponents about 0.3-0.8): (source, value).
PUBLISHED_THRESHOLDS: tuple[tuple[str, float], ...] = (
    ("Dapp et al., PRL 108 (2012) 244301", 0.42),
    ("Wang & Müser, arXiv:2010.13470", 0.415),
)
#: Fewer realisations per grid than this: the standard errors are themselves too uncertain to be used.
MIN_REALIZATIONS = 4
#: From this many grids on, the exponent p of X(a) = X∞ + c·a^p is fitted; below, p = 1.
FIT_EXPONENT_FROM = 4
#: Bounds of a fitted exponent p.
EXPONENT_BOUNDS = (0.2, 4.0)
#: An extrapolation whose χ² has a p-value below this does not fit the grids.
CHI2_P_VALUE = 1e-3
#: The system should span at least this many roll-off wavelengths for the threshold to be a bulk value.
MIN_ROLLOFF_WAVELENGTHS = 4.0


def standard_error(values: Any) -> tuple[float, float, int]:
    """(mean, standard error, n) of the finite ``values``: se = sd/√n with sd of ddof = 1 (NaN for n < 2)."""
    v = np.asarray(values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    n = int(v.size)
    if n == 0:
        return float("nan"), float("nan"), 0
    mean = float(v.mean())
    se = float(np.std(v, ddof=1) / np.sqrt(n)) if n > 1 else float("nan")
    return mean, se, n


@dataclass(frozen=True, kw_only=True)
class Extrapolation:
    """X(a) = X∞ + c·a^p fitted to (a_i, X_i ± s_i) by weighted least squares (docs/theory.md §6.8).

    Attributes
    ----------
    value, stderr
        X∞, the continuum limit a → 0, and its standard error: from the fit's covariance (AᵀWA)⁻¹,
        multiplied by √(χ²/dof) when that exceeds 1 (the scatter is larger than the s_i say).
    stderr_unscaled
        The standard error from the s_i alone (never rescaled).
    slope
        c, in units of X per m^p (a in m).
    exponent, exponent_stderr
        p, and its standard error (NaN when p was fixed).
    exponent_fitted
        Whether p was fitted (from :data:`FIT_EXPONENT_FROM` grids on) or fixed.
    chi2, dof
        χ² = Σ w_i r_i² of the fit and its degrees of freedom (points − parameters).
    weighted
        False when some s_i was missing or zero: then every point has the same weight and the standard
        error comes from the scatter about the fit alone (NaN without degrees of freedom).
    points
        The number of grids fitted.
    monotonic
        Whether X changes in one direction from grid to grid.
    """

    value: float = quantity("1", "extrapolated continuum limit X∞ (α or the percolation threshold)")
    stderr: float = quantity("1", "standard error of X∞")
    stderr_unscaled: float
    slope: float = quantity("1/m^exponent", "c of X(a) = X∞ + c·a^p, X per m^p")
    exponent: float = quantity("1", "p of X(a) = X∞ + c·a^p")
    exponent_stderr: float
    exponent_fitted: bool
    chi2: float
    dof: int
    weighted: bool
    points: int
    monotonic: bool

    @property
    def chi2_reduced(self) -> float:
        """χ²/dof (NaN without degrees of freedom)."""
        return self.chi2 / self.dof if self.dof > 0 else float("nan")

    @property
    def p_value(self) -> float:
        """The probability of a χ² at least this large if the model held and the s_i were right (NaN if dof = 0)."""
        return float(stats.chi2.sf(self.chi2, self.dof)) if self.dof > 0 and self.weighted else float("nan")


def _linear_fit(s: FloatArray, x: FloatArray, w: FloatArray, p: float) -> tuple[FloatArray, FloatArray, float]:
    """WLS of x = b0 + b1·s^p: (coefficients, (AᵀWA)⁻¹, χ²)."""
    design = np.column_stack([np.ones_like(s), s**p])
    normal = design.T @ (w[:, None] * design)
    cov = np.linalg.inv(normal)
    beta = cov @ (design.T @ (w * x))
    r = x - design @ beta
    return beta, np.asarray(cov, dtype=float), float(np.sum(w * r**2))


def extrapolate(spacing: Sequence[float] | FloatArray, values: Sequence[float] | FloatArray,
                stderr: Sequence[float] | FloatArray, exponent: float | None = None) -> Extrapolation:
    """Fit X(a) = X∞ + c·a^p to the grids' values by weighted least squares; X∞ is the continuum limit.

    Weights w_i = 1/s_i². With p fixed (``exponent``, else 1 below :data:`FIT_EXPONENT_FROM` points) the
    model is linear in (X∞, c) and Cov = (AᵀWA)⁻¹ with rows A_i = (1, a_i^p); with p fitted (``exponent``
    None and at least :data:`FIT_EXPONENT_FROM` points), p minimises χ² within :data:`EXPONENT_BOUNDS`
    and Cov = (JᵀWJ)⁻¹ with J_i = (1, a_i^p, c a_i^p ln a_i) (Gauss–Newton, linearised at the optimum).
    The reported standard error is √Cov₀₀ times √(χ²/dof) when χ²/dof > 1 (docs/theory.md §6.8).
    If any s_i is missing or not positive, all weights are 1 and Cov is scaled by χ²/dof.

    Parameters
    ----------
    spacing:
        Lattice spacings a_i = L/N_i (m), all different and positive.
    values:
        The grids' X_i (finite).
    stderr:
        Their standard errors s_i.
    exponent:
        p to use; None: fitted from :data:`FIT_EXPONENT_FROM` points on, else 1.
    """
    a = np.asarray(spacing, dtype=float)
    x = np.asarray(values, dtype=float)
    se = np.asarray(stderr, dtype=float)
    if a.size < 2 or a.size != x.size or a.size != se.size:
        raise ValueError("extrapolate needs at least two grids, with one value and one standard error each")
    if not (np.all(a > 0) and np.all(np.isfinite(x)) and np.unique(a).size == a.size):
        raise ValueError("spacings must be distinct and positive and values finite")
    order = np.argsort(a)
    a, x, se = a[order], x[order], se[order]
    weighted = bool(np.all(np.isfinite(se) & (se > 0)))
    w = 1.0 / se**2 if weighted else np.ones_like(x)
    scale = float(a.max())
    s = a / scale  # dimensionless, in (0, 1]: keeps the normal equations well conditioned
    fit_p = exponent is None and a.size >= FIT_EXPONENT_FROM
    p = 1.0 if exponent is None else float(exponent)
    if fit_p:
        p, beta, cov, chi2 = _fit_exponent(s, x, w)
        params = 3
    else:
        beta, cov, chi2 = _linear_fit(s, x, w, p)
        params = 2
    dof = int(a.size - params)
    unscaled = float(np.sqrt(cov[0, 0]))
    if not weighted:
        factor = chi2 / dof if dof > 0 else float("nan")
        cov = cov * factor
    elif dof > 0 and chi2 / dof > 1.0:
        cov = cov * (chi2 / dof)
    diffs = np.diff(x)
    monotonic = bool(np.all(diffs >= 0) or np.all(diffs <= 0))
    return Extrapolation(
        value=float(beta[0]), stderr=float(np.sqrt(cov[0, 0])), stderr_unscaled=unscaled if weighted else float("nan"),
        slope=float(beta[1] / scale**p), exponent=float(p),
        exponent_stderr=float(np.sqrt(cov[2, 2])) if fit_p else float("nan"), exponent_fitted=fit_p,
        chi2=chi2, dof=dof, weighted=weighted, points=int(a.size), monotonic=monotonic)


def _fit_exponent(s: FloatArray, x: FloatArray, w: FloatArray) -> tuple[float, FloatArray, FloatArray, float]:
    """(p, (X∞, k), Cov of (X∞, k, p), χ²) of x = X∞ + k·s^p, p within :data:`EXPONENT_BOUNDS`.

    χ²(p) is minimised with X∞ and k solved linearly at every p (variable projection), first on a grid of
    p, then by a bounded scalar search around its best point and a Gauss–Newton polish of all three.
    """
    lo, hi = EXPONENT_BOUNDS

    def chi2_at(p: float) -> float:
        return _linear_fit(s, x, w, p)[2]

    trial = np.linspace(lo, hi, 96)
    k = int(np.argmin([chi2_at(p) for p in trial]))
    bracket = (trial[max(k - 1, 0)], trial[min(k + 1, trial.size - 1)])
    p = float(optimize.minimize_scalar(chi2_at, bounds=bracket, method="bounded",
                                       options={"xatol": 1e-12}).x)
    beta, _, _ = _linear_fit(s, x, w, p)
    theta = np.array([beta[0], beta[1], p])
    sqrt_w = np.sqrt(w)
    for _ in range(20):  # Gauss-Newton on (X∞, k, p); stops when the step no longer lowers χ²
        x0, kk, pp = theta
        sp = s**pp
        r = sqrt_w * (x - x0 - kk * sp)
        jac = sqrt_w[:, None] * np.column_stack([np.ones_like(s), sp, kk * sp * np.log(s)])
        step, *_ = np.linalg.lstsq(jac, r, rcond=None)
        new = theta + step
        new[2] = min(max(new[2], lo), hi)
        if float(np.sum((sqrt_w * (x - new[0] - new[1] * s ** new[2])) ** 2)) > float(np.sum(r**2)):
            break
        theta = new
        if np.all(np.abs(step) <= 1e-15 * np.maximum(1.0, np.abs(theta))):
            break
    x0, kk, pp = theta
    sp = s**pp
    jac = np.column_stack([np.ones_like(s), sp, kk * sp * np.log(s)])
    normal = jac.T @ (w[:, None] * jac)
    cov = np.linalg.pinv(normal)
    chi2 = float(np.sum(w * (x - x0 - kk * sp) ** 2))
    return float(pp), theta[:2], cov, chi2


@dataclass(frozen=True, kw_only=True)
class GridStatistics:
    """One grid of a study: means and standard errors over its realisations (SI units, arrays per pressure).

    ``alpha`` is the mean over the percolating realisations (``alpha_count`` of them), ``alpha_stderr``
    sd/√n; ``relative_contact_area`` over all realisations; ``alpha_resolved`` whether the theory's
    critical wavelength spans at least :data:`~sealeak.cases.simulation.JUNCTION_CELLS` cells (else α
    reflects the grid and is left out of the extrapolation). ``threshold`` is the mean relative contact
    area at which the non-contact area stops percolating, over ``threshold_count`` realisations.
    """

    grid: int
    spacing: float = quantity("m", "grid spacing a = size/grid")
    realizations: int
    alpha: FloatArray
    alpha_stderr: FloatArray = quantity("1", "standard error of α over the grid's percolating realisations")
    alpha_count: NDArray[np.int64] = quantity("1", "percolating realisations α is the mean of")
    alpha_resolved: NDArray[np.bool_]
    relative_contact_area: FloatArray
    relative_contact_area_stderr: FloatArray = quantity("1", "standard error of A/A0")
    threshold: float = quantity("1", "A/A0 at which the non-contact area stops percolating, mean over realisations",
                                key="percolation_threshold")
    threshold_stderr: float = quantity("1", "standard error of the percolation threshold",
                                       key="percolation_threshold_stderr")
    threshold_count: int = quantity("1", "realisations with a percolation threshold", key="percolation_threshold_count")
    q_cut: float | None


@dataclass(frozen=True)
class ThresholdComparison:
    """Our threshold (finest grid or extrapolated) beside a published value: ``difference`` in units of our se."""

    ours_label: str
    ours: float
    ours_stderr: float
    source: str
    published: float

    @property
    def difference(self) -> float:
        """(ours − published)/se (NaN without a standard error)."""
        if not (np.isfinite(self.ours_stderr) and self.ours_stderr > 0):
            return float("nan")
        return (self.ours - self.published) / self.ours_stderr


@dataclass(frozen=True, kw_only=True)
class ConvergenceStudy:
    """The result of a convergence study: the runs, their statistics, the extrapolations, the comparison, the flags.

    ``results`` are the grids' :class:`~sealeak.cases.simulation.SimulationResult` (increasing N),
    ``statistics`` their :class:`GridStatistics`. ``alpha_extrapolation`` has one entry per squeeze
    pressure (None where fewer than two grids give a resolved α), ``alpha_converged`` whether the finest
    two grids with a resolved α agree within their combined standard error √(s₁² + s₂²) (None when that
    cannot be judged); the same for the threshold. ``comparison`` sets the finest grid's and the
    extrapolated threshold beside :data:`PUBLISHED_THRESHOLDS`; ``conditions`` says under which conditions
    (Hurst exponent, system size, resolution); ``flags`` say what the numbers cannot carry (notes, worded by
    :mod:`sealeak.render.notes`).
    """

    grids: tuple[int, ...]
    size: float
    squeeze_pressure: FloatArray
    results: tuple[SimulationResult, ...]
    statistics: tuple[GridStatistics, ...]
    alpha_extrapolation: tuple[Extrapolation | None, ...]
    alpha_converged: tuple[bool | None, ...]
    threshold_extrapolation: Extrapolation | None
    threshold_converged: bool | None
    comparison: tuple[ThresholdComparison, ...]
    hurst: float
    rolloff_wavelengths: float
    conditions: str
    flags: tuple[NoteLike, ...]


def convergence_study(case: Case, grids: Iterable[int], *, realizations: int, seed: int, threshold: bool = True,
                      runner_for: Callable[[int], Any] | None = None,
                      progress_for: Callable[[int], Callable[[int], None] | None] | None = None,
                      simulate_grid: Callable[..., SimulationResult] = simulate, device: str = "cpu") -> ConvergenceStudy:
    """Simulate ``case`` at every grid (same square, realisations and seed) and analyse the convergence.

    Each grid is an ordinary :func:`~sealeak.cases.simulation.simulate` run, so its numbers are exactly
    those of a single-grid run with the same seed. ``runner_for(N)`` gives the runner of grid N (e.g.
    :func:`sealeak.cases.ensemble.make_runner` with a store of its own), ``progress_for(N)`` its progress
    callback for the plain loop; ``device`` where each grid's synthesis and contact run (``"cpu"``, ``"cuda"``).
    """
    grids = parse_grid_list(list(grids), "grid")
    if len(grids) < 2:
        raise InputError("grid", list(grids), "a convergence study needs at least two grids")
    results = []
    for n in grids:
        runner = runner_for(n) if runner_for is not None else None
        progress = progress_for(n) if progress_for is not None and runner is None else None
        results.append(simulate_grid(case, grid=n, realizations=realizations, seed=seed, threshold=threshold,
                                     runner=runner, progress=progress, device=device))
    return analyse_convergence(case, results)


def _grid_statistics(res: SimulationResult) -> GridStatistics:
    per = res.per_realization
    n_p = res.squeeze_pressure.size
    alpha = np.full(n_p, np.nan)
    alpha_se = np.full(n_p, np.nan)
    alpha_n = np.zeros(n_p, dtype=np.int64)
    area = np.full(n_p, np.nan)
    area_se = np.full(n_p, np.nan)
    for i in range(n_p):
        alpha[i], alpha_se[i], alpha_n[i] = standard_error(per["alpha"][:, i])
        area[i], area_se[i], _ = standard_error(per["relative_contact_area"][:, i])
    cells = res.junction_cells if res.junction_cells.size else np.full(n_p, np.nan)
    resolved = np.isfinite(cells) & (cells >= JUNCTION_CELLS)
    th, th_se, th_n = standard_error(per.get("percolation_threshold", np.full(res.realizations, np.nan)))
    return GridStatistics(grid=res.grid, spacing=res.size / res.grid, realizations=res.realizations, alpha=alpha,
                          alpha_stderr=alpha_se, alpha_count=alpha_n, alpha_resolved=resolved,
                          relative_contact_area=area, relative_contact_area_stderr=area_se, threshold=th,
                          threshold_stderr=th_se, threshold_count=th_n, q_cut=res.q_cut)


def _agree(x: Sequence[float], se: Sequence[float]) -> bool | None:
    """Whether the last two values agree within √(se₁² + se₂²); None without two values with standard errors."""
    if len(x) < 2:
        return None
    s = float(np.hypot(se[-1], se[-2]))
    if not np.isfinite(s):
        return None
    return bool(abs(x[-1] - x[-2]) <= s)


def _fit(spacing: list[float], x: list[float], se: list[float]) -> Extrapolation | None:
    return extrapolate(spacing, x, se) if len(x) >= 2 else None


def _spectrum_shape(case: Case, q_top: float) -> tuple[float, float]:
    """(H, L/λ_r): the Hurst exponent fitted to C(q) between the roll-off and ``q_top``, and roll-off wavelengths in L.

    The roll-off q_r is taken as the largest wavevector at which C(q) is still at least 90 % of its maximum
    (3 % above the knee of a self-affine C ∝ q^(−2(1+H))); H from the slope −2(1 + H) of log C against
    log q above it (docs/theory.md §1.4). A spectrum that falls from its first wavevector on has q_r = q_min:
    the square then holds about one roll-off wavelength.
    """
    spec = case.spectrum
    q, c = spec.sample(400)
    q_r = float(q[c >= 0.9 * c.max()].max())
    keep = (q >= q_r) & (q <= q_top)
    hurst = float("nan")
    if keep.sum() >= 2 and q[keep].max() > 2.0 * q_r:
        slope = np.polyfit(np.log(q[keep]), np.log(c[keep]), 1)[0]
        hurst = float(-slope / 2.0 - 1.0)
    return hurst, float(case.square_side * q_r / (2.0 * np.pi))


def analyse_convergence(case: Case, results: Sequence[SimulationResult]) -> ConvergenceStudy:
    """Statistics, extrapolations, the comparison with :data:`PUBLISHED_THRESHOLDS` and the flags of a set of runs.

    ``results`` are runs of the same case at different grids (any order; sorted by N here).
    """
    runs = tuple(sorted(results, key=lambda r: r.grid))
    stats_ = tuple(_grid_statistics(r) for r in runs)
    grids = tuple(r.grid for r in runs)
    pressures = runs[0].squeeze_pressure
    spacing = [g.spacing for g in stats_]
    realizations = min(r.realizations for r in runs)
    flags: list[NoteLike] = []

    alpha_fits: list[Extrapolation | None] = []
    alpha_ok: list[bool | None] = []
    dropped = 0
    for i in range(pressures.size):
        use = [k for k, g in enumerate(stats_) if np.isfinite(g.alpha[i]) and g.alpha_resolved[i]]
        dropped += sum(1 for g in stats_ if np.isfinite(g.alpha[i]) and not g.alpha_resolved[i])
        xs = [stats_[k].alpha[i] for k in use]
        ses = [stats_[k].alpha_stderr[i] for k in use]
        alpha_fits.append(_fit([spacing[k] for k in use], xs, ses))
        alpha_ok.append(_agree(xs, ses))

    th_use = [k for k, g in enumerate(stats_) if np.isfinite(g.threshold)]
    th_x = [stats_[k].threshold for k in th_use]
    th_se = [stats_[k].threshold_stderr for k in th_use]
    th_fit = _fit([spacing[k] for k in th_use], th_x, th_se)
    th_ok = _agree(th_x, th_se)

    comparison: list[ThresholdComparison] = []
    if th_use:
        fine = stats_[th_use[-1]]
        for src, val in PUBLISHED_THRESHOLDS:
            comparison.append(ThresholdComparison(f"finest grid (N = {fine.grid})", fine.threshold,
                                                  fine.threshold_stderr, src, val))
        if th_fit is not None:
            for src, val in PUBLISHED_THRESHOLDS:
                comparison.append(ThresholdComparison("extrapolated (a → 0)", th_fit.value, th_fit.stderr, src, val))

    finest = runs[-1]
    hurst, n_rolloff = _spectrum_shape(case, case.spectrum.q_max)
    cut = (f"resolved up to q = {finest.q_cut:.4g} 1/m, below the spectrum's cut-off {case.spectrum.q_max:.4g} 1/m"
           if finest.q_cut is not None else "resolving the whole spectrum")
    conditions = (f"ours: one square of side L = {finest.size * 1e3:.4g} mm = {n_rolloff:.3g} roll-off wavelengths, "
                  f"H ≈ {hurst:.2g}, finest grid {finest.grid}x{finest.grid} ({cut}), {realizations} realisation(s) "
                  "per grid, fluid spanning inlet to outlet (periodic across); published: fine resolution, large "
                  "systems, H about 0.3-0.8, the same quantity (the contact area at which the non-contact area "
                  "stops percolating)")

    # ---------------------------------------------------------------- flags
    if realizations < 2:
        flags.append(f"only {realizations} realisation per grid: there is no standard error at all, so no difference "
                     "between grids or from the published threshold can be judged; run --realizations 8 or more.")
    elif realizations < MIN_REALIZATIONS:
        flags.append(f"only {realizations} realisations per grid: a standard error from so few values is itself "
                     "uncertain by 50 % or more, so the ± and the verdicts below are rough; run --realizations 8 or "
                     "more for error bars worth the name.")
    if n_rolloff < MIN_ROLLOFF_WAVELENGTHS:
        flags.append(f"the square is only {n_rolloff:.2g} roll-off wavelengths wide (fewer than "
                     f"{MIN_ROLLOFF_WAVELENGTHS:g}): each realisation holds few independent large asperities, so the "
                     "threshold and α scatter strongly and may be shifted by the finite system size; a larger "
                     "square (smaller q0) would tell.")
    if finest.q_cut is not None:
        flags.append(f"even the finest grid ({finest.grid}x{finest.grid}) resolves q only up to {finest.q_cut:.4g} 1/m, "
                     f"below the spectrum's cut-off {case.spectrum.q_max:.4g} 1/m: every grid simulates a smoother "
                     "surface than the case's, and refining the grid at a fixed square adds roughness as well as "
                     "resolution, so the extrapolation a → 0 is that of this sequence of cut spectra.")
    if dropped:
        flags.append(f"{dropped} α value(s) where the theory's critical wavelength spans fewer than {JUNCTION_CELLS} "
                     "cells (marked * per grid) were left out of the extrapolation: they reflect the grid more than "
                     "the seal.")
    if th_x:
        flags.extend(_fit_flags("threshold", th_fit, th_x, th_se))
    else:
        flags.append("no percolation threshold at any grid (the search was skipped with --no-threshold, or found none: "
                     "see the notes), so there is nothing to extrapolate or to compare with the published values.")
    if th_ok is False:
        flags.append(Note("extrapolation_doubtful", {"kind": "diverging", "quantity": "threshold"}))
    grouped: dict[str, list[float]] = {}
    for i in range(pressures.size):
        fitted = [g for g in stats_ if np.isfinite(g.alpha[i]) and g.alpha_resolved[i]]
        kinds = _fit_problems(alpha_fits[i], [g.alpha[i] for g in fitted], [g.alpha_stderr[i] for g in fitted])
        for kind in kinds + (["diverging"] if alpha_ok[i] is False else []):
            grouped.setdefault(kind, []).append(float(pressures[i]))
    for kind, ps in grouped.items():
        flags.append(Note("extrapolation_doubtful", {"kind": kind, "quantity": "alpha", "pressures": tuple(ps)}))
    if comparison and abs(comparison[0].difference) >= 2.0:
        first = comparison[0]
        q_top = finest.q_cut if finest.q_cut is not None else case.spectrum.q_max
        decades = np.log10(q_top * case.square_side / (2.0 * np.pi) / max(n_rolloff, 1e-300))
        why = []
        if finest.q_cut is not None:
            why.append("the finest grid cuts the spectrum")
        why.append(f"the resolved self-affine range spans {decades:.2g} decades of q")
        why.append(f"the square holds {n_rolloff:.3g} roll-off wavelengths")
        flags.append(f"the finest grid's threshold {first.ours:.3f} is {first.difference:+.2g} standard errors from "
                     f"{first.source.split(',')[0]}'s {first.published:g}. Their value is for fine resolution, many "
                     f"decades of self-affine roughness and large systems; here {', '.join(why)}: refine and enlarge "
                     "before reading the difference as a disagreement with the published value.")
    if th_use and th_fit is not None and np.isfinite(th_fit.stderr):
        for src, val in PUBLISHED_THRESHOLDS[:1]:
            if abs(th_fit.value - val) < th_fit.stderr:
                flags.append(f"the extrapolated threshold differs from the published {val:g} by less than its standard "
                             f"error ({th_fit.stderr:.2g}): consistent, but at this precision not a confirmation.")
    return ConvergenceStudy(grids=grids, size=finest.size, squeeze_pressure=pressures, results=runs, statistics=stats_,
                            alpha_extrapolation=tuple(alpha_fits), alpha_converged=tuple(alpha_ok),
                            threshold_extrapolation=th_fit, threshold_converged=th_ok, comparison=tuple(comparison),
                            hurst=hurst, rolloff_wavelengths=n_rolloff, conditions=conditions, flags=tuple(flags))


def _fit_problems(fit: Extrapolation | None, xs: list[float], ses: list[float]) -> list[str]:
    """Why an extrapolation is not to be trusted: the ``kind`` of an ``extrapolation_doubtful`` note (none if nothing is wrong)."""
    if fit is None:
        return ["none"] if len(xs) == 1 else []
    out: list[str] = []
    if fit.points == 2:
        out.append("two")
    if not fit.monotonic:
        out.append("non-monotonic")
    if np.isfinite(fit.p_value) and fit.p_value < CHI2_P_VALUE:
        out.append("chi2")
    spread = float(np.hypot(ses[-1], ses[0]))
    if np.isfinite(spread) and abs(xs[-1] - xs[0]) < spread:
        out.append("unresolved")
    return out


def _fit_flags(name: str, fit: Extrapolation | None, xs: list[float], ses: list[float]) -> list[Note]:
    """Notes on why the extrapolation of ``name`` ("threshold") is not to be trusted (none if nothing is wrong)."""
    if fit is None:
        return [Note("extrapolation_doubtful", {"kind": "none", "quantity": name})]
    return [Note("extrapolation_doubtful", {"kind": k, "quantity": name, "chi2": fit.chi2_reduced})
            for k in _fit_problems(fit, xs, ses)]
