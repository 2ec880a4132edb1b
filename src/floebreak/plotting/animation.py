"""Animation frames of a transit, replayed from a run's pieces (thesis colour code of Figs. 15–16, 18–24).

Pure drawing: `Transit` holds every piece of a run with its life span (``created_step``, ``ended_step`` as in
``pieces.parquet``) and the bow outline; `TransitFigure.draw(step)` draws the state after that step on one
figure (ice still in the field blue, flipped pieces orange and cusps red where they left the field, the bow's
ice waterlines at the current position). A `dynamic` run's pieces move: its `Transit` also holds
`PieceMotion`, the recorded poses of the moved pieces (``poses.parquet``), and a moved piece in the field is
drawn at its latest recorded pose at or before the step. Writing the frames to a file is
`floebreak.app.replay`'s
job.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from floebreak.plotting.common import CUSP_COLOUR, FLIPPED_COLOUR, UNTOUCHED_COLOUR

MAX_FRAMES = 200  # default frame budget: a 400 m transit (≈ 1 800 steps) as a ≈ 20 s clip at 10 fps
MIN_WINDOW_M = 100.0  # narrowest view window along x that follows the bow
BOW_TIP_AT = 0.65  # where the bow's stem tip sits in a following window (fraction of its width from the left)
MARGIN_M = 2.0


@dataclass(frozen=True, eq=False)
class PieceMotion:
    """The recorded poses of the pieces a `dynamic` run moved (the layout of ``poses.parquet``).

    Per moved piece (row): its index among `Transit.polygons` and its outline relative to its centroid where
    it entered the engine (`ring_xy_m`); per pose (sorted by row, then step): the row, the step, the centroid
    and the rotation from the entry outline (counter-clockwise). Poses were kept every `interval_steps` steps
    and at the last, only when a piece's pose had changed.
    """

    piece_index: np.ndarray
    ring_xy_m: tuple[np.ndarray, ...]
    entry_xy_m: np.ndarray  # (rows, 2)
    pose_row: np.ndarray
    pose_step: np.ndarray
    pose_xy_m: np.ndarray  # (poses, 2)
    pose_angle_rad: np.ndarray
    interval_steps: int

    def outlines_at(self, step: int) -> dict[int, np.ndarray]:
        """Piece index → its outline's vertices at its latest pose at or before `step` (where it entered, if
        it had not moved by then)."""
        bounds = np.searchsorted(self.pose_row, np.arange(len(self.piece_index) + 1))
        outlines = {}
        for row, piece in enumerate(self.piece_index.tolist()):
            lo, hi = bounds[row], bounds[row + 1]
            k = lo + int(np.searchsorted(self.pose_step[lo:hi], step, side="right")) - 1
            if k < lo:
                outlines[piece] = self.ring_xy_m[row] + self.entry_xy_m[row]
                continue
            c, s = math.cos(self.pose_angle_rad[k]), math.sin(self.pose_angle_rad[k])
            outlines[piece] = self.ring_xy_m[row] @ np.array([[c, s], [-s, c]]) + self.pose_xy_m[k]
        return outlines

    def extent_m(self) -> tuple[float, float, float, float] | None:
        """(x0, y0, x1, y1) covering every recorded pose of every moved piece, None without poses."""
        if not len(self.pose_row):
            return None
        radius = np.array([np.hypot(r[:, 0], r[:, 1]).max() for r in self.ring_xy_m])[self.pose_row]
        x, y = self.pose_xy_m[:, 0], self.pose_xy_m[:, 1]
        return (
            float((x - radius).min()),
            float((y - radius).min()),
            float((x + radius).max()),
            float((y + radius).max()),
        )


@dataclass(frozen=True, eq=False)
class Transit:
    """Every piece of a run with its life span, and the bow (bow frame: upper stem tip at the origin).

    A piece is in the field after step s if ``created_step ≤ s`` and it has not ended (``ended_step`` −1 or
    > s); a cusp or flipped piece is shown where it left the field from its ``ended_step`` on. Bow x at step
    s: ``x_start_m + s·step_m`` (the upper stem tip, field frame).
    """

    polygons: np.ndarray
    fate: np.ndarray
    created_step: np.ndarray
    ended_step: np.ndarray
    upper_xy_m: np.ndarray
    lower_xy_m: np.ndarray
    x_start_m: float
    step_m: float
    n_steps: int
    motion: PieceMotion | None = None  # a dynamic run's recorded poses

    def bow_x_m(self, step: int) -> float:
        return self.x_start_m + step * self.step_m

    def state(self, step: int) -> dict[str, np.ndarray]:
        """Boolean masks over the pieces after `step`: "field" (still in the field), "cusp", "flipped"."""
        ended = self.ended_step
        done = (ended >= 0) & (ended <= step)
        return {
            "field": (self.created_step <= step) & ~done,
            "cusp": (self.fate == "cusp") & done,
            "flipped": (self.fate == "flipped") & done,
        }

    def extent_m(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) covering every piece and the bow at its first and last position, with a margin."""
        upper = np.asarray(self.upper_xy_m)
        x0 = self.x_start_m + upper[:, 0].min()
        x1 = self.bow_x_m(self.n_steps - 1) + upper[:, 0].max()
        y0, y1 = upper[:, 1].min(), upper[:, 1].max()
        if len(self.polygons):
            bx0, by0, bx1, by1 = shapely.total_bounds(self.polygons)
            x0, y0, x1, y1 = min(x0, bx0), min(y0, by0), max(x1, bx1), max(y1, by1)
        moved = self.motion.extent_m() if self.motion is not None else None
        if moved is not None:
            x0, y0, x1, y1 = min(x0, moved[0]), min(y0, moved[1]), max(x1, moved[2]), max(y1, moved[3])
        return (
            float(x0 - MARGIN_M),
            float(y0 - MARGIN_M),
            float(x1 + MARGIN_M),
            float(y1 + MARGIN_M),
        )


