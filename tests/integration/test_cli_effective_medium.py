"""Gap distribution P(u) and the Bruggeman effective-medium leak rate (docs/theory.md § 5)."""

import numpy as np
import pytest

from sealeak import PowerSpectrum
from sealeak.cases import example_path, load_cases
from sealeak.physics.contact import PerssonContact, contact_modulus

E_STAR = contact_modulus(2.3e6, 0.5)
Q0 = 2 * np.pi / 5e-3


@pytest.fixture(scope="module")
def contact():
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=2 * np.pi / 20e-6, q_lowest=Q0, h_rms=44e-6)
    return PerssonContact(s, E_STAR, Q0, gamma=1.0)






# mean of P(u) / ū(1) for the bundled cases at the lowest, middle and highest squeeze pressure
# (computed with this code; pinned so a change of the quadrature or of u1 shows up)


def test_predict_both_models_through_the_cli(tmp_path, capsys):
    import json

    from sealeak.cli import main

    text = (example_path("reference-experiment").read_text()
            .replace('{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }', '["30 kPa", "60 kPa", "1 GPa"]')
            .replace("[theory]", '[theory]\nmodel = "both"'))
    cf = tmp_path / "both.toml"
    cf.write_text(text)
    out = tmp_path / "r.json"
    assert main(["predict", str(cf), "--json", str(out)]) == 0
    table = capsys.readouterr().out
    assert "Q_CJ (m³/s)" in table and "Q_EM (m³/s)" in table and "<u>_P (µm)" in table and "ū(1) (µm)" in table
    doc = json.loads(out.read_text())
    assert doc["units"]["leak_rate_effective_medium"] == "m^3/s"
    rows = doc["results"]
    assert all("leak_rate_effective_medium" in r and "leak_rate" in r for r in rows)
    assert rows[2]["leak_rate_effective_medium"] is None and rows[2]["percolates_effective_medium"] is False
    (case,) = load_cases(cf)
    from sealeak.cases import predict_effective_medium

    em = predict_effective_medium(case)
    assert rows[1]["leak_rate_effective_medium"] == pytest.approx(em.leak_rate[1], rel=1e-12, abs=0)
    assert rows[1]["gap_distribution_mean"] >= rows[1]["mean_gap"]
