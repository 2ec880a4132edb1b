"""Reading a user's text file (CSV, TOML) or a file shipped in `floebreak.data`, for the parsers of the
computing packages: they take the text, the io layer touches the file system (docs/architecture.md)."""

from __future__ import annotations

import importlib.resources
import os
from pathlib import Path

from floebreak.errors import InputError


def read_text_file(path: str | os.PathLike[str], field: str, encoding: str = "utf-8") -> str:
    """The text of the file `path`; a missing or unreadable file (or one not in `encoding`) is an
    InputError on `field` naming the path."""
    path = Path(path)
    try:
        return path.read_text(encoding=encoding)
    except FileNotFoundError:
        raise InputError(field, f"file {str(path)!r} does not exist", value=str(path)) from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(field, f"cannot read {str(path)!r}: {error}", value=str(path)) from None


def package_data_path(name: str) -> Path:
    """The path of the file `name` shipped in `floebreak.data`."""
    return Path(str(importlib.resources.files("floebreak.data").joinpath(name)))


def read_package_data(name: str) -> str:
    """The text (UTF-8) of the file `name` shipped in `floebreak.data`."""
    return importlib.resources.files("floebreak.data").joinpath(name).read_text(encoding="utf-8")
