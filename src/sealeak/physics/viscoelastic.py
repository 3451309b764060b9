"""The seal over its life: viscoelastic rubber, time–temperature superposition, thermal contraction, ageing.

* :class:`PronySeries`: the relaxation modulus E(t) = E∞ + Σ Ei exp(−t/τi) (docs/theory.md §16.1, eq. 16.1), its
  storage and loss moduli (eq. 16.2) and its creep compliance J(t), exact by the roots of the Laplace transform
  (§16.2, eqs. 16.3–16.5);
* :class:`MasterCurve`: E(t) from measured (time, modulus) points, PCHIP in log–log, and its creep compliance by a
  Prony series fitted to it (§16.3);
* :class:`WLFShift`, :class:`ArrheniusShift`: the shift factor a_T (eqs. 16.6, 16.7); the modulus at time t and
  temperature T is E(t/a_T(T)) (eq. 16.8, :func:`modulus_at`);
* :func:`thermal_compression`: the O-ring's compression at temperature T in a gland that expands differently (eq. 16.9),
  and :func:`glass_transition_warnings` near and below Tg (§16.5);
* :func:`fit_compression_set`, :class:`CompressionSet`: the compression set c(t, T) with Arrhenius time–temperature
  scaling (eqs. 16.10, 16.11) and the compression left ε (1 − c) (eq. 16.12).

Plain SI: moduli in Pa, times in s, temperatures in K, expansion coefficients in 1/K, activation energies in J/mol.
Errors name the field given by the caller (``field``, e.g. ``rubber.relaxation``) and the parameter after it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from functools import cached_property
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.constants import R as GAS_CONSTANT
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq, least_squares, nnls

from ..errors import InputError, positive_number
from ..io.leak_units import celsius

__all__ = [
    "PronySeries", "MasterCurve", "WLFShift", "ArrheniusShift", "modulus_at", "universal_wlf_glass_transition",
    "thermal_compression", "expansion_coefficient", "glass_transition_warnings", "CompressionSet", "fit_compression_set", "remaining_compression",
    "MAX_TERMS", "MAX_POINTS", "FIT_TERMS_PER_DECADE", "FIT_POINTS_PER_DECADE",
    "PRONY_MODULI", "PRONY_TIMES", "UNIVERSAL_WLF_C1", "UNIVERSAL_WLF_C2", "GLASS_MARGIN", "NBR_LINEAR_EXPANSION",
]

FloatArray = NDArray[np.float64]

MAX_TERMS = 64
"""The most terms a Prony series may have (a fitted series has one or two per decade of time)."""

MAX_POINTS = 10_000
"""The most points a master curve or a compression-set table may have."""

PRONY_MODULI = (1.0, 1e12)
"""The range (Pa) of a Prony series' moduli: from a gel's to beyond a glassy polymer's (about 3 GPa). Beyond it the
retardation spectrum's roots leave the range of floating-point numbers."""

PRONY_TIMES = (1e-15, 1e15)
"""The range (s) of a Prony series' relaxation times: a femtosecond to 30 million years (a master curve's reduced
times span about 10⁻¹² to 10¹² s)."""

UNIVERSAL_WLF_C1 = 17.44
"""C1 of the WLF equation with Tg as the reference temperature, averaged over many polymers (Williams, Landel &
Ferry 1955; Ferry 1980, ch. 11): the 'universal' constant (1)."""

UNIVERSAL_WLF_C2 = 51.6
"""C2 (K) of the WLF equation with Tg as the reference temperature, the 'universal' constant (Williams, Landel &
Ferry 1955)."""

GLASS_MARGIN = 20.0
"""K above Tg within which :func:`glass_transition_warnings` warns: the modulus rises by decades over this range."""

NBR_LINEAR_EXPANSION = 23e-5
"""Linear thermal expansion coefficient (1/K) of an NBR seal compound, from a seal maker's table of elastomer properties
(Problem Solving Products, Inc., 'Seal thermal stability', www.pspglobal.com/prop-thermal-stability.html: 23 × 10⁻⁵;
steel about 1.0–1.3 × 10⁻⁵ in the same table). A compound's value varies with its filler; measure it if it matters."""


