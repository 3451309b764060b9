"""The seal over its life in a case file: [conditions] time and temperature, [rubber] relaxation (docs/theory.md §16.7).

Expected values come from the closed forms of a one-term Prony series (a standard linear solid: E(t), and its creep
compliance J(t) = 1/E∞ − (1/E∞ − 1/E0) exp(−t E∞/(E0 τ))), the WLF equation and eq. 16.9, never from the code's output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sealeak.cases import parse_case_file
from sealeak.cases.run import run_case
from sealeak.errors import FileFormatError, InputError
from sealeak.physics.viscoelastic import CompressionSet, PronySeries
from sealeak.render import prediction_table

SURFACE = """
[surface]
model = "self-affine"
h_rms = "5 um"
hurst = 0.8
rolloff_wavelength = "100 um"
cutoff_wavelength = "1 um"
"""
ORING = SURFACE + """
[rubber]
{rubber}
[seal]
shape = "o-ring"
cross_section_diameter = "2.62 mm"
inner_diameter = "20 mm"
{seal}
[fluid]
viscosity = "1 mPa*s"

[conditions]
compression = "20 %"
pressure_difference = "1 bar"
{conditions}
[theory]
fluid_pressure = "ignored"
"""
RING = SURFACE + """
[rubber]
{rubber}
[seal]
shape = "ring"
inner_diameter = "3 cm"
outer_diameter = "4 cm"

[fluid]
viscosity = "1 mPa*s"

