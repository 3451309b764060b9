"""Gases: properties from the property library, compressible isothermal flow and rarefaction (docs/theory.md §Gases and leak tests)."""

import math

import numpy as np
import pytest

from sealeak.errors import InputError
from sealeak.physics.gas import (
    BK_ALPHA0,
    MOLAR_GAS_CONSTANT,
    Gas,
    check_pressures,
    flow_regime,
    free_molecular_coefficient,
    gas_leak,
    pressure_integral,
    sheet_conductance,
    slip_factor,
    viscous_mass_flow,
    viscous_throughput,
)
from sealeak.physics.properties import KNOWN_FLUIDS, canonical_fluid_name, fluid_state, vapour_pressure_note

T20 = 293.15
T25 = 298.15

BK = "beskok-karniadakis"


def slit_conductance(gas, gap, aspect=10.0):
    """No-slip conductance K = (W/L) h³/(12μ) of a slit of height ``gap`` (m³/(Pa·s))."""
    return aspect * gap**3 / (12.0 * gas.viscosity)


@pytest.fixture(scope="module")
def helium():
    return fluid_state("helium", T20, 1e5).gas()


@pytest.fixture(scope="module")
def air():
    return fluid_state("air", T20, 1e5).gas()


# ---------------------------------------------------------------------- properties against reference data
# Reference viscosities (µPa·s) at 1 bar: the values at 20 °C (3 digits); helium at 25 °C from
# ab initio theory (Hurly & Moldover 2000: 19.8253 µPa·s); argon at 25 °C from the measured ratio
# η_Ar/η_He = 1.13800 (May, Moldover, Berg & Hurly 2006) times that helium value; water from the CRC
# Handbook (Kestin et al.), 1.002 mPa·s at 20 °C and 0.354 mPa·s at 80 °C. Tolerance 1 %: the stated
# uncertainty of the library's correlations is at least that (Lemmon & Jacobsen 2004: 2 % for N2 and Ar;
# IAPWS 2008 for liquid water at 0.1 MPa: 1 %), and the 3-digit reference values are rounded by < 0.3 %.
@pytest.mark.parametrize("name, temperature, reference", [
    ("helium", T20, 19.6e-6),
    ("air", T20, 18.2e-6),
    ("nitrogen", T20, 17.6e-6),
    ("helium", T25, 19.8253e-6),
    ("argon", T25, 1.13800 * 19.8253e-6),
    ("water", T20, 1.002e-3),
    ("water", 353.15, 0.354e-3),
])
def test_viscosity_matches_reference_data(name, temperature, reference):
    state = fluid_state(name, temperature, 1e5)
    assert state.viscosity == pytest.approx(reference, rel=0.01)


@pytest.mark.parametrize("name, molar_mass", [("helium", 4.002602e-3), ("nitrogen", 28.0134e-3), ("argon", 39.948e-3),
                                              ("carbon dioxide", 44.0095e-3), ("water", 18.01528e-3)])
def test_molar_mass_is_the_iupac_value(name, molar_mass):
    assert fluid_state(name, T20).molar_mass == pytest.approx(molar_mass, rel=2e-4)


def test_water_viscosity_falls_with_temperature_and_gas_viscosity_rises():
    water = [fluid_state("water", t, 1e5).viscosity for t in (283.15, 313.15, 353.15)]
    helium = [fluid_state("helium", t, 1e5).viscosity for t in (250.0, 300.0, 400.0)]
    assert water[0] > water[1] > water[2] and helium[0] < helium[1] < helium[2]


def test_a_dilute_gas_viscosity_does_not_depend_on_pressure():
    """Maxwell: μ of a dilute gas is independent of p (why one μ serves the whole pressure drop)."""
    mus = [fluid_state("nitrogen", T20, p).viscosity for p in (100.0, 1e4, 1e5, 3e5)]
    assert max(mus) / min(mus) - 1 < 0.005


