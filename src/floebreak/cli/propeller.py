"""`floebreak propeller`: a run's or study's cusps → propeller loads (with `--shaft-line`, shaft torque)."""

from __future__ import annotations

from contextlib import nullcontext
from pathlib import Path
from typing import Annotated

import typer
import typer.core

from floebreak.cli.common import console, parse_floats, stage_progress
from floebreak.cli.options import (
    BeyondOption,
    ExcitationCasesOption,
    ExcitationOption,
    FemTableOption,
    FractionReachingOption,
    GeometryOption,
    HoursPerYearOption,
    LoadModelOption,
    MeanTorqueOption,
    OpenWaterTableOption,
    OverwriteOption,
    PolarClassOption,
    PoolOption,
    PropellersOption,
    QuietOption,
    RatedTorqueOption,
    RpmOption,
    ShaftLineOption,
    ShaftModelOption,
    SnCurveOption,
    SpeedOption,
    StationOption,
    TorqueLimitOption,
    TransportOption,
    TransportParameterOption,
    WakeFractionOption,
    YearsOption,
    operating_profile,
    transport_option,
)
from floebreak.cli.run import written_summary
from floebreak.cli.tables import print_pooling, print_propeller_summary, shaft_tables
from floebreak.errors import InputError, require_range


def _fem_tables(items: list[str] | None) -> list[tuple[float | None, Path]] | None:
    """`--fem-table [PITCH=]FILE` options → [(pitch or None, path)]; a repeated pitch is refused here, a
    file without a pitch (no PITCH= and no '# pitch_percent:' line) when it is read."""
    if not items:
        return None
    out: list[tuple[float | None, Path]] = []
    for item in items:
        pitch_text, sep, path = item.partition("=")
        if not sep:
            out.append((None, Path(item)))
            continue
        try:
            pitch = float(pitch_text)
        except ValueError:
            raise InputError(
                "--fem-table", f"{item!r}: {pitch_text!r} is not a pitch [%]", allowed="PITCH=FILE"
            ) from None
        if any(p == pitch for p, _ in out):
            raise InputError(
                "--fem-table", f"two tables for pitch {pitch:g} %", allowed="one table per pitch"
            )
        out.append((pitch, Path(path)))
    return out


def _load_options(load_model, transport, rated_torque_knm, geometry, transport_parameters=None):
    """The `propeller` command's load-model options, checked before anything is read: a function of the
    runs' profile giving `analyse_propeller`'s load_model, transport, propeller, rated torque and transport
    settings (`--transport-parameter`)."""
    from floebreak.config.analysis import propeller_defaults
    from floebreak.propeller.load_models import TRANSPORTS, check_choice
    from floebreak.propeller.loads import load_model_names

    if load_model is not None:
        check_choice("--load-model", load_model, load_model_names())
    if transport is not None:
        check_choice("--transport", transport, TRANSPORTS)
    if rated_torque_knm is not None:
        require_range("--rated-torque-knm", rated_torque_knm, low=0.0, unit="kN m")
    spec = _propeller_spec(geometry)
    settings = transport_option(transport_parameters)

    def for_profile(profile: str) -> dict:
        default_model, default_transport = propeller_defaults(profile)
        return {
            "load_model": load_model or default_model,
            "transport": transport or default_transport,
            "propeller": spec,
            "rated_torque_n_m": None if rated_torque_knm is None else rated_torque_knm * 1e3,
            "transport_settings": settings,
        }

    return for_profile


def _propeller_spec(items: list[str] | None):
    """`--propeller-geometry KEY=VALUE …` → PropellerSpec (Agulhas II for the keys not given)."""
    from dataclasses import fields

    from floebreak.propeller.spec import PropellerSpec

    keys = [f.name for f in fields(PropellerSpec) if f.name != "open_water_table"]
    values: dict = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or key not in keys:
            allowed = f"KEY=VALUE, KEY one of {', '.join(keys)}"
            raise InputError("--propeller-geometry", f"{item!r}", allowed=allowed)
        try:
            values[key] = int(text) if key == "blades" else float(text)
        except ValueError:
            raise InputError(f"propeller.{key}", f"{text!r} is not a number", value=text) from None
    return PropellerSpec(**values)


def _operating_point_options(wake_fraction: float | None, open_water_table: Path | None) -> dict:
    """`--wake-fraction` checked and `--open-water-table` read, before anything is written."""
    if wake_fraction is not None:
        require_range(
            "--wake-fraction", wake_fraction, low=0.0, high=1.0, low_inclusive=True, high_inclusive=False
        )
    table = None
    if open_water_table is not None:
        from floebreak.app.inputs import read_open_water_table

        table = read_open_water_table(open_water_table, "--open-water-table")
    return {"wake_fraction": wake_fraction, "open_water_table": table}


