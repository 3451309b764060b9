"""The numerically exact route on measured or given height maps: the map itself is the surface.

:func:`simulate` draws Gaussian random surfaces from C(q); a measured map (skewed, worn, plateau-honed)
is not one of them, and its height distribution is what the exact route is for. :func:`simulate_maps`
runs the same ensemble pipeline (:func:`sealeak.cases.pipeline.run_ensemble`, the :class:`MapSquares`
geometry) with one realisation per map (per file of a case, or per sub-window):

1. the map is cut to its central square (the solver's domain is square), optionally into k × k
   sub-windows; undefined points (NaN) are refused, not filled;
2. it is levelled: the least-squares plane is removed (a periodic map: its mean only);
3. a non-periodic map (every measured one) is **mirrored**: the even reflection of the square to a
   2L × 2L square is periodic and continuous, so the FFT contact solver and the periodic-in-y flow
   see no step at the edges, and every simulated height is a measured height (the height
   distribution, the reason for this route, is kept). The artefact, flagged in the result: slope kinks
   along the mirror lines, and a domain that holds the map four times (no new statistics; the fluid
   crosses the map and its mirror image). Tapering to the mean (a window) was not chosen: it adds a
   flat rim that opens a bypass channel around the map; embedding in a non-periodic solver does not
   exist for the square;
4. the (mirrored) square is resampled to the solver's N × N grid in Fourier space
   (:func:`scipy.signal.resample`: band-limited; downsampling drops the wavelengths the grid cannot
   hold, upsampling adds none); without a grid, N is the map's own points per side (doubled when
   mirrored, rounded up to even) and nothing is resampled; then it is low-pass filtered at the end of
   the map's reliable C(q) or at 4 points per wavelength, whichever is lower: the band of the theories;
5. contact, flow and the percolation threshold as for random surfaces (:func:`sealeak.cases.simulation.run_task`);
6. α against both theories computed from the map's own C(q) (:func:`sealeak.topography.analyze` of the
   same square, with its default analysis options but the reliable range from q = 2π/L), cut to what
   the grid resolves: α_cj = Q/Q_cj(α = 1) and α_em = Q/Q_em (Bruggeman). The map's
   skewness and kurtosis are the topography module's (:func:`sealeak.topography.surface_statistics`).

Liquids and uniform seals only: a gas case or an O-ring is refused.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal

from .. import numerics
from ..errors import InputError
from ..io.quantities import quantity
from ..physics.spectrum import PowerSpectrum
from ..topography import Topography, analyze, prepare
from .builders import topography_analysis
from .model import Case
from .notes import Note, NoteLike
from .pipeline import (
    FlowMethod,
    Flows,
    Records,
    RunSettings,
    TaskRecord,
    cut_spectrum,
    mean_std,
    ratio,
    resolved_spectrum_cut,
    run_ensemble,
)
from .prediction import predict_effective_medium
from .schema import Section
from .simulation import EnsembleSpec, EnsembleTask, SweepRecord, ThresholdRecord, _theory_leak_rate, _threshold_anchor

__all__ = ["MapSimulationResult", "MapInfo", "MapSquares", "MapSpec", "simulate_map", "simulate_maps",
           "solver_map", "case_maps", "map_windows", "MIN_MAP_POINTS", "MAX_WINDOWS"]

FloatArray = NDArray[np.float64]

#: Points per side a map (or each sub-window) needs at least.
MIN_MAP_POINTS = 16
#: Sub-windows per side a map may be cut into.
MAX_WINDOWS = 8
#: Relative difference of the two sides (or pixel sizes) below which a map counts as square.
_SQUARE_TOL = 1e-6


@dataclass(frozen=True, kw_only=True)
class MapInfo:
    """One map as simulated (SI units).

    ``label`` names it (file, window), ``side`` L (m) is its square's side, ``points`` the points across it
    as measured, ``domain`` the solver's square (2L when mirrored), ``periodic`` whether it was taken as
    periodic (else levelled and mirrored), ``skewness`` and ``kurtosis`` of its levelled heights
    (kurtosis 3 for Gaussian heights), ``h_rms`` (m) of its levelled heights, ``spectrum`` its own C(q)
    cut to what the grid resolves, ``notes`` what was done to it.
    """

    label: str
    side: float
    points: int
    domain: float
    periodic: bool
    skewness: float
    kurtosis: float
    h_rms: float
    spectrum: PowerSpectrum = field(repr=False)
    heights: FloatArray = field(repr=False)
    notes: tuple[NoteLike, ...] = ()

    @property
    def mirrored(self) -> bool:
        """True when the map was mirrored into a periodic square (a non-periodic map)."""
        return not self.periodic


@dataclass(frozen=True, kw_only=True)
class MapSimulationResult:
    """The exact route on maps: per map ([M, n] arrays, one row per map) and over maps, per pressure (SI units).

    ``alpha`` is α_cj = Q/Q_cj(α = 1) and ``alpha_effective_medium`` α_em = Q/Q_em, each map against the
    theories of its own C(q) (NaN where the map does not percolate or the theory has no leak); their
    ``_mean``/``_std`` are over the maps where defined (std ddof = 1, NaN with fewer than two).
    ``junction_cells`` N/ζc: below :data:`~sealeak.cases.simulation.JUNCTION_CELLS` α reflects the grid
    more than the seal (a note says so).
    """

    squeeze_pressure: FloatArray = quantity("Pa", "nominal squeeze pressure P0")
    pressure_difference: float = quantity("Pa", "pressure difference across the seal")
    maps: tuple[MapInfo, ...]
    relative_contact_area: FloatArray = quantity("1", "relative contact area A/A0 of each map")
    mean_gap: FloatArray = quantity("m", "mean gap ū of each map")
    percolates: NDArray[np.bool_] = quantity("1", "whether fluid crosses each map")
    leak_rate: FloatArray = quantity("m^3/s", "simulated leak rate Q of the seal on each map")
    leak_rate_critical_junction: FloatArray = quantity("m^3/s", "critical-junction Q (α = 1) of each map's C(q)")
    leak_rate_effective_medium: FloatArray = quantity("m^3/s", "effective-medium Q of each map's C(q)")
    alpha: FloatArray = quantity("1", "α_cj = Q over the critical-junction Q")
    alpha_effective_medium: FloatArray = quantity("1", "α_em = Q over the effective-medium Q")
    alpha_mean: FloatArray = quantity("1", "α_cj, mean over the maps")
    alpha_std: FloatArray = quantity("1", "standard deviation of α_cj over the maps")
    alpha_effective_medium_mean: FloatArray = quantity("1", "α_em, mean over the maps")
    alpha_effective_medium_std: FloatArray = quantity("1", "standard deviation of α_em over the maps")
    percolation_threshold: FloatArray = quantity("1", "A/A0 at which each map stops percolating (NaN: not searched)")
    junction_cells: FloatArray = quantity("1", "grid cells across the critical wavelength λc of each map's theory")
    grid: int
    notes: tuple[NoteLike, ...] = ()


def _side_points(topo: Topography) -> tuple[float, int, int]:
    """The central square's side (m) and its points along x and y."""
    side = min(topo.size)
    dx, dy = topo.pixel_size
    return side, int(round(side / dx)), int(round(side / dy))


