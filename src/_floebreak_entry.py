"""The `floebreak` console command's entry point: `floebreak.cli.main`, imported with the collector paused.

Objects created while modules are imported live as long as the process; at the collector's default
thresholds they are walked over and over while they are created. Here the collector is off while the
command line is imported (typer, rich, pydantic, numpy: ≈ 50 000 tracked objects, ≈ 0.01 s), and `gc.freeze`
then moves them out of its reach for good. The engine's libraries (numba, scipy.optimize, pyarrow: the
bulk of a run's imports) load only when a command needs them, the same way (`floebreak.cli._import_engine`).
This module lies outside the package because the package's own imports are the ones to pause, and they run
before any code inside it.
"""

from __future__ import annotations

import gc
import sys


def main() -> None:
    enabled = gc.isenabled()
    gc.disable()
    try:
        from floebreak.cli import main as cli_main
    except KeyboardInterrupt:  # Ctrl-C before the command line is loaded: as `floebreak.cli.main` reports it
        print("interrupted (Ctrl-C); nothing half-written was kept", file=sys.stderr)
        sys.exit(130)
    finally:
        gc.freeze()
        if enabled:
            gc.enable()
    cli_main()
