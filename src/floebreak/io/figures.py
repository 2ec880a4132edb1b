"""Write matplotlib figures atomically (temporary name, then rename)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from floebreak.io.atomic import atomic_path


def savefig(figure, target, *, dpi: float, **kwargs: Any) -> None:
    """``figure.savefig(target, dpi=dpi, **kwargs)`` with one draw instead of two, same pixels.

    With a layout engine (such as constrained layout) ``savefig`` draws the whole figure once
    without output to run the layout, then again for the file. Here the engine runs once at the output
    dpi, the figure is saved without it (one draw), and the engine is put back.
    """
    engine = figure.get_layout_engine()
    if engine is None or not figure.axes:
        figure.savefig(target, dpi=dpi, **kwargs)
        return
    screen_dpi = figure.dpi
    figure.dpi = dpi  # text extents, hence the layout, depend on the dpi
    try:
        engine.execute(figure)
    finally:
        figure.dpi = screen_dpi
    figure.set_layout_engine(None)
    try:
        figure.savefig(target, dpi=dpi, **kwargs)
    finally:
        figure.set_layout_engine(engine)


def save_figure(figure, path: str | os.PathLike[str], field: str = "figure", dpi: int = 150) -> Path:
    """Save `figure` to `path` (format from the suffix, PNG by default) without leaving partial files."""
    path = Path(path)
    file_format = path.suffix.lstrip(".") or "png"
    with atomic_path(path, field=field) as temp:
        savefig(figure, temp, format=file_format, dpi=dpi)
    return path
