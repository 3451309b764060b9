"""The pages (static HTML with ``static/app.js``) and their static files, Plotly.js from the ``plotly`` package.

Each page's ``static/NAME.html`` holds its own content; ``static/frame.html`` holds what every page shares (the
head, the navigation, the script) and the page is served as that frame around its content.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import plotly
from fastapi import APIRouter
from fastapi.responses import FileResponse, RedirectResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

__all__ = ["router", "PAGES", "Page", "page_html"]

_STATIC = resources.files("sealeak") / "web" / "static"


@dataclass(frozen=True)
class Page:
    """One page: its title (after "sealeak — ") and whether it draws with Plotly.js."""

    title: str
    plotly: bool = False


#: The pages: the path ``/NAME`` → its content ``static/NAME.html`` in the frame ``static/frame.html``.
PAGES = {"case": Page("Case"), "surface": Page("Surface", plotly=True), "prediction": Page("Prediction", plotly=True),
         "simulation": Page("Simulation"), "help": Page("Case-file keys")}

router = APIRouter(include_in_schema=False)


@router.get("/")
def index() -> RedirectResponse:
    """The case page."""
    return RedirectResponse("/case")


def page_html(name: str) -> str:
    """The HTML of the page ``/NAME``: the frame around the page's content."""
    scripts = "<script src=\"/static/plotly.min.js\"></script>\n" if PAGES[name].plotly else ""
    frame = (_STATIC / "frame.html").read_text(encoding="utf-8")
    return frame.format(title=PAGES[name].title, scripts=scripts, name=name,
                        main=(_STATIC / f"{name}.html").read_text(encoding="utf-8"))


def _page(name: str) -> Callable[[], Response]:
    """The route of one page: it takes no parameter (a query parameter naming the file would read any file)."""
    def page() -> Response:
        return Response(page_html(name).encode(), media_type="text/html; charset=utf-8")
    return page


for _name in PAGES:
    router.add_api_route(f"/{_name}", _page(_name), methods=["GET", "HEAD"], name=f"page_{_name}")


@router.api_route("/static/{name}", methods=["GET", "HEAD"])
def static(name: str) -> Response:
    """A script or style sheet of the pages (``[a-z]+.js``, ``[a-z]+.css``), or Plotly.js."""
    if name == "plotly.min.js":
        return FileResponse(Path(plotly.__file__).parent / "package_data" / "plotly.min.js", media_type="text/javascript")
    if not re.fullmatch(r"[a-z]+\.(js|css)", name) or not (_STATIC / name).is_file():
        raise StarletteHTTPException(404, f"{name}: no such file")
    kind = "text/javascript" if name.endswith(".js") else "text/css"
    return Response((_STATIC / name).read_bytes(), media_type=kind)
