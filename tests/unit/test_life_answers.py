"""When does a seal over its life first exceed conditions.max_leak_rate, and from which temperature up does it hold
(issue 25 item 5)? The crossings are checked against hand computations on synthetic leak rates: a power law
Q ∝ t^n is exact under interpolation in log t, log Q linear in T exact between temperatures."""

import math

import pytest

from sealeak.cases import parse_case_file
from sealeak.cases.life_answers import (
    LifeAnswer,
    first_exceeded,
    highest_holding_temperature,
    life_answers,
    lowest_holding_temperature,
)
from sealeak.cases.run import run_case
from sealeak.cases.uncertainty import parse_uncertain_case, propagate
from sealeak.render.life import volume_limit
from sealeak.render.uncertainty import _holding_text, passing_lines, uncertainty_summary
from tests.unit.test_life_cases import GAS_RING, PRONY, RING, WLF


def test_the_first_time_a_power_law_exceeds_the_limit_is_interpolated_in_log_t():
    times = [1.0, 100.0, 1e4, 1e6]
    q = [1e-9 * math.sqrt(t) for t in times]  # 1e-9, 1e-8, 1e-7, 1e-6 m³/s
    # 1e-9 √t = 3e-8 at t = 30² = 900 s, between 100 s and 1e4 s
    assert first_exceeded(times, q, 3e-8) == pytest.approx(900.0, rel=1e-12)
    assert first_exceeded(times, q, 2e-6) is None  # holds to the latest time
    assert first_exceeded(times, q, 1e-10) == 1.0  # exceeds already at the earliest
    assert first_exceeded(times, q, 1e-7) == pytest.approx(1e4, rel=1e-12)  # reaches it there, exceeds after


def test_a_time_of_zero_or_a_sealed_row_is_interpolated_linearly():
    # from 0 (no log) to 100 s, Q from 0 (it seals, no log) to 1e-8: Q = 1e-10 t, 4e-9 at 40 s
    assert first_exceeded([0.0, 100.0], [0.0, 1e-8], 4e-9) == pytest.approx(40.0, rel=1e-12)


def test_the_lowest_temperature_at_which_it_holds():
    temps = [250.0, 270.0, 290.0]
    q = [1e-6 * 10 ** (-(t - 250.0) / 10) for t in temps]  # falls a decade per 10 K
    assert lowest_holding_temperature(temps, q, 10 ** -7.5) == pytest.approx(265.0, rel=1e-12)
    assert lowest_holding_temperature(temps, q, 1e-5) == 250.0  # the coldest computed
    assert lowest_holding_temperature(temps, q, 1e-11) is None  # exceeds even at the warmest
    # holds in the cold, exceeds at 270 K, holds at 290 K: it holds from above 270 K up, not from 250 K
    assert 270.0 < lowest_holding_temperature(temps, [1e-9, 1e-7, 1e-9], 1e-8) < 290.0


def test_a_life_file_with_a_specification_answers_per_load():
    rubber = PRONY + '\nreference_temperature = "20 degC"\nwlf_c1 = 1\nwlf_c2 = 50\nglass_transition = "-60 degC"'
    text = RING.format(rubber=rubber, seal="", conditions='time = ["10 s", "1 h", "1 d"]\n'
                       'temperature = ["-10 degC", "60 degC"]\nmax_leak_rate = "0.05 ml/min"')
    result = propagate(parse_uncertain_case(text), 4, seed=0)
    answers = life_answers(result)
    assert [a.load_name for a in answers] == ["squeeze_pressure"] * 2  # one per load: 50 and 200 kPa
    limit = 0.05 * 1e-6 / 60  # m³/s
    for n, a in enumerate(answers):
        assert set(a.loads) == {(50e3, 200e3)[n]}
        for t_k, first in zip(a.temperatures, a.exceeded_from):
            q = {r.case.life.time: r.records()[n]["leak_rate"] for r in result.nominal
                 if r.case.life.temperature == t_k}
            exceeding = [t for t in sorted(q) if q[t] > limit]
            assert (first is None) == (not exceeding)
            if exceeding:  # between the last time it holds and the first it exceeds
                earlier = [t for t in sorted(q) if t < exceeding[0]]
                assert (earlier[-1] if earlier else exceeding[0]) <= first <= exceeding[0]
        latest = [r.records()[n]["leak_rate"] for r in result.nominal if r.case.life.time == a.latest_time]
        assert (a.holds_from is None) == (latest[-1] > limit)  # exceeds even at the warmest
        assert (a.holds_from == a.temperatures[0]) == all(q <= limit for q in latest)
        assert (a.holds_to is None) == (latest[0] > limit)  # exceeds even at the coldest
    assert any(e is not None for a in answers for e in a.exceeded_from)  # the checks above are not empty
    assert {a.holds_from is None for a in answers} == {True, False}
    lines = passing_lines(result)
    assert any(line.startswith("P0 = 50 kPa: at -10 °C exceeds 0.05 ml/min already at t = 10 s") for line in lines)
    assert uncertainty_summary(result)["answers"] == lines  # the web app shows them as predict words them
    life = uncertainty_summary(result)["life"]
    assert [x["values"] for x in life] == [[50e3], [200e3]]
    assert life[0]["temperatures"] == pytest.approx([263.15, 333.15], rel=1e-12)
    assert life[0]["latest_time"] == 86400.0
    assert [x["holds_to"] for x in life] == [a.holds_to for a in answers]


