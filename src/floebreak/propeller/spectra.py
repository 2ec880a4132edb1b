"""Load and torque spectra: probability density over force and torque per pitch (thesis Figs. 32–33, 35).

Densities are histograms normalised to unit area (``numpy.histogram(density=True)``) on fixed-width bins
starting at 0 (or at a multiple of the width below the smallest value for signed measured torque), in
1/kN and 1/(kN·m). A study's spectrum is the mean of its runs' densities, each run (floe field) weighted
equally, as the thesis averages over its four floe fields (Figs. 32–33). Simulated spectra use the load
magnitudes |F| and |Q|: the FEM torques are negative about the x-axis and the thesis multiplies them by −1
to compare with the shaft torque (Fig. 35).
"""

from __future__ import annotations

import math

import numpy as np

DENSITY_THRESHOLD_PER_KNM = 1e-3  # "probability density above 0.1 %" per kN·m (thesis §6.2)
MAX_BINS = 2_000  # more would mean loads far beyond the FEM table (e.g. `beyond="extrapolate"`)


def fitting_width(values, width: float) -> float:
    """`width`, or, when the finite |values| need more than `MAX_BINS` bins of it, the smallest 2-, 5- or
    10-fold multiple (then 20, 50, 100, …) that covers them in `MAX_BINS` bins.

    The quartic FEM interpolant extrapolated to thick ice gives torques of 10⁶ kN·m and more: 10 kN·m bins
    would then take minutes and gigabytes for a histogram that says nothing per bin. The widths used are
    recorded in the spectra's attributes.
    """
    values = np.abs(np.asarray(values, dtype=float))
    values = values[np.isfinite(values)]
    top = float(values.max()) if values.size else 0.0
    decade = 1.0
    while True:
        for mantissa in (1.0, 2.0, 5.0):
            if top / (width * mantissa * decade) <= MAX_BINS:
                return width * mantissa * decade
        decade *= 10.0


def bin_edges(values, width: float, start: float | None = None) -> np.ndarray:
    """Edges of width `width` from `start` (default 0, or lower for negative values) covering all values."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    lo = 0.0 if start is None else start
    if start is None and values.size and values.min() < 0.0:
        lo = math.floor(values.min() / width) * width
    hi = max(float(values.max()) if values.size else 0.0, lo + width)
    n = max(1, math.ceil((hi - lo) / width - 1e-12))
    if lo + n * width < hi:
        n += 1
    return lo + width * np.arange(n + 1)


def density(values, edges) -> np.ndarray:
    """Probability density of the finite `values` on `edges` (NaN everywhere if there are none)."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.full(len(edges) - 1, np.nan)
    counts, _ = np.histogram(values, bins=edges)
    inside = counts.sum()
    if inside == 0:
        return np.full(len(edges) - 1, np.nan)
    return counts / (inside * np.diff(edges))


def ranges_above(edges, dens, threshold: float) -> list[tuple[float, float]]:
    """Contiguous [lower, upper] intervals of the bins whose density exceeds `threshold`."""
    dens = np.nan_to_num(np.asarray(dens, dtype=float), nan=0.0)
    above = dens > threshold
    out = []
    i = 0
    while i < above.size:
        if above[i]:
            j = i
            while j + 1 < above.size and above[j + 1]:
                j += 1
            out.append((float(edges[i]), float(edges[j + 1])))
            i = j + 1
        else:
            i += 1
    return out


def envelope(intervals: list[tuple[float, float]]) -> tuple[float, float] | None:
    """(lowest lower edge, highest upper edge) of the intervals, None if empty."""
    if not intervals:
        return None
    return (intervals[0][0], intervals[-1][1])


