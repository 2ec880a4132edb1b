"""The shaft analysis of a run: read its cusps, resolved scenario and a measured torque series, compute
(`floebreak.shaft.analysis.shaft_response`), draw (`floebreak.plotting.shaft`) and write
(`floebreak.output.shaft_files`). Files: docs/shaft.md."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.app.figure_calls import drawn, figures_in_worker
from floebreak.app.inputs import load_shaft_line, measured_series, resolve_fem_tables
from floebreak.errors import InputError, require_range
from floebreak.output.run_files import read_resolved_scenario, read_run_cusps
from floebreak.output.shaft_files import write_shaft_files
from floebreak.propeller.loads.fem import DEFAULT_VOLUME_BASIS
from floebreak.propeller.measured import TorqueSeries
from floebreak.propeller.ruleform import BasquinCurve
from floebreak.propeller.spectra import DENSITY_THRESHOLD_PER_KNM
from floebreak.propeller.spread import SPREAD_DRAWS, band_text
from floebreak.propeller.transport import TransportSettings
from floebreak.shaft.analysis import (
    CUSP_INPUT_COLUMNS,
    MILLING_INPUT_COLUMNS,
    PROFILE_SHAFT_MODEL,
    SHAFT_MODELS,
    ShaftResult,
    cusp_torque_inputs,
    flow_transport_draws,
    milled_cusps,
    resonance_summary,
    shaft_drive_response,
    shaft_fatigue,
    shaft_response,
    shaft_summary,
    stall_message,
    torque_densities,
    torque_series_knm,
    with_stall_positions,
)
from floebreak.shaft.resonance import campbell


def run_cusp_inputs(
    run_dir: str | os.PathLike[str],
    *,
    fem_table=None,
    pitch_percent: float | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    volume_basis: str = DEFAULT_VOLUME_BASIS,
) -> dict:
    """Per cusp of the run directory `run_dir`, in transit order: ``bow_x_m``, ``thickness_m``,
    ``torque_n_m`` and the table's ``pitch_percent`` (`floebreak.shaft.analysis.cusp_torque_inputs`);
    `fem_table` as `floebreak.app.inputs.resolve_fem_tables` (default: the shipped tables)."""
    return cusp_torque_inputs(
        read_run_cusps(run_dir, CUSP_INPUT_COLUMNS),
        resolve_fem_tables(fem_table),
        pitch_percent=pitch_percent,
        interpolation=interpolation,
        beyond=beyond,
        volume_basis=volume_basis,
    )


def run_profile(run_dir: str | os.PathLike[str]) -> str:
    """``profile`` of the run's scenario.resolved.toml; "default" (the scenario's default) if absent."""
    scenario = read_resolved_scenario(run_dir, strict=False) or {}
    return str(scenario.get("profile", "default"))


def shaft_model_of_run(run_dir: str | os.PathLike[str], shaft_model: str | None) -> str:
    """`shaft_model` if given, else the run's profile's: "drive" (default profile), "linear" (thesis)."""
    if shaft_model is None:
        return PROFILE_SHAFT_MODEL.get(run_profile(run_dir), "drive")
    if shaft_model not in SHAFT_MODELS:
        raise InputError(
            "shaft_model",
            f"unknown model {shaft_model!r}",
            value=shaft_model,
            allowed=", ".join(SHAFT_MODELS),
        )
    return shaft_model


def run_ship_speed_m_s(run_dir: str | os.PathLike[str]) -> float | None:
    """``ship.speed_m_s`` of the run's scenario.resolved.toml, None if the key (or file) is absent."""
    scenario = read_resolved_scenario(run_dir, strict=False) or {}
    value = scenario.get("ship", {}).get("speed_m_s")
    return None if value is None else float(value)


