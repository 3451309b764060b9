"""The exact gas coupling: the gas pressure acting on the contact along the pV flow (docs/theory.md §13.5).

The sheet of the tests is an exponential σ(s) = σ0 exp(−s/p1) (m³/(Pa·s)) with the gap h = (12 μ σ)^(1/3) of a slit
of the same conductance and a constriction of length L = 30 h (1 + s/P0): σ and h fall with the effective pressure as
Persson's theory has them, and the slit length varies, so the kinetic cap does too.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

import sealeak.physics.coupling as coupling
from sealeak.physics.coupling import coupled_gas_band_flow, coupled_gas_integral, effective_pressure_integral, gas_sheet
from sealeak.physics.gas import Gas, pressure_integral, slip_factor
from sealeak.physics.profile import PressureProfile

MU = 1.8e-5  # Pa·s
AIR = Gas("air", 293.15, MU, 0.029)
P0 = 5e5  # Pa
SIGMA0, P1 = 3e-20, 1.5e5  # m³/(Pa·s), Pa: σ(P0) = 1e-21 m³/(Pa·s), u ≈ 60 nm: Kn ≈ 1 at 1 bar
W = 1e-3  # m, band width
MODELS = ("no-slip", "kinetic", "beskok-karniadakis")


def sigma(s):
    return SIGMA0 * np.exp(-np.asarray(s, dtype=float) / P1)


def gap(s):
    return np.cbrt(12.0 * MU * sigma(s))


def length(s):
    return 30.0 * gap(s) * (1.0 + np.asarray(s, dtype=float) / P0)


def sheet(s):
    return sigma(s), gap(s), length(s)


def _sheet(model, top=P0):
    made = gas_sheet(sheet, 1e-6 * top, top)
    assert made is not None
    return made.for_gas(AIR, model, 1.0)


def _direct(model, pb, dp, top=P0):
    """∫_{P_b}^{P_a} σ(s) P f(λ(P)/h(s), L(s)/h(s)) dP with s = P0 − (P − P_b), by adaptive quadrature on the sheet's
    own functions and the slip factor of docs/theory.md §11.4 (no table)."""
    def integrand(p):
        s = top - (p - pb)
        h = float(gap(s))
        kn = float(AIR.knudsen_number(h, p)) if p > 0 else math.inf
        ratio = float(length(s)) / h if model == "kinetic" else None
        f = float(slip_factor(kn, model, ratio)) if p > 0 else 0.0
        return float(sigma(s)) * p * f
    if model != "no-slip" and pb == 0:  # p f(c/p) stays finite at p = 0: integrate from a hair above
        return quad(integrand, 1e-9 * dp, pb + dp, epsabs=0.0, epsrel=1e-11, limit=400)[0]
    return quad(integrand, pb, pb + dp, epsabs=0.0, epsrel=1e-11, limit=400)[0]


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("pb, dp", [(1e5, 1e5), (0.0, 1e5), (1e5, 3e5)])
def test_uniform_integral_equals_an_independent_quadrature(model, pb, dp):
    got = coupled_gas_integral(_sheet(model), P0, pb, dp)
    assert not got.lifted[0]
    assert float(got.value[0]) == pytest.approx(_direct(model, pb, dp), rel=2e-6, abs=0)


@pytest.mark.parametrize("model", MODELS)
def test_small_pressure_difference_is_the_liquid_form_with_the_p2_integral(model):
    """ΔP ≪ P0: the contact hardly feels the gas, σ(s) → σ(P0) and h(s) → h(P0): K ∫ p f dp (§11.5) with K the
    liquid's coupled conductance (§13.2) and the gap and length at P0."""
    pb, dp = 1e5, 20.0
    k = float(effective_pressure_integral(sigma, P0, dp).value[0]) / dp  # (Ly/w) = 1
    h0 = float(gap(P0))
    expected = k * pressure_integral(h0, AIR, pb + dp, pb, model, float(length(P0)) if model == "kinetic" else None)
    # (O(ΔP/P0): 2.6e-5 here)
    assert float(coupled_gas_integral(_sheet(model), P0, pb, dp).value[0]) == pytest.approx(expected, rel=1e-4, abs=0)


def test_continuum_limit_is_the_p2_integral():
    """Kn → 0 (no slip) at any ΔP: the gas weights σ(s) by P: ∫σ(P0 − (P − P_b)) P dP, in closed form for the
    exponential σ."""
    pb, dp = 1e5, 2e5
    got = float(coupled_gas_integral(_sheet("no-slip"), P0, pb, dp).value[0])
    # ∫_{pb}^{pb+dp} σ0 e^{−(P0 − P + pb)/p1} P dP = σ0 e^{−(P0+pb)/p1} p1 [e^{P/p1} (P − p1)]
    def antiderivative(p):
        return SIGMA0 * math.exp(-(P0 + pb) / P1) * P1 * math.exp(p / P1) * (p - P1)
    assert got == pytest.approx(antiderivative(pb + dp) - antiderivative(pb), rel=1e-7, abs=0)  # (2e-8 here)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("pb", [0.0, 1e5])
