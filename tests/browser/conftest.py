"""A real browser against a real server: headless Chromium (the system's) driven by Playwright.

The server runs in a thread on a free loopback port for the whole session. Without Chromium or
Playwright these tests skip, unless ``SEALEAK_REQUIRE_BROWSER=1`` (``make test`` sets it), when
they fail. Screenshots of every page go to ``build/test-artifacts/``.
"""

from __future__ import annotations

import os
import shutil
import socket
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ARTIFACTS = ROOT / "build" / "test-artifacts"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _missing(reason: str):
    if os.environ.get("SEALEAK_REQUIRE_BROWSER") == "1":
        pytest.fail(f"{reason} (SEALEAK_REQUIRE_BROWSER=1: the browser tests must run)", pytrace=False)
    pytest.skip(reason)


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="session")
def server():
    """The web app served by uvicorn on 127.0.0.1 (a free port) in a thread: (base URL, app)."""
    try:
        import uvicorn

        from sealeak.web import WebConfig, create_app
    except ImportError as exc:
        _missing(f"the web extra is not installed ({exc.name})")
    app = create_app(WebConfig(max_running=2))  # the simulation test runs two jobs at once (a 2-core machine allows one)
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    srv = uvicorn.Server(uvicorn.Config(app, log_level="warning", access_log=False))
    thread = threading.Thread(target=srv.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    for _ in range(200):
        if srv.started:
            break
        time.sleep(0.05)
    assert srv.started, "the server did not start"
    yield f"http://127.0.0.1:{port}", app
    srv.should_exit = True
    thread.join(timeout=10)
    sock.close()


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium of the system (never a downloaded one)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _missing("Playwright for Python is not installed (the test extra)")
    path = _chromium()
    if path is None:
        _missing("no Chromium on this machine (make browser installs Debian's)")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=path, args=CHROMIUM_ARGS)
        yield b
        b.close()


def watched_page(browser, base, **context_options):
    """A page in a fresh browser context (a new session) at ``base``; yields it, then fails the test on any console
    error or warning or page error it reported."""
    context = browser.new_context(base_url=base, viewport={"width": 1400, "height": 1000}, **context_options)
    pg = context.new_page()
    problems: list[str] = []
    pg.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type in ("error", "warning") else None)
    pg.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    pg.set_default_timeout(30_000)
    yield pg
    context.close()
    assert not problems, "the browser reported:\n" + "\n".join(problems)


@pytest.fixture
def page(browser, server):
    """A fresh browser context (a new session) and page; the test fails on any console error or page error.

    Playwright evaluates the predicates of wait_for_function with eval, which the app's Content-Security-Policy
    forbids, so this page bypasses the policy; test_web_security_pages.py opens the pages under it."""
    base, _app = server
    yield from watched_page(browser, base, accept_downloads=True, bypass_csp=True)


@pytest.fixture(scope="session")
def artifacts() -> Path:
    """The folder of the screenshots (git-ignored)."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    return ARTIFACTS
