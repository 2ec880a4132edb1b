"""Shaft figures: load and shaft torque series, their spectra, the measured comparison (as thesis Figs.
35/37, but shaft against shaft), the free-free mode shapes, the Campbell diagram and the rainflow
histogram (docs/shaft.md)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from floebreak.plotting.common import SPECTRUM_MARGINS_IN, add_legend, new_figure, page_fonts, with_note_line

MAX_PLOTTED_GROUPS = 3_000  # ≈ 2 groups per pixel column of the full series' axes at 150 dpi


def decimated(t, y, max_groups: int = MAX_PLOTTED_GROUPS):
    """(t, y) reduced to each group's minimum and maximum, in time order (groups of ⌈n/max_groups⌉
    consecutive samples; the last, shorter group as it is): drawn as a line at ≥ 1 group per pixel column,
    it covers the pixels the whole series covers, and every extreme is drawn."""
    t, y = np.asarray(t), np.asarray(y)
    group = max(1, int(np.ceil(y.size / max_groups)))
    n = y.size // group * group
    if group < 3 or n == 0:
        return t, y
    shaped = y[:n].reshape(-1, group)
    lo, hi = shaped.argmin(axis=1), shaped.argmax(axis=1)
    first, second = np.minimum(lo, hi), np.maximum(lo, hi)
    start = np.arange(0, n, group)
    keep = np.concatenate([np.stack([start + first, start + second], axis=1).ravel(), np.arange(n, y.size)])
    return t[keep], y[keep]


def plot_series(time_s, series_knm: dict[str, np.ndarray], title: str, zoom_s: float = 3.0) -> Figure:
    """Torque series [kN·m] over time [s] (long series `decimated` to their extremes per group) and, below,
    `zoom_s` seconds around the largest value of the last series, sample by sample."""
    with page_fonts(10.0):
        return _draw_series(time_s, series_knm, title, zoom_s)


def _draw_series(time_s, series_knm: dict[str, np.ndarray], title: str, zoom_s: float) -> Figure:
    figure = Figure(figsize=(10.0, 6.5), constrained_layout=True)
    full, zoom = figure.subplots(2, 1)
    time_s = np.asarray(time_s)
    last = np.asarray(list(series_knm.values())[-1])
    centre = time_s[int(np.argmax(last))] if last.size else 0.0
    window = (time_s >= centre - zoom_s / 2) & (time_s <= centre + zoom_s / 2)
    n = len(series_knm)
    for i, (label, y) in enumerate(series_knm.items()):
        y = np.asarray(y)
        # the first series (the propeller load, the narrower signal) on top, the later ones translucent
        # beneath it: the shaft's wider swing would otherwise hide it
        style = {"color": f"C{i}", "label": label, "zorder": 2 + n - i, "alpha": 1.0 if i == 0 else 0.6}
        full.plot(*decimated(time_s, y), lw=0.8 if i == 0 else 0.6, **style)
        zoom.plot(time_s[window], y[window], lw=1.2 if i == 0 else 0.9, **style)
    for ax in (full, zoom):
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("torque [kN m]")
        add_legend(ax)
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
    ax.set_xlim(*_occupied(edges_knm, densities.values()))
    if log:
        ax.set_yscale("log")
        positive = [d[d > 0] for d in (np.nan_to_num(np.asarray(v)) for v in densities.values())]
        low = min((p.min() for p in positive if p.size), default=threshold)
        ax.set_ylim(bottom=min(low, threshold) / 2.0)
    ax.set_xlabel("torque Q [kN m]")
    ax.set_ylabel("probability density [1/(kN m)]")
    ax.set_title(title, fontsize=9)
    add_legend(ax)
    return figure


def _occupied(edges, densities) -> tuple[float, float]:
    """(lower, upper) edge of the bins where any density is > 0, one bin of margin each side; all the edges
    when none is."""
    edges = np.asarray(edges, dtype=float)
    occupied = np.zeros(edges.size - 1, dtype=bool)
    for dens in densities:
        occupied |= np.nan_to_num(np.asarray(dens, dtype=float)) > 0
    if not occupied.any():
        return float(edges[0]), float(edges[-1])
    first, last = np.flatnonzero(occupied)[[0, -1]]
    return float(edges[max(first - 1, 0)]), float(edges[min(last + 2, edges.size - 1)])


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
    add_legend(ax)
    return figure


def plot_campbell(
    rpm_grid,
    natural_frequency_hz,
    blades: int,
    operating_rpm: float,
    margin: float,
    harmonics=(1, 2, 3),
) -> Figure:
    """Campbell diagram: blade-passage orders f = k·Z·n/60 [Hz] (k in `harmonics`, Z = `blades`) over
    the rpm grid [1/min], the natural frequencies as horizontal lines, the operating rpm with a shaded
    band of ± `margin` (a fraction) around it, and the crossings n = 60 f_j/(k Z), filled red where they
    lie inside the band (the resonance margin of `floebreak.shaft.resonance`: |f_j − f_k(n_op)| /
    f_k(n_op) < margin exactly when the crossing lies within n_op (1 ± margin))."""
    rpm = np.asarray(rpm_grid, dtype=float)
    f_n = np.asarray(natural_frequency_hz, dtype=float).reshape(-1)
    figure, ax = new_figure(7.5, 4.5, with_note_line(SPECTRUM_MARGINS_IN))
    band = (operating_rpm * (1.0 - margin), operating_rpm * (1.0 + margin))
    ax.axvspan(*band, color="0.85", lw=0, label=f"operating {operating_rpm:g} rpm ± {margin:.0%}")
    ax.axvline(operating_rpm, color="0.3", lw=0.8, ls=":")
    for i, k in enumerate(harmonics):
        ax.plot(rpm, k * blades * rpm / 60.0, color=f"C{i}", lw=1.2, label=f"order {k * blades} (k = {k})")
    inside, outside = [], []
    for j, f in enumerate(f_n):
        ax.axhline(f, color="0.2", lw=0.8, ls="--" if j % 2 == 0 else "-.", label=f"mode {j + 1}: {f:.2f} Hz")
        for k in harmonics:
            n_cross = 60.0 * f / (k * blades)
            if rpm.min() <= n_cross <= rpm.max():
                (inside if band[0] <= n_cross <= band[1] else outside).append((n_cross, f))
    marks = ((outside, "white", "crossing"), (inside, "#d62728", "crossing in the band"))
    for points, colour, label in marks:
        if points:
            x, y = np.array(points).T
            ax.plot(x, y, "o", mfc=colour, mec="k", ms=6, ls="none", label=label)
    top = max(float(f_n.max(initial=0.0)), max(harmonics) * blades * float(rpm.max()) / 60.0)
    ax.set_xlim(rpm.min(), rpm.max())
    ax.set_ylim(0.0, 1.1 * top)
    ax.set_xlabel("propeller speed n [1/min]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(
        f"Campbell diagram: blade-passage orders k·Z·n/60 (Z = {blades}) and natural frequencies\n"
        f"{len(inside)} crossing(s) within ± {margin:.0%} of the operating speed",
        fontsize=9,
    )
    add_legend(ax, loc="upper left")
    return figure


def plot_rainflow_histogram(range_edges_n_m, counts, title: str = "", damage: float | None = None) -> Figure:
    """Rainflow cycle counts (half cycles as 0.5) per torque-range bin [kN·m] on a log scale, and the
    cumulative number of cycles with a range at or above each bin's lower edge; `damage` (Miner's sum of
    the same cycles) in the title."""
    edges_knm = np.asarray(range_edges_n_m, dtype=float) / 1e3
    counts = np.asarray(counts, dtype=float)
    figure, ax = new_figure(7.5, 4.0, with_note_line(SPECTRUM_MARGINS_IN))
    ax.stairs(counts, edges_knm, fill=True, color="C0", alpha=0.7, label="cycles per bin")
    cumulative = np.cumsum(counts[::-1])[::-1]
    ax.step(edges_knm[:-1], cumulative, where="post", color="C1", lw=1.0, label="cycles with range ≥ x")
    if np.any(counts > 0):
        ax.set_yscale("log")
        ax.set_ylim(bottom=0.3)  # a half cycle (0.5) stays visible
    else:
        ax.text(0.5, 0.5, "no cycles", transform=ax.transAxes, ha="center")
    ax.set_xlabel("torque range ΔQ [kN m]")
    ax.set_ylabel("cycles [-]")
    summary = f"{counts.sum():g} cycles (rainflow, ASTM E1049)"
    if damage is not None:
        summary += f", Miner's damage D = {damage:.3g}"
    ax.set_title(f"{title}\n{summary}" if title else summary, fontsize=9)
    add_legend(ax)
    return figure