def write_shaft_analysis(
    result: ShaftResult,
    out_dir: str | os.PathLike[str],
    *,
    measured: TorqueSeries | None = None,
    bin_knm: float = 10.0,
    overwrite: bool = False,
    extra_summary: dict | None = None,
    sn_curve: BasquinCurve | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    figure_worker: Any = None,
) -> Path:
    """Write `result` (and the comparison with `measured`) with its spectra, rainflow histogram (Miner's
    damage against `sn_curve` if given), summary and figures to `out_dir` atomically; return it. `progress`
    as `floebreak.output.shaft_files.write_shaft_files`'. `figure_worker`
    (`floebreak.output.run_directory.figure_worker`): a process that draws the figures while the tables are
    written (the same files)."""
    series = torque_series_knm(result, None if measured is None else measured.torque_nm)
    edges, densities = torque_densities(series, bin_knm)
    histogram, fatigue = shaft_fatigue(result, sn_curve)
    calls = shaft_figure_calls(result, series, edges, densities, measured)
    calls |= design_figure_calls(result, histogram, fatigue)
    tables = {"series": series, "edges": edges, "densities": densities, "rainflow": histogram}
    summary = shaft_summary(result, densities, extra_summary) | {"fatigue": fatigue}
    options = {"summary": summary, "overwrite": overwrite, "progress": progress, **tables}
    if figure_worker is not None:
        alongside = figures_in_worker(calls, figure_worker)
        return write_shaft_files(result, out_dir, figures={}, figures_alongside=alongside, **options)
    return write_shaft_files(result, out_dir, figures=drawn(calls), **options)


def design_figure_calls(result: ShaftResult, histogram, fatigue: dict) -> dict:
    """The Campbell diagram (`floebreak.shaft.resonance.campbell`) and the rainflow histogram, as figure
    calls (`shaft_figure_calls`)."""
    data = campbell(result.line, blades=result.blades)
    harmonics = tuple(int(k) for k in data.harmonics)
    campbell_args = (data.rpm, data.natural_frequency_hz, result.blades, data.operating_rpm)
    title = f"shaft torque at {result.station}, case {fatigue['case']}"
    return {
        "campbell.png": _call("plot_campbell", *campbell_args, data.required_margin, harmonics),
        "rainflow_histogram.png": _call(
            "plot_rainflow_histogram", histogram.range_edges_n_m, histogram.counts, title, fatigue["damage"]
        ),
    }


def _call(function: str, *args) -> tuple:
    """A `floebreak.output.figure_process.FigureCall` of `floebreak.plotting.shaft`."""
    return ("shaft", function, args, {})


def shaft_figure_calls(result: ShaftResult, series, edges, densities, measured: TorqueSeries | None) -> dict:
    """The shaft analysis' figures as plain data (file name → `floebreak.output.figure_process.FigureCall` of
    `floebreak.plotting.shaft`), to draw here or in a figure worker."""
    out = {}
    primary = result.cases[0]
    t = result.time_s
    out["excitation_series.png"] = _call(
        "plot_series",
        t,
        {f"propeller load, case {primary}": series[f"load_case{primary}"]},
        f"propeller load torque Q(t) = Q_mean + Q_ice(t), case {primary}",
    )
    out["shaft_series.png"] = _call(
        "plot_series",
        t,
        {
            "propeller load": series[f"load_case{primary}"],
            f"shaft at {result.station}": series[f"shaft_case{primary}"],
        },
        f"propeller load and shaft torque, case {primary}",
    )
    out["mode_shapes.png"] = _call(
        "plot_modes", [e.name for e in result.line.elements], result.modes.frequency_hz, result.modes.shapes
    )
    for log in (False, True):
        scale = "log" if log else "linear"
        shown = {
            "propeller load": densities[f"load_case{primary}"]["density"],
            f"shaft ({result.station})": densities[f"shaft_case{primary}"]["density"],
        }
        title = f"torque spectra, case {primary}"
        out[f"shaft_spectrum_{scale}.png"] = _call(
            "plot_densities", edges, shown, log, DENSITY_THRESHOLD_PER_KNM, title
        )
        if measured is not None:
            compared = {
                f"simulated shaft ({result.station}), case {primary}": shown[f"shaft ({result.station})"],
                "measured shaft": densities["measured"]["density"],
            }
            title = f"shaft torque: simulated vs measured ({Path(measured.source).name})"
            out[f"shaft_comparison_{scale}.png"] = _call(
                "plot_densities", edges, compared, log, DENSITY_THRESHOLD_PER_KNM, title
            )
    return out


