"""``sealeak simulate`` on a gas O-ring: the gas flow across the simulated band, its series-resistance gas leak, α_gas.

Tiny grids through the command line. The checks are relations the physics fixes, not numbers of a previous
run: without rarefaction the p² problem across the band has the liquid's conductance, so Q_pV = Q P̄ for the
simulation and for the series-resistance theory alike and α_gas = α (docs/theory.md §11.3, §11.10); with slip
the same gap fields pass more gas; the units follow from R and the molar mass; bad gas inputs are refused in
one line with exit status 2 and nothing written.
"""

import contextlib
import io
import json

import numpy as np
import pytest

from sealeak.cli import main

R = 8.314462618  # J/(mol K)
M_HELIUM = 4.002602e-3  # kg/mol (IUPAC)
T = 293.15

ORING = """
title = "O-ring on a rough face, helium"
[surface]
model = "self-affine"
h_rms = "20 um"
hurst = 0.8
rolloff_wavelength = "0.3 mm"
cutoff_wavelength = "5 um"
[rubber]
youngs_modulus = "5 MPa"
poisson_ratio = 0.5
[seal]
shape = "o-ring"
cross_section_diameter = "2.62 mm"
inner_diameter = "20 mm"
[fluid]
name = "helium"
temperature = "20 degC"
[conditions]
compression = ["3 %", "5 %"]
upstream_pressure = "1 bar"
downstream_pressure = "0 Pa"
"""
NO_SLIP = ORING + '[theory]\nrarefaction = "no-slip"\n'
OPTIONS = ["--grid", "48", "--realizations", "2", "--seed", "3"]


def _run(tmp, text, *extra):
    case = tmp / "case.toml"
    case.write_text(text)
    js = tmp / "res.json"
    assert main(["simulate", str(case), "--json", str(js), *OPTIONS, *extra]) == 0
    return json.loads(js.read_text())


def _rows(doc, key):
    return np.array([np.nan if r[key] is None else r[key] for r in doc["results"]], dtype=float)


