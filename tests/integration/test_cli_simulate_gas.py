"""``sealeak simulate`` on a gas case: the gas flow through the simulated gap fields and α_gas beside α.

Small grids through the command line. The checks are relations the physics fixes, not numbers of a
previous run: without rarefaction the p² problem has the liquid's conductance, so α_gas = α and
Q_pV = Q P̄ exactly (docs/theory.md §11.3); with slip the same gap fields pass more gas; the units
follow from R and the molar mass; bad gas inputs are refused in one line with exit status 2.
"""

import json
import math

import numpy as np
import pytest

from sealeak.cli import main
from sealeak.physics.gas import pressure_integral
from sealeak.physics.properties import fluid_state
from tests.casefiles import BASE, edit

R = 8.314462618  # J/(mol K)
M_HELIUM = 4.002602e-3  # kg/mol (IUPAC)
PA, PB, T = 1e5, 0.0, 293.15

GAS = edit('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "helium"\ntemperature = "20 degC"',
           edit('pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"',
                edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "0.1 MPa"]')))
NO_SLIP = edit("alpha = 0.2", 'alpha = 0.2\nrarefaction = "no-slip"', GAS)
OPTIONS = ["--grid", "32", "--realizations", "2", "--seed", "5", "--no-threshold"]


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
    tmp = tmp_path_factory.mktemp("gas")
    return _run(tmp, GAS, "--plots", str(tmp / "plots")), tmp


@pytest.fixture(scope="module")
def no_slip(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("noslip"), NO_SLIP, "-q")


def test_without_rarefaction_alpha_gas_is_the_liquid_alpha(no_slip):
    """No slip: ∇·(g³∇p²) = 0 has the liquid's conductance K, so Q_pV = K (P_a² − P_b²)/2 = (K ΔP) P̄ for the
    simulation and the theory alike, and α_gas = α."""
    mean = 0.5 * (PA + PB)
    assert np.all(_rows(no_slip, "percolating_fraction") == 1.0)
    assert np.allclose(_rows(no_slip, "leak_rate_pv"), _rows(no_slip, "leak_rate") * mean, rtol=1e-6)
    assert np.allclose(_rows(no_slip, "leak_rate_pv_critical_junction"), _rows(no_slip, "leak_rate_critical_junction") * mean,
                       rtol=1e-9)
    assert np.allclose(_rows(no_slip, "alpha_gas"), _rows(no_slip, "alpha"), rtol=1e-6)
    assert np.all(_rows(no_slip, "gas_iterations") == 0) and np.allclose(_rows(no_slip, "slip_gain"), 1.0, rtol=1e-12)
    assert no_slip["gas"]["rarefaction"] == "no-slip"


def test_rarefaction_adds_flow_through_the_same_gap_fields(slip, no_slip):
    doc, _ = slip
    # the same seeds give the same surfaces: the liquid columns do not depend on the rarefaction model
    assert _rows(doc, "leak_rate").tolist() == _rows(no_slip, "leak_rate").tolist()
    ratio = _rows(doc, "leak_rate_pv") / _rows(no_slip, "leak_rate_pv")
    assert np.all(ratio > 1.0)
    assert np.all(_rows(doc, "slip_gain") > 1.0)  # its mean over realisations (of Q_pV / Q_pV without slip)
    assert np.all(_rows(doc, "gas_iterations") >= 2)
    # Kn at u_c and the mean pressure, helium at 50 kPa: λ = (μ/p) √(π R T/(2M))
    assert np.all(_rows(doc, "knudsen_number") > 0) and {r["flow_regime"] for r in doc["results"]} <= {
        "continuum", "slip", "transition", "free molecular"}


def test_gas_units_follow_from_r_and_the_molar_mass(slip):
    doc, _ = slip
    pv = _rows(doc, "leak_rate_pv")
    assert np.allclose(_rows(doc, "leak_rate_mass"), pv * M_HELIUM / (R * T), rtol=1e-4)
    assert np.allclose(_rows(doc, "leak_rate_molar"), pv / (R * T), rtol=1e-9)
    assert np.allclose(_rows(doc, "leak_rate_mbar_l_s"), pv * 10.0, rtol=1e-12)
    assert doc["units"]["leak_rate_pv"] == "Pa*m^3/s" and doc["units"]["leak_rate_mass"] == "kg/s"
    assert doc["gas"]["name"] == "helium" and doc["gas"]["temperature"] == pytest.approx(T)
    assert (doc["gas"]["upstream_pressure"], doc["gas"]["downstream_pressure"]) == (PA, PB)
    alpha = _rows(doc, "alpha_gas")
    assert np.allclose(alpha, pv / _rows(doc, "leak_rate_pv_critical_junction"), rtol=1e-9, equal_nan=True)


def test_table_and_figures_show_the_gas(slip, capsys):
    doc, tmp = slip
    names = sorted(p.name for p in (tmp / "plots").iterdir())
    assert names == sorted(["simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png", "simulate_gas_leak_rate.png"])
    assert all(p.stat().st_size > 10_000 for p in (tmp / "plots").iterdir())
    case = tmp / "case.toml"
    assert main(["simulate", str(case), *OPTIONS, "-q"]) == 0  # -q: nothing printed
    assert capsys.readouterr().out == ""
    assert main(["simulate", str(case), "--grid", "16", "--realizations", "1", "--no-threshold"]) == 0
    out = capsys.readouterr().out
    assert "gas leak of helium, 100 kPa → 0 kPa (absolute)" in out
    for column in ("Kn at u_c", "Q_pV sim (Pa·m³/s)", "Q (mbar·l/s)", "ṁ (kg/s)", "slip gain", "Q_pV cj α=1", "α_gas"):
        assert column in out, column
    assert "incompressible formula with the gas's viscosity" in out


def test_a_liquid_case_has_no_gas_columns(tmp_path):
    doc = _run(tmp_path, BASE, "--plots", str(tmp_path / "plots"))
    assert "gas" not in doc and "leak_rate_pv" not in doc["results"][0] and "alpha_gas" not in doc["units"]
    assert not (tmp_path / "plots" / "simulate_gas_leak_rate.png").exists()


@pytest.mark.parametrize("old, new, names", [
    ('upstream_pressure = "1 bar"\n', "", ["conditions.upstream_pressure"]),
    ('downstream_pressure = "0 Pa"', 'downstream_pressure = "2 bar"', ["conditions.upstream_pressure", "downstream"]),
    ('downstream_pressure = "0 Pa"', 'downstream_pressure = "1 bar"', ["conditions.upstream_pressure"]),
    ('upstream_pressure = "1 bar"', 'upstream_pressure = "-1 bar"', ["conditions.upstream_pressure"]),
    ('name = "helium"', 'name = "heluim"', ["fluid.name", "helium", "nitrogen"]),
    ('temperature = "20 degC"', "temperature = 20", ["fluid.temperature"]),
    ('temperature = "20 degC"', 'temperature = "-300 degC"', ["fluid.temperature"]),
])
def test_bad_gas_input_one_line_exit_2_nothing_written(old, new, names, tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(edit(old, new, GAS))
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


def test_helium_mean_free_path_sets_the_reported_knudsen_number(slip):
    """Kn = λ(P̄)/u_c: the ratio of Kn at two squeeze pressures is the inverse ratio of their critical gaps, which the
    liquid Q_cj ∝ u_c³ carries: Kn1/Kn2 = (Q_cj2/Q_cj1)^(1/3)."""
    doc, _ = slip
    kn = _rows(doc, "knudsen_number")
    q = _rows(doc, "leak_rate_critical_junction")
    assert kn[0] / kn[1] == pytest.approx(math.pow(q[1] / q[0], 1 / 3), rel=1e-9)


def test_theory_column_is_a_slit_of_the_critical_wavelength(slip):
    """The theory's gas leak is predict's: K ∫ p f dp through a slit of height u_c and length λc, whose kinetic
    free-molecular flow is capped (docs/theory.md §11.4); against vacuum an infinite slit's f grows without bound as
    p → 0, so the capped slit passes less."""
    doc, _ = slip
    he = fluid_state("helium", T, PA).gas()
    grid, size = doc["settings"]["grid"], doc["settings"]["size"]
    for row in doc["results"]:
        if row["leak_rate_pv_critical_junction"] is None:
            continue
        k = row["leak_rate_critical_junction"] / (PA - PB)
        gap = float(he.mean_free_path(0.5 * (PA + PB))) / row["knudsen_number"]
        lam_c = size * row["junction_cells"] / grid  # λc = L/ζc, the cells N/ζc
        capped = k * pressure_integral(gap, he, PA, PB, "kinetic", lam_c)
        assert row["leak_rate_pv_critical_junction"] == pytest.approx(capped, rel=1e-9)
        # the test's gaps (tens of µm) are nearly continuum: the cap is small here, but well above the tolerance
        assert abs(k * pressure_integral(gap, he, PA, PB, "kinetic") / capped - 1) > 1e-7
