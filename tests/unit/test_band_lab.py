"""fit, linearity and rig for O-ring and pressure-profile seals (docs/theory.md §10.5), without the CLI.

The model values these tests compare with come from another route than the one under test: a
case file written at the measured loads (not :func:`sealeak.cases.seals.with_loads`), or the
uniform theory of a flat rectangle at each plateau of a step profile, combined by hand as
resistances in series.
"""

from dataclasses import replace

import numpy as np
import pytest

from sealeak import FileFormatError, InputError
from sealeak.cases import parse_cases, predict
from sealeak.cases.band import run_band
from sealeak.cases.fitting import fit_models, run_fit
from sealeak.cases.linearity_check import linearity
from sealeak.cases.prediction import conductance
from sealeak.cases.rig import rig_prediction
from sealeak.lab.data import read_leak_data
from sealeak.lab.rig import drain_time, exponential_height
from sealeak.render.notes import word
from tests.casefiles import FINE_SURFACE

SURFACE = FINE_SURFACE + """[fluid]
viscosity = "1 mPa*s"
density = "1000 kg/m^3"
"""

#: A step profile: 0.1 MPa over 0.2 mm, then 0.2 MPa over 0.3 mm (w = 0.5 mm); seal line 100 mm.
STEP = "x (mm), pressure (MPa)\n0, 0.1\n0.2, 0.1\n0.2, 0.2\n0.5, 0.2\n"
W1, W2, P1, P2, LY = 0.2e-3, 0.3e-3, 0.1e6, 0.2e6, 0.1


def profile_case(tmp_path, scale="1", alpha=0.5, extra="", theory=""):
    """The step profile with the fluid pressure ignored: the printed theory, Q = K ΔP, whose closed forms the lab
    tools are checked against here (the coupled flow: tests/unit/test_fluid_pressure.py)."""
    (tmp_path / "step.csv").write_text(STEP)
    text = SURFACE + f"""
[seal]
pressure_profile = "step.csv"
length = "100 mm"
[conditions]
profile_scale = {scale}
pressure_difference = "10 kPa"
[theory]
alpha = {alpha}
fluid_pressure = "ignored"
{theory}
""" + extra
    return parse_cases(text, tmp_path)[0]


def oring_case(compressions, alpha=1.0, theory=""):
    """An O-ring of the bundled example's size and rubber on its ground-steel stand-in surface.

    The spectrum starts at a stated wavelength (5 mm): with h_rms given and no lowest wavelength it
    would start at the case's q0, which depends on the widest band among the case's loads.
    """
    text = SURFACE.replace('youngs_modulus = "8 MPa"', 'youngs_modulus = "5.5 MPa"').replace(
        '"0.3 um"', '"1.5 um"\nlowest_wavelength = "5 mm"').replace('"50 um"', '"100 um"').replace('"5 nm"', '"10 nm"') + f"""
[seal]
shape = "o-ring"
cross_section_diameter = "2.62 mm"
inner_diameter = "20 mm"
[conditions]
compression = {compressions}
pressure_difference = "1 bar"
[theory]
alpha = {alpha}
{theory}
"""
    return parse_cases(text)[0]


def series_conductance(tmp_path, scale=1.0, alpha=0.5):
    """K = Ly / (w1/σ1 + w2/σ2) with σ(p) from the uniform theory of a flat 0.5 mm × 100 mm rectangle (q0 = 2π/w)."""
    uniform = parse_cases(SURFACE + f"""
[seal]
shape = "rectangle"
width = "0.5 mm"
length = "100 mm"
[conditions]
squeeze_pressure = ["{P1 * scale} Pa", "{P2 * scale} Pa"]
pressure_difference = "10 kPa"
[theory]
alpha = {alpha}
fluid_pressure = "ignored"
""")[0]
    q = predict(uniform).leak_rate  # α (Ly/w) u_c³ ΔP/(12η)
    sigma = q * (W1 + W2) / (LY * uniform.pressure_difference)
    return LY / (W1 / sigma[0] + W2 / sigma[1])


