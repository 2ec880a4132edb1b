"""Bow figure: both ice waterlines, panels coloured by ψ, outward panel normals (thesis Figs. 2, 8)."""

from __future__ import annotations

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from floebreak.plotting.common import new_figure


def plot_bow(bow, ax=None, title: str | None = None) -> Figure:
    """Plan view of a `floebreak.ship.bow.Bow`: both ice waterlines, the panel strips between them coloured by
    ψ_v (from the vertical, physics-notes §2.1) with a colorbar "ψ [deg]", and the outward panel normals."""
    upper = np.asarray(bow.upper_xy_m, dtype=float)
    lower = np.asarray(bow.lower_xy_m, dtype=float)
    if ax is None:
        x_extent = float(np.ptp(upper[:, 0])) or 1.0
        y_extent = float(np.ptp(upper[:, 1])) or 1.0
        figure, ax = new_figure(9.0, float(np.clip(9.0 * y_extent / x_extent, 3.0, 9.0)) + 0.8)
    else:
        figure = ax.figure
    quads = [np.array([upper[i], upper[i + 1], lower[i + 1], lower[i]]) for i in range(len(upper) - 1)]
    panels = PolyCollection(quads, cmap="viridis", edgecolors="0.3", linewidths=0.3)
    panels.set_array(np.degrees(np.asarray(bow.panel_psi_rad, dtype=float)))
    ax.add_collection(panels)
    figure.colorbar(panels, ax=ax, label="ψ [deg]")
    ax.plot(upper[:, 0], upper[:, 1], "-", color="tab:red", linewidth=1.2, label="upper ice waterline")
    ax.plot(lower[:, 0], lower[:, 1], "-", color="tab:blue", linewidth=1.0, label="lower ice waterline")
    for xy, colour in ((upper, "tab:red"), (lower, "tab:blue")):
        ax.plot([xy[0, 0], xy[-1, 0]], [xy[0, 1], xy[-1, 1]], ":", color=colour, linewidth=0.8)
    mid = np.asarray(bow.panel_midpoints_m, dtype=float)
    normals = np.asarray(bow.panel_normals, dtype=float)
    arrow_m = 0.05 * max(float(np.ptp(upper[:, 0])), float(np.ptp(upper[:, 1])), 1e-9)
    ax.quiver(
        mid[:, 0],
        mid[:, 1],
        normals[:, 0] * arrow_m,
        normals[:, 1] * arrow_m,
        angles="xy",
        scale_units="xy",
        scale=1.0,
        width=0.002,
        color="k",
        label="panel normals",
    )
    ax.set_aspect("equal")
    reach = np.vstack([upper, mid + normals * arrow_m])
    pad = 0.5 * arrow_m
    ax.set_xlim(reach[:, 0].min() - pad, reach[:, 0].max() + pad)
    ax.set_ylim(reach[:, 1].min() - pad, reach[:, 1].max() + pad)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="lower left", fontsize="small")
    ax.set_title(title or f"{bow.name}: ice waterlines and panel angles ψ")
    return figure
