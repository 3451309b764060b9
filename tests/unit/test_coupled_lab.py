"""The linearity check and the fit with the fluid pressure coupled (docs/theory.md §13.5) and capillarity (§12.1).

The models' leak rates compared with come from :func:`sealeak.cases.predict` of a uniform seal (eq. 13.2, itself
checked against scipy's quad in tests/unit/test_fluid_pressure.py) and the line through them from numpy's polyfit,
not from the linearity check's own route.
"""

import json
from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import predict
from sealeak.cases.fitting import fit_models
from sealeak.cases.linearity_check import linearity
from sealeak.lab.data import read_leak_data
from sealeak.render.lab import linearity_json, linearity_text
from sealeak.render.notes import word
from tests.unit.test_coupled_rig import NON_WETTING, P, band_case, uniform_case

CJ = "critical junction (α = 1)"
EM = "effective medium (Bruggeman)"


@pytest.fixture(scope="module")
def coupled():
    return uniform_case()


def test_linearity_of_the_printed_theory_is_a_line_through_the_origin(coupled):
    ignored = replace(coupled, fluid_pressure="ignored")
    dp = np.array([2e4, 4e4, 6e4, 8e4])
    k = predict(ignored, squeeze_pressure=[P], pressure_difference=1.0).leak_rate[0]
    check = linearity(ignored, dp, 0.5 * k * dp, squeeze_pressure=P)
    assert check.model_slopes[CJ] == pytest.approx(k, rel=1e-9, abs=0)
    assert abs(check.model_intercepts[CJ]) < 1e-9 * k * dp.max()
    assert check.model_nonlinearity[CJ] == pytest.approx(0.0, abs=1e-9)
    assert check.alpha_from_slope == pytest.approx(0.5, rel=1e-9)
    assert check.capillary_entry_pressure == {}


def test_linearity_compares_the_data_with_the_coupled_curve(coupled):
    dp = np.array([2e4, 4e4, 6e4, 8e4, 1e5])
    q = predict(coupled, squeeze_pressure=np.full(dp.size, P), pressure_difference=dp).leak_rate
    check = linearity(coupled, dp, 2.0 * q, squeeze_pressure=P)
    slope, intercept = np.polyfit(dp, q, 1)
    assert check.model_slopes[CJ] == pytest.approx(slope, rel=1e-6, abs=0)
    assert check.model_intercepts[CJ] == pytest.approx(intercept, rel=1e-6, abs=0)
    assert intercept < 0  # Q grows faster than linearly: the line through it cuts the ΔP axis above 0
    assert check.model_nonlinearity[CJ] == pytest.approx((q[-1] / dp[-1]) / (q[0] / dp[0]) - 1.0, rel=1e-9)
    assert check.model_nonlinearity[CJ] > 0.1
    assert check.alpha_from_slope == pytest.approx(2.0, rel=1e-9)
    # the figure's curve passes through the model at the measured ΔP
    x, curve = check.curve_pressure_difference, check.model_curves[CJ]
    assert x[0] == 0 and curve[0] == 0 and x[-1] == pytest.approx(1.1e5)
    np.testing.assert_allclose(np.interp(dp, x, curve), q, rtol=0.05)


def test_linearity_at_small_pressure_differences_is_the_printed_line(coupled):
    dp = np.array([10.0, 20.0, 30.0, 40.0])
    k = predict(replace(coupled, fluid_pressure="ignored"), squeeze_pressure=[P], pressure_difference=1.0).leak_rate[0]
    check = linearity(coupled, dp, k * dp, squeeze_pressure=P)
    assert check.model_slopes[CJ] == pytest.approx(k, rel=3e-3, abs=0)  # (1.2e-3 here)
    assert 0 < check.model_nonlinearity[CJ] < 1e-3


def test_linearity_with_capillarity_is_zero_below_the_entry_pressure():
    case = replace(uniform_case(NON_WETTING), fluid_pressure="ignored")
    k = predict(case, squeeze_pressure=[P], pressure_difference=1.0)
    p_e = -0.072 * 2.0 * np.cos(np.radians(90.3)) / k.critical_gap[0]  # eq. 12.2
    dp = np.array([0.25, 0.5, 1.5, 2.0]) * p_e
    measured = np.array([0.0, 1.0, 2.0, 3.0]) * k.leak_rate[0] * p_e  # the second point leaked below p_e
    check = linearity(case, dp, measured, squeeze_pressure=P)
    assert check.capillary_entry_pressure[CJ] == pytest.approx(p_e, rel=1e-9)
    # eq. 12.3: 0 below p_e, the whole K ΔP above it (a threshold, not ΔP − p_e)
    x, curve, at = check.curve_pressure_difference, check.model_curves[CJ], check.capillary_entry_pressure[CJ]
    np.testing.assert_array_equal(curve[x < at], 0.0)
    np.testing.assert_allclose(curve[x >= at], k.leak_rate[0] * x[x >= at], rtol=1e-12)
    assert at in x and np.nextafter(at, 0.0) in x  # the step drawn upright
    slope, intercept = np.polyfit(dp, np.where(dp < p_e, 0.0, k.leak_rate[0] * dp), 1)
    assert check.model_slopes[CJ] == pytest.approx(slope, rel=1e-9, abs=0)
    assert check.model_intercepts[CJ] == pytest.approx(intercept, rel=1e-9, abs=0) and intercept < 0  # the offset
    (note,) = [word(m) for m in check.messages if word(m).startswith(CJ + ": ")]
    assert "2 measured point(s) lie below" in note and "1 of them leaked" in note


