"""The pages (static HTML with ``static/app.js``) and their static files, Plotly.js from the ``plotly`` package."""

from __future__ import annotations

import re
from collections.abc import Callable
from importlib import resources
from pathlib import Path

import plotly
from fastapi import APIRouter
from fastapi.responses import FileResponse, RedirectResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

__all__ = ["router", "PAGES"]

_STATIC = resources.files("sealeak") / "web" / "static"
#: The pages: the path ``/NAME`` → its file in ``static/``.
PAGES = {"case": "case.html", "surface": "surface.html", "prediction": "prediction.html", "simulation": "simulation.html",
         "help": "help.html"}

router = APIRouter(include_in_schema=False)


@router.get("/")
def index() -> RedirectResponse:
    """The case page."""
    return RedirectResponse("/case")


def _page(filename: str) -> Callable[[], Response]:
    """The route of one page: it takes no parameter (a query parameter naming the file would read any file)."""
    def page() -> Response:
        return Response((_STATIC / filename).read_bytes(), media_type="text/html; charset=utf-8")
    return page


for _name, _file in PAGES.items():
    router.add_api_route(f"/{_name}", _page(_file), methods=["GET"], name=f"page_{_name}")


@router.get("/static/{name}")
def static(name: str) -> Response:
    """A script or style sheet of the pages (``[a-z]+.js``, ``[a-z]+.css``), or Plotly.js."""
    if name == "plotly.min.js":
        return FileResponse(Path(plotly.__file__).parent / "package_data" / "plotly.min.js", media_type="text/javascript")
    if not re.fullmatch(r"[a-z]+\.(js|css)", name) or not (_STATIC / name).is_file():
        raise StarletteHTTPException(404, f"{name}: no such file")
    kind = "text/javascript" if name.endswith(".js") else "text/css"
    return Response((_STATIC / name).read_bytes(), media_type=kind)
