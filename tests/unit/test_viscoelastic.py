"""The seal over its life (docs/theory.md §16): Prony series, creep compliance, master curve, shift factors,
thermal contraction, glass transition, compression set."""

import math
import warnings

import numpy as np
import pytest
from scipy.constants import R
from scipy.integrate import quad

from sealeak.errors import InputError
from sealeak.physics.viscoelastic import (
    GLASS_MARGIN,
    MAX_TERMS,
    UNIVERSAL_WLF_C1,
    UNIVERSAL_WLF_C2,
    ArrheniusShift,
    CompressionSet,
    MasterCurve,
    PronySeries,
    WLFShift,
    fit_compression_set,
    glass_transition_warnings,
    modulus_at,
    remaining_compression,
    thermal_compression,
    universal_wlf_glass_transition,
)

E_INF, E1, TAU = 4e6, 3e6, 10.0


def one_term() -> PronySeries:
    return PronySeries(E_INF, [E1], [TAU], field="rubber.relaxation")


def three_terms() -> PronySeries:
    return PronySeries(4e6, [2e6, 1e6, 5e5], [1e-3, 10.0, 1e4], field="rubber.relaxation")


# --- Prony series --------------------------------------------------------------------------------------------


def test_one_term_relaxation_modulus_is_the_closed_form():
    p = one_term()
    t = np.array([0.0, 1.0, TAU, 5 * TAU, 1e6])
    expected = [E_INF + E1 * math.exp(-x / TAU) for x in t]
    assert p.relaxation_modulus(t) == pytest.approx(expected, rel=1e-14)
    assert p.instantaneous_modulus == E_INF + E1
    assert p.relaxation_modulus(TAU) == pytest.approx(E_INF + E1 / math.e, rel=1e-14)


def test_standard_linear_solid_creep_compliance_is_its_closed_form():
    """J(t) = 1/E∞ − (1/E∞ − 1/E0) exp(−t E∞/(E0 τ)): retardation is slower than relaxation by E0/E∞."""
    p = one_term()
    e0 = E_INF + E1
    t = np.geomspace(1e-3, 1e4, 40)
    expected = 1 / E_INF - (1 / E_INF - 1 / e0) * np.exp(-t * E_INF / (e0 * TAU))
    assert p.creep_compliance(t) == pytest.approx(expected, rel=1e-12, abs=0)
    _, lam = p.retardation()
    assert lam == pytest.approx([TAU * e0 / E_INF], rel=1e-12)


@pytest.mark.parametrize("t", [1e-4, 1e-2, 3.0, 100.0, 5e4])
def test_creep_compliance_satisfies_the_convolution_identity(t):
    """∫₀ᵗ E(t − s) J(s) ds = t (eq. 16.3), and its derivative E(t) J(0) + ∫₀ᵗ E(t − s) J'(s) ds = 1, by quadrature."""
    p = three_terms()
    weights, lam = p.retardation()
    ends = np.geomspace(1e-6, t, 40)[:-1]  # E(t − s) changes fast near s = t, J(s) near s = 0
    options = {"points": np.concatenate([ends, t - ends]), "limit": 400, "epsabs": 0, "epsrel": 1e-11}
    integral, _ = quad(lambda s: float(p.relaxation_modulus(t - s) * p.creep_compliance(s)), 0.0, t, **options)
    assert integral == pytest.approx(t, rel=1e-8)
    rate, _ = quad(lambda s: float(p.relaxation_modulus(t - s)) * float(np.sum(weights / lam * np.exp(-s / lam))),
                   0.0, t, **options)
    assert float(p.relaxation_modulus(t) * p.creep_compliance(0.0)) + rate == pytest.approx(1.0, rel=1e-8)


def test_creep_compliance_limits_and_monotony():
    p = three_terms()
    assert float(p.creep_compliance(0.0)) == pytest.approx(1 / p.instantaneous_modulus, rel=1e-12, abs=0)
    assert float(p.creep_compliance(1e12)) == pytest.approx(1 / p.equilibrium_modulus, rel=1e-12, abs=0)
    j = p.creep_compliance(np.geomspace(1e-6, 1e8, 300))
    assert np.all(np.diff(j) >= 0)
    _, lam = p.retardation()
    # retardation times interlace with the relaxation times (each λj beyond its τj)
    assert np.all(np.sort(lam) > np.array(p.times))


