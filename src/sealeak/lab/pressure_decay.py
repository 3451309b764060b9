"""Virtual pressure-decay test: a gas-filled test volume leaking through the seal (docs/theory.md §11.7).

A test volume V (m³) holds a gas at absolute pressure P(t) (Pa), initially P1, at the constant
temperature T of the test; outside the seal the absolute pressure is P2 < P1. The seal passes the
pV throughput Q_pV(P, P2) (Pa·m³/s, counted at T). The gas in the volume obeys p V = n R T, so

    V dP/dt = −Q_pV(P, P2).

For isothermal viscous flow through a channel of no-slip conductance K (m³/(Pa·s)),
Q_pV = (K/2)(P² − P2²) and the decay has a closed form (:func:`viscous_decay`):

    P(t) = P2 / tanh(artanh(P2/P1) + K P2 t/(2V))       (P2 > 0)
    P(t) = P1 / (1 + K P1 t/(2V))                       (P2 = 0, vacuum outside)

For a leak linear in the pressure difference, Q_pV = C (P − P2) with C = K P̄ at a fixed mean
pressure P̄ (the small-ΔP limit, ΔP ≪ P), P − P2 = (P1 − P2) exp(−C t/V) (:func:`exponential_decay`).
:func:`pressure_decay` integrates the ODE with any throughput (scipy.integrate.solve_ivp, Radau,
tight tolerances) and finds by an event the time at which the volume has lost the test's pressure
loss ΔP; the test's standard leak rate is then V ΔP/Δt (Pa·m³/s).

The inverse (:func:`leak_rate_from_decay`): from readings (t_i, P_i), the leak rate of each interval
is V (P_i − P_(i+1))/(t_(i+1) − t_i) at the mean pressure, and the conductance K follows from the
straight line F(P_i) = F(P_0) + K (t_i − t_0)/(2V) with F(P) = artanh(P2/P)/P2 (1/P for P2 = 0). With a
model's throughput at α = 1, :func:`scale_factor_from_decay` gives the α the readings imply:
J_i = ∫_{P_i}^{P_0} dP/Q_1(P, P2) = (α/V)(t_i − t_0), a straight line in t (fitted with an intercept,
which absorbs the error of the first reading).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad, solve_ivp

from ..errors import ConvergenceError, FileFormatError, InputError, positive_number
from ..io.quantities import quantity

__all__ = ["PressureDecaySetup", "PressureDecay", "pressure_decay", "viscous_throughput_function", "viscous_decay",
           "viscous_decay_time", "exponential_decay", "standard_leak_rate", "DecayReadings", "leak_rate_from_decay",
           "ScaleFromDecay", "scale_factor_from_decay"]

FloatArray = NDArray[np.float64]
Throughput = Callable[[float, float], float]


@dataclass(frozen=True, kw_only=True)
class PressureDecaySetup:
    """A pressure-decay test (SI units; docs/theory.md §11.7).

    Attributes
    ----------
    volume
        The test volume V (m³).
    initial_pressure
        P1, the absolute pressure in the volume at t = 0 (Pa).
    outside_pressure
        P2, the absolute pressure outside the seal (Pa; 0 for vacuum); below P1.
    temperature
        T of the gas (K), constant (isothermal test).
    pressure_loss
        ΔP whose time Δt the test measures (Pa; None: (P1 − P2)/10), below P1 − P2.
    duration
        Time span of the simulated curve (s; None: 1.5 × the time to lose ΔP estimated from the
        initial leak rate, at least V P1/Q_pV(P1, P2) / 10).
    """

    volume: float = quantity("m^3", "test volume V")
    initial_pressure: float = quantity("Pa (absolute)", "pressure P1 at the start")
    outside_pressure: float = quantity("Pa (absolute)", "pressure P2 outside the seal")
    temperature: float = quantity("K", "temperature of the gas")
    pressure_loss: float | None = quantity("Pa", "the pressure drop ΔP whose time is reported", default=None)
    duration: float | None = None

    def __post_init__(self) -> None:
        positive_number("volume", self.volume)
        positive_number("temperature", self.temperature)
        p1 = positive_number("initial_pressure", self.initial_pressure)
        p2 = positive_number("outside_pressure", self.outside_pressure, allow_zero=True)
        if not p1 > p2:
            raise InputError("initial_pressure", self.initial_pressure,
                             f"must be above the outside pressure {p2:.6g} Pa (absolute pressures; the volume loses gas)")
        if self.pressure_loss is not None:
            positive_number("pressure_loss", self.pressure_loss,
                            below=(p1 - p2, f"the initial pressure difference P1 − P2 = {p1 - p2:.6g} Pa"))
        if self.duration is not None:
            positive_number("duration", self.duration)

    @property
    def loss(self) -> float:
        """ΔP (Pa): ``pressure_loss``, or (P1 − P2)/10 when not given."""
        return self.pressure_loss if self.pressure_loss is not None else 0.1 * (self.initial_pressure - self.outside_pressure)


def viscous_throughput_function(conductance: float) -> Throughput:
    """Q_pV(P_in, P_out) = (K/2)(P_in² − P_out²) in Pa·m³/s for a no-slip conductance K (m³/(Pa·s))
    (docs/theory.md §11.3)."""
    k = positive_number("conductance", conductance, allow_zero=True)

    def throughput(p_in: float, p_out: float) -> float:
        return 0.5 * k * (p_in - p_out) * (p_in + p_out)

    return throughput


def viscous_decay(setup: PressureDecaySetup, conductance: float, time: ArrayLike) -> FloatArray:
    """P(t) (Pa) of V dP/dt = −(K/2)(P² − P2²) in closed form (module docstring; docs/theory.md §11.7).

    K in m³/(Pa·s), t in s. Derivation: F(P) = artanh(P2/P)/P2 has dF/dP = −1/(P² − P2²), so dF/dt = K/(2V):
    artanh(P2/P) = artanh(P2/P1) + K P2 t/(2V); for P2 = 0, 1/P = 1/P1 + K t/(2V).
    """
    k = positive_number("conductance", conductance, allow_zero=True)
    t = np.asarray(time, dtype=float)
    p1, p2, v = setup.initial_pressure, setup.outside_pressure, setup.volume
    a = 0.5 * k / v
    if p2 == 0.0:
        return p1 / (1.0 + a * p1 * t)
    return p2 / np.tanh(np.arctanh(p2 / p1) + a * p2 * t)


def viscous_decay_time(setup: PressureDecaySetup, conductance: float, pressure_loss: float | None = None) -> float:
    """Time (s) for P to fall from P1 to P1 − ΔP with Q_pV = (K/2)(P² − P2²) (inf for K = 0).

    t = 2V (F(P1 − ΔP) − F(P1))/K with F(P) = artanh(P2/P)/P2 (1/P for P2 = 0); docs/theory.md §11.7.
    """
    k = positive_number("conductance", conductance, allow_zero=True)
    dp = setup.loss if pressure_loss is None else positive_number("pressure_loss", pressure_loss)
    p1, p2 = setup.initial_pressure, setup.outside_pressure
    pf = p1 - dp
    if not pf > p2:
        raise InputError("pressure_loss", pressure_loss, f"must be below P1 − P2 = {p1 - p2:.6g} Pa")
    if k == 0:
        return math.inf
    return float(2.0 * setup.volume * (_potential(pf, p2) - _potential(p1, p2)) / k)


def _potential(p: ArrayLike, p2: float) -> FloatArray:
    """F(P) = artanh(P2/P)/P2, or 1/P for P2 = 0: d F/dP = −1/(P² − P2²)."""
    p = np.asarray(p, dtype=float)
    if p2 == 0.0:
        return 1.0 / p
    return np.arctanh(p2 / p) / p2


def exponential_decay(setup: PressureDecaySetup, conductance: float, time: ArrayLike) -> FloatArray:
    """P(t) = P2 + (P1 − P2) exp(−t/τ), τ = V/(K P̄), P̄ = (P1 + P2)/2 (Pa; K in m³/(Pa·s), t in s).

    The exact solution for a throughput linear in the pressure difference, Q_pV = K P̄ (P − P2); the
    small-ΔP limit of the viscous decay (docs/theory.md §11.7)."""
    k = positive_number("conductance", conductance, allow_zero=True)
    p1, p2 = setup.initial_pressure, setup.outside_pressure
    rate = k * 0.5 * (p1 + p2) / setup.volume
    return p2 + (p1 - p2) * np.exp(-rate * np.asarray(time, dtype=float))


def standard_leak_rate(volume: float, pressure_loss: float, duration: float) -> float:
    """Q_pV = V ΔP/Δt in Pa·m³/s: the leak rate a pressure-decay test reports (at the test temperature)."""
    return positive_number("volume", volume) * positive_number("pressure_loss", pressure_loss) / positive_number("duration", duration)


@dataclass(frozen=True)
class PressureDecay:
    """Solution of V dP/dt = −Q_pV(P, P2) (docs/theory.md §11.7).

    Attributes
    ----------
    time, pressure
        t (s) and P(t) (Pa).
    throughput
        Q_pV(P(t), P2) (Pa·m³/s).
    pressure_loss
        The ΔP whose time is reported (Pa).
    time_to_loss
        Δt (s) at which P = P1 − ΔP; NaN if not reached within the simulated span.
    standard_leak_rate
        V ΔP/Δt (Pa·m³/s; NaN when Δt is).
    """

    time: FloatArray
    pressure: FloatArray
    throughput: FloatArray
    pressure_loss: float
    time_to_loss: float
    standard_leak_rate: float


def _q(throughput: Throughput, p: float, p2: float, what: str) -> float:
    q = float(throughput(p, p2))
    if not (math.isfinite(q) and q >= 0):
        raise InputError(what, q, "must be finite and >= 0 (Pa m^3/s)")
    return q


def pressure_decay(setup: PressureDecaySetup, throughput: Throughput, *, t_end: float | None = None,
                   t_eval: ArrayLike | None = None, rtol: float = 1e-12, atol: float | None = None) -> PressureDecay:
    """Integrate V dP/dt = −Q_pV(P, P2) from P1 with ``throughput(P_in, P_out)`` (Pa·m³/s) by solve_ivp (Radau).

    The time at which P = P1 − ΔP (``setup.loss``) is located by an event. ``t_end`` (s) defaults
    to the last of ``t_eval``, else ``setup.duration``, else 1.5× the time to lose ΔP at the initial
    leak rate, V ΔP/Q_pV(P1, P2) (3600 s when that is 0). docs/theory.md §11.7.
    """
    p1, p2, v = setup.initial_pressure, setup.outside_pressure, setup.volume
    dp = setup.loss
    q0 = _q(throughput, p1, p2, "throughput at the initial pressure")
    if t_end is None and t_eval is not None:
        t_end = float(np.max(np.asarray(t_eval, dtype=float)))
    if t_end is None:
        t_end = setup.duration
    if t_end is None:
        t_end = 3600.0 if q0 == 0 else 1.5 * v * dp / q0 * max(1.0, (p1 - p2) / (p1 - p2 - dp))
    if atol is None:
        atol = 1e-14 * p1

    def rhs(t, y):
        return [-_q(throughput, max(float(y[0]), p2), p2, "throughput") / v]

    def reach(t, y):
        return y[0] - (p1 - dp)

    reach.terminal = False  # type: ignore[attr-defined]
    reach.direction = -1  # type: ignore[attr-defined]
    if t_eval is None:
        t_eval = np.linspace(0.0, float(t_end), 401)
    sol = solve_ivp(rhs, (0.0, float(t_end)), [p1], method="Radau", t_eval=np.asarray(t_eval, dtype=float), events=reach,
                    rtol=rtol, atol=atol)
    if not sol.success:
        raise ConvergenceError(f"pressure decay: the ODE solver failed ({sol.message})")
    hits = sol.t_events[0]
    t_loss = float(hits[0]) if hits.size else math.nan
    pressure = sol.y[0]
    q = np.array([float(throughput(max(p, p2), p2)) for p in pressure])
    rate = v * dp / t_loss if t_loss > 0 else math.nan
    return PressureDecay(time=sol.t, pressure=pressure, throughput=q, pressure_loss=dp, time_to_loss=t_loss,
                         standard_leak_rate=rate)


def _check_readings(setup: PressureDecaySetup, time: ArrayLike, pressure: ArrayLike, source: str) -> tuple[FloatArray, FloatArray]:
    t = np.asarray(time, dtype=float)
    p = np.asarray(pressure, dtype=float)
    if t.size < 2 or t.shape != p.shape:
        raise FileFormatError(source, f"needs at least two readings of time and pressure, found {t.size}")
    if not (np.isfinite(t).all() and np.isfinite(p).all()):
        raise FileFormatError(source, "readings must be finite numbers")
    low = p <= setup.outside_pressure
    if low.any():
        i = int(np.argmax(low))
        raise FileFormatError(source, f"reading {i + 1}: pressure {p[i]:.6g} Pa is not above the outside pressure "
                                      f"{setup.outside_pressure:.6g} Pa (readings are absolute pressures)")
    dt = np.diff(t)
    if (dt <= 0).any():
        i = int(np.argmax(dt <= 0)) + 1
        raise FileFormatError(source, f"reading {i + 1}: time {t[i]:.6g} s is not after the previous reading "
                                      f"({t[i - 1]:.6g} s); times must increase")
    if not p[-1] < p[0]:
        raise FileFormatError(source, f"the pressure does not fall over the readings ({p[0]:.6g} Pa at t = {t[0]:.6g} s, "
                                      f"{p[-1]:.6g} Pa at t = {t[-1]:.6g} s): no leak rate can be read from them")
    return t, p


def _line(x: FloatArray, y: FloatArray) -> tuple[float, float, FloatArray]:
    """Least-squares slope b of y = a + b x, its standard error (NaN with two points) and the residuals."""
    xm = x.mean()
    sxx = float(np.sum((x - xm) ** 2))
    slope = float(np.sum((x - xm) * (y - y.mean()))) / sxx
    resid = y - (y.mean() + slope * (x - xm))
    dof = x.size - 2
    std = math.sqrt(float(np.sum(resid**2)) / dof / sxx) if dof > 0 else math.nan
    return slope, std, resid


@dataclass(frozen=True, kw_only=True)
class DecayReadings:
    """Leak rate from (time, pressure) readings of a pressure-decay test (docs/theory.md §11.7).

    Attributes
    ----------
    time, pressure
        The readings t_i (s) and absolute P_i (Pa).
    interval_pressure, interval_leak_rate
        Mean pressure (P_i + P_(i+1))/2 (Pa) and V (P_i − P_(i+1))/(t_(i+1) − t_i) (Pa·m³/s) of each interval.
    leak_rate
        V (P_0 − P_last)/(t_last − t_0): the standard leak rate over all readings (Pa·m³/s).
    conductance, conductance_std
        K (m³/(Pa·s)) of the viscous law Q_pV = (K/2)(P² − P2²) from the straight line
        F(P_i) = F(P_0) + K (t_i − t_0)/(2V), F(P) = artanh(P2/P)/P2, and its standard error (NaN
        with two readings).
    rms_relative_residual
        Rms of the fit's residuals in F divided by the span of F: how straight the line is.
    """

    time: FloatArray
    pressure: FloatArray
    interval_pressure: FloatArray = quantity("Pa", "mean pressure of each reading interval")
    interval_leak_rate: FloatArray = quantity("Pa*m^3/s", "pV leak rate of each reading interval",
                                              key="interval_leak_rate_pv")
    leak_rate: float = quantity("Pa*m^3/s", "V·(P_first − P_last)/(t_last − t_first) of the readings",
                                key="leak_rate_pv")
    conductance: float = quantity("m^3/(Pa*s)", "K from the viscous fit of the readings")
    conductance_std: float = quantity("m^3/(Pa*s)", "standard error of that K")
    rms_relative_residual: float


def leak_rate_from_decay(setup: PressureDecaySetup, time: ArrayLike, pressure: ArrayLike, source: str = "readings") -> DecayReadings:
    """Leak rate and viscous conductance from readings t (s) and absolute P (Pa) (module docstring).

    ``setup`` gives V and P2 (its initial pressure is not used: the readings start where they
    start). Raises :class:`FileFormatError` naming ``source`` for readings that cannot be used.
    """
    t, p = _check_readings(setup, time, pressure, source)
    v, p2 = setup.volume, setup.outside_pressure
    q = v * -np.diff(p) / np.diff(t)
    f = _potential(p, p2)
    slope, std, resid = _line(t - t[0], f - f[0])
    k = 2.0 * v * slope
    span = float(f.max() - f.min())
    return DecayReadings(time=t, pressure=p, interval_pressure=0.5 * (p[1:] + p[:-1]), interval_leak_rate=q,
                         leak_rate=float(v * (p[0] - p[-1]) / (t[-1] - t[0])), conductance=float(k),
                         conductance_std=float(2.0 * v * std), rms_relative_residual=float(np.sqrt(np.mean(resid**2)) / span))


@dataclass(frozen=True, kw_only=True)
class ScaleFromDecay:
    """The scale factor α implied by decay readings for a model Q_pV = α Q_1(P, P2) (docs/theory.md §11.7).

    Attributes
    ----------
    alpha, alpha_std
        α and its standard error (NaN with two readings).
    resistance_integral
        J_i = ∫_{P_i}^{P_0} dP/Q_1(P, P2) (s/m³) at each reading; J_i = (α/V)(t_i − t_0).
    rms_relative_residual
        Rms of the residuals of J divided by its span.
    """

    alpha: float = quantity("1", "factor on the model's K implied by the readings (α for the critical junction)")
    alpha_std: float = quantity("1", "standard error of that factor")
    resistance_integral: FloatArray
    rms_relative_residual: float


#: Readings from which the resistance integrals of :func:`scale_factor_from_decay` come from one Chebyshev series of
#: 1/Q_1(P) over their pressures instead of a quadrature per reading (whose cost, ~40 evaluations of Q_1 each, grew with
#: the readings: 1 000 readings of the pressure-decay example took 7 minutes).
SERIES_READINGS = 9
#: The largest degree of that series (its degree is doubled from 16 while its last coefficients are not negligible).
SERIES_DEGREE = 256
#: The share of the series' largest coefficient below which its last ones count as converged: Q_1 is itself a
#: quadrature whose last digits are noise (the coefficients of the example's 1/Q_1 level off at 10⁻¹²–10⁻¹³), and the
#: readings' own scatter is far larger.
SERIES_RTOL = 1e-10


def _resistance_integrals(inverse: Callable[[float], float], p: FloatArray) -> FloatArray:
    """J_i = ∫_{P_i}^{P_0} dP/Q_1(P) for the falling pressures ``p`` (Pa), ``inverse`` = 1/Q_1 (docs/theory.md §11.7).

    From :data:`SERIES_READINGS` readings on, 1/Q_1 is interpolated by a Chebyshev series on [P_n, P_0] whose degree is
    doubled from 16 up to :data:`SERIES_DEGREE` until its last three coefficients fall below :data:`SERIES_RTOL` of its
    largest, and the series is integrated exactly: a cost fixed by the smoothness of Q_1, not by the number of readings. Where it
    does not converge (a kink of Q_1 between the readings' pressures, e.g. lift-off), and for fewer readings, each
    J_i is an adaptive quadrature to 10⁻¹² relative, as before.
    """
    lo, hi = float(p.min()), float(p[0])
    if p.size >= SERIES_READINGS and hi > lo:
        degree = 16
        while degree <= SERIES_DEGREE:
            series = np.polynomial.chebyshev.Chebyshev.interpolate(
                lambda x: np.array([inverse(float(v)) for v in np.atleast_1d(x)]), degree, domain=[lo, hi])
            c = np.abs(series.coef)
            if c[-3:].max() <= SERIES_RTOL * c.max():
                area = series.integ()
                return np.asarray(area(hi) - area(p), dtype=float)
            degree *= 2
    return np.array([0.0] + [quad(inverse, pi, p[0], epsabs=0.0, epsrel=1e-12, limit=200)[0] for pi in p[1:]])


def scale_factor_from_decay(setup: PressureDecaySetup, time: ArrayLike, pressure: ArrayLike, unit_throughput: Throughput,
                            source: str = "readings") -> ScaleFromDecay:
    """α from readings (t, P) and the model's throughput at α = 1, ``unit_throughput(P_in, P_out)`` (Pa·m³/s).

    V dP/dt = −α Q_1(P, P2) gives J_i = (α/V)(t_i − t_0) with J_i = ∫_{P_i}^{P_0} dP/Q_1(P, P2)
    (adaptive quadrature); the least-squares line J = a + b (t − t_0) (the readings' errors are in
    the pressures, hence in J) has the slope b = α/V. For the viscous law Q_1 = (K_1/2)(P² − P2²)
    this is K/K_1 of :func:`leak_rate_from_decay`.
    """
    t, p = _check_readings(setup, time, pressure, source)
    p2 = setup.outside_pressure

    def inverse(x: float) -> float:
        q = float(unit_throughput(x, p2))
        if not (math.isfinite(q) and q > 0):
            raise InputError("unit_throughput", q, f"must be finite and > 0 at every pressure of the readings (at {x:.6g} Pa)")
        return 1.0 / q

    j = _resistance_integrals(inverse, p)
    slope, std, resid = _line(t - t[0], j)
    return ScaleFromDecay(alpha=float(setup.volume * slope), alpha_std=float(setup.volume * std), resistance_integral=j,
                          rms_relative_residual=float(np.sqrt(np.mean(resid**2)) / (j.max() - j.min())))
