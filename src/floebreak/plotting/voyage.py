"""Figures of a voyage: load rates per level, exceedance per hour, timeline of the periods."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

UNITS = {"force": "kN", "torque": "kN·m"}
SYMBOLS = {"force": "|F|", "torque": "|Q|"}


def _case_label(case: str) -> str:
    return "as operated (nearest FEM pitch)" if case == "operated" else f"pitch {case[1:]} %"


def _case_style(case: str) -> dict[str, Any]:
    """Dashed black for "operated": it often equals one FEM pitch's line, which must stay visible."""
    return {"color": "black", "linestyle": "--"} if case == "operated" else {}


def plot_rate_spectrum(data: dict[str, dict[str, Any]], quantity: str) -> Figure:
    """Loads per hour in ice per bin of |F| or |Q| (time-weighted over the periods), one line per case."""
    figure = Figure(figsize=(8.0, 4.0), constrained_layout=True)
    axes = figure.add_subplot(1, 1, 1)
    for case, spectrum in data.items():
        edges, rate = spectrum["edges"], spectrum["per_hour"]
        if not np.any(rate > 0):
            continue
        axes.stairs(np.where(rate > 0, rate, np.nan), edges, label=_case_label(case), **_case_style(case))
    axes.set_yscale("log")
    width = next(iter(data.values()))["width"] if data else 0.0
    axes.set_xlabel(f"{SYMBOLS[quantity]} [{UNITS[quantity]}]")
    axes.set_ylabel(f"loads per hour in ice per {width:g} {UNITS[quantity]} bin")
    axes.set_title(f"Voyage {quantity} spectrum (time-weighted over the periods)")
    if axes.lines or axes.patches:
        axes.legend()
    return figure


def plot_exceedance(data: dict[tuple[str, str], dict[str, Any]], hours: float) -> Figure:
    """Number of loads per hour in ice at or above each level, for |F| and |Q| (log scale)."""
    figure = Figure(figsize=(10.0, 4.0), constrained_layout=True)
    axes_of = {q: figure.add_subplot(1, 2, i + 1) for i, q in enumerate(UNITS)}
    for (case, quantity), spectrum in data.items():
        axes = axes_of[quantity]
        per_hour = spectrum["exceedances"] / hours if hours else spectrum["exceedances"] * np.nan
        levels = spectrum["edges"][:-1]
        keep = per_hour > 0
        if keep.any():
            axes.step(
                levels[keep], per_hour[keep], where="post", label=_case_label(case), **_case_style(case)
            )
    for quantity, axes in axes_of.items():
        axes.set_yscale("log")
        axes.set_xlabel(f"{SYMBOLS[quantity]} [{UNITS[quantity]}]")
        axes.set_ylabel("exceedances per hour in ice")
        axes.set_title(f"{quantity}: loads ≥ level")
        if axes.lines:
            axes.legend(fontsize="small")
    return figure


def plot_timeline(rows: list[dict[str, Any]]) -> Figure:
    """The periods one after the other (hours in ice, gaps between periods left out; dashed lines at the
    period boundaries):
    concentration, mean thickness, cusps per hour and the mean operated |Q| per period."""
    figure = Figure(figsize=(10.0, 7.0), constrained_layout=True)
    panels = (
        ("concentration_percent", "c [%]"),
        ("mean_thickness_m", "h [m]"),
        ("cusps_per_hour", "cusps per hour"),
        ("mean_torque_knm", "mean |Q| [kN·m]"),
    )
    axes_list = [figure.add_subplot(len(panels), 1, i + 1) for i in range(len(panels))]
    starts = np.concatenate([[0.0], np.cumsum([row["duration_h"] for row in rows])])
    for axes, (key, label) in zip(axes_list, panels, strict=True):
        values = np.array([np.nan if row[key] is None else row[key] for row in rows], dtype=float)
        axes.bar(starts[:-1], np.nan_to_num(values), width=np.diff(starts), align="edge", edgecolor="white")
        axes.set_ylabel(label)
        for x in starts[1:-1]:  # period boundaries
            axes.axvline(x, color="grey", linestyle="--", linewidth=0.6)
        axes.set_xlim(0.0, starts[-1] if starts[-1] > 0 else 1.0)
    axes_list[0].set_title("Voyage timeline: ice conditions and load rates per observation period")
    bottom = axes_list[-1]
    bottom.set_xticks(0.5 * (starts[:-1] + starts[1:]))
    bottom.set_xticklabels([row["start_utc"][:16].replace("T", "\n") for row in rows], fontsize="small")
    bottom.set_xlabel("observation period (start, UTC); bar width = duration, hours in ice")
    for axes in axes_list[:-1]:
        axes.set_xticklabels([])
    return figure
