"""Figures of the seal over its life (issue 25 item 5): Q against time at each temperature, against temperature at
each time, written by ``predict --plots`` when a file has several times or temperatures, and read right
(the checks of tests/integration/test_figures_render.py)."""

import numpy as np
import pytest

from sealeak.cases import example_text, parse_case_file, run_case
from sealeak.render import prediction_figures
from sealeak.render.figures import prediction_figure_names
from sealeak.render.life import life_figures
from tests.integration.test_figures_render import _assert_reads_right, _build, _data_lines
from tests.unit.test_life_cases import GAS_RING, ORING, RING, WLF

TIMES = 'time = ["0 s", "100 s", "1 h", "1 d"]'


EXPANSION = ('\nthermal_expansion = "23e-5 1/K"', 'gland_thermal_expansion = "1.2e-5 1/K"')  # the O-ring's compression


def _figures(template, conditions):
    rubber, seal = (WLF + EXPANSION[0], EXPANSION[1]) if template is ORING else (WLF, "")
    cases = parse_case_file(template.format(rubber=rubber, conditions=conditions, seal=seal)).cases
    results = [run_case(c) for c in cases]
    return cases, _build(lambda: prediction_figures(results))


@pytest.mark.parametrize("template", [RING, ORING], ids=["ring", "o-ring"])
def test_life_figures_are_drawn_one_line_per_temperature_and_per_time(template):
    cases, figures = _figures(template, TIMES + '\ntemperature = ["-10 degC", "20 degC", "60 degC"]')
    assert {"leak_rate_vs_time.png", "leak_rate_vs_temperature.png"} <= set(figures)
    assert set(figures) == set(prediction_figure_names(cases))
    _assert_reads_right({k: figures[k] for k in ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png")})

    (ax_t,) = [ax for ax in figures["leak_rate_vs_time.png"].axes if ax.get_lines()][:1]
    assert ax_t.get_xscale() == "log"
    assert "t = 0" in ax_t.get_title()  # the time 0 cannot be on a log axis: said so
    lines = _data_lines(ax_t)
    assert [ln.get_label() for ln in lines] == ["T = -10 °C", "T = 20 °C", "T = 60 °C"]
    assert all(len(ln.get_xdata()) == 3 for ln in lines)  # 100 s, 1 h, 1 d
    bottom = [ax for ax in figures["leak_rate_vs_time.png"].axes if _data_lines(ax)][-1]  # the panels share the x axis
    assert bottom.get_xlabel() == "time since assembly t (min)"  # the shortest time shown, 100 s, in minutes
    assert np.allclose(lines[0].get_xdata(), [100 / 60, 60, 1440], rtol=1e-12)

    ax_T = figures["leak_rate_vs_temperature.png"].axes[0]
    lines = _data_lines(ax_T)
    assert [ln.get_label() for ln in lines] == ["t = 0 s", "t = 100 s", "t = 1 h", "t = 1 d"]
    assert np.allclose(lines[0].get_xdata(), [-10, 20, 60], rtol=1e-12)


def test_one_time_gives_no_time_figure_and_one_temperature_no_temperature_figure():
    cases, figures = _figures(RING, TIMES)
    assert "leak_rate_vs_time.png" in figures and "leak_rate_vs_temperature.png" not in figures
    assert set(figures) == set(prediction_figure_names(cases))
    cases, figures = _figures(RING, 'temperature = ["-10 degC", "20 degC"]')
    assert "leak_rate_vs_temperature.png" in figures and "leak_rate_vs_time.png" not in figures
    cases, figures = _figures(RING, "")
    assert not {"leak_rate_vs_time.png", "leak_rate_vs_temperature.png"} & set(figures)


def test_the_specification_is_a_line_and_coinciding_curves_are_said_only_where_they_coincide():
    """A ring creeps (Q changes with time and temperature: no 'coincide' note); an O-ring at fixed compression whose
    compound only relaxes keeps Q with time (its pressure and modulus fall together): the note says so."""
    cases = parse_case_file(RING.format(rubber=WLF, conditions=TIMES + '\ntemperature = ["-10 degC", "60 degC"]',
                                        seal="")).cases
    results = [run_case(c) for c in cases]
    figures = _build(lambda: prediction_figures(results, limit=(1e-12, "6e-5 ml/min")))
    _assert_reads_right({k: figures[k] for k in ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png")})
    for name in ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png"):
        ax = figures[name].axes[0]
        assert "coincide" not in ax.get_title()
        spec = [ln for ln in ax.get_lines() if ln.get_label() == "max_leak_rate = 6e-5 ml/min"]
        assert len(spec) == 1 and spec[0].get_linestyle() == "-."
    cases = parse_case_file(ORING.format(rubber=WLF, conditions=TIMES + '\ntemperature = ["-10 degC", "60 degC"]',
                                         seal="")).cases  # no thermal expansion, a fixed viscosity: nothing moves Q
    results = [run_case(c) for c in cases]
    figures = _build(lambda: prediction_figures(results))
    assert "the curves coincide: Q does not change with temperature" in figures["leak_rate_vs_time.png"].axes[0].get_title()
    assert "the curves coincide: Q does not change with time" in figures["leak_rate_vs_temperature.png"].axes[0].get_title()


def _life_figures(template, conditions):
    """Only the life figures (:func:`sealeak.render.life.life_figures`) of the RING or ORING file with WLF relaxation."""
    cases = parse_case_file(template.format(rubber=WLF, conditions=conditions, seal="")).cases
    results = [run_case(c) for c in cases]
    return _build(lambda: life_figures(results))


def test_each_load_gets_a_panel_of_its_own_and_many_loads_four_spread_ones():
    """The ring of RING has two squeeze pressures: two panels, each headed by its load, one legend; six loads give
    four panels (the first, the last and two between) and say so."""
    figures = _life_figures(RING, 'time = ["100 s", "1 d"]\ntemperature = ["-10 degC", "60 degC"]')
    for name in ("leak_rate_vs_time.png", "leak_rate_vs_temperature.png"):
        panels = [ax for ax in figures[name].axes if _data_lines(ax)]
        assert len(panels) == 2
        assert "at P0 = 50 kPa" in panels[0].get_title() and panels[1].get_title() == "at P0 = 200 kPa"
        assert sum(ax.get_legend() is not None for ax in panels) + len(figures[name].legends) == 1  # one legend
        assert panels[0].get_xlabel() == "" and panels[1].get_xlabel() != ""  # the shared x axis, labelled below
        low, high = (np.concatenate([ln.get_ydata() for ln in _data_lines(ax)]) for ax in panels)
        assert np.nanmax(high) < np.nanmin(low)  # more squeeze, less leak: the panels are not the same load
    six = RING.replace('squeeze_pressure = ["50 kPa", "200 kPa"]',
                       'squeeze_pressure = ["50 kPa", "80 kPa", "110 kPa", "140 kPa", "170 kPa", "200 kPa"]')
    figures = _life_figures(six, 'time = ["100 s", "1 d"]')
    panels = [ax for ax in figures["leak_rate_vs_time.png"].axes if _data_lines(ax)]
    assert len(panels) == 4
    assert "4 of the 6 loads" in panels[0].get_title()
    assert [ax.get_title().splitlines()[-1 if i else 1] for i, ax in enumerate(panels)] == [
        "at P0 = 50 kPa", "at P0 = 110 kPa", "at P0 = 140 kPa", "at P0 = 200 kPa"]
    _assert_reads_right(figures)


def test_a_gas_is_drawn_as_its_pv_throughput_with_its_specification():
    """A gas's leak rate is Q_pV in mbar·l/s (the gas figures' unit), not the incompressible K ΔP of its Q column."""
    text = GAS_RING.replace('["100 kPa", "300 kPa"]', '"100 kPa"').replace("{cell}", 'time = ["100 s", "1 d"]')
    results = [run_case(c) for c in parse_case_file(text).cases]
    figures = _build(lambda: life_figures(results, limit=(1e-7, "1e-6 mbar*l/s")))  # 1e-7 Pa·m³/s = 1e-6 mbar·l/s
    (ax,) = [ax for ax in figures["leak_rate_vs_time.png"].axes if _data_lines(ax)]
    assert ax.get_ylabel() == "gas leak rate Q_pV (mbar·l/s)"
    (line,) = [ln for ln in _data_lines(ax) if len(ln.get_xdata()) == 2]  # one temperature: one line of two times
    expected = [r.records()[0]["leak_rate_mbar_l_s"] for r in results]
    assert np.allclose(line.get_ydata(), expected, rtol=1e-12, atol=0.0)
    assert expected != [r.records()[0]["leak_rate"] for r in results]  # not the incompressible column
    (spec,) = [ln for ln in ax.get_lines() if ln.get_label() == "max_leak_rate = 1e-6 mbar*l/s"]
    assert spec.get_ydata()[0] == pytest.approx(1e-6, rel=1e-12, abs=0)


def _axis_scale(ax):
    """The power of ten a linear leak-rate axis writes in its unit, "leak rate Q (10⁻⁹ m³/s)" → 1e-9 (else 1)."""
    unit = ax.get_ylabel().rsplit("(", 1)[1]
    if not unit.startswith("10"):
        return 1.0
    return 10.0 ** int(unit[2:].split()[0].translate(str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")))


@pytest.mark.parametrize("model, key", [("critical-junction", "leak_rate"),
                                        ("effective-medium", "leak_rate_effective_medium")])
def test_the_figures_draw_the_leak_rate_of_the_theory_the_tables_show(model, key):
    """Each line's y-data are Q of the shown theory at its (time, temperature), read from that case's own record under
    the shown theory's key (not the other theory's Q: they differ by some 20 % here) and scaled by the axis' unit."""
    text = RING.format(rubber=WLF, seal="", conditions='time = ["100 s", "1 d"]\ntemperature = ["-10 degC", "60 degC"]')
    results = [run_case(c) for c in parse_case_file(text + f'\n[theory]\nmodel = "{model}"\n').cases]
    figures = _build(lambda: life_figures(results))
    for n, ax in enumerate(ax for ax in figures["leak_rate_vs_time.png"].axes if _data_lines(ax)):
        for line, temperature in zip(_data_lines(ax), (263.15, 333.15)):
            shown = [r for r in results if r.case.life.temperature == pytest.approx(temperature, rel=1e-12)]
            shown.sort(key=lambda r: r.case.life.time)
            drawn = line.get_ydata() * _axis_scale(ax)
            assert np.allclose(drawn, [r.records()[n][key] for r in shown], rtol=1e-9, atol=0.0)
            if key != "leak_rate":  # the effective medium's records hold the critical junction's Q too: not drawn
                assert not np.allclose(drawn, [r.records()[n]["leak_rate"] for r in shown], rtol=0.05, atol=0.0)
    for n, ax in enumerate(ax for ax in figures["leak_rate_vs_temperature.png"].axes if _data_lines(ax)):
        for line, time in zip(_data_lines(ax), (100.0, 86400.0)):
            shown = sorted((r for r in results if r.case.life.time == time), key=lambda r: r.case.life.temperature)
            assert np.allclose(line.get_ydata() * _axis_scale(ax), [r.records()[n][key] for r in shown], rtol=1e-9, atol=0.0)


def test_each_study_variant_gets_panels_of_its_own():
    """A [study] with life keys: one panel per variant and load, headed by both, each drawing its variant's Q (the
    last variant does not overwrite the others)."""
    study = '\n[study]\nvary = "surface.h_rms"\nvalues = ["3 um", "5 um"]\n'
    text = RING.format(rubber=WLF, seal="", conditions='time = ["100 s", "1 d"]') + study
    results = [run_case(c) for c in parse_case_file(text).cases]
    figures = _build(lambda: life_figures(results))
    panels = [ax for ax in figures["leak_rate_vs_time.png"].axes if _data_lines(ax)]
    heads = ["h_rms = 3 um: at P0 = 50 kPa", "h_rms = 3 um: at P0 = 200 kPa", "h_rms = 5 um: at P0 = 50 kPa",
             "h_rms = 5 um: at P0 = 200 kPa"]
    assert [ax.get_title().splitlines()[1 if k == 0 else 0] for k, ax in enumerate(panels)] == heads
    for ax, head in zip(panels, heads):
        (line,) = _data_lines(ax)
        mine = sorted((r for r in results if r.case.label.startswith(head.split(":")[0])), key=lambda r: r.case.life.time)
        n = 0 if "50 kPa" in head else 1
        assert np.allclose(line.get_ydata() * _axis_scale(ax), [r.records()[n]["leak_rate"] for r in mine],
                           rtol=1e-9, atol=0.0)
    _assert_reads_right(figures)


def test_the_band_figure_of_a_life_file_names_its_time_and_tells_the_helium_equivalent_apart():
    """A life file's leak_rate.png draws the seal as assembled: its title names that time (it named the temperature
    alone), and where each curve is a lone point the helium equivalent's marker differs from the gas's (both were dots
    of one colour, told apart by line styles a lone point does not have)."""
    results = [run_case(c) for c in parse_case_file(example_text("nbr-o-ring-life")).cases]
    figures = _build(lambda: prediction_figures(results))
    (ax,) = [ax for ax in figures["leak_rate.png"].axes if _data_lines(ax)]
    assert ax._sealeak_heading.endswith("against compression at t = 1 h")
    markers = {ln.get_label(): ln.get_marker() for ln in _data_lines(ax) if not ln.get_label().startswith("_")}
    gas = [m for label, m in markers.items() if label.endswith("critical junction")]
    helium = [m for label, m in markers.items() if label.endswith("helium equivalent")]
    assert gas == ["o"] and helium == ["s"], markers
