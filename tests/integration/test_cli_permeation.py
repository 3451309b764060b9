"""``[rubber] permeability`` and ``diffusivity``: the permeation leak beside the interface leak (docs/case-files.md)."""

from __future__ import annotations

import json
import math

import pytest

from sealeak.cases import example_path
from sealeak.cli import main
from tests.casefiles import BASE

HELIUM = example_path("helium-test").read_text(encoding="utf-8")
RUBBER = "poisson_ratio = 0.5\n"
PERM = RUBBER + 'permeability = "2e-12 m^2/s"\ndiffusivity = "1e-6 cm^2/s"\n'
KEYS = ("leak_rate_permeation_pv", "permeation_breakthrough_time", "leak_rate_total_pv", "leak_rate_total_mbar_l_s")


def _run(tmp_path, capsys, text, *options):
    case = tmp_path / "c.toml"
    case.write_text(text, encoding="utf-8")
    out = tmp_path / "o.json"
    rc = main(["predict", str(case), "--json", str(out), "--force", "-q", *options])
    return rc, out, capsys.readouterr()


def test_permeation_columns_and_total(tmp_path, capsys):
    assert RUBBER in HELIUM
    rc, out, _ = _run(tmp_path, capsys, HELIUM.replace(RUBBER, PERM))
    assert rc == 0
    doc = json.loads(out.read_text())
    assert {doc["units"][k] for k in KEYS} == {"Pa*m^3/s", "s", "mbar*l/s"}
    d, ly, dp = 2.62e-3, math.pi * 22.62e-3, 1e5
    seen_sealed = False
    for r in doc["results"]:
        eps = r["compression"]
        assert r["leak_rate_permeation_pv"] == pytest.approx(2e-12 * dp * ly * 4 / math.pi * (1 - eps) ** 2, rel=1e-10, abs=0)
        path = math.pi * d / (4 * (1 - eps))
        assert r["permeation_breakthrough_time"] == pytest.approx(path**2 / (6 * 1e-10), rel=1e-10)
        interface = r["leak_rate_pv"] or 0.0
        seen_sealed |= r["leak_rate_pv"] is None
        assert r["leak_rate_total_pv"] == pytest.approx(interface + r["leak_rate_permeation_pv"], rel=1e-12, abs=0)
        assert r["leak_rate_total_mbar_l_s"] == pytest.approx(10 * r["leak_rate_total_pv"], rel=1e-12, abs=0)
    assert seen_sealed  # a sealed interface still leaks by permeation: the floor of the test


def test_table_shows_the_columns_and_says_what_they_are(tmp_path, capsys):
    table = tmp_path / "o.txt"
    rc, _, _ = _run(tmp_path, capsys, HELIUM.replace(RUBBER, PERM), "--table", str(table))
    text = table.read_text(encoding="utf-8")
    assert rc == 0 and "Q_perm (Pa·m³/s)" in text and "t_lag (s)" in text and "Q_total (mbar·l/s)" in text
    assert "Q_total = Q_pV + Q_perm" in text and "P = 2e-12 m²/s, pV at 20 °C" in text


def test_units_of_the_permeability_are_converted(tmp_path, capsys):
    _, si, _ = _run(tmp_path, capsys, HELIUM.replace(RUBBER, RUBBER + 'permeability = "2e-12 m^2/s"\n'))
    a = json.loads(si.read_text())["results"]
    _, other, _ = _run(tmp_path, capsys, HELIUM.replace(RUBBER, RUBBER + 'permeability = "2e-8 cm^2/s"\n'))
    b = json.loads(other.read_text())["results"]
    for x, y in zip(a, b, strict=True):
        assert x["leak_rate_permeation_pv"] == pytest.approx(y["leak_rate_permeation_pv"], rel=1e-12, abs=0)
        assert x["permeation_breakthrough_time"] is None  # no diffusivity, no breakthrough time