@pytest.mark.parametrize("name, pressure, phase", [("water", 1e5, "liquid"), ("helium", 1e5, "gas"), ("R134a", 1e5, "gas"),
                                                   ("R134a", 10e5, "liquid"), ("carbon dioxide", 1e5, "gas")])
def test_phase_at_room_temperature(name, pressure, phase):
    """R134a boils at 5.7 bar at 20 °C: a gas at 1 bar, a liquid at 10 bar."""
    state = fluid_state(name, T20, pressure)
    assert state.phase == phase and state.is_gas == (phase == "gas")


def test_light_gases_are_ideal_at_one_bar():
    for name in ("helium", "nitrogen", "air", "argon"):
        assert fluid_state(name, T20, 1e5).compressibility == pytest.approx(1.0, abs=1e-3)


def test_vapour_pressure_of_water_and_the_boiling_warning():
    water = fluid_state("water", T20, 1e5)
    assert water.vapour_pressure == pytest.approx(2339.0, rel=2e-3)  # 2.339 kPa at 20 °C (IAPWS-95 tables)
    note = vapour_pressure_note(water, 1e5, 1000.0)
    assert note is not None and "vapour pressure" in note and "water" in note
    assert vapour_pressure_note(water, 1e5, 5000.0) is None
    assert vapour_pressure_note(fluid_state("helium", T20, 1e5), 1e5, 0.0) is None


@pytest.mark.parametrize("spelling, name", [("He", "helium"), ("HELIUM", "helium"), ("CO2", "carbon dioxide"),
                                            ("carbon_dioxide", "carbon dioxide"), ("R-134a", "R134a"), ("r1234yf", "R1234yf"),
                                            ("H2O", "water"), ("N2", "nitrogen"), ("R744", "carbon dioxide")])
def test_names_and_aliases(spelling, name):
    assert canonical_fluid_name(spelling) == name


@pytest.mark.parametrize("bad", ["xenon", "unobtainium", "", "  ", None, 3])
def test_unknown_fluid_is_refused_listing_the_known_names(bad):
    with pytest.raises(InputError) as exc:
        fluid_state(bad, T20)
    assert exc.value.field == "fluid"
    text = str(exc.value)
    assert all(name in text for name in ("helium", "nitrogen", "R134a", "water"))


@pytest.mark.parametrize("oil", ["oil", "ISO VG 46", "hydraulic oil", "silicone oil", "SAE 30"])
def test_an_oil_asks_for_its_viscosity(oil):
    with pytest.raises(InputError, match="fluid.viscosity") as exc:
        fluid_state(oil, T20)
    assert exc.value.field == "fluid"


@pytest.mark.parametrize("temperature", [20.0, 0.0, -5.0, math.nan, math.inf, "hot"])
def test_temperature_not_absolute_or_outside_the_correlation_is_refused(temperature):
    """20 (a Celsius number taken as K) is below water's triple point: refused, naming the range."""
    with pytest.raises(InputError) as exc:
        fluid_state("water", temperature, 1e5)
    assert exc.value.field == "temperature"


@pytest.mark.parametrize("pressure", [0.0, -1e5, math.nan, 1e12])
def test_pressure_of_a_state_must_be_absolute_and_in_range(pressure):
    with pytest.raises(InputError) as exc:
        fluid_state("helium", T20, pressure)
    assert exc.value.field == "pressure"


def test_a_liquid_is_not_a_gas():
    with pytest.raises(InputError, match="liquid") as exc:
        fluid_state("water", T20, 1e5).gas()
    assert exc.value.field == "fluid"


def test_every_known_fluid_has_properties_at_room_temperature():
    for name in KNOWN_FLUIDS:
        state = fluid_state(name, T20, 1e5)
        assert state.viscosity > 0 and state.density > 0 and state.source.startswith("CoolProp")


