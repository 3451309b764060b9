"""Validity verdicts and input warnings (docs/theory.md §9.11), at the physics and case level."""

import numpy as np
import pytest
from scipy.optimize import brentq

from sealeak.cases import parse_cases, run_case
from sealeak.errors import InputError
from sealeak.physics.contact import PerssonContact
from sealeak.physics.critical_junction import critical_junction
from sealeak.physics.fluid import Fluid
from sealeak.physics.spectrum import PowerSpectrum
from sealeak.physics.validity import (
    DEFAULT_MOLECULAR_SIZE,
    assumption_warnings,
    continuum_verdict,
    molecular_size,
    pressures_text,
)
from sealeak.render.text import prediction_table
from tests.casefiles import BASE, ORING, edit

# ---------------------------------------------------------------------- verdicts


def test_gap_below_one_molecule_is_outside_and_above_is_inside():
    d = 0.3e-9
    gaps = np.array([d * (1 - 1e-12), d, d * 1.5, np.nan, 1e-30])
    valid, why = continuum_verdict(gaps, d)
    assert valid.tolist() == [False, True, True, True, False]
    assert "molecular size" in why[0] and why[1] == "" and why[3] == ""  # NaN: no channel, nothing to judge


def test_gap_wider_than_the_channel_is_not_a_thin_film():
    valid, why = continuum_verdict([1e-6, 3e-6], 1e-10, width=[2e-6, 2e-6])
    assert valid.tolist() == [True, False]
    assert "not small against" in why[1]


def test_verdict_keeps_the_shape_and_order_of_the_sweep():
    g = np.geomspace(1e-12, 1e-6, 50)
    valid, why = continuum_verdict(g, 2e-10)
    assert valid.shape == g.shape and len(why) == g.size
    assert np.array_equal(valid, g >= 2e-10)


@pytest.mark.parametrize(("name", "known"), [("water", True), ("Water", True), ("mineral_oil", True),
                                             ("Silicone-Oil", True), ("unobtainium", False), ("", False)])
def test_molecular_size_by_fluid_name(name, known):
    d, found = molecular_size(name)
    assert found is known
    assert 0.2e-9 < d < 1e-9  # of the order of a few ångström, as every simple liquid or gas
    if not known:
        assert d == DEFAULT_MOLECULAR_SIZE


def test_fluid_molecular_size_given_overrides_the_table():
    assert Fluid(1e-3, name="water").molecular_length == molecular_size("water")[0]
    assert Fluid(1e-3, name="water", molecular_size=1e-9).molecular_length == 1e-9
    with pytest.raises(InputError, match="molecular_size"):
        Fluid(1e-3, molecular_size=-1e-9)
    with pytest.raises(InputError, match="molecular_size"):
        Fluid(1e-3, molecular_size=1.0)  # a metre is no molecule


def test_pressures_text_names_a_single_pressure_or_the_span():
    p = np.array([1e5, 2e5, 3e5])
    assert pressures_text(p, [False, True, False]) == "P0 = 200 kPa"
    assert pressures_text(p, [False, True, True]).startswith("P0 = 200 kPa … 300 kPa (2 of 3")
    assert "all pressures" in pressures_text(p, [True, True, True])


# ---------------------------------------------------------------------- warnings

_FINE = dict(slope_rms=0.3, h_rms=1e-6, seal_width=5e-3, cutoff_wavevector=1e7, squeeze_pressure=[1e5],
             youngs_modulus=1e7, contact_area_at_cutoff=[0.1])


def test_ordinary_inputs_give_no_warning():
    assert assumption_warnings(**_FINE) == []


@pytest.mark.parametrize(("change", "words"), [
    ({"slope_rms": 1.5}, "slope"),
    ({"h_rms": 1e3}, "larger than the seal width"),
    ({"cutoff_wavevector": 2 * np.pi / 1e-15}, "below atomic size"),
    ({"squeeze_pressure": [1e5, 8e6]}, "linear elasticity"),
    ({"contact_area_at_cutoff": [1.0]}, "full contact"),
    ({"alpha": 1e308}, "shape factor"),
])
def test_each_assumption_broken_gives_one_warning_naming_it(change, words):
    out = assumption_warnings(**(_FINE | change))
    assert len(out) == 1 and words in out[0]


# ---------------------------------------------------------------------- on a case


def _run(text):
    return run_case(parse_cases(text, ".", "t.toml")[0])