NO_ICE_LOAD = (
    "no cusp reached the port propeller: the shaft torque is the mean torque alone, and Q_peak and the "
    "dynamic amplification describe no ice load"
)


@dataclass(frozen=True)
class PreparedShaftAnalysis:
    """A computed shaft analysis, validated and ready to write (`write`)."""

    result: ShaftResult
    measured: TorqueSeries | None
    extra_summary: dict
    sn_curve: BasquinCurve | None = None

    def messages(self) -> list[str]:
        """Lines for the terminal: the model, the drive's outcome per case, the resonance margin and
        the warnings (as in summary.json)."""
        r = self.result
        lines = [f"shaft model: {r.model} ({self.extra_summary.get('torque_model', '')})"]
        if "transport" in self.extra_summary:
            lines.append(
                f"cusps milled by the port propeller: {self.extra_summary['transport']['reaching_port']}"
            )
        if "no_ice_load" in self.extra_summary:
            lines.append(f"warning: {self.extra_summary['no_ice_load']}")
        spread = self.extra_summary.get("q_peak_spread")
        if spread:
            lines.append(
                f"shaft Q_peak, case {spread['case']}, over {spread['n_draws']} draws of the flow transport: "
                f"median {band_text(spread['q_peak_knm'])} kN·m"
            )
        for c, d in zip(r.cases, r.drive_summaries, strict=False):
            lines.append(
                f"case {c}: min {d['min_rpm']:.1f} rpm, peak motor torque "
                f"{d['peak_motor_torque_knm']:.0f} kN·m (limit {d['torque_limit_knm']:.0f}), "
                f"{'stalled' if d['stalled'] else 'not stalled'}"
            )
            if d["stalled"]:
                lines.append(stall_message(c, d))
        resonance = resonance_summary(r.line, r.blades)
        lowest = float(resonance["margin"].min())
        lines.append(
            f"resonance margin at {r.line.rpm:g} rpm: {lowest:.1%} (closest blade-passage order to a mode; "
            f"required {resonance['required_margin_note']})"
        )
        lines += [f"warning: {w}" for w in resonance["warnings"]]
        if "rule_excitation" in self.extra_summary:
            lines += rule_lines(self.extra_summary["rule_excitation"])
        return lines

    def write(
        self,
        out_dir: str | os.PathLike[str],
        overwrite: bool = False,
        progress: Callable[[str, int, int], None] | None = None,
        figure_worker: Any = None,
    ) -> Path:
        return write_shaft_analysis(
            self.result,
            out_dir,
            measured=self.measured,
            overwrite=overwrite,
            extra_summary=self.extra_summary,
            sn_curve=self.sn_curve,
            progress=progress,
            figure_worker=figure_worker,
        )


def _drive_response(
    run_dir,
    line,
    speed_m_s,
    rpm,
    mean_torque_n_m,
    torque_limit_knm,
    station,
    cases,
    transport_settings,
    progress=None,
    wake_fraction=None,
    open_water_table=None,
    transport=None,
):
    """The drive model on the cusps the transport (`transport`, default the run's profile's:
    `config.analysis.propeller_defaults`; with `transport_settings`) sends to the port propeller
    (`milled_cusps`); "flow" at the propeller's operating point, "all": every cusp."""
    from floebreak.config.analysis import propeller_defaults
    from floebreak.propeller.load_models import TRANSPORTS, check_choice
    from floebreak.propeller.operating import shaft_operating_point  # scipy.optimize: only when run

    if transport is None:
        transport = propeller_defaults(run_profile(run_dir))[1]
    check_choice("transport", transport, TRANSPORTS)
    # the propeller's own operating point: its mean torque is the model's, a measured one only compared
    point, comparison = shaft_operating_point(
        line, speed_m_s, mean_torque_n_m, wake_fraction, open_water_table=open_water_table
    )
    columns = read_run_cusps(run_dir, MILLING_INPUT_COLUMNS)
    milled = milled_cusps(
        columns,
        speed_m_s=speed_m_s,
        transport=transport != "all",
        transport_settings=transport_settings,
        flow_point=point if transport == "flow" else None,  # the cusps followed at this operating point
    )
    mean_torque_n_m = None if point.torque_limited else point.point.torque_n_m
    drive = {
        "rpm": rpm,
        "mean_torque_n_m": mean_torque_n_m,
        "torque_limit_n_m": None if torque_limit_knm is None else 1e3 * torque_limit_knm,
        "station": station,
    }
    result = shaft_drive_response(
        milled.arrival_s,
        milled.n_impacts,
        milled.impact_torque_n_m,
        line,
        speed_m_s=speed_m_s,
        cases=tuple(cases or ()),
        n_cusps=milled.n_cusps_run,
        progress=progress,
        **drive,
    )
    result = with_stall_positions(result, milled)
    extra = {
        "torque_model": "milling (propeller.milling.impact_loads at the rpm of each blade passage)",
        "transport": milled.counts | {"rule": transport},
        "propeller_operating_point": point.as_dict() | comparison,
    }
    if transport == "flow" and result.cases:
        spread = (columns, speed_m_s, transport_settings, point, line, result, SPREAD_DRAWS)
        extra["q_peak_spread"] = _q_peak_spread(*spread, **drive)
    if milled.counts.get("reaching_port", 0) == 0:  # zero ice load must be said, not shown as a result
        extra["no_ice_load"] = NO_ICE_LOAD
    return result, extra