def test_widely_spread_and_unequal_terms_keep_the_limits():
    p = PronySeries(1e6, [1e9, 1e3, 5e7, 2e5], [1e-9, 3e-9, 1.0, 1e9])
    assert float(p.creep_compliance(0.0)) == pytest.approx(1 / p.instantaneous_modulus, rel=1e-9, abs=0)
    assert float(p.creep_compliance(1e15)) == pytest.approx(1 / p.equilibrium_modulus, rel=1e-9, abs=0)


def test_storage_and_loss_modulus():
    p = one_term()
    assert float(p.storage_modulus(0.0)) == E_INF
    assert float(p.storage_modulus(1e12)) == pytest.approx(E_INF + E1, rel=1e-9)
    assert float(p.loss_modulus(1 / TAU)) == pytest.approx(E1 / 2, rel=1e-14)  # the loss peak at ωτ = 1
    w = np.geomspace(1e-4, 1e2, 601)
    assert w[np.argmax(p.loss_modulus(w))] == pytest.approx(1 / TAU, rel=0.03)
    assert np.all(np.diff(p.storage_modulus(w)) > 0)


@pytest.mark.parametrize("args, field", [
    ((0.0, [1e6], [1.0]), "rubber.relaxation.equilibrium_modulus"),
    ((1e6, [1e6, -1.0], [1.0, 2.0]), "rubber.relaxation.moduli[1]"),
    ((1e6, [1e6, 1e6], [1.0]), "rubber.relaxation.times"),
    ((1e6, [1e6, 1e6], [5.0, 5.0]), "rubber.relaxation.times"),
    ((1e6, [1e6], [0.0]), "rubber.relaxation.times[0]"),
    ((1e6, [float("nan")], [1.0]), "rubber.relaxation.moduli[0]"),
    ((1e6, "2 MPa", [1.0]), "rubber.relaxation.moduli"),
    ((1e6, None, [1.0]), "rubber.relaxation.moduli"),
    ((1e6, [1e6], [[1.0, 2.0], [3.0]]), "rubber.relaxation.times"),
    ((1e6, [1e6], "10"), "rubber.relaxation.times"),
    ((1e6, [1e6] * (MAX_TERMS + 1), list(range(1, MAX_TERMS + 2))), "rubber.relaxation.moduli"),
])
def test_prony_series_refuses_bad_input_naming_the_field(args, field):
    with pytest.raises(InputError) as err:
        PronySeries(*args, field="rubber.relaxation")
    assert err.value.field == field


# --- master curve --------------------------------------------------------------------------------------------


def test_master_curve_goes_through_its_points_and_keeps_a_power_law():
    t = np.geomspace(1e-2, 1e6, 9)
    e = 5e6 * t ** -0.08
    curve = MasterCurve(tuple(t), tuple(e))
    assert curve.relaxation_modulus(t) == pytest.approx(e, rel=1e-12)
    between = np.geomspace(2e-2, 5e5, 50)
    assert curve.relaxation_modulus(between) == pytest.approx(5e6 * between ** -0.08, rel=1e-10)
    assert float(curve.relaxation_modulus(1e-9)) == pytest.approx(e[0]) and float(curve.relaxation_modulus(1e12)) == pytest.approx(e[-1])


def test_master_curve_stays_monotone_between_steep_points():
    curve = MasterCurve((1.0, 10.0, 100.0, 1e3), (1e9, 1e8, 5e6, 4.9e6))
    e = curve.relaxation_modulus(np.geomspace(1.0, 1e3, 500))
    assert np.all(np.diff(e) <= 1e-9 * e[:-1])


@pytest.mark.parametrize("times, moduli, field", [
    ((1.0, 10.0, 100.0), (5e6, 6e6, 4e6), "relaxation.master_curve.modulus[1]"),
    ((1.0, 10.0, 10.0), (5e6, 4e6, 3e6), "relaxation.master_curve.time[2]"),
    ((0.0, 10.0), (5e6, 4e6), "relaxation.master_curve.time[0]"),
    ((1.0, 10.0), (5e6, -4e6), "relaxation.master_curve.modulus[1]"),
    ((1.0,), (5e6,), "relaxation.master_curve.time"),
    ((1.0, 2.0), (5e6,), "relaxation.master_curve.modulus"),
])
def test_master_curve_refuses_bad_data(times, moduli, field):
    with pytest.raises(InputError) as err:
        MasterCurve(times, moduli, field="relaxation.master_curve")
    assert err.value.field == field


