"""The routes of the web app, one router per job: pages, case, surface, predict, jobs, downloads.

Each module holds an ``APIRouter`` named ``router``; :func:`sealeak.web.app.create_app` includes
:data:`ROUTERS`. A route takes the server's shared state and the request's session as FastAPI
dependencies (:data:`sealeak.web.state.StateDep`, :data:`sealeak.web.state.SessionDep`) and its
JSON body as a model of :mod:`sealeak.web.models`.
"""

from . import case, downloads, jobs, pages, predict, surface

__all__ = ["ROUTERS"]

#: The routers of the app, in the order they are included.
ROUTERS = (pages.router, case.router, surface.router, predict.router, jobs.router, downloads.router)