def _q_peak_spread(columns, speed_m_s, settings, point, line, result, n_draws, **drive) -> dict:
    """Q_peak of the first excitation case over `n_draws` draws of the flow transport: the analysis' own and
    `n_draws − 1` more (`flow_transport.flow_draws`, seeded (0, 0, 1), as the propeller analysis seeds
    its first run's), each milled and run through the drive model as the first; its median and 5–95 %
    band (`propeller.spread.band`)."""
    from floebreak.propeller.spread import band

    case, settings = result.cases[0], settings or TransportSettings()
    peaks = [result.peaks()[case]["q_peak_n_m"] / 1e3]
    rng = np.random.default_rng([0, 0, 1])
    draws = flow_transport_draws(
        columns, n_draws - 1, rng, speed_m_s=speed_m_s, flow_point=point, settings=settings
    )
    for moved in draws:
        milled = milled_cusps(
            columns, speed_m_s=speed_m_s, transport_settings=settings, flow_point=point, moved=moved
        )
        again = shaft_drive_response(
            milled.arrival_s,
            milled.n_impacts,
            milled.impact_torque_n_m,
            line,
            speed_m_s=speed_m_s,
            cases=(case,),
            n_cusps=milled.n_cusps_run,
            **drive,
        )
        peaks.append(again.peaks()[case]["q_peak_n_m"] / 1e3)
    return {"case": case, "n_draws": n_draws, "q_peak_knm": band(peaks), "samples_knm": peaks}


