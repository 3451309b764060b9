"""Contact of a smooth cylinder (an O-ring's cross-section) with a rough surface: periodic along the seal line, free across it.

Problem (docs/theory.md §10.4). The rubber cylinder of radius R (axis along y, the seal line) is
pressed with a force f per unit length of seal line onto a rigid rough surface h(x, y); with the
contact modulus E* this is the same as a rigid surface of heights

    H(x, y) = h(x, y) - (x - x_c)² / (2R)

pressed onto an elastic half-space (the parabolic approximation of the cylinder, Johnson, Contact
Mechanics (1985) ch. 4). The computational domain is 0 <= x <= W across the band (cells dx = W/nx)
and one period 0 <= y < Ly along the seal line (dy = Ly/ny). Unlike :mod:`._contact`, the half-space
is **not** periodic across the band: pressure outside 0 <= x <= W is zero, so a band in the middle
of a domain 2-3 contact widths wide is an isolated line contact, not one of a row of neighbours.

Green's function, mixed form. Along y the pressure is a Fourier series, p(x, y) = Σ_k p_k(x) e^(iky),
k = 2πj/Ly; across x it is constant on each cell. For one mode the surface displacement of the
Boussinesq half-space, u = (1/(π E*)) ∫ p(x') / r dA' (Boussinesq; Johnson 1985 ch. 3, with E* = E/(1-ν²)),
integrated over y' gives a one-dimensional convolution along x,

    u_k(x) = ∫ G_k(x - x') p_k(x') dx',
    G_k(s) = (2/(π E*)) K0(|k| |s|)          (k ≠ 0;  ∫ e^(iky)/√(s²+y²) dy = 2 K0(|k||s|))
    G_0(s) = -(2/(π E*)) ln(|s|/ℓ)           (k = 0: the plane-strain line load, Johnson 1985 ch. 2)

The line load's displacement is defined only up to a constant (ℓ, here the domain width W): it
shifts every cell equally and is absorbed in the rigid-body approach, which is therefore not a
property of the solution and is not reported. A cell of width dx with unit pressure then displaces
the centre of the cell m columns away by

    K_k[m] = (2/(π E*|k|)) [I(|k|(|m|+½)dx) - I(|k|(|m|-½)dx)],   I(z) = ∫₀^z K0(t) dt  (scipy.special.iti0k0)
    K_0[m] = -(2/(π E*)) [F((|m|+½)dx) - F((|m|-½)dx)],          F(t) = t ln(t/ℓ) - t

(|m|-½ read as 0 for m = 0, with the integral taken over both halves of the cell). The convolution
over the nx columns is evaluated exactly, without wrap-around, by the discrete-convolution FFT of
Liu, Wang & Liu (Wear 243 (2000) 101, "DC-FFT"): the kernel is laid out for the offsets
-(nx-1) .. nx-1 on a grid of 2nx points, the pressure is zero-padded to 2nx columns, and the first nx
columns of the circular convolution are the linear one. Along y the convolution is periodic by
construction (the Fourier series). Cost per product: one real FFT pair on a 2nx × ny grid.

Solver: the same constrained conjugate gradient as :mod:`._contact` (Polonsky & Keer, Wear 231 (1999)
206; shared code), force-controlled: the mean pressure over the domain is f/W. The preconditioner is
the periodic Fourier stiffness E*|q|/2 of the nx × ny cell, exact for a periodic full contact and
close to the inverse of the free operator inside the band. The stopping test is the scale-free
residual of :mod:`._contact` with the height scale

    s = max(h_rms, 10⁻⁴ b_H²/(2R)),   b_H = √(4 f R/(π E*))  (Hertz half-width, Johnson 1985 eq. 4.43)

(h_rms of the rough part h; for a smooth cylinder the sag b_H²/(2R) of the contact edge sets the scale).
The iteration starts from the Hertz semi-ellipse p = p_max √(1 - (x - x_c)²/b_H²), p_max = 2f/(π b_H),
unless a previous solution is given.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Unpack

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import fft as sfft
from scipy import special

from ..errors import InputError, positive_values
from ._contact import ContactField, ContactOptions, _constrained_cg, contact_options
from ._memory import require_memory
from ._xp import contiguous, irfft2, maximum_into, namespace, rfft2, to_namespace

__all__ = ["BandContactResult", "solve_band_contact", "band_displacement", "band_contact_memory_bytes",
           "hertz_line_contact", "contact_edges"]

FloatArray = NDArray[np.float64]

#: Height scale of the residual for a smooth cylinder, relative to the Hertz sag b_H²/(2R) (module docstring).
SAG_SCALE = 1e-4


def hertz_line_contact(force_per_length: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz contact of a cylinder on a flat: half-width b (m) and peak pressure p_max (Pa).

    b = √(4 f R/(π E*)), p_max = 2 f/(π b) (Johnson, Contact Mechanics (1985) eqs. 4.43, 4.45;
    docs/theory.md §10.4, eq. 10.13), with f the force per unit length (N/m), R the radius (m), E* (Pa).
    """
    b = math.sqrt(4.0 * force_per_length * radius / (math.pi * e_star))
    return b, 2.0 * force_per_length / (math.pi * b)


