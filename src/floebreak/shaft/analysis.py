"""Shaft-torque analysis of the cusps of a run: excitation per rule case → shaft torque at a station.

`shaft_response` is pure and takes plain per-cusp arrays (bow position, torque amplitude, thickness), so
a voyage or a notebook can call it directly; `run_cusp_inputs` gets those arrays from a run directory
(cusps.parquet, the FEM torque interpolation of floebreak.propeller). See docs/shaft.md.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.cusps import CUSPS_FILE, box_dimensions
from floebreak.propeller.fem import resolve_fem_tables
from floebreak.propeller.interpolation import check_options, table_interpolant
from floebreak.propeller.pipeline import DEFAULT_VOLUME_BASIS, VOLUME_BASES
from floebreak.propeller.spec import PropellerSpec
from floebreak.propeller.spectra import (
    DENSITY_THRESHOLD_PER_KNM,
    bin_edges,
    density,
    envelope,
    fitting_width,
    ranges_above,
)
from floebreak.shaft.excitation import arrival_times_s, excitation_case, ice_torque_series
from floebreak.shaft.line import Modes, ShaftLine, modal_analysis, with_operating_point
from floebreak.shaft.response import station_torque_n_m


@dataclass(frozen=True)
class ShaftResult:
    """Propeller load torque and shaft torque at `station`, one row per excitation case [N·m]."""

    line: ShaftLine  # at the operating point used (rpm, mean torque)
    station: str
    cases: tuple[int, ...]
    blades: int
    speed_m_s: float
    samples_per_blade_passage: int
    time_s: np.ndarray
    load_torque_n_m: np.ndarray  # (case, time): mean hydrodynamic + ice torque at the propeller
    shaft_torque_n_m: np.ndarray  # (case, time)
    modes: Modes
    n_cusps: int
    overlap: str = "queue"

    @property
    def mean_torque_n_m(self) -> float:
        return self.line.mean_torque()

    def peaks(self) -> dict[int, dict[str, float]]:
        """Per case: Q_peak (largest shaft torque), the smallest, the largest load torque and the dynamic
        amplification of the ice part (Q_peak − Q_mean)/(max load − Q_mean) [N·m, −]."""
        out = {}
        q_mean = self.mean_torque_n_m
        for c, load, shaft in zip(self.cases, self.load_torque_n_m, self.shaft_torque_n_m, strict=True):
            ice_peak = float(load.max()) - q_mean if load.size else 0.0
            peak = float(shaft.max()) if shaft.size else q_mean
            out[c] = {
                "q_peak_n_m": peak,
                "q_min_n_m": float(shaft.min()) if shaft.size else q_mean,
                "load_peak_n_m": float(load.max()) if load.size else q_mean,
                "dynamic_amplification": (peak - q_mean) / ice_peak if ice_peak > 0.0 else None,
            }
        return out


def shaft_response(
    bow_x_m,
    torque_amplitude_n_m,
    thickness_m,
    line: ShaftLine,
    *,
    speed_m_s: float,
    rpm: float | None = None,
    mean_torque_n_m: float | None = None,
    blades: int = PropellerSpec().blades,
    cases=(1, 2, 3, 4),
    station: str | None = None,
    samples_per_blade_passage: int = 40,
    lead_s: float = 2.0,
    tail_s: float = 5.0,
    overlap: str = "queue",
) -> ShaftResult:
    """Excitation (floebreak.shaft.excitation) and shaft torque (floebreak.shaft.response) per case.

    Plain arrays per cusp, in any order: bow position when the cusp broke off [m], torque amplitude [N·m]
    (its magnitude is used), thickness [m]. `rpm`/`mean_torque_n_m` override the line's operating point.
    """
    line = with_operating_point(line, rpm, mean_torque_n_m)
    station_name = line.stations[line.station_index(station)]
    cases = tuple(int(excitation_case(c).number) for c in cases)
    if not cases:
        raise InputError("excitation_case", "no case given", allowed="1, 2, 3, 4")
    require_range("speed_m_s", speed_m_s, low=0.0, unit="m/s")
    arrival = arrival_times_s(bow_x_m, speed_m_s, lead_s)
    q_mean = line.mean_torque()
    loads, shafts, time_s = [], [], None
    duration = None
    for case in cases:
        t, ice = ice_torque_series(
            arrival,
            torque_amplitude_n_m,
            thickness_m,
            rpm=line.rpm,
            blades=blades,
            case=case,
            samples_per_blade_passage=samples_per_blade_passage,
            tail_s=tail_s,
            duration_s=duration,
            overlap=overlap,
        )
        if time_s is None:  # every case on the first case's time axis
            time_s, duration = t, float(t[-1]) if t.size else 0.0
        load = q_mean + ice
        loads.append(load)
        shafts.append(
            station_torque_n_m(
                line, load, 60.0 / (line.rpm * blades * samples_per_blade_passage), station_name
            )
        )
    return ShaftResult(
        line=line,
        station=station_name,
        cases=cases,
        blades=int(blades),
        speed_m_s=float(speed_m_s),
        samples_per_blade_passage=int(samples_per_blade_passage),
        time_s=time_s,
        load_torque_n_m=np.vstack(loads),
        shaft_torque_n_m=np.vstack(shafts),
        modes=modal_analysis(line),
        n_cusps=int(np.size(bow_x_m)),
        overlap=overlap,
    )


def run_cusp_inputs(
    run_dir: str | os.PathLike[str],
    *,
    fem_table=None,
    pitch_percent: float | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    volume_basis: str = DEFAULT_VOLUME_BASIS,
) -> dict[str, np.ndarray | float]:
    """Per cusp of a run, in transit order: ``bow_x_m``, ``thickness_m`` and ``torque_n_m`` (FEM torque
    of the cusp's volume, "actual" area × thickness or "box", as the propeller analysis, thesis §6.1.3,
    for the table nearest `pitch_percent`, default the propeller's 95.86 %), and the ``pitch_percent``
    of that table."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    check_options(interpolation, beyond)
    if volume_basis not in VOLUME_BASES:
        raise InputError("volume_basis", f"unknown value {volume_basis!r}", allowed=", ".join(VOLUME_BASES))
    path = Path(run_dir) / CUSPS_FILE
    if not path.is_file():
        raise InputError(
            "run_dir",
            f"no {CUSPS_FILE} in {str(run_dir)!r}",
            value=str(run_dir),
            allowed="a run directory (the shaft analysis needs one run's transit order)",
        )
    needed = ("bow_x_m", "step", "bbox_length_m", "bbox_width_m", "thickness_m", "volume_m3")
    try:
        parquet = pq.ParquetFile(path)
        missing = [c for c in needed if c not in parquet.schema_arrow.names]
        table = None if missing else parquet.read(columns=list(needed))
    except (OSError, pa.ArrowInvalid) as error:
        raise InputError("run_dir", f"cannot read {str(path)!r}: {error}", value=str(path)) from None
    if missing:
        raise InputError("run_dir", f"{str(path)!r} lacks column(s) {', '.join(missing)}", value=str(path))
    col = {c: table.column(c).to_numpy().astype(float) for c in needed}
    order = np.lexsort((col["step"], col["bow_x_m"]))
    tables = resolve_fem_tables(fem_table)
    target = PropellerSpec().pitch_percent if pitch_percent is None else float(pitch_percent)
    pitch = min(tables, key=lambda p: abs(p - target))
    longer, shorter, box_volume = box_dimensions(
        col["bbox_length_m"], col["bbox_width_m"], col["thickness_m"]
    )
    coordinates = {  # as the propeller analysis evaluates its tables (volume, box sides, thickness)
        "volume": box_volume if volume_basis == "box" else col["volume_m3"],
        "length": longer,
        "width": shorter,
        "thickness": col["thickness_m"],
        "height": col["thickness_m"],
    }
    torque, _ = table_interpolant(tables[pitch], "torque", interpolation, beyond)(coordinates)
    return {
        "bow_x_m": col["bow_x_m"][order],
        "thickness_m": col["thickness_m"][order],
        "torque_n_m": torque[order],
        "pitch_percent": float(pitch),
    }


def run_ship_speed_m_s(run_dir: str | os.PathLike[str]) -> float | None:
    """``ship.speed_m_s`` of the run's scenario.resolved.toml, None if the key (or file) is absent."""
    path = Path(run_dir) / "scenario.resolved.toml"
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except (OSError, tomllib.TOMLDecodeError):
        return None
    value = data.get("ship", {}).get("speed_m_s")
    return None if value is None else float(value)


def torque_densities(series_knm: dict[str, np.ndarray], bin_knm: float = 10.0):
    """Common bin edges [kN·m] over all `series_knm` (signed values) and each series' probability density
    [1/(kN·m)], its intervals above 0.1 %/(kN·m) and their envelope (thesis §6.2 comparison)."""
    values = np.concatenate([np.ravel(v) for v in series_knm.values()] + [np.zeros(0)])
    edges = bin_edges(values, fitting_width(values, bin_knm))
    out = {}
    for name, v in series_knm.items():
        dens = density(v, edges)
        intervals = ranges_above(edges, dens, DENSITY_THRESHOLD_PER_KNM)
        out[name] = {"density": dens, "intervals_knm": intervals, "envelope_knm": envelope(intervals)}
    return edges, out
