"""Fitting α, leak-test units, the virtual rig, the HTML report and bad data files (docs/theory.md § 4)."""

from dataclasses import replace

import numpy as np
import pytest

from sealeak import FileFormatError, UnitError
from sealeak.cases import fit_models, predict
from sealeak.io.leak_units import leak_rate_factor
from sealeak.lab.data import read_leak_data
from sealeak.lab.fitting import fit_line, fit_scale
from sealeak.lab.rig import RigSetup, drain_time, exponential_height, leak_rate_from_readings, water_column
from sealeak.physics.seal import Seal

G = 9.80665




# ---------------------------------------------------------------------- fitting
def test_sweep_spans_three_decades(sweep):
    _, cj, em = sweep
    assert np.log10(cj.max() / cj.min()) > 3 and np.log10(em.max() / em.min()) > 3


def test_fit_recovers_alpha_within_its_error(sweep):
    p0, cj, em = sweep
    rng = np.random.default_rng(20240601)
    for model in (cj, em):
        for alpha in (0.2, 3.0):
            q = alpha * model * np.exp(0.3 * rng.standard_normal(model.size))
            f = fit_scale(q, model)
            assert f.n_used == model.size and not f.excluded
            assert abs(f.alpha - alpha) < 3 * f.alpha_std
            assert f.rms_log10_residual == pytest.approx(0.3 / np.log(10), rel=0.4)


@pytest.mark.parametrize("model", ["critical_junction", "effective_medium"])
def test_stated_error_has_the_right_coverage(sweep, model):
    """Over many seeded data sets, |α̂ - α| < α_std about 68 % of the time (t with 15 dof: 66.7 %)."""
    _, cj, em = sweep
    prediction = cj if model == "critical_junction" else em
    rng = np.random.default_rng(7)
    hits = 0
    trials = 600
    for _ in range(trials):
        q = 0.2 * prediction * np.exp(0.5 * rng.standard_normal(prediction.size))
        f = fit_scale(q, prediction)
        hits += abs(np.log(f.alpha / 0.2)) < f.log10_alpha_std * np.log(10)
    assert 0.60 < hits / trials < 0.74


def test_rows_repeating_one_measurement_give_alpha_no_standard_error():
    """Four copies of one row printed α ± 0 (no scatter among copies), which reads as certainty: like one point, they
    give no standard error. Points that lie exactly on the model's curve at different loads keep se = 0, their
    scatter; one differing copy brings a standard error back."""
    q, model = np.full(4, 3e-8), np.full(4, 2e-7)
    f = fit_scale(q, model)
    assert f.alpha == pytest.approx(0.15, rel=1e-14, abs=0) and f.n_used == 4
    assert np.isnan(f.alpha_std) and np.isnan(f.log10_alpha_std)
    exact = fit_scale(0.15 * np.array([1e-7, 2e-7, 4e-7]), np.array([1e-7, 2e-7, 4e-7]))
    assert exact.alpha_std == pytest.approx(0.0, abs=1e-15)
    assert fit_scale(np.array([3e-8, 3e-8, 3e-8, 3.3e-8]), model).alpha_std > 0


def test_rows_without_pressure_difference_use_the_case_value(case):
    p0 = np.array([3e4, 6e4])
    a = fit_models(case, p0, [np.nan, np.nan], [1e-6, 1e-7])["critical_junction"].prediction
    b = predict(replace(case, alpha=1.0), squeeze_pressure=p0, pressure_difference=case.pressure_difference).leak_rate
    assert np.allclose(a, b, rtol=1e-14)
    c = fit_models(case, p0, [2e4, np.nan], [1e-6, 1e-7])["critical_junction"].prediction
    assert c[0] == pytest.approx(2 * b[0], rel=1e-12, abs=0) and c[1] == pytest.approx(b[1], rel=1e-14, abs=0)


def test_linear_fit_closed_form():
    rng = np.random.default_rng(1)
    x = np.linspace(1e3, 1e4, 12)
    y = 2e-10 * x + 1e-8 + 1e-8 * rng.standard_normal(x.size)
    f = fit_line(x, y)
    A = np.vstack([x, np.ones_like(x)]).T
    coef, res, *_ = np.linalg.lstsq(A, y, rcond=None)
    cov = res[0] / (x.size - 2) * np.linalg.inv(A.T @ A)
    assert f.slope == pytest.approx(coef[0], rel=1e-10, abs=0) and f.intercept == pytest.approx(coef[1], rel=1e-8, abs=0)
    assert f.slope_std == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-8, abs=0)
    assert f.intercept_std == pytest.approx(np.sqrt(cov[1, 1]), rel=1e-8, abs=0)


