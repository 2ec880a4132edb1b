"""The console command ``floebreak`` (pyproject.toml ``[project.scripts]``) and ``python -m floebreak``.

Its work around the command line: make Ctrl-C (SIGINT) and SIGTERM end the process with one line and their
own exit codes (130, 143, `floebreak.exit_codes`) at every moment this code runs, and set the console
process' garbage-collector settings (so that a test or a script calling `floebreak.cli.main` runs with
Python's defaults).

- While `floebreak.cli` loads (typer, rich and numpy, ≈ 0.2–1 s) a signal would otherwise print a
  KeyboardInterrupt traceback from inside some library's import, or end the process silently: the handler
  below ends it at once, with its line; nothing has been written yet. So that it is in place as early as
  possible, this module and the package's ``__init__`` import nothing but the standard library's lightest
  modules before it.
- While a command runs, Ctrl-C raises KeyboardInterrupt (`floebreak.cli.main` installs Python's handler) and
  SIGTERM raises `Terminated`, a KeyboardInterrupt: both unwind through the same clean-up (temporary
  outputs and spool directories removed, a study's pool closed), and `floebreak.cli.main` reports them with
  `exit_codes.interruption()`'s line and code.
- Once the command has returned (interpreter shutdown, atexit callbacks), a signal ends the process at once
  again: raised there, a KeyboardInterrupt printed "Exception ignored … KeyboardInterrupt:" and the process
  exited 0 (seen with a SIGINT that the parent had set to be ignored, which a command started in
  the background inherits).
"""

from __future__ import annotations

import os
import signal

from floebreak.exit_codes import Terminated, interruption, record_signal


def _exit_now(signum: int, frame: object) -> None:
    """Outside a command: end the process at once with the signal's line and code."""
    record_signal(signum)
    message, code = interruption()
    os.write(2, f"{message}\n".encode())
    os._exit(code)


def _raise_terminated(signum: int, frame: object) -> None:
    record_signal(signum)
    raise Terminated()


def main() -> None:
    signal.signal(signal.SIGINT, _exit_now)
    signal.signal(signal.SIGTERM, _exit_now)
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

    signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        cli_main(engine_loaded=gc.freeze)
    finally:
        signal.signal(signal.SIGINT, _exit_now)
        signal.signal(signal.SIGTERM, _exit_now)


if __name__ == "__main__":
    main()
