"""Figures of `floebreak validate`: our results with the thesis' values drawn in (thesis Figs. 13, 17–25)."""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from floebreak.plotting.common import new_figure

VOLUME_BIN_M3 = 0.5


def plot_bending_forces(forces_kn: dict[str, np.ndarray], band_kn: float = 2500.0) -> Figure:
    """Probability density of F_c at bending failures per label (thesis Fig. 13), the thesis' band shaded."""
    figure, ax = new_figure(7.5, 4.2)
    top = max([float(np.percentile(f, 99)) for f in forces_kn.values() if len(f)] + [band_kn * 1.2])
    edges = np.linspace(0.0, top, 61)
    ax.axvspan(0.0, band_kn, color="0.9", label=f"thesis §5.1: mainly 0–{band_kn:g} kN")
    colours = colormaps["tab10"](np.arange(max(len(forces_kn), 1)) % 10)
    for colour, (label, forces) in zip(colours, forces_kn.items(), strict=False):
        if len(forces):
            density, _ = np.histogram(np.clip(forces, 0.0, top), bins=edges, density=True)
            ax.stairs(density, edges, color=colour, linewidth=1.4, label=f"{label} (n = {len(forces)})")
    ax.set_xlabel("crushing force at bending failures F_c [kN]")
    ax.set_ylabel("probability density [1/kN]")
    ax.set_title("Crushing forces at bending failures, h = 1.0 m (thesis Fig. 13 analogue)")
    ax.legend(fontsize="small")
    return figure


def plot_volume_spectra_vs_thesis(
    volumes: dict[str, np.ndarray], thesis_means_m3: dict[str, float], title: str
) -> Figure:
    """Cusp-volume density per design point, our mean V̄ (solid) and the thesis' (dashed) per point
    (thesis Figs. 17, 19, 21, 23)."""
    figure, ax = new_figure(7.5, 4.2)
    top = max([float(np.percentile(v, 99.5)) for v in volumes.values() if len(v)] + [16.0])
    edges = np.arange(0.0, top + VOLUME_BIN_M3, VOLUME_BIN_M3)
    colours = colormaps["viridis"](np.linspace(0.05, 0.85, max(len(volumes), 1)))
    for colour, (label, v) in zip(colours, volumes.items(), strict=False):
        if not len(v):
            continue
        density, _ = np.histogram(np.clip(v, 0.0, top), bins=edges, density=True)
        ax.stairs(density, edges, color=colour, linewidth=1.4, label=f"{label}: V̄ = {np.mean(v):.2f} m³")
        ax.axvline(float(np.mean(v)), color=colour, linewidth=1.0)
        if label in thesis_means_m3:
            ax.axvline(thesis_means_m3[label], color=colour, linestyle="--", linewidth=1.0)
    ax.plot([], [], color="k", linestyle="--", label="thesis V̄ (Tables 5–8)")
    ax.set_xlabel("cusp volume V [m³]")
    ax.set_ylabel("probability density [1/m³]")
    ax.set_title(title)
    ax.legend(fontsize="small")
    return figure


def plot_trend_spider(
    changes: dict[str, dict[str, float]],
    thesis_changes: dict[str, dict[str, float]],
    labels: list[str],
    title: str,
) -> Figure:
    """Spider diagram (thesis Fig. 25): 1 + the paired relative change of each output at each design point
    against the reference (solid: ours, dashed: the thesis' Tables 5–8); the unit circle is no influence."""
    figure = Figure(figsize=(7.5, 7.0), constrained_layout=True)
    ax = figure.add_subplot(1, 1, 1, projection="polar")
    angles = np.linspace(0.0, 2.0 * np.pi, len(labels), endpoint=False)
    closed = np.r_[angles, angles[:1]]
    colours = colormaps["tab10"](np.arange(max(len(changes), 1)) % 10)
    for colour, (point, values) in zip(colours, changes.items(), strict=False):
        ours = np.array([1.0 + values.get(k, np.nan) for k in labels])
        ax.plot(closed, np.r_[ours, ours[:1]], color=colour, label=point)
        if point in thesis_changes:
            theirs = np.array([1.0 + thesis_changes[point].get(k, np.nan) for k in labels])
            ax.plot(closed, np.r_[theirs, theirs[:1]], color=colour, linestyle="--", linewidth=0.9)
    ax.plot(closed, np.ones_like(closed), color="0.5", linewidth=0.6)
    ax.set_xticks(angles, labels)
    ax.set_title(title + "\nsolid: ours, dashed: thesis; radius = value / value at the reference")
    ax.legend(fontsize="small", loc="upper right", bbox_to_anchor=(1.25, 1.1))
    return figure


def plot_elasticities(rows: list[dict], outputs: list[tuple[str, str]], title: str) -> Figure:
    """Horizontal bars of the elasticity d ln(output)/d ln(input) of each output to each input (± s.e.)."""
    figure = Figure(figsize=(12.0, 1.2 + 0.35 * len(rows) * 2), constrained_layout=True)
    axes = figure.subplots(1, len(outputs), sharey=True, squeeze=False)[0]
    names = [row["input"] for row in rows]
    y = np.arange(len(rows))
    for ax, (key, label) in zip(axes, outputs, strict=True):
        values = np.array([row.get(f"{key}_value", np.nan) for row in rows], dtype=float)
        errors = np.array([row.get(f"{key}_se", np.nan) for row in rows], dtype=float)
        ax.barh(y, values, xerr=np.nan_to_num(errors), color="tab:blue")
        ax.axvline(0.0, color="k", linewidth=0.6)
        ax.set_title(label, fontsize="small")
    axes[0].set_yticks(y, names)
    axes[0].invert_yaxis()
    figure.suptitle(title)
    return figure


def plot_convergence(
    table: dict[str, dict[float, dict[str, float]]], outputs: list[tuple[str, str]]
) -> Figure:
    """Each output relative to its value at the finest setting, per swept numerical parameter."""
    figure = Figure(figsize=(5.0 * len(table), 4.0), constrained_layout=True)
    axes = figure.subplots(1, len(table), squeeze=False)[0]
    for ax, (parameter, by_value) in zip(axes, table.items(), strict=True):
        xs = sorted(by_value)
        for key, label in outputs:
            ys = [by_value[x].get(key, np.nan) for x in xs]
            ax.plot(xs, ys, marker="o", label=label)
        ax.axhspan(-0.02, 0.02, color="0.9")
        ax.set_xscale("log", base=2)
        ax.set_xlabel(parameter)
        ax.set_ylabel("relative to the finest setting")
        ax.legend(fontsize="x-small")
    figure.suptitle("Convergence (grey: ±2 %)")
    return figure
