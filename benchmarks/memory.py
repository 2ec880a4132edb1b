"""Peak memory of whole runs (issue 20): the thin-floe case and transits of growing length.

Each case is one `floebreak run … -q` in a child process (the command a user types: field generation, the
run, writing the run directory with figures); its peak resident memory comes from ``os.wait4`` (the child's
own ``ru_maxrss``), its time from the wall clock. Goals: thin floe (one inline floe D = 40 m, h = 0.06 m,
Agulhas II, step 0.25 m) ≤ 500 MB; a 100 km × 200 m transit ≤ 1 GB. The command streams the contact records
to a scratch folder next to the run directory (`floebreak.run(spool=…)`), so these are the figures of a
user's run; `floebreak.run` without a spool keeps the records in memory (≈ 130 bytes per row, ≈ 20 000
rows per km of these transits).

    .venv/bin/python benchmarks/memory.py                      # thin floe, 1 km and 10 km × 200 m
    nice .venv/bin/python benchmarks/memory.py --no-thin --lengths 100000   # minutes
    nice .venv/bin/python benchmarks/memory.py --no-thin --lengths 100000 --dynamic   # ice that moves
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

THIN_FLOE = """\
[field]
floes = [{x_m = 30.0, y_m = 0.0, diameter_m = 40.0}]
[ice]
thickness_m = 0.06
[ship]
hull = "agulhas_ii"
step_m = 0.25
"""

TRANSIT = """\
seed = 1
[field]
observation = "2019-12-18T20:20"
length_m = {length:.1f}
width_m = 200.0
[ice]
thickness_m = 1.0
[ship]
hull = "agulhas_ii"
step_m = 0.25
"""


def measure(scenario_text: str, folder: Path, name: str) -> tuple[float, float, int]:
    """(peak resident memory [MB], wall time [s], exit code) of `floebreak run` on the scenario."""
    scenario = folder / f"{name}.toml"
    scenario.write_text(scenario_text, encoding="utf-8")
    command = [sys.executable, "-c", "from floebreak.cli import main; main()", "run", str(scenario)]
    started = time.perf_counter()
    child = subprocess.Popen([*command, "--out", str(folder / name), "-q"], stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - started
    shutil.rmtree(folder / name, ignore_errors=True)
    return usage.ru_maxrss / 1024, seconds, os.waitstatus_to_exitcode(status)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--lengths", type=float, nargs="*", default=[1000.0, 10000.0], help="transits [m]")
    parser.add_argument("--no-thin", action="store_true", help="skip the thin-floe case")
    parser.add_argument("--dynamic", action="store_true", help='transits with ice_motion = "dynamic"')
    args = parser.parse_args()
    cases = [] if args.no_thin else [("thin floe D = 40 m, h = 0.06 m", THIN_FLOE)]
    motion = '[simulation]\nice_motion = "dynamic"\n' if args.dynamic else ""
    cases += [
        (
            f"transit {length / 1000:g} km × 200 m{', dynamic' if args.dynamic else ''}",
            TRANSIT.format(length=length) + motion,
        )
        for length in args.lengths
    ]
    with tempfile.TemporaryDirectory() as temp:
        for i, (label, text) in enumerate(cases):
            peak_mb, seconds, code = measure(text, Path(temp), f"case{i}")
            print(f"{label:34s} peak {peak_mb:7.0f} MB  {seconds:7.1f} s  exit {code}", flush=True)


if __name__ == "__main__":
    main()