# ---------------------------------------------------------------------- ideal gas, mean free path, Knudsen number
def test_mean_free_path_of_air_by_hand():
    """λ = (μ/p) √(π R_s T/2) for air at 20 °C, 1 bar: μ = 18.2 µPa·s, R_s = 8.314462618/0.0289647 = 287.05 J/(kg K)
    → √(π·287.05·293.15/2) = 363.57 m/s → λ = 1.82e-10 m·s · 363.57 m/s = 66.2 nm (the issue's ≈ 70 nm)."""
    gas = Gas("air", T20, 18.2e-6, 0.0289647)
    assert gas.specific_gas_constant == pytest.approx(287.05, rel=1e-4)
    assert float(gas.mean_free_path(1e5)) == pytest.approx(66.17e-9, rel=1e-3)
    assert float(gas.knudsen_number(100e-9, 1e5)) == pytest.approx(0.6617, rel=1e-3)
    assert float(gas.mean_free_path(1e3)) == pytest.approx(100 * float(gas.mean_free_path(1e5)), rel=1e-12, abs=0)


def test_mean_free_path_is_longer_for_helium_and_at_low_pressure(helium, air):
    assert helium.mean_free_path(1e5) > 2.5 * air.mean_free_path(1e5)
    assert math.isinf(float(helium.mean_free_path(0.0)))


def test_mean_thermal_speed_of_helium_by_hand(helium):
    """v̄ = √(8RT/(πM)) = √(8·8.314462618·293.15/(π·0.004002602)) = √(19498.8/0.0125745) = 1245.26 m/s."""
    assert helium.mean_thermal_speed == pytest.approx(1245.26, rel=1e-5)


@pytest.mark.parametrize("field, kwargs", [
    ("temperature", {"temperature": -1.0}), ("temperature", {"temperature": 0.5}), ("viscosity", {"viscosity": 0.0}),
    ("molar_mass", {"molar_mass": 4.0}), ("molar_mass", {"molar_mass": math.nan}),
])
def test_gas_refuses_values_outside_si_ranges(field, kwargs):
    args = {"name": "x", "temperature": T20, "viscosity": 2e-5, "molar_mass": 0.004} | kwargs
    with pytest.raises(InputError) as exc:
        Gas(**args)
    assert exc.value.field == field


@pytest.mark.parametrize("kn, regime", [(1e-5, "continuum"), (0.01, "slip"), (1.0, "transition"), (100.0, "free molecular"),
                                        (math.inf, "free molecular")])
def test_flow_regime(kn, regime):
    assert flow_regime(kn) == regime


# ---------------------------------------------------------------------- pressures
@pytest.mark.parametrize("upstream, downstream, field", [
    (-1e5, 0.0, "upstream_pressure"), (0.0, 0.0, "upstream_pressure"), (1e5, -1.0, "downstream_pressure"),
    (math.nan, 0.0, "upstream_pressure"), (1e5, math.inf, "downstream_pressure"), (1e5, 2e5, "upstream_pressure"),
    ("1 bar", 0.0, "upstream_pressure"),
])
def test_bad_absolute_pressures_name_the_field(upstream, downstream, field, helium):
    for call in (lambda: check_pressures(upstream, downstream), lambda: viscous_throughput(1e-18, upstream, downstream),
                 lambda: gas_leak(1e-18, 1e-7, helium, upstream, downstream)):
        with pytest.raises(InputError) as exc:
            call()
        assert exc.value.field == field


def test_equal_pressures_give_no_flow(helium):
    assert gas_leak(1e-18, 1e-7, helium, 1e5, 1e5).throughput == 0.0


# ---------------------------------------------------------------------- compressible viscous flow
def test_viscous_throughput_and_mass_flow_by_hand(helium):
    """K = 1e-18 m³/(Pa s), 3 bar → 1 bar: Q = 1e-18·(9e10 − 1e10)/2 = 4e-8 Pa m³/s; ṁ = Q M/(R T)."""
    q = float(viscous_throughput(1e-18, 3e5, 1e5))
    assert q == pytest.approx(4e-8, rel=1e-14, abs=0)
    assert float(viscous_mass_flow(1e-18, 3e5, 1e5, helium)) == pytest.approx(4e-8 * 4.002602e-3 / (8.31446261815324 * T20), rel=1e-6, abs=0)


