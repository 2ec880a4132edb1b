"""Study figures: cusp-volume spectra per sweep (thesis Figs. 17, 19, 21, 23) and the spider diagram
(Fig. 25)."""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from floebreak.plotting.common import new_figure

VOLUME_BIN_M3 = 1.0


def plot_volume_spectra(volumes_by_point: dict[str, np.ndarray], title: str = "Cusp-volume spectrum"):
    """Probability density of cusp volume [1/m³] per design point, pooled over its fields (step lines)."""
    figure, ax = new_figure(7.5, 4.2)
    top = max([float(np.max(v)) for v in volumes_by_point.values() if len(v)] + [VOLUME_BIN_M3])
    edges = np.arange(0.0, top + VOLUME_BIN_M3, VOLUME_BIN_M3)
    colours = colormaps["viridis"](np.linspace(0.05, 0.85, max(len(volumes_by_point), 1)))
    for colour, (label, volumes) in zip(colours, volumes_by_point.items(), strict=False):
        if len(volumes) == 0:
            continue
        density, _ = np.histogram(volumes, bins=edges, density=True)
        ax.stairs(density, edges, color=colour, linewidth=1.4, label=f"{label} (n = {len(volumes)})")
    ax.set_xlabel("cusp volume V [m³]")
    ax.set_ylabel("probability density [1/m³]")
    ax.set_title(title)
    ax.legend(fontsize="small")
    return figure


def plot_spider(tables: dict[str, list[dict]], metrics) -> Figure:
    """Spider diagram (thesis Fig. 25): every design point's metrics divided by their mean over all points.

    A regular polygon of radius 1 means the parameter has no influence on these cusp/floe properties.
    """
    figure = Figure(figsize=(7.5, 7.0), constrained_layout=True)
    ax = figure.add_subplot(1, 1, 1, projection="polar")
    keys = [key for key, _ in metrics]
    labels = [label for _, label in metrics]
    rows = [(group, row) for group, group_rows in tables.items() for row in group_rows]
    means = {key: np.nanmean([row[f"{key}_mean"] for _, row in rows]) for key in keys}
    angles = np.linspace(0.0, 2.0 * np.pi, len(keys), endpoint=False)
    colours = colormaps["tab20"](np.linspace(0.0, 1.0, max(len(rows), 1)))
    for colour, (group, row) in zip(colours, rows, strict=False):
        values = np.array([row[f"{key}_mean"] / means[key] if means[key] else np.nan for key in keys])
        ax.plot(
            np.append(angles, angles[0]),
            np.append(values, values[0]),
            color=colour,
            linewidth=1.2,
            label=f"{group}: {row['point']}",
        )
    ax.set_xticks(angles, labels)
    ax.set_title("Study summary: each metric relative to its mean over all design points")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.05), fontsize="x-small", ncol=2)
    return figure