def test_a_master_curve_sampled_from_a_prony_series_has_its_creep_compliance():
    """J(t) of the Prony series fitted to the curve (§16.3) is the exact J (eq. 16.5) of the series it was sampled
    from, to the fit's 1 %, from the glassy 1/E(0) to the rubbery 1/E∞."""
    p = PronySeries(4e6, [3e7, 2e6, 1e6, 5e5], [1e-6, 1e-3, 10.0, 1e4])
    t = np.geomspace(1e-9, 1e8, 69)
    curve = MasterCurve(tuple(t), tuple(p.relaxation_modulus(t)))
    at = np.geomspace(1e-10, 1e10, 201)
    assert curve.creep_compliance(at) == pytest.approx(p.creep_compliance(at), rel=1e-2)
    assert curve.prony.relaxation_modulus(at) == pytest.approx(p.relaxation_modulus(at), rel=1e-2)
    assert float(curve.creep_compliance(1e10)) == pytest.approx(1 / p.equilibrium_modulus, rel=1e-3)


def test_a_master_curve_that_does_not_relax_creeps_not_at_all():
    """A flat curve (an elastic rubber measured as a master curve) has J = 1/E at every time; one that relaxes only
    beyond a Prony series' times (10¹⁵ s) keeps its short-time modulus at every time one can ask for."""
    flat = MasterCurve((1.0, 1e6), (5e6, 5e6))
    assert flat.prony is None
    assert flat.creep_compliance([0.0, 10.0, 1e9]) == pytest.approx([2e-7] * 3, rel=1e-12, abs=0)
    late = MasterCurve((1e20, 1e25), (5e9, 1e6))
    assert late.creep_compliance([0.0, 3.15e8]) == pytest.approx([2e-10] * 2, rel=1e-12, abs=0)


# --- shift factors -------------------------------------------------------------------------------------------


def test_wlf_shift_is_its_closed_form():
    tref, c1, c2 = 263.15, 9.5, 80.0
    wlf = WLFShift(tref, c1, c2)
    for temp in (tref - 50, tref - 10, tref, tref + 40, tref + 120):
        expected = -c1 * (temp - tref) / (c2 + temp - tref)
        assert float(wlf.log10_shift(temp)) == pytest.approx(expected, rel=1e-14, abs=1e-15)
    assert float(wlf.shift(tref)) == 1.0
    assert float(wlf.shift(tref - 20)) > 1 > float(wlf.shift(tref + 20))  # colder: slower


def test_wlf_refuses_the_divergence():
    wlf = WLFShift(293.15, 17.44, 51.6)
    with pytest.raises(InputError, match="WLF shift diverges") as err:
        wlf.log10_shift([300.0, 293.15 - 51.6 - 1.0], field="conditions.temperature")
    assert err.value.field == "conditions.temperature"
    with pytest.raises(InputError):
        WLFShift(293.15, -1.0, 51.6)


def test_wlf_shift_between_two_temperatures_does_not_depend_on_the_reference():
    """Referred to T' = Tg + 30 K, C1' = C1 C2/(C2 + 30), C2' = C2 + 30 (Ferry): the same shifts, the same Tg estimate."""
    tg = 250.0
    at_tg = WLFShift(tg, UNIVERSAL_WLF_C1, UNIVERSAL_WLF_C2)
    moved = WLFShift(tg + 30, UNIVERSAL_WLF_C1 * UNIVERSAL_WLF_C2 / (UNIVERSAL_WLF_C2 + 30), UNIVERSAL_WLF_C2 + 30)
    t1, t2 = 260.0, 330.0
    assert float(at_tg.log10_shift(t2) - at_tg.log10_shift(t1)) == pytest.approx(
        float(moved.log10_shift(t2) - moved.log10_shift(t1)), rel=1e-12)
    assert universal_wlf_glass_transition(at_tg) == pytest.approx(tg)
    assert universal_wlf_glass_transition(moved) == pytest.approx(tg)


