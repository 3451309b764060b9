"""Load on the web app: 20 concurrent ``POST /api/predict`` of the reference example against one server.

Starts ``sealeak serve`` (uvicorn, one process) on a free loopback port, sends the bundled
reference-experiment case 20 times at once from 20 threads (urllib), checks that every answer is
byte for byte what ``sealeak predict --json`` writes, and prints the median and maximum latency.
Then the same with 20 different cases (each a new squeeze pressure: nothing cached).

    python benchmarks/bench_web.py [N]
"""

from __future__ import annotations

import os
import platform
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from sealeak.cases import example_text


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def cli_json(folder: Path, text: str) -> bytes:
    (folder / "case.toml").write_text(text, encoding="utf-8")
    subprocess.run([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                    "predict", "case.toml", "--json", "out.json", "-q", "--force"], cwd=folder, check=True)
    return (folder / "out.json").read_bytes()


def post(url: str, body: bytes) -> tuple[float, bytes]:
    t = time.perf_counter()
    req = urllib.request.Request(url, data=body, method="POST", headers={"Content-Type": "application/toml"})
    with urllib.request.urlopen(req, timeout=120) as r:
        data = r.read()
    return time.perf_counter() - t, data


def burst(url: str, bodies: list[bytes], expected: list[bytes]) -> list[float]:
    with ThreadPoolExecutor(len(bodies)) as pool:
        answers = list(pool.map(lambda b: post(url, b), bodies))
    for (_, got), want in zip(answers, expected):
        assert got == want, "an answer differs from sealeak predict --json"
    return [t for t, _ in answers]


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    port = free_port()
    env = dict(os.environ)
    server = subprocess.Popen([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                               "serve", "--port", str(port), "--quiet"], env=env)
    try:
        url = f"http://127.0.0.1:{port}/api/predict?name=case.toml"
        for _ in range(200):
            try:
                urllib.request.urlopen(f"http://127.0.0.1:{port}/api/uploads", timeout=1).read()
                break
            except OSError:
                time.sleep(0.1)
        ref = example_text("reference-experiment")
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            same = cli_json(folder, ref)
            variants = [re.sub(r"squeeze_pressure = [^\n]*", f'squeeze_pressure = {{start = "{10 + i} kPa", stop = "1 MPa", num = 40}}', ref)
                        for i in range(n)]
            expected = [cli_json(folder, v) for v in variants]
        print(f"machine: {platform.node()} {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
              f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        t, _ = post(url, ref.encode())
        print(f"one request, first run of the case: {t:.3f} s")
        lat = burst(url, [ref.encode()] * n, [same] * n)
        print(f"{n} concurrent, the same case (cached):   median {statistics.median(lat):.3f} s, max {max(lat):.3f} s")
        lat = burst(url, [v.encode() for v in variants], expected)
        print(f"{n} concurrent, {n} different cases:       median {statistics.median(lat):.3f} s, max {max(lat):.3f} s")
        print("every answer equals sealeak predict --json byte for byte")
    finally:
        server.terminate()
        server.wait(timeout=10)


if __name__ == "__main__":
    main()
