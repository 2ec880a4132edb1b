"""The floebreak command line: a thin typer layer over the public functions."""

from __future__ import annotations

import sys

import typer
from rich.console import Console
from rich.table import Table

from floebreak.errors import InputError
from floebreak.ice.observations import thesis_observations

app = typer.Typer(no_args_is_help=True, add_completion=False, help=__doc__)
console = Console()
err_console = Console(stderr=True)


@app.command()
def observations() -> None:
    """Print the built-in ice observations (thesis Table 1, expedition Agu19/20)."""
    table = Table(title="Ice observations Agu19/20 (thesis Table 1); diameter shares are % of floe count")
    table.add_column("key")
    table.add_column(r"concentration \[%]", justify="right")
    table.add_column(r"mean thickness \[m]", justify="right")
    table.add_column(r"diameter class \[m]: share of floes \[%]")
    for key, obs in thesis_observations().items():
        shares = ", ".join(
            f"{d:g}: {p:g}" for d, p in zip(obs.diameter_classes_m, obs.percentages, strict=True)
        )
        table.add_row(key, f"{100 * obs.concentration:g}", f"{obs.mean_thickness_m:g}", shares)
    console.print(table)


@app.callback()
def _root() -> None:
    """floebreak: ship bow breaking sea-ice floes, and the cusps' propeller–ice loads."""


def main() -> None:
    """Entry point. A user error (InputError) prints one line naming the field and exits with code 2."""
    try:
        app()
    except InputError as error:
        err_console.print(f"[bold red]error:[/] {error}")
        sys.exit(2)
