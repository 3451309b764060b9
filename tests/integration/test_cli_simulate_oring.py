"""``sealeak simulate`` on an O-ring case: the cylinder on the rough surface, the flow across its band, α.

Small grids (64-128 cells) through the command line: reproducible with the seed, the physics of
the numbers (Hertz, proportionality to the seal line, ΔP and faces), and bad inputs refused in one
line with exit status 2.
"""

import json
import math

import numpy as np
import pytest

from sealeak.cli import main

ORING = """
title = "O-ring on a rough face"
[surface]
model = "self-affine"
h_rms = "20 um"
hurst = 0.8
rolloff_wavelength = "0.3 mm"
cutoff_wavelength = "5 um"
[rubber]
youngs_modulus = "5 MPa"
poisson_ratio = 0.5
[seal]
shape = "o-ring"
cross_section_diameter = "2.62 mm"
inner_diameter = "20 mm"
[fluid]
viscosity = "1 mPa*s"
[conditions]
compression = ["3 %", "5 %"]
pressure_difference = "1 bar"
"""


def _write(tmp_path, text, name="oring.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _run(tmp_path, text, *options, name="oring.toml", out="res.json"):
    case = _write(tmp_path, text, name)
    js = tmp_path / out
    assert main(["simulate", str(case), "--json", str(js), "-q", *options]) == 0
    return json.loads(js.read_text())


def _rows(doc, key):
    return np.array([np.nan if r[key] is None else r[key] for r in doc["results"]], dtype=float)


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("oring")
    return _run(tmp, ORING, "--grid", "64", "--realizations", "2", "--seed", "3")


def test_reproducible_with_the_seed_and_other_seeds_differ(base, tmp_path):
    again = _run(tmp_path, ORING, "--grid", "64", "--realizations", "2", "--seed", "3")
    assert again["results"] == base["results"]  # bit for bit
    other = _run(tmp_path, ORING, "--grid", "64", "--realizations", "2", "--seed", "4", out="other.json")
    assert not np.array_equal(_rows(other, "leak_rate"), _rows(base, "leak_rate"))
    # the smooth check and the theory do not depend on the random surface
    for key in ("smooth_contact_width", "hertz_contact_width", "leak_rate_series_resistance"):
        assert np.array_equal(_rows(other, key), _rows(base, key), equal_nan=True), key


def test_hertz_numbers_follow_the_force(base):
    """2b = 2√(4fR/(πE*)) and p_max = 2f/(πb) with R = d/2, written out here from the reported f and E*."""
    e_star = base["case"]["contact_modulus"]
    assert e_star == pytest.approx(5e6 / 0.75, rel=1e-12)
    R = 1.31e-3
    for row in base["results"]:
        f = row["force_per_length"]
        b = math.sqrt(4 * f * R / (math.pi * e_star))
        assert row["hertz_contact_width"] == pytest.approx(2 * b, rel=1e-12, abs=0)
        assert row["hertz_max_pressure"] == pytest.approx(2 * f / (math.pi * b), rel=1e-12)
        # the case's own O-ring relation carries the same force over its width (∫p dx = f, semi-ellipse)
        assert math.pi * row["model_contact_width"] * row["model_max_pressure"] / 4 == pytest.approx(f, rel=1e-12)
    # the rough band is wider than the smooth one, and held inside the domain
    widths, size = _rows(base, "contact_width"), base["settings"]["size"]
    assert (widths > _rows(base, "hertz_contact_width")).all() and (widths < size).all()


@pytest.mark.parametrize("compressions", [["10 %", "15 %"], ["2 %"]])
def test_smooth_cylinder_meets_hertz_to_one_percent(compressions, tmp_path, capsys):
    text = ORING.replace('compression = ["3 %", "5 %"]', f"compression = {json.dumps(compressions)}")
    case = _write(tmp_path, text)
    js = tmp_path / "s.json"
    assert main(["simulate", str(case), "--grid", "128", "--realizations", "1", "--json", str(js)]) == 0
    out = capsys.readouterr().out
    doc = json.loads(js.read_text())
    assert doc["smooth_check"]["passed"] is True
    assert (np.abs(_rows(doc, "smooth_width_error")) <= 0.01).all()
    assert (np.abs(_rows(doc, "smooth_pressure_error")) <= 0.01).all()
    assert np.allclose(_rows(doc, "smooth_contact_width") / _rows(doc, "hertz_contact_width") - 1,
                       _rows(doc, "smooth_width_error"), rtol=1e-12, atol=0)
    assert "Smooth check" in out and "agreement within 1 % at every load: yes" in out


def test_leak_rate_scales_with_the_seal_line_the_faces_and_the_pressure_difference(base, tmp_path):
    """Q_num = faces · (Ly/W) · Q_W ΔP-linear, and so is the series-resistance theory: α does not change."""
    q, q_sr, alpha = _rows(base, "leak_rate"), _rows(base, "leak_rate_series_resistance"), _rows(base, "alpha")
    assert (q > 0).all() and q[0] > q[1]  # more squeeze, less leak
    ly = base["settings"]["seal_length"]
    assert ly == pytest.approx(math.pi * 22.62e-3, rel=1e-12, abs=0)  # π × (inner diameter + d)
    variants = {
        "seal line x2": (ORING.replace('inner_diameter = "20 mm"', 'mean_diameter = "45.24 mm"'), 2.0),
        "two faces": (ORING.replace('inner_diameter = "20 mm"', 'inner_diameter = "20 mm"\nfaces = 2'), 2.0),
        "ΔP / 4": (ORING.replace('pressure_difference = "1 bar"', 'pressure_difference = "25 kPa"'), 0.25),
    }
    for k, (name, (text, factor)) in enumerate(variants.items()):
        doc = _run(tmp_path, text, "--grid", "64", "--realizations", "2", "--seed", "3", out=f"v{k}.json")
        assert np.allclose(_rows(doc, "leak_rate"), factor * q, rtol=1e-9, atol=0), name
        assert np.allclose(_rows(doc, "leak_rate_series_resistance"), factor * q_sr, rtol=1e-9, atol=0, equal_nan=True), name
        assert np.allclose(_rows(doc, "alpha"), alpha, rtol=1e-9, atol=0, equal_nan=True), name


def test_alpha_is_the_ratio_of_the_two_leak_rates(tmp_path):
    doc = _run(tmp_path, ORING, "--grid", "64", "--realizations", "1", "--seed", "0")
    q, q_sr, alpha = _rows(doc, "leak_rate"), _rows(doc, "leak_rate_series_resistance"), _rows(doc, "alpha")
    have = np.isfinite(q_sr) & (q > 0)
    assert have.any()
    assert np.allclose(alpha[have], q[have] / q_sr[have], rtol=1e-12, atol=0)
    assert np.isnan(alpha[~have]).all()


def test_table_and_figures(tmp_path, capsys):
    case = _write(tmp_path, ORING)
    plots = tmp_path / "plots"
    assert main(["simulate", str(case), "--grid", "64", "--realizations", "1", "--plots", str(plots)]) == 0
    out = capsys.readouterr().out
    assert "numerically exact leak rate of the O-ring" in out and "Q series α=1" in out
    assert "free edges" in out and "periodic" in out
    assert sorted(p.name for p in plots.iterdir()) == sorted(["simulate_leak_rate.png", "simulate_alpha.png",
                                                               "contact_map.png", "simulate_band_pressure.png"])
    assert all(p.stat().st_size > 10_000 for p in plots.iterdir())


def test_fields_hold_the_band(tmp_path):
    case = _write(tmp_path, ORING)
    folder = tmp_path / "fields"
    assert main(["simulate", str(case), "--grid", "32", "--realizations", "1", "--fields", str(folder), "-q"]) == 0
    assert sorted(p.name for p in folder.iterdir()) == ["r0-p0.npz", "r0-p1.npz"]
    with np.load(folder / "r0-p1.npz") as z:
        p, g, size = z["pressure"], z["gap"], float(z["size"])
        assert p.shape == g.shape == (32, 32) and float(z["period"]) == size
        # contact only in the middle of the domain: the band, free edges on both sides
        cols = np.flatnonzero((p > 0).any(axis=1))
        assert cols.min() > 0 and cols.max() < 31


# ---------------------------------------------------------------- bad inputs: one line, exit 2, nothing written
PROFILE_CSV = "x (mm), pressure (MPa)\n0, 0\n0.5, 1\n1, 0\n"
PROFILE = ORING.replace('shape = "o-ring"\ncross_section_diameter = "2.62 mm"\ninner_diameter = "20 mm"',
                        'pressure_profile = "p.csv"\nlength = "10 cm"').replace(
    'compression = ["3 %", "5 %"]', "profile_scale = [1.0]")


@pytest.mark.parametrize("text, options, names", [
    (PROFILE, [], ["pressure_profile", "O-ring"]),
    (ORING, ["--grid", "15"], ["--grid"]),
    (ORING, ["--grid", "8"], ["--grid"]),
    (ORING, ["--realizations", "0"], ["--realizations"]),
    (ORING, ["--seed", "-1"], ["--seed"]),
    (ORING + "\n[simulation]\ngrid = 7\n", [], ["simulation.grid"]),
    (ORING.replace('cutoff_wavelength = "5 um"', 'cutoff_wavelength = "0.25 mm"'), ["--grid", "16"], ["--grid = 16", "larger grid"]),
    (ORING.replace('compression = ["3 %", "5 %"]', 'compression = ["3 %", "120 %"]'), [], ["compression"]),
])
def test_bad_inputs_one_line_exit_2_nothing_written(text, options, names, tmp_path, capsys):
    (tmp_path / "p.csv").write_text(PROFILE_CSV)
    case = _write(tmp_path, text)
    js = tmp_path / "res.json"
    js.write_text("earlier\n")
    plots = tmp_path / "plots"
    rc = main(["simulate", str(case), "--json", str(js), "--plots", str(plots), "--force", *options])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for name in names:
        assert name in err, (name, err)
    assert js.read_text() == "earlier\n" and not plots.exists()
