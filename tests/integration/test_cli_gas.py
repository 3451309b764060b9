"""Gases in case files through the command line (issue 13): predict's gas fields and the bad inputs.

The checks compare the gas fields of ``predict --json`` with formulas evaluated here: the no-slip
limit Q_pV = K (P_a² − P_b²)/2 (docs/theory.md §11.3), the units (mbar·l/s, sccm, mol/s, kg/s), the
helium equivalent against :func:`sealeak.physics.gas.gas_leak` called by hand, and the limit ΔP ≪ P
where the gas leak is the liquid formula with the gas's viscosity.
"""

import json
import re
from pathlib import Path

import pytest

from sealeak.cases import example_path
from sealeak.cli import main
from sealeak.physics.gas import Gas, gas_leak, slip_factor
from sealeak.physics.properties import fluid_state
from tests.casefiles import BASE, edit
from tests.cli_errors import one_line_error

R = 6.02214076e23 * 1.380649e-23  # J/(mol K), exact

#: The base case with helium between two absolute pressures, at squeeze pressures where it leaks; the fluid pressure
#: is ignored, so that K does not depend on the pressure and the formulas of docs/theory.md §11 hold as written
#: (the coupled gas leak, §13.5: tests/unit/test_gas_coupling.py and the last test here).
GAS_BASE = edit("alpha = 0.2", 'alpha = 0.2\nfluid_pressure = "ignored"', BASE)
GAS = edit('viscosity = "1 mPa*s"', 'name = "helium"',
           edit('pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"',
                edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["0.3 MPa", "0.5 MPa"]',
                     GAS_BASE)))


def gas_case(fluid="helium", upstream="1 bar", downstream="0 Pa", extra_theory="", extra_fluid=""):
    text = edit('name = "helium"', f'name = "{fluid}"' + extra_fluid, GAS)
    text = edit('upstream_pressure = "1 bar"', f'upstream_pressure = "{upstream}"', text)
    text = edit('downstream_pressure = "0 Pa"', f'downstream_pressure = "{downstream}"', text)
    return edit("alpha = 0.2", "alpha = 0.2" + extra_theory, text)


def predict_json(tmp_path, capsys, text):
    case = tmp_path / "case.toml"
    case.write_text(text)
    out = tmp_path / "out.json"
    assert main(["predict", str(case), "--json", str(out), "--force"]) == 0
    capsys.readouterr()
    return json.loads(out.read_text())


def leaking(doc):
    rows = [r for r in doc["results"] if r["percolates"]]
    assert rows, "the test case must leak at some squeeze pressure"
    return rows


@pytest.mark.parametrize("fluid, upstream, downstream", [("helium", "1 bar", "0 Pa"), ("nitrogen", "5 bar", "1 bar"),
                                                         ("air", "101325 Pa", "50 kPa")])
def test_no_slip_throughput_is_k_times_half_the_difference_of_squares(tmp_path, capsys, fluid, upstream, downstream):
    doc = predict_json(tmp_path, capsys, gas_case(fluid, upstream, downstream, '\nrarefaction = "no-slip"'))
    pa, pb = (float(v.split()[0]) * {"bar": 1e5, "Pa": 1.0, "kPa": 1e3}[v.split()[1]] for v in (upstream, downstream))
    for rec in leaking(doc):
        k = rec["leak_rate"] / rec["pressure_difference"]  # the liquid law's K = Q/ΔP, with the gas's viscosity
        assert rec["pressure_difference"] == pytest.approx(pa - pb, rel=1e-12)
        assert rec["leak_rate_pv"] == pytest.approx(k * (pa**2 - pb**2) / 2, rel=1e-10, abs=0)
        assert rec["flow_regime"] in ("continuum", "slip", "transition", "free molecular")