def _with_table(models: dict, point: dict) -> dict:
    """The propeller analysis' options with the open-water table on its propeller spec."""
    from dataclasses import replace

    if point["open_water_table"] is None:
        return models
    return models | {"propeller": replace(models["propeller"], open_water_table=point["open_water_table"])}


def _sn_curve(text: str):
    """`--sn-curve QUANTITY,M,AMPLITUDE,CYCLES` → BasquinCurve in SI (amplitude given in kN or kN·m)."""
    from floebreak.propeller.ruleform import BasquinCurve

    parts = text.split(",")
    allowed = "QUANTITY,M,AMPLITUDE,CYCLES, e.g. torque,5,1000,1e7 (amplitude in kN·m or kN)"
    if len(parts) != 4:
        raise InputError("--sn-curve", f"{text!r} has {len(parts)} parts", allowed=allowed)
    try:
        m, amplitude, cycles = (float(p) for p in parts[1:])
    except ValueError:
        raise InputError("--sn-curve", f"{text!r}: not numbers", allowed=allowed) from None
    return BasquinCurve(m, amplitude * 1e3, cycles, quantity=parts[0].strip().lower())


def propeller(
    run_or_study_dir: Annotated[Path, typer.Argument(help="a run directory or a study directory")],
    out: Annotated[Path, typer.Option("--out", help="output directory")],
    fem_table: FemTableOption = None,
    torque_csv: Annotated[Path | None, typer.Option("--torque-csv", help="measured shaft torque CSV")] = None,
    polar_class: PolarClassOption = None,
    interpolation: Annotated[str, typer.Option("--interpolation", help="newton | pchip")] = "newton",
    beyond: BeyondOption = "power_law",
    pool: PoolOption = False,
    speed: SpeedOption = None,
    fraction_reaching: FractionReachingOption = None,
    propellers: PropellersOption = None,
    load_model: LoadModelOption = None,
    transport: TransportOption = None,
    transport_parameters: TransportParameterOption = None,
    rated_torque_knm: RatedTorqueOption = None,
    geometry: GeometryOption = None,
    hours_per_year: HoursPerYearOption = None,
    years: YearsOption = None,
    sn_curve: SnCurveOption = None,
    overwrite: OverwriteOption = False,
    quiet: QuietOption = False,
    shaft_line: ShaftLineOption = None,
    station: StationOption = None,
    rpm: RpmOption = None,
    mean_torque_knm: MeanTorqueOption = None,
    cases: ExcitationCasesOption = "1,2,3,4",
    shaft_model: ShaftModelOption = None,
    torque_limit_knm: TorqueLimitOption = None,
    excitation: ExcitationOption = "simulation",
    wake_fraction: WakeFractionOption = None,
    open_water_table: OpenWaterTableOption = None,
) -> None:
    """Propeller–ice force and torque spectra, rates and rule-form fit of the cusps of a run or study
    (thesis chapter 6; docs/propeller.md); with --shaft-line also the shaft torque at a measurement
    station of a run (docs/shaft.md)."""
    from floebreak.app.propeller import analyse_runs, read_runs
    from floebreak.output.figure_process import figure_worker

    models = _load_options(load_model, transport, rated_torque_knm, geometry, transport_parameters)
    point = _operating_point_options(wake_fraction, open_water_table)
    profile = operating_profile(hours_per_year, years)
    curve = None if sn_curve is None else _sn_curve(sn_curve)
    tables = _fem_tables(fem_table)
    shaft_options = dict(
        station=station, rpm=rpm, speed_m_s=speed, mean_torque_knm=mean_torque_knm, cases=cases
    )
    shaft_options |= dict(tables=tables, torque_csv=torque_csv, interpolation=interpolation, beyond=beyond)
    shaft_options |= dict(shaft_model=shaft_model, torque_limit_knm=torque_limit_knm, sn_curve=curve)
    shaft_options |= dict(transport_settings=transport_option(transport_parameters), excitation=excitation)
    shaft_options |= dict(transport=transport)
    with stage_progress("shaft", quiet) as progress:
        shaft = _shaft_analysis(
            run_or_study_dir, shaft_line, progress=progress, polar_class=polar_class, **shaft_options, **point
        )
    # forked after the shaft analysis, whose openTorsion imports matplotlib: the workers inherit it; one
    # for the propeller's figures, one for the shaft's
    with figure_worker() as first, figure_worker() if shaft is not None else nullcontext() as second:
        overrides = {"speed_m_s": speed, "fraction_reaching": fraction_reaching, "n_propellers": propellers}
        inputs = read_runs(run_or_study_dir, pool=pool, **overrides)
        with stage_progress("propeller analysis", quiet) as progress:
            result = analyse_runs(
                inputs,
                **_with_table(models(inputs.profile), point),
                fem_table=tables,
                torque_csv=torque_csv,
                polar_class=polar_class,
                interpolation=interpolation,
                beyond=beyond,
                operating_profile=profile,
                sn_curve=curve,
                progress=progress,
                wake_fraction=wake_fraction,
            )
        _write_propeller_outputs(result, inputs, shaft, out, overwrite, quiet, (first, second))


