"""`floebreak observations`, `schema`, `report` and `animate`: what the package knows and what a run directory
holds, shown or drawn."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
import typer.core
from rich.table import Table

from floebreak.cli.common import console, err_console
from floebreak.cli.options import (
    QuietOption,
)
from floebreak.errors import InputError
from floebreak.ice.observations import thesis_observations


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


def schema(
    format_: Annotated[
        str,
        typer.Option(
            "--format", help="json (the JSON schema), table (every key on screen) or markdown (a key table)"
        ),
    ] = "json",
) -> None:
    """Print every scenario key with its unit, range and default (JSON schema, a table or Markdown)."""
    import json

    from floebreak.config.scenario import json_schema, schema_rows

    if format_ not in SCHEMA_FORMATS:
        raise InputError(
            "format", f"unknown value {format_!r}", value=format_, allowed=", ".join(SCHEMA_FORMATS)
        )
    schema_ = json_schema()
    if format_ == "json":
        typer.echo(json.dumps(schema_, indent=2, ensure_ascii=False))
        return
    rows = schema_rows(schema_)
    columns = ("key", "type", "default", "allowed", "description")
    if format_ == "markdown":
        lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
        lines += ["| " + " | ".join(r[c].replace("|", "\\|") for c in columns) + " |" for r in rows]
        typer.echo("\n".join(lines))
        return
    table = Table(title="scenario keys (the unit in each description's brackets; --format json: the schema)")
    for column in columns:
        table.add_column(column, overflow="fold")
    for row in rows:
        table.add_row(*(row[c] for c in columns))
    console.print(table)


SCHEMA_FORMATS = ("json", "table", "markdown")


def report(
    run_dir: Annotated[Path, typer.Argument(metavar="DIR", help="run directory")],
) -> None:
    """Write DIR/report.html: summary, figures, scenario and provenance on one self-contained page."""
    from floebreak.output.report import write_report

    console.print(f"written: {write_report(run_dir)}", soft_wrap=True)


def animate(
    run_dir: Annotated[Path, typer.Argument(metavar="DIR", help="run directory (floebreak run / demo)")],
    out: Annotated[
        Path | None, typer.Option("--out", help="animation file (default DIR/animation.gif or .mp4)")
    ] = None,
    fps: Annotated[int, typer.Option("--fps", help="frames per second (1 … 60)")] = 10,
    every: Annotated[
        int | None,
        typer.Option(
            "--every",
            help="one frame every K bow steps (default: K for at most 200 frames; a dynamic run: a multiple "
            "of its simulation.pose_interval_steps)",
        ),
    ] = None,
    fmt: Annotated[
        str | None,
        typer.Option("--format", help="gif | mp4 (mp4 needs ffmpeg; default: from --out, else gif)"),
    ] = None,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="replace an existing animation file")
    ] = False,
    quiet: QuietOption = False,
) -> None:
    """Write an animation of the transit (bow advancing, floes breaking, cusps and flipped pieces appearing),
    replayed from DIR/pieces.parquet; the ice of a dynamic run moves, drawn from the poses it recorded
    (DIR/poses.parquet, simulation.pose_interval_steps). Written atomically; nothing written on bad input."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from floebreak.app.replay import animate_run_directory

    progress = Progress(
        TextColumn("frames"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=err_console,
        disable=quiet,
    )
    tasks = []

    def advance(done: int, total: int) -> None:
        if not tasks:  # started with the first frame: bad input fails before, without a bar
            progress.start()
            tasks.append(progress.add_task("frames", total=total))
        progress.update(tasks[0], completed=done)

    try:
        path, n_frames = animate_run_directory(
            run_dir, out, fps=fps, every=every, fmt=fmt, overwrite=overwrite, progress=advance
        )
    finally:
        progress.stop()
    console.print(f"written: {path} ({n_frames} frames at {fps} fps)", soft_wrap=True, highlight=False)


def register(app: typer.Typer) -> None:
    """Add this module's commands to `app`."""
    app.command()(observations)
    app.command()(schema)
    app.command()(report)
    app.command()(animate)