def test_arrhenius_shift_is_its_closed_form():
    tref, ea = 293.15, 90e3
    shift = ArrheniusShift(tref, ea)
    for temp in (233.15, 293.15, 373.15):
        assert float(np.log(shift.shift(temp))) == pytest.approx(ea / R * (1 / temp - 1 / tref), rel=1e-12, abs=1e-15)
    assert float(shift.shift(tref)) == 1.0
    with pytest.raises(InputError):
        shift.log10_shift(0.0)


def test_modulus_at_a_temperature_is_the_shifted_time():
    p = three_terms()
    wlf = WLFShift(293.15, 8.0, 120.0)
    t = np.array([1.0, 100.0, 1e5])
    cold, ref, hot = (modulus_at(p, t, temp, wlf) for temp in (253.15, 293.15, 353.15))
    assert ref == pytest.approx(p.relaxation_modulus(t), rel=1e-14)
    assert cold == pytest.approx(p.relaxation_modulus(t / float(wlf.shift(253.15))), rel=1e-14)
    assert np.all(cold >= ref) and np.all(ref >= hot) and np.any(cold > hot)  # colder is stiffer at the same time
    assert modulus_at(p, t, 253.15) == pytest.approx(p.relaxation_modulus(t))


def test_a_master_curve_shifts_like_a_prony_series():
    """One decade of a_T moves a power-law master curve E = A t^−n by a factor 10^n at every time."""
    n = 0.1
    t = np.geomspace(1e-3, 1e9, 13)
    curve = MasterCurve(tuple(t), tuple(8e6 * t ** -n))
    shift = ArrheniusShift(293.15, 60e3)
    cold = 273.15
    decades = float(shift.log10_shift(cold))
    at = np.array([1.0, 60.0, 3600.0])
    assert modulus_at(curve, at, cold, shift) == pytest.approx(curve.relaxation_modulus(at) * 10 ** (n * decades), rel=1e-10)


# --- thermal contraction and the glass transition ------------------------------------------------------------


def test_thermal_compression_is_one_minus_gland_depth_over_cord():
    d0, h0, ta = 3.53e-3, 2.8e-3, 293.15
    a_r, a_g = 23e-5, 1.2e-5
    for temp in (233.15, 293.15, 373.15):
        d = d0 * (1 + a_r * (temp - ta))
        h = h0 * (1 + a_g * (temp - ta))
        assert float(thermal_compression(1 - h0 / d0, temp, ta, a_r, a_g)) == pytest.approx(1 - h / d, rel=1e-12, abs=0)


def test_colder_squeezes_less_when_the_rubber_shrinks_more_than_the_gland():
    eps = thermal_compression(0.2, [233.15, 273.15, 293.15, 333.15, 373.15], 293.15, 23e-5, 1.2e-5)
    assert np.all(np.diff(eps) > 0) and float(eps[2]) == pytest.approx(0.2, rel=1e-14, abs=0)
    same = thermal_compression(0.2, [233.15, 373.15], 293.15, 5e-5, 5e-5)
    assert same == pytest.approx([0.2, 0.2], rel=1e-12, abs=0)
    # an aluminium gland (2.3e-5 1/K) around a cord that shrinks less loses squeeze when hot
    assert float(thermal_compression(0.2, 373.15, 293.15, 1e-5, 2.3e-5)) < 0.2


@pytest.mark.parametrize("kwargs, field", [
    ({"compression": 1.2}, "compression"),
    ({"temperature": -5.0}, "temperature"),
    ({"rubber_expansion": 0.5}, "rubber_expansion"),
    ({"assembly_temperature": 0.0}, "assembly_temperature"),
    ({"gland_expansion": "steel"}, "gland_expansion"),
    ({"temperature": None}, "temperature"),
])
def test_thermal_compression_refuses_bad_input(kwargs, field):
    args = {"compression": 0.2, "temperature": 250.0, "assembly_temperature": 293.15, "rubber_expansion": 2e-4,
            "gland_expansion": 1e-5} | kwargs
    with pytest.raises(InputError) as err:
        thermal_compression(**args)
    assert err.value.field == field


