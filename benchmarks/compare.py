"""Same-phase comparison of the breaking run with another commit.

The development VM's speed drifts by up to ≈ 40 % over minutes, so a figure measured today cannot be set
against one from another day. This script checks the other commit out into a temporary git worktree and
alternates the two versions round by round, each round a child process per version (the default profile on
the reference field, `simulate` alone, its CPU time, best of `--runs`), so both see the same phase of the
machine.

With `--end-to-end` each round instead runs the command line as a user does, `floebreak run
examples/reference.toml --quiet` on the field size given (default then 1 km × 200 m), one child process per
run (CPU time of the child, user + system, best of `--runs`: on a shared machine wall time follows the
other processes' load): start-up, field, simulation and the whole run directory with figures and report.
`--set KEY=VALUE` (repeatable) adds a scenario override to both sides' command lines, e.g.
`simulation.ice_motion=dynamic`. With `--end-to-end --propeller` it times `floebreak propeller` (shaft line,
PC5, operating profile: `PROPELLER_ARGS`) on each side's own run instead.
The child starts the console command's entry point of its version, the function its `pyproject.toml` names
under `[project.scripts]` (`floebreak.__main__:main` today, with the console process' collector settings;
`floebreak.cli:main` where no such file is found); both sides' sources are compiled to bytecode first, as an
installed copy is.

Run: `.venv/bin/python benchmarks/compare.py REV [--rounds 3] [--runs 5] [--length-m 400 --width-m 50]
[--end-to-end [--propeller] [--set KEY=VALUE …]] [--against REV2] [--new-params JSON] [--old-params JSON]
[--profile thesis]`
(REV: any git revision, e.g. a commit or `HEAD~3`; `--against` compares with REV2 instead of the working tree;
`--new-params` gives the compared side's `SimulationParams`, e.g. a coarser step with located events, issue
32, `--old-params` REV's; `--profile`: the engine's profile on both sides). Both sides' kernels are
compiled first (≈ 10 s, not timed).
"""

from __future__ import annotations

import argparse
import compileall
import json
import os
import statistics
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = """
import gc, json, sys, time
import numpy as np
from floebreak.ice.generation import generate_field
from floebreak.ice.observations import get_observation
from floebreak.mechanics import compile_kernels
from floebreak.ship.hulls import agulhas_ii
try:  # the package layout since config/ and engine/; a revision before them has the flat modules
    from floebreak.config.profiles import build_model
    from floebreak.engine.loop import SimulationParams, simulate
except ImportError:
    from floebreak.profiles import build_model
    from floebreak.simulation import SimulationParams, simulate
compile_kernels()
gc.freeze()  # as the CLI does after loading the engine
length_m, width_m, runs, profile = float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), sys.argv[5]
params = SimulationParams(**{"step_m": 0.25, **json.loads(sys.argv[4])})
field = generate_field(
    get_observation("2019-12-18T20:20"), length_m, width_m, np.random.default_rng(1), thickness_m=1.0
)
model, bow = build_model(profile), agulhas_ii(ice_thickness_m=1.0)
best = float("inf")
for _ in range(runs):
    start = time.process_time()
    result = simulate(field, bow, model, params)
    best = min(best, time.process_time() - start)
print(best, result.n_breaks)
"""

COMPILE = "from floebreak.mechanics import compile_kernels; compile_kernels()"

END_TO_END = """
import importlib, sys
entry, sys.argv = sys.argv[1], ["floebreak", *sys.argv[2:]]
module, function = entry.split(":")
getattr(importlib.import_module(module), function)()
"""


# `--propeller`: the analysis a designer runs on the reference run (issue 33), shaft line included
PROPELLER_ARGS = (
    *("--shaft-line", "agulhas_ii", "--speed-m-s", "3", "--mean-torque-knm", "105"),
    *("--polar-class", "PC5", "--hours-in-ice-per-year", "1000", "--years", "25"),
)


def _console_entry(src: Path) -> str:
    """`module:function` of the `floebreak` console command in the version at `src` (its pyproject.toml)."""
    pyproject = src.parent / "pyproject.toml"
    if pyproject.exists():
        scripts = tomllib.loads(pyproject.read_text()).get("project", {}).get("scripts", {})
        if "floebreak" in scripts:
            return scripts["floebreak"]
    return "floebreak.cli:main"


