"""analyze(): files → spectra → stitched C(q), statistics and a self-affine fit, for a thin CLI."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Unpack

import numpy as np

from ..errors import FileFormatError, InputError, SealeakError
from ..physics.spectrum import PowerSpectrum
from ._fit import SelfAffineFit, fit_self_affine
from ._preprocess import Detrend, Prepared, prepare
from ._readers import ReadOptions, read_topography
from ._spectrum import BinnedSpectrum, SpectrumOptions, length_text, spectrum_1d, spectrum_2d, spectrum_2d_from_1d, spectrum_options
from ._statistics import SurfaceStatistics, surface_statistics
from ._stitch import stitch
from ._types import LineScans, Topography
from ._units import option_name

__all__ = ["Analysis", "SourceAnalysis", "analyze"]

Source = str | Path | Topography | LineScans


@dataclass(frozen=True, eq=False, kw_only=True)
class SourceAnalysis:
    """One measurement: its data, 2D binned spectrum, profile spectrum (line scans), statistics, notes.

    ``spectrum_problem`` says why, when the measurement is too small for a reliable C(q): then it
    does not enter the combined C(q) (its height statistics are still given), and ``spectrum`` holds
    its bins, none of them reliable (None for line scans that could not be converted to 2D).
    """

    label: str
    surface: Topography | LineScans
    spectrum: BinnedSpectrum | None  # 2D C(q), m⁴
    profile_spectrum: BinnedSpectrum | None  # 1D C1D(q), m³ (line scans only)
    statistics: SurfaceStatistics
    notes: tuple[str, ...]
    spectrum_problem: str | None = None

    @property
    def name(self) -> str:
        """The file name (without folder and channel) or the label."""
        return Path(self.label.split(" [")[0]).name if self.label else self.label

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the user should know about this measurement's data (e.g. no-data markers found)."""
        return self.surface.warnings


@dataclass(frozen=True, eq=False, kw_only=True)
class Analysis:
    """Result of :func:`analyze`.

    Attributes
    ----------
    spectrum:
        The combined C(q) (m⁴) over the reliable ranges of all sources, a PowerSpectrum. Reading it
        raises :class:`~sealeak.errors.InputError` (naming the files and the reason) when no source
        gives a reliable C(q); ``has_spectrum`` tells beforehand.
    binned:
        The same as raw binned data (mode counts per bin), or None.
    sources:
        Per-file results (:class:`SourceAnalysis`), in input order.
    statistics:
        With one source, its statistics (heights and spectrum). With several: h_rms, slope_rms,
        curvature_rms and area_ratio from the combined C(q) (the heights of no single measurement
        span its whole band), skewness and kurtosis from the measurement that reaches the longest
        wavelengths (they carry the height distribution); ``statistics.method`` says so.
        Each source's own height statistics are in ``sources``.
    fit:
        Self-affine fit to ``binned`` (None if not requested or impossible; see ``notes``).
    notes:
        What was done, source by source, then for the combination.
    spectrum_problem:
        Why there is no combined C(q), or None.
    warnings:
        What the user must know to trust the result, as sentences: each source's data warnings
        (prefixed with its name) and the fit's (prefixed "self-affine fit:").
    """

    spectrum_or_none: PowerSpectrum | None
    binned: BinnedSpectrum | None
    sources: tuple[SourceAnalysis, ...]
    statistics: SurfaceStatistics
    fit: SelfAffineFit | None
    notes: tuple[str, ...] = field(default=())
    spectrum_problem: str | None = None
    warnings: tuple[str, ...] = field(default=())

    @property
    def has_spectrum(self) -> bool:
        return self.spectrum_or_none is not None

    @property
    def spectrum(self) -> PowerSpectrum:
        if self.spectrum_or_none is None:
            names = ", ".join(s.name for s in self.sources)
            raise InputError(option_name("file" if len(self.sources) == 1 else "files"), names,
                             f"no reliable C(q): {self.spectrum_problem}")
        return self.spectrum_or_none


def _longest(source: SourceAnalysis) -> tuple[float, int]:
    """Sort key: the measurement that reaches the longest wavelengths (its shorter side), then the most points."""
    s = source.surface
    side = min(s.size) if isinstance(s, Topography) else s.length
    return (side, int(np.isfinite(s.heights).sum()))


class AnalysisOptions(ReadOptions, SpectrumOptions, total=False):
    """The keyword options of :func:`analyze`: how each file is read (:class:`ReadOptions`) and how its C(q) is
    taken (:class:`SpectrumOptions`)."""


