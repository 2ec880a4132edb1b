"""Shaft figures: load and shaft torque series, their spectra, the measured comparison (as thesis Figs.
35/37, but shaft against shaft) and the free-free mode shapes (docs/shaft.md)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from floebreak.plotting.common import SPECTRUM_MARGINS_IN, new_figure

MAX_PLOTTED_POINTS = 3_000  # ≈ 2 groups per pixel column at 150 dpi


def _envelope(t, y, max_points: int = MAX_PLOTTED_POINTS):
    """(t, lower, upper) per group of samples, so a long series plots as its min-max band."""
    group = max(1, int(np.ceil(y.size / max_points)))
    if group == 1:
        return t, y, y
    n = y.size // group * group
    shaped = y[:n].reshape(-1, group)
    return t[:n:group], shaped.min(axis=1), shaped.max(axis=1)


def plot_series(time_s, series_knm: dict[str, np.ndarray], title: str, zoom_s: float = 3.0) -> Figure:
    """Torque series [kN·m] over time [s] (long series as min–max bands) and, below, `zoom_s` seconds
    around the largest value of the last series, sample by sample."""
    figure = Figure(figsize=(10.0, 6.5), constrained_layout=True)
    full, zoom = figure.subplots(2, 1)
    time_s = np.asarray(time_s)
    last = np.asarray(list(series_knm.values())[-1])
    centre = time_s[int(np.argmax(last))] if last.size else 0.0
    window = (time_s >= centre - zoom_s / 2) & (time_s <= centre + zoom_s / 2)
    for i, (label, y) in enumerate(series_knm.items()):
        y = np.asarray(y)
        t, lo, hi = _envelope(time_s, y)
        if lo is hi:
            full.plot(t, y, color=f"C{i}", lw=0.6, label=label)
        else:
            full.fill_between(t, lo, hi, color=f"C{i}", alpha=0.6, lw=0, label=f"{label} (min–max)")
        zoom.plot(time_s[window], y[window], color=f"C{i}", lw=0.9, label=label)
    for ax in (full, zoom):
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("torque [kN m]")
        ax.legend(fontsize=7)
    full.set_title(title, fontsize=9)
    zoom.set_title(f"{zoom_s:g} s around the largest value", fontsize=9)
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
