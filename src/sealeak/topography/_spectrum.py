"""Power spectra of measured surfaces in Persson's convention (docs/theory.md §1.1; method §7.2–§7.3).

2D, from a map of nx × ny points and size sx × sy (NumPy's unnormalised FFT)::

    C(q) = sx sy / (4π² nx² ny²) · |fft2(h)(q)|²              [m⁴]
    Σ_q C(q) Δqx Δqy = mean(h²)   (Parseval; Δq = 2π/s)       ⇒ h_rms² = ∫ d²q C = 2π ∫ q C dq

1D, from profiles of n points and length L, averaged over the profiles::

    C1D(q) = L / (2π n²) · |fft(h)(q)|²                       [m³],  h_rms² = 2 ∫_0^∞ C1D dq

Radial (2D) or plain (1D) averages go into log-spaced bins anchored at q = 1 1/m, edges
10^(k/bins_per_decade), so spectra of different measurements share bin edges (for stitching).
Each bin reports the number of Fourier modes it averages (± q counted separately) and its centre
√(q_min q_max) over the modes it holds (the geometric bin centre for well-filled bins, which is
where a steep power law takes its bin-average value to within a fraction of a percent).

Reliable range (bins whose centre lies in it): q ≥ low_cut · 2π/L (L the shorter side; the lowest
bins hold few modes and, for non-periodic data, the window's leakage) and
q ≤ min(2π/(resolution_pixels · Δx), 2π/resolution): detail finer than a few pixels or than the
instrument's lateral resolution is not reliable. ``resolution`` (shortest reliable wavelength, m)
defaults to what the file states (:attr:`Topography.resolution`, e.g. the tip-radius limit of a
stylus scan); all three are options.

1D → 2D for isotropic surfaces (inverse Abel transform)::

    C(q) = -(1/π) ∫_q^∞ dq' C1D'(q') / √(q'² - q²),      C1D(q) = 2 ∫_q^∞ dq' q' C(q') / √(q'² - q²)

computed for piecewise power laws (log-log interpolation between nodes) with q' = q cosh t, which
removes the square-root singularity; the smooth integrand is integrated by Gauss-Legendre on short
t intervals (breakpoints at the nodes), and the tail beyond the last node (its power law continued
to infinity) in closed form with the regularised incomplete beta function.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Literal, TypedDict, Unpack, cast

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sfft
from scipy import special

from ..errors import InputError
from ..io.quantities import quantity
from ..io.units import format_quantity
from ..physics.spectrum import PowerSpectrum
from ._preprocess import Detrend, Prepared, Window, prepare
from ._types import LineScans, Topography
from ._units import option_name

__all__ = [
    "BinnedSpectrum",
    "RangeBasis",
    "SpectrumOptions",
    "length_text",
    "power_spectrum_map",
    "spectrum_2d",
    "spectrum_1d",
    "spectrum_2d_from_1d",
    "spectrum_1d_from_2d",
    "abel_inverse",
    "abel_forward",
]

FloatArray = NDArray[np.float64]


def length_text(value: float) -> str:
    """A length in m as readable text with its unit (nm .. km), e.g. 2e-3 -> '2 mm'."""
    if abs(value) >= 1e3:
        return f"{value / 1e3:.4g} km"
    return format_quantity(value, "length", 4)


_length = length_text


@dataclass(frozen=True, kw_only=True)
class RangeBasis:
    """What sets the reliable range of one measurement's spectrum (for messages that name the cause).

    ``side``: the length L in m (shorter side of a map, length of a profile); ``pixel``: the (larger)
    pixel size in m; ``low_cut`` and ``resolution_pixels`` as given; ``resolution``: the lateral
    resolution in m that was considered, ``origin`` where it came from ("given" or "stated by the
    file"), ``by_resolution`` True when it (not the pixel limit) ends the range; ``kind``: "map"
    or "profile"; ``bins_per_decade`` as given.
    """

    side: float
    pixel: float
    low_cut: float
    resolution_pixels: float
    resolution: float | None
    origin: str
    by_resolution: bool
    kind: str
    bins_per_decade: float = 10.0

    @property
    def given_resolution_at_fault(self) -> bool:
        """True when a resolution the user gave ends the range (then it is the input to change)."""
        return self.by_resolution and self.origin == "given"

    def resolution_reason(self, lo: float, hi: float, n: int, need: int) -> str:
        """Why a given resolution leaves too few bins, without naming the option (see :meth:`problem`)."""
        longest = self.side / self.low_cut
        what = "map's shorter side" if self.kind == "map" else "profile"
        if lo >= hi:
            size = (f"longer than the {what} ({_length(self.side)})" if self.resolution >= self.side else  # type: ignore[operator]
                    f"too close to the {what} ({_length(self.side)})")
            return (f"{size}: the reliable range would start at q = {lo:.4g} 1/m ({self.low_cut:g}·2π/L) and end at "
                    f"{hi:.4g} 1/m (2π/resolution); give a resolution below L/{option_name('low_cut')} = "
                    f"{_length(longest)}")
        return (f"leaves {n} bin(s) in the reliable range q = {lo:.4g}..{hi:.4g} 1/m, at least {need} are needed; "
                f"give a resolution well below L/{option_name('low_cut')} = {_length(longest)}")

    def reason(self, lo: float, hi: float, n: int, need: int) -> str:
        """Why fewer than ``need`` reliable bins are left, naming the input at fault (a sentence)."""
        if self.given_resolution_at_fault:
            return (f"{option_name('resolution')} = {_length(self.resolution)} "  # type: ignore[arg-type]
                    f"{self.resolution_reason(lo, hi, n, need)}")
        across = self.side / self.pixel
        where = "across its shorter side" if self.kind == "map" else "along the profile"
        if self.by_resolution:  # the file's own resolution: the instrument, not an option, limits the range
            cause = (f"the lateral resolution the file states ({_length(self.resolution)}) "  # type: ignore[arg-type]
                     f"against the measured length L = {_length(self.side)}")
            fix = (f"measure a larger area (or give {option_name('resolution')} if the instrument resolves finer "
                   f"detail than the file states)")
        else:
            cause = (f"only {across:.3g} pixels {where} (L = {_length(self.side)}, pixel {_length(self.pixel)}); the "
                     f"reliable range spans wavelengths from {self.resolution_pixels:g} pixels "
                     f"({option_name('resolution_pixels')}) to L/{self.low_cut:g} ({option_name('low_cut')})")
            fix = (f"measure with more points (a finer pixel, or a larger area at this pixel size), or relax "
                   f"{option_name('low_cut')} / {option_name('resolution_pixels')}")
        if lo >= hi:
            return f"too small for a reliable C(q): {cause}, which leaves no wavelength between them; {fix}"
        decades = float(np.log10(hi / lo))
        if decades * self.bins_per_decade < need + 1:  # the bins are too wide for the range there is
            fix += (f", or give more {option_name('bins_per_decade')} (now {self.bins_per_decade:g}; the range spans "
                    f"{decades:.2g} decades)")
        return (f"its C(q) has {n} bin(s) in the reliable range q = {lo:.4g}..{hi:.4g} 1/m, at least {need} are "
                f"needed ({cause}); {fix}")


@dataclass(frozen=True, eq=False, kw_only=True)
class BinnedSpectrum:
    """A binned power spectrum of one measurement (raw data for plots, stitching and fits).

    Attributes
    ----------
    q:
        Bin centres in 1/m (non-empty bins only, increasing).
    C:
        Bin averages: the 2D C(q) in m⁴ (``dim == 2``) or the 1D C1D(q) in m³ (``dim == 1``).
    modes:
        Fourier modes averaged in each bin (± q counted separately; for line scans summed over the
        profiles, which are not independent).
    q_lo, q_hi:
        Bin edges in 1/m.
    reliable:
        True for bins inside the reliable range [q_reliable[0], q_reliable[1]].
    dim:
        2 for C(q) of a surface, 1 for the profile spectrum C1D(q).
    label, notes:
        Source description and what was done.
    basis:
        What sets the reliable range (:class:`RangeBasis`), or None (stitched spectra).
    """

    q: FloatArray
    C: FloatArray
    modes: NDArray[np.int64]
    q_lo: FloatArray
    q_hi: FloatArray
    reliable: NDArray[np.bool_]
    q_reliable: tuple[float, float] = quantity("1/m", "range of q the measurement resolves reliably", key="reliable_range")
    dim: int
    label: str = ""
    notes: tuple[str, ...] = field(default=())
    basis: RangeBasis | None = None

    @property
    def nb_reliable(self) -> int:
        """Reliable bins with a positive, finite C."""
        return int((self.reliable & (self.C > 0) & np.isfinite(self.C)).sum())

    def problem(self, need: int = 2) -> str | None:
        """Why fewer than ``need`` reliable bins are left (a sentence without the file name), or None."""
        n = self.nb_reliable
        if n >= need:
            return None
        lo, hi = self.q_reliable
        if self.basis is not None:
            return self.basis.reason(lo, hi, n, need)
        if not lo < hi:
            return (f"no reliable C(q): the reliable range would start at q = {lo:.4g} 1/m but ends at {hi:.4g} 1/m")
        return f"its C(q) has {n} bin(s) in the reliable range q = {lo:.4g}..{hi:.4g} 1/m, at least {need} are needed"

    def to_power_spectrum(self, label: str | None = None) -> PowerSpectrum:
        """The reliable, positive bins as a :class:`~sealeak.physics.spectrum.PowerSpectrum` (2D only)."""
        if self.dim != 2:
            raise InputError("spectrum.dim", self.dim, "a 1D profile spectrum must be converted to 2D first "
                                                       "(spectrum_2d_from_1d)")
        why = self.problem()
        if why is not None:
            raise InputError("spectrum", self.label or "the measurement", why)
        keep = self.reliable & (self.C > 0) & np.isfinite(self.C)
        return PowerSpectrum.from_arrays(self.q[keep], self.C[keep], label=self.label if label is None else label)


# ---------------------------------------------------------------------------- binning
def _bin_index(q: FloatArray, bins_per_decade: float) -> NDArray[np.int64]:
    return np.floor(bins_per_decade * np.log10(q) + 1e-9).astype(np.int64)


def _bin(q: FloatArray, C: FloatArray, w: FloatArray, bins_per_decade: float
         ) -> tuple[FloatArray, FloatArray, NDArray[np.int64], FloatArray, FloatArray]:
    """Weighted averages of C in log bins; q, C, w flat with q > 0."""
    k = _bin_index(q, bins_per_decade)
    k0 = int(k.min())
    kk = k - k0
    nb = int(kk.max()) + 1
    wsum = np.bincount(kk, weights=w, minlength=nb)
    csum = np.bincount(kk, weights=w * C, minlength=nb)
    qmin = np.full(nb, np.inf)
    qmax = np.zeros(nb)
    np.minimum.at(qmin, kk, q)
    np.maximum.at(qmax, kk, q)
    full = wsum > 0
    idx = np.arange(nb)[full] + k0
    return (np.sqrt(qmin[full] * qmax[full]), csum[full] / wsum[full], np.rint(wsum[full]).astype(np.int64),
            10.0 ** (idx / bins_per_decade), 10.0 ** ((idx + 1) / bins_per_decade))


class SpectrumOptions(TypedDict, total=False):
    """The keyword options of :func:`spectrum_2d`, :func:`spectrum_1d` and :func:`~sealeak.topography.analyze`.

    Each is optional (its default in parentheses):

    detrend, window:
        How the heights are prepared (:func:`~sealeak.topography.prepare`; "auto"); ignored for a
        surface that is prepared already.
    bins_per_decade:
        Log bins per decade of q (10; 1 to 200).
    low_cut:
        The reliable range starts at low_cut · 2π/L (3; >= 1).
    resolution_pixels:
        It ends at 2π/(resolution_pixels · Δx) at the latest (4; >= 2, 2 = Nyquist).
    resolution:
        Shortest reliable wavelength in m (None: the surface's own ``resolution``).
    """

    detrend: Detrend
    window: Window
    bins_per_decade: float
    low_cut: float
    resolution_pixels: float
    resolution: float | None


#: The value of each :class:`SpectrumOptions` key a call leaves out.
SPECTRUM_DEFAULTS: SpectrumOptions = {"detrend": "auto", "window": "auto", "bins_per_decade": 10.0, "low_cut": 3.0,
                                      "resolution_pixels": 4.0, "resolution": None}


def spectrum_options(options: Mapping[str, object]) -> SpectrumOptions:
    """``options`` completed with :data:`SPECTRUM_DEFAULTS`; a key that is no option is a TypeError, as for any
    unexpected keyword argument."""
    unknown = options.keys() - SpectrumOptions.__optional_keys__
    if unknown:
        raise TypeError(f"unexpected keyword argument {min(unknown)!r}")
    return cast(SpectrumOptions, {**SPECTRUM_DEFAULTS, **options})


def _prepared(surface: Topography | LineScans | Prepared, options: SpectrumOptions) -> tuple[Prepared, SpectrumOptions]:
    """The checked options (:class:`~sealeak.errors.InputError` naming a bad one) and the surface prepared with them."""
    o = spectrum_options(options)
    _check_options(o["bins_per_decade"], o["low_cut"], o["resolution_pixels"], o["resolution"])
    prepared = surface if isinstance(surface, Prepared) else prepare(surface, detrend=o["detrend"], window=o["window"])
    return prepared, o


def _check_options(bins_per_decade: float, low_cut: float, resolution_pixels: float,
                   resolution: float | None = None) -> None:
    if not (np.isfinite(bins_per_decade) and 1 <= bins_per_decade <= 200):
        raise InputError(option_name("bins_per_decade"), bins_per_decade, "a number between 1 and 200")
    if not (np.isfinite(low_cut) and low_cut >= 1):
        raise InputError(option_name("low_cut"), low_cut,
                         "a number >= 1 (the reliable range starts at low_cut · 2π/L)")
    if not (np.isfinite(resolution_pixels) and resolution_pixels >= 2):
        raise InputError(option_name("resolution_pixels"), resolution_pixels,
                         "a number >= 2 (2 = Nyquist; the reliable range ends at 2π/(resolution_pixels · Δx))")
    if resolution is not None and not (np.isfinite(resolution) and resolution > 0):
        raise InputError(option_name("resolution"), resolution, "a length > 0 (the shortest reliable wavelength, m)")


def _upper_limit(side: float, pixel: float, low_cut: float, resolution_pixels: float, resolution: float | None,
                 stated: float | None, kind: str, bins_per_decade: float) -> tuple[float, str, RangeBasis]:
    """Upper end of the reliable range (1/m), a note on what sets it, and the basis for messages."""
    q_pix = 2.0 * np.pi / (resolution_pixels * pixel)
    res, origin = (resolution, "given") if resolution is not None else (stated, "stated by the file")
    if res is None:
        return q_pix, f"wavelengths >= {resolution_pixels:g} pixels", RangeBasis(
            side=side, pixel=pixel, low_cut=low_cut, resolution_pixels=resolution_pixels, resolution=None, origin="",
            by_resolution=False, kind=kind, bins_per_decade=bins_per_decade)
    q_res = 2.0 * np.pi / res
    basis = RangeBasis(side=side, pixel=pixel, low_cut=low_cut, resolution_pixels=resolution_pixels, resolution=res,
                       origin=origin, by_resolution=q_res < q_pix, kind=kind, bins_per_decade=bins_per_decade)
    if q_res < q_pix:
        return q_res, f"wavelengths >= the lateral resolution {res:.4g} m ({origin})", basis
    return q_pix, (f"wavelengths >= {resolution_pixels:g} pixels, which is coarser than the lateral resolution "
                   f"{res:.4g} m ({origin})"), basis


# ---------------------------------------------------------------------------- 2D
def power_spectrum_map(prepared: Prepared) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Discrete C(q) of every Fourier mode of a prepared map, before binning.

    Returns ``(qx, qy, C, weight)`` in the ``rfft2`` layout: qx (nx,), qy (ny//2+1,) in 1/m, C[i, j]
    in m⁴, and the mode multiplicity weight[i, j] (2 for modes that stand for ±q, 1 otherwise), so
    that Σ weight·C·(2π/sx)(2π/sy) equals mean(windowed heights²) (Parseval).
    """
    surf = prepared.surface
    if not isinstance(surf, Topography):
        raise InputError("surface", type(surf).__name__, "a 2D map (Topography)")
    nx, ny = surf.nb_grid_pts
    sx, sy = surf.size
    F = sfft.rfft2(prepared.windowed)
    C = (sx * sy / (4.0 * np.pi**2 * nx**2 * ny**2)) * (F.real**2 + F.imag**2)
    qx = 2.0 * np.pi * sfft.fftfreq(nx, d=sx / nx)
    qy = 2.0 * np.pi * sfft.rfftfreq(ny, d=sy / ny)
    weight = np.full(C.shape, 2.0)
    weight[:, 0] = 1.0
    if ny % 2 == 0:
        weight[:, -1] = 1.0
    return qx, qy, C, weight


def spectrum_2d(topography: Topography | Prepared, **options: Unpack[SpectrumOptions]) -> BinnedSpectrum:
    """Radially averaged 2D C(q) (m⁴) of a map in Persson's convention, in log bins.

    Modes up to the smaller Nyquist wavevector π·min(1/Δx, 1/Δy) are binned (complete annuli).
    ``topography`` may be already prepared (then ``detrend``/``window`` are ignored).
    ``options``: :class:`SpectrumOptions` (``resolution`` by default the map's own).
    """
    prepared, o = _prepared(topography, options)
    bins_per_decade, low_cut = o["bins_per_decade"], o["low_cut"]
    surf = prepared.surface
    if not isinstance(surf, Topography):
        raise InputError("surface", type(surf).__name__, "a 2D map (Topography); use spectrum_1d for line scans")
    qx, qy, C, weight = power_spectrum_map(prepared)
    q = np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
    dx, dy = surf.pixel_size
    q_nyq = np.pi * min(1.0 / dx, 1.0 / dy)
    use = (q > 0) & (q <= q_nyq * (1 + 1e-12))
    if not use.any():
        raise InputError("topography", surf.nb_grid_pts, "too few points for a spectrum")
    qc, Cb, modes, lo, hi = _bin(q[use], C[use], weight[use], bins_per_decade)
    q_hi, why, basis = _upper_limit(min(surf.size), max(dx, dy), low_cut, o["resolution_pixels"], o["resolution"],
                                    surf.resolution, "map", bins_per_decade)
    q_rel = (low_cut * 2.0 * np.pi / min(surf.size), q_hi)
    reliable = (qc >= q_rel[0]) & (qc <= q_rel[1])
    notes = list(prepared.notes) + [
        f"2D spectrum: {surf.nb_grid_pts[0]}×{surf.nb_grid_pts[1]} map, radial average in "
        f"{bins_per_decade:g} bins per decade up to the Nyquist wavevector {q_nyq:.4g} 1/m",
        f"reliable range {q_rel[0]:.4g}..{q_rel[1]:.4g} 1/m (q >= {low_cut:g}·2π/L, {why})",
    ]
    return BinnedSpectrum(q=qc, C=Cb, modes=modes, q_lo=lo, q_hi=hi, reliable=reliable, q_reliable=q_rel, dim=2,
                          label=surf.source, notes=tuple(notes), basis=basis)


# ---------------------------------------------------------------------------- 1D
def spectrum_1d(scans: LineScans | Prepared, **options: Unpack[SpectrumOptions]) -> BinnedSpectrum:
    """Profile spectrum C1D(q) (m³), averaged over all profiles, in log bins (h_rms² = 2∫C1D dq).

    ``scans`` may be already prepared (then ``detrend``/``window`` are ignored).
    ``options``: :class:`SpectrumOptions` (``resolution`` by default the scans' own).
    """
    prepared, o = _prepared(scans, options)
    bins_per_decade, low_cut = o["bins_per_decade"], o["low_cut"]
    surf = prepared.surface
    if not isinstance(surf, LineScans):
        raise InputError("surface", type(surf).__name__, "line scans (LineScans); use spectrum_2d for maps")
    n, L = surf.nb_points, surf.length
    F = sfft.rfft(prepared.windowed, axis=1)
    C = (L / (2.0 * np.pi * n**2)) * np.mean(F.real**2 + F.imag**2, axis=0)
    q = 2.0 * np.pi * sfft.rfftfreq(n, d=L / n)
    weight = np.full(q.shape, 2.0 * surf.nb_scans)
    if n % 2 == 0:
        weight[-1] = surf.nb_scans
    qc, Cb, modes, lo, hi = _bin(q[1:], C[1:], weight[1:], bins_per_decade)
    q_hi, why, basis = _upper_limit(L, surf.pixel_size, low_cut, o["resolution_pixels"], o["resolution"], surf.resolution,
                                    "profile", bins_per_decade)
    q_rel = (low_cut * 2.0 * np.pi / L, q_hi)
    reliable = (qc >= q_rel[0]) & (qc <= q_rel[1])
    notes = list(prepared.notes) + [
        f"1D spectrum: {surf.nb_scans} profile(s) of {n} points, averaged, {bins_per_decade:g} bins per decade",
        f"reliable range {q_rel[0]:.4g}..{q_rel[1]:.4g} 1/m (q >= {low_cut:g}·2π/L, {why})",
    ]
    return BinnedSpectrum(q=qc, C=Cb, modes=modes, q_lo=lo, q_hi=hi, reliable=reliable, q_reliable=q_rel, dim=1,
                          label=surf.source, notes=tuple(notes), basis=basis)


# ---------------------------------------------------------------------------- Abel transforms
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
_DT = 0.25  # longest t interval per Gauss-Legendre panel


def _piecewise(qn: FloatArray, cn: FloatArray) -> tuple[FloatArray, FloatArray]:
    if qn.size < 2:
        raise InputError("spectrum", f"{qn.size} points", "at least two points are needed")
    if (np.diff(qn) <= 0).any() or (qn <= 0).any() or (cn <= 0).any() or not np.isfinite(cn).all():
        raise InputError("spectrum", "q, C", "q > 0 strictly increasing and C > 0 finite")
    return qn, np.log(cn[1:] / cn[:-1]) / np.log(qn[1:] / qn[:-1])


def _abel_panels(q: float, qn: FloatArray, g) -> float:  # type: ignore[no-untyped-def]
    """∫_{max(q, qn[0])}^{qn[-1]} g(q') / √(q'² - q²) dq' with q' = q cosh t (g piecewise smooth)."""
    lo = max(q, qn[0])
    if lo >= qn[-1]:
        return 0.0
    t_nodes = np.arccosh(np.maximum(qn[qn > lo] / q, 1.0))
    t0 = float(np.arccosh(lo / q))
    edges = np.concatenate([[t0], t_nodes])
    pieces = [edges[:1]]
    for a, b in zip(edges[:-1], edges[1:]):
        m = max(1, int(np.ceil((b - a) / _DT)))
        pieces.append(np.linspace(a, b, m + 1)[1:])
    e = np.concatenate(pieces)
    a, b = e[:-1], e[1:]
    half = 0.5 * (b - a)
    t = (0.5 * (a + b))[:, None] + half[:, None] * _GL_X[None, :]
    qp = q * np.cosh(t)
    vals = g(np.clip(qp, qn[0], qn[-1]))
    return float(np.sum(half[:, None] * _GL_W[None, :] * vals))


def _power_tail(q: float, q_n: float, c_n: float, beta: float) -> float:
    """∫_{q_n}^∞ C1D'(q')/√(q'²-q²) dq' for C1D = c_n (q'/q_n)^β beyond q_n (β < 0), q <= q_n.

    With u = q²/q'²: β c_n q_n^(-β) (q^(β-1)/2) B(s, ½) I_{q²/q_n²}(s, ½), s = (1-β)/2.
    """
    s = 0.5 * (1.0 - beta)
    x = min((q / q_n) ** 2, 1.0)
    return beta * c_n * (q / q_n) ** beta / q * 0.5 * special.beta(s, 0.5) * special.betainc(s, 0.5, x)


def abel_inverse(q_nodes: FloatArray, C1D: FloatArray, *, tail: Literal["power-law", "none"] = "power-law"
                 ) -> FloatArray:
    """2D C(q) at the nodes from a 1D spectrum given at them (piecewise power law between nodes).

    C(q) = -(1/π) ∫_q^∞ C1D'(q')/√(q'²-q²) dq'. ``tail="power-law"`` continues the last segment's power
    law to infinity (it must decrease); ``"none"`` lets C1D drop to zero at the last node, which adds
    C1D(q_n)/(π√(q_n²-q²)) and makes the last node undefined (returned as NaN).
    """
    qn, beta = _piecewise(np.asarray(q_nodes, dtype=float), np.asarray(C1D, dtype=float))
    cn = np.asarray(C1D, dtype=float)

    def dC(qp: FloatArray) -> FloatArray:
        k = np.clip(np.searchsorted(qn, qp, side="right") - 1, 0, qn.size - 2)
        return beta[k] * cn[k] * (qp / qn[k]) ** beta[k] / qp

    out = np.empty(qn.size)
    for j, q in enumerate(qn):
        total = _abel_panels(float(q), qn, dC)
        if tail == "power-law":
            if not beta[-1] < 0:
                raise InputError("1D spectrum tail", float(beta[-1]),
                                 "the last segment must decrease to continue it as a power law; use tail='none'")
            total += _power_tail(float(q), float(qn[-1]), float(cn[-1]), float(beta[-1]))
        elif tail == "none":
            total += -cn[-1] / np.sqrt(qn[-1] ** 2 - q**2) if q < qn[-1] else np.inf
        else:
            raise InputError("tail", tail, "allowed: 'power-law', 'none'")
        out[j] = -total / np.pi
    if tail == "none":
        out[-1] = np.nan
    return out


def abel_forward(spectrum: PowerSpectrum, q: FloatArray) -> FloatArray:
    """1D profile spectrum C1D(q) (m³) of an isotropic surface: C1D(q) = ∫ dq_y C(√(q² + q_y²)).

    Exact up to the Gauss-Legendre error (~1e-13 relative) for the piecewise power law C.
    """
    qn = spectrum.q

    def g(qp: FloatArray) -> FloatArray:
        return 2.0 * qp * spectrum(qp)

    qa = np.atleast_1d(np.asarray(q, dtype=float))
    if (qa <= 0).any():
        raise InputError("q", float(qa.min()), "must be > 0")
    out = np.array([_abel_panels(float(x), qn, g) for x in qa])
    return out if np.ndim(q) else out[0]


def spectrum_1d_from_2d(spectrum: PowerSpectrum, q: FloatArray) -> FloatArray:
    """Alias of :func:`abel_forward` (C1D from an isotropic C(q))."""
    return abel_forward(spectrum, q)


def spectrum_2d_from_1d(binned: BinnedSpectrum, *, tail: Literal["power-law", "none"] = "power-law"
                        ) -> BinnedSpectrum:
    """2D C(q) of an isotropic surface from its profile spectrum (inverse Abel transform).

    Uses the reliable, positive bins only (finer bins beyond the lateral resolution would feed
    their artefacts into every lower q), continuing the last reliable segment as a power law.
    Nodes where the transform of noisy data is not positive are dropped (noted).
    """
    if binned.dim != 1:
        raise InputError("spectrum.dim", binned.dim, "a 1D profile spectrum")
    keep = binned.reliable & (binned.C > 0)
    why = binned.problem(need=3)
    if why is not None:
        raise InputError("profile spectrum", binned.label or "the scan", f"{why} (for the 1D → 2D conversion)")
    q, c = binned.q[keep], binned.C[keep]
    try:
        C2 = abel_inverse(q, c, tail=tail)
        tail_note = "the last segment's power law continued to infinity"
    except InputError:
        C2 = abel_inverse(q, c, tail="none")
        tail_note = "C1D taken to vanish beyond the last bin (its last segment does not decrease)"
    good = np.isfinite(C2) & (C2 > 0)
    notes = list(binned.notes) + [
        f"converted to 2D for an isotropic surface by the inverse Abel transform ({tail_note})"]
    if (~good).any():
        notes.append(f"dropped {int((~good).sum())} bin(s) where the transform of the noisy 1D data was not positive")
    return replace(binned, q=q[good], C=C2[good], modes=binned.modes[keep][good], q_lo=binned.q_lo[keep][good],
                   q_hi=binned.q_hi[keep][good], reliable=np.ones(int(good.sum()), dtype=bool), dim=2,
                   notes=tuple(notes))
