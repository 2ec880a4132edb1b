"""Shared plotting helpers: a headless figure factory and polygon collections."""

from __future__ import annotations

import matplotlib
import numpy as np
import shapely
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

# thesis colour code for breaking patterns (Figs. 15–16, 18–24)
UNTOUCHED_COLOUR = "#4c72b0"  # blue
FLIPPED_COLOUR = "#f28e2b"  # orange
CUSP_COLOUR = "#d62728"  # red


# Fixed margins (left, bottom, right, top) [in] for the figures written with every run directory and
# propeller analysis: their contents are known, and constrained layout costs about as much as drawing one
# (≈ 0.08 s). Under constrained layout the reference, 1 km, thesis and small runs needed at most 0.81 /
# 0.47 / 0.15 / 0.25 in (y tick labels of up to six characters such as 0.0015).
SPECTRUM_MARGINS_IN = (0.85, 0.5, 0.18, 0.3)
PATTERN_MARGINS_IN = (0.78, 0.5, 1.38, 0.3)  # legend outside on the right (≤ 1.31 in)
FIELD_MARGINS_IN = (0.78, 0.5, 1.18, 0.3)  # legend "floe class" outside on the right (≤ 1.07 in)
# Legend text of a figure as wide as the single-panel ones (7.5 in); wider figures (two panels side by side)
# get a proportionally larger font, since report.html scales every figure to the same page width
LEGEND_PT = 7.0
LEGEND_REFERENCE_WIDTH_IN = 7.5
NOTE_LINE_IN = 0.22  # a second title line (the window note) at the default 12 pt title size, with its spacing


def window_note(x_window_m: tuple[float, float], field_x_m: tuple[float, float]) -> str:
    """What a figure drawn in the x window `x_window_m` [m] shows of a field spanning `field_x_m` [m]:
    "first 2 000 m of the 10 000 m field" (a window from the field's start), else "x = a to b m of …"."""
    (a, b), (f0, f1) = x_window_m, field_x_m
    whole = f"the {_metres(f1 - f0)} m field"
    if a <= f0:
        return f"first {_metres(min(b, f1) - f0)} m of {whole}"
    return f"x = {_metres(a)} to {_metres(b)} m of {whole}"


def _metres(value: float) -> str:
    """A length for a title: thousands grouped by a space (SI style), a decimal only where it shows."""
    text = f"{value:,.0f}" if abs(value - round(value)) < 0.05 else f"{value:,.1f}"
    return text.replace(",", " ")


def with_note_line(margins_in: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """`margins_in` (left, bottom, right, top) with room for one more title line at the top."""
    left, bottom, right, top = margins_in
    return left, bottom, right, top + NOTE_LINE_IN


def new_figure(
    width_in: float = 10.0,
    height_in: float = 4.0,
    margins_in: tuple[float, float, float, float] | None = None,
) -> tuple[Figure, object]:
    """A figure with one axes, created without pyplot (safe in threads, workers and notebooks).

    Constrained layout, or with `margins_in` (left, bottom, right, top) [in] the axes placed by fixed
    margins (`place_axes`)."""
    if margins_in is None:
        figure = Figure(figsize=(width_in, height_in), constrained_layout=True)
    else:
        figure = Figure(figsize=(width_in, height_in))
        place_axes(figure, *margins_in)
    return figure, figure.add_subplot(1, 1, 1)


def place_axes(
    figure: Figure, left: float, bottom: float, right: float, top: float, columns: int = 1, gap: float = 0.0
) -> None:
    """Subplot grid of `figure` at fixed margins [in], `gap` [in] between its `columns`."""
    width, height = figure.get_size_inches()
    axes_width = (width - left - right - (columns - 1) * gap) / columns
    figure.subplots_adjust(
        left=left / width,
        right=1.0 - right / width,
        bottom=bottom / height,
        top=1.0 - top / height,
        wspace=gap / axes_width,
    )


def legend_font_pt(figure: Figure) -> float:
    """Legend font size [pt] that reads as `LEGEND_PT` once the figure is scaled to the page width:
    `LEGEND_PT` × width / `LEGEND_REFERENCE_WIDTH_IN`, never smaller than `LEGEND_PT`."""
    return LEGEND_PT * max(1.0, float(figure.get_size_inches()[0]) / LEGEND_REFERENCE_WIDTH_IN)


def page_fonts(width_in: float):
    """A matplotlib rc context for a figure `width_in` wide: every font (ticks, labels, titles) scaled by
    width / `LEGEND_REFERENCE_WIDTH_IN` (at least 1), so that once report.html scales the figure to the
    page width its text reads as large as a single-panel figure's. Draw the whole figure inside it."""
    scale = max(1.0, width_in / LEGEND_REFERENCE_WIDTH_IN)
    return matplotlib.rc_context({"font.size": matplotlib.rcParamsDefault["font.size"] * scale})


def add_legend(ax, **kwargs):
    """`ax.legend` at `legend_font_pt` of its figure, one entry per distinct label (a repeated label,
    e.g. one style drawn per pitch, is listed once)."""
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    kwargs.setdefault("fontsize", legend_font_pt(ax.figure.figure))  # .figure.figure: the root figure
    return ax.legend(list(unique.values()), list(unique.keys()), **kwargs)


def polygon_collection(polygons, **kwargs) -> PolyCollection:
    """One PolyCollection of the exteriors of all polygons (multipolygons contribute every part)."""
    parts = shapely.get_parts(np.asarray(polygons, dtype=object))
    exteriors = shapely.get_exterior_ring(parts)
    coords, ring = shapely.get_coordinates(exteriors, return_index=True)  # one call, not one per ring
    ends = np.cumsum(np.bincount(ring, minlength=len(exteriors)))
    verts = np.split(coords, ends[:-1]) if len(exteriors) else []
    return PolyCollection(verts, **kwargs)