def solver_map(topo: Topography, grid: int | None, *, label: str = "", field_name: str = "heights") -> MapInfo:
    """``topo`` as the solver's N × N periodic heights (m, ``heights`` of the :class:`MapInfo` returned; the
    module docstring, steps 1-4).

    ``grid`` N (even, >= 16), or None for the map's own points. Refusals (InputError naming ``field_name``):
    undefined points, fewer than :data:`MIN_MAP_POINTS` points per side.
    """
    label = label or topo.source or "map"
    h = np.asarray(topo.heights, dtype=float)
    name = Path(label).name
    if np.isnan(h).any():
        raise InputError(field_name, name, f"has {int(np.isnan(h).sum())} undefined points (NaN): every height of a "
                                           "simulated map must be defined; crop the map to a fully measured window")
    side, mx, my = _side_points(topo)
    if min(mx, my) < MIN_MAP_POINTS:
        raise InputError(field_name, name, f"has {h.shape[0]}x{h.shape[1]} points: a map (or each window) needs at "
                                           f"least {MIN_MAP_POINTS} points across its square")
    notes: list[Note] = []
    square = (mx, my) == h.shape and abs(topo.size[0] - topo.size[1]) <= _SQUARE_TOL * side
    periodic = topo.periodic and square
    if topo.periodic and not square:
        notes.append(Note("map_not_square"))
    if (mx, my) != h.shape:
        x0, y0 = (h.shape[0] - mx) // 2, (h.shape[1] - my) // 2
        h = h[x0:x0 + mx, y0:y0 + my]
        notes.append(Note("map_cut_to_square", {"side": float(side), "points": (mx, my),
                                                "map_points": tuple(int(n) for n in topo.nb_grid_pts)}))
    cropped = Topography(heights=h, size=(side, side), periodic=periodic, source=label)
    analysis = analyze(cropped, fit=False, low_cut=1.0)
    flat = np.array(prepare(cropped, detrend="mean" if periodic else "plane", window="none").surface.heights)
    if periodic:
        notes.append(Note("map_mean_removed"))
    else:
        flat = np.concatenate([flat, flat[::-1]], axis=0)
        flat = np.concatenate([flat, flat[:, ::-1]], axis=1)
        notes.append(Note("map_mirrored"))
    n = flat.shape[0] + flat.shape[0] % 2 if grid is None else grid
    if flat.shape != (n, n):
        notes.append(Note("map_resampled", {"points": flat.shape, "grid": n}))
        flat = signal.resample(signal.resample(flat, n, axis=0), n, axis=1)
    domain = side if periodic else 2.0 * side
    # the band of the theories: the map's C(q) (its reliable range) cut where the grid resolves (cut_spectrum)
    q_band = min(resolved_spectrum_cut(n, domain), analysis.spectrum.q_max)
    modes = np.fft.rfft2(flat)
    modes[numerics.wavevector_grid(n, domain) > q_band] = 0.0
    flat = np.fft.irfft2(modes, s=(n, n))
    notes.append(Note("map_low_pass", {"q": float(q_band)}))
    stats = analysis.sources[0].statistics
    return MapInfo(label=label, side=side, points=int(min(mx, my)), domain=domain, periodic=periodic,
                   skewness=_value(stats.skewness), kurtosis=_value(stats.kurtosis), h_rms=_value(stats.h_rms),
                   spectrum=analysis.spectrum, heights=np.ascontiguousarray(flat), notes=tuple(notes))