def _array(field: str, value: ArrayLike, what: str) -> FloatArray:
    """``value`` as a finite 1-D float array of at most :data:`MAX_POINTS` entries, else an InputError naming ``field``."""
    if isinstance(value, (str, bytes)):
        raise InputError(field, value, f"must be a list of numbers ({what})")
    arr = _floats(field, value, f"must be a list of numbers ({what})")
    if arr.ndim > 1 or arr.size > MAX_POINTS:
        raise InputError(field, value, f"must be a list of at most {MAX_POINTS} numbers ({what})")
    arr = np.atleast_1d(arr)
    if arr.size == 0:
        raise InputError(field, [], f"is empty: give at least one value ({what})")
    for i, v in enumerate(arr):
        if not math.isfinite(v):
            raise InputError(f"{field}[{i}]", float(v), f"must be finite ({what})")
    return arr


def _floats(field: str, value: ArrayLike, allowed: str) -> FloatArray:
    """``value`` (a number or numbers) as a float array, else an InputError naming ``field`` (missing: "is required")."""
    if value is None:
        raise InputError(field, None, f"is required: {allowed.removeprefix('must be ')}")
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError, RecursionError):
        raise InputError(field, value, allowed) from None


def _positive(field: str, value: float, what: str) -> float:
    """:func:`~sealeak.errors.positive_number` with the unit in its message."""
    return positive_number(field, value, allowed=f"must be finite and > 0 ({what})")


def _refuse_where(field: str, values: FloatArray, bad: NDArray[np.bool_], allowed: str, *, kelvin: bool = False) -> None:
    """An InputError naming ``field`` and the first of ``values`` where ``bad`` holds (NaN included by the caller);
    ``kelvin``: the values are temperatures (K), shown with their unit and in °C (``"123.15 K (-150 °C)"``)."""
    if np.any(bad):
        value = float(np.ravel(values)[np.flatnonzero(np.ravel(bad))[0]])
        raise InputError(field, _kelvin_text(value) if kelvin else value, allowed)


def _kelvin_text(temperature: float) -> str:
    """A temperature (K) as a message shows it: ``"123.15 K (-150 °C)"``."""
    return f"{temperature:.6g} K ({celsius(temperature):.4g} °C)"


def expansion_coefficient(field: str, alpha: float) -> float:
    """A linear thermal expansion coefficient α (1/K) checked: finite, of magnitude below 1e-2 1/K (else an InputError
    naming ``field``)."""
    a = _floats(field, alpha, "must be a number (1/K)")
    if a.ndim or not (math.isfinite(a) and abs(a) < 1e-2):
        raise InputError(field, alpha, "must be a linear expansion coefficient of magnitude below 1e-2 1/K")
    return float(a)


class RelaxationModulus(Protocol):
    """What :func:`modulus_at` needs: E(t) in Pa at reduced times t in s."""

    def relaxation_modulus(self, t: ArrayLike) -> FloatArray: ...