def test_a_published_permeability_is_counted_at_the_gas_temperature(tmp_path, capsys):
    """3 Barrer = 3 · 3.3464e-16 mol/(m·s·Pa); its pV form P = Π R T follows fluid.temperature, the m²/s form does not."""
    barrer = 1e-10 * (101325 * 1e-6 / (8.314462618 * 273.15)) * 0.01 / (1e-4 * 1333.224)  # mol/(m·s·Pa), by hand
    warm = HELIUM.replace('temperature = "20 degC"', 'temperature = "60 degC"')
    assert warm != HELIUM
    perm = {}
    for name, text in (("cold", HELIUM), ("warm", warm)):
        for form in ("3 barrer", f"{3 * barrer * 8.314462618 * 293.15} m^2/s"):
            rc, out, _ = _run(tmp_path, capsys, text.replace(RUBBER, RUBBER + f'permeability = "{form}"\n'))
            assert rc == 0
            perm[name, form.split()[1]] = [r["leak_rate_permeation_pv"] for r in json.loads(out.read_text())["results"]]
    for a, b in zip(perm["cold", "barrer"], perm["cold", "m^2/s"], strict=True):
        assert a == pytest.approx(b, rel=1e-6, abs=0)  # at 20 °C the two are the same permeability
    for cold, warm_, fixed_cold, fixed_warm in zip(perm["cold", "barrer"], perm["warm", "barrer"], perm["cold", "m^2/s"],
                                                   perm["warm", "m^2/s"], strict=True):
        assert warm_ / cold == pytest.approx(333.15 / 293.15, rel=1e-9)
        assert fixed_warm == pytest.approx(fixed_cold, rel=1e-12, abs=0)


def test_no_permeability_no_columns(tmp_path, capsys):
    rc, out, _ = _run(tmp_path, capsys, HELIUM)
    assert rc == 0
    doc = json.loads(out.read_text())
    assert not any(k in doc["units"] for k in KEYS) and not any(k in doc["results"][0] for k in KEYS)


@pytest.mark.parametrize("edit, field, words", [
    ((RUBBER, RUBBER + 'diffusivity = "1e-10 m^2/s"\n'), "rubber.diffusivity", "permeability"),
    ((RUBBER, RUBBER + 'permeability = "-1e-12 m^2/s"\n'), "rubber.permeability", "> 0"),
    ((RUBBER, RUBBER + 'permeability = "1e-12 Pa"\n'), "rubber.permeability", "area per time"),
    ((RUBBER, RUBBER + "permeability = 1e-12\n"), "rubber.permeability", ""),
    ((RUBBER, RUBBER + 'permeability = "-3 barrer"\n'), "rubber.permeability", "> 0"),
    ((RUBBER, RUBBER + 'permeability = "3 barrers"\n'), "rubber.permeability", "Barrer"),
])
def test_bad_permeation_input_is_one_line(tmp_path, capsys, edit, field, words):
    rc, out, cap = _run(tmp_path, capsys, HELIUM.replace(*edit))
    assert rc == 2 and cap.err.count("\n") == 1 and field in cap.err and words in cap.err, cap.err
    assert not out.exists()


#: The test ring (tests.casefiles.BASE) with helium at 1 bar against vacuum and a permeability.
RING = BASE.replace('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "helium"').replace(
    'pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"').replace(
    "poisson_ratio = 0.5\n", PERM, 1)


def test_refused_for_a_liquid_and_for_a_ring_without_height(tmp_path, capsys):
    oring = example_path("o-ring").read_text(encoding="utf-8")
    rc, out, cap = _run(tmp_path, capsys, oring.replace(RUBBER, PERM))
    assert rc == 2 and "rubber.permeability" in cap.err and "gas" in cap.err and not out.exists()
    rc, out, cap = _run(tmp_path, capsys, RING)
    assert rc == 2 and cap.err.count("\n") == 1 and not out.exists(), cap.err
    assert "rubber.permeability" in cap.err and "seal.height" in cap.err, cap.err


