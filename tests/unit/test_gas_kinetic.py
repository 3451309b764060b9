"""The kinetic slit model of rarefied gas flow (docs/theory.md §11.4): the table against published
values and asymptotes, the slip factor's limits, the finite-length cap, and the model against
Beskok–Karniadakis."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sealeak.physics._kinetic_slit import (
    SIGMA_P,
    capped_rarefaction,
    capped_rarefactions,
    finite_slit_free_molecular,
    knudsen_minimum,
    poiseuille_flow_rate,
    poiseuille_flow_rate_at,
)
from sealeak.physics.gas import DEFAULT_RAREFACTION, RAREFACTION_MODELS, Gas, gas_leak, pressure_integral, slip_factor

SQRT_PI = math.sqrt(math.pi)


@pytest.fixture
def helium():
    return Gas("helium", 293.15, 1.96e-5, 4.0026e-3)


def test_kinetic_is_the_default_and_the_other_models_are_kept():
    assert DEFAULT_RAREFACTION == "kinetic" and set(RAREFACTION_MODELS) == {"kinetic", "beskok-karniadakis", "no-slip"}


def test_published_flow_rate_at_delta_one():
    """Cercignani & Daneri (1963), plane channel, BGK, diffuse walls: G_P(δ = 1) = 1.5389."""
    assert float(poiseuille_flow_rate(1.0)) == pytest.approx(1.5389, rel=1e-3)


def test_slip_asymptote_and_the_fukui_kaneko_formula():
    """δ → ∞: G_P → δ/6 + σ_P, σ_P = 1.0162 (BGK viscous slip, Sharipov & Seleznev 1998); for δ >= 5 the
    interpolation formula of Fukui & Kaneko (1990), D/6 + 1.0162 + 1.0653/D − 2.1354/D²."""
    for d in (1e3, 1e5):
        assert float(poiseuille_flow_rate(d)) - d / 6 == pytest.approx(SIGMA_P, rel=2e-3)
    for d in (5.0, 10.0, 20.0, 40.0):
        fk = d / 6 + 1.0162 + 1.0653 / d - 2.1354 / d**2
        assert float(poiseuille_flow_rate(d)) == pytest.approx(fk, rel=1e-2)
    # 0.15 <= D < 5 branch of the same formula
    for d in (0.2, 0.5, 2.0):
        fk = 0.13852 * d + 1.25087 + 0.15653 / d - 0.00969 / d**2
        assert float(poiseuille_flow_rate(d)) == pytest.approx(fk, rel=1e-2)


def test_free_molecular_asymptote_of_the_infinite_slit():
    """δ → 0: G_P = −ln(δ)/√π + 3(1 − γ)/(2√π) + o(1) (Cercignani): unbounded, logarithmic."""
    const = 1.5 * (1 - np.euler_gamma) / SQRT_PI
    gaps = [abs(float(poiseuille_flow_rate(d)) - (-math.log(d) / SQRT_PI + const)) for d in (1e-3, 1e-5, 1e-8)]
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 1e-4
    assert math.isinf(float(poiseuille_flow_rate(0.0)))


def test_knudsen_minimum_and_shape():
    """One minimum near δ = 1 (the Knudsen minimum); decreasing below it, increasing above it; G_P
    continuous across the ends of the table."""
    d_min, g_min = knudsen_minimum()
    assert 0.5 < d_min < 2.0 and g_min == pytest.approx(1.5389, rel=2e-3)
    lo = poiseuille_flow_rate(np.logspace(-10, math.log10(d_min) - 0.01, 400))
    hi = poiseuille_flow_rate(np.logspace(math.log10(d_min) + 0.01, 6, 400))
    assert np.all(np.diff(lo) < 0) and np.all(np.diff(hi) > 0)
    for edge in (1e-4, 10**1.7):
        below, above = poiseuille_flow_rate([edge * (1 - 1e-9), edge * (1 + 1e-9)])
        assert below == pytest.approx(above, rel=1e-6)


def test_slip_factor_limits():
    """f = 6 G_P/δ with δ = (√π/2)/Kn: f → 1 for Kn → 0 (the no-slip conductance), first-order slip
    f = 1 + (12 σ_P/√π) Kn for small Kn, increasing in Kn, infinite at Kn = ∞."""
    assert float(slip_factor(0.0)) == 1.0
    assert float(slip_factor(1e-9)) == pytest.approx(1.0, abs=1e-7)
    for kn in (1e-4, 1e-3):
        assert (float(slip_factor(kn)) - 1) / kn == pytest.approx(12 * SIGMA_P / SQRT_PI, rel=0.02)
    kn = np.logspace(-6, 8, 300)
    f = slip_factor(kn)
    assert np.all(np.diff(f) > 0) and np.all(f >= 1) and math.isinf(float(slip_factor(math.inf)))
    assert np.all(np.diff(slip_factor(kn, length_ratio=100.0)) > 0)


@pytest.mark.parametrize("kn, ratio", [(0.1, 0.96), (1.0, 0.82), (10.0, 0.63)])
def test_beskok_karniadakis_against_kinetic(kn, ratio):
    """B&K/kinetic ≈ 0.96, 0.82, 0.63 at Kn = 0.1, 1, 10 (the comparison in docs/theory.md §11.4)."""
    assert float(slip_factor(kn, "beskok-karniadakis") / slip_factor(kn)) == pytest.approx(ratio, rel=0.03)


def test_finite_length_free_molecular_flow():
    """A slot of length ℓ h: G_fm = ℓ W/√π grows like ln(ℓ)/√π; the cap δ_ℓ makes G_P(δ_ℓ) = G_fm(ℓ),
    shrinking as the slot gets longer, at the Knudsen minimum for a slot too short to reach it."""
    g = [finite_slit_free_molecular(ell) for ell in (10.0, 100.0, 1000.0, 1e4)]
    slopes = np.diff(g) * SQRT_PI / math.log(10.0)
    assert np.all(slopes == pytest.approx(1.0, abs=0.1))
    # short slot: W → 1 − ℓ/2 + ... for ℓ → 0 (the direct flight √(1 + ℓ²) − ℓ and more), W(1) = 0.684
    assert finite_slit_free_molecular(1.0) * SQRT_PI == pytest.approx(0.684, rel=2e-3)
    caps = [capped_rarefaction(ell) for ell in (30.0, 100.0, 1000.0)]
    assert caps[0] > caps[1] > caps[2]
    for ell, cap in zip((30.0, 100.0, 1000.0), caps):
        assert float(poiseuille_flow_rate(cap)) == pytest.approx(finite_slit_free_molecular(ell), rel=1e-9)
    assert finite_slit_free_molecular(10.0) < knudsen_minimum()[1]
    assert capped_rarefaction(10.0) == knudsen_minimum()[0]


def test_cap_bounds_the_free_molecular_leak(helium):
    """Against vacuum with Kn ≫ L/h the capped leak is linear in ΔP with G_fm(ℓ) h² v0/2 per unit width
    and W/L: Q_pV = K (12/√π) G_fm c ΔP; the infinite slit passes more and without that bound."""
    gap, ell = 1e-9, 50.0
    c = helium.rarefaction_pressure_scale / gap
    expected = 12 / SQRT_PI * finite_slit_free_molecular(ell) * c  # G_fm(ℓ), the slit's own free-molecular bound
    for pa in (1e-2, 1e-4):
        capped = pressure_integral(gap, helium, pa, 0.0, length=ell * gap)
        assert capped == pytest.approx(expected * pa, rel=1e-6)
        assert pressure_integral(gap, helium, pa, 0.0) > capped


def test_kinetic_leak_exceeds_beskok_karniadakis_and_reduces_to_no_slip(helium):
    """More flow than B&K in the transition regime, the no-slip leak in the continuum limit."""
    k = 1e-20
    for gap in (1e-7, 1e-6):
        kin = gas_leak(k, gap, helium, 1e5, 0.0, length=100 * gap)
        bk = gas_leak(k, gap, helium, 1e5, 0.0, "beskok-karniadakis")
        assert kin.throughput > bk.throughput > kin.throughput_no_slip
    wide = gas_leak(k, 1e-2, helium, 2e5, 1e5)
    assert wide.throughput == pytest.approx(wide.throughput_no_slip, rel=1e-4, abs=0)


def test_caps_of_many_lengths_at_once():
    """The array form of the cap, as a gas sheet takes it at ~240 lengths: G_P(δ_ℓ) = G_fm(ℓ) on the free-molecular
    side of the minimum, short slots at the minimum, longer slots lower, and past the G_fm table (ℓ > 500) too."""
    ell = np.concatenate([[1.0, 5.0, 10.0], np.geomspace(20.0, 1e6, 40)])
    caps = capped_rarefactions(ell)
    g_fm = np.array([finite_slit_free_molecular(e) for e in ell])
    delta_min, g_min = knudsen_minimum()
    short = g_fm <= g_min
    assert short[:3].all() and not short[3:].any()
    assert np.all(caps[short] == delta_min)
    assert np.all(caps[~short] < delta_min) and np.all(np.diff(caps[~short]) < 0)
    assert poiseuille_flow_rate(caps[~short]) == pytest.approx(g_fm[~short], rel=1e-9, abs=0)
    assert caps[10] == capped_rarefaction(float(ell[10]))


def test_flow_rate_at_one_point_matches_the_array_form_and_its_asymptotes():
    """The plain-float G_P an ODE calls: the array function's numbers inside the table and on both asymptotes
    (the slip side δ > 50, the free-molecular side δ < 1e-4), G_P(0) = inf."""
    delta = np.geomspace(1e-9, 1e4, 301)
    one = np.array([poiseuille_flow_rate_at(float(d)) for d in delta])
    assert one == pytest.approx(poiseuille_flow_rate(delta), rel=1e-14, abs=0)
    assert poiseuille_flow_rate_at(1e4) == pytest.approx(1e4 / 6 + SIGMA_P, rel=1e-6, abs=0)
    assert poiseuille_flow_rate_at(1e-9) == pytest.approx(-math.log(1e-9) / SQRT_PI + 0.3578, rel=1e-4, abs=0)
    assert poiseuille_flow_rate_at(0.0) == math.inf
