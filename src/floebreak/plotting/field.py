"""Figure of a floe field (thesis Fig. 1): all floes as one PolyCollection coloured by diameter class."""

from __future__ import annotations

import numpy as np
import shapely
from matplotlib import colormaps
from matplotlib.patches import Patch, Rectangle

from floebreak.ice.field import FloeField, diameter_classes_m
from floebreak.plotting.common import (
    FIELD_MARGINS_IN,
    NOTE_LINE_IN,
    new_figure,
    polygon_collection,
    window_note,
    with_note_line,
)


def plot_field(
    floe_field: FloeField,
    title: str | None = None,
    ax=None,
    x_window_m: tuple[float, float] | None = None,
    classes_m: tuple[float, ...] | None = None,
):
    """Plot `floe_field`; returns the matplotlib Figure. Floes are coloured by diameter class.

    `x_window_m`: show only this x range [m] of the field, in a figure sized for it (a long field); the
    title's second line says which part is shown (`window_note`: "first 2 000 m of the 10 000 m field").
    `classes_m`: the diameter classes [m] that the colours and the legend stand for (default: those of
    `floe_field`'s floes; a caller that passes only the floes in the window gives the whole field's)."""
    x0, y0, x1, y1 = floe_field.domain_m
    note = None
    if x_window_m is not None:
        note = window_note(x_window_m, (x0, x1))
        x0, x1 = x_window_m
    if ax is None:
        aspect = (y1 - y0) / max(x1 - x0, 1e-9)
        height_in = float(np.clip(10.0 * aspect + 1.2, 2.5, 10.0))
        margins_in = FIELD_MARGINS_IN
        if note:
            height_in, margins_in = height_in + NOTE_LINE_IN, with_note_line(margins_in)
        figure, ax = new_figure(10.0, height_in, margins_in)
    else:
        figure = ax.figure
    classes = floe_field.diameter_class_m
    known = diameter_classes_m(floe_field) if classes_m is None else classes_m
    palette = colormaps["viridis"](np.linspace(0.15, 0.9, max(len(known), 1)))
    colours = np.empty((floe_field.n_floes, 4))
    colours[:] = (0.6, 0.6, 0.6, 1.0)
    handles = []
    for colour, diameter in zip(palette, known, strict=False):
        colours[classes == diameter] = colour
        handles.append(Patch(facecolor=colour, label=f"d = {diameter:g} m"))
    shown = np.ones(floe_field.n_floes, dtype=bool)
    if x_window_m is not None:
        bounds = shapely.bounds(floe_field.polygons).reshape(-1, 4)
        shown = (bounds[:, 0] <= x1) & (bounds[:, 2] >= x0)
    ax.add_collection(
        polygon_collection(
            floe_field.polygons[shown], facecolors=colours[shown], edgecolors="k", linewidths=0.2
        )
    )
    domain = floe_field.domain_m
    ax.add_patch(
        Rectangle(
            (domain[0], domain[1]),
            domain[2] - domain[0],
            domain[3] - domain[1],
            fill=False,
            edgecolor="0.4",
            linestyle="--",
            linewidth=0.8,
        )
    )
    ax.set_xlim(x0 - 0.01 * (x1 - x0), x1 + 0.01 * (x1 - x0))
    ax.set_ylim(y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0))
    ax.set_aspect("equal")
    ax.set_xlabel("x (ship's forward direction) [m]")
    ax.set_ylabel("y (to port) [m]")
    if handles:
        ax.legend(
            handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small", title="floe class"
        )
    title = title or f"{floe_field.n_floes} floes, concentration {100 * floe_field.concentration:.1f} %"
    ax.set_title(f"{title}\n{note}" if note else title)
    return figure
