"""The figures of ``sealeak simulate`` (issue 22 §7): the periodic square and the O-ring, liquid and gas.

Tiny grids through the library. Every figure must read right (the checks every figure passes,
tests/integration/test_figures_render.py: nothing outside the figure, no legend over data, ticks or labels),
draw its texts literally, and show what the result holds: the simulated leak rates as points, the loads where
no realisation leaks as × on the bottom edge, the gas leak in mbar·l/s (1 mbar·l/s = 100 Pa × 10⁻³ m³ =
0.1 Pa·m³/s) with a second axis in Pa·m³/s, the liquid leak in m³/s with one in ml/min, and α_gas beside α.
"""

from functools import partial

import numpy as np
import pytest
from matplotlib.text import Text

from sealeak.cases import parse_case_file, simulate
from sealeak.cases.simulation_band import simulate_band
from sealeak.render.simulation import (
    BAND_SIMULATION_FIGURE_NAMES,
    SIMULATION_FIGURE_NAMES,
    SIMULATION_GAS_FIGURE_NAMES,
    band_simulation_figures,
    simulation_figures,
)
from tests.casefiles import edit
from tests.integration.test_cli_simulate_oring import ORING as ROUGH_ORING
from tests.integration.test_figures_render import _build, figure_problems

#: A uniform seal whose highest squeeze pressure seals the square (no leak channel in any realisation).
SQUARE = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "60 kPa", "3 MPa"]')
SQUARE_GAS = edit('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "helium"\ntemperature = "20 degC"',
                  edit('pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"', SQUARE))
#: An O-ring on a rough face that leaks at the lowest compression and seals at the highest.
ORING = edit('compression = ["3 %", "5 %"]', 'compression = ["2 %", "12 %"]', ROUGH_ORING)
ORING_GAS = edit('viscosity = "1 mPa*s"', 'name = "helium"\ntemperature = "20 degC"',
                 edit('pressure_difference = "1 bar"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"', ORING))
PA_M3_PER_MBAR_L = 100.0 * 1e-3  # 1 mbar·l/s in Pa·m³/s


@pytest.fixture(scope="module")
def runs():
    """(result, figures) of each route, by name."""
    out = {}
    for name, text in (("square", SQUARE), ("square-gas", SQUARE_GAS)):
        case = parse_case_file(text).cases[0]
        res = simulate(case, grid=32, realizations=2, seed=1, threshold=False)
        out[name] = (res, _build(partial(simulation_figures, case, res)))
    for name, text in (("o-ring", ORING), ("o-ring-gas", ORING_GAS)):
        case = parse_case_file(text).cases[0]
        res = simulate_band(case, grid=48, realizations=2, seed=3)
        out[name] = (res, _build(partial(band_simulation_figures, case, res)))
    return out


def _legend_texts(fig):
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)
    return [t.get_text() for leg in legends for t in leg.get_texts()]


def _points(ax):
    """(x, y) of the simulated points: the error-bar markers (filled circles without a line)."""
    (line,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o" and ln.get_linestyle() == "None"
               and ln.get_markerfacecolor() != "none"]
    return np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float)


@pytest.mark.parametrize("name", ["square", "square-gas", "o-ring", "o-ring-gas"])
def test_every_simulate_figure_reads_right_and_draws_its_text_literally(runs, name):
    res, figs = runs[name]
    names = BAND_SIMULATION_FIGURE_NAMES if name.startswith("o-ring") else SIMULATION_FIGURE_NAMES
    assert set(figs) == set(names) | (set(SIMULATION_GAS_FIGURE_NAMES) if name.endswith("gas") else set())
    bad = {n: p for n, fig in figs.items() if (p := figure_problems(fig))}
    assert not bad, bad
    for fig in figs.values():
        assert all(not t.get_parse_math() for t in fig.findobj(Text) if t.get_text())