def analyze(paths: Source | Sequence[Source], *, fit: bool = True, **options: Unpack[AnalysisOptions]) -> Analysis:
    """Analyze one or more measurements of a surface.

    Each file is read (:func:`read_topography`; the unit options apply to files that lack the
    information), detrended and windowed (:func:`prepare`), turned into a binned 2D C(q)
    (:func:`spectrum_2d`; line scans via :func:`spectrum_1d` and the inverse Abel transform for an
    isotropic surface), and its statistics computed. The reliable bins of all sources are stitched
    (:func:`stitch`) into one PowerSpectrum, to which the self-affine model is fitted.

    ``options``: :class:`AnalysisOptions`; the spectrum options prepare and bin every source. Reliable range of each
    source: q from ``low_cut``·2π/L up to the shortest reliable wavelength, the larger of
    ``resolution_pixels`` pixels and the lateral resolution: ``resolution`` (m) when given, else what
    the file states (e.g. a stylus tip radius), else none. A source too small for any reliable bin
    keeps its height statistics; its ``spectrum_problem`` says why.

    A flat measurement (all heights equal, or nothing but round-off left after detrending) has no
    roughness to analyze: :class:`~sealeak.errors.FileFormatError` naming it.
    """
    read: dict[str, Any] = {k: v for k, v in options.items() if k in ReadOptions.__optional_keys__}
    o = spectrum_options({k: v for k, v in options.items() if k not in read})
    items: list[Source] = [paths] if isinstance(paths, (str, Path, Topography, LineScans)) else list(paths)
    if not items:
        raise InputError("paths", [], "at least one file")
    sources: list[SourceAnalysis] = []
    for item in items:
        if isinstance(item, (Topography, LineScans)):
            surface = item
        else:
            surface = read_topography(item, **read)
        label = surface.source or f"source {len(sources) + 1}"
        prepared = prepare(surface, detrend=o["detrend"], window=o["window"])
        flat = _flatness(surface, prepared, o["detrend"])
        if flat is not None:
            name = Path(label.split(" [")[0]).name if surface.source else label
            channel = f" or channel ({option_name('channel')})" if " [channel" in label else ""
            raise FileFormatError(name, f"{flat}: there is no roughness to analyze (no C(q), no height distribution); "
                                        f"is it the right file{channel}?")
        profile = None
        binned: BinnedSpectrum | None = None
        problem: str | None = None
        spec: PowerSpectrum | None = None
        notes = list(surface.notes)
        if isinstance(surface, Topography):
            binned = spectrum_2d(prepared, **o)
            problem = binned.problem()
            notes += binned.notes
        else:
            profile = spectrum_1d(prepared, **o)
            notes += profile.notes
            problem = profile.problem(need=3)
            if problem is None:
                binned = spectrum_2d_from_1d(profile)
                notes = list(surface.notes) + list(binned.notes)
                problem = binned.problem()
        if problem is None and binned is not None:
            spec = binned.to_power_spectrum()
        else:
            problem = f"{_describe(surface)}: {problem}"
        stats = surface_statistics(prepare(surface, detrend=o["detrend"], window="none"), spec)
        sources.append(SourceAnalysis(label=label, surface=surface, spectrum=binned, profile_spectrum=profile,
                                      statistics=stats, notes=tuple(notes), spectrum_problem=problem))

    notes = [f"{s.name}: {n}" for s in sources for n in s.notes]
    usable = [s for s in sources if s.spectrum_problem is None]
    if not usable and o["resolution"] is not None:
        _refuse_resolution(sources, o["resolution"])
    combined: BinnedSpectrum | None = None
    spectrum: PowerSpectrum | None = None
    problem = None
    if usable:
        combined = stitch([s.spectrum for s in usable],  # type: ignore[misc]
                          label="combined" if len(sources) > 1 else sources[0].label)
        spectrum = combined.to_power_spectrum()
        if len(sources) > 1:
            notes += list(combined.notes)
            if len(usable) < len(sources):
                notes.append("left out of C(q): " + ", ".join(s.name for s in sources if s.spectrum_problem))
    else:
        problem = "; ".join(f"{s.name}: {s.spectrum_problem}" for s in sources)
    if len(sources) == 1:
        statistics = sources[0].statistics
    else:
        statistics = _combined_statistics(sources, spectrum)
    warnings = [f"{s.name}: {w}" for s in sources for w in s.warnings]
    fitted = None
    if fit and combined is not None:
        try:
            fitted = fit_self_affine(combined)
            notes.append(f"fitted {fitted!r}")
            warnings += [f"self-affine fit: {w}" for w in fitted.warnings]
        except SealeakError as exc:
            notes.append(f"self-affine fit not possible: {exc}")
    return Analysis(spectrum_or_none=spectrum, binned=combined, sources=tuple(sources), statistics=statistics,
                    fit=fitted, notes=tuple(notes), spectrum_problem=problem, warnings=tuple(warnings))


