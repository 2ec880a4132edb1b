"""TOML parsing with a bound on nesting: Python's `tomllib` parses nested arrays and inline tables by
recursion, so a file nested a few thousand levels deep ends in a RecursionError. No floebreak file needs
more than a handful of levels; deeper ones are refused with an InputError naming the file."""

from __future__ import annotations

import tomllib
from typing import Any

from floebreak.errors import InputError

# the deepest floebreak file (a study's [vary] lists of tables inside tables) uses about five levels
MAX_TOML_DEPTH = 32


def _too_deep(field: str, source: str) -> InputError:
    where = f"{source}: " if source else ""
    return InputError(
        field,
        f"{where}arrays or tables nested more than {MAX_TOML_DEPTH} levels deep",
        allowed=f"at most {MAX_TOML_DEPTH} levels of nesting",
    )


def _depth(value: Any) -> int:
    """The nesting depth of parsed TOML data (iterative: the data may be deep)."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        item, level = stack.pop()
        deepest = max(deepest, level)
        children = item.values() if isinstance(item, dict) else item if isinstance(item, list) else ()
        stack.extend((child, level + 1) for child in children if isinstance(child, dict | list))
    return deepest


def loads_toml(text: str, field: str, source: str = "") -> dict[str, Any]:
    """`tomllib.loads(text)`, its TOMLDecodeError passed on; nesting deeper than `MAX_TOML_DEPTH` (or deep
    enough to exhaust Python's recursion) is an InputError naming `field` and the file `source`."""
    try:
        data = tomllib.loads(text)
    except RecursionError:
        raise _too_deep(field, source) from None
    if _depth(data) > MAX_TOML_DEPTH:
        raise _too_deep(field, source)
    return data
