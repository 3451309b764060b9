"""A gas case's report and the verdicts of both theories (issue 21 §3).

* the report of a gas case has the gas tables of ``sealeak predict`` (Q_pV in Pa·m³/s and mbar·l/s,
  Kn, the regime, the helium equivalent) whose numbers are ``predict --json``'s, says what the gas
  model assumes (not an incompressible fluid), marks the incompressible Q as such, and its leak-rate
  captions name the units the figures draw (mbar·l/s, Pa·m³/s);
* a band seal with ``model = "both"`` has one labelled verdict column per theory, each theory judged
  at its own narrowest gap, and the uniform-seal comparison Q_u(p_mean) is named with its unit;
* ``sealeak fit`` names the rows that ``predict`` marks outside a theory's validity (kept in the fit).
"""

import csv
import html
import json
import re

import pytest

from sealeak.cases.loader import example_text
from sealeak.cli import main
from tests.casefiles import edit

RTOL = 1e-9


def _cells(row_html):
    """(text, data-value or None) of each cell of a table row."""
    return [(html.unescape(text).strip(), float(value) if value else None)
            for value, text in re.findall(r'<td(?: class="k")?(?: data-value="([^"]*)")?>([^<]*)</td>', row_html)]


def _tables(text):
    """Each table of a report: (header cells, rows of (text, data-value) cells), in order."""
    out = []
    for table in re.findall(r"<table>(.*?)</table>", text, re.S):
        rows = re.findall(r"<tr[^>]*>(.*?)</tr>", table, re.S)
        header = [html.unescape(h) for h in re.findall(r"<th[^>]*>([^<]*)</th>", rows[0])]
        out.append((header, [_cells(r) for r in rows[1:]]))
    return out


def _captions(text):
    return dict(re.findall(r'<figure id="fig-([^"]+)">.*?<figcaption>(.*?)</figcaption>', text, re.S))


@pytest.fixture(scope="module")
def gas_runs(tmp_path_factory):
    """The report and the ``predict --json`` document of the two bundled gas cases."""
    folder = tmp_path_factory.mktemp("gas")
    out = {}
    for name in ("helium-test", "pressure-decay"):
        report, doc = folder / f"{name}.html", folder / f"{name}.json"
        assert main(["report", "--example", name, "-o", str(report), "-q"]) == 0
        assert main(["predict", "--example", name, "--json", str(doc), "-q"]) == 0
        out[name] = (report.read_text(encoding="utf-8"), json.loads(doc.read_text(encoding="utf-8")))
    return out


def _gas_tables(text):
    return [t for t in _tables(text) if "Q_pV (Pa·m³/s)" in t[0]]


# the gas table's columns and the predict --json fields they show (the effective medium's carry a suffix)
GAS_FIELDS = {"Kn": "knudsen_number", "Q_pV (Pa·m³/s)": "leak_rate_pv", "Q (mbar·l/s)": "leak_rate_mbar_l_s",
              "ṁ (kg/s)": "leak_rate_mass", "ṅ (mol/s)": "leak_rate_molar", "Q (sccm)": "leak_rate_sccm",
              "He-eq (mbar·l/s)": "leak_rate_helium_mbar_l_s"}