# ---------------------------------------------------------------------- units
def test_leak_test_units_against_hand_computed_values():
    assert leak_rate_factor("ml/min") == pytest.approx(1e-6 / 60, rel=1e-14, abs=0)
    assert leak_rate_factor("l/h") == pytest.approx(1e-3 / 3600, rel=1e-14, abs=0)
    # 1 mbar·l/s = 100 Pa × 1e-3 m³/s = 0.1 Pa·m³/s; at 1 atm: 0.1/101325 m³/s
    assert leak_rate_factor("mbar*l/s") == pytest.approx(0.1 / 101325, rel=1e-14, abs=0)
    assert leak_rate_factor("mbar·l/s") == pytest.approx(9.8692e-7, rel=1e-4)
    assert leak_rate_factor("Pa*m^3/s") == pytest.approx(1 / 101325, rel=1e-14, abs=0)
    # at another stated pressure: volume flow = throughput / pressure
    assert leak_rate_factor("mbar*l/s", reference_pressure=2e5) == pytest.approx(0.1 / 2e5, rel=1e-14, abs=0)
    assert leak_rate_factor("Pa*m^3/s", reference_pressure=1e3) == pytest.approx(1e-3, rel=1e-14, abs=0)
    for bad in ("kPa", "m/s", "furlongs", ""):
        with pytest.raises(UnitError):
            leak_rate_factor(bad)




# ---------------------------------------------------------------------- rig
def test_load_to_squeeze_pressure_for_the_reference_ring(case):
    ring = Seal.ring(0.03, 0.04)
    rig = case.rig
    assert rig.load == pytest.approx(3.4 * G)
    want = 3.4 * G / (np.pi * (0.04**2 - 0.03**2) / 4)
    assert rig.squeeze_pressure(ring) == pytest.approx(want, rel=1e-14)
    assert want == pytest.approx(60.65e3, rel=1e-3)  # the paper's "P0 ≈ 60 kPa"


def test_exponential_matches_the_ode_solver():
    rig = RigSetup(cylinder_diameter=0.03, initial_height=1.0, load=30.0, density=1000.0, final_height=0.5)
    k = 1.2e-10
    col = water_column(rig, lambda dp: k * dp, t_eval=np.linspace(0, 2000, 81))
    exact = exponential_height(rig, k, col.time)
    assert np.max(np.abs(col.height - exact)) < 1e-8 * rig.initial_height
    assert col.time_to_final == pytest.approx(drain_time(rig, k, 0.5), rel=1e-8)
    tau = rig.cylinder_area / (k * 1000 * G)
    assert drain_time(rig, k, 0.5) == pytest.approx(tau * np.log(2), rel=1e-14)


def test_pressure_dependent_leak_uses_the_ode():
    # Q = c ΔP²: A dH/dt = -c (ρgH)² has H = H0/(1 + c (ρg)² H0 t/A)
    rig = RigSetup(cylinder_diameter=0.05, initial_height=0.8, load=30.0, density=1000.0, final_height=0.2)
    c = 1e-14
    col = water_column(rig, lambda dp: c * dp**2, t_eval=np.linspace(0, 5000, 51))
    b = c * (1000 * G) ** 2 / rig.cylinder_area
    assert np.allclose(col.height, 0.8 / (1 + b * 0.8 * col.time), rtol=1e-8)


def test_readings_inverse(case):
    rig = case.rig
    k = 1.2e-10
    t = np.linspace(0, 900, 10)
    h = exponential_height(rig, k, t)
    a = leak_rate_from_readings(rig, t, h)
    assert a.conductance == pytest.approx(k, rel=1e-10, abs=0)
    # Q between readings = -A ΔH/Δt, and it is close to K ρ g H at the mid-height
    assert np.allclose(a.interval_leak_rate, k * a.interval_pressure_difference, rtol=5e-3)


# ---------------------------------------------------------------------- report


@pytest.mark.parametrize("text", [
    "squeeze_pressure (kPa) leak_rate (ml/min)\n30 100\n60 30\n",  # spaces: 'name (unit)' is one cell
    "squeeze_pressure (kPa);leak_rate (ml/min);\n30;100;\n60;30;\n",  # spreadsheet export: trailing ';'
])
def test_file_layouts_read_the_same(tmp_path, text):
    data = tmp_path / "m.txt"
    data.write_text(text)
    d = read_leak_data(data)
    assert np.allclose(d.squeeze_pressure, [3e4, 6e4]) and np.allclose(d.leak_rate, [100e-6 / 60, 30e-6 / 60])


@pytest.mark.parametrize("text, problem", [
    ("squeeze_pressure (kPa)\n30\n60\n", "missing column leak_rate"),
    ("squeeze_pressure (kPa),leak_rate (ml/min)\n30,100,5\n", "3 values, but the header names 2 columns"),
])
def test_file_layout_errors(tmp_path, text, problem):
    data = tmp_path / "m.txt"
    data.write_text(text)
    with pytest.raises(FileFormatError) as err:
        read_leak_data(data)
    assert problem in str(err.value) and "decimal" not in str(err.value)
