"""Surface roughness power spectra C(q) in Persson's convention.

Convention (docs/theory.md §1.1–§1.2; Persson, J. Chem. Phys. 115 (2001) 3840)::

    C(q) = 1/(2π)² ∫ d²x <h(x) h(0)> exp(-i q·x)       [m⁴], isotropic, q = |q| in 1/m
    h_rms²        = 2π ∫ q  C(q) dq
    slope_rms²    = 2π ∫ q³ C(q) dq      (= <|∇h|²>)
    curvature_rms² = 2π ∫ q⁵ C(q) dq     (= <(∇²h)²>)

A :class:`PowerSpectrum` holds C at nodes q_0 < q_1 < ... < q_n and is a piecewise power law between
them (log C linear in log q), zero outside [q_0, q_n]. That representation is exact for the
self-affine model with roll-off, and every band moment ∫ qⁿ C dq is then a closed form
(docs/theory.md §1.3), so nothing downstream needs quadrature over C itself.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ..errors import FileFormatError, InputError
from ..io.quantities import quantity
from ..io.tables import read_spectrum_table

__all__ = ["PowerSpectrum", "area_ratio_from_slope"]

FloatArray = NDArray[np.float64]


def _exprel(z: FloatArray) -> FloatArray:
    """(e^z - 1)/z, equal to 1 at z = 0 (scipy.special.exprel)."""
    return special.exprel(z)


def _log1prel(z: FloatArray) -> FloatArray:
    """log(1 + z)/z, equal to 1 at z = 0 (log1p is accurate to rounding for small z, so only z = 0 is special)."""
    z = np.asarray(z, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.log1p(z) / z
    return np.where(z == 0.0, 1.0, out)


def area_ratio_from_slope(slope_rms: float | FloatArray) -> float | FloatArray:
    """True over nominal surface area, A_true/A0 = <√(1+|∇h|²)>, for Gaussian isotropic slopes.

    |∇h|² is then exponentially distributed with mean m = slope_rms², which gives the closed form
    ``1 + (√(π m)/2) erfcx(1/√m)`` (erfcx(x) = exp(x²) erfc(x)); docs/theory.md §1.2 (eq. 1.3). ``slope_rms``
    is dimensionless; so is the ratio.
    """
    m = np.asarray(slope_rms, dtype=float) ** 2
    with np.errstate(divide="ignore"):
        inv = np.where(m > 0, 1.0 / np.sqrt(np.where(m > 0, m, 1.0)), np.inf)
    out = 1.0 + 0.5 * np.sqrt(np.pi * m) * special.erfcx(inv)
    out = np.where(m > 0, out, 1.0)
    return float(out) if np.ndim(out) == 0 else out


@dataclass(frozen=True, eq=False)
class PowerSpectrum:
    """Isotropic 2D roughness power spectrum C(q), piecewise power law between nodes.

    Between nodes log C is linear in log q; C = 0 below ``q[0]`` and above ``q[-1]``
    (docs/theory.md §1.3). Instances are immutable (their arrays are read-only).

    Parameters
    ----------
    q:
        Node wavevectors in 1/m, strictly increasing, positive and finite.
    C:
        C at the nodes in m⁴, positive and finite.
    label:
        Free text describing where the spectrum comes from (shown in reports and figures).
    """

    q: FloatArray = quantity("1/m", "wavevectors q of the power spectrum's nodes")
    C: FloatArray = quantity("m^4", "isotropic power spectrum C(q) at the nodes")
    label: str = ""
    _cum: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        q = np.array(self.q, dtype=float, copy=True).ravel()
        C = np.array(self.C, dtype=float, copy=True).ravel()
        if q.size != C.size:
            raise InputError("spectrum", f"{q.size} q values and {C.size} C values", "q and C need the same length")
        if q.size < 2:
            raise InputError("spectrum.q", f"{q.size} point(s)", "at least two points are needed")
        bad = ~np.isfinite(q)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"spectrum.q[{i}]", float(q[i]), "q must be finite (no NaN or inf)")
        bad = ~np.isfinite(C)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"spectrum.C[{i}]", float(C[i]), "C must be finite (no NaN or inf)")
        if (q <= 0).any():
            i = int(np.argmax(q <= 0))
            raise InputError(f"spectrum.q[{i}]", float(q[i]), "q must be > 0 (1/m)")
        if (C <= 0).any():
            i = int(np.argmax(C <= 0))
            raise InputError(f"spectrum.C[{i}]", float(C[i]),
                             "C must be > 0 (m^4); drop rows outside the measured band instead of zeroing them")
        steps = np.diff(q)
        if (steps <= 0).any():
            i = int(np.argmax(steps <= 0)) + 1
            raise InputError(f"spectrum.q[{i}]", float(q[i]),
                             f"q must be strictly increasing (previous value {q[i - 1]:.6g})")
        q.setflags(write=False)
        C.setflags(write=False)
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "C", C)
        beta = np.log(C[1:] / C[:-1]) / np.log(q[1:] / q[:-1])
        beta.setflags(write=False)
        object.__setattr__(self, "_beta", beta)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def self_affine(
        cls,
        *,
        hurst: float,
        q_rolloff: float | None = None,
        q_cutoff: float | None = None,
        q_lowest: float | None = None,
        h_rms: float | None = None,
        C0: float | None = None,
        label: str = "",
        rolloff_wavelength: float | None = None,
        cutoff_wavelength: float | None = None,
        lowest_wavelength: float | None = None,
    ) -> PowerSpectrum:
        """Self-affine spectrum with roll-off (docs/theory.md §1.4, eqs. 1.5, 1.6; Persson et al., J. Phys.: Condens. Matter 17 (2005) R1)::

            C(q) = C0                          q_lowest <= q < q_rolloff
            C(q) = C0 (q/q_rolloff)^(-2(1+H))  q_rolloff <= q <= q_cutoff
            C(q) = 0                           otherwise

        Exactly one of ``h_rms`` (m) and ``C0`` (m⁴) fixes the amplitude (h_rms is that of the band
        [q_lowest, q_cutoff]). ``q_lowest`` defaults to ``q_rolloff`` (no plateau); above q_rolloff the
        band starts on the power law. All wavevectors in 1/m. Each wavevector may be given as a
        wavelength instead (``rolloff_wavelength`` etc., in m; q = 2π/λ), not both.
        """
        q_rolloff = cast(float, _wavevector_or_wavelength("rolloff", q_rolloff, rolloff_wavelength, required=True))
        q_cutoff = cast(float, _wavevector_or_wavelength("cutoff", q_cutoff, cutoff_wavelength, required=True))
        q_lowest = _wavevector_or_wavelength("lowest", q_lowest, lowest_wavelength, required=False)
        _check_positive("hurst", hurst, open_upper=1.0)
        _check_positive("q_rolloff", q_rolloff)
        _check_positive("q_cutoff", q_cutoff)
        if q_lowest is None:
            q_lowest = q_rolloff
        _check_positive("q_lowest", q_lowest)
        if not q_rolloff < q_cutoff:
            raise InputError("q_cutoff", q_cutoff,
                             f"must exceed the roll-off wavevector {q_rolloff:.6g} 1/m")
        if not q_lowest < q_cutoff:
            raise InputError("q_lowest", q_lowest,
                             f"must be below the cut-off wavevector {q_cutoff:.6g} 1/m")
        if (h_rms is None) == (C0 is None):
            raise InputError("h_rms", {"h_rms": h_rms, "C0": C0}, "give exactly one of h_rms and C0")
        decay = -2.0 * (1.0 + hurst)
        if q_lowest < q_rolloff:
            nodes = np.array([q_lowest, q_rolloff, q_cutoff])
            shape = np.array([1.0, 1.0, (q_cutoff / q_rolloff) ** decay])
        else:  # the band starts on the power law (roll-off at or below q_lowest)
            nodes = np.array([q_lowest, q_cutoff])
            shape = np.array([(q_lowest / q_rolloff) ** decay, (q_cutoff / q_rolloff) ** decay])
        if h_rms is not None:
            _check_positive("h_rms", h_rms)
            if not H_RMS_RANGE[0] <= h_rms <= H_RMS_RANGE[1]:
                raise InputError("h_rms", h_rms, f"must lie in [{H_RMS_RANGE[0]:g}, {H_RMS_RANGE[1]:g}] m: beyond it no surface "
                                                 "is rough and the contact mechanics leaves the range of floating-point "
                                                 "numbers; check the value and its unit")
            unit = cls(nodes, shape)
            with np.errstate(over="ignore", under="ignore"):
                C0 = float(np.float64(h_rms) ** 2 / unit.h_rms**2)
        else:
            _check_positive("C0", C0)
        with np.errstate(over="ignore", under="ignore"):
            values = shape * C0
        if not (np.isfinite(values).all() and (values > 0).all()):  # C(q) beyond what a float holds
            name, given = ("h_rms", h_rms) if h_rms is not None else ("C0", C0)
            raise InputError(name, given, "so far from any real roughness that C(q) is not representable as a "
                                          "float (it overflows or underflows); check the value and its unit")
        if not label:
            label = f"self-affine model, H = {hurst:g}"
        return cls(nodes, values, label=label)

    @classmethod
    def from_arrays(cls, q: ArrayLike, C: ArrayLike, label: str = "") -> PowerSpectrum:
        """Spectrum from tabulated values (q in 1/m, C in m⁴), validated."""
        return cls(np.asarray(q, dtype=float), np.asarray(C, dtype=float), label=label)

    @classmethod
    def from_table(cls, path: str | Path, label: str = "") -> PowerSpectrum:
        """Spectrum from a two-column text table q, C (:func:`sealeak.io.tables.read_spectrum_table`; docs/theory.md §1.5).

        q in 1/m and C in m⁴ unless a header row names other units, e.g. ``q (1/um), C (um^4)``.
        Problems (missing file, NaN, unsorted q, wrong units) raise :class:`FileFormatError`
        naming the file and line.
        """
        q, C = read_spectrum_table(path)
        try:
            return cls.from_arrays(q, C, label=label or f"table {Path(path).name}")
        except InputError as exc:
            raise FileFormatError(path, str(exc)) from None

    # ------------------------------------------------------------------ evaluation
    @property
    def q_min(self) -> float:
        """Lowest wavevector with C > 0 (1/m)."""
        return float(self.q[0])

    @property
    def q_max(self) -> float:
        """Short-wavelength cut-off q1 (1/m)."""
        return float(self.q[-1])

    @property
    def exponents(self) -> FloatArray:
        """Local power-law exponents d log C / d log q on each segment."""
        return self._beta  # type: ignore[attr-defined]

    def __call__(self, q: ArrayLike) -> FloatArray:
        """C(q) in m⁴ (log-log interpolation between nodes, zero outside the band)."""
        qa = np.asarray(q, dtype=float)
        inside = (qa >= self.q[0]) & (qa <= self.q[-1])
        qc = np.clip(qa, self.q[0], self.q[-1])
        k = np.clip(np.searchsorted(self.q, qc, side="right") - 1, 0, self.q.size - 2)
        val = self.C[k] * np.exp(self._beta[k] * np.log(qc / self.q[k]))  # type: ignore[attr-defined]
        return np.where(inside, val, 0.0)

    def sample(self, num: int = 400) -> tuple[FloatArray, FloatArray]:
        """A log-spaced grid of ``num`` points over the band with C on it, nodes included (for plots)."""
        qs = np.union1d(np.geomspace(self.q[0], self.q[-1], num), self.q)
        return qs, self(qs)

    # ------------------------------------------------------------------ moments
    def _node_cumulative(self, n: float) -> FloatArray:
        key = float(n)
        cum = self._cum.get(key)
        if cum is None:
            q, C, b = self.q, self.C, self._beta  # type: ignore[attr-defined]
            x = np.log(q[1:] / q[:-1])
            seg = C[:-1] * q[:-1] ** (n + 1.0) * x * _exprel((n + 1.0 + b) * x)
            cum = np.concatenate([[0.0], np.cumsum(seg)])
            cum.setflags(write=False)
            self._cum[key] = cum
        return cum

    def cumulative_moment(self, n: float, q: ArrayLike) -> FloatArray:
        """M_n(q) = ∫_{q_min}^{q} q'ⁿ C(q') dq' in m^(3-n), exact for the piecewise power law (docs/theory.md §1.3, eq. 1.4; vectorised over q)."""
        qa = np.asarray(q, dtype=float)
        qc = np.clip(qa, self.q[0], self.q[-1])
        k = np.clip(np.searchsorted(self.q, qc, side="right") - 1, 0, self.q.size - 2)
        cum = self._node_cumulative(n)
        x = np.log(qc / self.q[k])
        e = n + 1.0 + self._beta[k]  # type: ignore[attr-defined]
        return cum[k] + self.C[k] * self.q[k] ** (n + 1.0) * x * _exprel(e * x)

    def inverse_cumulative_moment(self, n: float, m: ArrayLike) -> FloatArray:
        """The q (1/m) at which M_n(q) = m (closed-form inverse of :meth:`cumulative_moment`, docs/theory.md §1.3; m clipped to the band).

        On segment k (exponent β_k, e = n + 1 + β_k), M_n(q) = M_n(q_k) + C_k q_k^(n+1) [(q/q_k)^e - 1]/e, so
        q = q_k exp(r log(1 + e r)/(e r)) with r = (m - M_n(q_k))/(C_k q_k^(n+1)).
        """
        cum = self._node_cumulative(n)
        ma = np.clip(np.asarray(m, dtype=float), 0.0, cum[-1])
        k = np.clip(np.searchsorted(cum, ma, side="right") - 1, 0, self.q.size - 2)
        start, scale, e = self._segment_constants(n, k)
        r = (ma - start) / scale
        x = r * _log1prel(e * r)
        return np.minimum(self.q[k] * np.exp(x), self.q[-1])

    def _segment_constants(self, n: float, k: NDArray[np.intp]) -> tuple[FloatArray, FloatArray, FloatArray]:
        """M_n(q_k), C_k q_k^(n+1) and e = n + 1 + β_k of segments k (the constants of :meth:`inverse_cumulative_moment`; cached per n)."""
        key = ("segments", float(n))
        table = self._cum.get(key)
        if table is None:
            table = (self.C[:-1] * self.q[:-1] ** (n + 1.0), n + 1.0 + self._beta)  # type: ignore[attr-defined]
            self._cum[key] = table
        return self._node_cumulative(n)[k], table[0][k], table[1][k]

    def moment(self, n: float, q_lo: ArrayLike | None = None, q_hi: ArrayLike | None = None) -> FloatArray | float:
        """Band moment ∫_{q_lo}^{q_hi} qⁿ C(q) dq in m^(3-n) (defaults: the whole band). Vectorised."""
        lo = self.q[0] if q_lo is None else q_lo
        hi = self.q[-1] if q_hi is None else q_hi
        out = self.cumulative_moment(n, hi) - self.cumulative_moment(n, lo)
        out = np.where(np.asarray(hi) > np.asarray(lo), out, 0.0)
        return float(out) if np.ndim(out) == 0 else out

    @property
    def h_rms(self) -> float:
        """Root-mean-square height in m: √(2π ∫ q C dq) (docs/theory.md §1.2, eq. 1.2)."""
        return float(np.sqrt(2.0 * np.pi * self.moment(1)))

    @property
    def slope_rms(self) -> float:
        """Root-mean-square slope (dimensionless): √(2π ∫ q³ C dq) (eq. 1.2)."""
        return float(np.sqrt(2.0 * np.pi * self.moment(3)))

    @property
    def curvature_rms(self) -> float:
        """Root-mean-square curvature ∇²h in 1/m: √(2π ∫ q⁵ C dq) (eq. 1.2)."""
        return float(np.sqrt(2.0 * np.pi * self.moment(5)))

    @property
    def area_ratio(self) -> float:
        """A_true/A0 for Gaussian slopes with this slope_rms (see :func:`area_ratio_from_slope`)."""
        return float(area_ratio_from_slope(self.slope_rms))

    # ------------------------------------------------------------------ derived spectra
    def truncated(self, q_lo: float | None = None, q_hi: float | None = None) -> PowerSpectrum:
        """The same C(q) restricted to [q_lo, q_hi] (new nodes inserted at the cuts)."""
        lo = self.q_min if q_lo is None else max(float(q_lo), self.q_min)
        hi = self.q_max if q_hi is None else min(float(q_hi), self.q_max)
        if not lo < hi:
            raise InputError("spectrum band", (q_lo, q_hi),
                             f"the cut must overlap the band [{self.q_min:.6g}, {self.q_max:.6g}] 1/m")
        inner = self.q[(self.q > lo) & (self.q < hi)]
        nodes = np.concatenate([[lo], inner, [hi]])
        return PowerSpectrum(nodes, self(nodes), label=self.label)

    def scaled(self, factor: float) -> PowerSpectrum:
        """C multiplied by ``factor`` (h_rms scales with √factor)."""
        _check_positive("spectrum scale factor", factor)
        return PowerSpectrum(self.q, self.C * factor, label=self.label)

    def refined(self, points_per_segment: int) -> PowerSpectrum:
        """The same function with extra nodes on every segment (identical C; for convergence tests)."""
        if points_per_segment < 1:
            raise InputError("points_per_segment", points_per_segment, "must be >= 1")
        pieces: list[Iterable[float]] = []
        for a, b in zip(self.q[:-1], self.q[1:]):
            pieces.append(np.geomspace(a, b, points_per_segment + 1)[:-1])
        nodes = np.concatenate([*pieces, [self.q[-1]]])
        return PowerSpectrum(nodes, self(nodes), label=self.label)

    def __repr__(self) -> str:
        return (f"PowerSpectrum({self.q.size} nodes, q = {self.q_min:.4g}..{self.q_max:.4g} 1/m, "
                f"h_rms = {self.h_rms:.4g} m, label={self.label!r})")


#: h_rms (m) a self-affine model accepts: from below a nucleus to a kilometre. Values far
#: outside what a seal meets are still computed (and warned about, docs/theory.md §9.11) inside it.
H_RMS_RANGE = (1e-15, 1e3)


def _check_positive(name: str, value: float | None, open_upper: float | None = None) -> None:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(name, value, "must be a number") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(name, value, "must be a finite number > 0")
    if open_upper is not None and not v < open_upper:
        raise InputError(name, value, f"must be < {open_upper:g}")


def _wavevector_or_wavelength(stem: str, q: float | None, wavelength: float | None, *, required: bool) -> float | None:
    """q (1/m) from either the wavevector or the wavelength (q = 2π/λ); exactly one when required."""
    if q is not None and wavelength is not None:
        raise InputError(f"q_{stem}", q, f"give either q_{stem} or {stem}_wavelength, not both")
    if wavelength is not None:
        _check_positive(f"{stem}_wavelength", wavelength)
        return 2.0 * np.pi / wavelength
    if q is None and required:
        raise InputError(f"q_{stem}", None, f"is required (or give {stem}_wavelength)")
    return q
