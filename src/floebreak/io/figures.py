"""Write matplotlib figures atomically (temporary name, then rename)."""

from __future__ import annotations

import os
from collections.abc import Mapping
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
