"""The JSON sanitiser: numpy data, paths and non-finite floats become strict JSON."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from floebreak.io.jsonable import jsonable, to_json


def test_numpy_paths_and_non_finite_floats_become_strict_json():
    value = {
        "n": np.int64(3),
        "x": np.float32(0.5),
        "nan": math.nan,
        "inf": np.float64(-np.inf),
        "array": np.array([[1.0, np.nan], [2.0, 3.0]]),
        "path": Path("a") / "b.toml",
        1: (True, None, "text"),
    }
    expected = {
        "n": 3,
        "x": 0.5,
        "nan": None,
        "inf": None,
        "array": [[1.0, None], [2.0, 3.0]],
        "path": str(Path("a") / "b.toml"),
        "1": [True, None, "text"],
    }
    assert jsonable(value) == expected
    assert json.loads(to_json(value)) == expected
    assert list(json.loads(to_json({"b": 1, "a": 2}))) == ["a", "b"]  # keys sorted by default


def test_to_json_refuses_what_it_cannot_represent():
    with pytest.raises(TypeError):
        to_json({"set": {1, 2}})
