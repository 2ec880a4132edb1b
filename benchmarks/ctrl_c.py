"""Ctrl-C at random moments (issue 20): SIGINT into `floebreak run examples/reference.toml` after a random
delay; every try must exit 130 with the one line and leave nothing behind (no run directory, no
failed-scenario file). The command is the console command as pip's script runs it: the target of
pyproject.toml's [project.scripts], so a checkout is measured without reinstalling.

    .venv/bin/python benchmarks/ctrl_c.py                          # 12 tries, 0.8–8 s in (the run)
    .venv/bin/python benchmarks/ctrl_c.py --low 0 --high 0.8       # while the command line loads

A delay below ≈ 30 ms lands before Python has installed any handler: the process then ends by the signal
itself (the shell shows 130, no line is printed); the output counts those apart.
"""

from __future__ import annotations

import argparse
import collections
import random
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINE = "interrupted (Ctrl-C); nothing half-written was kept"


def console_command() -> list[str]:
    target = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["scripts"]
    module, function = target["floebreak"].split(":")
    return [sys.executable, "-c", f"import sys; from {module} import {function}; sys.exit({function}())"]


def one_try(delay_s: float, folder: Path) -> str:
    out = folder / "out"
    command = [*console_command(), "run", str(ROOT / "examples" / "reference.toml"), "--out", str(out), "-q"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    time.sleep(delay_s)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=600)
    left = sorted(p.name for p in folder.iterdir())
    if process.returncode == 0:
        return "finished before the signal"
    if process.returncode == -signal.SIGINT and not err:
        return "ended by the signal before Python's handler (shell: 130, no line)"
    if process.returncode == 130 and err == LINE + "\n" and not left:
        return "exit 130, the one line, nothing left"
    return f"FAILED: exit {process.returncode}, left {left}, stderr {err[-300:]!r}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=12)
    parser.add_argument("--low", type=float, default=0.8, help="shortest delay [s]")
    parser.add_argument("--high", type=float, default=8.0, help="longest delay [s]")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    outcomes = collections.Counter()
    for _ in range(args.tries):
        delay = rng.uniform(args.low, args.high)
        with tempfile.TemporaryDirectory() as folder:
            outcome = one_try(delay, Path(folder))
        print(f"{delay:6.3f} s: {outcome}", flush=True)
        outcomes[outcome] += 1
    for outcome, count in outcomes.most_common():
        print(f"{count:3d} × {outcome}")


if __name__ == "__main__":
    main()
