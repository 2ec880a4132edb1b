"""The pose recorder of a run that stops stuck (`floebreak.output.pose_file.PoseRecorder.finish`): such a run
ends before its planned last step, after one more interval of ice motion, and poses.parquet must
end where the ice ended (the outlines of pieces.parquet), not at the last multiple of the pose interval."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

import floebreak
from floebreak.config.scenario import Scenario
from floebreak.engine.loop import StepDone
from floebreak.io.poses import read_poses

INTERVAL = 8
# the regression's stored field (150 m × 50 m of reference floes), not one generated here: how a field is
# packed depends on the CPU's BLAS kernels, and on some CPUs a generated 50 m field let this ship through
STORED_FIELD = Path(__file__).parents[1] / "regression" / "data" / "field.parquet"
# a light, weak ship (0.1 kt of displacement, 0.1 kN bollard pull): it spends its kinetic energy pushing the
# floes and stops within the field, between two pose steps
WEAK_SHIP = [
    f"field.file={str(STORED_FIELD)!r}",
    "simulation.ice_motion=dynamic",
    f"simulation.pose_interval_steps={INTERVAL}",
    "ship.propulsion.model=bollard_pull",
    "ship.propulsion.displacement_kg=1e5",
    "ship.propulsion.bollard_pull_n=1e2",
    "ship.propulsion.open_water_speed_m_s=8.23",
]


@pytest.fixture(scope="module")
def stuck(tmp_path_factory):
    motions = []

    def keep(event):
        if isinstance(event, StepDone) and not motions:
            motions.append(event.ice_motion)

    result = floebreak.run(Scenario.reference(WEAK_SHIP), callbacks=[keep])
    folder = tmp_path_factory.mktemp("stuck") / "run"
    result.write(folder, figures=False, report=False)
    return result, motions[0], read_poses(folder / "poses.parquet")


def test_the_run_stops_stuck_between_two_pose_steps(stuck):
    result, _, _ = stuck
    sim = result.simulation
    assert sim.surge.stuck
    assert (sim.n_steps - 1) % INTERVAL != 0  # the last step is not one the interval records anyway


def test_the_last_poses_are_where_the_ice_ended(stuck):
    """Every piece in the engine at the end that has moved: its last recorded pose (poses are kept when
    they change) equals its body's pose and rebuilds (entry outline turned by the angle about the entry
    centroid, moved to the centroid) the polygon the run left for it; the pieces that moved in the last
    interval have it at the run's last step."""
    result, motion, (outlines, pieces, poses, _) = stuck
    sim = result.simulation
    engine = motion.engine
    row_of = {int(pid): row for row, pid in enumerate(pieces["piece_id"])}
    checked, at_last_step = 0, 0
    for pid in engine.piece_ids():
        x, y, angle = engine.pose(pid)
        if (x, y) == motion.origin[pid] and angle == 0.0:
            continue  # never moved: no pose
        row = row_of[pid]
        k = np.flatnonzero(poses["row"] == row)[-1]
        assert poses["step"][k] <= sim.n_steps - 1
        at_last_step += int(poses["step"][k] == sim.n_steps - 1)
        assert (poses["x_m"][k], poses["y_m"][k], poses["angle_rad"][k]) == (x, y, angle)
        entry = (pieces["entry_x_m"][row], pieces["entry_y_m"][row])
        moved = shapely.affinity.rotate(outlines[row], angle, entry, use_radians=True)
        moved = shapely.affinity.translate(moved, x - entry[0], y - entry[1])
        assert shapely.hausdorff_distance(moved, sim.polygons([pid])[0]) < 1e-6
        checked += 1
    assert checked > 0 and at_last_step > 0


def test_each_piece_has_one_pose_per_step(stuck):
    _, _, (_, _, poses, _) = stuck
    pairs = set(zip(poses["row"].tolist(), poses["step"].tolist(), strict=True))
    assert len(pairs) == len(poses["row"])