def test_refused_for_a_pressure_profile(tmp_path, capsys):
    lip = example_path("lip-profile").read_text(encoding="utf-8")
    lip = lip.replace('name = "oil"\nviscosity = "30 mPa*s"', 'name = "helium"').replace(
        'pressure_difference = "20 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"').replace(
        'poisson_ratio = 0.5\n', PERM, 1)
    (tmp_path / "lip-profile.csv").write_text(example_path("lip-profile").with_suffix(".csv").read_text(encoding="utf-8"),
                                              encoding="utf-8")
    rc, out, cap = _run(tmp_path, capsys, lip)
    assert rc == 2 and cap.err.count("\n") == 1 and not out.exists(), cap.err
    assert "rubber.permeability" in cap.err and "pressure profile" in cap.err, cap.err


def test_a_ring_with_its_height_permeates_through_the_slab(tmp_path, capsys):
    """Fick's law through the slab of the seal's height H across its width w (docs/theory.md §11.11): Q = P ΔP Ly H/w,
    the time lag w²/(6D), the same at every squeeze pressure; doubling H doubles Q."""
    rows = {}
    for height in ("2 mm", "4 mm"):
        rc, out, cap = _run(tmp_path, capsys, RING.replace('outer_diameter = "4 cm"\n',
                                                           f'outer_diameter = "4 cm"\nheight = "{height}"\n'))
        assert rc == 0, cap.err
        rows[height] = json.loads(out.read_text(encoding="utf-8"))["results"]
    w, ly = 5e-3, math.pi * 35e-3  # the ring 30/40 mm: width (Do − Di)/2, seal line π (Do + Di)/2
    for row in rows["2 mm"]:
        assert row["leak_rate_permeation_pv"] == pytest.approx(2e-12 * 1e5 * ly * 2e-3 / w, rel=1e-12, abs=0)
        assert row["permeation_breakthrough_time"] == pytest.approx(w**2 / (6 * 1e-10), rel=1e-12)
        total = row["leak_rate_pv"] + row["leak_rate_permeation_pv"] if row["leak_rate_pv"] else row["leak_rate_permeation_pv"]
        assert row["leak_rate_total_pv"] == pytest.approx(total, rel=1e-12)
    for thin, thick in zip(rows["2 mm"], rows["4 mm"], strict=True):
        assert thick["leak_rate_permeation_pv"] == pytest.approx(2 * thin["leak_rate_permeation_pv"], rel=1e-12, abs=0)


def test_the_pass_or_fail_of_a_gas_case_with_permeation_compares_the_total(tmp_path, capsys):
    """max_leak_rate against a helium test: the leak test measures the interface leak plus permeation (the table's
    Q_total), but the probability of exceeding compared the interface leak alone: a row sealed at its interface, its
    permeation 2 times the limit, 'passed'. With h_rms uncertain the rows carry Q_total's percentiles too."""
    limit = 5e-8  # mbar·l/s, below every row's permeation (closed form in test_permeation_columns_and_total)
    text = HELIUM.replace(RUBBER, PERM).replace("[conditions]", f'[conditions]\nmax_leak_rate = "{limit} mbar*l/s"')
    rc, out, _ = _run(tmp_path, capsys, text)
    assert rc == 0
    rows = json.loads(out.read_text())["results"]
    assert any(r["leak_rate_pv"] is None for r in rows)  # a row sealed at the interface, leaking by permeation
    for r in rows:
        assert r["leak_rate_total_mbar_l_s"] > limit
        assert r["exceed_probability"] == 1.0
    spread = text.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 5 %"')
    assert spread != text
    rc, out, _ = _run(tmp_path, capsys, spread, "--samples", "16")
    rows = json.loads(out.read_text())["results"]
    for r in rows:
        assert r["leak_rate_total_mbar_l_s_p05"] <= r["leak_rate_total_mbar_l_s_p50"] <= r["leak_rate_total_mbar_l_s_p95"]
        assert r["leak_rate_total_mbar_l_s_p05"] >= r["leak_rate_permeation_pv"] * 10 * (1 - 1e-12)  # never below it
        assert r["exceed_probability"] == 1.0
