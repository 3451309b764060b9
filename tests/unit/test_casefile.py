"""Case files: units, examples, studies, and the catalogue of invalid inputs."""

import re

import numpy as np
import pytest

from sealeak.cases import example_names, example_path, example_text, load_cases, parse_cases
from sealeak.errors import InputError
from tests.casefiles import BASE, edit


def test_base_case_reads_in_si():
    (case,) = parse_cases(BASE)
    assert case.spectrum.h_rms == pytest.approx(44e-6, rel=1e-12, abs=0)
    assert case.spectrum.q_max == pytest.approx(2 * np.pi / 20e-6)
    assert case.e_star == pytest.approx(2.3e6 / 0.75)
    assert case.q0 == pytest.approx(2 * np.pi / 5e-3)
    assert case.spectrum.q_min == pytest.approx(case.q0)  # lowest_wavevector defaults to q0
    assert np.allclose(case.squeeze_pressure, [2e4, 6e4, 1e5])
    assert case.alpha == 0.2 and case.percolation_threshold == 0.6 and case.gamma == 1.0


def test_units_are_interchangeable():
    (a,) = parse_cases(BASE)
    (b,) = parse_cases(edit('h_rms = "44 um"', 'h_rms = "0.044 mm"', edit(
        'rolloff_wavevector = "9.1e3 1/m"', f'rolloff_wavelength = "{2 * np.pi / 9.1e3 * 1e3:.17g} mm"', edit(
            'youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2300 kPa"', edit(
                'viscosity = "1 mPa*s"', 'viscosity = "1 cP"')))))
    assert b.spectrum.h_rms == pytest.approx(a.spectrum.h_rms, rel=1e-12, abs=0)
    assert np.allclose(b.spectrum.q, a.spectrum.q, rtol=1e-12)
    assert b.e_star == pytest.approx(a.e_star) and b.fluid.viscosity == pytest.approx(1e-3)
    (c,) = parse_cases(edit('h_rms = "44 um"', 'h_rms = "44 µm"'))
    assert c.spectrum.h_rms == pytest.approx(44e-6)


def test_pressure_range_and_rectangle():
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]',
                'squeeze_pressure = {start = "10 kPa", stop = "1 MPa", num = 3, spacing = "log"}')
    text = edit('shape = "ring"\ninner_diameter = "3 cm"\nouter_diameter = "4 cm"',
                'shape = "rectangle"\nwidth = "2 mm"\nlength = "5 cm"', text)
    (case,) = parse_cases(text)
    assert np.allclose(case.squeeze_pressure, [1e4, 1e5, 1e6])
    assert case.seal.aspect_ratio == pytest.approx(25.0)


def test_table_spectrum_with_units_in_header(tmp_path):
    q = np.geomspace(1e3, 3e5, 20)
    c = 1e-18 * (q / 1e3) ** -3.6
    (tmp_path / "psd.csv").write_text("q (1/um), C (um^4)\n" + "".join(
        f"{a * 1e-6:.17g}, {b * 1e24:.17g}\n" for a, b in zip(q, c)))
    text = edit('model = "self-affine"\nh_rms = "44 um"\nhurst = 0.8\nrolloff_wavevector = "9.1e3 1/m"\n'
                'cutoff_wavelength = "20 um"', 'model = "table"\nfile = "psd.csv"')
    (tmp_path / "case.toml").write_text(text)
    (case,) = load_cases(tmp_path / "case.toml")
    assert np.allclose(case.spectrum.q, q, rtol=1e-12)
    assert np.allclose(case.spectrum.C, c, rtol=1e-12)


def test_study_expands_into_variants():
    text = BASE + '\n[study]\nvary = "surface.h_rms"\nvalues = ["10 um", "20 um"]\n'
    cases = parse_cases(text)
    assert [c.spectrum.h_rms for c in cases] == pytest.approx([1e-5, 2e-5])
    assert cases[0].label == "h_rms = 10 um"


def test_a_study_names_its_value_only_where_the_value_is_at_fault():
    study = '\n[study]\nvary = "surface.h_rms"\nvalues = ["10 um", "{}", "30 um"]\n'
    with pytest.raises(InputError) as bad_value:
        parse_cases(BASE + study.format("-20 um"))
    assert str(bad_value.value) == "surface.h_rms (study value '-20 um') = '-20 um': must be > 0"
    shared = edit('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "-2.3 MPa"') + study.format("20 um")
    with pytest.raises(InputError) as bad_shared:  # every variant fails alike: the first value is not to blame
        parse_cases(shared)
    assert str(bad_shared.value) == "rubber.youngs_modulus = '-2.3 MPa': must be > 0"


@pytest.mark.parametrize("base, study, field", [
    ('h_rms = "-3 um"', '[study]\nvary = "surface.h_rms"\nvalues = ["10 um", "20 um"]\n', "surface.h_rms"),
    ('viscosity = "-5 banana"', '[study]\nvary = "fluid"\nvalues = [{ viscosity = "1 mPa*s" }, { viscosity = "30 mPa*s" }]\n',
     "fluid.viscosity")])