def spectra_dataset(
    force_kn: dict[float, dict[str, np.ndarray]],
    torque_knm: dict[float, dict[str, np.ndarray]],
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    attrs: dict | None = None,
):
    """xarray Dataset of load and torque spectra.

    force_kn / torque_knm: {pitch_percent: {run_id: magnitudes}}. Dims (pitch, bin) for the run-averaged
    densities and (run, pitch, bin) for each run's; the bin coordinate counts bins of `force_bin_kn`
    (force) and `torque_bin_knm` (torque), both starting at 0, with centre and edge coordinates of each.
    """
    import xarray as xr

    pitches = sorted(force_kn)
    runs = sorted({r for p in pitches for r in force_kn[p]})
    all_f = np.concatenate([np.ravel(v) for p in pitches for v in force_kn[p].values()] + [np.zeros(0)])
    all_q = np.concatenate([np.ravel(v) for p in pitches for v in torque_knm[p].values()] + [np.zeros(0)])
    force_bin_kn, torque_bin_knm = fitting_width(all_f, force_bin_kn), fitting_width(all_q, torque_bin_knm)
    f_edges = bin_edges(all_f, force_bin_kn, start=0.0)
    q_edges = bin_edges(all_q, torque_bin_knm, start=0.0)
    n = max(f_edges.size, q_edges.size) - 1
    f_edges = force_bin_kn * np.arange(n + 1)
    q_edges = torque_bin_knm * np.arange(n + 1)
    f_run = np.full((len(runs), len(pitches), n), np.nan)
    q_run = np.full((len(runs), len(pitches), n), np.nan)
    counts = np.zeros((len(runs), len(pitches)), dtype=int)
    for j, p in enumerate(pitches):
        for i, r in enumerate(runs):
            f = np.asarray(force_kn[p].get(r, np.zeros(0)), dtype=float)
            q = np.asarray(torque_knm[p].get(r, np.zeros(0)), dtype=float)
            counts[i, j] = int(np.isfinite(f).sum())
            f_run[i, j] = density(f, f_edges)
            q_run[i, j] = density(q, q_edges)
    with np.errstate(all="ignore"):
        valid = np.isfinite(f_run).all(axis=2)  # runs with at least one load
        n_runs = valid.sum(axis=0)
        f_mean = np.where(
            n_runs[:, None] > 0, np.nansum(f_run, axis=0) / np.maximum(n_runs, 1)[:, None], np.nan
        )
        q_mean = np.where(
            n_runs[:, None] > 0, np.nansum(q_run, axis=0) / np.maximum(n_runs, 1)[:, None], np.nan
        )
    bins = np.arange(n)
    ds = xr.Dataset(
        data_vars={
            "force_density": (
                ("pitch", "bin"),
                f_mean,
                {"units": "1/kN", "long_name": "probability density of |F|, mean over runs"},
            ),
            "torque_density": (
                ("pitch", "bin"),
                q_mean,
                {"units": "1/(kN m)", "long_name": "probability density of |Q|, mean over runs"},
            ),
            "force_density_run": (("run", "pitch", "bin"), f_run, {"units": "1/kN"}),
            "torque_density_run": (("run", "pitch", "bin"), q_run, {"units": "1/(kN m)"}),
            "n_loads": (
                ("run", "pitch"),
                counts,
                {"units": "1", "long_name": "finite loads per run and pitch"},
            ),
            "n_runs_averaged": (("pitch",), n_runs.astype(int), {"units": "1"}),
        },
        coords={
            "pitch": (
                "pitch",
                np.asarray(pitches, dtype=float),
                {"units": "percent", "long_name": "pitch P_0.7%"},
            ),
            "bin": ("bin", bins),
            "run": ("run", np.asarray(runs, dtype=str)),
            "force_bin_lower_kn": ("bin", f_edges[:-1], {"units": "kN"}),
            "force_bin_upper_kn": ("bin", f_edges[1:], {"units": "kN"}),
            "force_bin_center_kn": ("bin", 0.5 * (f_edges[:-1] + f_edges[1:]), {"units": "kN"}),
            "torque_bin_lower_knm": ("bin", q_edges[:-1], {"units": "kN m"}),
            "torque_bin_upper_knm": ("bin", q_edges[1:], {"units": "kN m"}),
            "torque_bin_center_knm": ("bin", 0.5 * (q_edges[:-1] + q_edges[1:]), {"units": "kN m"}),
        },
        attrs={
            "force_bin_width_kn": float(force_bin_kn),
            "torque_bin_width_knm": float(torque_bin_knm),
            **(attrs or {}),
        },
    )
    return ds
