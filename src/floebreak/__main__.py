"""The console command ``floebreak`` (pyproject.toml ``[project.scripts]``) and ``python -m floebreak``.

Its only work before the command line: make Ctrl-C exit 130 with one line from the first moment this code
runs. Importing `floebreak.cli` loads typer, rich and numpy (≈ 0.2–1 s); a Ctrl-C meanwhile would otherwise
print a KeyboardInterrupt traceback from inside some library's import. Until `floebreak.cli.main` takes
over (it turns Ctrl-C into a KeyboardInterrupt again and reports it), the handler below ends the process at
once: nothing has been written yet. So that the handler is in place as early as possible, this module and
the package's ``__init__`` import nothing but the standard library's lightest modules before it.
"""

from __future__ import annotations

import os
import signal

# Ctrl-C: 128 + SIGINT, the shells' convention; one line, the same here and from `floebreak.cli.main`
EXIT_INTERRUPTED = 130
INTERRUPTED_MESSAGE = "interrupted (Ctrl-C); nothing half-written was kept"


def _interrupted_while_loading(signum: int, frame: object) -> None:
    os.write(2, f"{INTERRUPTED_MESSAGE}\n".encode())
    os._exit(EXIT_INTERRUPTED)


def main() -> None:
    signal.signal(signal.SIGINT, _interrupted_while_loading)
    from floebreak.cli import main as cli_main

    cli_main()


if __name__ == "__main__":
    main()