def test_contact_angle_of_90_degrees_changes_no_linearity_check_and_no_fit(coupled):
    right = uniform_case('surface_tension = "72 mN/m"\ncontact_angle = 90')
    dp = np.array([2e4, 4e4, 6e4])
    q = predict(coupled, squeeze_pressure=np.full(dp.size, P), pressure_difference=dp).leak_rate
    plain, wet = linearity(coupled, dp, q, squeeze_pressure=P), linearity(right, dp, q, squeeze_pressure=P)
    assert wet.capillary_entry_pressure[CJ] == 0.0
    assert wet.model_slopes == plain.model_slopes and wet.model_intercepts == plain.model_intercepts
    assert wet.messages == plain.messages
    a, b = fit_models(coupled, np.full(dp.size, P), dp, q), fit_models(right, np.full(dp.size, P), dp, q)
    assert a["critical_junction"].alpha == b["critical_junction"].alpha and not b["critical_junction"].excluded


def test_fit_excludes_the_rows_held_by_capillarity():
    case = uniform_case(NON_WETTING)
    u_c = predict(case, squeeze_pressure=[P], pressure_difference=1.0).critical_gap[0]
    p_e = -0.072 * 2.0 * np.cos(np.radians(90.3)) / u_c
    dp = np.array([0.5, 0.8, 1.5, 2.0, 3.0]) * p_e
    q = 0.3 * predict(case, squeeze_pressure=np.full(dp.size, P), pressure_difference=dp).leak_rate
    q[1] = 0.0  # held, as the model says
    fit = fit_models(case, np.full(dp.size, P), dp, q)["critical_junction"]
    assert fit.alpha == pytest.approx(0.3, rel=1e-9) and fit.n_used == 3
    reasons = dict(fit.excluded)
    assert set(reasons) == {0, 1}
    assert "capillarity" in reasons[0] and "yet it leaked" in reasons[0]
    assert "capillarity" in reasons[1] and "as measured" in reasons[1]


def test_band_fit_takes_the_coupled_flow_at_each_rows_pressure_difference(tmp_path):
    """Rows at ΔP other than the case's: the band's own flow there, not K(case ΔP) ΔP (docs/theory.md §13.5)."""
    band, uniform = band_case(tmp_path), uniform_case()
    dp = np.array([1e4, 3e4, 6e4, 1e5])  # the case's ΔP is 10 kPa
    q = 0.7 * predict(uniform, squeeze_pressure=np.full(dp.size, P), pressure_difference=dp).leak_rate
    fit = fit_models(band, np.ones(dp.size), dp, q)["critical_junction"]
    assert fit.alpha == pytest.approx(0.7, rel=1e-4)
    assert fit.rms_log10_residual < 1e-5


def test_linearity_outputs_carry_the_models_lines(tmp_path):
    case = uniform_case(NON_WETTING)
    path = tmp_path / "dp.csv"
    path.write_text("pressure_difference (kPa), leak_rate (m^3/s)\n20, 1e-17\n60, 4e-17\n100, 8e-17\n")
    data = read_leak_data(path, required=("pressure_difference", "leak_rate"))
    check = linearity(case, data.pressure_difference, data.leak_rate, squeeze_pressure=P)
    doc = json.loads(linearity_json(case, data, check))["linearity"]
    # keyed by the model's record key, its display name (which holds α) beside it
    assert doc["model_labels"] == {"critical_junction": CJ, "effective_medium": "effective medium (Bruggeman)"}
    assert doc["model_intercepts"]["critical_junction"] == pytest.approx(check.model_intercepts[CJ], rel=1e-12, abs=0)
    assert doc["model_nonlinearity"]["critical_junction"] > 0  # coupled: Q/ΔP rises over the data
    assert doc["capillary_entry_pressure"]["critical_junction"] == pytest.approx(check.capillary_entry_pressure[CJ], rel=1e-12)
    text = linearity_text(case, data, check)
    assert "Q/ΔP rises by" in text and "capillary entry pressure" in text
    plain = json.loads(linearity_json(uniform_case(), data, linearity(uniform_case(), data.pressure_difference,
                                                                      data.leak_rate, squeeze_pressure=P)))
    assert "capillary_entry_pressure" not in plain["linearity"] and "capillary_entry_pressure" not in plain["units"]
