"""Animation frames (pure): which pieces are shown after a step, frame selection, the view window, drawing."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from floebreak.plotting.animation import (
    Transit,
    TransitFigure,
    frame_steps,
    view_width_m,
    view_xlim,
)

# a bow outline in the bow frame: stem tip at the origin, 20 m long, 10 m wide (upper and lower waterline)
UPPER = np.array([[-20.0, 5.0], [-5.0, 5.0], [0.0, 0.0], [-5.0, -5.0], [-20.0, -5.0]])
LOWER = UPPER * np.array([1.0, 0.8])


def _story(length_m: float = 40.0, n_steps: int = 10) -> Transit:
    """Floe A (square) breaks at step 3 into B (cusp at once) and C (in the field until it flips at step 7);
    floe D is never touched."""
    a = shapely.box(10.0, -4.0, 18.0, 4.0)
    b = shapely.box(10.0, -4.0, 14.0, 4.0)
    c = shapely.box(14.0, -4.0, 18.0, 4.0)
    d = shapely.box(length_m - 8.0, -4.0, length_m, 4.0)
    return Transit(
        polygons=np.array([a, d, b, c], dtype=object),
        fate=np.array(["broken", "remaining", "cusp", "flipped"], dtype=object),
        created_step=np.array([-1, -1, 3, 3]),
        ended_step=np.array([3, -1, 3, 7]),
        upper_xy_m=UPPER,
        lower_xy_m=LOWER,
        x_start_m=0.0,
        step_m=0.5,
        n_steps=n_steps,
    )


def _shown(transit: Transit, step: int) -> dict[str, list[int]]:
    return {key: np.flatnonzero(mask).tolist() for key, mask in transit.state(step).items()}


def test_state_replays_the_story():
    transit = _story()
    assert _shown(transit, 0) == {"field": [0, 1], "cusp": [], "flipped": []}
    assert _shown(transit, 2) == {"field": [0, 1], "cusp": [], "flipped": []}
    assert _shown(transit, 3) == {"field": [1, 3], "cusp": [2], "flipped": []}
    assert _shown(transit, 6) == {"field": [1, 3], "cusp": [2], "flipped": []}
    assert _shown(transit, 7) == {"field": [1], "cusp": [2], "flipped": [3]}
    for step in range(transit.n_steps):  # field ice + ice gone = the initial 2 floes (8 m × 8 m each)
        state = transit.state(step)
        shown = state["field"] | state["cusp"] | state["flipped"]
        assert shapely.area(transit.polygons[shown]).sum() == pytest.approx(128.0)


@pytest.mark.parametrize(
    ("n_steps", "every", "expected"),
    [
        (10, 3, [0, 3, 6, 9]),
        (11, 3, [0, 3, 6, 9, 10]),
        (1, None, [0]),
        (5, None, [0, 1, 2, 3, 4]),
        (0, None, []),
    ],
)
def test_frame_steps(n_steps, every, expected):
    assert frame_steps(n_steps, every) == expected


@pytest.mark.parametrize("n_steps", [200, 201, 399, 1778, 4178])
def test_automatic_stride_keeps_the_frame_budget(n_steps):
    steps = frame_steps(n_steps, max_frames=200)
    assert steps[0] == 0 and steps[-1] == n_steps - 1
    assert len(steps) <= 200
    strides = np.diff(steps[:-1])  # the last frame is the last step, whatever the stride
    stride = int(strides[0])
    assert np.all(strides == stride) and steps[-1] - steps[-2] <= stride
    assert stride == 1 or len(frame_steps(n_steps, stride - 1)) > 200  # the smallest stride that fits


def test_small_field_is_shown_whole_and_long_field_is_followed():
    small = _story(length_m=40.0, n_steps=10)
    assert view_width_m(small) is None
    x0, _, x1, _ = small.extent_m()
    assert view_xlim(small, 5, None) == (x0, x1)
    long = _story(length_m=1000.0, n_steps=2000)  # bow runs 0 … 999.5 m
    width = view_width_m(long)
    assert width is not None and width >= 100.0
    x0, _, x1, _ = long.extent_m()
    for step in (0, 500, 1000, 1999):
        left, right = view_xlim(long, step, width)
        assert right - left == pytest.approx(width)
        assert x0 - 1e-9 <= left and right <= x1 + 1e-9
        bow_x = long.bow_x_m(step)
        assert left <= bow_x - 20.0 and bow_x <= right  # the whole bow is in view
    assert view_width_m(long, window_m=5000.0) is None  # a window wider than the run: whole extent


def test_draw_shows_the_state_and_title():
    view = TransitFigure(_story(), title="story")
    counts = view.draw(7)
    assert counts == {"cusps": 1, "flipped": 1}
    drawn = {key: len(collection.get_paths()) for key, collection in view._collections.items()}
    assert drawn == {"field": 1, "cusp": 1, "flipped": 1}
    title = view.ax.get_title()
    assert "story" in title and "bow x = 3.5 m" in title and "cusps 1" in title and "flipped 1" in title
    view.draw(2)
    assert {key: len(c.get_paths()) for key, c in view._collections.items()} == {
        "field": 2,
        "cusp": 0,
        "flipped": 0,
    }
    bow_x, _ = view._upper_line.get_data()
    np.testing.assert_allclose(bow_x, UPPER[:, 0] + 1.0)  # step 2 × 0.5 m
    pixels = view.render_rgb()
    width, height = view.figure.canvas.get_width_height()
    assert pixels.shape == (height, width, 3) and pixels.dtype == np.uint8
    assert width % 2 == 0 and height % 2 == 0  # H.264 (yuv420p) needs even sizes
