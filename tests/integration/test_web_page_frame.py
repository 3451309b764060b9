"""The pages are served as one shared frame (head, navigation, script) around each page's own content."""

from __future__ import annotations

import warnings
from html.parser import HTMLParser

import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
with warnings.catch_warnings():  # starlette's TestClient on httpx 0.28 warns that httpx2 exists
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from sealeak.web import create_app
from sealeak.web.routes.pages import PAGES


class _Tags(HTMLParser):
    """The start tags of a document, each with its attributes."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(), base_url="http://127.0.0.1:8765") as c:
        yield c


@pytest.mark.parametrize("name", sorted(PAGES))
def test_each_page_is_one_whole_document_with_the_shared_navigation(client, name):
    r = client.get(f"/{name}")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    text = r.text
    assert text.startswith("<!DOCTYPE html>") and text.rstrip().endswith("</html>")
    parser = _Tags()
    parser.feed(text)
    tags = parser.tags
    for once in ("html", "head", "body", "header", "nav", "main", "h1", "title"):
        assert [t for t, _ in tags].count(once) == 1, (name, once)
    assert [a for t, a in tags if t == "body"] == [{"data-page": name}]
    assert {a["href"] for t, a in tags if t == "a" and a.get("href", "").startswith("/") and "/download" not in a["href"]} \
        >= {f"/{p}" for p in PAGES}
    scripts = [a.get("src") for t, a in tags if t == "script"]
    assert scripts[-1] == "/static/app.js"
    assert ("/static/plotly.min.js" in scripts) == PAGES[name].plotly
    assert f"<title>sealeak — {PAGES[name].title}</title>" in text


def test_the_frame_is_not_served_as_a_static_file(client):
    assert client.get("/static/frame.html").status_code == 404
    assert client.get("/frame").status_code == 404
