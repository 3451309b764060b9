"""The local web app of ``sealeak serve``: pages to edit a case, analyse surfaces, predict and simulate.

A front end like the command line, and beside it: it runs cases through :mod:`sealeak.cases` and
renders with :mod:`sealeak.render` (no physics of its own), so its JSON API answers with exactly
what the command line writes. It needs the ``web`` extra (``pip install sealeak[web]``: FastAPI,
uvicorn, python-multipart, plotly for Plotly.js, tomli-w). ``docs/web.md`` describes the pages,
the API and the safety rules.
"""

from .app import DEFAULT_MAX_UPLOAD, WebConfig, create_app
from .server import serve

__all__ = ["create_app", "WebConfig", "DEFAULT_MAX_UPLOAD", "serve"]
