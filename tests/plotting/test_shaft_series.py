"""The shaft figures' long series: decimated to each group's extremes, drawn as the whole series
is, pixel for pixel within the line's antialiasing, every peak kept."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from floebreak.plotting.shaft import MAX_PLOTTED_GROUPS, decimated, plot_series


def _series(n=93_001, seed=3):
    """A drive-like torque series [kN·m]: mean, blade-passage pulses in bursts, a ringing mode, noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 1.29e-3
    bursts = np.sin(2 * np.pi * 0.05 * t) > 0
    pulses = 300.0 * np.maximum(np.sin(2 * np.pi * 9.33 * t), 0.0) * bursts
    ringing = 50.0 * np.sin(2 * np.pi * 7.76 * t) * np.exp(-(t % 10.0))
    return t, 105.0 + pulses + ringing + rng.normal(0.0, 2.0, n)


def _pixels(t, y, limits):
    figure = Figure(figsize=(10.0, 3.0), dpi=150)
    ax = figure.add_axes((0.05, 0.1, 0.9, 0.8))
    ax.plot(t, y, color="C0", lw=0.6)
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    ax.set_axis_off()
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[..., :3].astype(int)


def test_groups_keep_their_extremes_in_time_order():
    t, y = _series()
    td, yd = decimated(t, y)
    group = int(np.ceil(y.size / MAX_PLOTTED_GROUPS))
    n = y.size // group * group
    assert np.all(np.diff(td) > 0.0)  # time order, each sample at most once
    assert yd.max() == y.max() and yd.min() == y.min()
    for k in (0, 17, n // group - 1):  # every group's own extremes, by an independent slice
        part = y[k * group : (k + 1) * group]
        inside = (td >= t[k * group]) & (td <= t[(k + 1) * group - 1])
        assert sorted(yd[inside]) == sorted([part.min(), part.max()])
    assert np.array_equal(yd[-(y.size - n) :], y[n:])  # the short last group as it is
    short_t, short_y = t[:2000], y[:2000]  # short series: as they are
    assert np.array_equal(decimated(short_t, short_y)[1], short_y)


def test_decimated_line_draws_the_pixels_of_the_whole_series():
    t, y = _series()
    limits = ((t[0], t[-1]), (y.min() - 10.0, y.max() + 10.0))
    whole = _pixels(t, y, limits)
    drawn = np.any(whole < 250, axis=-1).sum()  # pixels the whole series colours
    differ = np.any(np.abs(_pixels(*decimated(t, y), limits) - whole) > 64, axis=-1).sum()
    assert drawn > 50_000
    assert differ < 0.01 * drawn, (differ, drawn)  # every 31st sample instead: 20 %


def test_plot_series_draws_the_decimated_line_and_the_zoom_sample_by_sample():
    t, y = _series()
    figure = plot_series(t, {"shaft": y / 1.0}, "title")
    full, zoom = figure.axes[:2]
    (line,) = full.get_lines()
    assert line.get_xdata().size <= 2 * MAX_PLOTTED_GROUPS + 40
    assert max(line.get_ydata()) == y.max()
    assert zoom.get_lines()[0].get_xdata().size == np.sum(np.abs(t - t[np.argmax(y)]) <= 1.5)