@dataclass(frozen=True, eq=False, kw_only=True)
class BandContactResult(ContactField):
    """Solution of one cylinder-on-rough-surface problem on an nx × ny grid (arrays indexed [x, y]).

    The derived properties (the contact columns, width and edges) work on NumPy arrays: take a GPU solution's
    :meth:`~sealeak.numerics.ContactField.on_host` first.

    :class:`~sealeak.numerics._contact.ContactField`'s gap (m) and pressure (Pa), and

    Attributes
    ----------
    force_per_length:
        The prescribed load f (N per m of seal line); Σ p dx dy / Ly = f.
    width, period:
        Domain across the band W (m, free edges) and along the seal line Ly (m, periodic).
    radius, center:
        Cylinder radius R (m) and the x of its axis (m).
    e_star:
        Contact modulus (Pa).
    contact_area:
        Fraction of the domain's cells in contact (pressure > 0).
    iterations, residual, tol:
        Conjugate-gradient iterations, final scale-free residual and the requested tolerance.
    height_scale:
        The residual's height scale s (m; module docstring).
    """

    force_per_length: float
    width: float
    period: float
    radius: float
    center: float
    e_star: float
    contact_area: float
    iterations: int
    residual: float
    tol: float
    height_scale: float

    @property
    def dx(self) -> float:
        """Cell size across the band (m)."""
        return self.width / self.pressure.shape[0]

    @property
    def x(self) -> FloatArray:
        """Cell centres across the band (m), 0 at the domain's inlet edge."""
        return (np.arange(self.pressure.shape[0], dtype=np.float64) + 0.5) * self.dx

    @property
    def line_pressure(self) -> FloatArray:
        """Pressure averaged along the seal line, p̄(x) (Pa); ∫ p̄ dx = f."""
        return self.pressure.mean(axis=1)

    @property
    def max_pressure(self) -> float:
        """Largest cell pressure (Pa)."""
        return float(self.pressure.max())

    @property
    def contact_columns(self) -> tuple[int, int]:
        """First and last column (x index) holding contact; (-1, -1) without contact."""
        cols = np.flatnonzero(self.contact.any(axis=1))
        return (int(cols[0]), int(cols[-1])) if cols.size else (-1, -1)

    @property
    def contact_width(self) -> float:
        """Extent of the contact across the band (m): from the first to the last column with contact, whole cells."""
        a, b = self.contact_columns
        return (b - a + 1) * self.dx if a >= 0 else 0.0

    @property
    def touches_edge(self) -> bool:
        """Whether contact reaches the first or last column: the domain is too narrow for the band."""
        a, b = self.contact_columns
        return a == 0 or b == self.pressure.shape[0] - 1