def _value(x: float | None) -> float:
    return float("nan") if x is None else float(x)


def map_windows(topo: Topography, windows: int, field_name: str = "windows") -> list[Topography]:
    """The central square of ``topo`` cut into ``windows`` × ``windows`` square sub-windows (row-major order;
    ``windows = 1``: ``topo`` itself). Sub-windows are never periodic."""
    if not isinstance(windows, (int, np.integer)) or isinstance(windows, bool) or not 1 <= windows <= MAX_WINDOWS:
        raise InputError(field_name, windows, f"must be an integer from 1 to {MAX_WINDOWS} (k x k sub-windows per map)")
    if windows == 1:
        return [topo]
    side, mx, my = _side_points(topo)
    h = np.asarray(topo.heights)
    x0, y0 = (h.shape[0] - mx) // 2, (h.shape[1] - my) // 2
    wx, wy = mx // windows, my // windows
    return [Topography(heights=h[x0 + i * wx:x0 + (i + 1) * wx, y0 + j * wy:y0 + (j + 1) * wy],
                       size=(wx * topo.pixel_size[0], wy * topo.pixel_size[1]),
                       source=f"{topo.source or 'map'} [window {i + 1},{j + 1}]")
            for i in range(windows) for j in range(windows)]


@dataclass(frozen=True, kw_only=True)
class MapSpec(EnsembleSpec):
    """One map's task inputs: :class:`~sealeak.cases.simulation.EnsembleSpec` with the map's solver heights
    (m) in place of a random draw, and ``maps_digest``, the SHA-256 of every map of the run (its identity)."""

    heights: FloatArray
    maps_digest: str

    def surface(self, r: int) -> FloatArray:
        """The map's heights (m): no random draw."""
        return self.heights

    def geometry_identity(self) -> dict[str, Any]:
        """The square's inputs and the digest of all the run's maps."""
        return super().geometry_identity() | {"maps": self.maps_digest}