@pytest.mark.parametrize("ratio", [1e-2, 1e-3])
def test_small_pressure_drop_tends_to_the_liquid_formula_with_the_gas_viscosity(tmp_path, capsys, ratio):
    """ΔP ≪ P: Q_pV/p_mean → K ΔP f(Kn_mean), K with the gas's viscosity (a liquid case run with μ of the gas)."""
    pa = 20e5
    pb = pa * (1 - ratio)
    gas = predict_json(tmp_path, capsys, gas_case("nitrogen", f"{pa} Pa", f"{pb} Pa"))
    mu = fluid_state("nitrogen", 293.15, pa).viscosity
    liquid_text = edit('pressure_difference = "10 kPa"', f'pressure_difference = "{pa - pb} Pa"',
                       edit('viscosity = "1 mPa*s"', f'viscosity = "{mu!r} Pa*s"',
                            edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                                 'squeeze_pressure = ["0.3 MPa", "0.5 MPa"]', GAS_BASE)))
    liquid = predict_json(tmp_path, capsys, liquid_text)
    pm = 0.5 * (pa + pb)
    for g, q in zip(gas["results"], liquid["results"]):
        if not q["percolates"]:
            continue
        f = float(slip_factor(g["knudsen_number"]))
        assert g["leak_rate_pv"] / pm == pytest.approx(q["leak_rate"] * f, rel=10 * ratio**2, abs=0)
        assert 1.0 < f < 1.2  # slip, not continuum: the comparison is not trivial


def test_unit_columns_agree_with_each_other(tmp_path, capsys):
    doc = predict_json(tmp_path, capsys, gas_case("argon", "3 bar", "1 bar"))
    molar_mass = fluid_state("argon", 293.15, 3e5).molar_mass
    for rec in leaking(doc):
        pv = rec["leak_rate_pv"]
        assert rec["leak_rate_mbar_l_s"] == pytest.approx(pv * 10, rel=1e-12, abs=0)  # 1 mbar·l/s = 0.1 Pa·m³/s
        assert rec["leak_rate_molar"] == pytest.approx(pv / (R * 293.15), rel=1e-12, abs=0)
        assert rec["leak_rate_mass"] == pytest.approx(rec["leak_rate_molar"] * molar_mass, rel=1e-12, abs=0)
        # sccm: cm³/min of the gas at 0 °C and 101325 Pa
        assert rec["leak_rate_sccm"] == pytest.approx(rec["leak_rate_molar"] * R * 273.15 / 101325 * 1e6 * 60, rel=1e-12)
    assert doc["units"]["leak_rate_pv"] == "Pa*m^3/s" and doc["units"]["leak_rate_mass"] == "kg/s"
    assert doc["units"]["leak_rate_sccm"] == "sccm" and doc["units"]["knudsen_number"] == "1"


def _helium_by_hand(k_case, mu_case, gap, length):
    """The helium leak of the same seal; ``length`` λ_c caps the kinetic model's free-molecular flow."""
    he = fluid_state("helium", 293.15, 1e5)
    gas = Gas("helium", 293.15, he.viscosity, he.molar_mass)
    return gas_leak(k_case * mu_case / he.viscosity, gap, gas, 1e5, 0.0, length=length).throughput


def test_helium_equivalent_of_a_gas_case_is_gas_leak_of_helium(tmp_path, capsys):
    doc = predict_json(tmp_path, capsys, gas_case("nitrogen", "2 bar", "1 bar", '\nmodel = "both"'))
    mu = doc["cases"][0]["fluid"]["viscosity"]
    for rec in leaking(doc):
        expected = _helium_by_hand(rec["leak_rate"] / rec["pressure_difference"], mu, rec["critical_gap"],
                                   rec["critical_wavelength"])
        assert rec["leak_rate_helium_pv"] == pytest.approx(expected, rel=1e-12, abs=0)
        assert rec["leak_rate_helium_mbar_l_s"] == pytest.approx(10 * expected, rel=1e-12, abs=0)
        k_em = rec["leak_rate_effective_medium"] / rec["pressure_difference"]  # K = Q/ΔP (fluid pressure coupled)
        expected_em = _helium_by_hand(k_em, mu, rec["effective_gap"], rec["critical_wavelength"])
        assert rec["leak_rate_helium_pv_effective_medium"] == pytest.approx(expected_em, rel=1e-9)
        assert rec["leak_rate_pv_effective_medium"] > 0