def test_glass_transition_warnings():
    tg = 243.15
    assert "below the glass transition" in glass_transition_warnings(tg - 5, tg)[0]
    near = glass_transition_warnings(tg + GLASS_MARGIN / 2, tg, estimated=True)
    assert "within" in near[0] and "estimated" in near[0]
    assert glass_transition_warnings(tg + GLASS_MARGIN + 1, tg) == ()


# --- ageing: compression set ---------------------------------------------------------------------------------


TRUE = CompressionSet(time_constant=3e8, exponent=0.45, activation_energy=85e3, reference_temperature=293.15)


def synthetic_points():
    temps = np.repeat([343.15, 373.15, 398.15], 5)
    times = np.tile(np.array([1, 3, 7, 14, 42]) * 86400.0, 3)
    return times, temps, TRUE(times, temps)


def test_ageing_fit_recovers_the_parameters_of_exact_data():
    fit = fit_compression_set(*synthetic_points())
    assert fit.time_constant == pytest.approx(TRUE.time_constant, rel=1e-6)
    assert fit.exponent == pytest.approx(TRUE.exponent, rel=1e-6)
    assert fit.activation_energy == pytest.approx(TRUE.activation_energy, rel=1e-6)
    assert fit.rms_residual < 1e-9


def test_ageing_fit_of_noisy_data_is_close():
    times, temps, sets = synthetic_points()
    noisy = sets + np.random.default_rng(7).normal(0, 0.005, sets.size)
    fit = fit_compression_set(times, temps, noisy)
    assert fit.exponent == pytest.approx(TRUE.exponent, rel=0.15)
    assert fit.activation_energy == pytest.approx(TRUE.activation_energy, rel=0.15)
    assert 0.002 < fit.rms_residual < 0.01


def test_compression_set_follows_iso_11346_arrhenius_lifetimes():
    """The time to reach a given set (the lifetime) is a straight line in ln t against 1/T of slope Ea/R."""
    c_end = 0.5
    temps = np.array([313.15, 343.15, 373.15])
    life = TRUE.time_scale(temps) * (-math.log(1 - c_end)) ** (1 / TRUE.exponent)
    assert TRUE(life, temps) == pytest.approx([c_end] * 3, rel=1e-12, abs=0)
    slope = np.polyfit(1 / temps, np.log(life), 1)[0]
    assert slope == pytest.approx(TRUE.activation_energy / R, rel=1e-10)
    assert float(TRUE(0.0, 300.0)) == 0.0 and float(TRUE(1e30, 300.0)) == pytest.approx(1.0)


def test_remaining_compression():
    assert remaining_compression([0.2, 0.25], [0.0, 0.4]) == pytest.approx([0.2, 0.15])


@pytest.mark.parametrize("times, temps, sets, field", [
    ([1e5, 1e6, 1e7], [373.15] * 3, [0.1, 0.2, 0.3], "compression_set.temperatures"),
    ([1e5, 1e6, 1e7], [343.15, 373.15, 373.15], [0.1, 20.0, 0.3], "compression_set.sets[1]"),
    ([1e5, -1.0, 1e7], [343.15, 373.15, 373.15], [0.1, 0.2, 0.3], "compression_set.times[1]"),
    ([1e5, 1e6], [343.15, 373.15, 373.15], [0.1, 0.2, 0.3], "compression_set.sets"),
    # sets that grow as the temperature falls (the nbr-o-ring-life example's points with its temperatures reversed):
    # no activation energy > 0 fits them; the fit ran off to an Ea < 0 and a τ that overflowed later, or at once
    ([70 * 3600.0, 1000 * 3600.0, 1000 * 3600.0, 3.156e7, 3.156e7], [296.15, 343.15, 343.15, 373.15, 373.15],
     [0.15, 0.42, 0.2, 0.4, 0.08], "compression_set.sets"),
    ([70 * 3600.0, 1000 * 3600.0, 1000 * 3600.0, 3.156e7, 3.156e7], [373.15, 273.15, 343.15, 343.15, 296.15],
     [0.15, 0.42, 0.2, 0.4, 0.08], "compression_set.sets"),
])
def test_ageing_fit_refuses_bad_points(times, temps, sets, field):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (no overflow warning on the way)
        with pytest.raises(InputError) as err:
            fit_compression_set(times, temps, sets)
    assert err.value.field == field
