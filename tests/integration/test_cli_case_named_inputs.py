"""A file a case names (a C(q) table, a topography, a pressure profile) is an input of the run: no
output may replace it, even with --force (docs/cli.md, "Output files")."""

import shutil

import numpy as np
import pytest

from sealeak.cases import example_path, read_case_file
from sealeak.cli import main
from tests.casefiles import edit


def _lip(tmp_path):
    """The bundled lip seal and its pressure profile, copied into ``tmp_path``."""
    for name in ("lip-profile.toml", "lip-profile.csv"):
        shutil.copy(example_path("lip-profile").with_name(name), tmp_path / name)
    return tmp_path / "lip-profile.toml", tmp_path / "lip-profile.csv"


def _table_case(tmp_path, study=False):
    """A case whose C(q) is a table file (psd.csv); with ``study``, a study whose second value names psd2.csv."""
    q = np.geomspace(1e3, 1e7, 40)
    rows = "".join(f"{x:.6e}, {c:.6e}\n" for x, c in zip(q, 1e-20 * (q / 1e3) ** -2.8, strict=True))
    for name in ("psd.csv", "psd2.csv"):
        (tmp_path / name).write_text("q (1/m), C (m^4)\n" + rows)
    text = edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                'cutoff_wavelength = "20 um"\n', 'model = "table"\nfile = "psd.csv"\n')
    if study:
        text += '[study]\nvary = "surface.file"\nvalues = ["psd.csv", "psd2.csv"]\n'
    case = tmp_path / "case.toml"
    case.write_text(text)
    return case


def _refused(capsys, target, before, *names):
    err = capsys.readouterr().err
    assert err.startswith("sealeak: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    assert "even with --force" in err and target.name in err
    for name in names:
        assert name in err, err
    assert target.read_bytes() == before, "the input was replaced"


@pytest.mark.parametrize("option", ["--json", "--csv", "--table"])
def test_predict_never_replaces_the_pressure_profile_its_case_names(tmp_path, capsys, monkeypatch, option):
    case, profile = _lip(tmp_path)
    before = profile.read_bytes()
    monkeypatch.chdir(tmp_path)  # as in the issue: a relative output name that is the profile
    assert main(["predict", case.name, option, "lip-profile.csv", "--force", "-q"]) == 2
    _refused(capsys, profile, before, option)
    assert main(["predict", case.name, "-q"]) == 0  # the next run still works


def test_the_same_file_under_another_name_is_refused(tmp_path, capsys):
    case, profile = _lip(tmp_path)
    before = profile.read_bytes()
    (tmp_path / "out").mkdir()
    assert main(["predict", str(case), "--json", str(tmp_path / "out" / ".." / "lip-profile.csv"), "--force", "-q"]) == 2
    _refused(capsys, profile, before)


@pytest.mark.parametrize("study", [False, True], ids=["table", "table-of-a-study-value"])
def test_a_spectrum_table_is_an_input_of_predict_report_and_fit(tmp_path, capsys, study):
    case = _table_case(tmp_path, study)
    target = tmp_path / ("psd2.csv" if study else "psd.csv")
    assert {p.name for p in read_case_file(case).files} == ({"psd.csv", "psd2.csv"} if study else {"psd.csv"})
    before = target.read_bytes()
    for argv in (["predict", str(case), "--json", str(target)],
                 ["report", str(case), "-o", str(target)]):
        assert main([*argv, "--force", "-q"]) == 2, argv
        _refused(capsys, target, before)


def test_fit_and_simulate_refuse_to_write_over_the_table(tmp_path, capsys):
    case = _table_case(tmp_path)
    target = tmp_path / "psd.csv"
    before = target.read_bytes()
    data = example_path("reference-experiment").with_name("reference-measured.csv")
    assert main(["fit", str(case), "--data", str(data), "--json", str(target), "--force", "-q"]) == 2
    _refused(capsys, target, before, "--json")
    assert main(["simulate", str(case), "--grid", "16", "--json", str(target), "--force", "-q"]) == 2
    _refused(capsys, target, before, "--json")


def test_surface_synthesize_never_writes_over_the_topography_its_case_names(tmp_path, capsys):
    heights = tmp_path / "map.npy"
    assert main(["surface", "synthesize", "--example", "reference-experiment", "--grid", "32", "--seed", "1",
                 "--size", "2 mm", "-o", str(heights), "-q"]) == 0
    case = tmp_path / "case.toml"
    case.write_text(edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                         'cutoff_wavelength = "20 um"\n', 'model = "topography"\nfile = "map.npy"\n'))
    before = heights.read_bytes()
    assert main(["surface", "synthesize", str(case), "--grid", "32", "--seed", "2", "-o", str(heights), "--force", "-q"]) == 2
    _refused(capsys, heights, before)