[conditions]
squeeze_pressure = ["50 kPa", "200 kPa"]
pressure_difference = "10 kPa"
{conditions}
"""
E_INF, E_1, TAU = 2e6, 3e6, 100.0  # Pa, Pa, s: one Prony term
PRONY = 'relaxation = { equilibrium_modulus = "2 MPa", moduli = ["3 MPa"], times = ["100 s"] }'
#: The Prony series at 20 °C with a WLF shift (C1 = 1, C2 = 50 K) and a glass transition of -60 °C.
WLF = PRONY + '\nreference_temperature = "20 degC"\nwlf_c1 = 1\nwlf_c2 = 50\nglass_transition = "-60 degC"'
#: A ring holding nitrogen at 2 bar against 1 bar on that rubber; ``{cell}`` takes the time and temperature keys.
GAS_RING = SURFACE + f"""
[rubber]
{WLF}
[seal]
shape = "ring"
inner_diameter = "3 cm"
outer_diameter = "4 cm"
[fluid]
name = "nitrogen"
[conditions]
squeeze_pressure = ["100 kPa", "300 kPa"]
upstream_pressure = "2 bar"
downstream_pressure = "1 bar"
{{cell}}
[theory]
fluid_pressure = "ignored"
"""


def cases(template: str, rubber: str = 'youngs_modulus = "5 MPa"', conditions: str = "", seal: str = ""):
    return parse_case_file(template.format(rubber=rubber, conditions=conditions, seal=seal)).cases


def test_a_one_term_prony_series_relaxes_the_oring_force_by_e_t_over_e_0():
    times = [0.0, 30.0, 100.0, 3600.0]
    relaxed = cases(ORING, PRONY, 'time = ["0 s", "30 s", "100 s", "1 h"]')
    (elastic,) = cases(ORING, 'youngs_modulus = "5 MPa"')  # E(0) = E∞ + E1
    f_el = elastic.band.profiles[0].force_per_length
    assert [c.life.time for c in relaxed] == times
    for case, t in zip(relaxed, times):
        ratio = (E_INF + E_1 * math.exp(-t / TAU)) / (E_INF + E_1)
        assert case.band.profiles[0].force_per_length == pytest.approx(ratio * f_el, rel=1e-9)
        assert case.band.profiles[0].width == pytest.approx(elastic.band.profiles[0].width, rel=1e-12, abs=0)  # ε alone sets w
        assert case.life.modulus == pytest.approx(ratio * (E_INF + E_1), rel=1e-9)


def test_a_seal_under_a_squeeze_pressure_creeps_with_one_over_j():
    times = [0.0, 100.0, 1e4]
    crept = cases(RING, PRONY, 'time = ["0 s", "100 s", "1e4 s"]')
    e0 = E_INF + E_1
    for case, t in zip(crept, times):
        j = 1 / E_INF - (1 / E_INF - 1 / e0) * math.exp(-t * E_INF / (e0 * TAU))
        assert case.youngs_modulus == pytest.approx(1 / j, rel=1e-9)
    assert crept[-1].youngs_modulus == pytest.approx(E_INF, rel=1e-6)  # long times: the equilibrium modulus


def test_the_wlf_shift_slows_the_relaxation_in_the_cold():
    # C1 = 1, C2 = 50 K at Tref = 20 °C; at −5 °C (ΔT = −25 K) log10 a_T = −1 × (−25)/(50 − 25) = 1: a_T = 10
    rubber = PRONY + '\nreference_temperature = "20 degC"\nwlf_c1 = 1\nwlf_c2 = 50\nglass_transition = "-60 degC"'
    (cold,) = cases(ORING, rubber, 'time = "100 s"\ntemperature = "-5 degC"')
    expected = E_INF + E_1 * math.exp(-100.0 / 10 / TAU)  # E(t/a_T), a_T = 10
    assert cold.youngs_modulus == pytest.approx(expected, rel=1e-9)
    assert cold.life.temperature == pytest.approx(268.15, rel=1e-12)
    assert cold.temperature == pytest.approx(268.15, rel=1e-12)  # the fluid is taken there too
    assert cold.label == "t = 100 s, T = -5 °C"


def test_colder_gives_less_compression_and_more_leak():
    alpha_r, alpha_g, eps0 = 23e-5, 1.2e-5, 0.2
    both = cases(ORING, conditions='temperature = ["-20 degC", "60 degC"]',
                 rubber='youngs_modulus = "5 MPa"\nthermal_expansion = "23e-5 1/K"',
                 seal='gland_thermal_expansion = "1.2e-5 1/K"')
    for case, dt in zip(both, (-40.0, 40.0)):  # assembled at 20 °C
        expected = 1 - (1 - eps0) * (1 + alpha_g * dt) / (1 + alpha_r * dt)
        assert case.band.loads[0] == pytest.approx(expected, rel=1e-12, abs=0)
    cold, hot = (run_case(c).band.critical_junction.leak_rate[0] for c in both)
    assert both[0].band.loads[0] < eps0 < both[1].band.loads[0]
    assert cold > hot


def test_groove_depth_follows_the_gland_and_the_cord():
    both = cases(ORING.replace('compression = "20 %"', 'groove_depth = "2.1 mm"'), conditions='temperature = "-30 degC"',
                 rubber='youngs_modulus = "5 MPa"\nthermal_expansion = "2e-4 1/K"',
                 seal='gland_thermal_expansion = "1e-5 1/K"\n')
    dt = -50.0
    expected = 1 - 2.1 * (1 + 1e-5 * dt) / (2.62 * (1 + 2e-4 * dt))
    assert both[0].band.loads[0] == pytest.approx(expected, rel=1e-9)


def test_without_relaxation_time_changes_nothing():
    (plain,) = cases(RING)
    over_life = cases(RING, conditions='time = ["1 s", "30 a"]')
    base = run_case(plain).records()
    for case in over_life:
        rows = run_case(case).records()
        assert [{k: v for k, v in r.items() if k not in ("variant", "time", "temperature", "modulus")} for r in rows] == base
        assert all(r["modulus"] == plain.youngs_modulus for r in rows)
    assert [r["time"] for c in over_life for r in run_case(c).records()[:1]] == [1.0, 30 * 365.25 * 86400]
    assert plain.life is None and "time" not in base[0]


def test_rows_lead_with_time_temperature_and_modulus():
    (case,) = cases(RING, PRONY, 'time = "1 h"')
    result = run_case(case)
    assert list(result.units)[:3] == ["time", "temperature", "modulus"]
    assert list(result.records()[0])[:4] == ["variant", "time", "temperature", "modulus"]
    assert result.units["modulus"] == "Pa" and result.units["temperature"] == "K"


def test_a_warning_near_the_glass_transition():
    rubber = 'youngs_modulus = "5 MPa"\nglass_transition = "-35 degC"'
    near, far = cases(RING, rubber, 'temperature = ["-30 degC", "40 degC"]')
    assert any("glass transition" in w for w in near.input_warnings)
    assert not any("glass transition" in w for w in far.input_warnings)


def write_master_curve(tmp_path, series, rows=None):
    """The relaxation modulus of ``series`` at 10 points per decade from 1 ms to 1e7 s, as a master-curve file
    (modulus in MPa), or the rows given."""
    t = np.geomspace(1e-3, 1e7, 101)
    rows = rows or [f"{x:.17g}, {e / 1e6:.17g}" for x, e in zip(t, series.relaxation_modulus(t))]
    (tmp_path / "nbr-master.csv").write_text("# sampled\ntime (s), modulus (MPa)\n" + "\n".join(rows) + "\n")


MASTER = 'relaxation = { master_curve = "nbr-master.csv" }'


def test_a_master_curve_file_relaxes_the_oring_and_creeps_the_ring_like_its_prony_series(tmp_path):
    series = PronySeries(E_INF, (E_1,), (TAU,))
    write_master_curve(tmp_path, series)
    times = [1.0, 100.0, 1e4]
    conditions = 'time = ["1 s", "100 s", "1e4 s"]'
    for template, expected in ((ORING, series.relaxation_modulus), (RING, lambda t: 1 / series.creep_compliance(t))):
        text = template.format(rubber=MASTER, conditions=conditions, seal="")
        got = [c.youngs_modulus for c in parse_case_file(text, tmp_path).cases]
        assert got == pytest.approx([float(expected(t)) for t in times], rel=1e-2)
        assert got[0] > got[-1]


def test_a_master_curve_shifts_with_the_wlf_constants(tmp_path):
    series = PronySeries(E_INF, (E_1,), (TAU,))
    write_master_curve(tmp_path, series)
    rubber = MASTER + '\nreference_temperature = "20 degC"\nwlf_c1 = 1\nwlf_c2 = 50\nglass_transition = "-60 degC"'
    (cold,) = parse_case_file(ORING.format(rubber=rubber, conditions='time = "100 s"\ntemperature = "-5 degC"', seal=""),
                              tmp_path).cases
    assert cold.youngs_modulus == pytest.approx(float(series.relaxation_modulus(10.0)), rel=1e-3)  # a_T = 10


@pytest.mark.parametrize("row, shown", [("1e4, -2", "modulus = -2 MPa"), ("1e4, 9", "modulus = 9 MPa"),
                                        ("0.5, 3", "time = 0.5 s"), ("1e4, nan", "modulus = nan MPa")])
def test_a_bad_master_curve_row_gets_one_line_naming_the_file_line_and_value(tmp_path, row, shown):
    write_master_curve(tmp_path, None, ["1, 5", "100, 3", row])
    with pytest.raises(FileFormatError) as err:
        parse_case_file(ORING.format(rubber=MASTER, conditions="", seal=""), tmp_path)
    message = str(err.value)
    assert "nbr-master.csv: line 5: " + shown in message and "\n" not in message  # a comment, the header, 2 rows


def test_a_master_curve_is_given_alone(tmp_path):
    write_master_curve(tmp_path, PronySeries(E_INF, (E_1,), (TAU,)))
    with pytest.raises(InputError) as err:
        cases(ORING, 'relaxation = { master_curve = "nbr-master.csv", equilibrium_modulus = "2 MPa" }')
    assert err.value.field == "rubber.relaxation.equilibrium_modulus"


@pytest.mark.parametrize("template, rubber, conditions, seal, field", [
    (RING, PRONY + '\nyoungs_modulus = "5 MPa"', "", "", "rubber.youngs_modulus"),
    (RING, PRONY + "\nshore_a = 70", "", "", "rubber.shore_a"),
    (RING, 'youngs_modulus = "5 MPa"\nwlf_c1 = 8', "", "", "rubber.wlf_c1"),
    (RING, PRONY + "\nwlf_c1 = 8\nwlf_c2 = 100", "", "", "rubber.reference_temperature"),
    (RING, PRONY.replace('"3 MPa"', '"-3 MPa"'), "", "", "rubber.relaxation.moduli[0]"),
    (RING, PRONY.replace('"100 s"', '"100 m"'), "", "", "rubber.relaxation.times[0]"),
    (RING, PRONY.replace('"100 s"', '"100 s", "1 h"'), "", "", "rubber.relaxation.times"),
    (RING, 'youngs_modulus = "5 MPa"\nthermal_expansion = "2e-4 1/K"', "", "", "rubber.thermal_expansion"),
    (ORING, 'youngs_modulus = "5 MPa"\nthermal_expansion = "2e-4 1/K"', "", "", "seal.gland_thermal_expansion"),
    (RING, 'youngs_modulus = "5 MPa"', 'time = "-1 s"', "", "conditions.time"),
    (RING, 'youngs_modulus = "5 MPa"', 'time = "3 kg"', "", "conditions.time"),
    (RING, 'youngs_modulus = "5 MPa"', 'time = {start = "-1 h", stop = "1 a", num = 5}', "", "conditions.time.start"),
    (RING, 'youngs_modulus = "5 MPa"', 'time = ["1 h", "-1 h"]', "", "conditions.time[1]"),
    (RING, 'youngs_modulus = "5 MPa"', "temperature = 20", "", "conditions.temperature"),
    (RING, 'youngs_modulus = "5 MPa"', 'time = {start = "0 s", stop = "1 a", num = 20}\n'
                                       'temperature = ["0 degC", "10 degC", "20 degC", "30 degC", "40 degC", "50 degC"]',
     "", "conditions.time"),
    (RING, 'youngs_modulus = "5 MPa"', 'assembly_temperature = "20 degC"', "", "conditions.assembly_temperature"),
])
def test_bad_life_keys_get_one_line_naming_the_key(template, rubber, conditions, seal, field):
    with pytest.raises(InputError) as err:
        cases(template, rubber, conditions, seal)
    assert err.value.field.startswith(field) and "\n" not in str(err.value)


def test_the_fluid_temperature_and_conditions_temperature_are_not_both_given():
    text = RING.format(rubber='youngs_modulus = "5 MPa"', conditions='temperature = "0 degC"')
    with pytest.raises(InputError) as err:
        parse_case_file(text.replace('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\ntemperature = "20 degC"'))
    assert err.value.field == "fluid.temperature"


# --- ageing: compression set (docs/theory.md §16.6) ----------------------------------------------------------------

AGEING = CompressionSet(time_constant=3e10, exponent=0.5, activation_energy=80e3, reference_temperature=293.15)


def set_points(model: CompressionSet = AGEING) -> str:
    """rubber.compression_set: the sets ``model`` gives after 1000 h and 1 a at 23, 70 and 100 °C."""
    points = [(t, temp) for t in (3.6e6, 3.15576e7) for temp in (296.15, 343.15, 373.15)]
    sets = [float(model(t, temp)) for t, temp in points]
    return (f"compression_set = {{ times = {[f'{t!r} s' for t, _ in points]}, "
            f"temperatures = {[f'{temp!r} K' for _, temp in points]}, sets = {sets} }}").replace("'", '"')


def test_a_compression_set_reduces_the_oring_compression_by_one_minus_c():
    times, temp = (0.0, 3600.0, 3.15576e8), 343.15
    aged = cases(ORING, 'youngs_modulus = "5 MPa"\n' + set_points(),
                 'time = ["0 s", "1 h", "10 a"]\ntemperature = "70 degC"')
    for case, t in zip(aged, times):
        c = float(AGEING(t, temp))  # the fit recovers the model of its exact points
        assert case.life.compression_set == pytest.approx(c, rel=1e-6, abs=1e-12)
        assert case.band.loads[0] == pytest.approx(0.2 * (1 - c), rel=1e-6)
    assert aged[0].band.loads[0] == 0.2 and 0.2 > aged[1].band.loads[0] > aged[2].band.loads[0]


def test_a_set_of_zero_changes_nothing_bit_for_bit():
    (plain,) = cases(ORING, conditions='time = "0 s"')
    (aged,) = cases(ORING, 'youngs_modulus = "5 MPa"\n' + set_points(), 'time = "0 s"')  # c(0, T) = 0
    rows = run_case(aged).records()
    assert [r.pop("compression_set") for r in rows] == [0.0]
    assert rows == run_case(plain).records()


def test_more_set_means_less_compression_and_more_leak():
    fresh, old = cases(ORING, 'youngs_modulus = "5 MPa"\n' + set_points(), 'time = ["1 d", "10 a"]\ntemperature = "70 degC"')
    assert fresh.life.compression_set < old.life.compression_set
    assert fresh.band.loads[0] > old.band.loads[0]
    q_fresh, q_old = (run_case(c).band.critical_junction.leak_rate[0] for c in (fresh, old))
    assert q_old > q_fresh


def test_rows_have_the_compression_set_only_where_given():
    (aged,) = cases(ORING, 'youngs_modulus = "5 MPa"\n' + set_points(), 'time = "1 a"')
    (plain,) = cases(ORING, conditions='time = "1 a"')
    assert run_case(aged).units["compression_set"] == "1" and "compression_set" in run_case(aged).records()[0]
    assert "compression_set" not in run_case(plain).units and "compression_set" not in run_case(plain).records()[0]


@pytest.mark.parametrize("template, rubber, field", [
    (RING, 'youngs_modulus = "5 MPa"\n' + set_points(), "rubber.compression_set"),
    (ORING, 'youngs_modulus = "5 MPa"\ncompression_set = { times = ["1 h"], temperatures = ["20 degC"], sets = [20] }',
     "rubber.compression_set.sets[0]"),
    (ORING, 'youngs_modulus = "5 MPa"\ncompression_set = { times = ["1 h"], temps = ["20 degC"], sets = [0.2] }',
     "rubber.compression_set.temps"),
    (ORING, 'youngs_modulus = "5 MPa"\ncompression_set = { times = ["1 h", "2 h", "3 h"], temperatures = ["20 degC", '
            '"20 degC", "20 degC"], sets = [0.1, 0.2, 0.3] }', "rubber.compression_set.temperatures"),
    (ORING, 'youngs_modulus = "5 MPa"\ncompression_set = "20 %"', "rubber.compression_set"),
])
def test_bad_compression_set_data_get_one_line_naming_the_key(template, rubber, field):
    with pytest.raises(InputError) as err:
        cases(template, rubber, 'time = "1 a"')
    assert err.value.field.startswith(field) and "\n" not in str(err.value)


def test_the_text_says_the_compression_set_of_each_case():
    (aged,) = cases(ORING, 'youngs_modulus = "5 MPa"\n' + set_points(), 'time = "10 a"\ntemperature = "70 degC"')
    c = aged.life.compression_set
    text = prediction_table([run_case(aged)])
    assert f"compression set c = {100 * c:.3g} %" in text
    assert c == pytest.approx(float(AGEING(3.15576e8, 343.15)), rel=1e-4)  # the model the set points were made from
    (plain,) = cases(ORING, conditions='time = "10 a"')
    assert "compression set" not in prediction_table([run_case(plain)])


@pytest.mark.parametrize("squeeze", ['compression = "20 %"', 'groove_depth = "2.096 mm"'])
def test_a_cord_the_cold_shrinks_out_of_its_gland_is_refused_naming_the_temperature(squeeze):
    """α_r = 9e-3 1/K over 40 K: ε(T) = 1 − 0.8 (1 − 1.2e-5 × 40)/(1 − 9e-3 × 40) = −24.9 % (eq. 16.9), as the
    user's temperature, not as a compression they never wrote (2.096 mm of a 2.62 mm cord is 20 % too)."""
    eps = 1 - 0.8 * (1 - 1.2e-5 * 40) / (1 - 9e-3 * 40)
    text = ORING.format(rubber='youngs_modulus = "5 MPa"\nthermal_expansion = "9e-3 1/K"',
                        seal='gland_thermal_expansion = "1.2e-5 1/K"',
                        conditions='temperature = ["20 degC", "-20 degC"]').replace('compression = "20 %"', squeeze)
    with pytest.raises(InputError) as err:
        parse_case_file(text)
    assert err.value.field == "conditions.temperature (at t = 0 s, T = -20 °C)"
    assert f"no longer fills the gland at -20 °C (ε(T) = {100 * eps:.3g} %, 20 % at assembly)" in str(err.value)
    assert "conditions.compression" not in str(err.value) and "\n" not in str(err.value)


