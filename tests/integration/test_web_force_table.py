"""The web app reads a case's ``seal.force_table`` only from the files uploaded in its session (docs/web.md)."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")

from tests.integration.test_cli_band import ORING  # noqa: E402
from tests.integration.test_web_api import create_app, web_client  # noqa: E402

LINE = 'inner_diameter = "20 mm"'


@pytest.mark.parametrize("value", ["/etc/passwd", "../f.csv", "sub/f.csv", "f.csv"])
def test_a_force_table_must_be_uploaded_in_the_session(value):
    with web_client(create_app()) as c:
        r = c.post("/api/predict", content=ORING.replace(LINE, LINE + f'\nforce_table = "{value}"').encode())
    assert r.status_code == 422
    body = r.json()
    assert body["field"] == "seal.force_table" and "uploaded in this session" in body["error"]
    assert "root:" not in r.text  # nothing of the file was read


@pytest.mark.parametrize("rubber", ['relaxation = {{ master_curve = "{value}" }}',
                                    'youngs_modulus = "5.5 MPa"\n[study]\nvary = "rubber.relaxation"\n'
                                    'values = [{{ master_curve = "{value}" }}]'])
@pytest.mark.parametrize("value", ["/etc/passwd", "../m.csv"])
def test_a_master_curve_must_be_uploaded_in_the_session(rubber, value):
    text = ORING.replace('youngs_modulus = "5.5 MPa"', rubber.format(value=value))
    assert text != ORING
    with web_client(create_app()) as c:
        r = c.post("/api/predict", content=text.encode())
    assert r.status_code == 422
    body = r.json()
    assert "master_curve" in body["error"] and "uploaded in this session" in body["error"]
    assert "root:" not in r.text
