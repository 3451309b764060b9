"""The pressure-decay figure: a logarithmic time axis when the models' times to lose ΔP differ by more than a
factor 10 (a linear axis would draw the faster model as a vertical line at t = 0), a linear one otherwise."""

import dataclasses

import numpy as np

from sealeak.cases import example_path, load_cases
from sealeak.cases.leak_tests import decay_prediction
from sealeak.render.lab_figures import DECAY_LOG_RATIO, figure_decay


def _axis(pred, rig):
    fig = figure_decay(rig, pred)
    ax = fig.axes[0]
    return ax, [line for line in ax.get_lines() if len(line.get_xdata()) > 2]


def test_times_a_factor_95_apart_share_a_log_axis_each_curve_drawn_whole():
    case = load_cases(example_path("pressure-decay"))[0]
    pred = decay_prediction(case)
    times = [m.decay.time_to_loss for m in pred.models.values()]
    assert max(times) / min(times) > DECAY_LOG_RATIO  # the bundled example's two models are ~95x apart
    ax, curves = _axis(pred, case.rig)
    assert ax.get_xscale() == "log"
    assert len(curves) == len(pred.models)
    for line, m in zip(curves, pred.models.values(), strict=True):
        x = np.asarray(line.get_xdata())
        assert np.all(x > 0)  # t = 0 cannot be drawn on a log axis: each curve starts at its first time > 0
        assert len(x) == np.count_nonzero(m.decay.time > 0)


def test_one_model_keeps_a_linear_axis_from_zero():
    case = load_cases(example_path("pressure-decay"))[0]
    pred = decay_prediction(case)
    first = next(iter(pred.models))
    one = dataclasses.replace(pred, models={first: pred.models[first]})
    ax, curves = _axis(one, case.rig)
    assert ax.get_xscale() == "linear"
    assert ax.get_xlim()[0] == 0
    assert np.asarray(curves[0].get_xdata())[0] == 0
