"""Shaft-torque analysis of the cusps of a run: excitation per rule case → shaft torque at a station.

`shaft_response` is pure and takes plain per-cusp arrays (bow position, torque amplitude, thickness), so
a voyage or a notebook can call it directly; `cusp_torque_inputs` gets those arrays from a run's cusp
columns (read by `floebreak.app.shaft.run_cusp_inputs`; the FEM torque interpolation of floebreak.propeller).
See docs/shaft.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from floebreak.errors import InputError, require_range
from floebreak.propeller.cusps import box_dimensions
from floebreak.propeller.interpolation import check_options, table_interpolant
from floebreak.propeller.load_models import PLACEMENT_ENGAGED, PLACEMENT_TIP, engaged_intervals
from floebreak.propeller.loads.fem import DEFAULT_VOLUME_BASIS, VOLUME_BASES, fem_table_dict
from floebreak.propeller.loads.milling import BladeGeometry, IceBlock, impact_loads
from floebreak.propeller.ruleform import BasquinCurve
from floebreak.propeller.spec import PropellerSpec
from floebreak.propeller.spectra import (
    DENSITY_THRESHOLD_PER_KNM,
    bin_edges,
    density,
    envelope,
    fitting_width,
    ranges_above,
)
from floebreak.propeller.transport import PropellerArrangement, TransportSettings, transport_cusps
from floebreak.shaft.drive import DriveResult, drive_for_line, simulate_drive, train_from_line
from floebreak.shaft.excitation import (
    EXCITATION_CASES,
    arrival_times_s,
    excitation_case,
    ice_torque_series,
    mean_torque_per_passage_n_m,
)
from floebreak.shaft.fatigue import RainflowHistogram, miner_damage, rainflow_histogram
from floebreak.shaft.impact_torque import CuspTorques
from floebreak.shaft.line import Modes, ShaftLine, modal_analysis, with_operating_point
from floebreak.shaft.resonance import DEFAULT_REQUIRED_MARGIN, campbell
from floebreak.shaft.response import station_torque_n_m

SHAFT_MODELS = ("drive", "linear")
PROFILE_SHAFT_MODEL = {"default": "drive", "thesis": "linear"}


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
    model: str = "linear"  # "drive": torque-limited PI motor (shaft.drive); "linear": constant rpm
    rpm: np.ndarray | None = None  # (case, time), drive model only: propeller rpm
    motor_torque_n_m: np.ndarray | None = None  # (case, time), drive model only
    drive_summaries: tuple[dict, ...] = ()  # per case, drive model only (`drive_case_summary`)
    torque_limit_n_m: float | None = None  # drive model only

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
    progress: Callable[[str, int, int], None] | None = None,
) -> ShaftResult:
    """Excitation (floebreak.shaft.excitation) and shaft torque (floebreak.shaft.response) per case.

    Plain arrays per cusp, in any order: bow position when the cusp broke off [m], torque amplitude [N·m]
    (its magnitude is used), thickness [m]. `rpm`/`mean_torque_n_m` override the line's operating point.
    `progress(stage, done, total)`, if given, is called after each case (`report_case`).
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
        report_case(progress, cases, len(loads))
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


