"""Virtual water-column rig: the reference paper's apparatus (docs/theory.md §4).

A glass cylinder of inner diameter D_cyl stands on the rubber ring, which is pressed onto the rough
substrate by a load m (or force F = m g) on the top of the cylinder. The cylinder holds a fluid
column of height H; the fluid leaks out through the ring/substrate interface. Then

    P0  = F / (π (D_o² - D_i²)/4)              (nominal squeeze pressure on the ring, Seal.squeeze_pressure_from_load)
    ΔP  = ρ g H(t)                              (hydrostatic pressure at the seal; outside: ambient)
    A_cyl dH/dt = -Q(ρ g H),   A_cyl = π D_cyl²/4

For a leak rate linear in ΔP, Q = K ΔP (both theories at fixed P0: K = α (Ly/Lx) u_c³/(12η) or
(Ly/Lx) σ_eff), the level falls exponentially: H(t) = H0 exp(-t/τ), τ = A_cyl/(K ρ g), and it takes
t = τ ln(H0/H1) to fall from H0 to H1. :func:`water_column` solves the ODE in general
(scipy.integrate.solve_ivp, Radau, tight tolerances) so a pressure-dependent Q(ΔP) works as well.

The inverse (:func:`leak_rate_from_readings`): from readings (t_i, H_i) the leak rate between
consecutive readings is Q = -A_cyl ΔH/Δt at ΔP = ρ g (H_i + H_{i+1})/2, and a straight-line fit of
ln H against t gives the conductance K = -A_cyl/(ρ g) d ln H/dt with its standard error.
The load of the fluid itself is not added to P0 (the cylinder stands on the ring; the paper's load
is what presses the cylinder down).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from ..errors import ConvergenceError, FileFormatError, InputError, UnitError, positive_number
from ..io.quantities import quantity
from ..io.units import unit_factor
from ..physics.gas import DEFAULT_RAREFACTION, Gas, check_rarefaction_model
from ..physics.seal import STANDARD_GRAVITY, Seal
from .data import read_readings_table
from .pressure_decay import PressureDecaySetup, leak_rate_from_decay

__all__ = ["RIG_KINDS", "RigSetup", "WaterColumn", "water_column", "exponential_height", "drain_time",
           "ReadingsAnalysis", "leak_rate_from_readings", "DecayRigSetup",
           "read_decay_readings"]

#: The rigs a case file's ``[rig] kind`` may name: the reference paper's water column (the default)
#: and the pressure-decay test of a gas (docs/theory.md §11.7).
RIG_KINDS = ("water-column", "pressure-decay")

#: The columns of pressure-decay readings and the names they may go by.
_DECAY_COLUMNS = {"time": {"time", "t"}, "pressure": {"pressure", "p", "absolute_pressure", "test_pressure"}}

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True)
class RigSetup:
    """The water-column rig (SI units; docs/theory.md §4.2).

    Attributes
    ----------
    cylinder_diameter
        Inner diameter D_cyl of the cylinder (m).
    initial_height
        Fluid column H0 at the start (m).
    load
        Force F pressing the ring (N; a mass m in the case file becomes m g).
    density
        ρ of the fluid (kg/m³).
    final_height
        The level whose time of arrival is reported (m; None: H0/2 in :func:`water_column`).
    gravity
        g (m/s²).
    duration
        Time span of the simulated curve (s; None: 1.5× the arrival time at the final height
        estimated from the initial leak rate, at least one time constant, see :func:`water_column`).
    load_note
        How the load was given (e.g. a mass converted with g), for reports.
    """

    cylinder_diameter: float
    initial_height: float
    load: float = quantity("N", "load pressing the seal")
    density: float
    final_height: float | None = quantity("m", "the level whose time of arrival is reported", default=None)
    gravity: float = STANDARD_GRAVITY
    duration: float | None = None
    load_note: str = ""

    def __post_init__(self) -> None:
        positive_number("cylinder_diameter", self.cylinder_diameter)
        positive_number("initial_height", self.initial_height)
        positive_number("load", self.load)
        positive_number("density", self.density)
        positive_number("gravity", self.gravity)
        if self.final_height is not None:
            positive_number("final_height", self.final_height,
                            below=(self.initial_height, f"the initial height {self.initial_height:.6g} m"))
        if self.duration is not None:
            positive_number("duration", self.duration)

    @property
    def kind(self) -> str:
        """"water-column" (:data:`RIG_KINDS`)."""
        return "water-column"

    @property
    def cylinder_area(self) -> float:
        """A_cyl = π D_cyl²/4 in m² (docs/theory.md §4.2)."""
        return 0.25 * np.pi * self.cylinder_diameter**2

    def squeeze_pressure(self, seal: Seal) -> float:
        """P0 = F / (Lx Ly) (for a ring: F / (π (D_o² - D_i²)/4)) in Pa."""
        return seal.squeeze_pressure_from_load(self.load)

    def pressure_difference(self, height: ArrayLike) -> FloatArray:
        """ΔP = ρ g H in Pa."""
        return self.density * self.gravity * np.asarray(height, dtype=float)


def exponential_height(rig: RigSetup, conductance: float, t: ArrayLike) -> FloatArray:
    """H(t) = H0 exp(-K ρ g t / A_cyl) in m for a linear leak Q = K ΔP (K in m³/(s·Pa), t in s; docs/theory.md §4.2)."""
    k = conductance * rig.density * rig.gravity / rig.cylinder_area
    return rig.initial_height * np.exp(-k * np.asarray(t, dtype=float))


def drain_time(rig: RigSetup, conductance: float, final_height: float) -> float:
    """Time (s) for the level to fall from H0 to ``final_height`` with Q = K ΔP (inf for K = 0).

    t = τ ln(H0/H1), τ = A_cyl/(K ρ g) (docs/theory.md §4.2); K in m³/(s·Pa), heights in m.
    """
    if conductance <= 0:
        return float("inf")
    return rig.cylinder_area / (conductance * rig.density * rig.gravity) * np.log(rig.initial_height / final_height)


@dataclass(frozen=True)
class WaterColumn:
    """Solution of A_cyl dH/dt = -Q(ρ g H) (docs/theory.md §4.2).

    Attributes
    ----------
    time
        Times t (s).
    height
        Fluid level H(t) (m).
    leak_rate
        Q(ρ g H(t)) (m³/s).
    final_height
        The level whose time of arrival is reported (m).
    time_to_final
        The time the level reached ``final_height`` (s; NaN if it did not within the simulated span).
    stop_height
        The level at which capillarity stops the fall, ρ g H_e = the entry pressure p_e (m; None: no stop;
        docs/theory.md §12.1): Q = 0 there and below.
    time_to_stop
        The time the level reached ``stop_height`` (s; 0 if held from the start, NaN if not within the span).
    """

    time: FloatArray
    height: FloatArray
    leak_rate: FloatArray
    final_height: float
    time_to_final: float
    stop_height: float | None = None
    time_to_stop: float = float("nan")


#: The shortest time scale A H0/Q0 (s) of a water column the rig simulates: a microsecond (a real one takes minutes to days).
MIN_TIME_SCALE = 1e-6


def water_column(rig: RigSetup, leak_rate: Callable[[FloatArray], FloatArray], *, t_end: float | None = None,
                 t_eval: ArrayLike | None = None, rtol: float = 1e-12, atol: float | None = None,
                 entry_pressure: float = 0.0) -> WaterColumn:
    """Integrate A_cyl dH/dt = -Q(ρ g H) from H0 with ``leak_rate(ΔP)`` (m³/s) by solve_ivp (Radau).

    The time of arrival at ``rig.final_height`` (H0/2 if None) is located by an event. ``t_end`` (s)
    defaults to the last of ``t_eval``, else ``rig.duration``, else 1.5× the arrival time estimated
    from the initial leak rate with τ = A_cyl H0/Q(ρgH0) (at least τ; 3600 s when that leak rate is 0).
    docs/theory.md §4.2.

    ``entry_pressure`` p_e > 0 (Pa): capillarity holds the liquid where ρ g H < p_e (docs/theory.md eq. 12.3), so
    the level stops at H_e = p_e/(ρ g) (a terminal event; ``leak_rate`` is the leak without capillarity) and
    stays there with Q = 0; a column with ρ g H0 < p_e does not fall at all. p_e <= 0: no stop.
    """
    area = rig.cylinder_area
    h1 = rig.final_height if rig.final_height is not None else 0.5 * rig.initial_height
    h_stop = entry_pressure / (rig.density * rig.gravity) if entry_pressure > 0 else None
    q0 = float(np.asarray(leak_rate(np.array([rig.pressure_difference(rig.initial_height)])))[0])
    if not np.isfinite(q0) or q0 < 0:
        raise InputError("leak rate at the initial height", q0, "must be finite and >= 0 (m^3/s)")
    if t_end is None and t_eval is not None:
        t_end = float(np.max(np.asarray(t_eval, dtype=float)))
    if t_end is None:
        t_end = rig.duration
    tau = area * rig.initial_height / q0 if q0 > 0 else math.inf  # the column's time scale A H0/Q0 (s)
    if tau < MIN_TIME_SCALE:  # (a cylinder of 1e-90 m: the ODE overflowed into a traceback)
        raise InputError("rig", f"A H0/Q0 = {tau:.3g} s",
                         f"the column would empty within {MIN_TIME_SCALE:g} s (cylinder area A = {area:.3g} m², initial "
                         f"height H0 = {rig.initial_height:.3g} m, leak rate Q0 = {q0:.3g} m³/s): check "
                         "rig.cylinder_diameter and rig.initial_height")
    if t_end is None:
        if q0 == 0:
            t_end = 3600.0
        else:  # linear estimate: τ = A H0/Q0; go to the final level and a bit beyond
            t_end = tau * max(1.5 * np.log(rig.initial_height / h1), 1.0)
    if t_eval is None:
        t_eval = np.linspace(0.0, t_end, 401)
    t_eval = np.asarray(t_eval, float)
    if h_stop is not None and h_stop >= rig.initial_height:  # held from the start: H = H0, Q = 0
        return WaterColumn(time=t_eval, height=np.full(t_eval.size, rig.initial_height), leak_rate=np.zeros(t_eval.size),
                           final_height=h1, time_to_final=float("nan"), stop_height=h_stop, time_to_stop=0.0)
    if atol is None:
        atol = 1e-14 * rig.initial_height

    def rhs(t, y):
        return [-float(np.asarray(leak_rate(np.array([rig.pressure_difference(max(y[0], 0.0))])))[0]) / area]

    def reach(t, y):
        return y[0] - h1

    def stop(t, y):
        return y[0] - (h_stop or 0.0)

    reach.terminal = False  # type: ignore[attr-defined]  # scipy's event attributes
    reach.direction = -1  # type: ignore[attr-defined]
    stop.terminal = True  # type: ignore[attr-defined]
    stop.direction = -1  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0.0, float(t_end)), [rig.initial_height], method="Radau", t_eval=t_eval,
                    events=[reach] if h_stop is None else [reach, stop], rtol=rtol, atol=atol)
    if not sol.success:
        raise ConvergenceError(f"water column: the ODE solver failed ({sol.message})")
    hits = sol.t_events[0]
    t_final = float(hits[0]) if hits.size else float("nan")
    times, heights = sol.t, sol.y[0]
    q = np.asarray(leak_rate(rig.pressure_difference(heights)), dtype=float)
    t_stop = float("nan")
    if h_stop is not None and sol.t_events[1].size:  # the meniscus holds the rest: H = H_e, Q = 0
        t_stop = float(sol.t_events[1][0])
        after = t_eval[t_eval > t_stop]
        times = np.concatenate([times, [t_stop], after])
        heights = np.concatenate([heights, [h_stop], np.full(after.size, h_stop)])
        q = np.concatenate([q, [0.0], np.zeros(after.size)])
    return WaterColumn(time=times, height=heights, leak_rate=q, final_height=h1, time_to_final=t_final,
                       stop_height=h_stop, time_to_stop=t_stop)


@dataclass(frozen=True, kw_only=True)
class ReadingsAnalysis:
    """Leak rate from (time, height) readings of the rig (docs/theory.md §4.3).

    Attributes
    ----------
    time, height
        The readings t_i (s) and H_i (m).
    interval_pressure_difference, interval_leak_rate
        ΔP = ρ g (H_i + H_(i+1))/2 at the mid-height and Q = -A_cyl ΔH/Δt of each interval between
        consecutive readings (Pa, m³/s).
    conductance, conductance_std
        K = -A_cyl b/(ρ g) from the straight-line fit ln H = a + b t (m³/(s·Pa)) and its standard
        error (NaN with two readings).
    rms_log_residual
        Rms residual of the fit of ln H, in decades.
    """

    time: FloatArray
    height: FloatArray
    interval_pressure_difference: FloatArray = quantity("Pa", "mean ΔP of each reading interval")
    interval_leak_rate: FloatArray = quantity("m^3/s", "leak rate of each reading interval")
    conductance: float = quantity("m^3/(s*Pa)", "K from the exponential fit of the readings")
    conductance_std: float = quantity("m^3/(s*Pa)", "standard error of that K")
    rms_log_residual: float


def leak_rate_from_readings(rig: RigSetup, time: ArrayLike, height: ArrayLike, source: str = "readings") -> ReadingsAnalysis:
    """Leak rate against ΔP from (t, H) readings in s and m (see the module docstring; docs/theory.md §4.3)."""
    t = np.asarray(time, dtype=float)
    h = np.asarray(height, dtype=float)
    if t.size < 2:
        raise FileFormatError(source, f"needs at least two readings, found {t.size}")
    if not (np.isfinite(t).all() and np.isfinite(h).all()):
        raise FileFormatError(source, "readings must be finite numbers")
    if (h <= 0).any():
        i = int(np.argmax(h <= 0))
        raise FileFormatError(source, f"reading {i + 1}: height = {h[i]:.6g} m (must be > 0)")
    dt = np.diff(t)
    if (dt <= 0).any():
        i = int(np.argmax(dt <= 0)) + 1
        raise FileFormatError(source, f"reading {i + 1}: time {t[i]:.6g} s is not after the previous reading "
                                      f"({t[i - 1]:.6g} s); times must increase")
    area = rig.cylinder_area
    q = -area * np.diff(h) / dt
    dp = rig.pressure_difference(0.5 * (h[1:] + h[:-1]))
    y = np.log(h)
    if t.size >= 2:
        tm = t.mean()
        sxx = np.sum((t - tm) ** 2)
        slope = np.sum((t - tm) * (y - y.mean())) / sxx
        resid = y - (y.mean() + slope * (t - tm))
        if t.size > 2:
            s2 = np.sum(resid**2) / (t.size - 2)
            slope_std = np.sqrt(s2 / sxx)
        else:
            slope_std = float("nan")
    k = -slope * area / (rig.density * rig.gravity)
    k_std = slope_std * area / (rig.density * rig.gravity)
    if not k > 0:
        raise FileFormatError(source, f"the water level does not fall over the readings (H = {h[0]:.6g} m at "
                                      f"t = {t[0]:.6g} s, {h[-1]:.6g} m at t = {t[-1]:.6g} s; fitted K = Q/ΔP = "
                                      f"{k:.3g} m³/(s·Pa)): no leak rate can be read from them (check the columns)")
    rms = float(np.sqrt(np.mean(resid**2)) / np.log(10.0))
    return ReadingsAnalysis(time=t, height=h, interval_pressure_difference=dp, interval_leak_rate=q,
                            conductance=float(k), conductance_std=float(k_std), rms_log_residual=rms)


@dataclass(frozen=True)
class DecayRigSetup:
    """The pressure-decay rig: a test volume of gas leaking through the seal (SI units; docs/theory.md §11.7).

    Attributes
    ----------
    test
        V (m³), the initial and outside absolute pressures P1, P2 (Pa), the temperature T (K), the
        pressure loss ΔP to time (Pa) and the simulated duration (s):
        :class:`~sealeak.lab.pressure_decay.PressureDecaySetup`.
    gas
        The ideal gas at T (viscosity μ in Pa·s, molar mass M in kg/mol) whose throughput
        Q_pV = K ∫ p f(Kn(p)) dp through the seal empties the volume (docs/theory.md §11.5).
    rarefaction_model
        The f(Kn) of :func:`~sealeak.physics.gas.slip_factor` ("kinetic", "beskok-karniadakis" or "no-slip").
    load
        Force F pressing a flat seal (N), as for the water column; None for an O-ring or pressure-profile
        seal, whose compression or profile scale sets the contact.
    load_note
        How the load was given (e.g. a mass converted with g), for reports.
    gas_note
        Where the gas's properties come from (property library, temperature), for reports.
    """

    test: PressureDecaySetup
    gas: Gas
    rarefaction_model: str = DEFAULT_RAREFACTION
    load: float | None = quantity("N", "load pressing the seal", default=None)
    load_note: str = ""
    gas_note: str = ""

    def __post_init__(self) -> None:
        check_rarefaction_model(self.rarefaction_model)
        if self.load is not None:
            positive_number("load", self.load)
        if abs(self.gas.temperature - self.test.temperature) > 1e-9 * self.test.temperature:
            raise InputError("temperature", self.gas.temperature,
                             f"the gas must be at the test temperature {self.test.temperature:.6g} K")

    @property
    def kind(self) -> str:
        """"pressure-decay" (:data:`RIG_KINDS`)."""
        return "pressure-decay"

    def squeeze_pressure(self, seal: Seal) -> float:
        """P0 = F / (Lx Ly) in Pa for a flat seal pressed by ``load``."""
        if self.load is None:
            raise InputError("load", None, "the rig has no load: the seal's compression or profile scale sets the contact")
        return seal.squeeze_pressure_from_load(self.load)


def read_decay_readings(path: str | Path, setup: PressureDecaySetup | None = None) -> tuple[FloatArray, FloatArray]:
    """Pressure-decay readings: columns time and pressure with units (e.g. 'time (min), pressure (mbar)');
    returns t (s) and the absolute pressure P (Pa). A missing or unknown column, a column without a
    unit or in a unit of the wrong kind, a value that is not a finite number, more than
    :data:`~sealeak.lab.data.MAX_READINGS` readings or a file over :data:`~sealeak.lab.data.MAX_DATA_BYTES` bytes is a
    :class:`FileFormatError` naming the file and the column. With ``setup`` (the rig's test) the readings are also
    checked against it as :func:`~sealeak.lab.pressure_decay.leak_rate_from_decay` does (at least two, times
    increasing, pressures above the outside one and falling), so a caller can refuse them before any model runs."""
    p = Path(path)
    table = read_readings_table(p, min_columns=2)
    if not table.has_header:
        raise FileFormatError(p, "the first row must name every column with its unit, e.g. 'time (min), pressure (mbar)'")
    found: dict[str, int] = {}
    for i, name in enumerate(table.names):
        key = name.strip().lower().replace(" ", "_")
        canon = next((c for c, names in _DECAY_COLUMNS.items() if key in names), None)
        if canon is None:
            raise FileFormatError(p, f"column {i + 1} '{name}' is not one of the columns this file takes: time, pressure "
                                     "(the absolute pressure in the test volume)")
        if canon in found:
            raise FileFormatError(p, f"column {i + 1} '{name}' repeats column {found[canon] + 1} ({canon})")
        found[canon] = i
    missing = [c for c in _DECAY_COLUMNS if c not in found]
    if missing:
        raise FileFormatError(p, f"missing column {', '.join(missing)} (found: {', '.join(table.names)})")
    out = []
    for canon, dimension in (("time", "time"), ("pressure", "pressure")):
        i = found[canon]
        if not table.units[i]:
            raise FileFormatError(p, f"column '{table.names[i]}' has no unit: write it in parentheses, e.g. "
                                     f"'{table.names[i]} ({'min' if canon == 'time' else 'mbar'})'")
        try:
            factor = unit_factor(f"column '{table.names[i]}' unit", table.units[i], dimension)
        except UnitError as exc:
            raise FileFormatError(p, str(exc)) from None
        values = table.data[:, i]
        if not np.isfinite(values).all():
            r = int(np.argmax(~np.isfinite(values)))
            raise FileFormatError(p, f"line {table.line_of(r)}, column '{table.names[i]}': not a finite number")
        # a value within the case file's SI range (times of 1e-300 min left no time between readings: a traceback)
        out.append(table.in_si(i, factor, "s" if canon == "time" else "Pa"))
    if setup is not None:
        leak_rate_from_decay(setup, out[0], out[1], source=str(path))
    return out[0], out[1]