def shaft_analysis_of_run(
    run_dir: str | os.PathLike[str],
    shaft_line: str | os.PathLike[str],
    *,
    station: str | None = None,
    rpm: float | None = None,
    speed_m_s: float | None = None,
    mean_torque_knm: float | None = None,
    cases=(1, 2, 3, 4),
    fem_table=None,
    pitch_percent: float | None = None,
    torque_csv: str | os.PathLike[str] | None = None,
    interpolation: str = "newton",
    beyond: str = "power_law",
    samples_per_blade_passage: int = 40,
    shaft_model: str | None = None,
    torque_limit_knm: float | None = None,
    sn_curve: BasquinCurve | None = None,
    transport_settings: TransportSettings | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    wake_fraction: float | None = None,
    excitation: str = "simulation",
    polar_class: str | None = None,
    open_water_table=None,
    transport: str | None = None,
) -> PreparedShaftAnalysis:
    """Read a run's cusps, the shaft line and the measured series; compute the shaft analysis. Nothing is
    written (write with ``.write(out_dir)``). The ship speed: `speed_m_s`, else the run's resolved
    scenario's ``ship.speed_m_s``, else an InputError asking for it. `shaft_model`: "drive" (the cusps the
    transport sends to the port propeller, milled by the drive model) or "linear" (every cusp, FEM torque,
    constant rpm); default: the run's profile's (default → drive, thesis → linear). `sn_curve`: a torque
    S–N curve for Miner's damage of the shaft torque's rainflow cycles (`shaft_fatigue`). `torque_csv`: a
    path or a `TorqueSeries`. `transport` ("flow" | "hull" | "all", default the run's profile's) and its
    `transport_settings` (`--transport-parameter`): the drive model's. `progress(stage, done, total)` is
    told of each excitation case computed. `excitation` "rule": the rule's four excitation cases and their
    resonance sweep beside the simulation (`rule_baseline`; `polar_class` default PC5 for the built-in
    Agulhas II line, required for another). `wake_fraction` and
    `open_water_table` (`propeller.open_water.OpenWaterTable`) set the open-water operating point."""
    model = shaft_model_of_run(run_dir, shaft_model)
    rule_class = rule_polar_class(excitation, polar_class, shaft_line)
    _check_torque_limit(torque_limit_knm, model)
    line = load_shaft_line(shaft_line)
    speed_m_s = _speed_of_run(run_dir, speed_m_s)
    measured = measured_series(torque_csv)
    mean_torque_n_m = None if mean_torque_knm is None else 1e3 * mean_torque_knm
    extra = {"run_dir": Path(run_dir).name, "measured_source": None if measured is None else measured.source}
    curves = {"wake_fraction": wake_fraction, "open_water_table": open_water_table}
    if model == "drive":
        drive_args = (rpm, mean_torque_n_m, torque_limit_knm, station, cases, transport_settings)
        more_args = {"progress": progress, "transport": transport}
        result, more = _drive_response(run_dir, line, speed_m_s, *drive_args, **more_args, **curves)
        extra |= more
    else:
        fem = {"fem_table": fem_table, "pitch_percent": pitch_percent, "interpolation": interpolation}
        cusps = run_cusp_inputs(run_dir, beyond=beyond, **fem)
        result = shaft_response(
            cusps["bow_x_m"],
            cusps["torque_n_m"],
            cusps["thickness_m"],
            line,
            speed_m_s=speed_m_s,
            rpm=rpm,
            station=station,
            cases=tuple(cases or ()),
            mean_torque_n_m=mean_torque_n_m,
            samples_per_blade_passage=samples_per_blade_passage,
            progress=progress,
        )
        extra |= {"torque_model": "fem", "fem_pitch_percent": cusps["pitch_percent"]}
        extra |= {"interpolation": interpolation, "beyond": beyond}
    if rule_class is not None:
        limit = None if torque_limit_knm is None or model != "drive" else 1e3 * torque_limit_knm
        args = (rpm, mean_torque_n_m, station, cases, limit)
        extra["rule_excitation"] = rule_baseline(result, line, rule_class, speed_m_s, *args, **curves)
    return PreparedShaftAnalysis(result, measured, extra, sn_curve)


def _check_torque_limit(torque_limit_knm: float | None, model: str) -> None:
    if torque_limit_knm is not None:
        require_range("torque_limit_knm", torque_limit_knm, low=0.0, unit="kN m")
        if model != "drive":
            raise InputError(
                "torque_limit_knm",
                "applies to the drive model only",
                allowed='shaft_model="drive" (--shaft-model drive)',
            )


def _speed_of_run(run_dir, speed_m_s: float | None) -> float:
    """`speed_m_s`, else the run's scenario's ``ship.speed_m_s``, else an InputError asking for it."""
    if speed_m_s is None:
        speed_m_s = run_ship_speed_m_s(run_dir)
        if speed_m_s is None:
            raise InputError(
                "speed_m_s",
                f"not given, and {str(run_dir)!r} has no ship.speed_m_s in scenario.resolved.toml",
                allowed="speed_m_s > 0 m/s (--speed-m-s)",
            )
    return speed_m_s