@pytest.mark.parametrize("name", ["square", "o-ring"])
def test_the_liquid_leak_rate_is_drawn_in_m3_per_s_with_sealed_loads_as_crosses(runs, name):
    res, figs = runs[name]
    fig = figs["simulate_leak_rate.png"]
    ax = fig.axes[0]
    sealed = res.leak_rate == 0
    assert sealed.any() and not sealed.all(), "the case must leak at one load and seal at another"
    _, y = _points(ax)
    np.testing.assert_allclose(np.sort(y), np.sort(res.leak_rate[~sealed]), rtol=1e-12)
    (cross,) = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert len(cross.get_xdata()) == int(sealed.sum()) and np.allclose(cross.get_ydata(), 0.0)  # axes units: the bottom
    assert any("no leak channel" in t for t in _legend_texts(fig))
    assert "m³/s" in ax.get_ylabel() and ax.get_yscale() == "log"
    (second,) = ax.child_axes
    assert "ml/min" in second.get_ylabel()


@pytest.mark.parametrize("name", ["square-gas", "o-ring-gas"])
def test_the_gas_leak_is_drawn_in_mbar_l_per_s_with_a_second_axis_in_pa_m3_per_s(runs, name):
    res, figs = runs[name]
    ax = figs["simulate_gas_leak_rate.png"].axes[0]
    leaks = res.gas.throughput > 0
    assert leaks.any()
    _, y = _points(ax)
    np.testing.assert_allclose(np.sort(y) * PA_M3_PER_MBAR_L, np.sort(res.gas.throughput[leaks]), rtol=1e-12)
    assert "mbar·l/s" in ax.get_ylabel()
    (second,) = ax.child_axes
    assert "Pa·m³/s" in second.get_ylabel()
    lo, hi = ax.get_ylim()  # the second axis reads the same leak 10 times smaller in Pa·m³/s
    np.testing.assert_allclose(second.get_ylim(), (lo * PA_M3_PER_MBAR_L, hi * PA_M3_PER_MBAR_L), rtol=1e-9)
    assert "helium" in ax.get_title()


def test_the_alpha_figure_of_a_gas_shows_alpha_gas_beside_alpha(runs):
    res, figs = runs["square-gas"]
    resolved = np.isfinite(res.gas.alpha) & (res.junction_cells >= 8)
    assert resolved.any(), "the case must have an α_gas the grid resolves"
    ax = figs["simulate_alpha.png"].axes[0]
    texts = _legend_texts(figs["simulate_alpha.png"])
    assert any(t.startswith("α_gas") and "helium" in t for t in texts) and any(t.startswith("α = ") for t in texts)
    drawn = [ln for ln in ax.get_lines() if ln.get_marker() == "s"]  # α_gas: squares
    np.testing.assert_allclose(drawn[0].get_ydata(), res.gas.alpha[resolved], rtol=1e-12)


def test_the_grid_flagged_theory_is_dotted_and_the_resolved_one_solid(runs):
    res, figs = runs["square"]
    coarse = np.isfinite(res.junction_cells) & (res.junction_cells < 8)
    assert coarse.any() and (np.isfinite(res.junction_cells) & ~coarse).any()
    ax = figs["simulate_leak_rate.png"].axes[0]
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and "α = 1" in ln.get_label()]
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    assert len(solid) == 1 and len(dotted) == 1
    y = np.asarray(solid[0].get_ydata(), dtype=float)
    assert np.isnan(y[coarse]).all()
    np.testing.assert_allclose(y[~coarse & np.isfinite(y)], res.leak_rate_critical_junction[~coarse & np.isfinite(y)])
    assert "λc < 8 cells" in dotted[0].get_label()


def test_an_oring_whose_theory_has_no_leak_channel_says_so(runs):
    """The series-resistance theory finds no channel (the band's peak pressure seals it): no α, and the figures say why."""
    res, figs = runs["o-ring-gas"]
    assert not np.isfinite(res.gas.throughput_critical_junction).any() and (res.gas.throughput > 0).any()
    assert "series-resistance theory finds no leak channel" in figs["simulate_gas_leak_rate.png"].axes[0].get_title()
    assert any(t.get_text().startswith("no α") for t in figs["simulate_alpha.png"].axes[0].texts)