def frame_steps(
    n_steps: int, every: int | None = None, max_frames: int = MAX_FRAMES, stride_multiple: int = 1
) -> list[int]:
    """Steps shown as frames: 0, K, 2K, … and always the last step.

    Without `every`, K is the smallest multiple of `stride_multiple` (a dynamic run's pose interval: its
    poses are known at those steps) that keeps the count ≤ `max_frames`.
    """
    if n_steps <= 0:
        return []
    if every is None:
        every = max(1, math.ceil((n_steps - 1) / max(max_frames - 1, 1)))
        every = stride_multiple * math.ceil(every / stride_multiple)
    steps = list(range(0, n_steps, every))
    if steps[-1] != n_steps - 1:
        steps.append(n_steps - 1)
    return steps


def view_width_m(transit: Transit, window_m: float | None = None) -> float | None:
    """Width of a view window along x that follows the bow, or None to show the whole extent (small runs).

    Default: at least `MIN_WINDOW_M`, the bow's length plus as much ahead, and 2.5× the field's width (so
    the frame is not a thin strip); the whole extent is shown when it is at most twice that.
    """
    x0, y0, x1, y1 = transit.extent_m()
    if window_m is None:
        upper = np.asarray(transit.upper_xy_m)
        bow_length = float(upper[:, 0].max() - upper[:, 0].min())
        window_m = max(MIN_WINDOW_M, 2.0 * bow_length, 2.5 * (y1 - y0))
        if x1 - x0 <= 2.0 * window_m:
            return None
    return None if window_m >= x1 - x0 else float(window_m)


def view_xlim(transit: Transit, step: int, width_m: float | None) -> tuple[float, float]:
    """x limits at `step`: the whole extent, or a `width_m` window with the stem tip at `BOW_TIP_AT`."""
    x0, _, x1, _ = transit.extent_m()
    if width_m is None:
        return x0, x1
    left = transit.bow_x_m(step) - BOW_TIP_AT * width_m
    left = min(max(left, x0), x1 - width_m)
    return left, left + width_m


