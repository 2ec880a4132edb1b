"""Figures of the propeller and shaft analyses as plain data (`floebreak.output.figure_process.FigureCall`:
a module of `floebreak.plotting`, its function and the arguments), drawn here or by the figure workers the
command line forks (`floebreak.output.run_directory.figure_worker`) while the tables are written."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any


def drawn(calls: Mapping[str, Any]) -> dict[str, Any]:
    """The figures of `calls` (file name → `FigureCall`) drawn here (file name → matplotlib Figure)."""
    from floebreak.output.figure_process import draw_figure

    return {name: draw_figure(call) for name, call in calls.items()}


def figures_in_worker(calls: Mapping[str, Any], worker: Any) -> Callable[[Path], AbstractContextManager]:
    """The io writers' `figures_alongside`: `calls` drawn into the figures folder by the figure `worker`
    while the tables are written (`floebreak.output.run_directory.figures_drawn_alongside`)."""
    from floebreak.output.figure_process import figures_drawn_alongside

    return lambda folder: figures_drawn_alongside(calls, folder, worker)
