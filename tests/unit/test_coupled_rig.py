"""The water-column rig with the fluid pressure coupled (docs/theory.md §13.5) and with capillarity (§12.1).

The values compared with come from other routes than the rig's tabulated Q(ΔP) and ODE: the uniform seal's
rig against the band's, scipy's quad of the time to fall t = A ∫ dH / Q(ρgH), and the closed forms of the
exponential fall and of the capillary stop H_e = p_e/(ρg).
"""

import json
from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate

from sealeak.cases import parse_cases, predict
from sealeak.cases.prediction import leak_curve
from sealeak.cases.rig import rig_prediction
from sealeak.render.lab import rig_json, rig_text
from sealeak.render.notes import word
from tests.unit.test_band_lab import SURFACE as BAND_SURFACE

SURFACE = BAND_SURFACE + "{fluid}\n"  # the band-lab tests' surface, rubber and water, and the fluid's other keys

#: A flat band: 0.2 MPa over 0.5 mm, seal line 100 mm; q0 fixed so that a rectangle of the same size has the same.
FLAT = "x (mm), pressure (MPa)\n0, 0.2\n0.5, 0.2\n"
P, W, LY = 0.2e6, 0.5e-3, 0.1
THEORY = '[theory]\nalpha = 1.0\nlowest_wavevector = "1.2566e4 1/m"\n'
#: 10 m of water: ΔP0 = 98 kPa, half the contact pressure, where the coupling matters.
RIG = '[rig]\ncylinder_diameter = "0.5 mm"\ninitial_height = "10 m"\nfinal_height = "2 m"\nduration = "{duration} s"\n'


def band_case(tmp_path, fluid="", duration=4e8):
    (tmp_path / "flat.csv").write_text(FLAT)
    text = SURFACE.format(fluid=fluid) + """
[seal]
pressure_profile = "flat.csv"
length = "100 mm"
[conditions]
profile_scale = 1
pressure_difference = "10 kPa"
""" + THEORY + RIG.format(duration=duration)
    (case,) = parse_cases(text, tmp_path)
    return case


def uniform_case(fluid="", duration=4e8):
    text = SURFACE.format(fluid=fluid) + f"""
[seal]
shape = "rectangle"
width = "{W * 1e3} mm"
length = "{LY * 1e3} mm"
[conditions]
squeeze_pressure = "{P} Pa"
pressure_difference = "10 kPa"
""" + THEORY + RIG.format(duration=duration) + f'load = "{P * W * LY} N"\n'
    (case,) = parse_cases(text)
    return case


def _time_to_fall(case, h0, h1):
    """t = A ∫_{H1}^{H0} dH / Q(ρ g H) (s) by scipy's adaptive quadrature, Q of the coupled uniform seal (eq. 13.2)."""
    rig = case.rig
    p0 = float(case.squeeze_pressure[0])

    def inverse_q(h):
        return 1.0 / predict(case, squeeze_pressure=[p0], pressure_difference=rig.density * rig.gravity * h).leak_rate[0]
    return rig.cylinder_area * integrate.quad(inverse_q, h1, h0, epsrel=1e-6)[0]


def test_band_rig_of_a_flat_profile_is_the_uniform_seal_coupled_rig(tmp_path):
    band, uniform = band_case(tmp_path), uniform_case()
    assert band.coupled and uniform.coupled
    b, u = rig_prediction(band), rig_prediction(uniform)
    (name,) = b.conductance
    dp0 = band.rig.pressure_difference(band.rig.initial_height)
    assert b.squeeze_pressure == pytest.approx(P, rel=1e-12) and u.squeeze_pressure == pytest.approx(P, rel=1e-12)
    # K at the initial head: Q(ΔP0)/ΔP0 of eq. 13.2, the same for both seals
    q0 = predict(uniform, squeeze_pressure=[P], pressure_difference=dp0).leak_rate[0]
    assert b.conductance[name] == pytest.approx(q0 / dp0, rel=1e-5, abs=0)
    assert u.conductance[name] == pytest.approx(q0 / dp0, rel=1e-12, abs=0)
    # the band follows Q(ρgH) along the fall: its column is the uniform seal's, and the time to the final height
    # is the quadrature of dH/Q
    np.testing.assert_allclose(b.columns[name].height, u.columns[name].height, rtol=1e-4)
    t_quad = _time_to_fall(uniform, 10.0, 2.0)
    assert b.drain_time[name] == pytest.approx(t_quad, rel=1e-4)
    assert u.drain_time[name] == pytest.approx(t_quad, rel=1e-4)
    # K = Q/ΔP falls with the head, so the level takes longer than with K held at its initial value
    tau = band.rig.cylinder_area / (b.conductance[name] * 1000.0 * 9.80665)
    assert b.drain_time[name] > tau * np.log(10.0 / 2.0)


def test_band_rig_at_a_small_head_is_the_printed_band(tmp_path):
    """ΔP ≪ p: the coupled band rig is the linear one, K = Ly/∫dx/σ (docs/theory.md §13.3)."""
    case = band_case(tmp_path)
    small = replace(case, rig=replace(case.rig, initial_height=0.005, final_height=0.001, duration=None))  # ΔP0 = 49 Pa
    coupled, ignored = rig_prediction(small), rig_prediction(replace(small, fluid_pressure="ignored"))
    (name,) = coupled.conductance
    assert coupled.conductance[name] > ignored.conductance[name]  # the fluid pressure only opens the contact
    assert coupled.conductance[name] == pytest.approx(ignored.conductance[name], rel=2e-3, abs=0)
    assert coupled.drain_time[name] < ignored.drain_time[name]
    assert coupled.drain_time[name] == pytest.approx(ignored.drain_time[name], rel=2e-3)


