"""Height statistics of a measured surface, from the heights directly and from C(q).

From the heights (detrended, over the points the file defines)::

    h_rms = √<h²>,  skewness = <h³>/h_rms³,  kurtosis = <h⁴>/h_rms⁴  (3 for Gaussian heights)
    slope_rms = √<|∇h|²>,  curvature_rms = √<(∇²h)²>,  area ratio = <√(1 + |∇h|²)>

with spectral derivatives (exact for the sampled band, the Nyquist mode excepted, as for C(q)).
Periodic maps are differentiated directly. A measured map is not periodic: its periodic
continuation jumps at the edges, and finite differences read 20-30 % low for rough surfaces
(central differences damp a mode q by sin(qΔx)/(qΔx)). Non-periodic data are therefore split
into a periodic and a smooth component, h = p + s (Moisan, J. Math. Imaging Vis. 39 (2011) 161:
s is the discrete harmonic function that carries the mismatch between opposite edges), and
∇h = ∇p (spectral) + ∇s (finite differences, accurate for the smooth s); likewise ∇²h. This gives
the same values as the periodic analysis of the surface the data were cut from. For line scans the
profile values are converted for an isotropic surface: <|∇h|²> = 2<h'²>, <(∇²h)²> = (8/3)<h''²>,
and the area ratio follows from the slope assuming Gaussian slopes.

From C(q) (Persson; docs/theory.md §1.2, §7.8): h_rms² = 2π∫qC dq, slope_rms² = 2π∫q³C dq,
curvature_rms² = 2π∫q⁵C dq over the spectrum's band, area ratio for Gaussian slopes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sfft

from ..io.quantities import quantity
from ..physics.spectrum import PowerSpectrum, area_ratio_from_slope
from ._preprocess import Detrend, Prepared, prepare
from ._types import LineScans, Topography

__all__ = ["SurfaceStatistics", "surface_statistics"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True)
class SurfaceStatistics:
    """Roughness statistics (SI units). ``None`` where a value is not available.

    Attributes
    ----------
    h_rms:
        RMS height in m, from the heights.
    slope_rms:
        RMS gradient √<|∇h|²> (dimensionless), from the heights.
    curvature_rms:
        RMS Laplacian √<(∇²h)²> in 1/m, from the heights.
    area_ratio:
        A_true/A0 = <√(1+|∇h|²)> from the heights (line scans: Gaussian-slope estimate).
    skewness, kurtosis:
        Of the height distribution (kurtosis 3 for Gaussian heights).
    spectrum_h_rms, spectrum_slope_rms, spectrum_curvature_rms, spectrum_area_ratio:
        The same from C(q) over its band (m, 1, 1/m, 1).
    method:
        How derivatives were taken.
    """

    h_rms: float | None = quantity("m", "rms height, from the heights")
    slope_rms: float | None = quantity("1", "rms gradient √<|∇h|²>, from the heights")
    curvature_rms: float | None = quantity("1/m", "rms Laplacian √<(∇²h)²>, from the heights")
    area_ratio: float | None = quantity("1", "true over nominal area <√(1+|∇h|²)>")
    skewness: float | None = quantity("1", "skewness of the height distribution")
    kurtosis: float | None = quantity("1", "kurtosis of the height distribution (3 for Gaussian heights)")
    spectrum_h_rms: float | None = quantity("m", "rms height from C(q) over its band", default=None)
    spectrum_slope_rms: float | None = quantity("1", "rms gradient from C(q) over its band", default=None)
    spectrum_curvature_rms: float | None = quantity("1/m", "rms Laplacian from C(q) over its band", default=None)
    spectrum_area_ratio: float | None = quantity("1", "true over nominal area from C(q) over its band", default=None)
    method: str = ""

    @classmethod
    def from_spectrum(cls, spectrum: PowerSpectrum, method: str = "from C(q) only") -> SurfaceStatistics:
        """Statistics of a surface known only by its C(q): h_rms, slope_rms, curvature_rms and area_ratio
        from the spectrum (also in the ``spectrum_*`` fields); skewness and kurtosis are not
        determined by C(q) (None)."""
        sp = _spectral(spectrum)
        return cls(h_rms=sp["spectrum_h_rms"], slope_rms=sp["spectrum_slope_rms"],
                   curvature_rms=sp["spectrum_curvature_rms"],
                   area_ratio=sp["spectrum_area_ratio"], skewness=None, kurtosis=None, **sp, method=method)


def _spectral(spectrum: PowerSpectrum | None) -> dict[str, float | None]:
    if spectrum is None:
        return {}
    return {"spectrum_h_rms": spectrum.h_rms, "spectrum_slope_rms": spectrum.slope_rms,
            "spectrum_curvature_rms": spectrum.curvature_rms, "spectrum_area_ratio": spectrum.area_ratio}


def _rms(values: FloatArray) -> float:
    """√<v²> (in the unit of ``values``) computed in units of the largest magnitude, so that neither the squares
    overflow (values above ~1e154, as the curvature of a map of sub-1e-100 m pixels) nor underflow: the result
    is finite wherever √<v²> is. NaN for no values, inf when some value is infinite."""
    if not values.size:
        return float("nan")
    scale = float(np.max(np.abs(values)))
    if not (np.isfinite(scale) and scale > 0):
        return scale  # 0, inf or nan
    return scale * float(np.sqrt(np.mean((values / scale) ** 2)))


def _spectral_derivatives(h: FloatArray, size: tuple[float, float]) -> tuple[FloatArray, FloatArray, FloatArray]:
    nx, ny = h.shape
    F = sfft.rfft2(h)
    kx = 2.0 * np.pi * sfft.fftfreq(nx, d=size[0] / nx)
    ky = 2.0 * np.pi * sfft.rfftfreq(ny, d=size[1] / ny)
    if nx % 2 == 0:
        kx_d = kx.copy()
        kx_d[nx // 2] = 0.0  # the Nyquist mode has no defined derivative in a real signal
    else:
        kx_d = kx
    ky_d = ky.copy()
    if ny % 2 == 0:
        ky_d[-1] = 0.0
    gx = sfft.irfft2(1j * kx_d[:, None] * F, s=h.shape)
    gy = sfft.irfft2(1j * ky_d[None, :] * F, s=h.shape)
    lap = sfft.irfft2(-(kx[:, None] ** 2 + ky[None, :] ** 2) * F, s=h.shape)
    return gx, gy, lap


def _smooth_component_2d(h: FloatArray) -> FloatArray:
    """The smooth component s of Moisan's periodic + smooth decomposition of a map."""
    nx, ny = h.shape
    v = np.zeros_like(h)
    v[0, :] += h[-1, :] - h[0, :]
    v[-1, :] += h[0, :] - h[-1, :]
    v[:, 0] += h[:, -1] - h[:, 0]
    v[:, -1] += h[:, 0] - h[:, -1]
    den = (2.0 * np.cos(2.0 * np.pi * np.arange(nx) / nx)[:, None]
           + 2.0 * np.cos(2.0 * np.pi * np.arange(ny // 2 + 1) / ny)[None, :] - 4.0)
    den[0, 0] = 1.0
    S = sfft.rfft2(v) / den
    S[0, 0] = 0.0
    return sfft.irfft2(S, s=h.shape)


def _smooth_component_1d(h: FloatArray) -> FloatArray:
    """The same for each profile (row) of ``h``: s carries the mismatch h[-1] - h[0]."""
    n = h.shape[1]
    v = np.zeros_like(h)
    v[:, 0] = h[:, -1] - h[:, 0]
    v[:, -1] = h[:, 0] - h[:, -1]
    den = 2.0 * np.cos(2.0 * np.pi * np.arange(n // 2 + 1) / n) - 2.0
    den[0] = 1.0
    S = sfft.rfft(v, axis=1) / den[None, :]
    S[:, 0] = 0.0
    return sfft.irfft(S, n=n, axis=1)


def _profile_derivatives(h: FloatArray, dx: float) -> tuple[FloatArray, FloatArray]:
    """Spectral first and second derivatives along the rows (profiles) of a periodic ``h``."""
    n = h.shape[1]
    k = 2.0 * np.pi * sfft.rfftfreq(n, d=dx)
    kd = k.copy()
    if n % 2 == 0:
        kd[-1] = 0.0  # the Nyquist mode has no defined derivative in a real signal
    F = sfft.rfft(h, axis=1)
    return sfft.irfft(1j * kd * F, n=n, axis=1), sfft.irfft(-(k**2) * F, n=n, axis=1)


def surface_statistics(
    surface: Topography | LineScans | Prepared,
    spectrum: PowerSpectrum | None = None,
    *,
    detrend: Detrend = "auto",
) -> SurfaceStatistics:
    """Statistics of a map or line scans (detrended as in :func:`prepare`), and of ``spectrum`` if given."""
    prepared = surface if isinstance(surface, Prepared) else prepare(surface, detrend=detrend, window="none")
    s = prepared.surface
    h = np.asarray(s.heights)
    good = prepared.defined
    hv = h[good]
    h_rms = _rms(hv)
    if h_rms > 0:  # moments of the heights in units of h_rms: no overflow of hv**4 for any height a double holds
        u = hv / h_rms
        skew, kurt = float(np.mean(u**3)), float(np.mean(u**4))
    else:
        skew = kurt = float("nan")
    if isinstance(s, Topography):
        dx, dy = s.pixel_size
        if s.periodic:
            gx, gy, lap = _spectral_derivatives(h, s.size)
            method = "spectral derivatives (periodic map)"
        else:
            sm = _smooth_component_2d(h)
            gx, gy, lap = _spectral_derivatives(h - sm, s.size)
            sx, sy = np.gradient(sm, dx, dy)
            gx += sx
            gy += sy
            lap += np.gradient(np.gradient(sm, dx, axis=0), dx, axis=0)
            lap += np.gradient(np.gradient(sm, dy, axis=1), dy, axis=1)
            del sm, sx, sy
            method = "spectral derivatives of the periodic component + finite differences of the smooth one"
        grad = np.hypot(gx, gy)[good]  # |∇h|, without squaring (a steep map's |∇h|² can overflow)
        slope = _rms(grad)
        area = float(np.mean(np.hypot(1.0, grad)))
        curv = _rms(lap[good])
    else:
        dx = s.pixel_size
        if s.periodic:
            g, c = _profile_derivatives(h, dx)
            method = "spectral derivatives (periodic profiles), converted for an isotropic surface"
        else:
            sm = _smooth_component_1d(h)
            g, c = _profile_derivatives(h - sm, dx)
            g += np.gradient(sm, dx, axis=1)
            c += np.gradient(np.gradient(sm, dx, axis=1), dx, axis=1)
            method = ("spectral derivatives of the periodic component + finite differences of the smooth one, "
                      "along the profiles, converted for an isotropic surface")
        slope = float(np.sqrt(2.0)) * _rms(g[good])
        cg = c[good]
        curv = float(np.sqrt(8.0 / 3.0)) * _rms(cg[np.isfinite(cg)])
        area = float(area_ratio_from_slope(slope))
    return SurfaceStatistics(h_rms=h_rms, slope_rms=slope, curvature_rms=curv, area_ratio=area, skewness=skew,
                             kurtosis=kurt, **_spectral(spectrum), method=method)