def rule_lines(rule: dict) -> list[str]:
    """The rule baseline for the terminal: its sequence, Q_peak per case beside the simulation's, and the
    largest Q_peak of each case over the resonance sweep."""
    e = rule["excitation"]
    lines = [
        f"rule excitation ({e['polar_class']}, as recalled): Q_max {e['q_max_knm']:.0f} kN·m, {e['impacts']} "
        f"impacts over N_Q = {e['revolutions_n_q']:g} revolutions, on the open-water mean torque "
        f"{rule['mean_torque_knm']:.0f} kN·m ({rule['shaft_model']} model)"
    ]
    for case, p in rule["cases"].items():
        sim = p["simulation_q_peak_knm"]
        stalled = ", propeller stopped" if p.get("stalled") else ""
        lines.append(
            f"  case {case}: Q_peak rule {p['q_peak_knm']:.0f} kN·m, simulation "
            f"{'–' if sim is None else f'{sim:.0f}'} kN·m (rule load peak {p['load_peak_knm']:.0f}{stalled})"
        )
    sweep = rule["resonance_sweep"]
    crossings = ", ".join(
        f"order {c['order']} × mode {c['mode']} at {c['rpm']:.1f}" for c in sweep["crossings"]
    )
    lines.append(
        f"  resonance sweep over {len(sweep['points'])} set speeds (crossings: {crossings or 'none'} rpm):"
    )
    for case in rule["cases"]:
        top = max(sweep["points"], key=lambda row: row["cases"][case]["q_peak_knm"])
        peak = top["cases"][case]["q_peak_knm"]
        lines.append(f"    case {case}: largest Q_peak {peak:.0f} kN·m at {top['rpm']:.1f} rpm")
    return lines


def rule_polar_class(excitation: str, polar_class: str | None, shaft_line) -> str | None:
    """The polar class of the rule's excitation; None for the simulation alone. Without `polar_class`
    the built-in Agulhas II line is PC5 (physics-notes §7.2), another line needs one."""
    from floebreak.propeller.iceclass import check_polar_class
    from floebreak.shaft.rule_excitation import EXCITATIONS

    if excitation not in EXCITATIONS:
        raise InputError(
            "excitation", f"unknown {excitation!r}", value=excitation, allowed=", ".join(EXCITATIONS)
        )
    if excitation == "simulation":
        return None
    if polar_class is not None:
        return check_polar_class(polar_class)
    if str(shaft_line) == "agulhas_ii":
        return "PC5"
    raise InputError(
        "polar_class",
        "the rule's excitation needs a polar class for this shaft line",
        allowed="--polar-class PC1…PC7",
    )


def rule_baseline(
    result, line, polar_class, speed_m_s, rpm, measured_n_m, station, cases, limit, **curves
) -> dict:
    """The rule's four excitation cases on the open-water mean torque, with the simulation's Q_peak beside
    each, and the resonance sweep (`floebreak.shaft.rule_excitation`), for the summary. `curves`:
    `wake_fraction` and `open_water_table` of the operating point."""
    from floebreak.propeller.operating import shaft_operating_point
    from floebreak.propeller.spec import PropellerSpec
    from floebreak.shaft.rule_excitation import (
        case_peaks,
        rule_excitation,
        rule_resonance_sweep,
        rule_response,
    )

    point, _ = shaft_operating_point(line, speed_m_s, measured_n_m, **curves)
    mean = point.point.torque_n_m
    spec = PropellerSpec(rpm=line.rpm)
    excitation = rule_excitation(spec, polar_class)
    common = {
        "model": result.model,
        "mean_torque_n_m": mean,
        "speed_m_s": speed_m_s,
        "station": result.station,
    }
    common |= {"cases": tuple(cases or (1, 2, 3, 4)), "torque_limit_n_m": limit}
    rule = case_peaks(rule_response(excitation, line, rpm=rpm, **common))
    simulated = result.peaks()
    for case, entry in rule.items():
        sim = simulated.get(case)
        entry["simulation_q_peak_knm"] = None if sim is None else sim["q_peak_n_m"] / 1e3
    return {
        "excitation": excitation.as_dict(),
        "mean_torque_knm": mean / 1e3,
        "mean_torque_source": "open-water operating point (propeller.operating), not a measured mean",
        "shaft_model": result.model,
        "station": result.station,
        "cases": rule,
        "resonance_sweep": rule_resonance_sweep(excitation, line, **common),
    }
