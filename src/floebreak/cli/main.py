"""The floebreak command line: each command parses its options and calls the public or application-layer
functions (docs/architecture.md); help texts follow `Command`'s conventions."""

from __future__ import annotations

import importlib
import signal
import sys
from typing import Annotated

import typer
import typer.core
from rich.markup import escape

from floebreak.cli.common import Group, console, err_console, use_command_class
from floebreak.errors import InputError
from floebreak.exit_codes import EXIT_INPUT, EXIT_INTERRUPTED, EXIT_STORAGE, interruption

DESCRIPTION = (
    "floebreak: a ship's bow breaking sea-ice floes (thesis model), the broken cusps' propeller-ice loads "
    "and the shaft torque they cause. Start with `floebreak demo --out demo-output`."
)


# the built-in command modules, each with `register(app)`: a command group is one module; an installed
# package adds one through the entry point group ``floebreak.commands`` (``name = "my_pkg.cli"``)
COMMAND_MODULES = (
    "floebreak.cli.views",
    "floebreak.cli.run",
    "floebreak.cli.study",
    "floebreak.cli.propeller",
    "floebreak.cli.validate",
)
ENTRY_POINT_GROUP = "floebreak.commands"
# the order `floebreak --help` lists the built-in commands in (a package's come after them)
HELP_ORDER = (
    "observations",
    "field",
    "run",
    "demo",
    "schema",
    "report",
    "animate",
    "study",
    "aggregate",
    "voyage",
    "propeller",
    "validate",
)


class _Root(Group):
    """The root group: its commands listed in `HELP_ORDER`."""

    def list_commands(self, ctx) -> list[str]:
        names = super().list_commands(ctx)
        rank = {name: k for k, name in enumerate(HELP_ORDER)}
        return sorted(names, key=lambda name: rank.get(name, len(rank)))


app = typer.Typer(
    cls=_Root,
    no_args_is_help=True,
    add_completion=False,
    help=DESCRIPTION,
    pretty_exceptions_enable=False,
)


def _command_modules() -> list[str]:
    """The built-in command modules, then those of installed packages (entry points)."""
    from importlib.metadata import entry_points

    return [*COMMAND_MODULES, *(point.value for point in entry_points(group=ENTRY_POINT_GROUP))]


def register_commands(typer_app: typer.Typer) -> None:
    """Every command module's commands on `typer_app`, with the help conventions of `Command`."""
    for name in _command_modules():
        importlib.import_module(name).register(typer_app)
    use_command_class(typer_app)


def _print_version(value: bool) -> None:
    """`--version`: floebreak's version and what results depend on (libraries, BLAS kernels), for reports."""
    if not value:
        return
    import numpy  # noqa: F401  (loads numpy's BLAS)
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS, which the field packing uses)

    from floebreak.io.provenance import floebreak_version, library_versions

    console.print(f"floebreak {floebreak_version()}", highlight=False)
    for name, version in library_versions().items():
        console.print(f"  {name} {version}", highlight=False, soft_wrap=True)
    raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            callback=_print_version,
            is_eager=True,
            help="Print floebreak's version, the library versions and BLAS kernels results depend on.",
        ),
    ] = False,
) -> None:
    """floebreak: ship bow breaking sea-ice floes, and the cusps' propeller–ice loads."""


def main(engine_loaded=None) -> None:
    """The command line (the console command reaches it through `floebreak.__main__`). A user error
    (InputError) prints one line naming the field and exits with code 2. `engine_loaded()`, if given, is
    called once a run's engine is imported, before it runs (passed to the commands as the context's `obj`)."""
    from floebreak.io.storage import StorageError

    try:
        # Ctrl-C raises KeyboardInterrupt from here, reported below (`floebreak.__main__`: while loading)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        app(obj=engine_loaded)
    except InputError as error:
        err_console.print(f"[bold red]error:[/] {escape(str(error))}", soft_wrap=True, highlight=False)
        sys.exit(EXIT_INPUT)
    except StorageError as error:
        err_console.print(f"[bold red]error:[/] {escape(error.strerror)}", soft_wrap=True, highlight=False)
        sys.exit(EXIT_STORAGE)
    except KeyboardInterrupt:
        _report_interrupt()
    except Exception as error:  # a bug, a machine's storage problem, or Ctrl-C inside a library
        from floebreak.app.unexpected import report_unexpected

        code = report_unexpected(error, err_console)
        if code is None:
            _report_interrupt()
        sys.exit(code)
    except SystemExit as exit_:
        if exit_.code == EXIT_INTERRUPTED:  # typer turns a KeyboardInterrupt into exit code 130, silently
            _report_interrupt()
        raise


def _report_interrupt() -> None:
    message, code = interruption()  # Ctrl-C's, or SIGTERM's (`floebreak.__main__`)
    err_console.print(message, highlight=False)
    sys.exit(code)


register_commands(app)