def test_a_temperature_beyond_the_shift_law_is_shown_in_kelvin_and_celsius():
    rubber = PRONY + '\nreference_temperature = "20 degC"\nwlf_c1 = 1\nwlf_c2 = 50'  # diverges at -30 °C
    with pytest.raises(InputError) as err:
        cases(RING, rubber, 'temperature = ["-150 degC", "20 degC"]')
    assert err.value.field.startswith("conditions.temperature")
    assert "'123.15 K (-150 °C)'" in str(err.value) and "243.15 K (-30 °C)" in str(err.value)


@pytest.mark.parametrize("rubber, seal, field, written", [
    ("0.2 1/K", "1.2e-5 1/K", "rubber.thermal_expansion", "0.2 1/K"),
    ("23e-5 1/K", "-0.5 1/K", "seal.gland_thermal_expansion", "-0.5 1/K"),
])
def test_an_expansion_coefficient_out_of_range_is_a_material_constant_not_a_case(rubber, seal, field, written):
    """Checked once where the life keys are read: named without a time and temperature, shown as written."""
    with pytest.raises(InputError) as err:
        cases(ORING, f'youngs_modulus = "5 MPa"\nthermal_expansion = "{rubber}"',
              'time = ["1 s", "1 h"]\ntemperature = ["-20 degC", "20 degC"]', f'gland_thermal_expansion = "{seal}"')
    assert (err.value.field, err.value.value) == (field, written)