class TransitFigure:
    """One figure redrawn per frame: `draw(step)` updates pieces, bow and title in place (fast for GIFs)."""

    def __init__(
        self,
        transit: Transit,
        window_m: float | None = None,
        width_px: int = 800,
        dpi: float = 80.0,
        title: str | None = None,
    ):
        self.transit = transit
        self.width_m = view_width_m(transit, window_m)
        x0, y0, x1, y1 = transit.extent_m()
        shown_x = self.width_m if self.width_m is not None else x1 - x0
        # fixed pixel margins (labels, two title lines, legend on the right): the layout must not move
        # between frames, so no constrained layout
        left, right, bottom, top = 56, 140, 40, 44
        width_px = 2 * (max(width_px, 400) // 2)  # even pixel sizes: H.264 in yuv420p (MP4) needs them
        axes_w = width_px - left - right
        axes_h = int(np.clip(axes_w * (y1 - y0) / shown_x, 120, 2 * axes_w))
        height_px = 2 * ((axes_h + bottom + top + 1) // 2)
        self.figure = Figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi)
        FigureCanvasAgg(self.figure)  # attaches itself: frames are rendered without pyplot
        ax = self.figure.add_axes(
            (left / width_px, bottom / height_px, axes_w / width_px, axes_h / height_px)
        )
        self.ax = ax
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        self.label = title
        # exteriors of all polygon parts, once; multipolygons contribute every part
        parts, owner = shapely.get_parts(np.asarray(transit.polygons, dtype=object), return_index=True)
        self._verts = [shapely.get_coordinates(ring) for ring in shapely.get_exterior_ring(parts)]
        self._owner = owner
        bounds = shapely.bounds(parts) if len(parts) else np.zeros((0, 4))
        self._part_x0, self._part_x1 = bounds[:, 0], bounds[:, 2]
        # parts of moved pieces: drawn at their poses while in the field
        self._posed = np.zeros(len(owner), dtype=bool)
        if transit.motion is not None:
            self._posed = np.isin(owner, transit.motion.piece_index)
        self._collections = {}
        for key, colour in (("field", UNTOUCHED_COLOUR), ("flipped", FLIPPED_COLOUR), ("cusp", CUSP_COLOUR)):
            collection = PolyCollection([], facecolors=colour, edgecolors="k", linewidths=0.15)
            ax.add_collection(collection)
            self._collections[key] = collection
        (self._upper_line,) = ax.plot([], [], "-", color="k", linewidth=0.9)
        (self._lower_line,) = ax.plot([], [], "-", color="0.5", linewidth=0.6)
        ax.legend(
            handles=[
                Patch(facecolor=UNTOUCHED_COLOUR, label="ice in the field"),
                Patch(facecolor=FLIPPED_COLOUR, label="flipped"),
                Patch(facecolor=CUSP_COLOUR, label="cusps"),
            ],
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            fontsize="small",
        )

    def draw(self, step: int) -> dict[str, int]:
        """Show the state after `step`; returns the counts shown in the title (cusps, flipped so far)."""
        transit = self.transit
        xlim = view_xlim(transit, step, self.width_m)
        state = transit.state(step)
        visible = (self._part_x1 >= xlim[0]) & (self._part_x0 <= xlim[1])
        for key, collection in self._collections.items():
            shown = state[key][self._owner]
            if key != "field" or transit.motion is None:
                collection.set_verts([self._verts[i] for i in np.flatnonzero(shown & visible)])
                continue
            moved = transit.motion.outlines_at(step)
            verts = [self._verts[i] for i in np.flatnonzero(shown & visible & ~self._posed)]
            verts += [moved[self._owner[i]] for i in np.flatnonzero(shown & self._posed)]
            collection.set_verts(verts)
        bow_x = transit.bow_x_m(step)
        upper, lower = np.asarray(transit.upper_xy_m), np.asarray(transit.lower_xy_m)
        self._upper_line.set_data(upper[:, 0] + bow_x, upper[:, 1])
        self._lower_line.set_data(lower[:, 0] + bow_x, lower[:, 1])
        self.ax.set_xlim(*xlim)
        counts = {"cusps": int(state["cusp"].sum()), "flipped": int(state["flipped"].sum())}
        prefix = f"{self.label}\n" if self.label else ""
        self.ax.set_title(
            f"{prefix}bow x = {bow_x:.1f} m    cusps {counts['cusps']}    flipped {counts['flipped']}",
            fontsize="medium",
        )
        return counts

    def render_rgb(self) -> np.ndarray:
        """The figure as it stands, as an (height, width, 3) uint8 array (Agg, no file involved)."""
        self.figure.canvas.draw()
        return np.asarray(self.figure.canvas.buffer_rgba())[..., :3].copy()