def _write_propeller_outputs(result, inputs, shaft, out: Path, overwrite: bool, quiet: bool, workers) -> None:
    """Write the propeller analysis `result` of `inputs` and the prepared `shaft` analysis (if any) as one
    atomic directory, then print their summaries; of the two figure `workers` (or None) the first draws
    the propeller's figures, the second the shaft's."""
    from floebreak.app.propeller_output import write_propeller_directory

    record = {"runs": sorted(inputs.run_dirs), "pooled_differing_keys": list(inputs.differing_keys)}
    written = write_propeller_directory(
        result,
        record,
        shaft,
        out,
        overwrite=overwrite,
        stage=lambda label: stage_progress(label, quiet),
        workers=workers,
    )
    print_pooling(inputs)
    print_propeller_summary(written_summary(written.folder), written.folder, quiet)
    if shaft is not None:
        _print_shaft(shaft, written.folder / "shaft")
    console.print(f"report: {written.report}", highlight=False, soft_wrap=True)
    if written.run_report is not None:
        console.print(f"updated the run's report: {written.run_report}", highlight=False, soft_wrap=True)


def _print_shaft(shaft, shaft_dir: Path) -> None:
    """Print the written shaft analysis: the design tables (`shaft_tables`), the model's lines and
    warnings, and where it was written."""
    import json

    summary = json.loads((Path(shaft_dir) / "summary.json").read_text(encoding="utf-8"))
    for table in shaft_tables(summary):
        console.print(table)
    for line in shaft.messages():
        console.print(line, highlight=False, soft_wrap=True)
    console.print(
        f"shaft torque written to {shaft_dir}/ (shaft_series.nc/.csv, shaft_spectra.nc/.csv, modes.csv, "
        "rainflow.csv, summary.json, figures/ with campbell.png and rainflow_histogram.png)",
        highlight=False,
        soft_wrap=True,
    )


def _shaft_analysis(
    run_dir,
    shaft_line,
    *,
    station,
    rpm,
    speed_m_s,
    mean_torque_knm,
    cases,
    tables,
    torque_csv,
    interpolation,
    beyond,
    shaft_model=None,
    torque_limit_knm=None,
    sn_curve=None,
    transport_settings=None,
    transport=None,
    progress=None,
    excitation="simulation",
    polar_class=None,
    wake_fraction=None,
    open_water_table=None,
):
    """The `propeller` command's shaft analysis, computed (not written) before anything is written; None
    without --shaft-line (then its own options are refused)."""
    if shaft_line is None:
        given = {
            "--station": station,
            "--rpm": rpm,
            "--mean-torque-knm": mean_torque_knm,
            "--shaft-model": shaft_model,
            "--torque-limit-knm": torque_limit_knm,
            "--excitation": None if excitation == "simulation" else excitation,
        }
        for name, value in given.items():
            if value is not None:
                raise InputError(
                    name, "is an option of the shaft analysis", allowed="add --shaft-line NAME|FILE"
                )
        return None
    from floebreak.app.shaft import shaft_analysis_of_run

    return shaft_analysis_of_run(
        run_dir,
        shaft_line,
        station=station,
        rpm=rpm,
        speed_m_s=speed_m_s,
        mean_torque_knm=mean_torque_knm,
        cases=parse_floats(cases, "excitation_cases"),
        fem_table=tables,
        torque_csv=torque_csv,
        interpolation=interpolation,
        beyond=beyond,
        shaft_model=shaft_model,
        torque_limit_knm=torque_limit_knm,
        sn_curve=sn_curve,
        transport_settings=transport_settings,
        transport=transport,
        progress=progress,
        excitation=excitation,
        polar_class=polar_class,
        wake_fraction=wake_fraction,
        open_water_table=open_water_table,
    )


def register(app: typer.Typer) -> None:
    """Add this module's commands to `app`."""
    app.command()(propeller)
