"""Start-up time of the command line and of ``import sealeak``: the median of fresh interpreters.

Usage: python benchmarks/bench_startup.py [RUNS]   (default 15)
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

COMMANDS = {
    "python -c pass (the interpreter alone)": [sys.executable, "-c", "pass"],
    "import sealeak": [sys.executable, "-c", "import sealeak"],
    "sealeak --help": [sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(['--help']))"],
    "sealeak predict --help": [sys.executable, "-c",
                               "import sys; from sealeak.cli import main; sys.exit(main(['predict', '--help']))"],
    "import sealeak; sealeak.run_case (the cases layer)": [sys.executable, "-c", "import sealeak; sealeak.run_case"],
}


def wall(argv: list[str]) -> float:
    """Seconds one fresh interpreter takes to run ``argv`` to its end."""
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    print(f"{'command':52s} {'median (s)':>10s} {'min (s)':>8s}")
    for name, argv in COMMANDS.items():
        wall(argv)  # warm the file cache
        times = [wall(argv) for _ in range(runs)]
        print(f"{name:52s} {statistics.median(times):10.3f} {min(times):8.3f}")


if __name__ == "__main__":
    main()
