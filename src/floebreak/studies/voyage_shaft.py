"""Shaft torque over a voyage (`floebreak voyage --shaft-line`): the shaft analysis of every complete run
(`floebreak.app.shaft.shaft_analysis_of_run`: the run's speed and profile choose the model, as
`floebreak propeller --shaft-line` does), summarised per period and pooled by time (docs/studies.md,
"Voyages"):

- per period p: the largest and smallest shaft torque of its runs (first excitation case), the simulated
  time S_p (the runs' series, summed) and, per level q, the time above it, A_p(q);
- the voyage: the largest and smallest over the periods; the share of time above q,
  P(q) = Σ_p T_p A_p(q)/S_p / Σ_p T_p (T_p: the period's hours in ice), and the hours above q over the
  voyage, Σ_p T_p A_p(q)/S_p; rainflow cycles per hour Σ_p T_p C_p/S_p / Σ_p T_p likewise (C_p: the
  cycles of range ≥ 10 kN·m).

A period without complete runs adds neither time nor torque. The series stand for the period's ice
conditions: its runs are L ≤ D long, so a period's extremes are those of the simulated stretch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.io.writers import rows_to_columns, write_csv, write_json

# level spacing of the pooled exceedance and the smallest rainflow range counted [kN·m] (the spectra's bin
# width; smaller ranges are the solver's ripple on a series without ice, not load cycles)
LEVEL_STEP_KNM = 10.0


@dataclass(frozen=True)
class RunShaft:
    """The shaft torque series of one run (first excitation case) [kN·m], its time step [s] and its rainflow
    cycles with a range ≥ `LEVEL_STEP_KNM`."""

    torque_knm: np.ndarray
    time_step_s: float
    n_cycles: float
    model: str
    station: str

    @property
    def duration_s(self) -> float:
        return self.torque_knm.size * self.time_step_s


def run_shaft(run_dir: Path, shaft_line: str, transport: dict[str, Any] | None = None) -> RunShaft:
    """The shaft analysis of one run (`shaft_analysis_of_run`, its defaults, with the transport settings
    `transport`: `propeller.transport.TRANSPORT_KEYS` → value, as the voyage's propeller analysis), reduced
    to `RunShaft`."""
    from floebreak.app.shaft import shaft_analysis_of_run
    from floebreak.propeller.transport import transport_settings
    from floebreak.shaft.analysis import shaft_fatigue

    settings = transport_settings(transport)
    result = shaft_analysis_of_run(run_dir, shaft_line, transport_settings=settings).result
    t = result.time_s
    step = float(t[1] - t[0]) if t.size > 1 else 0.0
    cycles = shaft_fatigue(result)[0].cycles
    counted = float(np.sum(cycles.count[cycles.range_n_m >= 1e3 * LEVEL_STEP_KNM]))
    return RunShaft(result.shaft_torque_n_m[0] / 1e3, step, counted, result.model, result.station)


def time_above(torque_knm: np.ndarray, time_step_s: float, levels_knm: np.ndarray) -> np.ndarray:
    """Time [s] the series spends at or above each level (uniform time step)."""
    ordered = np.sort(torque_knm)
    return (ordered.size - np.searchsorted(ordered, levels_knm, side="left")) * time_step_s


def pool_periods(periods: list[dict], shafts: dict[int, list[RunShaft]]) -> dict[str, Any]:
    """Per period and pooled over the voyage by time (module docstring). `periods`: index and duration_h;
    `shafts`: period index → its runs' `RunShaft`."""
    done = {p: runs for p, runs in shafts.items() if runs and sum(r.duration_s for r in runs) > 0.0}
    values = [r.torque_knm for runs in done.values() for r in runs if r.torque_knm.size]
    every = np.concatenate(values) if values else np.zeros(0)
    if every.size:
        low = math.floor(every.min() / LEVEL_STEP_KNM) * LEVEL_STEP_KNM
        levels = np.arange(low, every.max() + LEVEL_STEP_KNM, LEVEL_STEP_KNM)
    else:
        levels = np.zeros(0)
    rows, hours_above, cycles, hours = [], np.zeros(levels.size), 0.0, 0.0
    for period in periods:
        runs = done.get(period["index"], [])
        simulated_s = sum(r.duration_s for r in runs)
        row = {"index": period["index"], "duration_h": period["duration_h"], "runs": len(runs)}
        row["simulated_s"] = simulated_s
        row["max_shaft_torque_knm"] = max((float(r.torque_knm.max()) for r in runs), default=math.nan)
        row["min_shaft_torque_knm"] = min((float(r.torque_knm.min()) for r in runs), default=math.nan)
        row["cycles_per_hour"] = math.nan
        if runs:
            above_s = sum(time_above(r.torque_knm, r.time_step_s, levels) for r in runs)
            hours_above += period["duration_h"] * above_s / simulated_s
            n_cycles = sum(r.n_cycles for r in runs)
            row["cycles_per_hour"] = n_cycles / (simulated_s / 3600.0)
            cycles += period["duration_h"] * row["cycles_per_hour"]
            hours += period["duration_h"]
        rows.append(row)
    finite = [r for r in rows if r["runs"]]
    return {
        "hours": hours,
        "max_shaft_torque_knm": max((r["max_shaft_torque_knm"] for r in finite), default=None),
        "min_shaft_torque_knm": min((r["min_shaft_torque_knm"] for r in finite), default=None),
        "cycles_per_hour": cycles / hours if hours else None,
        "cycle_range_min_knm": LEVEL_STEP_KNM,
        "periods": rows,
        "exceedance": {
            "level_knm": levels,
            "hours_above": hours_above,
            "time_share_above": hours_above / hours if hours else np.full(levels.size, np.nan),
        },
    }


@dataclass(frozen=True)
class VoyageShaft:
    """The voyage's shaft statistics (`summary`), written by `write`."""

    summary: dict[str, Any]

    def write(self, folder: Path) -> None:
        """shaft_periods.csv, shaft_exceedance.csv and summary.json into the new `folder`."""
        folder.mkdir()
        write_csv(folder / "shaft_periods.csv", rows_to_columns(self.summary["periods"]), [NOTE])
        exceedance = self.summary["exceedance"]
        write_csv(folder / "shaft_exceedance.csv", exceedance, [NOTE])
        write_json(folder / "summary.json", self.summary)


NOTE = "shaft torque (first excitation case) per period and pooled by the periods' hours in ice"


def voyage_shaft(
    voyage_dir: Path,
    periods: list[dict],
    rows: list[dict],
    shaft_line: str,
    transport: dict[str, Any] | None = None,
) -> VoyageShaft:
    """The shaft analysis of each complete run of each period (a run shared by periods is analysed once),
    pooled by time (`pool_periods`). `rows`: the period table (its `n_fields_complete`); `transport`: the
    voyage's transport settings (`VoyageAnalysis.transport`)."""
    cache: dict[str, RunShaft] = {}
    shafts: dict[int, list[RunShaft]] = {}
    for period, row in zip(periods, rows, strict=True):
        shafts[period["index"]] = []
        if not row["n_fields_complete"]:
            continue
        for name in period["runs"]:
            run_dir = voyage_dir / "runs" / name
            if not (run_dir / "summary.json").exists():
                continue
            if name not in cache:
                cache[name] = run_shaft(run_dir, shaft_line, transport)
            shafts[period["index"]].append(cache[name])
    summary = pool_periods(periods, shafts)
    models = sorted({s.model for s in cache.values()})
    stations = sorted({s.station for s in cache.values()})
    summary = {"shaft_line": str(shaft_line), "model": models, "station": stations, "note": NOTE} | summary
    return VoyageShaft(summary)
