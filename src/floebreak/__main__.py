"""The console command ``floebreak`` (pyproject.toml ``[project.scripts]``) and ``python -m floebreak``.

Its only work before the command line: make Ctrl-C exit 130 with one line from the first moment this code
runs. Importing `floebreak.cli` loads typer, rich and numpy (≈ 0.2–1 s); a Ctrl-C meanwhile would otherwise
print a KeyboardInterrupt traceback from inside some library's import. Until `floebreak.cli.main` takes
over (it turns Ctrl-C into a KeyboardInterrupt again and reports it), the handler below ends the process at
once: nothing has been written yet.
"""

from __future__ import annotations

import os
import signal

from floebreak.errors import EXIT_INTERRUPTED, INTERRUPTED_MESSAGE


def _interrupted_while_loading(signum: int, frame: object) -> None:
    os.write(2, f"{INTERRUPTED_MESSAGE}\n".encode())
    os._exit(EXIT_INTERRUPTED)


def main() -> None:
    signal.signal(signal.SIGINT, _interrupted_while_loading)
    from floebreak.cli import main as cli_main

    cli_main()


if __name__ == "__main__":
    main()