@pytest.mark.parametrize("name, theories", [("helium-test", [""]), ("pressure-decay", ["", "_effective_medium"])])
def test_gas_report_tables_show_the_leak_rates_of_predict_json(gas_runs, name, theories):
    text, doc = gas_runs[name]
    tables = _gas_tables(text)
    assert len(tables) == len(theories)
    for (header, rows), suffix in zip(tables, theories):
        assert "regime" in header and "He-eq (mbar·l/s)" in header
        assert len(rows) == len(doc["results"])
        for cells, record in zip(rows, doc["results"]):
            for head, field in GAS_FIELDS.items():
                shown, value = cells[header.index(head)]
                expected = record[field + suffix]
                if expected is None:  # no leak channel: no number, a dash
                    assert value is None and shown == "—"
                    continue
                # the cell carries the record's number in full, and shows it rounded
                assert value == pytest.approx(expected, rel=RTOL, abs=0)
                assert float(shown) == pytest.approx(expected, rel=5e-3, abs=0)
            assert cells[header.index("regime")][0] == (record["flow_regime" + suffix] or "—")
        # 1 mbar·l/s = 0.1 Pa·m³/s: the two columns are one throughput
        pv = [c[header.index("Q_pV (Pa·m³/s)")][1] for c in rows]
        mbar = [c[header.index("Q (mbar·l/s)")][1] for c in rows]
        for a, b in zip(pv, mbar):
            assert (a is None) == (b is None)
            if a is not None:
                assert b == pytest.approx(10 * a, rel=RTOL, abs=0)
    # the helium test at 10 % compression leaks: the table holds a real Q_pV
    if name == "helium-test":
        assert any(c[tables[0][0].index("Q_pV (Pa·m³/s)")][1] for c in tables[0][1])


@pytest.mark.parametrize("name", ["helium-test", "pressure-decay"])
def test_gas_report_says_what_the_gas_model_assumes_and_marks_the_incompressible_q(gas_runs, name):
    text, _ = gas_runs[name]
    plain = html.unescape(re.sub(r"<[^>]+>", " ", text))
    assert "incompressible Newtonian" not in plain
    assumptions = plain[plain.index("Assumptions"):plain.index("Results")]
    for phrase in ("ideal gas", "compressible, isothermal", "Q_pV = K ∫ p f(Kn) dp", "Rarefaction", "Kn"):
        assert phrase in assumptions
    # the incompressible K ΔP columns of the main table say what they are
    q_heads = [h for header, _ in _tables(text) for h in header
               if h.startswith("Q") and ("(m³/s)" in h or "(ml/min)" in h)]
    assert q_heads and all("incompr." in h for h in q_heads)
    assert "for comparison only" in plain


def test_gas_report_captions_name_the_units_the_figures_draw(gas_runs):
    band = _captions(gas_runs["helium-test"][0])
    assert "mbar·l/s" in band["leak_rate.png"] and "Pa·m³/s" in band["leak_rate.png"]
    assert "m³/s on the left" not in band["leak_rate.png"] and "ml/min" not in band["leak_rate.png"]
    uniform = _captions(gas_runs["pressure-decay"][0])
    for name in ("leak_rate.png", "leak_rate_log.png", "leak_rate_vs_pressure_difference.png"):
        assert "mbar·l/s" in uniform[name] and "ml/min" not in uniform[name]
    # a gas's Q_pV is not linear in ΔP
    assert "straight line" not in uniform["leak_rate_vs_pressure_difference.png"].replace("not a straight line", "")


def test_pressure_decay_report_shows_the_test(gas_runs):
    text, _ = gas_runs["pressure-decay"]
    rig = html.unescape(text[text.index('id="rig"'):])
    assert "time to lose ΔP = 5 mbar" in rig and "standard leak rate V·ΔP/Δt" in rig
    assert "critical junction" in rig and "effective medium" in rig


# ---------------------------------------------------------------- model "both": a verdict per theory
@pytest.fixture(scope="module")
def oring_both(tmp_path_factory):
    """The o-ring example's water variant (model "both") at 15, 20 and 27.5 % compression: table, JSON, CSV, report."""
    folder = tmp_path_factory.mktemp("both")
    text = example_text("o-ring").split("[study]")[0]
    text = re.sub(r"(?m)^compression = .*$", 'compression = ["15 %", "20 %", "27.5 %"]', text)
    assert 'model = "both"' in text
    case = folder / "ring.toml"
    case.write_text(text, encoding="utf-8")
    paths = {k: folder / f"out.{k}" for k in ("txt", "json", "csv", "html")}
    assert main(["predict", str(case), "--table", str(paths["txt"]), "--json", str(paths["json"]),
                 "--csv", str(paths["csv"]), "-q"]) == 0
    assert main(["report", str(case), "-o", str(paths["html"]), "-q"]) == 0
    return {k: p.read_text(encoding="utf-8") for k, p in paths.items()}


