"""Simulation jobs of the web app: ``sealeak simulate`` in a process of its own, with progress and cancel.

A job runs the command line's ``simulate`` (the ensemble runner of :mod:`sealeak.cases.ensemble`,
``--store`` in the job's folder, so its progress comes as one line per finished task) in a new
process group, in the job's folder ``<session>/jobs/<id>/``, which holds a copy of the case file and
of the uploaded files it names. A long job therefore never blocks the server; cancelling kills the
whole process group (the simulation and any Dask workers it started). The results are the
command's own files: ``result.json``, ``table.txt`` and the figures in ``figures/``.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

__all__ = ["Job", "start_job"]

_TASKS = re.compile(r"\((\d+) of (\d+) tasks")
_BAR = re.compile(r"(\d+)/(\d+) \[")
#: How the job's process starts the command line (the web app itself never imports it).
_ENTRY = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"


class Job:
    """One ``simulate`` run: its state (``running``, ``done``, ``failed``, ``cancelled``), progress and files."""

    def __init__(self, folder: Path, title: str, options: dict[str, int]) -> None:
        self.id = folder.name
        self.folder = folder
        self.title = title
        self.options = options
        self.state = "starting"
        self.done = 0
        self.total = 0
        self.message = ""
        self.started = time.time()
        self.finished: float | None = None
        self._proc: subprocess.Popen[bytes] | None = None
        self._lock = threading.Lock()

    def info(self) -> dict[str, Any]:
        """The job as JSON: id, title, options, state, progress, message, figure names."""
        figures = sorted(p.name for p in (self.folder / "figures").glob("*.png")) if self.state == "done" else []
        return {"id": self.id, "title": self.title, "options": self.options, "state": self.state, "done": self.done,
                "total": self.total, "message": self.message, "figures": figures,
                "elapsed": round((self.finished or time.time()) - self.started, 1)}

    def _run(self, argv: list[str]) -> None:
        env = {k: v for k, v in os.environ.items() if not k.startswith("SEALEAK_WEB_")}
        env["PYTHONUNBUFFERED"] = "1"
        with open(self.folder / "table.txt", "wb") as out:
            proc = subprocess.Popen(argv, cwd=self.folder, stdout=out, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                                    start_new_session=True, env=env)
            with self._lock:
                self._proc = proc
                if self.state == "starting":
                    self.state = "running"
                elif self.state == "cancelled":  # cancelled before the process existed
                    _kill(proc)
            last = ""
            assert proc.stderr is not None
            for raw in iter(proc.stderr.readline, b""):
                for line in raw.decode("utf-8", "replace").replace("\r", "\n").splitlines():
                    m = _TASKS.search(line) or _BAR.search(line)
                    if m:
                        self.done, self.total = int(m.group(1)), int(m.group(2))
                    if line.startswith("sealeak: error:"):
                        last = line[len("sealeak: error:"):].strip()
            code = proc.wait()
        with self._lock:
            self.finished = time.time()
            if self.state == "cancelled":
                return
            if code == 0:
                self.state, self.done = "done", self.total
            else:
                self.state = "failed"
                self.message = last or f"the simulation stopped (exit status {code})"

    def cancel(self) -> None:
        """Stop the job: kill its process group (the simulation and its workers); finished jobs stay as they are."""
        with self._lock:
            if self.state not in ("starting", "running"):
                return
            self.state = "cancelled"
            self.message = "cancelled"
            self.finished = time.time()
            proc = self._proc
        if proc is not None:
            _kill(proc)

    def remove(self) -> None:
        """Cancel the job and delete its folder."""
        self.cancel()
        shutil.rmtree(self.folder, ignore_errors=True)


def _kill(proc: subprocess.Popen[bytes]) -> None:
    try:
        os.killpg(proc.pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    try:
        proc.wait(timeout=3)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def start_job(jobs_folder: Path, case_text: str, case_name: str, files: Iterable[Path], title: str,
              grid: int | None, realizations: int | None, seed: int | None, workers: int | None) -> Job:
    """Start ``sealeak simulate`` on a copy of the case (and the files it names) in a new job folder.

    ``grid``, ``realizations``, ``seed`` override the case's ``[simulation]`` (None: the case's value);
    ``workers`` is ``--workers`` (0: one process, no Dask; None: the command line's default, a local
    Dask cluster on every core from a 512² grid up).
    """
    folder = jobs_folder / secrets.token_hex(6)
    folder.mkdir(parents=True)
    for f in files:  # a snapshot: uploading a file anew does not change a running job
        try:
            os.link(f, folder / f.name)
        except OSError:
            shutil.copyfile(f, folder / f.name)
    (folder / case_name).write_text(case_text, encoding="utf-8")
    options = {k: v for k, v in (("grid", grid), ("realizations", realizations), ("seed", seed), ("workers", workers))
               if v is not None}
    # random surfaces from C(q), also for a topography case (the map route has no store, hence no progress, nor figures)
    argv = [sys.executable, "-c", _ENTRY, "simulate", case_name, "--surface", "random", "--json", "result.json",
            "--plots", "figures", "--store", "store", *[x for k, v in options.items() for x in (f"--{k}", str(v))]]
    job = Job(folder, title, options)
    threading.Thread(target=job._run, args=(argv,), name=f"sealeak-job-{job.id}", daemon=True).start()
    return job