#: Detrended heights whose rms is below this fraction of the largest height are round-off: a flat map.
FLAT_RELATIVE = 1e-10
_SHAPES = {0: ("a constant", "the mean"), 1: ("a plane", "the mean and tilt"), 2: ("a quadratic surface", "the mean, "
                                                                                    "tilt and curvature")}


def _flatness(surface: Topography | LineScans, prepared: Prepared, detrend: Detrend) -> str | None:
    """Why a measurement is flat (a sentence without its name), or None when it has roughness.

    Flat: all defined heights equal, or the detrended heights (less their mean) have an rms below
    ``FLAT_RELATIVE`` times the largest height, i.e. nothing but round-off of the detrending is left.
    """
    raw = surface.heights[prepared.defined]
    n = raw.size
    if n and float(np.ptp(raw)) == 0.0:
        which = "" if prepared.defined.all() else f" defined (of {prepared.defined.size})"
        return f"all {n}{which} heights are equal ({length_text(float(raw[0]))})"
    d = prepared.surface.heights[prepared.defined]
    d = d - d.mean()
    rms = float(np.sqrt(np.mean(d * d)))
    scale = float(np.max(np.abs(raw)))
    if rms > FLAT_RELATIVE * scale:
        return None
    order = {"none": 0, "mean": 0, "plane": 1, "curvature": 2}.get(detrend, 0 if surface.periodic else 1)
    shape, removed = _SHAPES[order]
    if isinstance(surface, LineScans):
        shape = {"a plane": "a straight line", "a quadratic surface": "a parabola"}.get(shape, shape)
        shape = f"{'each profile is' if surface.nb_scans > 1 else 'the profile is'} {shape}"
    else:
        shape = f"the map is {shape}"
    return (f"{shape}: after removing {removed} only round-off is left (rms {rms:.2g} m of heights up to "
            f"{scale:.3g} m)")


def _refuse_resolution(sources: Sequence[SourceAnalysis], resolution: float) -> None:
    """A resolution the user gave that leaves no source a reliable C(q) is the input to change: say so."""
    spectra = []
    for src in sources:
        b = src.profile_spectrum if src.profile_spectrum is not None else src.spectrum
        if b is None or b.basis is None or not b.basis.given_resolution_at_fault:
            return  # something else (too few points) is at fault for this source: keep its own reason
        if b.nb_reliable >= (3 if b.dim == 1 else 2):  # the 1D→2D conversion dropped bins
            return
        spectra.append((src, b))
    src, b = max(spectra, key=lambda sb: sb[1].basis.side)  # type: ignore[union-attr]
    lo, hi = b.q_reliable
    reason = b.basis.resolution_reason(lo, hi, b.nb_reliable, 3 if b.dim == 1 else 2)  # type: ignore[union-attr]
    if len(sources) > 1:
        reason = f"leaves none of the {len(sources)} measurements a reliable C(q); the largest, {src.name}: {reason}"
    raise InputError(option_name("resolution"), length_text(resolution), reason)


def _describe(surface: Topography | LineScans) -> str:
    if isinstance(surface, Topography):
        nx, ny = surface.nb_grid_pts
        return f"{nx}×{ny} map of {length_text(surface.size[0])} × {length_text(surface.size[1])}"
    return f"{surface.nb_scans} profile(s) of {surface.nb_points} points over {length_text(surface.length)}"


def _combined_statistics(sources: Sequence[SourceAnalysis], spectrum: PowerSpectrum | None) -> SurfaceStatistics:
    """Statistics of the surface several measurements describe together (see :class:`Analysis`)."""
    largest = max(sources, key=_longest)
    own = largest.statistics
    if spectrum is None:
        return replace(own, method=f"no combined C(q): all values from the heights of {largest.name}, the "
                                   f"measurement of the largest area ({own.method})")
    return replace(
        SurfaceStatistics.from_spectrum(spectrum), skewness=own.skewness, kurtosis=own.kurtosis,
        method=(f"h_rms, slope_rms, curvature_rms and area_ratio from the combined C(q) over "
                f"q = {spectrum.q_min:.4g}..{spectrum.q_max:.4g} 1/m; skewness and kurtosis from the heights of "
                f"{largest.name}, the measurement that reaches the longest wavelengths"),
    )
