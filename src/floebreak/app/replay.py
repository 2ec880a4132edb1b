"""Replay a run directory as an animation (``floebreak animate DIR``): GIF by default, MP4 with ffmpeg.

Reads ``pieces.parquet`` (every piece with ``created_step``/``ended_step``, written by `floebreak.run`), the
resolved scenario (the bow is rebuilt with `floebreak.app.run.build_bow`, as in the run) and draws the frames
with `floebreak.plotting.animation`. A `dynamic` run's pieces move: its replay needs the poses recorded with
``simulation.pose_interval_steps`` (``poses.parquet``, `floebreak.io.poses`), and its frames fall on the
recorded steps; a dynamic run without them is refused. The file is written under a temporary name and renamed
when complete, so a failure leaves nothing; every input is checked before anything is written.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import shapely

from floebreak.errors import InputError, require_range
from floebreak.io.atomic import atomic_path
from floebreak.io.poses import POSES_FILE, read_poses
from floebreak.plotting.animation import MAX_FRAMES, PieceMotion, Transit, TransitFigure, frame_steps

FORMATS = ("gif", "mp4")
PIECE_COLUMNS = ("piece_id", "parent_piece_id", "fate", "created_step", "ended_step")
RERUN_HINT = "a complete run directory written by this version of floebreak"
Progress = Callable[[int, int], None] | None


def _write_gif(view: TransitFigure, steps: list[int], path: Path, fps: int, progress: Progress) -> None:
    """Frames as 256-colour palette images (as a GIF stores them; ⅓ of the RGB memory), written by Pillow
    with the options of matplotlib's PillowWriter."""
    from PIL import Image

    frames = []
    for done, step in enumerate(steps, start=1):
        view.draw(step)
        frames.append(Image.fromarray(view.render_rgb()).quantize(256, method=Image.Quantize.FASTOCTREE))
        if progress is not None:
            progress(done, len(steps))
    duration_ms = int(1000 / fps)
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:], duration=duration_ms, loop=0)


def _write_mp4(view: TransitFigure, steps: list[int], path: Path, fps: int, progress: Progress) -> None:
    writer = _mp4_writer(fps)
    with writer.saving(view.figure, str(path), dpi=view.figure.dpi):
        for done, step in enumerate(steps, start=1):
            view.draw(step)
            writer.grab_frame()
            if progress is not None:
                progress(done, len(steps))


def _mp4_writer(fps: int):
    from matplotlib.animation import FFMpegWriter

    # yuv420p: playable in browsers and common players (the frame size is even, see TransitFigure)
    return FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])


def choose_format(out: Path | None, fmt: str | None) -> str:
    """The animation format from `fmt` or the suffix of `out` (default gif); mp4 needs ffmpeg on PATH."""
    suffix = out.suffix.lower().lstrip(".") if out is not None else ""
    if fmt is not None:
        fmt = fmt.lower()
        if fmt not in FORMATS:
            raise InputError("format", repr(fmt), allowed=", ".join(FORMATS))
        if suffix and suffix != fmt:
            raise InputError(
                "out", f"suffix .{suffix} does not match fmt={fmt!r} (--format)", allowed=f"*.{fmt}"
            )
    elif suffix in FORMATS:
        fmt = suffix
    elif suffix:
        raise InputError("out", f"unknown animation suffix .{suffix}", allowed="*.gif, *.mp4")
    else:
        fmt = "gif"
    if fmt == "mp4" and shutil.which("ffmpeg") is None:
        raise InputError(
            "format",
            "mp4 needs ffmpeg, which is not on PATH",
            allowed="gif (no extra program needed), or install ffmpeg for mp4",
        )
    return fmt


def _check_run_directory(run_dir: Path) -> None:
    if not run_dir.is_dir():
        raise InputError(
            "run_dir",
            f"{str(run_dir)!r} is not a directory",
            allowed="a run directory (floebreak run / demo)",
        )
    if not (run_dir / "pieces.parquet").is_file():
        raise InputError(
            "run_dir",
            f"{str(run_dir)!r} has no pieces.parquet (run directories of floebreak before the animation "
            "support lack it); re-run the scenario with this version",
            allowed=RERUN_HINT,
        )
    for name in ("scenario.resolved.toml", "field.parquet"):
        if not (run_dir / name).is_file():
            raise InputError("run_dir", f"{str(run_dir)!r} has no {name}", allowed=RERUN_HINT)