@pytest.mark.parametrize("name", ["helium", "air", "R134a"])
@pytest.mark.parametrize("upstream, downstream", [(2e5, 1e5), (1e5, 0.0), (10e5, 1e5), (1.001e5, 1e5)])
def test_continuum_limit_is_the_viscous_law_to_1e_10(name, upstream, downstream):
    """Kn → 0 (a gap of 100 km: Kn ~ 1e-12 at 1 bar): Q_pV = K (Pa² − Pb²)/2 to 1e-10."""
    gas = fluid_state(name, T20, 1e5).gas()
    gap = 1e5 if downstream > 0 else 1e9  # against vacuum the mean pressure, hence Kn, is set by the upstream side
    k = slit_conductance(gas, gap)
    leak = gas_leak(k, gap, gas, upstream, downstream)
    exact = k * (upstream**2 - downstream**2) / 2
    assert leak.knudsen_mean < 1e-11
    assert leak.throughput == pytest.approx(exact, rel=1e-10)
    assert leak.throughput_no_slip == pytest.approx(exact, rel=1e-14)
    assert leak.mass_flow == pytest.approx(exact / (gas.specific_gas_constant * T20), rel=1e-10)
    assert leak.molar_flow == pytest.approx(exact / (MOLAR_GAS_CONSTANT * T20), rel=1e-10)


def test_no_slip_model_is_the_viscous_law_at_any_knudsen_number(helium):
    k = slit_conductance(helium, 10e-9)
    leak = gas_leak(k, 10e-9, helium, 3e5, 1e5, model="no-slip")
    assert leak.knudsen_mean > 1 and leak.throughput == pytest.approx(k * (9e10 - 1e10) / 2, rel=1e-14, abs=0)


@pytest.mark.parametrize("name", ["helium", "nitrogen"])
def test_small_pressure_difference_gives_the_liquid_formula_with_the_gas_viscosity(name):
    """ΔP ≪ P: the volume flow at the mean pressure, Q_pV/P̄, tends to σ ΔP with σ = (W/L) h³/(12μ_gas) f(Kn(P̄));
    without rarefaction it is exactly K ΔP for any ΔP (Pa² − Pb² = 2 P̄ ΔP)."""
    gas = fluid_state(name, T20, 1e5).gas()
    gap, p = 1e-6, 1e5
    k = slit_conductance(gas, gap)
    liquid = 10.0 * float(sheet_conductance(gap, gas, p))  # the liquid's law with the gas's μ and the slip at p
    errors = []
    for dp in (1e4, 1e3, 1e2):
        pa, pb = p + dp / 2, p - dp / 2
        leak = gas_leak(k, gap, gas, pa, pb)
        errors.append(abs(leak.throughput / p / (liquid * dp) - 1))
        assert leak.throughput_no_slip / p == pytest.approx(k * dp, rel=1e-12, abs=0)
    assert errors[2] < 1e-6 and errors[0] > errors[1] > errors[2]


def test_first_order_slip_at_small_knudsen_number(air):
    """Kn → 0: Q/Q_no-slip − 1 → 6 Kn(P̄) (Maxwell first-order slip, diffuse walls); the Beskok–Karniadakis
    α term adds at most (α0·2α1/(6π)) Kn^0.4 ≈ 0.58 Kn^0.4 relative to it."""
    deviations = []
    for gap in (1e-4, 1e-2, 1.0):
        k = slit_conductance(air, gap)
        leak = gas_leak(k, gap, air, 2e5, 1e5, BK)
        ratio = (leak.throughput / leak.throughput_no_slip - 1) / (6 * leak.knudsen_mean)
        deviations.append(abs(ratio - 1))
        assert deviations[-1] < 2 * BK_ALPHA0 * 2 * 4 / (6 * math.pi) * leak.knudsen_mean**0.4
    assert deviations[0] > deviations[1] > deviations[2]


