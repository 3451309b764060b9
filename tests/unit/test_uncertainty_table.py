"""The uncertainty table ``sealeak predict`` prints: its columns line up also where a cell is wider than its header."""

from sealeak.cases.uncertainty import parse_uncertain_case, propagate
from sealeak.render import prediction_table
from tests.casefiles import BASE

#: BASE with a spread on h_rms, two squeeze pressures and a study whose variant names are wider than "variant".
STUDY = BASE.replace('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"').replace(
    'squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "60 kPa"]') + """
[study]
vary = "fluid.viscosity"
values = ["1 mPa*s", "2 mPa*s"]
"""


def test_every_row_of_the_uncertainty_table_is_as_wide_as_its_header():
    result = propagate(parse_uncertain_case(STUDY), 2, seed=0)
    lines = prediction_table(result.nominal, result).splitlines()
    head = next(i for i, line in enumerate(lines) if "variant" in line and "p50" in line)
    rows = lines[head + 1:head + 5]
    assert all(r.startswith("viscosity = ") for r in rows)
    assert {len(r) for r in rows} == {len(lines[head])}
    # right-aligned: the load column ends under its header
    assert lines[head].index("P0 (kPa)") + len("P0 (kPa)") == rows[0].index(" 20 ") + len(" 20")