def _check_out(out: Path, overwrite: bool) -> None:
    if out.exists() and not overwrite:
        raise InputError("out", f"{str(out)!r} exists", allowed="a new path, or overwrite=True (--overwrite)")
    if out.is_dir():
        raise InputError("out", f"{str(out)!r} is a directory", allowed="a file path")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("out", f"directory {str(parent)!r} does not exist", allowed="an existing directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("out", f"directory {str(parent)!r} is not writable", allowed="a writable directory")


def _piece_motion(run_dir: Path, scenario, piece_id: np.ndarray) -> PieceMotion | None:
    """The recorded poses of a dynamic run (None for static ice); InputError when they were not recorded."""
    if (scenario.simulation.ice_motion or "static") != "dynamic":
        return None
    path = run_dir / POSES_FILE
    if not path.is_file():
        raise InputError(
            "run_dir",
            f"{str(run_dir)!r} is a run of moving ice (simulation.ice_motion = dynamic) without "
            f"{POSES_FILE}: the pieces' motion was not recorded",
            allowed="a dynamic run made with simulation.pose_interval_steps set (e.g. --set "
            "simulation.pose_interval_steps=4), or a static run",
        )
    outlines, pieces, poses, meta = read_poses(path)
    index = np.searchsorted(piece_id, pieces["piece_id"])
    if np.any(index >= len(piece_id)) or np.any(
        piece_id[np.minimum(index, len(piece_id) - 1)] != pieces["piece_id"]
    ):
        raise InputError(
            "run_dir", f"{POSES_FILE} names pieces that pieces.parquet lacks", allowed=RERUN_HINT
        )
    entry = np.column_stack([pieces["entry_x_m"], pieces["entry_y_m"]])
    rings = tuple(
        shapely.get_coordinates(shapely.get_exterior_ring(outline)) - xy
        for outline, xy in zip(outlines, entry, strict=True)
    )
    return PieceMotion(
        piece_index=index,
        ring_xy_m=rings,
        entry_xy_m=entry,
        pose_row=poses["row"],
        pose_step=poses["step"],
        pose_xy_m=np.column_stack([poses["x_m"], poses["y_m"]]),
        pose_angle_rad=poses["angle_rad"],
        interval_steps=int(meta["pose_interval_steps"]),
    )


def load_transit(run_dir: str | os.PathLike[str]) -> tuple[Transit, str]:
    """The `Transit` of a run directory and a short label (scenario name, profile, seed) for titles."""
    from floebreak.app.run import build_bow
    from floebreak.config.scenario import Scenario
    from floebreak.io.geoparquet import read_geoparquet
    from floebreak.output.field_files import load_field

    run_dir = Path(run_dir)
    _check_run_directory(run_dir)
    polygons, columns, meta = read_geoparquet(run_dir / "pieces.parquet", field="run_dir")
    missing = [name for name in PIECE_COLUMNS if name not in columns]
    stepping = [key for key in ("x_start_m", "step_m", "n_steps") if key not in meta]
    if missing or stepping:
        raise InputError(
            "run_dir", f"pieces.parquet lacks {missing + stepping}", allowed="pieces.parquet of " + RERUN_HINT
        )
    scenario = Scenario.from_toml(run_dir / "scenario.resolved.toml")
    floe_field = None
    if scenario.ice.thickness_m is None and scenario.ice.thickness_range_m is None:
        floe_field = load_field(run_dir / "field.parquet", field="run_dir")  # bow at the field's mean h
    bow = build_bow(scenario, floe_field)
    motion = _piece_motion(run_dir, scenario, np.asarray(columns["piece_id"], dtype=np.int64))
    transit = Transit(
        polygons=polygons,
        fate=np.asarray(columns["fate"], dtype=object),
        created_step=np.asarray(columns["created_step"], dtype=np.int64),
        ended_step=np.asarray(columns["ended_step"], dtype=np.int64),
        upper_xy_m=np.asarray(bow.upper_xy_m, dtype=float),
        lower_xy_m=np.asarray(bow.lower_xy_m, dtype=float),
        x_start_m=float(meta["x_start_m"]),
        step_m=float(meta["step_m"]),
        n_steps=int(meta["n_steps"]),
        motion=motion,
    )
    name = scenario.name or scenario.field.observation or scenario.field.source
    return transit, f"{name}, profile {scenario.profile}, seed {scenario.seed}"


def animate_run_directory(
    run_dir: str | os.PathLike[str],
    out: str | os.PathLike[str] | None = None,
    *,
    fps: int = 10,
    every: int | None = None,
    fmt: str | None = None,
    overwrite: bool = False,
    max_frames: int = MAX_FRAMES,
    window_m: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Path, int]:
    """Write the animation of `run_dir` (default ``run_dir/animation.gif``); returns (path, frame count).

    `every`: one frame per `every` bow steps (default: as few as keep ≤ `max_frames` frames; the last step
    is always shown). `progress(done, total)` is called after each frame.
    """
    run_dir = Path(run_dir)
    if fps != int(fps):
        raise InputError("fps", f"{fps!r} is not a whole number", allowed="1 … 60")
    fps = int(require_range("fps", fps, low=1, high=60, low_inclusive=True))
    if every is not None:
        if every != int(every) or every < 1:
            raise InputError("every", f"{every!r}", allowed="a whole number of steps ≥ 1")
        every = int(every)
    require_range("max_frames", max_frames, low=1, low_inclusive=True)
    out_path = Path(out) if out is not None else None
    fmt = choose_format(out_path, fmt)
    _check_run_directory(run_dir)
    out_path = out_path if out_path is not None else run_dir / f"animation.{fmt}"
    _check_out(out_path, overwrite)
    transit, label = load_transit(run_dir)
    interval = 1 if transit.motion is None else transit.motion.interval_steps
    if every is not None and every % interval:
        raise InputError(
            "every",
            f"{every}: this dynamic run's poses were recorded every {interval} steps",
            allowed=f"a multiple of {interval}",
        )
    steps = frame_steps(transit.n_steps, every, max_frames, stride_multiple=interval)
    if not steps:
        raise InputError("run_dir", "the run has no steps to show", allowed=RERUN_HINT)
    view = TransitFigure(transit, window_m=window_m, title=label)
    write = _write_gif if fmt == "gif" else _write_mp4
    with atomic_path(out_path, field="out", keep_suffix=True) as temp:
        write(view, steps, temp, fps, progress)
    return out_path, len(steps)
