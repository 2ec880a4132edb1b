"""Fatigue of the shaft line: rainflow cycles of a torque series and Miner's damage against a Basquin S–N
curve (docs/shaft.md "Fatigue of the shaft line").

Counting: ASTM E1049-85 (2011) §5.4.4 rainflow counting, through the `rainflow` package
(`rainflow.extract_cycles`): every cycle has a range (peak to valley), a mean and a count of 1.0, or 0.5
for a half cycle of the residue that the standard counts at the end. The counting is the library's; this
module bins, sums and applies Palmgren–Miner.

Damage: D = Σ n_i / N(S_i) (Palmgren–Miner linear rule) with N(S) = N_ref (S_ref / S)^m the user's
`floebreak.propeller.ruleform.BasquinCurve` (`--sn-curve torque,M,AMPLITUDE,CYCLES`). The curve's
reference is an *amplitude* (half the range) by default, as the option says; `measure="range"` takes
it as a range (the convention of e.g. DNV-RP-C203 curves). No mean-stress correction: the S–N curve is
taken to hold at the series' own mean torque (a correction such as Goodman's needs the material's
ultimate strength and a stress, not a torque, and the `rainflow` package gives none).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import rainflow

from floebreak.errors import InputError, require_range
from floebreak.propeller.ruleform import BasquinCurve

SN_MEASURES = ("amplitude", "range")


@dataclass(frozen=True)
class RainflowCycles:
    """Rainflow cycles of a torque series: range, mean [N·m] and count (1.0 full, 0.5 half) per cycle."""

    range_n_m: np.ndarray
    mean_n_m: np.ndarray
    count: np.ndarray

    @property
    def amplitude_n_m(self) -> np.ndarray:
        """Half the range."""
        return self.range_n_m / 2.0

    @property
    def total_count(self) -> float:
        return float(self.count.sum())


@dataclass(frozen=True)
class RainflowHistogram:
    """Cycle counts binned by range: `counts[i]` cycles (half cycles as 0.5) with a range in
    [range_edges_n_m[i], range_edges_n_m[i + 1]) (the last bin closed), and the cycles themselves."""

    cycles: RainflowCycles
    range_edges_n_m: np.ndarray
    counts: np.ndarray

    def as_dict(self) -> dict:
        """JSON-ready, in kN·m (units in the keys)."""
        return {
            "range_edges_kn_m": (self.range_edges_n_m / 1e3).tolist(),
            "cycle_counts": self.counts.tolist(),
            "n_cycles": self.cycles.total_count,
            "max_range_kn_m": float(self.cycles.range_n_m.max() / 1e3) if self.cycles.count.size else None,
            "counting": "rainflow, ASTM E1049-85 §5.4.4 (package rainflow); half cycles count 0.5",
        }


def rainflow_cycles(torque_n_m) -> RainflowCycles:
    """The rainflow cycles of a torque series [N·m] (ASTM E1049-85 §5.4.4, `rainflow.extract_cycles`),
    without cycles of zero range."""
    series = np.asarray(torque_n_m, dtype=float).ravel()
    if not np.all(np.isfinite(series)):
        raise InputError("torque_n_m", "the series has values that are not finite", allowed="finite numbers")
    rows = list(rainflow.extract_cycles(series.tolist())) if series.size >= 2 else []
    table = np.asarray([row[:3] for row in rows], dtype=float).reshape(-1, 3)
    table = table[table[:, 0] > 0.0]  # a constant series yields one half cycle of range 0
    return RainflowCycles(table[:, 0], table[:, 1], table[:, 2])


def rainflow_histogram(torque_n_m, range_bin_n_m: float) -> RainflowHistogram:
    """Rainflow-count a torque series [N·m] and bin the cycles by range in bins of `range_bin_n_m` [N·m]
    from 0 to the largest range (at least one bin)."""
    require_range("range_bin_n_m", range_bin_n_m, low=0.0, unit="N·m")
    cycles = rainflow_cycles(torque_n_m)
    top = float(cycles.range_n_m.max()) if cycles.count.size else 0.0
    n_bins = max(1, int(np.ceil(top / range_bin_n_m - 1e-12)))
    edges = np.arange(n_bins + 1) * float(range_bin_n_m)
    counts, _ = np.histogram(cycles.range_n_m, bins=edges, weights=cycles.count)
    return RainflowHistogram(cycles, edges, counts)


def miner_damage(cycles: RainflowCycles, sn_curve: BasquinCurve, measure: str = "amplitude") -> float:
    """Palmgren–Miner damage D = Σ n_i / N(S_i) of rainflow cycles on a torque S–N curve.

    S_i is the cycle's amplitude (range / 2) with `measure="amplitude"` (the `--sn-curve` convention,
    N(S) = CYCLES · (AMPLITUDE / S)^M) or its range with `measure="range"`; n_i is 1 or 0.5. Cycles of
    zero range are not counted. No mean-stress correction (module docstring)."""
    if sn_curve.quantity != "torque":
        raise InputError("sn_curve.quantity", f"{sn_curve.quantity!r} on a shaft torque", allowed="torque")
    if measure not in SN_MEASURES:
        raise InputError("measure", f"unknown {measure!r}", allowed=", ".join(SN_MEASURES))
    stress = cycles.range_n_m if measure == "range" else cycles.amplitude_n_m
    return float(np.sum(cycles.count / sn_curve.cycles_to_failure(stress)))