def test_a_value_every_study_value_replaces_is_checked_all_the_same(base, study, field):
    """A base value that no case uses (every study value replaces it) passed unread: "-5 banana" as the viscosity of
    the [fluid] a whole-section study replaces. It is checked as written; a valid one, or none, builds as before."""
    key = field.split(".")[1]
    text = re.sub(rf'(?m)^{key} = .*$', base, BASE) + "\n" + study
    with pytest.raises(InputError) as exc:
        parse_cases(text)
    assert exc.value.field == field and "every study value replaces it" in str(exc.value)
    assert len(parse_cases(BASE + "\n" + study)) == 2
    assert len(parse_cases(re.sub(rf'(?m)^{key} = .*$', "", BASE) + "\n" + study)) == 2


@pytest.mark.parametrize("name", example_names())
def test_bundled_examples_load_and_print(name):
    assert len(example_names()) >= 3
    cases = load_cases(example_path(name))
    assert cases and all(c.title for c in cases)
    assert parse_cases(example_text(name), example_path(name).parent)[0].spectrum.h_rms == pytest.approx(cases[0].spectrum.h_rms, rel=1e-6, abs=0)


def test_reference_experiment_stand_in():
    (case,) = load_cases(example_path("reference-experiment"))
    assert case.spectrum.h_rms == pytest.approx(44e-6)
    assert case.spectrum.q_max == pytest.approx(2 * np.pi / 20e-6)
    assert case.spectrum.area_ratio == pytest.approx(1.4, abs=0.05)
    assert "stand-in" in case.spectrum_note.lower() or "stand-in" in case.title.lower()
    assert case.seal.aspect_ratio == pytest.approx(np.pi * 7 / 1)



# (case text, files to create, text the error must contain)


def test_case_file_with_byte_order_mark_reads(tmp_path):
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + BASE.encode())
    (case,) = load_cases(p)
    assert case.title == "test case"


def test_hrms_study_has_the_parameters_of_the_study():
    cases = load_cases(example_path("hrms-study"))
    assert [c.spectrum.h_rms for c in cases] == pytest.approx([1e-6, 2e-6, 4e-6, 6e-6], rel=1e-12, abs=0)
    for c in cases:
        assert c.youngs_modulus == 10e6 and c.poisson_ratio == 0.5
        assert c.e_star == pytest.approx(10e6 / 0.75)
        assert c.q0 == pytest.approx(1e4) and c.spectrum.q_min == pytest.approx(1e4)
        assert c.spectrum.q_max == pytest.approx(7.8e9)
        # H = 0.8: C ∝ q^-2(1+H) = q^-3.6 above q_r = q0 (no plateau)
        assert c.spectrum.exponents == pytest.approx([-3.6])
        assert c.pressure_difference == 1e4 and c.fluid.viscosity == pytest.approx(1e-3)
        assert c.seal.aspect_ratio == pytest.approx(1.0)


def test_square_side_defaults_to_the_seal_width_and_can_be_overridden():
    rect = edit('shape = "ring"\ninner_diameter = "3 cm"\nouter_diameter = "4 cm"',
                'shape = "rectangle"\nwidth = "2 mm"\nlength = "5 cm"')
    (c,) = parse_cases(rect)
    assert c.seal.width == pytest.approx(2e-3) and c.seal.aspect_ratio == pytest.approx(25.0)
    assert c.q0 == pytest.approx(2 * np.pi / 2e-3) and c.square_side == pytest.approx(2e-3)
    (d,) = parse_cases(edit("alpha = 0.2", 'alpha = 0.2\nsquare_side = "1 mm"', rect))
    assert d.q0 == pytest.approx(2 * np.pi / 1e-3) and d.square_side == pytest.approx(1e-3)
    (e,) = parse_cases(edit("alpha = 0.2", 'alpha = 0.2\nlowest_wavevector = "5e3 1/m"', rect))
    assert e.q0 == pytest.approx(5e3)
    # λc = L/ζc with the overridden L; the aspect ratio stays the seal's Ly/Lx
    from sealeak.cases import predict

    r = predict(d)
    assert np.allclose(r.critical_wavelength, 1e-3 / r.critical_magnification, rtol=1e-12)


@pytest.mark.parametrize("change, kw, field, both", [
    (dict(gamma=1.5), {}, "theory.gamma", True),
    (dict(percolation_threshold=1.0), {}, "theory.percolation_threshold", False),
    ({}, dict(pressure_difference=-5.0), "conditions.pressure_difference", True),
    ({}, dict(squeeze_pressure=[1e4, -1.0]), "conditions.squeeze_pressure[1]", True),
])
def test_physics_errors_name_the_case_file_key(change, kw, field, both):
    """The physics names its own parameters; running a case re-labels them with the case-file key."""
    from dataclasses import replace

    from sealeak.cases import predict, predict_effective_medium

    case = replace(load_cases(example_path("reference-experiment"))[0], **change)
    for run in (predict, predict_effective_medium) if both else (predict,):
        with pytest.raises(InputError) as err:
            run(case, **kw)
        assert err.value.field == field