def test_band_leak_curve_grows_faster_than_linear(tmp_path):
    case = band_case(tmp_path)
    dp = np.array([1e3, 5e4, 1e5, 1.5e5])
    k = leak_curve(case, "critical-junction", 1.0, dp) / dp
    assert np.all(np.diff(k) > 0)
    k_ignored = leak_curve(replace(case, fluid_pressure="ignored"), "critical-junction", 1.0, dp) / dp
    np.testing.assert_allclose(k_ignored, k_ignored[0], rtol=1e-12)
    assert k[0] == pytest.approx(k_ignored[0], rel=5e-2, abs=0)  # (ΔP = 1 kPa already opens the band by 2.4 %)


#: A liquid just short of wetting: cos θ_r + cos θ_s = 2 cos 90.3° < 0, so the meniscus opposes entry (p_e ≈ 50 kPa here).
NON_WETTING = 'surface_tension = "72 mN/m"\ncontact_angle = 90.3'


@pytest.mark.parametrize("pressure", ["ignored", "coupled"])
def test_rig_column_stops_at_the_capillary_entry_pressure(pressure):
    case = replace(uniform_case(NON_WETTING), fluid_pressure=pressure)
    rig = case.rig
    pred = rig_prediction(case)
    (name,) = pred.conductance
    u_c = predict(case, squeeze_pressure=[P], pressure_difference=1.0).critical_gap[0]
    p_e = -0.072 * 2.0 * np.cos(np.radians(90.3)) / u_c  # eq. 12.2
    h_e = p_e / (1000.0 * 9.80665)
    assert 2.0 < h_e < 10.0  # the column stops between the start and the final height
    col = pred.columns[name]
    assert pred.entry_pressure[name] == pytest.approx(p_e, rel=1e-9)
    assert col.stop_height == pytest.approx(h_e, rel=1e-9)
    assert col.height.min() == pytest.approx(h_e, rel=1e-9)
    after = col.time > col.time_to_stop
    assert after.any() and np.all(col.height[after] == col.stop_height) and np.all(col.leak_rate[after] == 0)
    assert np.isnan(col.time_to_final) and pred.drain_time[name] == np.inf  # it never reaches 2 m
    if pressure == "ignored":  # the linear fall: t = τ ln(H0/H_e)
        tau = rig.cylinder_area / (pred.conductance[name] * 1000.0 * 9.80665)
        assert col.time_to_stop == pytest.approx(tau * np.log(10.0 / h_e), rel=1e-6)
    else:
        assert col.time_to_stop == pytest.approx(_time_to_fall(case, 10.0, h_e), rel=1e-4)
    text = " ".join(word(m) for m in pred.messages)
    assert f"the level stops at H = p_e/(ρg) = {h_e:.4g} m" in text


def test_rig_held_from_the_start_below_the_entry_pressure():
    case = uniform_case(NON_WETTING)
    low = replace(case, rig=replace(case.rig, initial_height=1.0, final_height=0.5))
    pred = rig_prediction(low)
    (name,) = pred.conductance
    col = pred.columns[name]
    assert pred.conductance[name] > 0  # the seal has a channel: capillarity alone holds the water
    assert np.all(col.height == 1.0) and np.all(col.leak_rate == 0) and col.time_to_stop == 0
    assert "the level stays at H0 = 1 m" in " ".join(word(m) for m in pred.messages)


def test_contact_angle_of_90_degrees_changes_nothing(tmp_path):
    for make in (lambda f: band_case(tmp_path, f), uniform_case):
        plain = rig_prediction(make(""))
        right = rig_prediction(make('surface_tension = "72 mN/m"\ncontact_angle = 90'))
        (name,) = plain.conductance
        assert right.entry_pressure[name] == 0.0
        np.testing.assert_array_equal(right.columns[name].height, plain.columns[name].height)
        assert right.drain_time[name] == plain.drain_time[name]
        assert right.messages == plain.messages


def test_rig_outputs_name_the_stop():
    case = uniform_case(NON_WETTING)
    pred = rig_prediction(case)
    (name,) = pred.conductance
    col = pred.columns[name]
    doc = json.loads(rig_json(case, pred))
    model = doc["models"][name]
    assert model["capillary_entry_pressure"] == pytest.approx(pred.entry_pressure[name], rel=1e-12)
    assert model["stop_height"] == pytest.approx(col.stop_height, rel=1e-12)
    assert model["time_to_stop"] == pytest.approx(col.time_to_stop, rel=1e-12)
    assert model["time_to_final_height"] is None  # the final height lies below the stop
    assert doc["units"]["stop_height"] == "m" and doc["units"]["capillary_entry_pressure"] == "Pa"
    text = rig_text(case, pred)
    assert "the level stops at H = p_e/(ρg)" in text and "fluid pressure coupled" in text
    plain = json.loads(rig_json(uniform_case(), rig_prediction(uniform_case())))
    assert "stop_height" not in plain["models"][name] and "stop_height" not in plain["units"]
