"""`sealeak rig` on a pressure-decay test (docs/theory.md §11.7): the ODE against its closed forms through the
JSON, α recovered from synthetic readings, and bad input (one line naming the field, exit 2, nothing written)."""

import json
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from sealeak.cases import example_path
from sealeak.cases.leak_tests import decay_prediction
from sealeak.cases.loader import parse_cases
from sealeak.cases.run import run_case
from sealeak.cli import main
from tests.casefiles import edit

#: A flat ring (area 5.498 cm²) on a self-affine face, air at 20 °C; P0 = 76 N / 5.498 cm² = 138 kPa. The fluid
#: pressure is ignored (K independent of the pressure: the closed forms of docs/theory.md §11.7 hold).
DECAY = edit("""[fluid]
viscosity = "1 mPa*s"
[conditions]
squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]
pressure_difference = "10 kPa"
[theory]
alpha = 0.2
""", """[fluid]
name = "air"
temperature = "20 degC"
[conditions]
squeeze_pressure = "0.3 MPa"
upstream_pressure = "2 bar"
downstream_pressure = "1 bar"
[theory]
alpha = 0.2
rarefaction = "RAREFACTION"
fluid_pressure = "ignored"
[rig]
kind = "pressure-decay"
volume = "0.5 l"
initial_pressure = "P1"
outside_pressure = "P2"
pressure_loss = "LOSS"
load = "76 N"
""", edit('h_rms = "44 um"', 'h_rms = "4 um"', edit('rolloff_wavevector = "9.1e3 1/m"', 'rolloff_wavevector = "2e4 1/m"',
                                                     edit('cutoff_wavelength = "20 um"', 'cutoff_wavelength = "5 um"'))))


def decay_case(tmp_path, rarefaction="no-slip", p1="2 bar", p2="1 bar", loss="5 mbar", name="case.toml", **swap):
    text = DECAY.replace("RAREFACTION", rarefaction).replace('"P1"', f'"{p1}"').replace('"P2"', f'"{p2}"')
    text = text.replace('"LOSS"', f'"{loss}"')
    for old, new in swap.values():
        text = edit(old, new, text)
    path = tmp_path / name
    path.write_text(text)
    return path


def run_json(tmp_path, path, *extra):
    out = tmp_path / "rig.json"
    assert main(["rig", str(path), "--json", str(out), "-q", "--force", *extra]) == 0
    return json.loads(out.read_text())


@pytest.mark.parametrize("p1, p2", [(2e5, 1e5), (1.5e5, 0.0), (3e5, 1e3)])
def test_viscous_decay_matches_closed_form(tmp_path, p1, p2):
    """No-slip flow, Q_pV = (K/2)(P² − P2²): P(t) = P2/tanh(artanh(P2/P1) + K P2 t/(2V)) (1/P = 1/P1 + K t/(2V) for vacuum)."""
    doc = run_json(tmp_path, decay_case(tmp_path, p1=f"{p1:g} Pa", p2=f"{p2:g} Pa", loss=f"{0.3 * (p1 - p2):g} Pa"))
    assert doc["test"]["rarefaction_model"] == "no-slip"
    (model,) = doc["models"].values()
    k, v = model["conductance"], 0.5e-3
    assert k > 0
    t = np.array(model["time"])
    p = np.array(model["pressure"])
    a = k / (2 * v)
    exact = p1 / (1 + a * p1 * t) if p2 == 0 else p2 / np.tanh(np.arctanh(p2 / p1) + a * p2 * t)
    assert np.max(np.abs(p - exact) / exact) < 1e-8
    assert p[-1] < p1 - 0.3 * (p1 - p2)  # the curve goes beyond the pressure loss
    # time to lose ΔP: F(P) = artanh(P2/P)/P2 (1/P for vacuum) rises by K t/(2V)
    pf = p1 - 0.3 * (p1 - p2)
    f = (lambda x: 1 / x) if p2 == 0 else (lambda x: math.atanh(p2 / x) / p2)
    t_loss = (f(pf) - f(p1)) / a
    assert model["time_to_pressure_loss"] == pytest.approx(t_loss, rel=1e-8)
    assert model["time_to_pressure_loss_no_slip"] == pytest.approx(t_loss, rel=1e-12)
    q_std = v * 0.3 * (p1 - p2) / t_loss
    assert model["standard_leak_rate_pv"] == pytest.approx(q_std, rel=1e-8, abs=0)
    assert model["standard_leak_rate_mbar_l_s"] == pytest.approx(10 * q_std, rel=1e-12, abs=0)  # 1 Pa·m³/s = 10 mbar·l/s