def test_seal_errors_name_the_case_file_key(tmp_path):
    text = example_text("reference-experiment").replace('outer_diameter = "4 cm"', 'outer_diameter = "2 cm"')
    with pytest.raises(InputError) as err:
        parse_cases(text, tmp_path)
    assert err.value.field == "seal.outer_diameter"


def test_a_rubber_without_a_modulus_is_told_of_both_ways_to_give_it():
    with pytest.raises(InputError) as exc:
        parse_cases(edit('youngs_modulus = "2.3 MPa"\n', "", BASE))
    assert exc.value.field == "rubber.youngs_modulus" and "rubber.shore_a" in str(exc.value)
    (case,) = parse_cases(edit('youngs_modulus = "2.3 MPa"', "shore_a = 70", BASE))
    assert 3e6 < case.e_star * 0.75 < 1e7  # Gent's relation at 70 Shore A: E of about 5.5 MPa


@pytest.mark.parametrize("edit_from, edit_to, message", [
    ("alpha = 0.2", "alpha = 1e-320", "theory.alpha = 9.99989e-321: must lie in [1e-06, 1e+06]"),
    ("alpha = 0.2", "alpha = 1e308", "theory.alpha = 1e+308: must lie in [1e-06, 1e+06]"),
    ("alpha = 0.2", 'alpha = "1e-7"', "theory.alpha = '1e-7': must lie in [1e-06, 1e+06]"),
    ("alpha = 0.2", "alpha = 0.2\npercolation_threshold = 1e-320", "theory.percolation_threshold = 9.99989e-321: must lie in [0.01, 0.99]"),
    ("alpha = 0.2", "alpha = 0.2\npercolation_threshold = 0.999", "theory.percolation_threshold = 0.999: must lie in [0.01, 0.99]"),
])
def test_alpha_and_the_percolation_threshold_are_refused_far_from_their_physical_range(edit_from, edit_to, message):
    """α = 1e-320 gave every leak rate 0 ("sealed") and valid; p_c = 1e-320 rounded the area 1 − p_c to 1, refused by
    the contact theory without naming the key."""
    with pytest.raises(InputError) as err:
        parse_cases(edit(edit_from, edit_to))
    assert str(err.value) == message
    for ok in ("alpha = 1e-6", "alpha = 1e6"):  # both ends allowed
        assert parse_cases(edit("alpha = 0.2", ok))[0].alpha in (1e-6, 1e6)


@pytest.mark.parametrize("line", ["force_factor = 1.2", 'force_table = "forces.csv"'])
def test_an_o_rings_force_keys_on_a_ring_are_refused_not_ignored(line):
    """``seal.force_factor`` scales an O-ring's line load; a ring seal took it (even ``"x"``) and ignored it."""
    with pytest.raises(InputError) as err:
        parse_cases(edit('shape = "ring"', 'shape = "ring"\n' + line))
    assert err.value.field == "seal." + line.split(" ")[0] and "is for an O-ring" in str(err.value)


@pytest.mark.parametrize("key, text", [("title", 'title = "line1\\u001b[31m red"'), ("title", 'title = "a\\u0000b"'),
                                       ("title", 'title = "two\\nlines"'), ("surface.label", 'label = "x\\u0007"')])
def test_control_characters_in_printed_text_are_refused(key, text):
    """A title reaches the terminal and the report: an escape sequence recoloured the terminal, a NUL byte reached the
    HTML. A description may hold line breaks."""
    doc = edit('title = "test case"', text) if key == "title" else edit('model = "self-affine"', 'model = "self-affine"\n' + text)
    with pytest.raises(InputError) as err:
        parse_cases(doc)
    assert err.value.field == key and "holds the control character U+" in str(err.value)
    (case,) = parse_cases(edit('title = "test case"', 'title = "test case"\ndescription = """first\nsecond\tthird"""'))
    assert case.title == "test case"


@pytest.mark.parametrize("surface, field", [
    ('model = "topography"\nfile = "nosuch.plu"', "surface.file"),
    ('model = "topography"\nfiles = ["nosuch.plu"]', "surface.files[0]"),
    ('model = "table"\nfile = "nosuch.csv"', "surface.file"),
])
def test_a_missing_surface_file_is_named_by_its_key_and_where_it_was_looked_for(tmp_path, surface, field):
    """'nosuch.plu: no such file' named neither the key nor the folder a relative name is read from."""
    text = re.sub(r"(?s)\[surface\].*?(?=\n\[)", "[surface]\n" + surface + "\n", BASE, count=1)
    with pytest.raises(InputError) as exc:
        parse_cases(text, tmp_path)
    assert exc.value.field == field and "no such file" in str(exc.value)
    assert str(tmp_path / "nosuch") in str(exc.value)
