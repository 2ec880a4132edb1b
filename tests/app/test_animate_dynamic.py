"""Moving ice replayed: `simulation.pose_interval_steps` records the moved pieces' poses
into poses.parquet without changing the run; `floebreak animate` draws a dynamic run from them and refuses a
dynamic run without them (exit code 2, nothing written)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import shapely
from PIL import Image

import floebreak
from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.io.poses import read_poses
from floebreak.plotting.animation import PieceMotion

INTERVAL = 10
SHORT = ["field.length_m=50", "simulation.ice_motion=dynamic"]  # the reference observation's floes


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The same short dynamic run with poses recorded every `INTERVAL` steps and without."""
    folder = tmp_path_factory.mktemp("dynamic")
    with_poses = floebreak.run(Scenario.reference([*SHORT, f"simulation.pose_interval_steps={INTERVAL}"]))
    without = floebreak.run(Scenario.reference(SHORT))
    with_poses.write(folder / "poses", figures=False, report=False)
    without.write(folder / "plain", figures=False, report=False)
    return {"with": with_poses, "without": without, "dir": folder / "poses", "plain_dir": folder / "plain"}


def _listing(folder):
    return {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}


def test_recording_poses_does_not_change_the_run(runs):
    a, b = runs["with"].simulation, runs["without"].simulation
    assert np.array_equal(a.fate, b.fate)
    assert all(pa.equals_exact(pb, 0.0) for pa, pb in zip(a.polygons(), b.polygons(), strict=True))
    assert runs["without"].poses is None
    assert not (runs["plain_dir"] / "poses.parquet").exists()


def test_the_last_pose_rebuilds_the_outline_the_engine_left(runs):
    """A piece in the field at the end whose pose was recorded at the last step: its entry outline, rotated
    by the recorded angle about the entry centroid and moved to the recorded centroid, is its final
    polygon (written by the engine from its own body state)."""
    sim = runs["with"].simulation
    outlines, pieces, poses, meta = read_poses(runs["dir"] / "poses.parquet")
    assert meta["pose_interval_steps"] == INTERVAL
    assert set(np.unique(poses["step"])) <= set(range(0, sim.n_steps, INTERVAL)) | {sim.n_steps - 1}
    checked = 0
    for row in range(len(outlines)):
        mine = np.flatnonzero(poses["row"] == row)
        assert np.all(np.diff(poses["step"][mine]) > 0)
        k = mine[-1]
        pid = pieces["piece_id"][row]
        if poses["step"][k] != sim.n_steps - 1 or sim.fate[pid] != "remaining":
            continue
        entry = (pieces["entry_x_m"][row], pieces["entry_y_m"][row])
        moved = shapely.affinity.rotate(outlines[row], poses["angle_rad"][k], entry, use_radians=True)
        moved = shapely.affinity.translate(moved, poses["x_m"][k] - entry[0], poses["y_m"][k] - entry[1])
        assert shapely.hausdorff_distance(moved, sim.polygons([pid])[0]) < 1e-6
        checked += 1
    assert checked > 0


def test_animate_a_dynamic_run_frames_at_the_recorded_steps(runs, tmp_path, cli):
    n_steps = json.loads((runs["dir"] / "summary.json").read_text())["n_steps"]
    out = tmp_path / "moving.gif"
    code, stdout, err = cli("animate", str(runs["dir"]), "--out", str(out), "--every", "20")
    assert code == 0, err
    expected = math.ceil(n_steps / 20) + (1 if (n_steps - 1) % 20 else 0)  # 0, 20, 40, … and the last
    with Image.open(out) as image:
        assert image.format == "GIF" and image.n_frames == expected
    assert f"{expected} frames" in stdout
    assert [p.name for p in tmp_path.iterdir()] == ["moving.gif"]


@pytest.mark.parametrize(("which", "args", "words"), [
    ("plain_dir", [], ["poses.parquet", "pose_interval_steps"]),  # dynamic, poses not recorded
    ("dir", ["--every", "15"], ["every", "multiple of 10"]),  # between two recorded steps
])  # fmt: skip
def test_bad_input_exits_2_and_writes_nothing(runs, which, args, words, tmp_path, cli):
    before, before_tmp = _listing(runs[which]), _listing(tmp_path)
    code, _, err = cli("animate", str(runs[which]), "--out", str(tmp_path / "a.gif"), *args)
    assert code == 2
    assert all(word in err for word in words), err
    assert _listing(runs[which]) == before and _listing(tmp_path) == before_tmp


def test_poses_of_static_ice_are_refused():
    with pytest.raises(InputError, match="pose_interval_steps"):
        floebreak.run(Scenario.reference(["field.length_m=50", "simulation.pose_interval_steps=5"]))


def test_outlines_at_a_pose():
    """A 2 m × 1 m rectangle entering with its centroid at (10, 0), recorded at step 5 turned by 90° and moved
    to (12, 3): before step 5 it is where it entered, from step 5 on its long side lies along y."""
    rectangle = np.array([[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]])
    motion = PieceMotion(
        piece_index=np.array([7]),
        ring_xy_m=(rectangle,),
        entry_xy_m=np.array([[10.0, 0.0]]),
        pose_row=np.array([0]),
        pose_step=np.array([5]),
        pose_xy_m=np.array([[12.0, 3.0]]),
        pose_angle_rad=np.array([math.pi / 2]),
        interval_steps=5,
    )
    np.testing.assert_allclose(motion.outlines_at(4)[7], rectangle + np.array([10.0, 0.0]))
    # (x, y) turned by +90° is (−y, x)
    expected = np.array([[12.5, 2.0], [12.5, 4.0], [11.5, 4.0], [11.5, 2.0]])
    np.testing.assert_allclose(motion.outlines_at(5)[7], expected, atol=1e-12)
    np.testing.assert_allclose(motion.outlines_at(9)[7], expected, atol=1e-12)
    r = math.hypot(1.0, 0.5)  # the rectangle's largest radius
    assert motion.extent_m() == pytest.approx((12.0 - r, 3.0 - r, 12.0 + r, 3.0 + r))