# --- the Prony series ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PronySeries:
    """E(t) = E∞ + Σ Ei exp(−t/τi) (docs/theory.md eq. 16.1), a generalized Maxwell solid.

    Parameters
    ----------
    equilibrium_modulus
        E∞ in Pa (> 0: a cross-linked rubber keeps a modulus at long times).
    moduli
        Ei in Pa (each > 0), at most :data:`MAX_TERMS`.
    times
        τi in s (each > 0, pairwise distinct by more than one part in 10⁹), as many as ``moduli``.
    field
        The name errors give the series (``rubber.relaxation``); the parameters follow it
        (``rubber.relaxation.moduli[1]``).
    """

    equilibrium_modulus: float
    moduli: tuple[float, ...]
    times: tuple[float, ...]
    field: str = dataclass_field(default="relaxation", compare=False)

    def __post_init__(self) -> None:
        f = self.field
        e_inf = _positive(f"{f}.equilibrium_modulus", self.equilibrium_modulus, "Pa")
        moduli = _array(f"{f}.moduli", self.moduli, "Pa")
        times = _array(f"{f}.times", self.times, "s")
        if moduli.size > MAX_TERMS:
            raise InputError(f"{f}.moduli", self.moduli, f"must have at most {MAX_TERMS} terms")
        if moduli.size != times.size:
            raise InputError(f"{f}.times", self.times, f"must have one relaxation time per modulus ({moduli.size})")
        if not PRONY_MODULI[0] <= e_inf <= PRONY_MODULI[1]:
            raise InputError(f"{f}.equilibrium_modulus", e_inf, f"must lie in [{PRONY_MODULI[0]:g}, {PRONY_MODULI[1]:g}] Pa")
        for name, arr, unit, (lo, hi) in (("moduli", moduli, "Pa", PRONY_MODULI), ("times", times, "s", PRONY_TIMES)):
            for i, v in enumerate(arr):
                if not v > 0:
                    raise InputError(f"{f}.{name}[{i}]", float(v), f"must be > 0 ({unit})")
                if not lo <= v <= hi:
                    raise InputError(f"{f}.{name}[{i}]", float(v), f"must lie in [{lo:g}, {hi:g}] {unit}")
        ordered = np.sort(times)
        close = np.flatnonzero(ordered[1:] <= ordered[:-1] * (1 + 1e-9))
        if close.size:
            raise InputError(f"{f}.times", self.times, f"must be distinct ({ordered[close[0]]:.6g} s appears twice): "
                                                       "add the moduli of equal times into one term")
        object.__setattr__(self, "equilibrium_modulus", e_inf)
        object.__setattr__(self, "moduli", tuple(float(v) for v in moduli))
        object.__setattr__(self, "times", tuple(float(v) for v in times))

    @property
    def instantaneous_modulus(self) -> float:
        """E(0) = E∞ + Σ Ei in Pa."""
        return self.equilibrium_modulus + math.fsum(self.moduli)

    def relaxation_modulus(self, t: ArrayLike) -> FloatArray:
        """E(t) in Pa at times t >= 0 in s (eq. 16.1)."""
        tt = np.asarray(t, dtype=float)
        e = np.full(tt.shape, self.equilibrium_modulus)
        for ei, taui in zip(self.moduli, self.times):
            e = e + ei * np.exp(-tt / taui)
        return e

    def storage_modulus(self, omega: ArrayLike) -> FloatArray:
        """E'(ω) = E∞ + Σ Ei ω²τi²/(1 + ω²τi²) in Pa at angular frequencies ω in rad/s (eq. 16.2)."""
        w = np.asarray(omega, dtype=float)
        e = np.full(w.shape, self.equilibrium_modulus)
        for ei, taui in zip(self.moduli, self.times):
            x = (w * taui) ** 2
            e = e + ei * x / (1 + x)
        return e

    def loss_modulus(self, omega: ArrayLike) -> FloatArray:
        """E''(ω) = Σ Ei ωτi/(1 + ω²τi²) in Pa at angular frequencies ω in rad/s (eq. 16.2)."""
        w = np.asarray(omega, dtype=float)
        e = np.zeros(w.shape)
        for ei, taui in zip(self.moduli, self.times):
            e = e + ei * w * taui / (1 + (w * taui) ** 2)
        return e

    @cached_property
    def _retardation_terms(self) -> tuple[FloatArray, FloatArray]:
        return _retardation(self.equilibrium_modulus, self.moduli, self.times)

    def retardation(self) -> tuple[FloatArray, FloatArray]:
        """(Jj in 1/Pa, λj in s), the creep compliance's terms J(t) = 1/E∞ − Σ Jj exp(−t/λj) (eqs. 16.4, 16.5).

        λj = −1/sj with sj the N roots of s Ē(s) = E∞ + Σ Ei s τi/(1 + s τi), one between each two neighbouring
        poles −1/τi and one between the slowest pole and 0; each found by Brent's method on the function times the
        factors (1 + s τ) of the two poles that bracket it, which is finite and changes sign there (§16.2).
        """
        weights, lam = self._retardation_terms
        return weights.copy(), lam.copy()

    def creep_compliance(self, t: ArrayLike) -> FloatArray:
        """J(t) in 1/Pa at times t >= 0 in s: the strain under a unit step of stress (eq. 16.5).

        J(0) = 1/E(0), J(∞) = 1/E∞; it satisfies ∫₀ᵗ E(t − s) J(s) ds = t (eq. 16.3).
        """
        weights, lam = self.retardation()
        tt = np.asarray(t, dtype=float)
        j = np.full(tt.shape, 1.0 / self.equilibrium_modulus)
        for wj, lj in zip(weights, lam):
            j = j - wj * np.exp(-tt / lj)
        return j


