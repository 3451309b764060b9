"""The web app's OpenAPI schema: every API path, request bodies that refuse members they do not declare."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
with warnings.catch_warnings():  # starlette's TestClient on httpx 0.28 warns that httpx2 exists
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from sealeak.web import create_app
from sealeak.web.app import UPLOAD_PATHS
from sealeak.web.routes import ROUTERS

#: The API as docs/web.md lists it: (method, path).
API = {
    ("get", "/api/form"), ("get", "/api/case"), ("post", "/api/case/example"), ("post", "/api/case/upload"),
    ("put", "/api/case/fields"), ("put", "/api/case/toml"), ("put", "/api/case/surface"),
    ("post", "/api/uploads"), ("get", "/api/uploads"), ("post", "/api/surface/analyze"), ("post", "/api/predict"),
    ("post", "/api/jobs"), ("get", "/api/jobs"), ("get", "/api/jobs/{job_id}"), ("delete", "/api/jobs/{job_id}"),
    ("post", "/api/jobs/{job_id}/cancel"),
    ("get", "/api/jobs/{job_id}/result.json"), ("get", "/api/jobs/{job_id}/table.txt"),
    ("get", "/api/jobs/{job_id}/figures/{name}"),
    ("get", "/download/case.toml"), ("get", "/download/bundle.zip"), ("get", "/download/results.json"),
    ("get", "/download/results.csv"), ("get", "/download/figures.zip"), ("get", "/download/report.html"),
}
#: The requests with a JSON body, and a member each takes.
JSON_BODIES = {("post", "/api/case/example"): "name", ("put", "/api/case/fields"): "fields",
               ("put", "/api/case/toml"): "toml", ("put", "/api/case/surface"): "files", ("post", "/api/jobs"): "grid"}
#: The uploads (multipart forms, read by the app's own streaming parser) and their file field.
UPLOADS = {"/api/case/upload": "file", "/api/uploads": "files", "/api/surface/analyze": "files"}


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(), base_url="http://127.0.0.1:8765") as c:
        yield c


@pytest.fixture(scope="module")
def schema(client):
    r = client.get("/openapi.json")
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/json")
    return r.json()


def operations(schema: dict) -> set[tuple[str, str]]:
    return {(method, path) for path, ops in schema["paths"].items() for method in ops}


def resolve(schema: dict, node: dict) -> dict:
    """``node`` with its ``$ref`` (and that of a nullable ``anyOf``) followed into the components."""
    refs = [node] + [n for n in node.get("anyOf", []) if "$ref" in n]
    for n in refs:
        if "$ref" in n:
            return schema["components"]["schemas"][n["$ref"].rsplit("/", 1)[-1]]
    return node


def test_the_schema_lists_every_api_path_and_no_page(schema):
    assert operations(schema) == API
    served = {(m.lower(), r.path) for router in ROUTERS for r in router.routes for m in getattr(r, "methods", ())
              if r.path.startswith(("/api/", "/download/")) and m != "HEAD"}
    assert served == API  # nothing the app serves under /api or /download is missing from the schema
    assert schema["info"]["title"] == "sealeak" and schema["info"]["version"]


def test_there_is_no_swagger_page_that_would_load_scripts_from_the_internet(client):
    assert client.get("/docs").status_code == 404 and client.get("/redoc").status_code == 404


@pytest.mark.parametrize("op", sorted(JSON_BODIES))
def test_every_json_body_forbids_other_members(schema, op):
    method, path = op
    body = schema["paths"][path][method]["requestBody"]
    assert list(body["content"]) == ["application/json"]
    model = resolve(schema, body["content"]["application/json"]["schema"])
    assert model["additionalProperties"] is False and JSON_BODIES[op] in model["properties"]
    for member in model["properties"].values():  # a nested object (the surface's options) refuses others too
        inner = resolve(schema, member)
        if inner is not member:
            assert inner["additionalProperties"] is False


def test_only_the_json_requests_have_a_json_body(schema):
    with_json = {(m, p) for p, ops in schema["paths"].items() for m, op in ops.items()
                 if "application/json" in op.get("requestBody", {}).get("content", {})}
    assert with_json == set(JSON_BODIES)


@pytest.mark.parametrize("op", sorted(JSON_BODIES))
def test_a_member_the_schema_does_not_declare_is_refused_naming_it(client, op):
    method, path = op
    r = client.request(method.upper(), path, json={"colour": "red"})
    assert r.status_code == 422
    body = r.json()
    assert body["field"] == "colour" and body["error"].startswith("colour = 'red': is not a member of this request")
    assert f"'{JSON_BODIES[op]}'" in body["error"] and body["message"] == f"sealeak: error: {body['error']}"


@pytest.mark.parametrize("path", sorted(UPLOADS))
def test_the_uploads_are_described_as_multipart_forms(schema, path):
    content = schema["paths"][path]["post"]["requestBody"]["content"]
    form = content["multipart/form-data"]["schema"]
    assert form["required"] == [UPLOADS[path]]
    file = form["properties"][UPLOADS[path]]
    assert "binary" in (file.get("format"), file.get("items", {}).get("format"))


def test_the_multipart_requests_are_those_the_guard_gives_the_upload_limit(schema):
    multipart = {p for p, ops in schema["paths"].items() for op in ops.values()
                 if "multipart/form-data" in op.get("requestBody", {}).get("content", {})}
    assert multipart == set(UPLOADS) == set(UPLOAD_PATHS)


def test_predict_takes_a_case_file(schema):
    assert "application/toml" in schema["paths"]["/api/predict"]["post"]["requestBody"]["content"]
    assert [p["name"] for p in schema["paths"]["/api/predict"]["post"]["parameters"]] == ["name"]


def test_the_web_page_of_the_docs_names_every_request_and_the_schema():
    text = (Path(__file__).parents[2] / "docs" / "web.md").read_text(encoding="utf-8")
    for method, path in sorted(API):
        written = path.replace("{job_id}", "ID").replace("{name}", "NAME.png")
        assert f"{method.upper()} {written}" in text, f"docs/web.md does not name {method.upper()} {written}"
    assert "GET /openapi.json" in text


@pytest.mark.parametrize("body, field, words", [
    ({"files": ["map.txt"], "options": {"colour": "red"}}, "options.colour", "it takes 'size', 'pixel_size'"),
    ({"files": ["map.txt"], "options": {"size": ["1 mm"]}}, "options.size", "must be text, true or false, an integer or a number"),
    ({"files": "map.txt"}, "files", "must be a list"),
])
def test_a_nested_member_is_named_by_its_path(client, body, field, words):
    r = client.put("/api/case/surface", json=body)
    assert r.status_code == 422 and r.json()["field"] == field
    assert r.json()["error"].startswith(f"{field} = ") and words in r.json()["error"]
