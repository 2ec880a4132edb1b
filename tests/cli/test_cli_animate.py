"""`floebreak animate DIR`: a GIF Pillow can read with the expected frames; bad input exits with code 2 and
writes nothing; a failure while drawing leaves no file."""

from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path

import pytest
from PIL import Image

import floebreak

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """A small run: the three single floes of examples/single_floe.toml (≈ 560 bow steps)."""
    out = tmp_path_factory.mktemp("animate") / "run"
    floebreak.run(EXAMPLES / "single_floe.toml").write(out, figures=False, report=False)
    return out


def _listing(folder: Path) -> dict[str, int]:
    return {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}


def test_animate_writes_a_gif_with_the_expected_frames(run_dir, tmp_path, cli):
    n_steps = json.loads((run_dir / "summary.json").read_text())["n_steps"]
    every, fps = 40, 5
    out = tmp_path / "transit.gif"
    code, stdout, err = cli(
        "animate",
        str(run_dir),
        "--out",
        str(out),
        "--every",
        str(every),
        "--fps",
        str(fps),
    )
    assert code == 0, err
    # frames at steps 0, 40, 80, … plus the last step when the stride misses it
    expected = math.ceil(n_steps / every) + (1 if (n_steps - 1) % every else 0)
    with Image.open(out) as image:
        assert image.format == "GIF"
        assert image.n_frames == expected
        assert image.info["duration"] == 1000 / fps
        assert image.size[0] == 800
    assert f"{expected} frames" in stdout
    assert [p.name for p in tmp_path.iterdir()] == ["transit.gif"]  # no temporary leftovers


def test_default_output_is_in_the_run_directory(run_dir, cli):
    before = _listing(run_dir)
    code, _, err = cli("animate", str(run_dir), "--every", "200", "--quiet")
    assert code == 0, err
    try:
        assert set(_listing(run_dir)) == set(before) | {"animation.gif"}
        with Image.open(run_dir / "animation.gif") as image:
            assert image.n_frames == 4  # steps 0, 200, 400 and the last (n_steps ≈ 560)
        # an existing animation is refused without --overwrite, and left as it was
        stamp = (run_dir / "animation.gif").stat().st_mtime_ns
        code, _, err = cli("animate", str(run_dir), "--every", "200", "--quiet")
        assert code == 2 and "--overwrite" in err
        assert (run_dir / "animation.gif").stat().st_mtime_ns == stamp
    finally:
        (run_dir / "animation.gif").unlink()


@pytest.fixture
def old_run_dir(run_dir, tmp_path):
    """A run directory of an older version: no pieces.parquet."""
    old = tmp_path / "old"
    shutil.copytree(run_dir, old)
    (old / "pieces.parquet").unlink()
    return old


@pytest.mark.parametrize(
    ("case", "args", "field"),
    [
        ("missing", [], "run_dir"),
        ("old", [], "pieces.parquet"),
        ("corrupt", [], "run_dir"),
        ("ok", ["--fps", "0"], "fps"),
        ("ok", ["--every", "0"], "every"),
        ("ok", ["--format", "avi"], "format"),
        ("ok", ["--out", "{tmp}/a.mp4", "--format", "gif"], "out"),
        ("ok", ["--out", "{tmp}/a.webm"], "out"),
        ("ok", ["--out", "{tmp}/no/such/dir/a.gif"], "out"),
    ],
)
def test_bad_input_exits_2_and_writes_nothing(case, args, field, run_dir, old_run_dir, tmp_path, cli):
    target = {"missing": tmp_path / "nope", "old": old_run_dir, "ok": run_dir}.get(case)
    if case == "corrupt":
        target = tmp_path / "corrupt"
        shutil.copytree(run_dir, target)
        (target / "pieces.parquet").write_bytes(b"not parquet")
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    before_run = _listing(target) if target.exists() else None
    before_tmp = _listing(tmp_path)
    code, _, err = cli("animate", str(target), *args)
    assert code == 2
    assert field in err
    if case == "old":
        assert "re-run" in err
    assert _listing(tmp_path) == before_tmp
    if before_run is not None:
        assert _listing(target) == before_run


def test_mp4_without_ffmpeg_is_a_clear_error(run_dir, tmp_path, monkeypatch, cli):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    before = _listing(run_dir)
    code, _, err = cli("animate", str(run_dir), "--format", "mp4")
    assert code == 2 and "ffmpeg" in err and "format" in err
    code, _, err = cli("animate", str(run_dir), "--out", str(tmp_path / "a.mp4"))
    assert code == 2 and "ffmpeg" in err
    assert _listing(run_dir) == before and list(tmp_path.iterdir()) == []


@pytest.fixture
def ffmpeg_on_path(tmp_path_factory, monkeypatch):
    """An ffmpeg executable on PATH: the static binary of the `imageio-ffmpeg` wheel (a dev dependency),
    linked as ``ffmpeg`` in a folder of its own."""
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    folder = tmp_path_factory.mktemp("ffmpeg-bin")
    (folder / "ffmpeg").symlink_to(imageio_ffmpeg.get_ffmpeg_exe())
    monkeypatch.setenv("PATH", f"{folder}{os.pathsep}{os.environ.get('PATH', '')}")
    return imageio_ffmpeg


def test_animate_writes_an_mp4_with_ffmpeg(run_dir, tmp_path, ffmpeg_on_path, cli):
    n_steps = json.loads((run_dir / "summary.json").read_text())["n_steps"]
    every, fps = 40, 5
    out = tmp_path / "transit.mp4"
    code, stdout, err = cli("animate", str(run_dir), "--out", str(out), "--every", str(every),
        "--fps", str(fps),
    )  # fmt: skip
    assert code == 0, err
    expected = math.ceil(n_steps / every) + (1 if (n_steps - 1) % every else 0)
    assert f"{expected} frames" in stdout
    assert out.read_bytes()[4:8] == b"ftyp"  # an ISO base media (MP4) file
    frames, seconds = ffmpeg_on_path.count_frames_and_secs(str(out))  # decoded by ffmpeg itself
    assert frames == expected
    assert seconds == pytest.approx(expected / fps, abs=1.0 / fps)
    assert [p.name for p in tmp_path.iterdir()] == ["transit.mp4"]  # no temporary leftovers


def test_a_failure_while_drawing_leaves_no_file(run_dir, tmp_path, monkeypatch):
    from floebreak.app.replay import animate_run_directory
    from floebreak.plotting.animation import TransitFigure

    calls = []

    def failing_draw(self, step):
        calls.append(step)
        if len(calls) == 3:
            raise RuntimeError("boom")
        return {"cusps": 0, "flipped": 0}

    monkeypatch.setattr(TransitFigure, "draw", failing_draw)
    with pytest.raises(RuntimeError, match="boom"):
        animate_run_directory(run_dir, tmp_path / "a.gif", every=50)
    assert list(tmp_path.iterdir()) == []