def test_both_model_band_table_has_a_labelled_verdict_per_theory(oring_both):
    rows = json.loads(oring_both["json"])["results"]
    cj = [r["valid"] for r in rows]
    em = [r["valid_effective_medium"] for r in rows]
    # each theory judged at its own narrowest gap: here they disagree, once each way
    assert cj != em and (True in cj) and (False in cj) and (False in em)
    for r in rows:
        if not r["valid_effective_medium"]:
            assert "u_e" in r["validity_effective_medium"] and "molecular size" in r["validity_effective_medium"]
    lines = oring_both["txt"].splitlines()
    at = next(i for i, line in enumerate(lines) if line.strip().startswith("ε (%)"))
    header = re.split(r"\s{2,}", lines[at].strip())
    assert "valid CJ" in header and "valid EM" in header and "valid" not in header
    assert "Q_u,CJ(p_mean) (m³/s)" in header
    for k, r in enumerate(rows):
        cells = re.split(r"\s{2,}", lines[at + 1 + k].strip())
        assert len(cells) == len(header)
        verdict = {"valid CJ": ("valid", "percolates"), "valid EM": ("valid_effective_medium", "percolates_effective_medium")}
        for head, (key, channel) in verdict.items():
            assert cells[header.index(head)] == ("—" if not r[channel] else "yes" if r[key] else "NO")
        q_u = r["leak_rate_uniform_mean_pressure"]
        shown = cells[header.index("Q_u,CJ(p_mean) (m³/s)")]
        assert (shown == "—") if q_u is None else float(shown) == pytest.approx(q_u, rel=5e-3, abs=0)
    assert "Q_u,CJ(p_mean): the leak rate of a uniform seal of the same width and length at the mean contact pressure" \
        in oring_both["txt"]
    # the CSV header names the second verdict and the JSON declares its unit
    head = next(csv.reader(oring_both["csv"].splitlines()))
    assert "valid_effective_medium (1)" in head and "leak_rate_uniform_mean_pressure (m^3/s)" in head
    assert json.loads(oring_both["json"])["units"]["valid_effective_medium"] == "1"


def test_both_model_band_report_highlights_a_row_either_theory_rejects(oring_both):
    rows = json.loads(oring_both["json"])["results"]
    text = oring_both["html"]
    table = re.search(r"<table>(<tr><th[^>]*>ε \(%\).*?)</table>", text.replace("\n", ""), re.S).group(1)
    header = [html.unescape(h) for h in re.findall(r"<th[^>]*>([^<]*)</th>", table)]
    assert "valid CJ" in header and "valid EM" in header and "Q_u,CJ(p_mean) (m³/s)" in header
    # each theory's leak rate in ml/min too (the effective medium's had none)
    assert {"Q_CJ (m³/s)", "Q_CJ (ml/min)", "Q_EM (m³/s)", "Q_EM (ml/min)"} <= set(header)
    cells = [[html.unescape(c) for c in re.findall(r"<td[^>]*>([^<]*)</td>", row)]
             for row in re.findall(r"<tr(?: class=\"[^\"]*\")?>(<td.*?)</tr>", table)]
    column = header.index("Q_EM (ml/min)")
    for row, record in zip(cells, rows, strict=True):
        if record["percolates_effective_medium"]:
            assert float(row[column]) == pytest.approx(record["leak_rate_effective_medium"] * 6e7, rel=1e-3, abs=0)
    classes = re.findall(r'<tr(?: class="([^"]*)")?><td', table)
    assert classes == ["invalid" if not (r["valid"] and r["valid_effective_medium"]) else "" for r in rows]
    assert "valid EM = NO (effective medium)" in html.unescape(text)