def _liquid_with_helium_equivalent(base):
    return edit('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nhelium_equivalent = true',
                edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["0.3 MPa", "0.5 MPa"]',
                     base))


def test_helium_equivalent_of_a_liquid_when_asked(tmp_path, capsys):
    doc = predict_json(tmp_path, capsys, _liquid_with_helium_equivalent(GAS_BASE))
    for rec in leaking(doc):
        expected = _helium_by_hand(rec["leak_rate"] / rec["pressure_difference"], 1e-3, rec["critical_gap"],
                                   rec["critical_wavelength"])
        assert rec["leak_rate_helium_mbar_l_s"] == pytest.approx(10 * expected, rel=1e-12, abs=0)
        assert "leak_rate_pv" not in rec  # a liquid has no gas throughput of its own
    plain = predict_json(tmp_path, capsys, BASE)
    assert not any(k.startswith("leak_rate_helium") for k in plain["units"])


def test_coupled_helium_equivalent_is_the_helium_test_of_the_same_seal(tmp_path, capsys):
    """With the fluid pressure coupled (the default), the helium equivalent of a liquid case is the exact gas coupling
    of helium at 1 bar against vacuum (docs/theory.md §13.5): the gas leak of a helium case with the same seal, not
    the liquid's K at its own ΔP."""
    liquid = predict_json(tmp_path, capsys, _liquid_with_helium_equivalent(BASE))
    helium = predict_json(tmp_path, capsys, edit('fluid_pressure = "ignored"', 'fluid_pressure = "coupled"', GAS))
    for rec, he in zip(leaking(liquid), leaking(helium), strict=True):
        assert rec["squeeze_pressure"] == he["squeeze_pressure"]
        assert rec["leak_rate_helium_pv"] == pytest.approx(he["leak_rate_pv"], rel=1e-6)
        # ΔP = 1 bar against P0 = 0.3–0.5 MPa: the helium presses on the contact and leaks more than the liquid's
        # K at its 10 kPa would let it (the old approximation)
        by_k = _helium_by_hand(rec["leak_rate"] / rec["pressure_difference"], 1e-3, rec["critical_gap"],
                               rec["critical_wavelength"])
        assert rec["leak_rate_helium_pv"] > 1.2 * by_k


