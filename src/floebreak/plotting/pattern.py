"""Breaking pattern (thesis Figs. 15–16, 18–24): blue untouched/remaining ice, orange flipped, red cusps,
with the bow's ice waterlines at the start and end positions."""

from __future__ import annotations

import numpy as np
import shapely
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
    """Plot a `SimulationResult`: remaining ice blue, flipped orange, cusps red; bow outline at the start
    (dashed) and, with `bow_at_end`, at the end position (solid). Pieces are drawn where they were made.

    `x_window_m`: draw only the pieces within this x range [m], in a figure sized for it (a long transit:
    its whole length would be a sliver of pixels, and every piece would be held once more as a path); the
    title's last line says which part of the field is shown (`window_note`: "first 2 000 m of the 10 000 m
    field")."""
    field_x0, _, field_x1, _ = result.field.domain_m
    note = None if x_window_m is None else window_note(x_window_m, (field_x0, field_x1))
    if ax is None:
        x0, y0, x1, y1 = result.field.domain_m
        hull_x0, hull_y0, _, hull_y1 = shapely.bounds(result.bow.hull_upper)
        x_range = x1 - x0 - hull_x0 + 4.0
        if x_window_m is not None:
            x_range = x_window_m[1] - x_window_m[0]
        y_range = max(y1, hull_y1) - min(y0, hull_y0) + 4.0
        # axes ≈ 8 in wide (legend outside on the right), equal aspect; + room for title and labels
        height_in = float(np.clip(8.0 * y_range / max(x_range, 1e-9) + 1.0, 2.0, 10.0))
        margins_in = PATTERN_MARGINS_IN
        if note:
            height_in, margins_in = height_in + NOTE_LINE_IN, with_note_line(margins_in)
        figure, ax = new_figure(10.0, height_in, margins_in)
    else:
        figure = ax.figure
    bounds = result.piece_bounds_m  # NaN for an empty piece
    shown = np.ones(len(bounds), dtype=bool)
    if x_window_m is not None:
        xlim = x_window_m
        shown = (bounds[:, 0] <= x_window_m[1]) & (bounds[:, 2] >= x_window_m[0])
    for fate, colour in (("remaining", UNTOUCHED_COLOUR), ("flipped", FLIPPED_COLOUR), ("cusp", CUSP_COLOUR)):
        polygons = result.polygons(np.flatnonzero(result.mask(fate) & shown))
        if polygons.size:
            ax.add_collection(
                polygon_collection(polygons, facecolors=colour, edgecolors="k", linewidths=0.15)
            )
    upper = np.asarray(result.bow.upper_xy_m)
    lower = np.asarray(result.bow.lower_xy_m)
    positions = [(result.params.x_start_m, "--")]
    if bow_at_end:
        positions.append((result.params.x_start_m + (result.n_steps - 1) * result.params.step_m, "-"))
    for x_b, style in positions:
        ax.plot(upper[:, 0] + x_b, upper[:, 1], style, color="k", linewidth=0.8)
        ax.plot(lower[:, 0] + x_b, lower[:, 1], style, color="0.5", linewidth=0.6)
    if len(bounds) and not np.isnan(bounds).all():  # as shapely.total_bounds of the pieces
        bounds = np.concatenate([np.nanmin(bounds[:, :2], axis=0), np.nanmax(bounds[:, 2:], axis=0)])
    else:
        bounds = np.array(result.field.domain_m)
    ax.set_xlim(xlim or (min(bounds[0], upper[:, 0].min()) - 2, bounds[2] + 2))
    ax.set_ylim(ylim or (min(bounds[1], upper[:, 1].min()) - 2, max(bounds[3], upper[:, 1].max()) + 2))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if legend:
        ax.legend(
            handles=[
                Patch(facecolor=UNTOUCHED_COLOUR, label="ice in the field"),
                Patch(facecolor=FLIPPED_COLOUR, label=f"flipped ({int(result.mask('flipped').sum())})"),
                Patch(facecolor=CUSP_COLOUR, label=f"cusps ({int(result.mask('cusp').sum())})"),
            ],
            loc="upper left",
            bbox_to_anchor=(1.0, 1.0),
            fontsize="small",
        )
    title = "\n".join(line for line in (title, note) if line)
    if title:
        ax.set_title(title)
    return figure