def _retardation(e_inf: float, moduli: Sequence[float], times: Sequence[float]) -> tuple[FloatArray, FloatArray]:
    order = np.argsort(times)
    tau = np.asarray(times, dtype=float)[order]
    ei = np.asarray(moduli, dtype=float)[order]

    def regular(s: float, poles: tuple[int, ...]) -> float:
        """s Ē(s) (eq. 16.4) × Π (1 + s τk) over the bracketing poles k: finite at those poles."""
        value = e_inf * math.prod(1 + s * tau[k] for k in poles)
        for k in range(tau.size):
            term = ei[k] * s * tau[k]
            for m in poles:
                if m != k:
                    term *= 1 + s * tau[m]
            value += term if k in poles else term / (1 + s * tau[k])
        return value

    roots = []
    for i in range(tau.size):
        poles = (i, i + 1) if i + 1 < tau.size else (i,)
        hi = math.log(1 / tau[i])  # u = ln(−s): s = −1/τi, the faster pole
        if i + 1 < tau.size:
            lo = math.log(1 / tau[i + 1])
        else:  # between the slowest pole and s = 0, where s Ē(s) = E∞ > 0
            lo = hi - 1.0
            while regular(-math.exp(lo), poles) * regular(-math.exp(hi), poles) > 0 and lo > hi - 200:
                lo -= 2.0
        u = brentq(lambda x: regular(-math.exp(x), poles), lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        roots.append(-math.exp(u))
    s = np.asarray(roots)
    slope = np.array([np.sum(ei * tau / (1 + sj * tau) ** 2) for sj in s])  # f'(s) > 0
    weights = 1.0 / (-s * slope)  # minus the residue of 1/(s² Ē(s)) at sj
    return weights, -1.0 / s


# --- the master curve ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MasterCurve:
    """E(t) from a measured relaxation master curve at its reference temperature (§16.3).

    ``times`` (s, > 0, increasing) and ``moduli`` (Pa, > 0, non-increasing: a relaxation modulus never rises),
    2 to :data:`MAX_POINTS` points; interpolated by a monotone cubic (PCHIP) in log t, log E, held at the first and
    last modulus outside the measured times. ``field`` names the curve in errors (``rubber.relaxation.master_curve``).
    """

    times: tuple[float, ...]
    moduli: tuple[float, ...]
    field: str = dataclass_field(default="master_curve", compare=False)

    def __post_init__(self) -> None:
        f = self.field
        times = _array(f"{f}.time", self.times, "s")
        moduli = _array(f"{f}.modulus", self.moduli, "Pa")
        if times.size != moduli.size:
            raise InputError(f"{f}.modulus", self.moduli, f"must have one modulus per time ({times.size})")
        if times.size < 2:
            raise InputError(f"{f}.time", self.times, "must have at least 2 points")
        for name, arr, unit in (("time", times, "s"), ("modulus", moduli, "Pa")):
            for i, v in enumerate(arr):
                if not v > 0:
                    raise InputError(f"{f}.{name}[{i}]", float(v), f"must be > 0 ({unit}): the curve is interpolated in log–log")
        for i in range(1, times.size):
            if not times[i] > times[i - 1]:
                raise InputError(f"{f}.time[{i}]", float(times[i]), f"must exceed the time before it ({times[i - 1]:.6g} s): "
                                                                     "times increase")
            if moduli[i] > moduli[i - 1]:
                raise InputError(f"{f}.modulus[{i}]", float(moduli[i]), f"must not exceed the modulus before it "
                                                                         f"({moduli[i - 1]:.6g} Pa): a relaxation modulus "
                                                                         "falls with time")
        object.__setattr__(self, "times", tuple(float(v) for v in times))
        object.__setattr__(self, "moduli", tuple(float(v) for v in moduli))

    @property
    def instantaneous_modulus(self) -> float:
        """The modulus at the first measured time (Pa), the curve's value as t → 0."""
        return self.moduli[0]

    @property
    def equilibrium_modulus(self) -> float:
        """The modulus at the last measured time (Pa), the curve's value as t → ∞."""
        return self.moduli[-1]

    @cached_property
    def _spline(self) -> PchipInterpolator:
        return PchipInterpolator(np.log10(np.asarray(self.times)), np.log10(np.asarray(self.moduli)))

    def relaxation_modulus(self, t: ArrayLike) -> FloatArray:
        """E(t) in Pa at times t in s; held at the end values outside the measured times."""
        tt = np.asarray(t, dtype=float)
        with np.errstate(divide="ignore"):
            x = np.clip(np.log10(np.maximum(tt, 0.0)), math.log10(self.times[0]), math.log10(self.times[-1]))
        return np.asarray(10.0 ** self._spline(x), dtype=float)

    @cached_property
    def prony(self) -> PronySeries | None:
        """A Prony series fitted to the curve (§16.3): relaxation times :data:`FIT_TERMS_PER_DECADE` per
        decade over the measured times (within :data:`PRONY_TIMES`), E∞ and Ei >= 0 by non-negative least squares on
        the relative error at :data:`FIT_POINTS_PER_DECADE` points per decade from two decades before to two after the
        measured times (where the curve is held); terms below 10⁻⁶ E(0) are dropped. None where no term is left (a
        curve that does not relax, or relaxes only outside :data:`PRONY_TIMES`)."""
        return _fit_prony(self)

    def creep_compliance(self, t: ArrayLike) -> FloatArray:
        """J(t) in 1/Pa at times t >= 0 in s: the exact creep compliance (eq. 16.5) of :attr:`prony`; 1/E(t) where it
        is None (exact for a curve that does not relax)."""
        if self.prony is None:
            return np.asarray(1.0 / self.relaxation_modulus(t), dtype=float)
        return self.prony.creep_compliance(t)


FIT_TERMS_PER_DECADE = 2
"""Relaxation times per decade of the Prony series :attr:`MasterCurve.prony` fits (Park & Schapery 1999: one to two)."""

FIT_POINTS_PER_DECADE = 8
"""Collocation points per decade of the fit of :attr:`MasterCurve.prony`."""


def _fit_prony(curve: MasterCurve) -> PronySeries | None:
    bounds = [math.log10(b) for b in PRONY_TIMES]  # a Prony series' times stay in PRONY_TIMES
    lo, hi = (min(max(math.log10(t), bounds[0]), bounds[1]) for t in (curve.times[0], curve.times[-1]))
    span = hi - lo
    terms = min(MAX_TERMS - 1, max(2, math.ceil(FIT_TERMS_PER_DECADE * span) + 1))
    tau = np.unique(np.logspace(lo, hi, terms))
    t = np.logspace(lo - 2, hi + 2, math.ceil(FIT_POINTS_PER_DECADE * (span + 4)) + 1)
    e = curve.relaxation_modulus(t)
    design = np.column_stack([np.ones_like(t), np.exp(-t[:, None] / tau[None, :])]) / e[:, None]
    coef, _ = nnls(design, np.ones_like(t), maxiter=50 * design.shape[1])
    keep = coef[1:] >= max(1e-6 * curve.instantaneous_modulus, PRONY_MODULI[0])
    e_inf = max(float(coef[0]), PRONY_MODULI[0])
    if not keep.any():
        return None
    return PronySeries(e_inf, tuple(coef[1:][keep]), tuple(tau[keep]), field=curve.field)


# --- time–temperature superposition ----------------------------------------------------------------------------


class _Shift:
    """a_T from :meth:`log10_shift`, which each shift law defines."""

    def log10_shift(self, temperature: ArrayLike, *, field: str = "temperature") -> FloatArray:
        raise NotImplementedError

    def shift(self, temperature: ArrayLike, *, field: str = "temperature") -> FloatArray:
        """a_T (1) at temperatures T in K: > 1 below Tref (slower), a_T(Tref) = 1."""
        with np.errstate(over="ignore"):  # a_T = inf far below Tref: E(t/a_T) is then E(0), the glassy limit
            return np.asarray(10.0 ** self.log10_shift(temperature, field=field), dtype=float)


@dataclass(frozen=True)
class WLFShift(_Shift):
    """log10 a_T = −C1 (T − Tref)/(C2 + T − Tref) (Williams, Landel & Ferry 1955; docs/theory.md eq. 16.6).

    ``reference_temperature`` Tref in K, ``c1`` (1) and ``c2`` (K) > 0. Defined for T > Tref − C2 (the Vogel
    temperature T∞, where a_T diverges); :meth:`log10_shift` refuses T at or below it.
    """

    reference_temperature: float
    c1: float
    c2: float
    field: str = dataclass_field(default="rubber", compare=False)

    def __post_init__(self) -> None:
        _positive(f"{self.field}.reference_temperature", self.reference_temperature, "K")
        _positive(f"{self.field}.wlf_c1", self.c1, "1")
        _positive(f"{self.field}.wlf_c2", self.c2, "K")

    @property
    def vogel_temperature(self) -> float:
        """T∞ = Tref − C2 in K, where the WLF shift diverges."""
        return self.reference_temperature - self.c2

    def log10_shift(self, temperature: ArrayLike, *, field: str = "temperature") -> FloatArray:
        """log10 a_T at temperatures T in K (> T∞ = Tref − C2; else an InputError naming ``field``)."""
        temp = _floats(field, temperature, "must be a number (K)")
        dt = temp - self.reference_temperature
        _refuse_where(field, temp, ~(self.c2 + dt > 0), f"must be above Tref − C2 = {_kelvin_text(self.vogel_temperature)}, "
                      "where the WLF shift diverges (the rubber is glassy long before)", kelvin=True)
        return np.asarray(-self.c1 * dt / (self.c2 + dt), dtype=float)


@dataclass(frozen=True)
class ArrheniusShift(_Shift):
    """ln a_T = (Ea/R)(1/T − 1/Tref) (docs/theory.md eq. 16.7): ``reference_temperature`` in K, ``activation_energy``
    Ea in J/mol (> 0)."""

    reference_temperature: float
    activation_energy: float
    field: str = dataclass_field(default="rubber", compare=False)

    def __post_init__(self) -> None:
        _positive(f"{self.field}.reference_temperature", self.reference_temperature, "K")
        _positive(f"{self.field}.activation_energy", self.activation_energy, "J/mol")

    def log10_shift(self, temperature: ArrayLike, *, field: str = "temperature") -> FloatArray:
        """log10 a_T at temperatures T in K (> 0)."""
        temp = _floats(field, temperature, "must be a number (K)")
        _refuse_where(field, temp, ~(temp > 0), "must be an absolute temperature > 0 K", kelvin=True)
        return np.asarray(self.activation_energy / GAS_CONSTANT * (1 / temp - 1 / self.reference_temperature)
                          / math.log(10), dtype=float)


def modulus_at(material: RelaxationModulus, time: ArrayLike, temperature: ArrayLike,
               shift: WLFShift | ArrheniusShift | None = None) -> FloatArray:
    """E(t/a_T(T)) in Pa: the relaxation modulus at time t (s) held at temperature T (K) (eq. 16.8).

    ``material`` gives E at the reference temperature of ``shift``; without a shift (a material measured at the
    one temperature of the case) E(t) itself. The time and the temperature broadcast against each other.
    """
    t = np.asarray(time, dtype=float)
    if shift is None:
        return material.relaxation_modulus(t)
    return material.relaxation_modulus(t / shift.shift(temperature))


def universal_wlf_glass_transition(shift: WLFShift) -> float:
    """An estimate of Tg in K from WLF constants at any reference: Tg ≈ T∞ + 51.6 K = Tref − C2 + 51.6 K (§16.5).

    The WLF constants referred to Tg have C2g = C2 + Tg − Tref; with the universal C2g = 51.6 K this gives Tg.
    An estimate only: measured C2g vary from polymer to polymer (Ferry 1980, ch. 11)."""
    return shift.vogel_temperature + UNIVERSAL_WLF_C2


# --- thermal contraction ---------------------------------------------------------------------------------------


def thermal_compression(compression: ArrayLike, temperature: ArrayLike, assembly_temperature: float,
                        rubber_expansion: float, gland_expansion: float) -> FloatArray:
    """ε(T) = 1 − h(T)/d(T) (docs/theory.md eq. 16.9), the O-ring's compression at temperature T.

    The cord diameter d(T) = d0 (1 + α_r (T − Ta)) and the gland depth h(T) = h0 (1 + α_g (T − Ta)) each follow their own
    linear expansion coefficient (1/K) from the assembly temperature Ta (K), where the compression is ε0 = 1 − h0/d0.
    Returns ε(T) (1), which may be <= 0: the cord no longer fills the gland (no contact force). ``compression`` and
    ``temperature`` broadcast against each other.
    """
    eps0 = _floats("compression", compression, "must be a number (the squeeze over the cord diameter)")
    _refuse_where("compression", eps0, ~((eps0 >= 0) & (eps0 < 1)), "must be in [0, 1): the squeeze over the cord diameter")
    ta = _positive("assembly_temperature", assembly_temperature, "K")
    temp = _floats("temperature", temperature, "must be a number (K)")
    _refuse_where("temperature", temp, ~(temp > 0), "must be an absolute temperature > 0 K", kelvin=True)
    alphas = [expansion_coefficient("rubber_expansion", rubber_expansion),
              expansion_coefficient("gland_expansion", gland_expansion)]
    dt = temp - ta
    cord = 1 + alphas[0] * dt
    gland = 1 + alphas[1] * dt
    _refuse_where("temperature", np.broadcast_to(temp, cord.shape), ~((cord > 0) & (gland > 0)),
                  "must keep 1 + α (T − Ta) > 0 for the cord and the gland", kelvin=True)
    return np.asarray(1 - (1 - eps0) * gland / cord, dtype=float)


def glass_transition_warnings(temperature: float, glass_transition: float, *, estimated: bool = False) -> tuple[str, ...]:
    """A warning at temperatures (K) below Tg + :data:`GLASS_MARGIN` (§16.5): the empty tuple above it.

    ``estimated`` says that Tg comes from the WLF constants (:func:`universal_wlf_glass_transition`), not a measurement.
    """
    t, tg = float(temperature), float(glass_transition)
    how = " (estimated from the WLF constants)" if estimated else ""
    if t < tg:
        return (f"{celsius(t):.4g} °C is below the glass transition ({celsius(tg):.4g} °C{how}): the rubber is glassy, "
                "its modulus some hundred to a thousand times the rubbery one; it no longer follows the squeeze and the "
                "seal may leak; the viscoelastic model does not hold there",)
    if t < tg + GLASS_MARGIN:
        return (f"{celsius(t):.4g} °C is within {GLASS_MARGIN:.0f} K of the glass transition ({celsius(tg):.4g} °C{how}): "
                "the modulus rises by decades and the relaxation slows as the rubber approaches Tg; check the seal "
                "against the compound's TR10 (ISO 2921)",)
    return ()


# --- ageing: compression set -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class CompressionSet:
    """c(t, T) = 1 − exp(−(t/τ(T))^β), τ(T) = τref exp((Ea/R)(1/T − 1/Tref)) (docs/theory.md eqs. 16.10, 16.11).

    Attributes: ``time_constant`` τref (s) at ``reference_temperature`` Tref (K), ``exponent`` β (1),
    ``activation_energy`` Ea (J/mol), ``rms_residual`` the fit's root-mean-square residual in c (1; 0 when not fitted).
    """

    time_constant: float
    exponent: float
    activation_energy: float
    reference_temperature: float
    rms_residual: float = 0.0

    def time_scale(self, temperature: ArrayLike) -> FloatArray:
        """τ(T) in s at temperatures T in K (eq. 16.11)."""
        temp = np.asarray(temperature, dtype=float)
        with np.errstate(over="ignore"):  # (far below Tref τ → inf: no set forms, the right limit)
            return np.asarray(self.time_constant * np.exp(self.activation_energy / GAS_CONSTANT
                                                          * (1 / temp - 1 / self.reference_temperature)), dtype=float)

    def __call__(self, time: ArrayLike, temperature: ArrayLike) -> FloatArray:
        """c (1, between 0 and 1) after a time (s) held compressed at a temperature (K)."""
        t = np.maximum(np.asarray(time, dtype=float), 0.0)
        return np.asarray(-np.expm1(-((t / self.time_scale(temperature)) ** self.exponent)), dtype=float)


def remaining_compression(compression: ArrayLike, compression_set: ArrayLike) -> FloatArray:
    """ε_eff = ε (1 − c) (eq. 16.12): the compression a set c leaves of the compression ε."""
    return np.asarray(np.asarray(compression, dtype=float) * (1 - np.asarray(compression_set, dtype=float)), dtype=float)


def fit_compression_set(times: ArrayLike, temperatures: ArrayLike, sets: ArrayLike, *,
                        reference_temperature: float = 293.15, field: str = "compression_set") -> CompressionSet:
    """Fit eqs. 16.10–16.11 to measured compression sets (§16.6).

    ``times`` (s, > 0), ``temperatures`` (K, > 0) and ``sets`` (fractions, 0 < c < 1) per point, at least 3 points at
    two or more temperatures and two or more times. A straight-line least-squares fit of
    ln(−ln(1 − c)) = β ln t − β ln τref − (β Ea/R)(1/T − 1/Tref) starts a nonlinear least-squares fit of c itself.
    """
    t = _array(f"{field}.times", times, "s")
    temp = _array(f"{field}.temperatures", temperatures, "K")
    c = _array(f"{field}.sets", sets, "fraction")
    if not (t.size == temp.size == c.size):
        raise InputError(f"{field}.sets", sets, f"must have one time, temperature and set per point "
                                               f"({t.size}, {temp.size}, {c.size} given)")
    tref = _positive("reference_temperature", reference_temperature, "K")
    for name, arr, allowed in (("times", t, "must be > 0 (s)"), ("temperatures", temp, "must be > 0 K")):
        for i, v in enumerate(arr):
            if not v > 0:
                raise InputError(f"{field}.{name}[{i}]", float(v), allowed)
    for i, v in enumerate(c):
        if not 0 < v < 1:
            raise InputError(f"{field}.sets[{i}]", float(v), "must be between 0 and 1, exclusive (a fraction, not %)")
    if t.size < 3 or np.unique(temp).size < 2 or np.unique(t).size < 2:
        raise InputError(f"{field}.temperatures", temperatures, "needs at least 3 points, at two or more temperatures "
                                                               "and two or more times, to fit β and Ea")
    x = 1 / temp - 1 / tref
    design = np.column_stack([np.log(t), np.ones_like(t), x])
    (beta, a0, b), *_ = np.linalg.lstsq(design, np.log(-np.log1p(-c)), rcond=None)
    beta = max(float(beta), 1e-3)
    start = np.array([math.log(beta), -a0 / beta, -b / beta])  # ln β, ln τref, Ea/R

    def model(p: FloatArray) -> FloatArray:
        ln_tau = p[1] + p[2] * x
        return np.asarray(-np.expm1(-np.exp(np.exp(p[0]) * (np.log(t) - ln_tau))), dtype=float)

    # (trial parameters far off overflow the model: those trials fail, which is the fit's business, not an error)
    with np.errstate(over="ignore", invalid="ignore"):
        result = least_squares(lambda p: model(p) - c, start, method="lm", xtol=1e-14, ftol=1e-14, gtol=1e-14)
        p = result.x if result.success and np.all(np.isfinite(result.x)) else start
        residual = float(np.sqrt(np.mean((model(p) - c) ** 2)))
    if not (np.all(np.isfinite(p)) and abs(p[0]) < 50.0 and abs(p[1]) < 700.0 and p[2] > 0 and np.isfinite(residual)):
        raise InputError(f"{field}.sets", sets, "cannot be fitted by eqs. 16.10–16.11 with a finite time scale and an "
                                               "activation energy > 0: a compression set grows with time, and faster "
                                               "when warmer; check each point's time, temperature and set")
    return CompressionSet(time_constant=float(math.exp(p[1])), exponent=float(math.exp(p[0])),
                          activation_energy=float(p[2] * GAS_CONSTANT), reference_temperature=tref,
                          rms_residual=residual)
