"""User text in figures is drawn as written (issue 21 §5): '$' in a title, a label, a study label or a
file name is no matplotlib mathtext, so no figure fails to render and the text appears literally."""

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.text import Text

from sealeak.cases import parse_case_file, read_case_file, rig_prediction, run_case, run_fit, simulate
from sealeak.cli import main
from sealeak.lab.data import read_leak_data
from sealeak.render import figure_fit, figure_rig, prediction_figures
from sealeak.render.figures import figure_png
from sealeak.render.plotstyle import wrap_phrases
from sealeak.render.report import html_report
from sealeak.render.simulation import simulation_figures
from tests.casefiles import edit

TITLE = "$\\foo$"
LABEL = "h_rms $h_{rms$"
STUDY_LABEL = "$x$ rough $"
STUDY = f"""
[study]
vary = "surface.h_rms"
values = ["44 um", "20 um"]
labels = ["{LABEL}", "{STUDY_LABEL}"]
"""
RIG = """
[rig]
cylinder_diameter = "3 cm"
initial_height = "1 m"
final_height = "0.5 m"
load = "3.4 kg"
density = "1000 kg/m^3"
"""


def _texts(fig: Figure) -> list[Text]:
    return [t for t in fig.findobj(Text) if t.get_text()]


def _case_text(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "dollar.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _assert_literal(figs: dict[str, Figure], wanted: tuple[str, ...]) -> None:
    """Every figure renders to PNG and all its texts are literal; each wanted string appears, as written, in some figure."""
    shown = []
    for name, fig in figs.items():
        assert figure_png(fig).startswith(b"\x89PNG"), name
        texts = _texts(fig)
        assert all(not t.get_parse_math() for t in texts), name
        shown += [t.get_text() for t in texts]
    for w in wanted:
        assert any(w in t for t in shown), f"{w!r} appears in none of {sorted(figs)}"


def test_every_prediction_figure_of_a_study_with_dollar_text(tmp_path):
    text = edit('title = "test case"', f'title = "{TITLE.replace(chr(92), chr(92) * 2)}"') + RIG + STUDY
    results = [run_case(c) for c in read_case_file(_case_text(tmp_path, text)).cases]
    assert results[0].case.title == TITLE
    figs = prediction_figures(results)
    _assert_literal(figs, (LABEL, STUDY_LABEL))  # the study labels, as written, in the legends
    rig = rig_prediction(results[0].case)
    _assert_literal({"rig.png": figure_rig(results[0].case.rig, rig.columns, rig.squeeze_pressure, f"load of {TITLE}")}, (TITLE,))
    report = html_report(results, read_case_file(_case_text(tmp_path, text)).inputs)
    assert "<img" in report and "$\\foo$" in report


def test_band_figures_and_a_fit_to_a_file_named_with_dollars(tmp_path):
    text = edit('title = "test case"', f'title = "{TITLE.replace(chr(92), chr(92) * 2)}"')
    text = edit('shape = "ring"\ninner_diameter = "3 cm"\nouter_diameter = "4 cm"',
                'shape = "o-ring"\ncross_section_diameter = "2.62 mm"\ninner_diameter = "20 mm"', text)
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'compression = ["15 %", "25 %"]', text)
    text = edit('[surface]\n', f'[surface]\nlabel = "{LABEL}"\n', text)
    case = read_case_file(_case_text(tmp_path, text)).cases[0]
    _assert_literal(prediction_figures([run_case(case)]), (LABEL,))
    data_file = tmp_path / "$ring$ data.csv"
    data_file.write_text("compression (%), leak_rate (ml/min)\n15, 1e-4\n20, 3e-5\n25, 1e-6\n", encoding="utf-8")
    fit = run_fit(case, read_leak_data(data_file, load_column="compression"))
    _assert_literal({"fit.png": figure_fit(fit)}, ())


def test_cli_plots_of_a_case_titled_with_dollars(tmp_path, capsys):
    text = edit('title = "test case"', f'title = "{TITLE.replace(chr(92), chr(92) * 2)}"')
    text = edit('[surface]\n', f'[surface]\nlabel = "{LABEL}"\n', text)
    case = _case_text(tmp_path, text)
    assert main(["predict", str(case), "--plots", str(tmp_path / "plots"), "-q"]) == 0
    assert "Traceback" not in capsys.readouterr().err
    assert len(list((tmp_path / "plots").glob("*.png"))) >= 9


def test_subtitles_wrap_between_phrases():
    line = ("Q_pV = K ∫ p f(Kn) dp over P_b…P_a, K through the band (strips in series), Ly = 71.06 mm, η = 19.62 µPa·s, "
            "α = 1")
    lines = wrap_phrases(line, 92)
    assert len(lines) == 2 and all(len(s) <= 92 for s in lines)
    assert lines[1] == "η = 19.62 µPa·s, α = 1"  # not "η" on one line and "= 19.62 µPa·s" on the next
    assert " ".join(lines) == line
    assert wrap_phrases("a (b, c), d", 10) == ["a (b, c),", "d"]  # no break inside brackets


def test_simulated_loads_without_a_leak_channel_are_marked_at_the_axis_bottom():
    case = parse_case_file(edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                                'squeeze_pressure = ["20 kPa", "1 MPa", "3 MPa"]')).cases[0]
    res = simulate(case, grid=32, realizations=1, seed=0)
    sealed = res.leak_rate == 0
    assert sealed.any() and not sealed.all()
    fig = simulation_figures(case, res)["simulate_leak_rate.png"]
    ax = fig.axes[0]
    marks = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert len(marks) == 1 and "no leak channel" in marks[0].get_label()
    scale = res.squeeze_pressure[sealed] / np.asarray(marks[0].get_xdata())
    assert np.allclose(scale, scale[0], rtol=1e-9)  # one × per sealed load, at its pressure
    assert np.allclose(marks[0].get_ydata(), 0.0)  # the bottom edge (axes units)
    lo, hi = ax.get_xlim()
    assert lo <= float(np.min(marks[0].get_xdata())) and float(np.max(marks[0].get_xdata())) <= hi
    legends = [leg for leg in (ax.get_legend(), *fig.legends) if leg is not None]  # inside the axes or below them
    assert any("no leak channel" in t.get_text() for leg in legends for t in leg.get_texts())
