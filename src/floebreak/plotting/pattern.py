"""Breaking pattern (thesis Figs. 15–16, 18–24): blue untouched/remaining ice, orange flipped, red cusps,
with the bow's ice waterlines at the start and end positions."""

from __future__ import annotations

import numpy as np
from matplotlib.patches import Patch

from floebreak.plotting.common import (
    CUSP_COLOUR,
    FLIPPED_COLOUR,
    NOTE_LINE_IN,
    PATTERN_MARGINS_IN,
    UNTOUCHED_COLOUR,
    new_figure,
    polygon_collection,
    window_note,
    with_note_line,
)
from floebreak.plotting.pattern_data import FATES, BreakingPattern, breaking_pattern


def plot_breaking_pattern(
    result,
    ax=None,
    title: str | None = None,
    xlim=None,
    ylim=None,
    bow_at_end: bool = True,
    legend: bool = True,
    x_window_m: tuple[float, float] | None = None,
):
    """Plot a `SimulationResult` (or its `BreakingPattern`): remaining ice blue, flipped orange, cusps red;
    bow outline at the start (dashed) and, with `bow_at_end`, at the end position (solid). Pieces are drawn
    where they were made.

    `x_window_m`: draw only the pieces within this x range [m], in a figure sized for it (a long transit:
    its whole length would be a sliver of pixels, and every piece would be held once more as a path); the
    title's last line says which part of the field is shown (`window_note`: "first 2 000 m of the 10 000 m
    field"). A `BreakingPattern` carries its window (`breaking_pattern(result, x_window_m)`)."""
    if isinstance(result, BreakingPattern):
        if x_window_m is not None and tuple(x_window_m) != result.x_window_m:
            raise ValueError(f"x_window_m {x_window_m} differs from the pattern's {result.x_window_m}")
        pattern = result
    else:
        pattern = breaking_pattern(result, x_window_m)
    x_window_m = pattern.x_window_m
    field_x0, _, field_x1, _ = pattern.field_domain_m
    note = None if x_window_m is None else window_note(x_window_m, (field_x0, field_x1))
    if ax is None:
        figure, ax = _pattern_figure(pattern, note)
    else:
        figure = ax.figure
    if x_window_m is not None:
        xlim = x_window_m
    for fate, colour in zip(FATES, (UNTOUCHED_COLOUR, FLIPPED_COLOUR, CUSP_COLOUR), strict=True):
        polygons = pattern.polygons[fate]
        if polygons.size:
            ax.add_collection(
                polygon_collection(polygons, facecolors=colour, edgecolors="k", linewidths=0.15)
            )
    upper, lower = pattern.upper_xy_m, pattern.lower_xy_m
    positions = [(pattern.bow_start_x_m, "--")]
    if bow_at_end:
        positions.append((pattern.bow_end_x_m, "-"))
    for x_b, style in positions:
        ax.plot(upper[:, 0] + x_b, upper[:, 1], style, color="k", linewidth=0.8)
        ax.plot(lower[:, 0] + x_b, lower[:, 1], style, color="0.5", linewidth=0.6)
    bounds = pattern.pieces_bounds_m
    ax.set_xlim(xlim or (min(bounds[0], upper[:, 0].min()) - 2, bounds[2] + 2))
    ax.set_ylim(ylim or (min(bounds[1], upper[:, 1].min()) - 2, max(bounds[3], upper[:, 1].max()) + 2))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if legend:
        ax.legend(
            handles=[
                Patch(facecolor=UNTOUCHED_COLOUR, label="ice in the field"),
                Patch(facecolor=FLIPPED_COLOUR, label=f"flipped ({pattern.counts['flipped']})"),
                Patch(facecolor=CUSP_COLOUR, label=f"cusps ({pattern.counts['cusp']})"),
            ],
            loc="upper left",
            bbox_to_anchor=(1.0, 1.0),
            fontsize="small",
        )
    title = "\n".join(line for line in (title, note) if line)
    if title:
        ax.set_title(title)
    return figure


def _pattern_figure(pattern: BreakingPattern, note: str | None):
    """A new figure sized for `pattern`'s field (or window): axes ≈ 8 in wide, the legend outside on the
    right, equal aspect, room for the title, its window `note` and the labels."""
    x0, y0, x1, y1 = pattern.field_domain_m
    hull_x0, hull_y0, _, hull_y1 = pattern.hull_upper_bounds_m
    x_range = x1 - x0 - hull_x0 + 4.0
    if pattern.x_window_m is not None:
        x_range = pattern.x_window_m[1] - pattern.x_window_m[0]
    y_range = max(y1, hull_y1) - min(y0, hull_y0) + 4.0
    height_in = float(np.clip(8.0 * y_range / max(x_range, 1e-9) + 1.0, 2.0, 10.0))
    margins_in = PATTERN_MARGINS_IN
    if note:
        height_in, margins_in = height_in + NOTE_LINE_IN, with_note_line(margins_in)
    return new_figure(10.0, height_in, margins_in)