@dataclass(frozen=True)
class _MapPlan:
    """What :class:`MapSquares` prepares: per map its info, theory case and theories (SI units)."""

    case: Case
    pressures: FloatArray
    infos: tuple[MapInfo, ...]
    cases: tuple[Case, ...]
    q_cj: FloatArray
    q_em: FloatArray
    junction_cells: FloatArray


@dataclass(frozen=True)
class MapSquares:
    """The geometry of the map route: each map (mirrored when not periodic) a periodic square, one realisation.

    ``maps`` are the topographies, ``grid`` the solver grid asked for (None: each map's own points),
    ``threshold`` whether to search each map's percolation threshold.
    """

    maps: tuple[Topography, ...]
    grid: int | None = None
    threshold: bool = True
    field_name: str = "heights"

    def check_memory(self, grid: int, memory_limit: float | None) -> None:
        """The periodic contact problem of an N × N grid must fit in memory."""
        numerics.check_memory(grid, "contact", available=memory_limit)

    def prepare(self, case: Case, grid: int, grid_field: str, notes: list[NoteLike],
                progress: Callable[[int], None] | None) -> _MapPlan:
        """Each map on the solver grid, its own C(q) cut to the grid, both theories of it at q0 = 2π/L."""
        pressures = np.sort(np.asarray(case.squeeze_pressure, dtype=float))
        if not np.array_equal(pressures, case.squeeze_pressure):
            notes.append(Note("pressures_sorted"))
        infos, cases, q_cj, q_em, cells = [], [], [], [], []
        for topo in self.maps:
            info = solver_map(topo, grid, field_name=self.field_name)
            spectrum, cut_at, cut_notes = cut_spectrum(info.spectrum, grid, info.domain, grid_field,
                                                       "critical-junction and effective-medium")
            map_notes: list[NoteLike] = [Note("of_map", {"label": info.label, "note": n})
                                         for n in (*info.notes, *cut_notes)]
            # q0 = 2π/domain: the map's C(q) starts at 2π/L (it is zero below), so the theories are those of
            # q0 = 2π/L, and the grid cells across the critical wavelength are counted on the solver's grid
            sim_case = replace(case, spectrum=spectrum, q0=2.0 * np.pi / info.domain, alpha=1.0,
                               spectrum_note=f"{info.label}: its own C(q)")
            cj, cells_r, _, _ = _theory_leak_rate(sim_case, pressures, grid, cut_at, map_notes)
            em = predict_effective_medium(sim_case, squeeze_pressure=pressures).leak_rate
            notes.extend(map_notes)
            infos.append(replace(info, spectrum=spectrum))
            cases.append(sim_case)
            q_cj.append(cj)
            cells.append(cells_r)
            q_em.append(np.where(np.isfinite(em), em, np.nan))
        return _MapPlan(case=case, pressures=pressures, infos=tuple(infos), cases=tuple(cases), q_cj=np.array(q_cj),
                        q_em=np.array(q_em), junction_cells=np.array(cells))

    def tasks(self, plan: _MapPlan, common: RunSettings, realizations: int) -> list[EnsembleTask]:
        """Each map's sweep, then (if asked) its threshold search."""
        digest = hashlib.sha256()
        for info in plan.infos:
            digest.update(np.ascontiguousarray(info.heights).tobytes())
            digest.update(np.float64(info.domain).tobytes())
        kinds = ("sweep", "threshold") if self.threshold else ("sweep",)
        out = []
        for r, (info, sim_case) in enumerate(zip(plan.infos, plan.cases, strict=True)):
            spec = common.spec(MapSpec, spectrum=info.spectrum, size=info.domain, pressures=plan.pressures,
                               aspect=plan.case.seal.aspect_ratio, threshold_anchor=_threshold_anchor(sim_case),
                               heights=info.heights, maps_digest=digest.hexdigest())
            out += [EnsembleTask(k, r, spec) for k in kinds]
        return out

    def aggregate(self, plan: _MapPlan, records: Records, notes: list[NoteLike]) -> MapSimulationResult:
        """Per map its contact, flow and α against both theories; α's mean and spread over the maps."""
        n_p = plan.pressures.size
        flows = Flows.of(records, SweepRecord, n_p)
        thresholds = np.full(records.realizations, np.nan)
        for rec in records.of(ThresholdRecord):
            thresholds[rec.realization] = rec.threshold
            notes.extend(map(Note.of, rec.notes))
        perc = flows.percolates
        a_cj = np.vstack([ratio(perc[r:r + 1], flows.leak_rate[r:r + 1], plan.q_cj[r]) for r in range(records.realizations)])
        a_em = np.vstack([ratio(perc[r:r + 1], flows.leak_rate[r:r + 1], plan.q_em[r]) for r in range(records.realizations)])
        cj_m, cj_s = mean_std(a_cj)
        em_m, em_s = mean_std(a_em)
        return MapSimulationResult(
            squeeze_pressure=plan.pressures, pressure_difference=float(plan.case.pressure_difference), maps=plan.infos,
            relative_contact_area=flows.area, mean_gap=records.stack(SweepRecord, lambda rec: rec.mean_gap, n_p), percolates=perc,
            leak_rate=flows.leak_rate, leak_rate_critical_junction=plan.q_cj, leak_rate_effective_medium=plan.q_em,
            alpha=a_cj, alpha_effective_medium=a_em, alpha_mean=cj_m, alpha_std=cj_s, alpha_effective_medium_mean=em_m,
            alpha_effective_medium_std=em_s, percolation_threshold=thresholds, junction_cells=plan.junction_cells,
            grid=records.grid, notes=tuple(notes))


