"""Case files: units, examples, studies, and the catalogue of invalid inputs."""

import pytest

from sealeak.cli import main
from tests.casefiles import BASE, edit

PSD_OK = "q (1/m), C (m^4)\n1e3, 1e-18\n1e4, 1e-21\n1e5, 1e-24\n"
TABLE_CASE = edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                  'cutoff_wavelength = "20 um"', 'model = "table"\nfile = "psd.csv"')

# (case text, files to create, text the error must contain)
INVALID = [
    ("missing section", BASE.replace("[fluid]\nviscosity = \"1 mPa*s\"\n", ""), {}, "fluid"),
    ("missing field", edit('youngs_modulus = "2.3 MPa"\n', ""), {}, "rubber.youngs_modulus"),
    ("negative modulus", edit('"2.3 MPa"', '"-2.3 MPa"'), {}, "rubber.youngs_modulus = '-2.3 MPa'"),
    ("poisson above 0.5", edit("poisson_ratio = 0.5", "poisson_ratio = 0.51"), {}, "rubber.poisson_ratio = 0.51"),
    ("unknown unit", edit('"44 um"', '"44 furlongs_per_fortnight"'), {}, "surface.h_rms"),
    ("length for a pressure", edit('pressure_difference = "10 kPa"', 'pressure_difference = "10 mm"'), {},
     "conditions.pressure_difference = '10 mm'"),
    ("bare number for a length", edit('h_rms = "44 um"', "h_rms = 44"), {}, "surface.h_rms = 44"),
    ("p_c outside (0,1)", edit("alpha = 0.2", "alpha = 0.2\npercolation_threshold = 1.2"), {},
     "theory.percolation_threshold = 1.2"),
    ("p_c zero", edit("alpha = 0.2", "alpha = 0.2\npercolation_threshold = 0"), {}, "theory.percolation_threshold"),
    ("empty squeeze list", edit('["20 kPa", "60 kPa", "0.1 MPa"]', "[]"), {}, "conditions.squeeze_pressure"),
    ("negative squeeze", edit('"60 kPa"', '"-60 kPa"'), {}, "conditions.squeeze_pressure[1]"),
    ("malformed toml", BASE + "\n[rubber\n", {}, "malformed TOML"),
    ("hurst out of range", edit("hurst = 0.8", "hurst = 1.5"), {}, "surface.hurst = 1.5"),
    ("cutoff below rolloff", edit('cutoff_wavelength = "20 um"', 'cutoff_wavelength = "2 mm"'), {},
     "surface.cutoff_wavelength = '2 mm'"),
    ("unknown key", edit("alpha = 0.2", "alpha = 0.2\nalfa = 0.3"), {}, "theory.alfa"),
    ("unknown model", edit('model = "self-affine"', 'model = "fractal"'), {}, "surface.model = 'fractal'"),
    ("both h_rms and C0", edit('h_rms = "44 um"', 'h_rms = "44 um"\nC0 = "1e-18 m^4"'), {}, "surface.h_rms"),
    ("ring inverted", edit('outer_diameter = "4 cm"', 'outer_diameter = "2 cm"'), {}, "seal.outer_diameter"),
    ("gamma zero", edit("alpha = 0.2", "alpha = 0.2\ngamma = 0"), {}, "theory.gamma = 0"),
    ("alpha negative", edit("alpha = 0.2", "alpha = -0.2"), {}, "theory.alpha = -0.2"),
    ("text for a number", edit("hurst = 0.8", 'hurst = "high"'), {}, "surface.hurst = 'high'"),
    ("table missing file", edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                                'cutoff_wavelength = "20 um"', 'model = "table"\nfile = "none.csv"'), {},
     "surface.file = 'none.csv': no such file (looked for "),
    ("table with NaN", None, {"psd.csv": "q (1/m), C (m^4)\n1e3, 1e-18\n1e4, nan\n1e5, 1e-24\n"}, "C is nan"),
    ("table unsorted", None, {"psd.csv": "q (1/m), C (m^4)\n1e3, 1e-18\n1e5, 1e-21\n1e4, 1e-24\n"},
     "q must be strictly increasing"),
    ("table text cell", None, {"psd.csv": "q (1/m), C (m^4)\n1e3, 1e-18\n1e4, abc\n"}, "'abc' is not a number"),
    ("table wrong unit", None, {"psd.csv": "q (m), C (m^4)\n1e3, 1e-18\n1e4, 1e-21\n"}, "not a wavevector"),
    ("table empty", None, {"psd.csv": ""}, "no numeric rows"),
    ("empty case file", "", {}, "is empty"),
    ("self-affine key with a table", TABLE_CASE.replace('file = "psd.csv"', 'file = "psd.csv"\nh_rms = "1 mm"'),
     {"psd.csv": PSD_OK}, "surface.h_rms = '1 mm': not used by model = 'table'"),
    ("table key with self-affine", edit('model = "self-affine"', 'model = "self-affine"\nfile = "psd.csv"'), {},
     "surface.file = 'psd.csv': not used by model = 'self-affine'"),
    ("missing field says so", edit("hurst = 0.8\n", ""), {}, "surface.hurst is required"),
    ("output folder in the way", BASE, {"out.json/keep": "x"}, "out.json is a folder"),
    # found by fuzzing the examples: each was a traceback
    ("model a table", edit('model = "self-affine"', "model = {}"), {}, "surface.model = {}: allowed: 'self-affine'"),
    ("model a list", edit('model = "self-affine"', 'model = ["table"]'), {}, "surface.model = ['table']: allowed"),
    ("squeeze below any seal's", edit('"60 kPa"', '"1e-9 Pa"'), {},
     "conditions.squeeze_pressure[1] = '1e-9 Pa': must be at least 1 mPa"),
    ("squeeze near the smallest double", edit('"60 kPa"', '"1e-320 MPa"'), {},
     "conditions.squeeze_pressure[1] = '1e-320 MPa': too small: between 0 and 1e-100 Pa"),
    ("modulus beyond any solid", edit('"2.3 MPa"', '"1e20 Pa"'), {}, "rubber.youngs_modulus = 1e+20: must be at most 1e+13 Pa"),
    ("a length near the smallest double", edit('h_rms = "44 um"', 'h_rms = "1e-320 mm"'), {},
     "surface.h_rms = '1e-320 mm': too small: between 0 and 1e-100 m in SI units"),
    ("a length near the largest double", edit('h_rms = "44 um"', 'h_rms = "1e308 mm"'), {},
     "surface.h_rms = '1e308 mm': too large: beyond 1e+100 m in SI units"),
    ("a temperature beyond any rubber's", edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\ntemperature = "1e308 K"'), {},
     "fluid.temperature = '1e308 K': is above 10000 K"),
    ("a life case without [conditions]", BASE.split("[conditions]")[0] + "\n[rubber.compression_set]\n"
     'times = ["1 h", "10 h", "100 h"]\ntemperatures = ["20 degC", "70 degC", "100 degC"]\nsets = ["5 %", "10 %", "20 %"]\n',
     {}, "conditions: section [conditions] is missing"),
]



@pytest.mark.parametrize("name, text, files, expected", INVALID, ids=[i[0] for i in INVALID])
def test_invalid_case_files_give_clear_errors(tmp_path, capsys, name, text, files, expected):
    assert len(INVALID) >= 15
    for fname, content in files.items():
        (tmp_path / fname).parent.mkdir(exist_ok=True)
        (tmp_path / fname).write_text(content)
    case = tmp_path / "case.toml"
    case.write_text(TABLE_CASE if text is None else text)
    out_json = tmp_path / "out.json"
    code = main(["predict", str(case), "--json", str(out_json)])
    err = capsys.readouterr().err
    assert code == 2
    assert expected in err, err
    assert err.startswith("sealeak: error:")
    assert "Traceback" not in err
    assert not out_json.is_file()
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".part")] == []


def test_valid_table_case_runs(tmp_path):
    (tmp_path / "psd.csv").write_text(PSD_OK)
    (tmp_path / "case.toml").write_text(TABLE_CASE)
    assert main(["predict", str(tmp_path / "case.toml"), "-q"]) == 0
