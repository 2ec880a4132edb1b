"""The `floebreak` console command's entry point: `floebreak.cli.main`, imported with the collector paused.

Importing floebreak and the libraries it uses (numpy, scipy.optimize, numba, shapely, pyarrow, pydantic,
typer, rich) creates about a million objects that live as long as the process. At the collector's default
thresholds they would be walked over and over while they are created (≈ 250 collections, 0.09–0.16 s of
every start); here the collector is off while they are imported, and `gc.freeze` then moves them out of its
reach for good (as `floebreak.cli.main` does for everything else at start). This module lies outside the
package because the package's own imports are the ones to pause, and they run before any code inside it.
"""

from __future__ import annotations

import gc


def main() -> None:
    enabled = gc.isenabled()
    gc.disable()
    try:
        from floebreak.cli import main as cli_main
    finally:
        gc.freeze()
        if enabled:
            gc.enable()
    cli_main()