@pytest.mark.parametrize("name", ["helium", "argon"])
def test_free_molecular_limit(name):
    """Kn → ∞: Q_pV = (W/L) G_fm ΔP with G_fm = (7α0/12) h² √(π R_s T/2), independent of μ and of p."""
    gas = fluid_state(name, T20, 1e5).gas()
    gap = 1e-9
    k = slit_conductance(gas, gap)
    expected = 10.0 * float(free_molecular_coefficient(gap, gas, BK))
    hand = 10.0 * 7 * (64 / (15 * math.pi)) / 12 * gap**2 * math.sqrt(math.pi / 2 * 8.31446261815324 / gas.molar_mass * T20)
    assert expected == pytest.approx(hand, rel=1e-12, abs=0)
    errors = []
    for pa in (1e-1, 1e-3, 1e-5):
        leak = gas_leak(k, gap, gas, pa, 0.0, BK)
        errors.append(abs(leak.throughput / (expected * pa) - 1))
        assert leak.regime == "free molecular"
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-5


def test_graham_law_in_the_free_molecular_limit_and_viscosity_in_the_viscous_one(helium, air):
    """Same channel (a slit 100 gaps long): helium/air → μ_air/μ_He (< 1) in viscous flow, → √(M_air/M_He) = 2.69
    in molecular flow."""
    def ratio(gap, pa, pb):
        he = gas_leak(slit_conductance(helium, gap), gap, helium, pa, pb, length=100 * gap).throughput
        return he / gas_leak(slit_conductance(air, gap), gap, air, pa, pb, length=100 * gap).throughput

    assert ratio(1e3, 2e5, 1e5) == pytest.approx(air.viscosity / helium.viscosity, rel=1e-8)
    assert ratio(1e-9, 1e-3, 0.0) == pytest.approx(math.sqrt(air.molar_mass / helium.molar_mass), rel=1e-4)


def test_slip_factor_limits_and_monotonicity():
    kn = np.logspace(-6, 6, 200)
    f = slip_factor(kn, BK)
    assert np.all(np.diff(f) > 0) and np.all(f > 1)
    assert float(slip_factor(0.0, BK)) == 1.0 and math.isinf(float(slip_factor(math.inf, BK)))
    assert float(slip_factor(1e-9, BK)) == pytest.approx(1 + 6e-9, rel=1e-12)
    assert float(slip_factor(1e12, BK)) / 1e12 == pytest.approx(7 * BK_ALPHA0, rel=1e-4)
    assert np.all(slip_factor(kn, "no-slip") == 1.0)
    with pytest.raises(InputError):
        slip_factor(1.0, "maxwell")


def test_rarefaction_raises_the_leak_against_vacuum_and_the_integrand_is_finite_there(helium):
    """Against vacuum Kn → ∞ at the outlet: the integral is finite and continuous as P_b → 0."""
    gap = 50e-9
    at_zero = pressure_integral(gap, helium, 1e5, 0.0)
    near = pressure_integral(gap, helium, 1e5, 1e-6)
    assert math.isfinite(at_zero) and near == pytest.approx(at_zero, rel=1e-9)
    assert at_zero > 0.5 * 1e10  # more than the no-slip (Pa²)/2


@pytest.mark.parametrize("field, args", [("gap", (0.0, 1e5, 0.0)), ("gap", (-1e-9, 1e5, 0.0)), ("rarefaction_model", None)])
def test_pressure_integral_refuses_bad_input(field, args, helium):
    with pytest.raises(InputError) as exc:
        if args is None:
            pressure_integral(1e-7, helium, 1e5, 0.0, model="slippery")
        else:
            pressure_integral(args[0], helium, args[1], args[2])
    assert exc.value.field == field