def simulate_maps(maps: Sequence[Topography], case: Case, *, grid: int | None = None, windows: int = 1,
                  threshold: bool = True, fields_dir: str | Path | None = None, contact_tol: float = 1e-8,
                  flow_method: FlowMethod = "auto", progress: Callable[[int], None] | None = None,
                  memory_limit: float | None = None, grid_name: str = "grid", field_name: str = "heights",
                  windows_name: str = "windows",
                  runner: Callable[[list[EnsembleTask]], Iterable[TaskRecord]] | None = None,
                  device: str = "cpu") -> MapSimulationResult:
    """The exact leak rate of ``case``'s seal on each of ``maps`` (module docstring), α against both theories.

    ``maps`` are height maps (:class:`sealeak.topography.Topography`, heights in m; e.g.
    :func:`sealeak.topography.read_topography`), each cut into ``windows`` × ``windows`` sub-windows
    (one realisation each); ``case`` gives the rubber (E*), the fluid, the seal's aspect ratio Ly/Lx, the
    squeeze pressures and ΔP (its spectrum and q0 are replaced by each map's own). Messages name the
    maps ``field_name``, the windows ``windows_name``. ``grid`` N (even,
    >= 16) or None: the largest map's own points per side (doubled when mirrored), so that no map is
    upsampled beyond its data. The other arguments (``device`` too) as for :func:`sealeak.cases.simulate`.
    """
    _refuse_case(case)
    items = [w for m in maps for w in map_windows(m, windows, windows_name)]
    if not items:
        raise InputError(field_name, "no maps", "at least one height map")
    if grid is None:
        sizes = [_own_points(m) for m in items]
        grid = max(MIN_MAP_POINTS, max(sizes))
        grid_name = f"{grid_name} (from the map's {grid} points)"
    return run_ensemble(MapSquares(tuple(items), grid, threshold, field_name), case, grid=grid,
                        realizations=len(items), seed=0, grid_field=grid_name, fields_dir=fields_dir,
                        contact_tol=contact_tol, flow_method=flow_method, progress=progress,
                        memory_limit=memory_limit, runner=runner, device=device)