def test_the_highest_temperature_at_which_it_holds_mirrors_the_lowest():
    """Ageing runs faster when warm: Q rises with T, and the seal holds up to a temperature."""
    temps = [250.0, 270.0, 290.0]
    q = [1e-9 * 10 ** ((t - 250.0) / 10) for t in temps]  # rises a decade per 10 K
    assert highest_holding_temperature(temps, q, 10 ** -7.5) == pytest.approx(265.0, rel=1e-12)
    assert highest_holding_temperature(temps, q, 1.0) == 290.0  # the warmest computed
    assert highest_holding_temperature(temps, q, 1e-10) is None  # exceeds even at the coldest
    assert lowest_holding_temperature(temps, q, 10 ** -7.5) is None  # the warmest exceeds: no cold limit


@pytest.mark.parametrize("cold, warm, exceeded, text", [
    (250.0, 290.0, (None, None, None), "holds at every temperature computed at 1 a"),
    (265.0, None, (1.0, None, None), "holds from -8.15 °C up at 1 a"),
    (None, 265.0, (None, None, 1.0), "holds up to -8.15 °C at 1 a"),
    (280.0, 260.0, (None, 1.0, None), "holds up to -13.1 °C and from 6.85 °C up at 1 a"),
    (None, None, (1.0, None, 1.0), "exceeds it at the coldest and the warmest at 1 a, holds only between them"),
    (None, None, (1.0, 1.0, 1.0), "exceeds it at every temperature at 1 a"),
])
def test_the_holding_range_is_said_from_both_ends(cold, warm, exceeded, text):
    answer = LifeAnswer(row=0, load_name="squeeze_pressure", loads=(1e5,), temperatures=(250.0, 270.0, 290.0),
                        exceeded_from=exceeded, earliest_time=1.0, latest_time=365.25 * 86400, holds_from=cold,
                        holds_to=warm)
    assert _holding_text(answer, "1 a").startswith(text)


def _cell(text, time, temperature):
    """The nominal result of ``text`` run alone at one (time, temperature): a deterministic run of its own."""
    (case,) = parse_case_file(text.replace("{cell}", f'time = "{time}"\ntemperature = "{temperature}"')).cases
    return run_case(case)


def _check(answer, times, temperatures, q, limit):
    """``answer`` agrees with Q and the limit per (temperature, time) cell (``q[T][t]``, ``limit[T][t]``) computed
    apart: it first exceeds between the last time it holds and the first it does not, and holds at the latest time
    where (and only where) Q does not exceed the limit there."""
    for k, first in enumerate(answer.exceeded_from):
        exceeding = [t for n, t in enumerate(times) if q[k][n] > limit[k][n]]
        assert (first is None) == (not exceeding)
        if exceeding:
            earlier = [t for t in times if t < exceeding[0]]
            assert (earlier[-1] if earlier else exceeding[0]) <= first <= exceeding[0]
    latest = [q[k][-1] > limit[k][-1] for k in range(len(temperatures))]
    assert (answer.holds_from is None) == latest[-1]
    assert (answer.holds_to is None) == latest[0]
    assert (answer.holds_from == answer.temperatures[0]) == (not any(latest))


