"""The pages under the app's own Content-Security-Policy and headers: they work, and the browser reports no violation."""

from __future__ import annotations

import numpy as np
import pytest

from tests.browser.conftest import watched_page


@pytest.fixture
def strict_page(browser, server):
    """A page that enforces the app's Content-Security-Policy (the ``page`` fixture bypasses it for Playwright's sake)."""
    base, _app = server
    yield from watched_page(browser, base)


def test_the_pages_work_under_their_content_security_policy(strict_page, tmp_path):
    page = strict_page
    answer = page.goto("/case")
    assert "frame-ancestors 'none'" in answer.headers["content-security-policy"]
    page.wait_for_selector("body[data-ready]", state="attached")
    page.select_option("#example", "reference-experiment")
    page.click("#load-example")
    page.wait_for_selector("#status:has-text('the case is valid')")
    page.fill('[name="conditions.squeeze_pressure"]', "0.5 MPa")  # a PUT from the page itself: its Origin is served
    page.wait_for_selector("#status:has-text('the case is valid')")
    page.goto("/prediction")
    page.wait_for_selector("body[data-ready]", state="attached")
    page.wait_for_selector("#plot-leak .main-svg", state="attached")  # Plotly draws (its inline styles are allowed)
    assert page.get_attribute("#leak-rate", "data-si")
    rng = np.random.default_rng(0)
    np.savetxt(tmp_path / "map.txt", rng.standard_normal((32, 32)))
    page.goto("/surface")
    page.wait_for_selector("body[data-ready]", state="attached")
    page.set_input_files("#surface-form input[type=file]", str(tmp_path / "map.txt"))
    page.fill("#opt-size", "0.5 mm")
    page.fill("#opt-height_unit", "um")
    page.click("#analyze")
    page.wait_for_selector("#plot-psd .main-svg", state="attached")
    page.goto("/simulation")
    page.wait_for_selector("body[data-ready]", state="attached")
