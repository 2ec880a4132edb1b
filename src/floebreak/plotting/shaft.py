"""Shaft figures: load and shaft torque series, their spectra, the measured comparison (as thesis Figs.
35/37, but shaft against shaft) and the free-free mode shapes (docs/shaft.md)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from floebreak.plotting.common import SPECTRUM_MARGINS_IN, new_figure

MAX_PLOTTED_POINTS = 20_000


def _envelope(t, y, max_points: int = MAX_PLOTTED_POINTS):
    """(t, lower, upper) per group of samples, so a long series plots as its min-max band."""
    group = max(1, int(np.ceil(y.size / max_points)))
    if group == 1:
        return t, y, y
    n = y.size // group * group
    shaped = y[:n].reshape(-1, group)
    return t[:n:group], shaped.min(axis=1), shaped.max(axis=1)


def plot_series(time_s, series_knm: dict[str, np.ndarray], title: str) -> Figure:
    """Torque series [kN·m] over time [s]; long series as min–max bands."""
    figure, ax = new_figure(10.0, 4.0, SPECTRUM_MARGINS_IN)
    for i, (label, y) in enumerate(series_knm.items()):
        t, lo, hi = _envelope(np.asarray(time_s), np.asarray(y))
        colour = f"C{i}"
        if lo is hi:
            ax.plot(t, y, color=colour, lw=0.6, label=label)
        else:
            ax.fill_between(t, lo, hi, color=colour, alpha=0.6, lw=0, label=f"{label} (min–max)")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("torque [kN m]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    return figure


def plot_densities(edges_knm, densities: dict[str, np.ndarray], log: bool, threshold: float, title: str):
    """Probability densities [1/(kN·m)] on common bins, step lines; the 0.1 % threshold dotted."""
    figure, ax = new_figure(7.5, 4.0, SPECTRUM_MARGINS_IN)
    for i, (label, dens) in enumerate(densities.items()):
        values = np.nan_to_num(np.asarray(dens, dtype=float))
        ax.stairs(values, edges_knm, color=f"C{i}", label=label, lw=1.0)
    ax.axhline(threshold, color="0.4", lw=0.7, ls=":", label="0.1 % per kN m")
    if log:
        ax.set_yscale("log")
        positive = [d[d > 0] for d in (np.nan_to_num(np.asarray(v)) for v in densities.values())]
        low = min((p.min() for p in positive if p.size), default=threshold)
        ax.set_ylim(bottom=min(low, threshold) / 2.0)
    ax.set_xlabel("torque Q [kN m]")
    ax.set_ylabel("probability density [1/(kN m)]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    return figure


def plot_modes(element_names, frequency_hz, shapes) -> Figure:
    """Free-free mode shapes (angle amplitude per element, largest = 1)."""
    figure, ax = new_figure(7.5, 4.0, SPECTRUM_MARGINS_IN)
    x = np.arange(len(element_names))
    for i, (f, shape) in enumerate(zip(frequency_hz, shapes, strict=True)):
        ax.plot(x, shape, "o-", color=f"C{i}", label=f"mode {i + 1}: {f:.2f} Hz")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xticks(x, element_names, fontsize=8)
    ax.set_ylabel("relative angle amplitude [-]")
    ax.set_title("free-free torsional modes (motor → propeller)", fontsize=9)
    ax.legend(fontsize=7)
    return figure
