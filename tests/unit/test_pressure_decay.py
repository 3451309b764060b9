"""The virtual pressure-decay test and the leak rate and α from its readings (docs/theory.md §Pressure-decay test)."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

import sealeak.lab.pressure_decay as module
from sealeak.errors import FileFormatError, InputError
from sealeak.lab.pressure_decay import (
    PressureDecaySetup,
    exponential_decay,
    leak_rate_from_decay,
    pressure_decay,
    scale_factor_from_decay,
    standard_leak_rate,
    viscous_decay,
    viscous_decay_time,
    viscous_throughput_function,
)
from sealeak.physics.gas import Gas, gas_leak

V = 1e-4  # 100 cm³
AIR = Gas("air", 293.15, 18.2e-6, 0.0289647)


def decay_setup(p1=3e5, p2=1e5, loss=None):
    return PressureDecaySetup(volume=V, initial_pressure=p1, outside_pressure=p2, temperature=293.15, pressure_loss=loss)


def linear_throughput(k, mean_pressure):
    return lambda p_in, p_out: k * mean_pressure * (p_in - p_out)


# ---------------------------------------------------------------------- the ODE against its closed forms
@pytest.mark.parametrize("p1, p2", [(3e5, 1e5), (2e5, 1e5), (1e5, 0.0), (10e5, 1e5), (1.01e5, 1e5)])
@pytest.mark.parametrize("k", [1e-15])
def test_viscous_decay_ode_matches_its_closed_form_to_1e_8(p1, p2, k):
    s = decay_setup(p1, p2)
    t_half = 2 * V / (k * p1)  # for vacuum outside, P1/2 is reached at t = 2V/(K P1)
    t = np.linspace(0.0, 5 * t_half, 60)
    ode = pressure_decay(s, viscous_throughput_function(k), t_eval=t)
    exact = viscous_decay(s, k, t)
    assert np.max(np.abs(ode.pressure - exact) / exact) < 1e-8
    assert np.max(np.abs(ode.pressure - exact)) / (p1 - p2) < 1e-8
    assert ode.time_to_loss == pytest.approx(viscous_decay_time(s, k), rel=1e-8)


def test_vacuum_decay_by_hand():
    """P2 = 0: P = P1/(1 + K P1 t/(2V)): half the pressure at t = 2V/(K P1) = 2e-4/(1e-15·1e5) = 2e6 s."""
    s = decay_setup(1e5, 0.0, loss=0.5e5)
    assert viscous_decay_time(s, 1e-15) == pytest.approx(2e6, rel=1e-12)
    assert float(viscous_decay(s, 1e-15, 2e6)) == pytest.approx(0.5e5, rel=1e-12)


@pytest.mark.parametrize("p1, p2", [(3e5, 1e5), (1.001e5, 1e5), (1e5, 0.0)])
def test_linear_leak_ode_matches_the_exponential_to_1e_8(p1, p2):
    s = decay_setup(p1, p2)
    k = 1e-14
    pm = 0.5 * (p1 + p2)
    tau = V / (k * pm)
    t = np.linspace(0.0, 4 * tau, 50)
    ode = pressure_decay(s, linear_throughput(k, pm), t_eval=t)
    exact = exponential_decay(s, k, t)
    assert np.max(np.abs(ode.pressure - exact)) / (p1 - p2) < 1e-8


def test_viscous_decay_tends_to_the_exponential_for_small_pressure_difference():
    """ΔP ≪ P: (K/2)(P² − P2²) ≈ K P̄ (P − P2); the difference of the two decays shrinks with (P1 − P2)/P2."""
    k, p2 = 1e-14, 1e5
    errors = []
    for dp in (1e5, 1e4, 1e3, 1e2):
        s = decay_setup(p2 + dp, p2)
        tau = V / (k * (p2 + dp / 2))
        t = np.linspace(0.0, 3 * tau, 40)
        errors.append(np.max(np.abs(viscous_decay(s, k, t) - exponential_decay(s, k, t))) / dp)
    assert errors[0] > errors[1] > errors[2] > errors[3]
    assert errors[3] < 1e-3 and errors[1] / errors[2] == pytest.approx(10, rel=0.2)  # first order in ΔP/P


def test_standard_leak_rate_is_the_throughput_for_a_small_loss():
    """V ΔP/Δt with ΔP ≪ P1 − P2 tends to Q_pV(P1, P2) = (K/2)(P1² − P2²)."""
    k = 1e-15
    for loss, tol in ((1e3, 1e-2), (1e1, 1e-4)):
        s = decay_setup(3e5, 1e5, loss=loss)
        decay = pressure_decay(s, viscous_throughput_function(k))
        assert decay.standard_leak_rate == pytest.approx(0.5 * k * (9e10 - 1e10), rel=tol)
        assert decay.standard_leak_rate == pytest.approx(standard_leak_rate(V, loss, decay.time_to_loss), rel=1e-14, abs=0)


def test_rarefied_decay_leaks_more_than_the_viscous_one():
    gap = 100e-9
    k = 10 * gap**3 / (12 * AIR.viscosity)
    s = decay_setup(2e5, 1e5, loss=1e4)
    rarefied = pressure_decay(s, lambda pi, po: gas_leak(k, gap, AIR, pi, po).throughput)
    assert rarefied.time_to_loss < viscous_decay_time(s, k)
    assert np.all(rarefied.pressure[1:] < viscous_decay(s, k, rarefied.time[1:]))


def test_no_leak_no_decay():
    decay = pressure_decay(decay_setup(), viscous_throughput_function(0.0))
    assert np.all(decay.pressure == 3e5) and math.isnan(decay.time_to_loss)
    assert math.isinf(viscous_decay_time(decay_setup(), 0.0))


# ---------------------------------------------------------------------- readings: leak rate, conductance, α
@pytest.mark.parametrize("p1, p2", [(3e5, 1e5), (1e5, 0.0)])
def test_conductance_from_exact_readings(p1, p2):
    k = 2e-15
    s = decay_setup(p1, p2)
    t = np.linspace(0.0, 3e5, 12)
    readings = leak_rate_from_decay(s, t, viscous_decay(s, k, t))
    assert readings.conductance == pytest.approx(k, rel=1e-9, abs=0)
    assert readings.rms_relative_residual < 1e-10
    p = viscous_decay(s, k, t)
    assert readings.leak_rate == pytest.approx(V * (p[0] - p[-1]) / (t[-1] - t[0]), rel=1e-12, abs=0)
    assert np.all(readings.interval_leak_rate > 0) and np.all(np.diff(readings.interval_leak_rate) < 0)


def test_alpha_from_readings_of_a_rarefied_leak():
    """Readings simulated with α = 0.37 times a rarefied model give α back through the model at α = 1."""
    gap = 80e-9
    k1 = 10 * gap**3 / (12 * AIR.viscosity)

    def model(p_in, p_out):
        return gas_leak(k1, gap, AIR, p_in, p_out).throughput

    s = decay_setup(2e5, 1e5)
    t = np.linspace(0.0, 4e4, 15)
    simulated = pressure_decay(s, lambda pi, po: 0.37 * model(pi, po), t_eval=t)
    fit = scale_factor_from_decay(s, simulated.time, simulated.pressure, model)
    assert fit.alpha == pytest.approx(0.37, rel=1e-7)
    viscous = scale_factor_from_decay(s, t, viscous_decay(s, 0.37 * k1, t), viscous_throughput_function(k1))
    assert viscous.alpha == pytest.approx(0.37, rel=1e-9)
    assert leak_rate_from_decay(s, t, viscous_decay(s, 0.37 * k1, t)).conductance / k1 == pytest.approx(viscous.alpha, rel=1e-9)


def test_alpha_from_noisy_readings_within_its_error():
    rng = np.random.default_rng(13)
    k1 = 1e-15
    s = decay_setup(3e5, 1e5)
    t = np.linspace(0.0, 2e5, 25)
    hits = 0
    for _ in range(40):
        p = viscous_decay(s, 2.0 * k1, t) + rng.normal(0.0, 20.0, t.size)
        fit = scale_factor_from_decay(s, t, p, viscous_throughput_function(k1))
        hits += abs(fit.alpha - 2.0) < 3 * fit.alpha_std
    assert hits >= 36


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize("field, kwargs", [
    ("volume", {"volume": -1e-4}), ("volume", {"volume": 0.0}), ("temperature", {"temperature": -10.0}),
    ("initial_pressure", {"initial_pressure": -1e5}), ("outside_pressure", {"outside_pressure": -1.0}),
    ("initial_pressure", {"initial_pressure": 1e5, "outside_pressure": 2e5}), ("initial_pressure", {"initial_pressure": 1e5}),
    ("pressure_loss", {"pressure_loss": 3e5}), ("pressure_loss", {"pressure_loss": -1.0}), ("duration", {"duration": 0.0}),
    ("initial_pressure", {"initial_pressure": math.nan}),
])
def test_bad_setup_names_the_field(field, kwargs):
    args = {"volume": V, "initial_pressure": 3e5, "outside_pressure": 1e5, "temperature": 293.15} | kwargs
    if field == "initial_pressure" and kwargs == {"initial_pressure": 1e5}:
        args["outside_pressure"] = 1e5
    with pytest.raises(InputError) as exc:
        PressureDecaySetup(**args)
    assert exc.value.field == field


@pytest.mark.parametrize("t, p, why", [
    ([0, 10, 20], [2e5, 2e5, 2.1e5], "does not fall"),
    ([0, 10, 10], [2e5, 1.9e5, 1.8e5], "times must increase"),
    ([0, 10, 20], [2e5, 1.5e5, 0.9e5], "outside pressure"),
    ([0], [2e5], "at least two"),
    ([0, 10, np.nan], [2e5, 1.9e5, 1.8e5], "finite"),
])
def test_unusable_readings_name_the_file(t, p, why):
    for call in (lambda: leak_rate_from_decay(decay_setup(), t, p, source="decay.csv"),
                 lambda: scale_factor_from_decay(decay_setup(), t, p, viscous_throughput_function(1e-15), source="decay.csv")):
        with pytest.raises(FileFormatError, match=why) as exc:
            call()
        assert exc.value.path == "decay.csv"


def test_a_throughput_function_returning_nonsense_is_refused():
    with pytest.raises(InputError):
        pressure_decay(decay_setup(), lambda pi, po: -1.0)


def test_many_readings_cost_one_series_not_a_quadrature_each_and_agree_with_it(monkeypatch):
    """J_i = ∫ dP/Q_1 was an adaptive quadrature per reading (~40 throughputs each; 1 000 readings of the
    pressure-decay example took 7 minutes). From 9 readings on one Chebyshev series of 1/Q_1 serves them all: the
    throughputs it takes do not grow with the readings, and α agrees with the quadrature per reading and with the
    closed form of the viscous law. A throughput with a kink between the readings (no series converges) takes the
    quadrature, and is still right."""
    k1 = 1e-15
    s = decay_setup(3e5, 1e5)
    calls = {"n": 0}

    def counted(law):
        def q(p_in, p_out):
            calls["n"] += 1
            return law(p_in, p_out)
        return q

    fits = {}
    for n in (50, 2000):
        t = np.linspace(0.0, 2e5, n)
        calls["n"] = 0
        fits[n] = scale_factor_from_decay(s, t, viscous_decay(s, 2.0 * k1, t), counted(viscous_throughput_function(k1)))
        assert calls["n"] <= 2 * (module.SERIES_DEGREE + 1)  # (16 + 1 points for this smooth law)
        assert fits[n].alpha == pytest.approx(2.0, rel=1e-9)
    t = np.linspace(0.0, 2e5, 50)
    monkeypatch.setattr(module, "SERIES_READINGS", 10**6)  # the quadrature per reading
    per_reading = scale_factor_from_decay(s, t, viscous_decay(s, 2.0 * k1, t), viscous_throughput_function(k1))
    assert fits[50].alpha == pytest.approx(per_reading.alpha, rel=1e-9)
    np.testing.assert_allclose(fits[50].resistance_integral, per_reading.resistance_integral, rtol=1e-9, atol=0)
    monkeypatch.undo()
    law = viscous_throughput_function(k1)
    p = viscous_decay(s, 2.0 * k1, t)
    kink = float(np.median(p))

    def kinked(p_in, p_out):
        return law(p_in, p_out) * (1.0 if p_in < kink else 1.0 + (p_in - kink) / kink)
    calls["n"] = 0
    fit = scale_factor_from_decay(s, t, p, counted(kinked))
    assert calls["n"] > 2 * (module.SERIES_DEGREE + 1)  # no series converged: a quadrature per reading
    exact = np.array([0.0] + [quad(lambda x: 1.0 / kinked(x, s.outside_pressure), pi, p[0], epsrel=1e-12)[0] for pi in p[1:]])
    np.testing.assert_allclose(fit.resistance_integral, exact, rtol=1e-9, atol=0)
