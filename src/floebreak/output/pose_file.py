"""Recording the pieces' poses of a `dynamic` run (``simulation.pose_interval_steps = K``)
and writing them (``poses.parquet``, `floebreak.io.poses`).

`PoseRecorder` is a callback of the stepping loop: after every K-th step (0, K, 2K, …) and after the last,
it reads the rigid-body engine of the run (`StepDone.ice_motion`; nothing is changed there) and keeps, for
each piece in the engine that has moved from where it entered, its pose (centroid, rotation) when that
differs from the pose last kept; the first time a piece is kept, also its outline where it entered. A run
that stops stuck ends before its planned last step, after one more interval of ice motion (the one in which
the ship stopped): `finish` keeps the poses the ice ended in, as those of the run's last step (the outlines
of ``pieces.parquet``). The physics never sees the recorder: a run with it gives the same results as one
without.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import shapely

from floebreak.engine.loop import RunStarted, StepDone
from floebreak.errors import InputError
from floebreak.io.poses import POSE_COLUMNS, POSES_FILE, write_poses
from floebreak.output.record import RunRecord


class PoseRecorder:
    """Callback keeping the moved pieces' poses every `interval_steps` steps (module docstring)."""

    def __init__(self, interval_steps: int):
        self.interval_steps = int(interval_steps)
        self.n_steps = 0
        self._last: dict[int, tuple[float, float, float]] = {}
        self._entry: dict[int, tuple[shapely.Polygon, float, float]] = {}
        self._rows: list[tuple[int, int, float, float, float]] = []  # piece, step, x, y, angle
        self._motion = None  # the run's `IceMotion`, as the last step reported it

    def __call__(self, event) -> None:
        if isinstance(event, RunStarted):
            self.n_steps = event.n_steps
        elif isinstance(event, StepDone) and event.ice_motion is not None:
            self._motion = event.ice_motion
            if event.step % self.interval_steps == 0 or event.step == self.n_steps - 1:
                self._record(event.step, event.ice_motion)

    def finish(self, n_steps: int) -> None:
        """After the run (`n_steps`: the steps it made): if it stopped stuck, the poses the ice ended in
        replace those kept at its last step, n_steps − 1 (the steps after it were never reached)."""
        motion = self._motion
        if motion is None or not motion.stuck or n_steps < 1:
            return
        last = n_steps - 1
        self._rows = [row for row in self._rows if row[1] != last]
        self._last = {row[0]: tuple(row[2:]) for row in self._rows}  # rows are in step order
        self._record(last, motion)

    def _record(self, step: int, motion) -> None:
        engine = motion.engine
        for pid in engine.piece_ids():
            x, y, angle = pose = engine.pose(pid)
            x0, y0 = motion.origin[pid]
            if ((x, y) == (x0, y0) and angle == 0.0) or self._last.get(pid) == pose:
                continue
            if pid not in self._entry:  # the outline now, turned back by the angle about the centroid
                outline = shapely.affinity.rotate(engine.polygon(pid), -angle, (x, y), use_radians=True)
                self._entry[pid] = (shapely.affinity.translate(outline, x0 - x, y0 - y), x0, y0)
            self._last[pid] = pose
            self._rows.append((pid, step, x, y, angle))

    @property
    def n_poses(self) -> int:
        return len(self._rows)

    def tables(self) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]:
        """(entry outlines, piece columns, flat pose columns with ``row``), pieces by id, poses by piece
        and step: the layout `floebreak.io.poses.write_poses` takes."""
        ids = np.array(sorted(self._entry), dtype=np.int64)
        row_of = {pid: row for row, pid in enumerate(ids.tolist())}
        outlines = np.array([self._entry[pid][0] for pid in ids.tolist()], dtype=object)
        pieces = {
            "piece_id": ids,
            "entry_x_m": np.array([self._entry[pid][1] for pid in ids.tolist()], dtype=float),
            "entry_y_m": np.array([self._entry[pid][2] for pid in ids.tolist()], dtype=float),
        }
        rows = sorted(self._rows, key=lambda r: (row_of[r[0]], r[1]))
        flat = np.array([r[1:] for r in rows], dtype=float).reshape(-1, 4)
        poses = {"row": np.array([row_of[r[0]] for r in rows], dtype=np.int64)}
        poses |= {name: flat[:, k] for k, name in enumerate(POSE_COLUMNS)}
        poses["step"] = poses["step"].astype(np.int64)
        return outlines, pieces, poses


def check_pose_interval(interval_steps: int | None, ice_motion: str) -> None:
    """InputError when poses are asked for from ice that does not move."""
    if interval_steps is not None and ice_motion != "dynamic":
        raise InputError(
            "simulation.pose_interval_steps",
            f"{interval_steps} with simulation.ice_motion = {ice_motion!r}: static pieces have no poses "
            "(floebreak animate replays a static run from pieces.parquet)",
            allowed="simulation.ice_motion = dynamic, or no pose_interval_steps",
        )


def write_poses_file(result: RunRecord, run_dir: str | os.PathLike[str]) -> None:
    """Write ``poses.parquet`` into `run_dir` if the run recorded poses."""
    if result.poses is None:
        return
    outlines, pieces, poses = result.poses.tables()
    sim = result.simulation
    meta = result.provenance("poses") | {
        "pose_interval_steps": result.poses.interval_steps,
        "x_start_m": sim.params.x_start_m,
        "step_m": sim.params.step_m,
        "n_steps": sim.n_steps,
        "angle_convention": "counter-clockwise about the entry centroid [rad]",
    }
    write_poses(Path(run_dir) / POSES_FILE, outlines, pieces, poses, meta)