def shaft_drive_response(
    arrival_s,
    n_impacts,
    impact_torque_n_m: Callable[[int, float], float],
    line: ShaftLine,
    *,
    speed_m_s: float,
    rpm: float | None = None,
    mean_torque_n_m: float | None = None,
    torque_limit_n_m: float | None = None,
    blades: int = PropellerSpec().blades,
    cases=(1, 2, 3, 4),
    station: str | None = None,
    tail_s: float = 5.0,
    n_cusps: int | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> ShaftResult:
    """The drive model (`floebreak.shaft.drive.simulate_drive` on the line's 3-inertia train) per case.

    Per cusp: arrival at the propeller [s], blade impacts, and `impact_torque_n_m(cusp, rpm)` [N·m] at the
    rpm of each blade passage. The torque limit defaults to `drive_for_line`'s (overload factor × the
    line's rated torque P/(2π n); a line without rated power: its mean torque). The cusps are free blocks
    (`simulate_drive(free_blocks=True)`: a stopped propeller pushes its block away). Cases after the first run
    for the first case's duration, on its time axis (resampled linearly if their step differs).
    `progress(stage, done, total)`, if given, is called after each case (`report_case`).
    """
    rated = None if line.rated_power_w is not None else line.mean_torque()
    drive = drive_for_line(line, rated_torque_n_m=rated, rpm=rpm)
    if torque_limit_n_m is not None:
        limit = require_range("torque_limit_n_m", torque_limit_n_m, low=0.0, unit="N m")
        drive = type(drive)(drive.rpm_set, limit, drive.kp_n_m_s_per_rad, drive.ki_n_m_per_rad)
    line = with_operating_point(line, rpm, mean_torque_n_m)
    station_name = line.stations[line.station_index(station)]
    cases = tuple(int(excitation_case(c).number) for c in cases)
    if not cases:
        raise InputError("excitation_case", "no case given", allowed="1, 2, 3, 4")
    require_range("speed_m_s", speed_m_s, low=0.0, unit="m/s")
    train, q_mean = train_from_line(line, station_name), line.mean_torque()
    runs: list[DriveResult] = []
    for case in cases:
        runs.append(
            simulate_drive(
                train,
                drive,
                arrival_s,
                n_impacts,
                impact_torque_n_m,
                mean_torque_n_m=q_mean,
                blades=blades,
                case=case,
                tail_s=tail_s,
                duration_s=None if not runs else float(runs[0].time_s[-1]) + runs[0].dt_s,
                free_blocks=True,
            )
        )
        report_case(progress, cases, len(runs))
    t = runs[0].time_s
    summaries = tuple(drive_case_summary(r, c, blades, q_mean) for r, c in zip(runs, cases, strict=True))

    def stacked(name):
        return np.vstack([np.interp(t, r.time_s, getattr(r, name)) for r in runs])

    return ShaftResult(
        line=line,
        station=station_name,
        cases=cases,
        blades=int(blades),
        speed_m_s=float(speed_m_s),
        samples_per_blade_passage=round(60.0 / (line.rpm * blades) / runs[0].dt_s),
        time_s=t,
        load_torque_n_m=stacked("hydro_torque_n_m") + stacked("ice_torque_n_m"),
        shaft_torque_n_m=stacked("shaft_torque_n_m"),
        modes=modal_analysis(line),
        n_cusps=int(np.size(arrival_s)) if n_cusps is None else int(n_cusps),
        model="drive",
        rpm=stacked("rpm"),
        motor_torque_n_m=stacked("motor_torque_n_m"),
        drive_summaries=summaries,
        torque_limit_n_m=drive.torque_limit_n_m,
    )


def report_case(progress: Callable[[str, int, int], None] | None, cases: tuple[int, ...], done: int) -> None:
    """Tell `progress` that `done` of the excitation `cases` are computed (stage "shaft case N")."""
    if progress is not None:
        progress(f"shaft case {cases[done - 1]}", done, len(cases))


def drive_case_summary(
    result: DriveResult, case: int = 1, blades: int = PropellerSpec().blades, hydro_n_m: float = 0.0
) -> dict:
    """Min rpm, peak motor torque, time at the limit and the stall of one drive run [rpm, kN·m, s]: the
    first stop (`DriveResult.stall`) with the case's mean ice torque per blade passage of the cusp then
    milled (`mean_torque_per_passage_n_m` of its impacts' mean peak) against the limit, and the stops."""
    s = result.summary()
    stall = result.stall()
    if stall is not None:
        peak = stall.pop("mean_impact_peak_n_m")
        stall |= {
            "mean_ice_torque_per_passage_knm": float(mean_torque_per_passage_n_m(peak, case, blades)) / 1e3,
            "hydrodynamic_torque_knm": hydro_n_m / 1e3,
        }
    return {
        "min_rpm": s["min_rpm"],
        "peak_motor_torque_knm": s["peak_motor_torque_n_m"] / 1e3,
        "torque_limit_knm": result.drive.torque_limit_n_m / 1e3,
        "time_at_torque_limit_s": s["time_at_torque_limit_s"],
        "stalled": stall is not None,
        "stalled_at_s": None if stall is None else stall["time_s"],
        "stall": stall,
        "stops": s["stops"],
        "impacts": int(result.impact_time_s.size),
        "complete": result.complete,
        "time_step_s": result.dt_s,
    }


def stall_message(case: int, d: dict) -> str | None:
    """'case N stalls at t = … s, position …' with why (the case's mean ice torque per passage plus the
    hydrodynamic torque against the limit) and what follows; None when the case does not stall. `d`: a
    `drive_case_summary` (with ``bow_x_m`` and ``run_cusp`` in its stall when the caller knows them)."""
    stall = d.get("stall")
    if not stall:
        return None
    where = f"milling cusp {stall['cusp']}"
    if stall.get("run_cusp") is not None:
        where = f"milling the run's cusp {stall['run_cusp']} (broken off at bow x = {stall['bow_x_m']:.1f} m)"
    load = stall["mean_ice_torque_per_passage_knm"] + stall["hydrodynamic_torque_knm"]
    return (
        f"case {case} stalls at t = {stall['time_s']:.2f} s, position: {where}, after its impact "
        f"{stall['impacts_of_cusp']}; the case's mean ice torque per blade passage, "
        f"{stall['mean_ice_torque_per_passage_knm']:.0f} kN·m, plus the hydrodynamic "
        f"{stall['hydrodynamic_torque_knm']:.0f} kN·m ({load:.0f} kN·m) exceeds the motor's "
        f"{d['torque_limit_knm']:.0f} kN·m limit ({d['stops']} stop(s) in the run; a stopped blade's free "
        "block is pushed away and the run goes on)"
    )


RESONANCE_MARGIN_NOTE = f"margin {DEFAULT_REQUIRED_MARGIN:.0%} (assumed; IACS UR I3 text not available)"


def resonance_summary(line: ShaftLine, blades: int) -> dict:
    """Campbell margins of the blade-passage orders against the line's free-free modes at its rpm
    (`floebreak.shaft.resonance`), with the warnings inside the required margin (module default, assumed)."""
    data = campbell(line, blades=blades)
    return {
        "operating_rpm": data.operating_rpm,
        "orders": data.orders,
        "natural_frequencies_hz": data.natural_frequency_hz,
        "margin": data.margin,
        "crossing_rpm": data.crossing_rpm,
        "required_margin": data.required_margin,
        "required_margin_note": RESONANCE_MARGIN_NOTE,
        "warnings": [f"{w}; {RESONANCE_MARGIN_NOTE}" for w in data.warnings()],
    }


RAINFLOW_BIN_N_M = 10e3  # 10 kN·m range bins
NO_SN_CURVE_NOTE = "no S–N curve given (--sn-curve torque,M,AMPLITUDE,CYCLES): no damage computed"


def shaft_fatigue(
    result: ShaftResult, sn_curve: BasquinCurve | None = None, range_bin_n_m: float = RAINFLOW_BIN_N_M
) -> tuple[RainflowHistogram, dict]:
    """Rainflow histogram (`floebreak.shaft.fatigue.rainflow_histogram`) of the station's shaft torque of
    the first excitation case and its summary: the histogram, Miner's damage D = Σ n_i/N(S_i) against
    `sn_curve` (amplitude convention of `--sn-curve`), or None with a note when no curve is given."""
    case = result.cases[0]
    histogram = rainflow_histogram(result.shaft_torque_n_m[0], range_bin_n_m)
    out = {
        "case": case,
        "station": result.station,
        "duration_s": float(result.time_s[-1] - result.time_s[0]) if result.time_s.size > 1 else 0.0,
        "histogram": histogram.as_dict(),
        "damage": None,
        "sn_curve": None,
        "note": NO_SN_CURVE_NOTE,
    }
    if sn_curve is not None and sn_curve.quantity != "torque":
        out["note"] = f"the S–N curve is a {sn_curve.quantity} curve: no shaft damage computed (needs torque)"
    elif sn_curve is not None:
        out["damage"] = miner_damage(histogram.cycles, sn_curve, measure="amplitude")
        out["sn_curve"] = {
            "quantity": sn_curve.quantity,
            "exponent_m": sn_curve.exponent_m,
            "reference_amplitude_kn_m": sn_curve.reference_amplitude / 1e3,
            "reference_cycles": sn_curve.reference_cycles,
            "measure": "amplitude",
        }
        out["note"] = (
            "Palmgren–Miner over this series only (no mean-stress correction); "
            "damage of the series, not of a lifetime"
        )
    return histogram, out


CUSP_INPUT_COLUMNS = ("bow_x_m", "step", "bbox_length_m", "bbox_width_m", "thickness_m", "volume_m3")


def cusp_torque_inputs(
    columns: dict[str, np.ndarray],
    fem_tables,
    *,
    pitch_percent: float | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    volume_basis: str = DEFAULT_VOLUME_BASIS,
) -> dict[str, np.ndarray | float]:
    """Per cusp of a run's `columns` (CUSP_INPUT_COLUMNS of its cusps.parquet), in transit order:
    ``bow_x_m``, ``thickness_m`` and ``torque_n_m`` (FEM torque of the cusp's volume, "actual" area ×
    thickness or "box", as the propeller analysis, thesis §6.1.3, for the table nearest `pitch_percent`,
    default the propeller's 95.86 %), and the ``pitch_percent`` of that table. `fem_tables`: FemTables or
    {pitch: FemTable} (files: `floebreak.app.inputs.resolve_fem_tables`)."""
    check_options(interpolation, beyond)
    if volume_basis not in VOLUME_BASES:
        raise InputError("volume_basis", f"unknown value {volume_basis!r}", allowed=", ".join(VOLUME_BASES))
    col = columns
    order = np.lexsort((col["step"], col["bow_x_m"]))
    tables = fem_table_dict(fem_tables)
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


TRANSPORT_INPUT_COLUMNS = ("bow_x_m", "centroid_x_m", "centroid_y_m", "area_m2", "thickness_m")
MILLING_INPUT_COLUMNS = (*CUSP_INPUT_COLUMNS, "centroid_x_m", "centroid_y_m", "area_m2")


def port_propeller_index(arrangement: PropellerArrangement) -> int:
    """The transport's propeller on the port side (offset y > 0; the built-in line is the port shaft)."""
    for k, prop in enumerate(arrangement.propellers):
        if prop.offset_y_m > 0.0:
            return k
    raise InputError("transport.arrangement.propellers", "no propeller to port (offset_y_m > 0)")


@dataclass(frozen=True)
class MilledCusps:
    """The cusps one propeller mills (`milled_cusps`): per cusp its arrival [s], blade impacts, ice block,
    and the transport's counts over all cusps of the run."""

    arrival_s: np.ndarray
    n_impacts: np.ndarray
    block: IceBlock
    blade: BladeGeometry
    advance_speed_m_s: float
    n_cusps_run: int
    counts: dict
    run_index: np.ndarray | None = None  # per cusp: its row in the run's cusp table
    bow_x_m: np.ndarray | None = None  # per cusp: the bow position where it broke off [m]

    @cached_property
    def _torques(self) -> CuspTorques:
        return CuspTorques(self.block, self.blade, self.advance_speed_m_s)

    def impact_torque_n_m(self, cusp: int, rpm: float) -> float:
        """Torque of one blade impact on cusp `cusp` at `rpm` (`propeller.milling.impact_loads`'s, through
        `floebreak.shaft.impact_torque.CuspTorques`) [N·m]."""
        return self._torques.torque_n_m(cusp, rpm)


def milled_cusps(
    columns: dict[str, np.ndarray],
    *,
    speed_m_s: float,
    spec: PropellerSpec | None = None,
    lead_s: float = 2.0,
    transport: bool = True,
    transport_settings: TransportSettings | None = None,
    engaged: bool = True,
    flow_point=None,
    moved=None,
) -> MilledCusps:
    """The cusps of a run's `columns` (MILLING_INPUT_COLUMNS) that reach the port propeller, at their
    arrival times (`propeller.transport.transport_cusps` with the hull, parameters and tip clearance of
    `transport_settings`, default `TransportSettings()`, on two discs of the spec's radius, as the
    propeller analysis of a two-propeller run), shifted so the first arrives at `lead_s` (the constant
    bow-to-propeller delay is left out, as in the linear model); blade impacts from the milling model at
    the nominal rpm (`impact_loads`: ⌈length / cut depth⌉, ≥ 1; advance speed = ship speed). Each block
    lies on the blade's engaged interval in its cross-section at the disc
    (`propeller.load_models.engaged_intervals`, as the propeller analysis); `engaged=False` puts every
    block at the tip (tip placement, docs/propeller.md §10 choice 5). `transport=False`: every cusp, at the
    linear model's arrival times, tip placement. counts: "placement", and "engaged_zero_length", the port
    cusps whose interval has zero length (milled with zero torque). `flow_point` (an
    `operating.ControlledPoint`): the flow transport (`propeller.flow_transport`) at that operating point
    instead of the kinematic one, seeded with (0, 0) as the propeller analysis' first run. `moved`: a
    transport already computed for these cusps and this arrangement (e.g. a `flow_transport.flow_draws`
    draw)."""
    col, spec = columns, PropellerSpec() if spec is None else spec
    inner = outer = np.full(col["bow_x_m"].size, np.nan)
    if transport:
        settings = TransportSettings() if transport_settings is None else transport_settings
        arrangement = settings.arrangement(2, spec.radius_m)
        if moved is None:
            moved = _moved(col, speed_m_s, settings, arrangement, spec, flow_point)
        port = port_propeller_index(arrangement)
        chosen = np.flatnonzero(moved.propeller_index == port)
        arrival = moved.arrival_time_s[chosen]
        counts = {"reaching_port": int(chosen.size), **moved.path_counts()}
        counts["reaching"] = moved.counts().tolist()
        counts["settings"] = settings.as_dict()
        if engaged:
            all_rows = np.arange(col["bow_x_m"].size)
            inner, outer = engaged_intervals({"run": (all_rows, moved)}, all_rows.size, spec)
        zero = outer[chosen] - inner[chosen] <= 0.0
        counts |= {"placement": PLACEMENT_ENGAGED if engaged else PLACEMENT_TIP}
        counts |= {"engaged_zero_length": int(np.sum(zero))}
    else:
        chosen = np.arange(col["bow_x_m"].size)
        arrival = arrival_times_s(col["bow_x_m"], speed_m_s, lead_s)
        counts = {"reaching_port": int(chosen.size), "all_cusps": True}
    if arrival.size:
        arrival = arrival - arrival.min() + lead_s
    block = IceBlock.from_box(
        *(col[k][chosen] for k in ("bbox_length_m", "bbox_width_m", "thickness_m")),
        inner[chosen],
        outer[chosen],
    )
    blade = BladeGeometry.from_spec(spec)
    nominal = impact_loads(block, blade, spec.rpm, speed_m_s)
    return MilledCusps(
        arrival_s=arrival,
        n_impacts=np.maximum(nominal.n_impacts, 1),
        block=block,
        blade=blade,
        advance_speed_m_s=float(speed_m_s),
        n_cusps_run=int(col["bow_x_m"].size),
        counts=counts,
        run_index=chosen,
        bow_x_m=np.asarray(col["bow_x_m"], dtype=float)[chosen],
    )


def _moved(col, speed_m_s, settings, arrangement, spec, flow_point):
    """The transport of `milled_cusps`: the flow transport at `flow_point`, else the kinematic one."""
    if flow_point is None:
        return transport_cusps(
            *(col[k] for k in TRANSPORT_INPUT_COLUMNS),
            speed_m_s=speed_m_s,
            hull=settings.hull,
            arrangement=arrangement,
            params=settings.params,
        )
    rng = np.random.default_rng([0, 0])
    draw = dict(speed_m_s=speed_m_s, flow_point=flow_point, settings=settings, radius_m=spec.radius_m)
    return flow_transport_draws(col, 1, rng, **draw)[0]


def flow_transport_draws(
    columns, n_draws: int, rng, *, speed_m_s: float, flow_point, settings=None, radius_m=None
):
    """`n_draws` draws of the flow transport (`propeller.flow_transport.flow_draws`) of a run's cusps
    (`columns`: TRANSPORT_INPUT_COLUMNS) at the operating point `flow_point` (`operating.ControlledPoint`),
    on two discs of `radius_m` (default the spec's) with the hull and parameters of `settings` (default
    `TransportSettings()`). `milled_cusps` seeds its own draw with (0, 0)."""
    from floebreak.propeller.flow_transport import flow_draws

    settings = TransportSettings() if settings is None else settings
    radius_m = PropellerSpec().radius_m if radius_m is None else radius_m
    return flow_draws(
        [columns[k] for k in TRANSPORT_INPUT_COLUMNS],
        n_draws,
        rng,
        speed_m_s=speed_m_s,
        induced_velocity_m_s=flow_point.point.induced_velocity_m_s,
        wake_fraction=flow_point.wake_fraction,
        hull=settings.hull,
        arrangement=settings.arrangement(2, radius_m),
        params=settings.params,
        flow=settings.flow,
    )


def with_stall_positions(result: ShaftResult, milled: MilledCusps) -> ShaftResult:
    """`result` with each stall's cusp located in the run: its row in the cusp table (``run_cusp``) and the
    bow position where it broke off (``bow_x_m``)."""
    summaries = []
    for d in result.drive_summaries:
        stall = d.get("stall")
        if stall and milled.run_index is not None and milled.bow_x_m is not None:
            cusp = stall["cusp"]
            stall = stall | {"run_cusp": int(milled.run_index[cusp]), "bow_x_m": float(milled.bow_x_m[cusp])}
        summaries.append(d | {"stall": stall})
    return replace(result, drive_summaries=tuple(summaries))


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


def torque_series_knm(result: ShaftResult, measured_torque_n_m=None) -> dict[str, np.ndarray]:
    """The load and shaft torque of each case [kN m] (``load_case<n>``, ``shaft_case<n>``) and, if given,
    the measured series (``measured``): what the spectra, files and figures show."""
    series = {f"load_case{c}": q / 1e3 for c, q in zip(result.cases, result.load_torque_n_m, strict=True)}
    series |= {f"shaft_case{c}": q / 1e3 for c, q in zip(result.cases, result.shaft_torque_n_m, strict=True)}
    if measured_torque_n_m is not None:
        series["measured"] = np.asarray(measured_torque_n_m) / 1e3
    return series


THESIS_MEASURED = {  # thesis §6.2 / Fig. 35, Agulhas II port shaft, 18/12/2019 20:20-20:30
    "range_knm": [-100.0, 400.0],
    "above_threshold_knm": [58.0, 152.0],
    "source": "thesis §6.2 (measured shaft torque, including hydrodynamic torque)",
}


def shaft_summary(result: ShaftResult, densities: dict[str, dict], extra: dict | None = None) -> dict:
    """The summary.json content: line, modes, excitation, Q_peak per case, spectra ranges (numpy values
    as they are: `floebreak.io.writers.write_json` makes them JSON)."""
    line = result.line
    elements = []
    for e, j in zip(line.elements, line.inertias_kg_m2, strict=True):
        elements.append(
            {
                "name": e.name,
                "inertia_kg_m2": j,
                "shaft": e.shaft,
                "stiffness_n_m_per_rad": e.stiffness_n_m_per_rad,
                "damping_ratio": e.damping_ratio,
            }
        )
    for e, c in zip(elements, line.damping_n_m_s_per_rad, strict=False):
        e["damping_n_m_s_per_rad"] = c
    blade_rate = result.blades * line.rpm / 60.0
    return {
        "shaft_line": {
            "name": line.name,
            "source": line.source,
            "elements": elements,
            "propeller_dry_inertia_kg_m2": line.elements[-1].inertia_kg_m2,
            "entrained_water_fraction": line.entrained_water_fraction,
            "speed_control_bandwidth_hz": line.speed_control_bandwidth_hz,
            "speed_control_damping_ratio": line.speed_control_damping_ratio,
            "hydrodynamic_damping": line.hydrodynamic_damping,
        },
        "operating_point": {
            "rpm": line.rpm,
            "mean_torque_knm": line.mean_torque() / 1e3,
            "rated_power_w": line.rated_power_w,
            "blade_passage_frequency_hz": blade_rate,
        },
        "modes_free_free": {
            "natural_frequencies_hz": result.modes.frequency_hz,
            "damping_ratios": result.modes.damping_ratio,
            "mode_shapes": result.modes.shapes,
            "frequency_over_blade_passage": result.modes.frequency_hz / blade_rate,
        },
        "station": result.station,
        "excitation": {
            "cases": {c: EXCITATION_CASES[c].__dict__ for c in result.cases},
            "note": "rule cases as recalled (physics-notes §7.3): verify against the rule text",
            "n_cusps": result.n_cusps,
            "overlap": result.overlap,
            "ship_speed_m_s": result.speed_m_s,
            "samples_per_blade_passage": result.samples_per_blade_passage,
            "time_step_s": float(result.time_s[1] - result.time_s[0]) if result.time_s.size > 1 else None,
            "duration_s": float(result.time_s[-1]) if result.time_s.size else 0.0,
        },
        "q_peak_knm": {
            c: {
                (k[:-4] + "_knm" if k.endswith("_n_m") else k): (v / 1e3 if k.endswith("_n_m") else v)
                for k, v in p.items()
            }
            for c, p in result.peaks().items()
        },
        "spectra_above_threshold_knm": {
            n: {"intervals": d["intervals_knm"], "envelope": d["envelope_knm"]} for n, d in densities.items()
        },
        "density_threshold_per_knm": DENSITY_THRESHOLD_PER_KNM,
        "thesis_measured": THESIS_MEASURED,
        **_model_summary(result, (extra or {}).get("no_ice_load")),
        **(extra or {}),
    }


def _model_summary(result: ShaftResult, no_ice_load: str | None = None) -> dict:
    """The shaft model, the drive's outcome per case (drive model) and the resonance margin, with the
    warnings (no ice load, resonance, stall)."""
    resonance = resonance_summary(result.line, result.blades)
    warnings = ([no_ice_load] if no_ice_load else []) + list(resonance["warnings"])
    out: dict = {"shaft_model": result.model, "resonance": resonance}
    if result.model == "drive":
        out["drive"] = {
            "torque_limit_knm": result.torque_limit_n_m / 1e3,
            "cases": dict(zip(result.cases, result.drive_summaries, strict=True)),
        }
        stalls = (stall_message(c, d) for c, d in zip(result.cases, result.drive_summaries, strict=True))
        warnings += [m for m in stalls if m]
    out["warnings"] = warnings
    return out
