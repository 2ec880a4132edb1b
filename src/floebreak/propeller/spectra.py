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
from dataclasses import dataclass

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


def pitch_label(pitch: float) -> str:
    """Column suffix of a pitch: 95.0 → "p95"."""
    return f"p{pitch:g}"


def torque_ranges_above(ds, threshold_per_knm: float = DENSITY_THRESHOLD_PER_KNM) -> dict[str, dict]:
    """Per pitch label ("p0", "p95"): the torque intervals [kN·m] whose run-averaged density exceeds
    `threshold_per_knm` (the thesis' "probability density above 0.1 %", §6.2) and their envelope."""
    q_edges = spectrum_edges(ds, "torque")
    out = {}
    for pitch in ds["pitch"].values:
        intervals = ranges_above(q_edges, ds["torque_density"].sel(pitch=pitch).values, threshold_per_knm)
        out[pitch_label(float(pitch))] = {"intervals_knm": intervals, "envelope_knm": envelope(intervals)}
    return out


def finite_range(values) -> list[float] | None:
    """[min, max] of the finite values, None if there are none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return [float(values.min()), float(values.max())] if values.size else None


def spectrum_edges(ds, quantity: str) -> np.ndarray:
    """Bin edges [kN or kN·m] of the "force" or "torque" spectrum of a `spectra_dataset`."""
    bounds = ds[f"{_BIN[quantity]}_bounds"].values
    return np.r_[bounds[:, 0], bounds[-1:, 1]] if bounds.size else np.zeros(1)


@dataclass(frozen=True)
class SpectrumCurves:
    """The run-averaged density of one quantity ("force" or "torque") per pitch, as plain arrays: what the
    spectrum figures draw (`floebreak.plotting.propeller`), so that a figure process needs no xarray (and,
    where dask is installed, no dask, which xarray imports to index a Dataset)."""

    quantity: str
    edges: np.ndarray  # bin edges [kN or kN·m] (`spectrum_edges`)
    pitch_percent: np.ndarray
    density: np.ndarray  # (pitch, bin) [1/kN or 1/(kN·m)]; NaN where no run has a load
    n_runs: int  # runs in the Dataset (its "run" dimension)


def spectrum_curves(ds, quantity: str) -> SpectrumCurves:
    """The `SpectrumCurves` of the "force" or "torque" spectrum of a `spectra_dataset`."""
    return SpectrumCurves(
        quantity,
        spectrum_edges(ds, quantity),
        ds["pitch"].values,
        ds[f"{quantity}_density"].values,
        int(ds.sizes.get("run", 1)),
    )


FIGURE_MIN_BINS = 8  # a figure's histogram shows a shape, not one or two bars
FIGURE_MAX_BINS = 120  # about 5 pixels per bar at the figures' width


def figure_edges(values, min_bins: int = FIGURE_MIN_BINS, max_bins: int = FIGURE_MAX_BINS) -> np.ndarray:
    """Bin edges for a figure of the finite `values`, chosen from the data: numpy's "auto" rule (the
    smaller of the Sturges and Freedman–Diaconis widths) over [min, max], with at least `min_bins` and at
    most `max_bins` bins; [0, 1] without values. The spectra files keep their fixed widths (`bin_edges`),
    whose densities the thesis' 0.1 % threshold is read on."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.array([0.0, 1.0])
    lo, hi = float(values.min()), float(values.max())
    if hi <= lo:  # one value (or all equal): a bar of unit width around it
        return np.linspace(lo - 0.5, hi + 0.5, min_bins + 1)
    edges = np.histogram_bin_edges(values, bins="auto")
    n = min(max(edges.size - 1, min_bins), max_bins)
    return edges if n == edges.size - 1 else np.linspace(lo, hi, n + 1)


def figure_curves(quantity: str, values: dict[float, dict[str, np.ndarray]]) -> SpectrumCurves:
    """The run-averaged density of |F| [kN] ("force") or |Q| [kN·m] ("torque") per pitch on `figure_edges`
    of all pitches' values, every run weighted equally as in the spectra files. values: {pitch_percent:
    {run_id: magnitudes}}."""
    pitches = sorted(values)
    runs = sorted({r for per_run in values.values() for r in per_run})
    every = [np.asarray(v, dtype=float) for per_run in values.values() for v in per_run.values()]
    edges = figure_edges(np.concatenate(every) if every else np.zeros(0))
    _, _, mean, _ = _run_densities(values, pitches, runs, edges)
    return SpectrumCurves(quantity, edges, np.asarray(pitches, dtype=float), mean, len(runs))


_BIN = {"force": "force_kn", "torque": "torque_knm"}
_UNITS = {"force": "kN", "torque": "kN m"}
_DENSITY_UNITS = {"force": "kN-1", "torque": "kN-1 m-1"}


