"""Start-up time of the commands that do not run the engine (issue 34 §6), and where it goes.

Each case is a fresh child process, repeated `--repeat` times (default 7) and alternated case by case so
that all see the same phase of a shared machine; the table gives the median and the fastest wall time and
the largest peak memory (the child's ``ru_maxrss`` from ``os.wait4``). Cases: ``python -c "import
floebreak"``, ``python -c "import floebreak.cli"``, ``floebreak --help``, ``floebreak --version``,
``floebreak observations`` and ``floebreak schema``. With ``--importtime`` the heaviest imports of a
command are listed from ``python -X importtime`` (cumulative time of each package's first import and of
floebreak's modules; one run, so only the ranking is meaningful).

An editable install's src/ is compiled to bytecode first, as an installed copy is (end_to_end.py does the
same). Run: ``.venv/bin/python benchmarks/startup.py [--repeat N] [--importtime]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from end_to_end import _cli, _compile_bytecode, print_load_average

REPO = Path(__file__).resolve().parents[1]


def cases() -> dict[str, list[str]]:
    cli = _cli()
    return {
        'python -c "import floebreak"': [sys.executable, "-c", "import floebreak"],
        'python -c "import floebreak.cli"': [sys.executable, "-c", "import floebreak.cli"],
        "floebreak --help": [cli, "--help"],
        "floebreak --version": [cli, "--version"],
        "floebreak observations": [cli, "observations"],
        "floebreak schema": [cli, "schema"],
    }


def time_once(command: list[str]) -> tuple[float, float]:
    """Wall time [s] and peak memory [MB] of one child running `command`."""
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)  # reaped by wait4; Popen must not wait again
    if child.returncode != 0:
        sys.exit(f"{' '.join(command)} failed with exit code {child.returncode}")
    return wall, usage.ru_maxrss / 1024.0  # Linux: KiB


def heaviest_imports(command: list[str], n: int = 10) -> list[tuple[int, str]]:
    """The `n` imports with the largest cumulative time [µs] (`python -X importtime`): per third-party
    package its first import (which includes its own sub-imports), and floebreak's modules one by one."""
    if Path(command[0]).name == "floebreak":  # the entry point is a Python script: run it under -X importtime
        command = [sys.executable, "-X", "importtime", "-m", "floebreak", *command[1:]]
    else:
        command = [command[0], "-X", "importtime", *command[1:]]
    result = subprocess.run(command, capture_output=True, text=True, cwd=REPO, check=True)
    largest: dict[str, int] = {}
    for line in result.stderr.splitlines():
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _, cumulative, name = (part.strip() for part in line.removeprefix("import time:").split("|"))
        key = name if name.startswith("floebreak.") else name.split(".")[0]
        largest[key] = max(largest.get(key, 0), int(cumulative))
    return sorted(((us, key) for key, us in largest.items()), reverse=True)[:n]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="runs per case (≥ 5; the median is reported)")
    parser.add_argument("--importtime", action="store_true", help="list each command's heaviest imports")
    options = parser.parse_args()
    _compile_bytecode()
    print_load_average()
    commands = cases()
    walls: dict[str, list[float]] = {name: [] for name in commands}
    peaks: dict[str, list[float]] = {name: [] for name in commands}
    for _ in range(max(options.repeat, 5)):
        for name, command in commands.items():  # alternated: every case sees the same phases
            wall, peak = time_once(command)
            walls[name].append(wall)
            peaks[name].append(peak)
    print("| command | median wall s | fastest s | peak MB | runs |\n|---|---|---|---|---|")
    for name in commands:
        print(
            f"| `{name}` | {statistics.median(walls[name]):.2f} | {min(walls[name]):.2f} | "
            f"{max(peaks[name]):.0f} | {len(walls[name])} |"
        )
    if options.importtime:
        for name, command in commands.items():
            heavy = ", ".join(f"{package} {us / 1e6:.2f} s" for us, package in heaviest_imports(command))
            print(f"\n{name}: {heavy}")


if __name__ == "__main__":
    main()
