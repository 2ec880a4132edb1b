"""Write matplotlib figures atomically (temporary name, then rename)."""

from __future__ import annotations

import os
from pathlib import Path

from floebreak.io.atomic import atomic_path


def save_figure(figure, path: str | os.PathLike[str], field: str = "figure", dpi: int = 150) -> Path:
    """Save `figure` to `path` (format from the suffix, PNG by default) without leaving partial files."""
    path = Path(path)
    file_format = path.suffix.lstrip(".") or "png"
    with atomic_path(path, field=field) as temp:
        figure.savefig(temp, format=file_format, dpi=dpi)
    return path