def _bin_coordinate(edges: np.ndarray, quantity: str) -> dict:
    """CF coordinate variable (bin centres) and its bounds variable for one load axis."""
    name = _BIN[quantity]
    what = "blade force |F|" if quantity == "force" else "ice torque |Q|"
    return {
        name: (
            name,
            0.5 * (edges[:-1] + edges[1:]),
            {"units": _UNITS[quantity], "long_name": f"{what}, bin centre", "bounds": f"{name}_bounds"},
        ),
        f"{name}_bounds": (
            (name, "nv"),
            np.stack([edges[:-1], edges[1:]], axis=1),
            {"units": _UNITS[quantity]},
        ),
    }


def _run_densities(values: dict[float, dict[str, np.ndarray]], pitches, runs, edges):
    """(run, pitch, bin) densities and counts, and the run-averaged density (runs without loads left out)."""
    dens = np.full((len(runs), len(pitches), edges.size - 1), np.nan)
    counts = np.zeros(dens.shape, dtype=np.int64)
    for j, p in enumerate(pitches):
        for i, r in enumerate(runs):
            v = np.asarray(values[p].get(r, np.zeros(0)), dtype=float)
            dens[i, j] = density(v, edges)
            counts[i, j] = np.histogram(v[np.isfinite(v)], bins=edges)[0]
    with np.errstate(all="ignore"):
        valid = np.isfinite(dens).all(axis=2)
        n_runs = valid.sum(axis=0)
        mean = np.where(n_runs[:, None] > 0, np.nansum(dens, axis=0) / np.maximum(n_runs, 1)[:, None], np.nan)
    return dens, counts, mean, n_runs


def spectra_dataset(
    force_kn: dict[float, dict[str, np.ndarray]],
    torque_knm: dict[float, dict[str, np.ndarray]],
    force_bin_kn: float = 10.0,
    torque_bin_knm: float = 10.0,
    attrs: dict | None = None,
):
    """CF-1.8 xarray Dataset of the load and torque spectra.

    force_kn / torque_knm: {pitch_percent: {run_id: magnitudes}}. The force and torque axes are separate
    dimensions (``force_kn``, ``torque_knm``: bin centres with ``*_bounds`` variables), both starting at 0
    with bins of `force_bin_kn` / `torque_bin_knm` (widened by `fitting_width` for far loads). Variables:
    run-averaged densities ``force_density(pitch, force_kn)``, ``torque_density(pitch, torque_knm)``, each
    run's densities and counts, ``n_loads(run, pitch)``. Every numeric variable carries UDUNITS units.
    """
    import xarray as xr

    pitches = sorted(force_kn)
    runs = sorted({r for p in pitches for r in force_kn[p]})
    all_f = np.concatenate([np.ravel(v) for p in pitches for v in force_kn[p].values()] + [np.zeros(0)])
    all_q = np.concatenate([np.ravel(v) for p in pitches for v in torque_knm[p].values()] + [np.zeros(0)])
    force_bin_kn, torque_bin_knm = fitting_width(all_f, force_bin_kn), fitting_width(all_q, torque_bin_knm)
    edges = {
        "force": bin_edges(all_f, force_bin_kn, start=0.0),
        "torque": bin_edges(all_q, torque_bin_knm, 0.0),
    }
    data_vars = {}
    for quantity, values in (("force", force_kn), ("torque", torque_knm)):
        dens, counts, mean, n_runs = _run_densities(values, pitches, runs, edges[quantity])
        axis, what = _BIN[quantity], "|F|" if quantity == "force" else "|Q|"
        unit = _DENSITY_UNITS[quantity]
        data_vars[f"{quantity}_density"] = (
            ("pitch", axis),
            mean,
            {"units": unit, "long_name": f"probability density of {what}, mean over runs"},
        )
        data_vars[f"{quantity}_density_run"] = (
            ("run", "pitch", axis),
            dens,
            {"units": unit, "long_name": f"probability density of {what} per run"},
        )
        data_vars[f"{quantity}_count_run"] = (
            ("run", "pitch", axis),
            counts,
            {"units": "1", "long_name": f"number of cusps per {what} bin and run"},
        )
        if quantity == "force":  # loads are finite for both or neither
            data_vars["n_loads"] = (
                ("run", "pitch"),
                counts.sum(axis=2),
                {"units": "1", "long_name": "cusps with a finite load per run"},
            )
            data_vars["n_runs_averaged"] = (("pitch",), n_runs.astype(np.int64), {"units": "1"})
    coords = {
        "pitch": (
            "pitch",
            np.asarray(pitches, dtype=float),
            {"units": "percent", "long_name": "pitch P_0.7%"},
        ),
        "run": ("run", np.asarray(runs, dtype=str), {"long_name": "run (floe field) identifier"}),
        **_bin_coordinate(edges["force"], "force"),
        **_bin_coordinate(edges["torque"], "torque"),
    }
    return xr.Dataset(
        data_vars=data_vars,
        coords=coords,
        attrs={
            "Conventions": "CF-1.8",
            "force_bin_width_kn": float(force_bin_kn),
            "torque_bin_width_knm": float(torque_bin_knm),
            **(attrs or {}),
        },
    )
