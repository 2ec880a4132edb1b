"""Strict JSON from floebreak's data: the one sanitiser for summaries, provenance and file metadata."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np


def jsonable(value: Any) -> Any:
    """`value` with numpy scalars and arrays as Python numbers and lists, paths as strings, mapping keys as
    strings and non-finite floats (NaN, ±inf) as None (strict JSON has no NaN), recursively."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, Path):
        return str(value)
    return value


def to_json(value: Any, **kwargs: Any) -> str:
    """``json.dumps`` of `jsonable(value)`, keys sorted unless `kwargs` say otherwise; raises on NaN left."""
    return json.dumps(jsonable(value), **{"sort_keys": True, "allow_nan": False, **kwargs})