def band_contact_memory_bytes(nx: int, ny: int) -> int:
    """Peak memory of :func:`solve_band_contact` on an nx × ny grid in bytes (estimate).

    Fourteen nx × ny float64 arrays as in the periodic solver (heights, pressure, displacement, gap,
    directions, masks, temporaries, result), the real kernel and preconditioner on the padded
    2nx × (ny/2+1) and nx × (ny/2+1) half-spectra, and three complex padded half-spectra.
    """
    nx, ny = int(nx), int(ny)
    half = (ny // 2 + 1)
    return int(8 * nx * ny * 14 + 8 * (2 * nx + nx) * half + 16 * 2 * nx * half * 3)


def _band_kernel(nx: int, ny: int, width: float, period: float, e_star: float) -> FloatArray:
    """Fourier transform over the 2nx padded columns of the cell influence coefficients K_k[m] (m/Pa).

    Shape (2nx, ny//2+1), real (the kernel is even in m); column j is the mode k = 2πj/Ly of
    ``scipy.fft.rfft`` along y (module docstring).
    """
    dx = width / nx
    m = np.abs(np.concatenate([np.arange(nx + 1), -np.arange(nx - 1, 0, -1)])).astype(float)  # offsets, DC-FFT layout
    hi = (m + 0.5) * dx
    lo = np.maximum(m - 0.5, 0.0) * dx
    c = 2.0 / (math.pi * e_star)
    k = 2.0 * math.pi * sfft.rfftfreq(ny, d=period / ny)
    kern = np.empty((2 * nx, k.size))

    def f_log(t: FloatArray) -> FloatArray:  # ∫₀^t ln(s/ℓ) ds with ℓ = W
        out = np.zeros_like(t)
        pos = t > 0
        out[pos] = t[pos] * np.log(t[pos] / width) - t[pos]
        return out

    col0 = -c * (f_log(hi) - f_log(lo))
    col0[0] *= 2.0  # both halves of the own cell
    kern[:, 0] = col0
    if k.size > 1:
        kk = k[None, 1:]
        i_hi = special.iti0k0(kk * hi[:, None])[1]
        i_lo = special.iti0k0(kk * lo[:, None])[1]
        part = c / kk * (i_hi - i_lo)
        part[0] *= 2.0
        kern[:, 1:] = part
    return np.ascontiguousarray(sfft.fft(kern, axis=0).real)


def _check_grid(heights: ArrayLike, width: float, period: float, e_star: float) -> FloatArray:
    xp = namespace(heights)
    h = xp.asarray(heights, dtype=xp.float64)
    if h.ndim != 2 or h.shape[0] < 4 or h.shape[1] < 1:
        raise InputError("heights", f"array of shape {tuple(h.shape)}", "must be an nx × ny array with nx >= 4, ny >= 1")
    if not bool(xp.all(xp.isfinite(h))):
        raise InputError("heights", "non-finite values", "heights must be finite (no NaN or inf)")
    positive_values(("width", width, "a length > 0 (m)"), ("period", period, "a length > 0 (m)"),
                    ("e_star", e_star, "a contact modulus > 0 (Pa)"))
    return h


def band_displacement(pressure: ArrayLike, width: float, period: float, e_star: float, *, workers: int = -1) -> FloatArray:
    """Surface displacement u[x, y] (m) of the half-space under the cell pressures p[x, y] (Pa).

    Free (no pressure) outside 0 <= x <= ``width``, periodic with ``period`` along y (eqs. 10.11, 10.12; module
    docstring; Liu, Wang & Liu, Wear 243 (2000) 101). The y-uniform part is defined up to one
    additive constant (the plane-strain line load), the same for every cell.
    """
    p = _check_grid(pressure, width, period, e_star)
    nx, ny = p.shape
    kernel = _band_kernel(nx, ny, float(width), float(period), float(e_star))
    return _convolver(to_namespace(kernel, p), nx, ny, workers, namespace(p))(p)


def _convolver(kernel: FloatArray, nx: int, ny: int, workers: int, xp: Any) -> Callable[[FloatArray], FloatArray]:
    def convolve(x: FloatArray) -> FloatArray:
        spec = rfft2(x, xp, workers, s=(2 * nx, ny))  # zero-padded to 2nx columns
        spec *= kernel
        return contiguous(irfft2(spec, xp, workers, (2 * nx, ny))[:nx, ...], xp)

    return convolve


def solve_band_contact(
    heights: ArrayLike,
    width: float,
    period: float,
    e_star: float,
    radius: float,
    force_per_length: float,
    *,
    center: float | None = None,
    initial: BandContactResult | None = None,
    **options: Unpack[ContactOptions],
) -> BandContactResult:
    """Frictionless contact of a smooth elastic cylinder with a rigid rough surface, free across the band.

    Solves g = u - H + c >= 0, p >= 0, g p = 0, Σ p dx dy = f Ly with H = h - (x - x_c)²/(2R) and u
    from the half-space Green's function, zero-padded across x and periodic along y (module
    docstring; docs/theory.md §10.4, eqs. 10.9, 10.10).

    Parameters
    ----------
    heights:
        Rough-surface heights h[x, y] (m) on an nx × ny grid (any mean); zeros for a smooth surface. An array
        of another namespace (CuPy on a GPU) is solved there, as for :func:`~sealeak.numerics.solve_contact`.
    width:
        Domain across the band W (m); cells dx = W/nx. It must hold the whole contact band.
    period:
        Period along the seal line Ly (m); cells dy = Ly/ny.
    e_star:
        Contact modulus E* (Pa) of the rubber (and the substrate).
    radius:
        Cylinder radius R (m): half the O-ring's cross-section diameter.
    force_per_length:
        Load f per unit length of seal line (N/m).
    center:
        x of the cylinder's axis (m); default W/2.
    initial:
        A previous :class:`BandContactResult` on the same grid; its pressure, rescaled to the load,
        starts the iteration (e.g. along increasing loads).
    options:
        The solver's :class:`~sealeak.numerics.ContactOptions` (``tol``, ``max_iter``, ``workers``,
        ``precondition``, ``memory_limit``), as for :func:`~sealeak.numerics.solve_contact`.

    Returns
    -------
    BandContactResult
    """
    h = _check_grid(heights, width, period, e_star)
    xp = namespace(h)
    positive_values(("radius", radius, "a length > 0 (m)"),
                    ("force_per_length", force_per_length, "a force per length > 0 (N/m)"))
    o = contact_options(options)
    width, period, e_star, radius, f = float(width), float(period), float(e_star), float(radius), float(force_per_length)
    xc = width / 2.0 if center is None else float(center)
    if not (0.0 <= xc <= width):
        raise InputError("center", center, f"must lie inside the domain 0 .. {width:.6g} m")
    nx, ny = h.shape
    require_memory(band_contact_memory_bytes(nx, ny), f"the {nx}x{ny} band contact problem", o["memory_limit"])
    dx = width / nx
    x = (np.arange(nx) + 0.5) * dx  # host arrays (the cylinder's shape, the Hertz start) are moved to h's device
    rough = h - float(xp.mean(h))
    h_rms = float(xp.sqrt(xp.mean(rough**2)))
    b_h, p_h = hertz_line_contact(f, radius, e_star)
    scale = max(h_rms, SAG_SCALE * b_h**2 / (2.0 * radius))
    hs = rough - to_namespace(((x - xc) ** 2 / (2.0 * radius))[:, None], h)
    p0 = f / width  # mean pressure over the domain

    if initial is not None:
        if initial.pressure.shape != h.shape:
            raise InputError("initial", f"result on a {tuple(initial.pressure.shape)} grid", f"must come from the same {nx}x{ny} grid")
        p = initial.pressure * (p0 / float(xp.mean(initial.pressure)))
    else:
        s = 1.0 - ((x - xc) / b_h) ** 2
        line = p_h * np.sqrt(np.clip(s, 0.0, None))
        if np.count_nonzero(line) >= 2:
            p = np.repeat(line[:, None], ny, axis=1)
            p *= p0 / float(p.mean())
            p = to_namespace(p, h)
        else:
            p = xp.full_like(hs, p0)

    kernel = _band_kernel(nx, ny, width, period, e_star)
    workers = o["workers"]
    convolve = _convolver(to_namespace(kernel, h), nx, ny, workers, xp)
    stiffness = None
    if o["precondition"]:
        kx = 2.0 * math.pi * sfft.fftfreq(nx, d=dx)
        ky = 2.0 * math.pi * sfft.rfftfreq(ny, d=period / ny)
        stiff = to_namespace(0.5 * e_star * np.sqrt(kx[:, None] ** 2 + ky[None, :] ** 2), h)

        def stiffness(g: FloatArray) -> FloatArray:
            spec = rfft2(g, xp, workers)
            spec *= stiff
            return irfft2(spec, xp, workers, (nx, ny))

    label = f"{nx}x{ny} band, f = {f:.6g} N/m"
    p, g, _, residual, it = _constrained_cg(hs, p, p0, scale, convolve, stiffness, float(o["tol"]), int(o["max_iter"]), label)
    gap = maximum_into(g, 0.0, g, xp)
    return BandContactResult(
        gap=gap, pressure=p, force_per_length=f, width=width, period=period, radius=radius, center=xc,
        e_star=e_star, contact_area=float(xp.count_nonzero(p > 0)) / p.size, iterations=it, residual=residual,
        tol=float(o["tol"]), height_scale=scale)


def contact_edges(x: ArrayLike, pressure: ArrayLike) -> tuple[float, float]:
    """Edges (m) of a smooth contact from a pressure line p(x) on cell centres, to a fraction of a cell.

    Near the edge of a smooth (non-conforming) contact p ∝ √(distance to the edge) (Johnson 1985
    ch. 4; docs/theory.md §10.4), so p² is linear there: each edge is where the straight line through
    p² of the two outermost loaded cells reaches zero (clipped to the next empty cell centre).
    Returns (NaN, NaN) when fewer than three cells carry pressure.
    """
    xs = np.asarray(x, dtype=float)
    p = np.asarray(pressure, dtype=float)
    idx = np.flatnonzero(p > 0)
    if idx.size < 3:
        return float("nan"), float("nan")
    dx = float(xs[1] - xs[0])
    a, b = int(idx[0]), int(idx[-1])
    q = p * p

    def edge(i: int, j: int, direction: float) -> float:  # i the outermost loaded cell, j its inner neighbour
        slope = (q[j] - q[i]) / dx  # > 0 for a rising p² towards the inside
        reach = q[i] / slope if slope > 0 else 0.5 * dx
        return float(xs[i] + direction * min(reach, dx))

    return edge(a, a + 1, -1.0), edge(b, b - 1, 1.0)