# ---------------------------------------------------------------------- conductance of a band at a load
def test_step_profile_conductance_is_the_series_sum_of_uniform_strips(tmp_path):
    case = profile_case(tmp_path, scale="0.8")
    for scale in (0.8, 1.3):
        k = conductance(case, [scale], "critical-junction")[0]
        assert k == pytest.approx(series_conductance(tmp_path, scale), rel=1e-9, abs=0)
    # α enters linearly; K is Q/ΔP of the band
    k2 = conductance(replace(case, alpha=1.0), [0.8], "critical-junction")[0]
    assert k2 == pytest.approx(2 * series_conductance(tmp_path, 0.8), rel=1e-9, abs=0)


def test_conductance_at_other_loads_equals_a_case_written_at_them():
    case = oring_case('"15 %"')
    written = oring_case('["11 %", "18 %", "28 %"]')
    q = run_band(written, effective=False).critical_junction.leak_rate
    k = conductance(case, [0.11, 0.18, 0.28])
    want = np.where(np.isfinite(q), q / written.pressure_difference, 0.0)
    # (the same numbers by both routes here; 1e-8 is the coupled band's own tolerance, should a parsed load differ by an ulp)
    assert np.allclose(k, want, rtol=1e-8, atol=0)
    assert k[0] > k[1] > 0 and k[2] == 0  # more squeeze, less leak; at 28 % the band seals


def test_a_fixed_q0_stays_fixed_at_other_loads():
    fixed = 'square_side = "30 um"'  # q0 above the roll-off: it matters
    case = oring_case('"15 %"', theory=fixed)
    written = oring_case('["12 %", "20 %"]', theory=fixed)
    assert np.all(written.band.q0 == written.band.q0[0])
    q = run_band(written, effective=False).critical_junction.leak_rate
    assert np.allclose(conductance(case, [0.12, 0.20]), q / written.pressure_difference, rtol=1e-8, atol=0)
    # and without it, q0 = 2π/w per load: a different leak rate
    free = conductance(oring_case('"15 %"'), [0.12, 0.20])
    assert not np.allclose(free, q / written.pressure_difference, rtol=1e-3, atol=0)


# ---------------------------------------------------------------------- fit
def test_fit_recovers_a_known_alpha_from_synthetic_oring_data():
    """Data = α × the band theory at each compression (a case written at them) × seeded log-normal scatter.

    Each compression is measured twice; the band is computed once per distinct compression. One
    fit of both theories (the effective medium costs 1–2 s per compression).
    """
    alpha = 4.0
    eps = np.array([0.10, 0.14, 0.18, 0.22])
    written = oring_case("[" + ", ".join(f'"{100 * e:g} %"' for e in eps) + "]", alpha=1.0)
    q_model = np.repeat(run_band(written, effective=False).critical_junction.leak_rate, 2)
    assert np.isfinite(q_model).all()
    noise = np.exp(0.25 * np.random.default_rng(12).standard_normal(q_model.size))
    q = alpha * q_model * noise
    case = oring_case('"20 %"', alpha=0.7)  # the case's own α and compression do not enter the fit
    fits = fit_models(case, np.repeat(eps, 2), np.full(q.size, np.nan), q)
    cj = fits["critical_junction"]
    assert cj.prediction == pytest.approx(q_model, rel=1e-12, abs=0)
    # the closed form of least squares in ln Q (docs/theory.md §8.1), and the truth within 3 standard errors
    r = np.log(q / q_model)
    assert cj.alpha == pytest.approx(np.exp(r.mean()), rel=1e-12)
    assert cj.alpha_std == pytest.approx(cj.alpha * r.std(ddof=1) / np.sqrt(r.size), rel=1e-10)
    assert abs(cj.alpha - alpha) < 3 * cj.alpha_std and cj.n_used == q.size
    # the effective medium: a factor on its own band prediction, which leaks more than the junction at low squeeze
    em = fits["effective_medium"]
    assert em.fitted and em.n_used == q.size
    assert em.alpha == pytest.approx(np.exp(np.mean(np.log(q / em.prediction))), rel=1e-12, abs=0)
    assert em.prediction[0] == em.prediction[1] and em.prediction[0] > em.prediction[-1] > 0