@pytest.fixture(scope="module")
def slip(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("gasoring")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        doc = _run(tmp, ORING, "--plots", str(tmp / "plots"))
    return doc, tmp, out.getvalue()


@pytest.fixture(scope="module")
def no_slip(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("gasoring-noslip"), NO_SLIP, "-q")


def test_without_rarefaction_the_gas_leak_is_the_liquid_one_times_the_mean_pressure(no_slip):
    """No slip: ∇·(g³∇p²) = 0 across the band has the liquid's conductance K, so Q_pV = K (P_a² − P_b²)/2 = Q P̄ for the
    simulation and for the series-resistance theory (K = Q_sr/ΔP, the same rarefaction-free channel), and α_gas = α."""
    mean = 0.5 * (1e5 + 0.0)
    assert np.all(_rows(no_slip, "percolating_fraction") == 1.0)  # the checks below compare real channels
    assert np.all(np.isfinite(_rows(no_slip, "alpha")))
    assert np.allclose(_rows(no_slip, "leak_rate_pv"), _rows(no_slip, "leak_rate") * mean, rtol=1e-6)
    assert np.allclose(_rows(no_slip, "leak_rate_pv_series_resistance"),
                       _rows(no_slip, "leak_rate_series_resistance") * mean, rtol=1e-9)
    assert np.allclose(_rows(no_slip, "alpha_gas"), _rows(no_slip, "alpha"), rtol=1e-6)
    assert np.all(_rows(no_slip, "gas_iterations") == 0) and np.allclose(_rows(no_slip, "slip_gain"), 1.0, rtol=1e-12)
    assert no_slip["gas"]["rarefaction"] == "no-slip"


def test_rarefaction_adds_flow_through_the_same_gap_fields(slip, no_slip):
    doc, _, _ = slip
    # the same seeds give the same surfaces and contacts: the liquid columns do not depend on the rarefaction model
    for key in ("leak_rate", "leak_rate_series_resistance", "contact_width"):
        assert _rows(doc, key).tolist() == _rows(no_slip, key).tolist(), key
    assert np.all(_rows(doc, "leak_rate_pv") > _rows(no_slip, "leak_rate_pv"))
    assert np.all(_rows(doc, "leak_rate_pv_series_resistance") > _rows(no_slip, "leak_rate_pv_series_resistance"))
    assert np.all(_rows(doc, "slip_gain") > 1.0)
    assert np.all(_rows(doc, "gas_iterations") >= 2)
    # Kn = λ(P̄)/u_c at the peak pressure grows with the load as the gap there closes
    kn = _rows(doc, "knudsen_number")
    assert np.all(kn > 0) and kn[1] > kn[0]
    assert {r["flow_regime"] for r in doc["results"]} <= {"continuum", "slip", "transition", "free molecular"}


def test_gas_units_follow_from_r_and_the_molar_mass(slip):
    doc, _, _ = slip
    pv = _rows(doc, "leak_rate_pv")
    assert np.allclose(_rows(doc, "leak_rate_mass"), pv * M_HELIUM / (R * T), rtol=1e-4)
    assert np.allclose(_rows(doc, "leak_rate_molar"), pv / (R * T), rtol=1e-9)
    assert np.allclose(_rows(doc, "leak_rate_mbar_l_s"), pv * 10.0, rtol=1e-12)  # 1 Pa·m³/s = 10 mbar·l/s
    units = doc["units"]
    assert units["leak_rate_pv"] == units["leak_rate_pv_series_resistance"] == "Pa*m^3/s"
    assert units["leak_rate_mass"] == "kg/s" and units["alpha_gas"] == "1"
    assert doc["gas"]["name"] == "helium" and doc["gas"]["temperature"] == pytest.approx(T)
    alpha = _rows(doc, "alpha_gas")
    assert np.allclose(alpha, pv / _rows(doc, "leak_rate_pv_series_resistance"), rtol=1e-9, equal_nan=True)


def test_the_gas_leak_scales_with_the_seal_line(no_slip, tmp_path):
    """Q_pV of the seal is the strip's times faces · Ly / W: doubling the faces doubles it and its series-resistance
    prediction alike, and leaves α_gas."""
    two = _run(tmp_path, NO_SLIP.replace('inner_diameter = "20 mm"', 'inner_diameter = "20 mm"\nfaces = 2'), "-q")
    for key in ("leak_rate_pv", "leak_rate_pv_series_resistance"):
        assert np.allclose(_rows(two, key), 2.0 * _rows(no_slip, key), rtol=1e-12), key
    assert np.allclose(_rows(two, "alpha_gas"), _rows(no_slip, "alpha_gas"), rtol=1e-12)


def test_table_and_figures_show_the_gas(slip):
    doc, tmp, out = slip
    names = sorted(p.name for p in (tmp / "plots").iterdir())
    assert names == sorted(["simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png", "simulate_band_pressure.png",
                            "simulate_gas_leak_rate.png"])
    assert all(p.stat().st_size > 10_000 for p in (tmp / "plots").iterdir())
    assert "Gas leak across the band: helium, 100 kPa → 0 kPa (absolute), 20 °C" in out
    for column in ("Kn at u_c", "Q_pV sim (Pa·m³/s)", "Q (mbar·l/s)", "ṁ (kg/s)", "slip gain", "Q_pV series α=1", "α_gas"):
        assert column in out, column
    assert "incompressible formula with the gas's viscosity" in out
    assert "simulated for uniform seals only" not in out and "simulated as a liquid" not in out


def test_a_liquid_oring_has_no_gas_columns(tmp_path):
    liquid = ORING.replace('name = "helium"\ntemperature = "20 degC"', 'viscosity = "1 mPa*s"').replace(
        'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"', 'pressure_difference = "1 bar"')
    doc = _run(tmp_path, liquid, "-q", "--realizations", "1", "--plots", str(tmp_path / "plots"))
    assert "gas" not in doc and "leak_rate_pv" not in doc["results"][0] and "alpha_gas" not in doc["units"]
    assert not (tmp_path / "plots" / "simulate_gas_leak_rate.png").exists()


@pytest.mark.parametrize("old, new, names", [
    ('upstream_pressure = "1 bar"\n', "", ["conditions.upstream_pressure"]),
    ('downstream_pressure = "0 Pa"', 'downstream_pressure = "2 bar"', ["conditions.upstream_pressure", "downstream"]),
    ('upstream_pressure = "1 bar"', 'upstream_pressure = "-1 bar"', ["conditions.upstream_pressure"]),
    ('name = "helium"', 'name = "heluim"', ["fluid.name", "helium", "nitrogen"]),
    ('temperature = "20 degC"', "temperature = 20", ["fluid.temperature"]),
    ("[fluid]", '[theory]\nrarefaction = "slippy"\n[fluid]', ["rarefaction", "beskok-karniadakis"]),
])
def test_bad_gas_input_one_line_exit_2_nothing_written(old, new, names, tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(ORING.replace(old, new, 1))
    js = tmp_path / "res.json"
    js.write_text("earlier\n")
    plots = tmp_path / "plots"
    rc = main(["simulate", str(case), "--json", str(js), "--plots", str(plots), "--force", "--grid", "16"])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for name in names:
        assert name in err, (name, err)
    assert js.read_text() == "earlier\n" and not plots.exists()