def test_flat_band_equals_the_uniform_closed_form(model, pb):
    flat = PressureProfile.table([0.0, 0.4 * W, W], [P0, P0, P0])
    band = coupled_gas_band_flow(flat, _sheet(model), pb, 2e5)
    assert band.converged and not band.lifted
    assert band.flow == pytest.approx(float(coupled_gas_integral(_sheet(model), P0, pb, 2e5).value[0]) / W, rel=1e-6, abs=0)


@pytest.mark.parametrize("model", ["no-slip", "kinetic"])
def test_band_against_shooting_in_x(model):
    """A Hertz band solved independently: dP/dx = −q/g(p(x) − (P − P_b), P) in x by Radau from P_a, q by bisection
    on P(w) = P_b (P_b > 0: regular at the outlet)."""
    pb, dp, peak = 1e5, 1.5e5, 8e5
    profile = PressureProfile.semi_elliptic(W, peak)
    g = _sheet(model, peak)

    def outlet(q):
        sol = solve_ivp(lambda x, y: [-q / g(float(profile.at(x)) - (y[0] - pb), max(y[0], 1.0))], (0.0, W), [pb + dp],
                        method="Radau", rtol=1e-10, atol=1e-6)
        return sol.y[0, -1] - pb

    guess = float(coupled_gas_integral(g, profile.mean_pressure, pb, dp).value[0]) / W
    q = brentq(outlet, 0.2 * guess, 5 * guess, rtol=1e-10)
    assert coupled_gas_band_flow(profile, g, pb, dp).flow == pytest.approx(q, rel=1e-4, abs=0)  # (2e-5 here)


def test_coupled_gas_leak_and_the_old_approximation():
    """The old approximation took K = Q/ΔP of the liquid (σ averaged over s) times ∫ p f dp at the narrowest gap.
    Without slip, weighting σ by the gas pressure P (both largest upstream) leaks more (Chebyshev's sum inequality).
    With slip, the wider gaps upstream slip less than the narrowest: the exact leak lies between f at the widest
    and at the narrowest gap, below the approximation when slip dominates."""
    pb, dp = 1e5, 2e5
    k = float(effective_pressure_integral(sigma, P0, dp).value[0]) / dp
    exact = float(coupled_gas_integral(_sheet("no-slip"), P0, pb, dp).value[0])
    assert exact > k * 0.5 * ((pb + dp) ** 2 - pb**2) * 1.01

    kinetic = float(coupled_gas_integral(_sheet("kinetic"), P0, pb, dp).value[0])

    def at_gap(s_gap):
        h, ell = float(gap(s_gap)), float(length(s_gap) / gap(s_gap))
        return quad(lambda p: float(sigma(P0 - (p - pb))) * p * float(slip_factor(float(AIR.knudsen_number(h, p)),
                                                                                    "kinetic", ell)),
                    pb, pb + dp, epsrel=1e-10)[0]
    assert at_gap(P0 - dp) < kinetic < at_gap(P0)
    assert kinetic > exact  # slip only adds flow


def test_lift_off_is_the_limit():
    g = _sheet("no-slip")
    lifted = coupled_gas_integral(g, P0, 1e5, 2 * P0)
    limit = coupled_gas_integral(g, P0, 1e5, P0 * (1 - 1e-6))
    assert lifted.lifted[0] and float(lifted.value[0]) == pytest.approx(float(limit.value[0]), rel=1e-6, abs=0)


def test_a_sealed_contact_has_no_sheet_and_no_flow():
    assert gas_sheet(lambda s: (np.zeros_like(s), gap(s), length(s)), 1.0, P0) is None
    profile = PressureProfile.semi_elliptic(W, P0)
    assert coupled_gas_band_flow(profile, None, 1e5, 1e5).flow == 0.0


@pytest.mark.parametrize("model", MODELS)
def test_band_at_the_flow_tolerance_and_with_the_python_integrator(model, monkeypatch):
    """A Hertz band against a vacuum outlet, whose P = √y makes each shot's P(w) noisy at ~1e-7 ΔP: Brent's method
    at the default tolerance (1e-7) gives the flow of one run to 1e-10 within 1e-6, and a band the Fortran DOP853
    gives up on is shot with solve_ivp's DOP853 instead, to the same flow within the shots' own error (the two codes
    control their steps differently: 1.5e-6 apart here on the kinetic sheet, whose tables have kinks)."""
    profile = PressureProfile.semi_elliptic(W, P0)
    g = _sheet(model)
    default = coupled_gas_band_flow(profile, g, 0.0, 1e5)
    tight = coupled_gas_band_flow(profile, g, 0.0, 1e5, rtol=1e-10)
    assert default.converged and default.flow == pytest.approx(tight.flow, rel=1e-6, abs=0)
    assert default.shots < tight.shots
    across = coupling._across

    def fortran_gives_up(slope, y, dp, fortran):
        if fortran:
            raise coupling._GaveUp
        return across(slope, y, dp, fortran)
    monkeypatch.setattr(coupling, "_across", fortran_gives_up)
    python = coupled_gas_band_flow(profile, g, 0.0, 1e5)
    assert python.converged and python.flow == pytest.approx(default.flow, rel=1e-5, abs=0)
