"""analyze(): files → spectra → stitched C(q), statistics and a self-affine fit, for a thin CLI."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence, Union

from ..errors import InputError, SealeakError
from ..roughness import PowerSpectrum
from ._fit import SelfAffineFit, fit_self_affine
from ._preprocess import Detrend, Window, prepare
from ._readers import LengthLike, read_topography
from ._spectrum import BinnedSpectrum, spectrum_1d, spectrum_2d, spectrum_2d_from_1d
from ._statistics import SurfaceStatistics, surface_statistics
from ._stitch import stitch
from ._types import LineScans, Topography

__all__ = ["Analysis", "SourceAnalysis", "analyze"]

Source = Union[str, Path, Topography, LineScans]


@dataclass(frozen=True, eq=False)
class SourceAnalysis:
    """One measurement: its data, 2D binned spectrum, profile spectrum (line scans), statistics, notes."""

    label: str
    surface: Topography | LineScans
    spectrum: BinnedSpectrum  # 2D C(q), m⁴
    profile_spectrum: BinnedSpectrum | None  # 1D C1D(q), m³ (line scans only)
    statistics: SurfaceStatistics
    notes: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class Analysis:
    """Result of :func:`analyze`.

    Attributes
    ----------
    spectrum:
        The combined C(q) (m⁴) over the reliable ranges of all sources, a PowerSpectrum.
    binned:
        The same as raw binned data (mode counts per bin).
    sources:
        Per-file results (:class:`SourceAnalysis`), in input order.
    statistics:
        With one source, its statistics (heights and spectrum); with several, the values from the
        combined C(q) only (per-source height statistics are in ``sources``).
    fit:
        Self-affine fit to ``binned`` (None if not requested or impossible; see ``notes``).
    notes:
        What was done, source by source, then for the combination.
    """

    spectrum: PowerSpectrum
    binned: BinnedSpectrum
    sources: tuple[SourceAnalysis, ...]
    statistics: SurfaceStatistics
    fit: SelfAffineFit | None
    notes: tuple[str, ...] = field(default=())


def analyze(
    paths: Source | Sequence[Source],
    *,
    pixel_size: LengthLike | Sequence[LengthLike] | None = None,
    size: LengthLike | Sequence[LengthLike] | None = None,
    height_unit: str | None = None,
    lateral_unit: str | None = None,
    periodic: bool = False,
    channel: int | str | None = None,
    detrend: Detrend = "auto",
    window: Window = "auto",
    bins_per_decade: float = 10.0,
    low_cut: float = 3.0,
    resolution_pixels: float = 4.0,
    fit: bool = True,
) -> Analysis:
    """Analyze one or more measurements of a surface.

    Each file is read (:func:`read_topography`; the unit options apply to files that lack the
    information), detrended and windowed (:func:`prepare`), turned into a binned 2D C(q)
    (:func:`spectrum_2d`; line scans via :func:`spectrum_1d` and the inverse Abel transform for an
    isotropic surface), and its statistics computed. The reliable bins of all sources are stitched
    (:func:`stitch`) into one PowerSpectrum, to which the self-affine model is fitted.
    """
    items: list[Source] = [paths] if isinstance(paths, (str, Path, Topography, LineScans)) else list(paths)
    if not items:
        raise InputError("paths", [], "at least one file")
    sources: list[SourceAnalysis] = []
    for item in items:
        if isinstance(item, (Topography, LineScans)):
            surface = item
        else:
            surface = read_topography(item, pixel_size=pixel_size, size=size, height_unit=height_unit,
                                      lateral_unit=lateral_unit, periodic=periodic, channel=channel)
        prepared = prepare(surface, detrend=detrend, window=window)
        opts = dict(bins_per_decade=bins_per_decade, low_cut=low_cut, resolution_pixels=resolution_pixels)
        profile = None
        if isinstance(surface, Topography):
            binned = spectrum_2d(prepared, **opts)
        else:
            profile = spectrum_1d(prepared, **opts)
            binned = spectrum_2d_from_1d(profile)
        try:
            spec: PowerSpectrum | None = binned.to_power_spectrum()
        except InputError:
            spec = None
        stats = surface_statistics(prepare(surface, detrend=detrend, window="none"), spec)
        label = surface.source or f"source {len(sources) + 1}"
        notes = tuple(surface.notes) + tuple(binned.notes)
        sources.append(SourceAnalysis(label, surface, binned, profile, stats, notes))
    combined = stitch([s.spectrum for s in sources], label="combined" if len(sources) > 1 else sources[0].label)
    spectrum = combined.to_power_spectrum()
    notes = [f"{Path(s.label.split(' [')[0]).name}: {n}" for s in sources for n in s.notes]
    if len(sources) > 1:
        notes += list(combined.notes)
        statistics = SurfaceStatistics.from_spectrum(spectrum, method="from the combined C(q)")
    else:
        statistics = sources[0].statistics
    fitted = None
    if fit:
        try:
            fitted = fit_self_affine(combined)
            notes.append(f"fitted {fitted!r}")
        except SealeakError as exc:
            notes.append(f"self-affine fit not possible: {exc}")
    return Analysis(spectrum, combined, tuple(sources), statistics, fitted, tuple(notes))
