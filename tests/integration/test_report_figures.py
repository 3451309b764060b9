"""The HTML report says what `sealeak predict` says, and the figure outputs of every command are all or nothing.

* the report's result tables have the columns and digits of the command-line table (ml/min and
  the validity verdict included), its figures sit in a grid with captions that say what they
  show, its inputs include [study], its warnings and validity notes are those of the run, and the
  rig section gives Q at the initial height and the time constant τ;
* a sweep without any leak channel draws its figures through the CLI (no traceback, no warning);
* when drawing a figure fails, no output of the command is left or replaced.
"""

import html
import math
import re
from html.parser import HTMLParser

import pytest

from sealeak.cases import example_path, load_cases, read_case_file, run_case
from sealeak.cli import main
from sealeak.render import PREDICTION_FIGURE_NAMES
from tests.casefiles import BASE, edit


class _Report(HTMLParser):
    """Tables (rows of cell texts, with each row's class), figures and captions of a report."""

    def __init__(self):
        super().__init__()
        self.tables, self.figures, self.captions, self.grid_figures = [], [], [], 0
        self._cell, self._row, self._caption, self._grid_depth, self._div_depth = None, None, None, None, 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "div":
            self._div_depth += 1
            if a.get("class") == "figures":
                self._grid_depth = self._div_depth
        elif tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self._row = ([], a.get("class", ""))
        elif tag in ("td", "th"):
            self._cell = ""
        elif tag == "figure":
            self.figures.append(a.get("id", ""))
            self.grid_figures += self._grid_depth is not None
        elif tag == "figcaption":
            self._caption = ""

    def handle_endtag(self, tag):
        if tag == "div":
            if self._grid_depth == self._div_depth:
                self._grid_depth = None
            self._div_depth -= 1
        elif tag in ("td", "th"):
            self._row[0].append(self._cell.strip())
            self._cell = None
        elif tag == "tr":
            self.tables[-1].append(self._row)
        elif tag == "figcaption":
            self.captions.append(self._caption.strip())
            self._caption = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data
        if self._caption is not None:
            self._caption += data


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The report and the command-line table of a study (hrms-study) and of a case with a rig."""
    out = {}
    folder = tmp_path_factory.mktemp("reports")
    for name in ("hrms-study", "reference-experiment"):
        path = folder / f"{name}.html"
        table = folder / f"{name}.txt"
        assert main(["report", "--example", name, "-o", str(path), "-q"]) == 0
        assert main(["predict", "--example", name, "--table", str(table), "-q"]) == 0
        parser = _Report()
        text = path.read_text()
        parser.feed(text)
        out[name] = (text, parser, table.read_text())
    return out


def _cli_tables(text):
    """The rows of the command-line tables: each header line and the rows under it, split into cells."""
    tables, current = [], None
    for line in text.splitlines():
        if line.strip().startswith("P0 (kPa)"):
            current = [re.split(r"\s{1,}(?=\S)", line.strip())]
            tables.append(current)
        elif current is not None and re.match(r"^\s*[\d.e+-]+\s", line):
            current.append(line.split())
        else:
            current = None
    return tables


@pytest.mark.parametrize("name", ["hrms-study", "reference-experiment"])
def test_report_tables_have_the_columns_and_digits_of_the_command_line(name, reports):
    text, report, cli = reports[name]
    cli_tables = _cli_tables(cli)
    html_tables = [t for t in report.tables if t and t[0][0] and t[0][0][0] == "P0 (kPa)"]
    assert len(html_tables) == len(cli_tables) >= 1
    for cli_rows, html_rows in zip(cli_tables, html_tables):
        header = [c for c in html_rows[0][0]]
        assert any("ml/min" in h for h in header) and header[-1] == "valid"
        # the command line pads the header with spaces; compare its words
        assert " ".join(cli_rows[0]).split() == " ".join(header).split()
        assert [r for r in cli_rows[1:]] == [cells for cells, _ in html_rows[1:]]
        # rows outside the theory's validity are highlighted, and only those
        for cells, cls in html_rows[1:]:
            assert (cls == "invalid") == ("NO" in cells[-1].split("/"))


def test_report_of_a_study_shows_the_study_the_verdicts_and_the_warnings(reports):
    text, report, _ = reports["hrms-study"]
    results = [run_case(c) for c in read_case_file(example_path("hrms-study")).cases]
    assert "[study] vary" in text and "surface.h_rms" in text and "[study] values" in text
    assert sum(cls == "invalid" for t in report.tables for _, cls in t) == sum(int((~r.valid).sum()) for r in results) > 0
    assert "below the molecular size" in text
    for r in results:
        for w in r.warnings:
            assert html.escape(w, quote=True) in text


@pytest.mark.parametrize("name", ["hrms-study", "reference-experiment"])
def test_report_figures_sit_in_a_grid_with_captions_that_say_what_they_show(name, reports):
    text, report, _ = reports[name]
    assert ".figures { display: grid" in text
    prediction = [f"fig-{n}" for n in PREDICTION_FIGURE_NAMES]
    assert [f for f in report.figures if f in prediction] == prediction
    assert report.grid_figures == len(report.figures)  # every figure, the rig's too, is in a grid
    assert len(set(report.captions)) == len(report.captions) == len(report.figures)
    for caption in report.captions:
        assert ".png" not in caption and len(caption) > 60, caption


def test_report_rig_gives_q_at_the_initial_height_and_the_time_constant(reports):
    text, report, _ = reports["reference-experiment"]
    case = load_cases(example_path("reference-experiment"))[0]
    rig = case.rig
    (table,) = [t for t in report.tables if t and "τ (min)" in t[0][0]]
    header = table[0][0]
    for cells, _ in table[1:]:
        row = dict(zip(header, cells))
        k = float(row["K = Q/ΔP (m³/(s·Pa))"])
        q0 = k * rig.density * 9.80665 * rig.initial_height  # Q = K ΔP, ΔP = ρ g H0
        assert float(row["Q at H0 (m³/s)"]) == pytest.approx(q0, rel=2e-3)
        assert float(row["Q at H0 (ml/min)"]) == pytest.approx(q0 * 6e7, rel=2e-3)
        area = math.pi * rig.cylinder_diameter ** 2 / 4
        assert float(row["τ (min)"]) * 60 == pytest.approx(area / (k * rig.density * 9.80665), rel=2e-3)
    # one theory computed: neither "both theories" nor a legend of Q_CJ/Q_EM columns the tables do not have
    assert len(table) == 2 and "The theory is linear in ΔP" in text and "Both theories" not in text
    assert "Q_EM" not in text and "Q_CJ" not in text


# ---------------------------------------------------------------------- figures through the command line
@pytest.mark.filterwarnings("error")
def test_predict_plots_a_sweep_without_any_leak_channel(tmp_path, capsys):
    case = tmp_path / "tight.toml"
    case.write_text(edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["100 MPa"]'))
    plots = tmp_path / "plots"
    assert main(["predict", str(case), "--plots", str(plots), "--json", str(tmp_path / "r.json"), "-q"]) == 0
    assert capsys.readouterr().err == ""
    for name in PREDICTION_FIGURE_NAMES:
        assert (plots / name).read_bytes()[:4] == b"\x89PNG", name


def _boom(*args, **kwargs):
    raise RuntimeError("drawing failed")


@pytest.fixture
def linearity_data(tmp_path):
    data = tmp_path / "dp.csv"
    data.write_text("pressure_difference (kPa), leak_rate (ml/min)\n2, 14\n4, 29\n6, 43\n8, 58\n")
    return data


@pytest.mark.parametrize("command, patched, outputs", [
    (["predict", "CASE"], "prediction_figures", ["--table", "--json", "--csv"]),
    (["fit", "--example", "reference-experiment", "--linearity", "--data", "DATA"], "figure_linearity", ["--json"]),
    (["rig", "--example", "reference-experiment"], "figure_rig", ["--json"]),
])
def test_a_failure_while_drawing_leaves_no_output(command, patched, outputs, tmp_path, monkeypatch, linearity_data):
    case = tmp_path / "case.toml"
    case.write_text(BASE)
    argv = [str(case) if a == "CASE" else str(linearity_data) if a == "DATA" else a for a in command]
    old = {}
    for option in outputs:
        path = tmp_path / f"out{option.strip('-')}"
        path.write_text("earlier output\n")
        old[path] = path.read_text()
        argv += [option, str(path)]
    plots = tmp_path / "plots"
    argv += ["--plots", str(plots), "--force", "-q"]
    monkeypatch.setattr(f"sealeak.render.{patched}", _boom)
    with pytest.raises(RuntimeError, match="drawing failed"):
        main(argv)
    for path, text in old.items():
        assert path.read_text() == text, path  # not replaced
    assert not plots.exists() or not any(plots.iterdir())
    assert not any(p.name.endswith(".part") for p in tmp_path.rglob("*"))