def test_high_pressure_sweep_judges_rows_by_their_own_critical_gap():
    """Q ∝ u_c³ falls by tens of decades as P0 rises; the rows below one molecule are flagged, the rest not."""
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                'squeeze_pressure = { start = "0.1 MPa", stop = "1 MPa", num = 30, spacing = "log" }',
                edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "10 MPa"',
                     edit('cutoff_wavelength = "20 um"', 'cutoff_wavelength = "1 nm"',
                          edit('h_rms = "44 um"', 'h_rms = "1 um"'))))
    r = _run(text)
    res = r.critical_junction
    d = r.case.fluid.molecular_length
    ok = res.percolates
    assert (~r.valid).any() and r.valid[ok].any()  # both kinds occur in this sweep
    assert np.array_equal(r.valid[ok], res.critical_gap[ok] >= d)
    assert all(r.valid[~ok])  # no channel: nothing to judge
    recs = r.records()
    assert all((rec["validity"] == "") == rec["valid"] for rec in recs)
    # a smaller molecule moves the limit: fewer rows flagged, never more
    small = _run(edit('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\nmolecular_size = "0.01 nm"', text))
    assert (~small.valid).sum() < (~r.valid).sum()
    assert np.all(small.valid | ~r.valid)


def test_reference_case_is_inside_the_theory_with_the_slope_warning_only():
    r = _run(BASE)
    assert r.valid.all()
    assert len(r.warnings) == 1 and "slope" in r.warnings[0]  # the stand-in's slope_rms is 1.08
    assert r.case.spectrum.slope_rms > 1


def test_effective_medium_is_judged_by_its_own_gap():
    r = _run(edit("alpha = 0.2", 'alpha = 0.2\nmodel = "both"\n') + "\n")
    assert r.valid_effective_medium is not None and r.validity_effective_medium is not None
    assert r.valid_effective_medium.all()
    rec = r.records()[0]
    assert rec["valid_effective_medium"] is True and rec["validity_effective_medium"] == ""


def test_junction_at_the_end_of_the_band_gives_zero_gap_flagged_not_an_error():
    """Just below the pressure at which A(ζ1)/A0 = 1 - p_c, ζc → ζ1 and u_c = u1(ζc) → u1(ζ1) = 0 (ū(ζ1) = 0)."""
    c = PerssonContact(PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e4, q_cutoff=1e7, h_rms=1e-6), 1e7, 1e4)
    p_end = brentq(lambda p: c.area(c.zeta_max, np.array([p]))[0] - 0.4, 1e3, 1e8, xtol=1e-14, rtol=1e-15)
    p0 = p_end * np.array([0.5, 0.99, 1 - 1e-6, 1 - 1e-12])
    r = critical_junction(c, squeeze_pressure=p0, pressure_difference=1e4, viscosity=1e-3, aspect_ratio=1.0)
    assert r.percolates.all()
    assert np.all(np.diff(r.critical_gap) <= 0) and r.critical_gap[-1] >= 0  # u_c falls to zero at the end
    assert r.critical_gap[0] > 1e-9
    valid, _ = continuum_verdict(r.critical_gap, 0.3e-9)
    assert valid[0] and not valid[-1]


@pytest.mark.parametrize("h_rms", [1e150, 1e-300, 2e3])
def test_h_rms_beyond_any_real_surface_is_refused_naming_it(h_rms):
    with pytest.raises(InputError, match=r"^h_rms = .*must lie in"):
        PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e4, q_cutoff=1e7, h_rms=h_rms)


@pytest.mark.parametrize("coupling, dp, lifted", [
    ("", "50 bar", [True, True, True]),  # ΔP above every peak (0.63, 0.96, 2.24 MPa)
    ("", "10 bar", [True, True, False]),  # above the first two peaks only
    ('fluid_pressure = "ignored"', "15 bar", [True, True, True]),  # ΔP > p_max/2 at every load
])
def test_a_band_the_fluid_pressure_opens_is_not_valid_whether_or_not_it_has_a_leak_channel(coupling, dp, lifted):
    """An O-ring at ΔP = 50 bar against a 2.2 MPa peak, its contact sealed there (no leak channel at the peak without
    the fluid's pressure), was reported sealed and valid: the fluid pressure that opens the seal was not said. Every
    row whose ΔP reaches the peak (coupled), or is not small against it (ignored), is now not valid, with the reason
    first; a sealed row's reason says that the theory's 'sealed' does not hold, and an O-ring's that the model leaves
    out pressure energisation."""
    text = ORING.replace('pressure_difference = "1 bar"', f'pressure_difference = "{dp}"') + f"\n[theory]\n{coupling}\n"
    r = run_case(parse_cases(text)[0])
    percolates = r.band.critical_junction.percolates
    assert percolates.tolist() == [True, True, False]  # the 30 % row seals at its peak
    assert (~r.valid).tolist() == lifted
    for i, reason in enumerate(r.validity):
        if not lifted[i]:
            assert reason == ""
            continue
        assert reason.startswith("ΔP = ")
        assert ("does not hold" in reason) == (not percolates[i])
        assert ("pressure energisation" in reason) == (coupling == "")
    table = prediction_table([r])
    assert ("compression 30 %: valid = NO" in table) == lifted[2]
