"""What every command module shares: the help conventions of commands and groups, the consoles, a stage's
progress bar."""

from __future__ import annotations

import re
from contextlib import contextmanager

import typer
import typer.core
from rich.console import Console
from rich.markup import escape

from floebreak.errors import InputError


class HelpConventions:
    """Every floebreak command's and group's help: texts printed as written (units such as [m] escaped, not
    read as rich markup), arguments named in capitals (RUN_OR_STUDY_DIR, LOG) without the braces typer
    puts around required ones in the usage line, and flags without a `<bool>` type."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.help = None if self.help is None else escape(self.help)
        for param in self.params:
            if getattr(param, "help", None):
                param.help = escape(param.help)

    def get_params(self, ctx):
        params = super().get_params(ctx)
        for param in params:
            if isinstance(param, typer.core.TyperArgument) and param.metavar is None:
                param.metavar = param.name.upper()
            elif getattr(param, "is_flag", False) and param.metavar is None:
                param.metavar = ""
        return params

    def collect_usage_pieces(self, ctx) -> list[str]:
        return [re.sub(r"^\{(.*)\}$", r"\1", piece) for piece in super().collect_usage_pieces(ctx)]


class Command(HelpConventions, typer.core.TyperCommand):
    pass


class Group(HelpConventions, typer.core.TyperGroup):
    pass


def use_command_class(typer_app: typer.Typer) -> None:
    """`Command` for every command of `typer_app` registered without a class of its own."""
    for info in typer_app.registered_commands:
        if info.cls in (None, typer.core.TyperCommand):
            info.cls = Command


console = Console()


err_console = Console(stderr=True)


def parse_floats(text: str | None, field: str) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        return tuple(float(v) for v in text.replace(";", ",").split(",") if v.strip())
    except ValueError:
        raise InputError(field, f"{text!r} is not a comma-separated list of numbers") from None


@contextmanager
def stage_progress(label: str, quiet: bool = False):
    """A transient progress bar on stderr for a stage longer than about 2 s whose function takes a plain
    `progress(stage, done, total)` callback: `generate_field` (placement rounds; large fields take
    minutes), the shaft cases, the propeller analysis and the writing of its files and figures."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=err_console, transient=True, disable=quiet) as bar:
        task = bar.add_task(label, total=None)

        def progress(stage: str, done: int, total: int) -> None:
            bar.update(task, description=f"{label}: {stage}", completed=done, total=total or None)

        yield progress