def simulate_map(heights: ArrayLike, pixel_size: float | tuple[float, float], case: Case, *, periodic: bool = False,
                 grid: int | None = None, windows: int = 1, threshold: bool = True, label: str = "map",
                 **options: Any) -> MapSimulationResult:
    """The exact leak rate of ``case``'s seal on one height map given as an array (module docstring).

    ``heights`` h[i, j] in m at x = i·dx, y = j·dy (first index along the flow), every value finite;
    ``pixel_size`` dx (m), or (dx, dy); ``periodic``: the map is one period of a periodic surface (a
    synthesized one), else it is levelled and mirrored. ``options`` go to :func:`simulate_maps`.
    Bad input raises :class:`~sealeak.errors.InputError` naming ``heights`` or ``pixel_size``.
    """
    h = np.asarray(heights)
    if h.ndim != 2 or not np.issubdtype(h.dtype, np.number) or np.issubdtype(h.dtype, np.complexfloating):
        raise InputError("heights", f"array of shape {h.shape} ({h.dtype})", "a 2D array of real heights in m")
    h = h.astype(float)
    if not np.isfinite(h).all():
        raise InputError("heights", f"{int((~np.isfinite(h)).sum())} non-finite values",
                         "every height must be finite (no NaN or inf): crop the map to a fully measured window")
    if min(h.shape) < MIN_MAP_POINTS:
        raise InputError("heights", f"array of shape {h.shape}", f"at least {MIN_MAP_POINTS} points per side")
    pix = np.atleast_1d(np.asarray(pixel_size, dtype=object))
    try:
        dxy = [float(v) for v in pix]
    except (TypeError, ValueError):
        dxy = []
    if len(dxy) not in (1, 2) or not all(np.isfinite(v) and v > 0 for v in dxy):
        raise InputError("pixel_size", pixel_size, "a finite length > 0 (m), or a pair (dx, dy)")
    dx, dy = (dxy[0], dxy[-1])
    topo = Topography(heights=h, size=(h.shape[0] * dx, h.shape[1] * dy), periodic=bool(periodic), source=label)
    return simulate_maps([topo], case, grid=grid, windows=windows, threshold=threshold, **options)


def case_maps(surface: Any, case_dir: str | Path) -> list[Topography]:
    """The height maps of a case file's ``[surface]`` table (``model = "topography"``), read with its options.

    ``case_dir`` is the folder relative file names are taken from. A line scan is refused (InputError naming
    ``surface.file``): the map route needs maps.
    """
    sec = Section("surface", surface)
    if sec.raw("model") != "topography":
        raise InputError("surface.model", sec.raw("model"), "the map route needs model = \"topography\" (its files "
                                                            "are the maps)")
    analysis, _ = topography_analysis(sec, Path(case_dir), fit=False)
    maps = []
    for source in analysis.sources:
        if not isinstance(source.surface, Topography):
            raise InputError("surface.file", source.name, "is a line scan: the map route needs height maps "
                                                          "(random surfaces from its C(q): simulate --surface random)")
        maps.append(source.surface)
    return maps


def _own_points(topo: Topography) -> int:
    """The solver points of a map at its own resolution: its square's points, doubled when it is mirrored."""
    _, mx, my = _side_points(topo)
    square = (mx, my) == topo.nb_grid_pts and abs(topo.size[0] - topo.size[1]) <= _SQUARE_TOL * min(topo.size)
    n = max(mx, my) * (1 if topo.periodic and square else 2)
    return n + n % 2


def _refuse_case(case: Case) -> None:
    """The map route solves liquids on uniform seals."""
    if case.band is not None:
        raise InputError("seal.shape", case.band.kind, "the map route simulates uniform seals (a rectangle or a "
                                                       "ring): an O-ring's band needs random surfaces (simulate)")
    if case.gas is not None:
        raise InputError("fluid.name", case.gas.gas.name, "the map route simulates liquids; a gas case runs on "
                                                          "random surfaces (simulate --surface random)")
