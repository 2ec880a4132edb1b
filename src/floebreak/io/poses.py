"""``poses.parquet``: the poses of the pieces the ice motion moved (``simulation.pose_interval_steps``), for
replaying a `dynamic` run (``floebreak animate``).

GeoParquet (`floebreak.io.geoparquet`), one row per piece that moved: ``geometry`` its outline where it
entered the rigid-body engine (field frame), ``piece_id``, ``entry_x_m``/``entry_y_m`` (its centroid there),
and one list per piece of its recorded poses, in step order: ``step``, ``x_m``, ``y_m`` (centroid),
``angle_rad`` (rotation from the entry outline, counter-clockwise). The outline at a pose is the entry outline
rotated by ``angle_rad`` about the entry centroid and moved to (``x_m``, ``y_m``). Written atomically.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from floebreak.errors import InputError
from floebreak.io.geoparquet import arrow_array, read_geoparquet, write_geoparquet

POSES_FILE = "poses.parquet"
PIECE_COLUMNS = ("piece_id", "entry_x_m", "entry_y_m")
POSE_COLUMNS = ("step", "x_m", "y_m", "angle_rad")


def write_poses(
    path: str | os.PathLike[str],
    entry_outlines: np.ndarray,
    pieces: Mapping[str, np.ndarray],
    poses: Mapping[str, np.ndarray],
    metadata: Mapping[str, Any],
) -> Path:
    """Write ``poses.parquet``. `pieces`: `PIECE_COLUMNS`, one value per entry outline; `poses`: flat
    `POSE_COLUMNS` plus ``row`` (the piece's row in `pieces`), sorted by row, then step."""
    row = np.asarray(poses["row"], dtype=np.int64)
    if np.any(np.diff(row) < 0):
        raise ValueError("poses must be sorted by piece row")
    offsets = np.searchsorted(row, np.arange(len(entry_outlines) + 1)).astype(np.int32)
    lists = {
        name: pa.ListArray.from_arrays(pa.array(offsets), arrow_array(np.asarray(poses[name])))
        for name in POSE_COLUMNS
    }
    columns = {name: np.asarray(pieces[name]) for name in PIECE_COLUMNS}
    return write_geoparquet(path, np.asarray(entry_outlines, dtype=object), columns | lists, metadata)


def read_poses(
    path: str | os.PathLike[str], field: str = "run_dir"
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray], dict[str, Any]]:
    """(entry outlines, piece columns, flat pose columns with ``row``, metadata) of a ``poses.parquet``;
    InputError naming `field` for a file that is not one."""
    outlines, columns, metadata = read_geoparquet(path, field=field)
    missing = [name for name in (*PIECE_COLUMNS, *POSE_COLUMNS) if name not in columns]
    if missing:
        raise InputError(field, f"{str(path)!r} lacks the columns {missing}", allowed="a poses.parquet file")
    lengths = np.array([len(item) for item in columns["step"]], dtype=np.int64)
    poses = {"row": np.repeat(np.arange(len(outlines)), lengths)}
    for name in POSE_COLUMNS:
        items = [np.asarray(item) for item in columns[name]]
        dtype = np.int64 if name == "step" else float
        poses[name] = np.concatenate(items).astype(dtype) if items else np.zeros(0, dtype=dtype)
    pieces = {name: np.asarray(columns[name]) for name in PIECE_COLUMNS}
    return outlines, pieces, poses, metadata