def _cli_cpu_s(src: Path, command: list[str]) -> float:
    """CPU time (user + system) of one CLI child process of the version at `src`."""
    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    child = subprocess.Popen(
        [sys.executable, "-c", END_TO_END, _console_entry(src), *command],
        env=env,
        cwd=src.parent,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    _, status, usage = os.wait4(child.pid, 0)  # the rusage of that one child
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        sys.exit(f"`{command[0]}` of {src} failed with exit code {child.returncode}")
    return usage.ru_utime + usage.ru_stime


def _run_end_to_end(src: Path, args: argparse.Namespace, params: str = "{}") -> tuple[float, int]:
    """CPU time (user + system) of the best of `args.runs` CLI runs (one child process each): on a shared
    machine it follows the code's work, where wall time follows the other processes' load. With
    `args.propeller`: the CPU time of `floebreak propeller RUN … PROPELLER_ARGS` on each run instead (the
    run itself untimed). `params` (`--new-params`) is for the engine alone: refused here (a run takes
    `--set` in its scenario)."""
    if params != "{}":
        sys.exit("--new-params times the engine alone: not with --end-to-end")
    best = float("inf")
    with tempfile.TemporaryDirectory(prefix="floebreak-compare-run-") as tmp:
        for run in range(args.runs):
            out = Path(tmp) / f"run{run}"
            command = [
                *("run", str(ROOT / "examples" / "reference.toml"), "--quiet", "--out", str(out)),
                *("--set", f"field.length_m={args.length_m}", "--set", f"field.width_m={args.width_m}"),
                *(item for setting in args.set for item in ("--set", setting)),
            ]
            seconds = _cli_cpu_s(src, command)
            if args.propeller:
                seconds = _cli_cpu_s(src, ["propeller", str(out), "--out", str(out / "p"), *PROPELLER_ARGS])
            best = min(best, seconds)
            breaks = json.loads((out / "summary.json").read_text())["n_breaks"]
    return best, breaks


def _run(src: Path, args: argparse.Namespace, params: str = "{}") -> tuple[float, int]:
    sizes = (str(args.length_m), str(args.width_m), str(args.runs))
    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1"}
    out = subprocess.run(
        [sys.executable, "-c", CHILD, *sizes, params, args.profile],
        env=env,
        cwd=src.parent,
        check=True,
        capture_output=True,
        text=True,
    ).stdout.split()
    return float(out[0]), int(out[1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rev", help="the git revision to compare with")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--runs", type=int, default=5, help="runs per child process (best is kept)")
    parser.add_argument("--length-m", type=float, default=None, help="default 400 m (1 000 m end to end)")
    parser.add_argument("--width-m", type=float, default=None, help="default 50 m (200 m end to end)")
    parser.add_argument("--end-to-end", action="store_true", help="time the command line's whole run")
    parser.add_argument("--against", help="compare with this revision instead of the working tree")
    parser.add_argument(
        "--new-params",
        default="{}",
        help='SimulationParams of the compared side (not REV) as JSON, e.g. \'{"step_m": 0.5, '
        '"event_location": "root"}\' (engine only; default step_m 0.25)',
    )
    parser.add_argument("--old-params", default="{}", help="as --new-params, for REV's side")
    parser.add_argument("--profile", default="default", help="the engine's profile (default: default)")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="with --end-to-end: a scenario override for both sides, e.g. simulation.ice_motion=dynamic",
    )
    parser.add_argument(
        "--propeller", action="store_true", help="with --end-to-end: time `floebreak propeller` on the run"
    )
    args = parser.parse_args()
    if args.propeller and not args.end_to_end:
        parser.error("--propeller needs --end-to-end")
    if args.set and not args.end_to_end:
        parser.error("--set needs --end-to-end (the engine alone takes --new-params)")
    if args.length_m is None:
        args.length_m = 1000.0 if args.end_to_end else 400.0
    if args.width_m is None:
        args.width_m = 200.0 if args.end_to_end else 50.0
    run = _run_end_to_end if args.end_to_end else _run
    new = args.against or "working tree"
    with tempfile.TemporaryDirectory(prefix="floebreak-compare-") as tmp:
        trees = {args.rev: Path(tmp) / "old"} | ({new: Path(tmp) / "new"} if args.against else {})
        for rev, tree in trees.items():
            subprocess.run(["git", "worktree", "add", "--detach", "-q", str(tree), rev], cwd=ROOT, check=True)
        try:
            sides = {args.rev: trees[args.rev] / "src", new: trees.get(new, ROOT) / "src"}
            _compare(sides, run, args)
        finally:
            for tree in trees.values():
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, check=True)


def _compare(sides: dict[str, Path], run, args: argparse.Namespace) -> None:
    for src in sides.values():  # numba caches per source path: compile both before timing
        env = {**os.environ, "PYTHONPATH": str(src)}
        subprocess.run([sys.executable, "-c", COMPILE], env=env, cwd=src.parent, check=True)
    if args.end_to_end:  # as an installed copy: no compilation to bytecode at each start
        for src in sides.values():
            compileall.compile_dir(src, quiet=1)
    unit = "s CPU"
    best: dict[str, list[float]] = {name: [] for name in sides}
    old, new = sides
    for round_ in range(1, args.rounds + 1):
        for name, src in sides.items():
            seconds, breaks = run(src, args, args.old_params if name == old else args.new_params)
            best[name].append(seconds)
            print(f"round {round_}: {name:>14}  {seconds:.3f} {unit}  ({breaks} breaks)", flush=True)
    medians = {name: statistics.median(values) for name, values in best.items()}
    print(
        f"{args.length_m:.0f} m × {args.width_m:.0f} m, median of the rounds' best: "
        + ", ".join(f"{name} {value:.3f} {unit}" for name, value in medians.items())
        + f"; ratio {medians[old] / medians[new]:.2f}"
    )


if __name__ == "__main__":
    main()