def test_small_pressure_difference_is_exponential(tmp_path):
    """P1 − P2 ≪ P2: P − P2 = (P1 − P2) exp(−t K P̄/V), P̄ = (P1 + P2)/2; the viscous law differs at order (P1 − P2)/P2."""
    p1, p2 = 100001.0, 1e5
    doc = run_json(tmp_path, decay_case(tmp_path, p1=f"{p1:.6f} Pa", p2=f"{p2:g} Pa", loss="0.5 Pa"))
    (model,) = doc["models"].values()
    k, v = model["conductance"], 0.5e-3
    t, p = np.array(model["time"]), np.array(model["pressure"])
    exact = p2 + (p1 - p2) * np.exp(-t * k * 0.5 * (p1 + p2) / v)
    assert np.max(np.abs(p - exact) / p) < 1e-8
    assert model["time_to_pressure_loss"] == pytest.approx(v / (k * 0.5 * (p1 + p2)) * math.log(2.0), rel=1e-4)


def test_rarefaction_speeds_the_decay(tmp_path):
    """With the slip model the same seal leaks faster (f(Kn) >= 1) and the JSON reports Kn and the regime."""
    slip = run_json(tmp_path, decay_case(tmp_path, rarefaction="beskok-karniadakis"))
    (model,) = slip["models"].values()
    assert model["knudsen_number"] > 0.01 and model["flow_regime"] in ("slip", "transition")
    assert model["time_to_pressure_loss"] < model["time_to_pressure_loss_no_slip"]
    assert model["initial_leak_rate_mbar_l_s"] == pytest.approx(10 * model["initial_leak_rate_pv"], rel=1e-12, abs=0)


@pytest.mark.parametrize("alpha_true, noise", [(0.37, 0.0), (1.3, 0.0), (0.6, 2e-3)])
def test_alpha_from_synthetic_readings(tmp_path, capsys, alpha_true, noise):
    """Readings made by integrating V dP/dt = −α K1 ∫ p f(Kn) dp by hand give back α (K1 = K/α_case, same gap)."""
    path = decay_case(tmp_path, rarefaction="beskok-karniadakis")
    doc = run_json(tmp_path, path)
    (model,) = doc["models"].values()
    k1, gap, v = model["conductance"] / 0.2, model["gap"], 0.5e-3
    mu, molar = doc["test"]["viscosity"], doc["test"]["molar_mass"]
    c = mu * math.sqrt(0.5 * math.pi * 8.314462618 / molar * 293.15) / gap  # λ p / h
    a0 = 64 / (15 * math.pi)

    def f(p):  # Beskok–Karniadakis, written out: (1 + α Kn)(1 + 6 Kn/(1 + Kn))
        kn = c / p
        return (1 + a0 * 2 / math.pi * math.atan(4 * kn**0.4) * kn) * (1 + 6 * kn / (1 + kn))

    def rhs(t, y):
        return [-alpha_true * k1 * quad(lambda p: p * f(p), 1e5, y[0], epsrel=1e-12)[0] / v]

    t_end = 3 * model["time_to_pressure_loss"] / alpha_true
    t = np.linspace(0, t_end, 12)
    p = solve_ivp(rhs, (0, t_end), [2e5], t_eval=t, rtol=1e-11, atol=1e-9).y[0]
    p = p + noise * (p[0] - p[-1]) * np.random.default_rng(5).standard_normal(p.size)
    data = tmp_path / "readings.csv"
    data.write_text("time (min), pressure (mbar)\n" + "\n".join(f"{a / 60:.12g}, {b / 100:.12g}" for a, b in zip(t, p)) + "\n")
    doc = run_json(tmp_path, path, "--readings", str(data))
    (scale,) = doc["readings"]["scale"].values()
    if noise == 0:
        assert scale["alpha"] == pytest.approx(alpha_true, rel=1e-6)
    else:
        assert abs(scale["alpha"] - alpha_true) < 4 * scale["alpha_std"]
    # the leak rate over the readings is V (P_first − P_last)/(t_last − t_first)
    assert doc["readings"]["leak_rate_pv"] == pytest.approx(v * (p[0] - p[-1]) / t_end, rel=1e-9, abs=0)
    main(["rig", str(path), "--readings", str(data)])
    text = capsys.readouterr().out
    assert "α implied by the readings" in text and "mbar·l/s" in text