def test_fit_scales_each_row_with_its_own_pressure_difference(tmp_path):
    case = profile_case(tmp_path, scale="1")
    k = series_conductance(tmp_path, 1.0, alpha=1.0)
    dp = np.array([5e3, np.nan, 4e4])  # NaN: the case's 10 kPa
    q = 0.2 * k * np.array([5e3, 1e4, 4e4])
    fits = fit_models(case, [1.0, 1.0, 1.0], dp, q)
    assert fits["critical_junction"].alpha == pytest.approx(0.2, rel=1e-9)
    assert fits["critical_junction"].rms_log10_residual < 1e-9


def test_fit_of_a_data_file_by_profile_scale(tmp_path):
    case = profile_case(tmp_path, scale="[0.5, 1.0]")
    scales = np.array([0.7, 1.0, 1.4])
    q = 3.0 * np.array([series_conductance(tmp_path, s, alpha=1.0) for s in scales]) * case.pressure_difference
    data = tmp_path / "m.csv"
    data.write_text("profile_scale, leak_rate (m^3/s)\n" + "".join(f"{s}, {v:.17g}\n" for s, v in zip(scales, q)))
    d = read_leak_data(data)
    assert d.load_name == "profile_scale" and np.isnan(d.squeeze_pressure).all()
    result = run_fit(case, d)
    assert result.fits["critical_junction"].alpha == pytest.approx(3.0, rel=1e-9)
    assert result.load_name == "profile_scale"
    # the figure's curve: at α = 1 and the data's ΔP, over the measured scales; the effective medium at the measured ones
    assert result.grid.min() == pytest.approx(0.7) and result.grid.max() == pytest.approx(1.4)
    assert np.array_equal(result.curve_grids["effective_medium"], scales)
    curve_at_1 = np.interp(1.0, result.grid, np.log(result.curves["critical_junction"]))
    assert np.exp(curve_at_1) == pytest.approx(q[1] / 3.0, rel=0.05, abs=0)


# ---------------------------------------------------------------------- data files
@pytest.mark.parametrize("header, values", [("compression (%)", "15\n20\n"), ("compression (1)", "0.15\n0.20\n"),
                                            ("Compression [percent]", "15\n20\n")])
def test_compression_in_percent_or_as_a_fraction(tmp_path, header, values):
    data = tmp_path / "m.csv"
    rows = values.split()
    data.write_text(f"{header}, leak_rate (ml/min)\n" + "".join(f"{r}, 1e-9\n" for r in rows))
    d = read_leak_data(data)
    assert d.load_name == "compression" and np.allclose(d.load, [0.15, 0.20], rtol=1e-14, atol=0)


@pytest.mark.parametrize("text, problem", [
    ("compression, leak_rate (ml/min)\n15, 1e-9\n", "has no unit: write 'compression (%)'"),
    ("compression (1), leak_rate (ml/min)\n0.1, 1e-9\n15, 1e-9\n",
     "line 3, column 'compression': 15 1 is not a compression between 0 and 100 % (as a fraction: for per cent write"),
    ("compression (%), leak_rate (ml/min)\n0, 1e-9\n", "line 2, column 'compression': 0 % is not a compression"),
    ("compression (%), leak_rate (ml/min)\n120, 1e-9\n", "120 % is not a compression between 0 and 100 %"),
    ("compression (mm), leak_rate (ml/min)\n0.3, 1e-9\n", "'mm' is a length"),
    ("profile_scale, leak_rate (ml/min)\n1, 1e-9\n-2, 1e-9\n", "line 3, column 'profile_scale': -2 must be > 0"),
    ("compression (%), squeeze_pressure (kPa), leak_rate (ml/min)\n15, 30, 1e-9\n",
     "columns squeeze_pressure and compression: give one load column"),
    ("leak_rate (ml/min), pressure_difference (kPa)\n1e-9, 10\n",
     "missing column squeeze_pressure (or compression for an O-ring, profile_scale for a pressure profile)"),
])
def test_bad_load_columns(tmp_path, text, problem):
    data = tmp_path / "m.csv"
    data.write_text(text)
    with pytest.raises(FileFormatError) as err:
        read_leak_data(data)
    assert problem in str(err.value) and str(data) in str(err.value)