def test_gas_table_is_printed(tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(GAS)
    assert main(["predict", str(case)]) == 0
    out = capsys.readouterr().out
    for text in ("helium", "Q (mbar·l/s)", "Q (sccm)", "Kn", "regime", "He-eq (mbar·l/s)", "0 °C and 101.325 kPa"):
        assert text in out, text


def test_oring_with_a_gas_uses_the_band_conductance(tmp_path, capsys):
    from sealeak.cases import example_path

    text = example_path("o-ring").read_text()
    text = text.split("[study]")[0]
    text = text.replace('name = "water"\nviscosity = "1 mPa*s"', 'name = "nitrogen"')
    text = text.replace('pressure_difference = "1 bar"', 'upstream_pressure = "2 bar"\ndownstream_pressure = "1 bar"')
    text = text.replace('model = "both"', 'model = "critical-junction"\nrarefaction = "no-slip"')
    text = text.replace('num = 9', 'num = 3')
    ignored = predict_json(tmp_path, capsys, text.replace('rarefaction = "no-slip"',
                                                          'rarefaction = "no-slip"\nfluid_pressure = "ignored"'))
    for rec in leaking(ignored):
        k = rec["leak_rate"] / rec["pressure_difference"]
        assert rec["leak_rate_pv"] == pytest.approx(k * (4e10 - 1e10) / 2, rel=1e-10, abs=0)
        assert rec["knudsen_number"] > 0
    # coupled (the default): the gas pressure, largest where σ is (upstream), weights the band's conductance, so
    # the no-slip leak exceeds the coupled liquid K times (P_a² − P_b²)/2 (docs/theory.md §13.5)
    for rec in leaking(predict_json(tmp_path, capsys, text)):
        k = rec["leak_rate"] / rec["pressure_difference"]
        assert rec["leak_rate_pv"] > 1.001 * k * (4e10 - 1e10) / 2


def test_kinetic_default_predicts_more_than_beskok_karniadakis(tmp_path, capsys):
    """The helium-test example (kinetic, the default): in the transition and free-molecular regimes the
    kinetic slit passes more than Beskok–Karniadakis (up to ~1.6x at Kn = 10 for one slit, more beyond:
    docs/theory.md §11.4); leaving theory.rarefaction out gives the kinetic result."""
    from sealeak.cases import example_path

    text = example_path("helium-test").read_text()
    assert 'rarefaction = "kinetic"' in text
    kinetic = predict_json(tmp_path, capsys, text)
    bk = predict_json(tmp_path, capsys, text.replace('rarefaction = "kinetic"', 'rarefaction = "beskok-karniadakis"'))
    ratios = [a["leak_rate_pv"] / b["leak_rate_pv"] for a, b in zip(leaking(kinetic), leaking(bk))]
    assert all(1.3 < r < 4.0 for r in ratios), ratios
    plain = predict_json(tmp_path, capsys, text.replace('rarefaction = "kinetic"\n', ""))
    assert [r["leak_rate_pv"] for r in leaking(plain)] == [r["leak_rate_pv"] for r in leaking(kinetic)]  # the default


# ------------------------------------------------------------------------------------ bad input

BAD = [  # (case text, names the message must hold)
    (gas_case(upstream="-1 bar"), ["conditions.upstream_pressure"]),
    (gas_case(downstream="-5 kPa"), ["conditions.downstream_pressure"]),
    (gas_case(upstream="1 bar", downstream="2 bar"), ["conditions.upstream_pressure", "downstream"]),
    (gas_case(fluid="unobtainium"), ["fluid.name", "helium", "nitrogen", "R134a"]),
    (gas_case(extra_fluid='\ntemperature = "20"'), ["fluid.temperature"]),
    (gas_case(extra_fluid='\ntemperature = "20 C"'), ["fluid.temperature", "degC"]),
    (gas_case(extra_fluid='\ntemperature = "20 Pa"'), ["fluid.temperature"]),
    (gas_case(extra_fluid="\ntemperature = 20"), ["fluid.temperature"]),
    (edit('upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"', 'pressure_difference = "1 bar"', GAS),
     ["conditions.upstream_pressure", "gas"]),
    (edit('downstream_pressure = "0 Pa"', 'downstream_pressure = "0 Pa"\npressure_difference = "0.5 bar"', GAS),
     ["conditions.pressure_difference", "conditions.upstream_pressure", "conditions.downstream_pressure"]),
    (edit('downstream_pressure = "0 Pa"\n', "", GAS), ["conditions.downstream_pressure"]),
    (gas_case(extra_theory='\nrarefaction = "magic"'), ["theory.rarefaction"]),
    (edit('viscosity = "1 mPa*s"', 'name = "ISO VG 46 oil"'), ["fluid.name", "fluid.viscosity"]),
]


@pytest.mark.parametrize("text, names", BAD, ids=[str(i) for i in range(len(BAD))])
def test_bad_gas_input_is_one_line_naming_the_field(tmp_path, capsys, text, names):
    case = tmp_path / "case.toml"
    case.write_text(text)
    kept = tmp_path / "kept.json"
    kept.write_text("earlier result\n")
    new_out = tmp_path / "new.csv"
    assert main(["predict", str(case), "--json", str(kept), "--csv", str(new_out), "--force"]) == 2
    one_line_error(capsys, *names)
    assert kept.read_text() == "earlier result\n" and not new_out.exists()


def test_a_liquid_below_its_vapour_pressure_warns(tmp_path, capsys):
    text = edit('viscosity = "1 mPa*s"', 'name = "water"',
                edit('pressure_difference = "10 kPa"', 'upstream_pressure = "50 kPa"\ndownstream_pressure = "1 kPa"'))
    case = tmp_path / "case.toml"
    case.write_text(text)
    assert main(["predict", str(case)]) == 0
    out = capsys.readouterr().out
    assert "warning:" in out and "vapour pressure" in out and "boil" in out
    above = edit('downstream_pressure = "1 kPa"', 'downstream_pressure = "10 kPa"', text)
    case.write_text(above)
    assert main(["predict", str(case)]) == 0
    assert "vapour pressure" not in capsys.readouterr().out


# ------------------------------------------------------------------------------------ fit with gas leak data
FIT_UNITS = [("mbar*l/s", "leak_rate_mbar_l_s", 1.0), ("Pa*m^3/s", "leak_rate_pv", 1.0), ("sccm", "leak_rate_sccm", 1.0),
             ("mol/s", "leak_rate_molar", 1.0), ("g/s", "leak_rate_mass", 1e3)]


@pytest.mark.parametrize("unit, key, scale", FIT_UNITS, ids=[u[0] for u in FIT_UNITS])
def test_fit_of_gas_leak_data_recovers_alpha_in_any_leak_unit(tmp_path, capsys, unit, key, scale):
    """Data made from predict's gas leak at α = 0.2, in each unit: fit's α of the critical junction is 0.2."""
    text = gas_case("nitrogen", "3 bar", "1 bar")
    doc = predict_json(tmp_path, capsys, text)
    rows = leaking(doc)
    assert len(rows) >= 2
    data = tmp_path / "measured.csv"
    data.write_text(f"squeeze_pressure (kPa), leak_rate ({unit})\n"
                    + "".join(f"{r['squeeze_pressure'] / 1e3!r}, {r[key] * scale!r}\n" for r in rows))
    case = tmp_path / "case.toml"
    case.write_text(text)
    out = tmp_path / "fit.json"
    assert main(["fit", str(case), "--data", str(data), "--json", str(out), "--force"]) == 0
    fit = json.loads(out.read_text())
    assert fit["critical_junction"]["alpha"] == pytest.approx(0.2, rel=1e-9)
    assert "pV throughputs of nitrogen" in capsys.readouterr().out


def test_fit_of_a_coupled_gas_case_recovers_alpha_from_the_exact_coupling_at_each_rows_pressures(tmp_path, capsys):
    """Data made from predict's coupled gas leak (theory §13.5) at α = 0.3: fit's α of the critical junction is 0.3
    (σ ∝ α, while u_c and so the slip do not depend on α). Rows measured at 5 bar, each with its ΔP, fit to 0.3 as
    well, to the gas's properties, which the fit takes at the case's pressures (3 bar)."""
    def text(upstream):
        coupled = edit('fluid_pressure = "ignored"', 'fluid_pressure = "coupled"', gas_case("nitrogen", upstream, "1 bar"))
        return edit("alpha = 0.2", "alpha = 0.3", coupled)

    def lines(upstream, dp_kpa):
        rows = leaking(predict_json(tmp_path, capsys, text(upstream)))
        assert len(rows) >= 2
        return [f"{r['squeeze_pressure'] / 1e3!r}, {r['leak_rate_pv']!r}, {dp_kpa!r}\n" for r in rows]

    def fit(rows):
        data = tmp_path / "measured.csv"
        data.write_text("squeeze_pressure (kPa), leak_rate (Pa*m^3/s), pressure_difference (kPa)\n" + "".join(rows))
        case = tmp_path / "case.toml"
        case.write_text(text("3 bar"))
        out = tmp_path / "fit.json"
        assert main(["fit", str(case), "--data", str(data), "--json", str(out), "--force"]) == 0
        capsys.readouterr()
        result = json.loads(out.read_text())["critical_junction"]
        assert result["points_used"] == len(rows)
        return result["alpha"]

    at_case = lines("3 bar", 200.0)
    assert fit(at_case) == pytest.approx(0.3, rel=1e-6)
    # the uncoupled K ∫ p f dp at 5 bar would be off by a factor (the gas pressure opens the contact more at 5 bar)
    assert fit(at_case + lines("5 bar", 400.0)) == pytest.approx(0.3, rel=1e-2)


def test_fit_of_a_coupled_band_gas_case_recovers_alpha(tmp_path, capsys):
    """An O-ring's helium leak (the helium-test example, fluid pressure coupled) at α = 0.3: fit's α is 0.3."""
    text = re.sub(r"(?m)^compression = .*$", 'compression = ["10 %", "15 %"]', Path(example_path("helium-test")).read_text())
    text = edit("alpha = 1.0", "alpha = 0.3", text)
    assert "fluid_pressure" not in text  # coupled by default
    rows = leaking(predict_json(tmp_path, capsys, text))
    data = tmp_path / "measured.csv"
    data.write_text("compression (%), leak_rate (Pa*m^3/s)\n"
                    + "".join(f"{100 * r['compression']!r}, {r['leak_rate_pv']!r}\n" for r in rows))
    out = tmp_path / "fit.json"
    assert main(["fit", str(tmp_path / "case.toml"), "--data", str(data), "--json", str(out), "--force"]) == 0
    capsys.readouterr()
    fit = json.loads(out.read_text())["critical_junction"]
    assert fit["points_used"] == len(rows) == 2
    assert fit["alpha"] == pytest.approx(0.3, rel=1e-6)


@pytest.mark.parametrize("coupling, dp_bar, said", [
    ('fluid_pressure = "ignored"', 5.0, "is not small against the peak contact pressure"),  # ΔP > p_max/2
    ("", 7.0, "reaches the lift-off pressure difference, the peak contact pressure")])  # ΔP >= p_max
def test_a_band_gas_fit_says_where_the_pressure_difference_is_large_against_the_peak(tmp_path, capsys, coupling, dp_bar,
                                                                                   said):
    """The helium test's O-ring (peak contact pressure 6.4 bar at 10 % compression, theory eq. 10.4) fitted to a row at
    ΔP = 5 bar (fluid pressure ignored: p >> ΔP doubtful) or 7 bar (coupled: the gas opens the seal): a liquid's band
    fit and a uniform gas fit say so; a band gas fit said nothing."""
    text = Path(example_path("helium-test")).read_text().replace("[theory]", f"[theory]\n{coupling}")
    (tmp_path / "case.toml").write_text(text)
    data = tmp_path / "measured.csv"
    data.write_text("compression (%), pressure_difference (bar), leak_rate (mbar*l/s)\n"
                    f"10, 1, 1e-6\n10, {dp_bar}, 2e-5\n15, 1, 1e-8\n")
    assert main(["fit", str(tmp_path / "case.toml"), "--data", str(data)]) == 0
    out = capsys.readouterr().out
    assert f"line 3: ΔP = {dp_bar * 1e5:g} Pa {said}" in out and "at compression 10 % (1 row(s) like it)" in out
    assert "line 2:" not in out and "line 4:" not in out  # 1 bar against 6.4 and 9.6 bar: not large


@pytest.mark.parametrize("unit", ["sccm", "mol/s", "kg/s"])
def test_a_gas_leak_unit_for_a_liquid_case_is_one_line(tmp_path, capsys, unit):
    case = tmp_path / "case.toml"
    case.write_text(BASE)
    data = tmp_path / "measured.csv"
    data.write_text(f"squeeze_pressure (kPa), leak_rate ({unit})\n20, 1e-3\n60, 1e-4\n")
    assert main(["fit", str(case), "--data", str(data)]) == 2
    one_line_error(capsys, "measured.csv", "liquid")
