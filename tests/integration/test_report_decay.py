"""The HTML report of a case with a pressure-decay rig (docs/theory.md §11.7)."""

from sealeak.cli import main


def test_report_of_a_pressure_decay_case_has_the_test_and_its_figure(tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["report", "--example", "pressure-decay", "-o", str(out)]) == 0
    capsys.readouterr()
    html = out.read_text(encoding="utf-8")
    assert "Virtual pressure-decay test" in html and "Virtual water-column rig" not in html
    assert "V·ΔP/Δt" in html and "mbar·l/s" in html
    assert html.count("data:image/png;base64,") >= 2
