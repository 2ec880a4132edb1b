"""The console command ``floebreak`` (pyproject.toml ``[project.scripts]``) and ``python -m floebreak``.

Its only work before the command line: make Ctrl-C exit 130 with one line from the first moment this code
runs. Importing `floebreak.cli` loads typer, rich and numpy (≈ 0.2–1 s); a Ctrl-C meanwhile would otherwise
print a KeyboardInterrupt traceback from inside some library's import. Until `floebreak.cli.main` takes over
(it turns Ctrl-C into a KeyboardInterrupt again and reports it), the handler below ends the process at once:
nothing has been written yet. The garbage collector's settings of the console process are made here too, so
that a test or a script calling `floebreak.cli.main` runs with Python's defaults. So that the handler is in
place as early as possible, this module and the package's ``__init__`` import nothing but the standard
library's lightest modules before it.
"""

from __future__ import annotations

import os
import signal

from floebreak.exit_codes import EXIT_INTERRUPTED, INTERRUPTED_MESSAGE


def _interrupted_while_loading(signum: int, frame: object) -> None:
    os.write(2, f"{INTERRUPTED_MESSAGE}\n".encode())
    os._exit(EXIT_INTERRUPTED)


def main() -> None:
    signal.signal(signal.SIGINT, _interrupted_while_loading)
    import atexit
    import gc

    # the collector settings of the console process only (tests and library users keep Python's): a run
    # creates many long-lived objects and few reference cycles, so a lazier collector, the engine's
    # libraries frozen once loaded, and no collection over everything alive at exit (it pays,
    # benchmarks/README.md "Simple over clever")
    gc.set_threshold(50_000, 20, 10)
    atexit.unregister(gc.freeze)  # registered once, however often main() runs in one process
    atexit.register(gc.freeze)
    from floebreak.cli import main as cli_main

    cli_main(engine_loaded=gc.freeze)


if __name__ == "__main__":
    main()
