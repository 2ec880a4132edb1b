"""The console command ``floebreak`` (pyproject.toml ``[project.scripts]``) and ``python -m floebreak``.

Its work around the command line: make Ctrl-C (SIGINT) and SIGTERM end the process with one line and their
own exit codes (130, 143) at every moment this code runs.

- While `floebreak.cli` loads (typer, rich and numpy, ≈ 0.2–1 s) a signal would otherwise print a
  KeyboardInterrupt traceback from inside some library's import, or end the process silently: the handler
  below ends it at once, with its line; nothing has been written yet. So that it is in place as early as
  possible, this module and the package's ``__init__`` import nothing but the standard library's lightest
  modules before it.
- While a command runs, Ctrl-C raises KeyboardInterrupt (`floebreak.cli.main` installs Python's handler) and
  SIGTERM raises `Terminated`, a KeyboardInterrupt: both unwind through the same clean-up (temporary
  outputs and spool directories removed, a study's pool closed), and `floebreak.cli.main` reports them with
  `interruption()`'s line and code.
- Once the command has returned (interpreter shutdown, atexit callbacks), a signal ends the process at once
  again: raised there, a KeyboardInterrupt printed "Exception ignored … KeyboardInterrupt:" and the process
  exited 0 (issue 31; seen with a SIGINT that the parent had set to be ignored, which a command started in
  the background inherits).
"""

from __future__ import annotations

import os
import signal

# 128 + the signal number, the shells' convention; one line each, the same here and from `floebreak.cli.main`
EXIT_INTERRUPTED = 130
INTERRUPTED_MESSAGE = "interrupted (Ctrl-C); nothing half-written was kept"
EXIT_TERMINATED = 143
TERMINATED_MESSAGE = "terminated (SIGTERM); nothing half-written was kept"


class Terminated(KeyboardInterrupt):
    """SIGTERM during a command: raised like Ctrl-C, so that the same clean-up runs."""


# the last signal that interrupted the command: signals are process-wide, and so is this record
_received: list[int] = []


def interruption() -> tuple[str, int]:
    """(message, exit code) of the interruption being reported: SIGTERM's if one came, else Ctrl-C's."""
    if _received and _received[-1] == signal.SIGTERM:
        return TERMINATED_MESSAGE, EXIT_TERMINATED
    return INTERRUPTED_MESSAGE, EXIT_INTERRUPTED


def _exit_now(signum: int, frame: object) -> None:
    """Outside a command: end the process at once with the signal's line and code."""
    _received.append(signum)
    message, code = interruption()
    os.write(2, f"{message}\n".encode())
    os._exit(code)


def _raise_terminated(signum: int, frame: object) -> None:
    _received.append(signum)
    raise Terminated()


def main() -> None:
    signal.signal(signal.SIGINT, _exit_now)
    signal.signal(signal.SIGTERM, _exit_now)
    from floebreak.cli import main as cli_main

    signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        cli_main()
    finally:
        signal.signal(signal.SIGINT, _exit_now)
        signal.signal(signal.SIGTERM, _exit_now)


if __name__ == "__main__":  # `python -m floebreak`: run as the module `floebreak.cli` imports (one record)
    from floebreak.__main__ import main as package_main

    package_main()
