"""Write matplotlib figures atomically (temporary name, then rename)."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path

from floebreak.io.atomic import atomic_path


def save_figure(
    figure,
    path: str | os.PathLike[str],
    field: str = "figure",
    dpi: int = 150,
    metadata: Mapping[str, str] | None = None,
) -> Path:
    """Save `figure` to `path` (format from the suffix, PNG by default) without leaving partial files;
    `metadata` goes to ``Figure.savefig`` (PNG text chunks, e.g. ``Software``, ``Description``)."""
    path = Path(path)
    file_format = path.suffix.lstrip(".") or "png"
    with atomic_path(path, field=field) as temp:
        figure.savefig(temp, format=file_format, dpi=dpi, metadata=dict(metadata) if metadata else None)
    return path


def save_figures(
    figures: Mapping[str, object],
    folder: Path,
    progress: Callable[[str, int, int], None] | None = None,
    done: int = 0,
    total: int | None = None,
) -> None:
    """Save each of `figures` (file name → Figure) in the new directory `folder`; `progress(stage, done,
    total)`, if given, is told after each one, counting on from `done` (`total`: default done + figures)."""
    folder.mkdir()
    total = done + len(figures) if total is None else total
    for name, figure in figures.items():
        save_figure(figure, folder / name)
        done += 1
        if progress is not None:
            progress(f"figure {name}", done, total)