# ---------------------------------------------------------------- fit: rows outside the theory's validity
def test_fit_names_the_rows_predict_marks_invalid(tmp_path, capsys):
    data = example_text("o-ring-measured.csv")
    (tmp_path / "m.csv").write_text(data, encoding="utf-8")
    text = example_text("o-ring").split("[study]")[0]
    loads = [float(line.split(",")[0]) for line in data.splitlines() if line[:1].isdigit()]
    text = re.sub(r"(?m)^compression = .*$", "compression = [" + ", ".join(f'"{v:g} %"' for v in loads) + "]", text)
    (tmp_path / "c.toml").write_text(text, encoding="utf-8")
    assert main(["predict", str(tmp_path / "c.toml"), "--json", str(tmp_path / "p.json"), "-q"]) == 0
    assert main(["fit", str(tmp_path / "c.toml"), "--data", str(tmp_path / "m.csv"), "--json", str(tmp_path / "f.json")]) == 0
    printed = capsys.readouterr().out
    predicted = json.loads((tmp_path / "p.json").read_text())["results"]
    fit = json.loads((tmp_path / "f.json").read_text())
    lines = data.splitlines()
    line_of = {float(line.split(",")[0]): n for n, line in enumerate(lines, start=1) if line[:1].isdigit()}
    for model, key in (("critical_junction", "valid"), ("effective_medium", "valid_effective_medium")):
        invalid = [line_of[round(100 * r["compression"], 6)] for r in predicted if r["percolates"] and not r[key]]
        assert fit[model]["outside_validity_lines"] == invalid
        assert fit[model]["points_used"] == len(loads)  # kept in the fit
    invalid = fit["critical_junction"]["outside_validity_lines"]
    assert invalid  # the example's 20 % row: u_c at the peak pressure is below a water molecule
    note = next(m for m in fit["messages"] if m.startswith("critical junction: line"))
    for n in invalid:
        assert f"{n} (compression {lines[n - 1].split(',')[0]} %)" in note
    assert "outside the theory's validity" in note and "kept in the fit" in note
    assert "note: " + note in printed


def test_fit_of_a_uniform_seal_names_the_rows_predict_marks_invalid(tmp_path, capsys):
    # near the percolation threshold u_c falls below a molecule (850 kPa), far from it not (100, 400 kPa)
    case = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                'squeeze_pressure = ["100 kPa", "400 kPa", "850 kPa"]', edit("alpha = 0.2", 'alpha = 0.2\nmodel = "both"'))
    (tmp_path / "c.toml").write_text(case, encoding="utf-8")
    (tmp_path / "m.csv").write_text("squeeze_pressure (kPa), leak_rate (m^3/s)\n100, 1e-7\n400, 1e-10\n850, 1e-40\n",
                                    encoding="utf-8")
    assert main(["predict", str(tmp_path / "c.toml"), "--json", str(tmp_path / "p.json"), "-q"]) == 0
    assert main(["fit", str(tmp_path / "c.toml"), "--data", str(tmp_path / "m.csv"), "--json", str(tmp_path / "f.json"),
                 "-q"]) == 0
    capsys.readouterr()
    predicted = json.loads((tmp_path / "p.json").read_text())["results"]
    fit = json.loads((tmp_path / "f.json").read_text())
    for model, key in (("critical_junction", "valid"), ("effective_medium", "valid_effective_medium")):
        # data line n + 2 is predict's row n (a header line first)
        assert fit[model]["outside_validity_lines"] == [n + 2 for n, r in enumerate(predicted) if not r[key]]
    assert fit["critical_junction"]["outside_validity_lines"] == [4]
    assert fit["critical_junction"]["points_used"] == 3
    assert any(m.startswith("critical junction: line 4 (P0 = 850 kPa) outside the theory's validity")
               for m in fit["messages"])
