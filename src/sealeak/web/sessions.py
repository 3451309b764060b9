"""Browser sessions of the web app: a random token (cookie), a private temporary folder, its jobs.

Each session has its own folder under the server's temporary root: ``uploads/`` (the files a case
may name) and ``jobs/<id>/`` (simulation runs). The folder is removed when the session has been
idle for ``idle`` seconds and when the server stops; its running jobs are cancelled first. A
session never sees another's files or jobs: everything is looked up through its own token.
"""

from __future__ import annotations

import secrets
import shutil
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import SealeakError

__all__ = ["Session", "SessionStore", "SessionsFull", "COOKIE", "DEFAULT_MAX_SESSIONS", "REPLACEABLE_AFTER"]

#: The most sessions one server holds at once.
DEFAULT_MAX_SESSIONS = 100

#: Seconds idle after which a session with files or jobs (none running) may be replaced by a new one when the server
#: holds its most sessions.
REPLACEABLE_AFTER = 600.0

#: The name of the session cookie.
COOKIE = "sealeak_session"


@dataclass(kw_only=True)
class Session:
    """One browser session: its folder, its current case (TOML text and name) and its jobs."""

    token: str
    folder: Path
    last_seen: float = field(default_factory=time.monotonic)
    case_text: str | None = None
    case_name: str = "case.toml"
    jobs: dict[str, Any] = field(default_factory=dict)
    #: uploaded files: the name each is stored under → the name the user gave it (shown, never a path)
    upload_names: dict[str, str] = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)

    @property
    def uploads(self) -> Path:
        """The folder of the files uploaded in this session (created on first use)."""
        p = self.folder / "uploads"
        p.mkdir(parents=True, exist_ok=True)
        return p

    @property
    def uploads_path(self) -> Path:
        """Where the uploads are (the folder may not exist yet: nothing was uploaded)."""
        return self.folder / "uploads"

    @property
    def jobs_folder(self) -> Path:
        """The folder of this session's simulation jobs (created on first use)."""
        p = self.folder / "jobs"
        p.mkdir(parents=True, exist_ok=True)
        return p

    def uploaded(self) -> set[str]:
        """The names of the files uploaded in this session."""
        up = self.uploads_path
        return {p.name for p in up.iterdir() if p.is_file()} if up.is_dir() else set()


class SessionsFull(SealeakError):
    """The server holds its most sessions, each in use (files or jobs, seen lately; status 503)."""


class SessionStore:
    """The sessions of one server, in folders under ``root``; idle ones expire after ``idle`` seconds.

    At most ``limit`` sessions at once: a new one then replaces the least recently seen session that stored nothing,
    else one that holds only a case, else one idle for :data:`REPLACEABLE_AFTER` s with no simulation running; when
    every session is in use, :class:`SessionsFull`.
    """

    def __init__(self, root: Path, idle: float = 4 * 3600.0, limit: int = DEFAULT_MAX_SESSIONS) -> None:
        self.root = root
        self.idle = idle
        self.limit = limit
        self._sessions: dict[str, Session] = {}
        self._lock = threading.Lock()

    def get(self, token: str | None) -> Session | None:
        """The live session of ``token`` (its idle clock restarted), or None."""
        with self._lock:
            s = self._sessions.get(token or "")
            if s is not None:
                s.last_seen = time.monotonic()
            return s

    def create(self) -> Session:
        """A new session with a random 256-bit token (its folder is made when first needed)."""
        token = secrets.token_urlsafe(32)
        s = Session(token=token,
                    folder=self.root / secrets.token_hex(8))  # its folder is made on its first upload or job
        ended = None
        with self._lock:
            if len(self._sessions) >= self.limit:
                ended = self._replaced()
                if ended is None:
                    raise SessionsFull(f"the server holds {len(self._sessions)} sessions, its most, each with files or "
                                       f"jobs and seen in the last {REPLACEABLE_AFTER / 60:.0f} minutes: try again "
                                       "when one has ended")
                del self._sessions[ended.token]
            self._sessions[token] = s
        if ended is not None:
            _end(ended)
        return s

    def _replaced(self) -> Session | None:
        """The session a new one replaces when the server is full, least recently seen first among: those that stored
        nothing; those that hold only a case (a text; a script without the cookie stores one with each request); those
        idle for :data:`REPLACEABLE_AFTER` s with no simulation running. None: every session is in use."""
        now = time.monotonic()
        sessions = list(self._sessions.values())
        for tier in ([o for o in sessions if not _holds(o)],
                     [o for o in sessions if not (o.folder.exists() or o.jobs)],
                     [o for o in sessions if now - o.last_seen > REPLACEABLE_AFTER
                      and not any(j.state in ("starting", "running") for j in list(o.jobs.values()))]):
            if tier:
                return min(tier, key=lambda o: o.last_seen)
        return None

    def running_jobs(self) -> int:
        """The simulations running (or starting) in all sessions."""
        with self._lock:
            sessions = list(self._sessions.values())
        return sum(1 for s in sessions for j in list(s.jobs.values()) if j.state in ("starting", "running"))

    def __len__(self) -> int:
        with self._lock:
            return len(self._sessions)

    def expire(self, now: float | None = None) -> list[Session]:
        """End the sessions idle for longer than ``idle``: cancel their jobs, remove their folders."""
        now = time.monotonic() if now is None else now
        # a session that never stored anything (a script's request without the cookie) goes after 10 minutes
        with self._lock:
            old = [s for s in self._sessions.values() if now - s.last_seen > (self.idle if _holds(s) else min(self.idle, 600.0))]
            for s in old:
                del self._sessions[s.token]
        for s in old:
            _end(s)
        return old

    def close(self) -> None:
        """End every session (server shutdown)."""
        with self._lock:
            sessions = list(self._sessions.values())
            self._sessions.clear()
        for s in sessions:
            _end(s)


def _holds(s: Session) -> bool:
    """Whether a session stored anything: a folder (uploads, jobs), a case or a job."""
    return bool(s.folder.exists() or s.case_text or s.jobs)


def _end(s: Session) -> None:
    for job in list(s.jobs.values()):
        job.cancel()
    shutil.rmtree(s.folder, ignore_errors=True)