def test_a_compression_the_oring_relations_refuse_names_its_line(tmp_path):
    data = tmp_path / "m.csv"
    data.write_text("compression (%), leak_rate (ml/min)\n15, 1e-9\n55, 1e-10\n")
    with pytest.raises(FileFormatError) as err:
        run_fit(oring_case('"15 %"'), read_leak_data(data))
    assert "line 3, column 'compression (%)': compression 55 %: must be below 0.5" in str(err.value)


# ---------------------------------------------------------------------- linearity and rig
def test_linearity_slope_of_a_profile_seal_at_its_load(tmp_path):
    case = profile_case(tmp_path, scale="1.2")
    k = series_conductance(tmp_path, 1.2)
    dp = np.array([2e3, 4e3, 6e3, 8e3])
    check = linearity(case, dp, 0.5 * k * dp)
    assert check.load == 1.2 and check.load_name == "profile_scale"
    assert check.model_slopes["critical junction (α = 0.5)"] == pytest.approx(k, rel=1e-9, abs=0)
    assert check.alpha_from_slope == pytest.approx(0.5 * 0.5, rel=1e-9)  # half the case's slope: half its α
    # mean contact pressure of the scaled step: (0.2 × 0.1 + 0.3 × 0.2)/0.5 MPa × 1.2
    assert check.squeeze_pressure == pytest.approx(1.2 * (W1 * P1 + W2 * P2) / (W1 + W2), rel=1e-12)
    several = linearity(profile_case(tmp_path, scale="[1, 2]"), dp, k * dp)
    assert several.model_slopes == {} and "2 values of conditions.profile_scale" in word(several.messages[0])


RIG = """
[rig]
cylinder_diameter = "0.5 mm"
initial_height = "1 m"
final_height = "0.25 m"
"""


def test_rig_of_a_profile_seal_drains_with_the_series_conductance(tmp_path):
    case = profile_case(tmp_path, scale="1.5", alpha=2.0, extra=RIG)
    k = series_conductance(tmp_path, 1.5, alpha=2.0)
    pred = rig_prediction(case)
    name = "critical junction (α = 2)"
    assert pred.conductance[name] == pytest.approx(k, rel=1e-9, abs=0)
    rig = case.rig
    tau = rig.cylinder_area / (k * 1000.0 * 9.80665)  # closed form: H = H0 exp(-t/τ)
    assert pred.time_constant[name] == pytest.approx(tau, rel=1e-9)
    assert pred.drain_time[name] == pytest.approx(tau * np.log(4.0), rel=1e-9)
    col = pred.columns[name]
    assert np.allclose(col.height, exponential_height(rig, k, col.time), rtol=1e-6, atol=1e-9)
    assert col.time_to_final == pytest.approx(drain_time(rig, k, 0.25), rel=1e-6)
    # the band at its load, and its contact force as the rig's load
    assert pred.band is not None and pred.band.band.loads.tolist() == [1.5]
    assert pred.squeeze_pressure == pytest.approx(1.5 * (W1 * P1 + W2 * P2) / (W1 + W2), rel=1e-12)
    assert rig.load == pytest.approx(1.5 * (W1 * P1 + W2 * P2) * LY, rel=1e-12)


def test_rig_of_a_band_seal_needs_one_load_and_no_load_key(tmp_path):
    case = profile_case(tmp_path, scale="[1, 1.5]", extra=RIG)
    with pytest.raises(InputError) as err:
        rig_prediction(case)
    assert err.value.field == "conditions.profile_scale" and "one profile_scale" in str(err.value)
    with pytest.raises(InputError) as err:
        profile_case(tmp_path, extra=RIG + 'load = "3 kg"\n')
    assert err.value.field == "rig.load" and "remove load" in str(err.value)