BAD = [
    ("initial pressure below outside", dict(p1="0.9 bar"), "rig.initial_pressure"),
    ("negative volume", dict(swap=('volume = "0.5 l"', 'volume = "-0.5 l"')), "rig.volume"),
    ("volume without unit", dict(swap=('volume = "0.5 l"', 'volume = 0.5')), "rig.volume"),
    ("a liquid", dict(swap=('name = "air"', 'name = "water"'), swap2=('rarefaction = "no-slip"\n', '')), "fluid.name"),
    ("loss beyond the difference", dict(loss="2 bar"), "rig.pressure_loss"),
    ("key of the water column", dict(swap=('volume = "0.5 l"', 'volume = "0.5 l"\ninitial_height = "1 m"')), "rig.initial_height"),
]


@pytest.mark.parametrize("what, change, field", BAD, ids=[b[0] for b in BAD])
def test_bad_case_one_line_exit_2(tmp_path, capsys, what, change, field):
    path = decay_case(tmp_path, **change)
    out = tmp_path / "out.json"
    out.write_text("old")
    assert main(["rig", str(path), "--json", str(out), "--force", "--plots", str(tmp_path / "plots")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err and field in err, err
    assert out.read_text() == "old" and not (tmp_path / "plots").exists()


@pytest.mark.parametrize("header, why", [("time (min), pressure (cm)", "pressure"), ("time (mbar), pressure (mbar)", "time"),
                                         ("time (s), height (cm)", "pressure")])
def test_bad_readings_one_line_exit_2(tmp_path, capsys, header, why):
    path = decay_case(tmp_path)
    data = tmp_path / "r.csv"
    data.write_text(header + "\n0, 2000\n10, 1999\n20, 1998\n")
    out = tmp_path / "out.json"
    assert main(["rig", str(path), "--readings", str(data), "--json", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err and "r.csv" in err and why in err, err
    assert not out.exists()


def _same_pressures(text):
    """The case's squeeze pressure set to the rig's P0 = load/area, so that predict and the rig see the same seal."""
    case = parse_cases(text)[0]
    p0 = case.rig.squeeze_pressure(case.seal)
    return parse_cases(text.replace('squeeze_pressure = "0.3 MPa"', f'squeeze_pressure = "{p0!r} Pa"'))[0]


@pytest.mark.parametrize("fluid_pressure", ["coupled", "ignored"])
@pytest.mark.parametrize("rarefaction", ["kinetic", "no-slip"])
def test_initial_leak_is_predicts_gas_leak(tmp_path, fluid_pressure, rarefaction):
    """The rig's leak at t = 0 (P1 against P2) is predict's gas leak at the same pressures, for both models: the same
    slit length λc and, with the fluid pressure coupled, the same exact gas coupling (docs/theory.md §11.7.1, §13.5)."""
    text = decay_case(tmp_path, rarefaction).read_text().replace('fluid_pressure = "ignored"',
                                                                 f'fluid_pressure = "{fluid_pressure}"')
    case = _same_pressures(text.replace('alpha = 0.2\n', 'alpha = 0.2\nmodel = "both"\n', 1))
    gas = run_case(case).gas
    assert gas is not None
    rig = decay_prediction(case)
    for name, model in rig.models.items():
        rows = gas["critical_junction" if name.startswith("critical") else "effective_medium"]
        assert model.initial_leak is not None and rows.leaks is not None and rows.leaks[0] is not None
        assert model.initial_leak.throughput == pytest.approx(rows.leaks[0].throughput, rel=1e-6, abs=0)
        assert model.decay.throughput[0] == pytest.approx(rows.leaks[0].throughput, rel=1e-6, abs=0)


def test_band_rig_initial_leak_is_predicts_gas_leak():
    """An O-ring at one compression, tested by pressure decay at predict's pressures (helium, 1 bar against vacuum):
    the rig's coupled throughput, interpolated in P, is exact at P1."""
    text = example_path("helium-test").read_text(encoding="utf-8").replace(
        'compression = ["10 %", "15 %", "20 %", "25 %"]', 'compression = "15 %"') + (
        '\n[rig]\nkind = "pressure-decay"\nvolume = "0.1 l"\ninitial_pressure = "1 bar"\noutside_pressure = "0 Pa"\n'
        'pressure_loss = "1 mbar"\n')
    case = parse_cases(text)[0]
    rows = run_case(case).gas["critical_junction"]
    (model,) = decay_prediction(case).models.values()
    assert model.initial_leak.throughput == pytest.approx(rows.leaks[0].throughput, rel=1e-6, abs=0)
    # the interpolated Q(P) below P1 lies between 0 and Q(P1) and falls with P
    q = model.decay.throughput
    assert np.all(np.diff(q) < 0) and q[-1] > 0


@pytest.mark.parametrize("load, opens", [("40 N", True), ("165 N", False)])
def test_a_coupled_decay_test_notes_where_the_gas_opens_the_seal(load, opens, capsys):
    """The fluid pressure coupled (the default), a test whose P1 − P2 reaches P0 lifts the seal: said, where nothing
    was (the note was kept for the fluid pressure ignored)."""
    text = example_path("pressure-decay").read_text().replace('load = "165 N"', f'load = "{load}"')
    (case,) = parse_cases(text)
    assert case.coupled
    words = " ".join(str(m) for m in decay_prediction(case).messages)
    assert ("decay_pressure_difference_large" in words) == opens, words
    assert main(["rig", "--example", "pressure-decay"]) == 0 and "lift-off" not in capsys.readouterr().out


@pytest.mark.parametrize("load, flagged", [("165 N", False), ("60 N", True)])
def test_an_uncoupled_decay_test_flags_a_large_pressure_difference_where_predict_does(load, flagged):
    """With the fluid pressure ignored, P1 − P2 = 1 bar against P0 = 3.0 bar (165 N) is not flagged by predict, the
    fit or the other rigs (ΔP/P0 = 0.33 is below their ratio 1/2); the pressure-decay rig flagged it at 1/10. Against
    P0 = 1.09 bar (60 N) every one of them flags it."""
    text = example_path("pressure-decay").read_text().replace('load = "165 N"', f'load = "{load}"').replace(
        "[theory]", '[theory]\nfluid_pressure = "ignored"')
    (case,) = parse_cases(text)
    assert not case.coupled
    decay = decay_prediction(case)
    ratio = 1e5 / decay.squeeze_pressure  # (P1 − P2: 2 bar − 1 bar, as the example gives them)
    assert (ratio > 0.5) == flagged, ratio
    assert any(m.code == "decay_pressure_difference_large" for m in decay.messages) == flagged