def test_the_effective_medium_answers_compare_its_own_leak_rate():
    """With [theory] model = "effective-medium" the tables show its Q: the answers compare that one, not the
    critical junction's (which exceeds 1.8 ml/min at 50 kPa, -10 °C and 10 s where the effective medium holds)."""
    text = RING.format(rubber=WLF, seal="", conditions="{cell}") + '\n[theory]\nmodel = "effective-medium"\n'
    times, temperatures = (10.0, 3600.0, 86400.0), (263.15, 333.15)
    cells = [[_cell(text, f"{t} s", f"{T} K") for t in times] for T in temperatures]
    limit = 1.8e-6 / 60  # m³/s
    life = text.replace("{cell}", 'time = ["10 s", "1 h", "1 d"]\ntemperature = ["-10 degC", "60 degC"]\n'
                                  'max_leak_rate = "1.8 ml/min"')
    answers = life_answers(propagate(parse_uncertain_case(life), 4, seed=0))
    assert len(answers) == 2
    for n, a in enumerate(answers):
        q = [[c.records()[n]["leak_rate_effective_medium"] for c in row] for row in cells]
        _check(a, times, temperatures, q, [[limit] * len(times)] * len(temperatures))
    critical = cells[0][0].records()[0]["leak_rate"]
    assert critical > limit >= cells[0][0].records()[0]["leak_rate_effective_medium"]  # the theories disagree here
    assert answers[0].exceeded_from[0] is None  # the effective medium holds to 1 d at -10 °C




def test_a_standard_flow_limit_is_the_gas_s_throughput_at_each_temperature():
    """0.15 sccm is a molar flow: at 150 °C it is the pV throughput 0.15 cm³/min × 101325 Pa × 423.15 K/273.15 K,
    44 % more than at 20 °C (ideal gas). Compared so, the ring at 300 kPa holds it after a day at 150 °C and not at
    20 °C; against the 20 °C throughput it would exceed it at both."""
    times, temperatures = (100.0, 86400.0), (293.15, 423.15)
    cells = [[_cell(GAS_RING, f"{t} s", f"{T} K") for t in times] for T in temperatures]
    limit = [[0.15e-6 / 60 * 101325 * T / 273.15] * len(times) for T in temperatures]  # Pa·m³/s
    life = GAS_RING.replace("{cell}", 'time = ["100 s", "1 d"]\ntemperature = ["20 degC", "150 degC"]\n'
                                      'max_leak_rate = "0.15 sccm"')
    result = propagate(parse_uncertain_case(life), 4, seed=0)
    answers = life_answers(result)
    assert len(answers) == 2
    assert volume_limit(result) is None  # no one line in the figures: a throughput per temperature
    for n, a in enumerate(answers):
        _check(a, times, temperatures, [[c.records()[n]["leak_rate_pv"] for c in row] for row in cells], limit)
    hot = cells[1][1].records()[1]["leak_rate_pv"]
    assert limit[0][0] < hot <= limit[1][1]  # the two limits give two answers here
    assert answers[1].holds_from is not None and 293.15 < answers[1].holds_from < 423.15


STUDY = '\n[study]\nvary = "surface.h_rms"\nvalues = ["3 um", "5 um"]\n'


def test_each_study_variant_gets_answers_of_its_own():
    """A [study] with life keys: each variant's (T, t) cases are answered apart, named by the variant, from separate
    runs of its own cells (the rougher surface exceeds 0.5 ml/min at 50 kPa where the smoother one holds)."""
    text = RING.format(rubber=WLF, seal="", conditions="{cell}")
    times, temperatures = (10.0, 3600.0, 86400.0), (263.15, 333.15)
    limit = [[0.5e-6 / 60] * len(times)] * len(temperatures)  # m³/s
    life = text.replace("{cell}", 'time = ["10 s", "1 h", "1 d"]\ntemperature = ["-10 degC", "60 degC"]\n'
                                  'max_leak_rate = "0.5 ml/min"') + STUDY
    result = propagate(parse_uncertain_case(life), 4, seed=0)
    answers = life_answers(result)
    assert [(a.variant, a.row) for a in answers] == [("h_rms = 3 um", 0), ("h_rms = 3 um", 1),
                                                     ("h_rms = 5 um", 0), ("h_rms = 5 um", 1)]
    for a in answers:
        alone = text.replace('h_rms = "5 um"', f'h_rms = "{a.variant.split(" = ")[1]}"')
        cells = [[_cell(alone, f"{t} s", f"{T} K") for t in times] for T in temperatures]
        _check(a, times, temperatures, [[c.records()[a.row]["leak_rate"] for c in row] for row in cells], limit)
    assert answers[0].exceeded_from == (None, None) and answers[2].exceeded_from == (10.0, 10.0)
    lines = passing_lines(result)
    assert any(line.startswith("h_rms = 3 um, P0 = 50 kPa: at -10 °C holds to 1 d") for line in lines)
    assert any(line.startswith("h_rms = 5 um, P0 = 50 kPa: at -10 °C exceeds") for line in lines)
    assert [x["variant"] for x in uncertainty_summary(result)["life"]] == [a.variant for a in answers]
