"""CLI of studies: `floebreak study FILE|thesis --out DIR`, `floebreak aggregate DIR` (thin layer)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from floebreak.app.study_output import prepare_study_directory
from floebreak.cli.options import (
    FractionReachingOption,
    PolarClassOption,
    PropellersOption,
    SchedulerOption,
    ShaftLineOption,
    TransportParameterOption,
    WorkersOption,
    operating_profile,
    transport_values,
)
from floebreak.errors import InputError

console = Console()


def study(
    spec: Annotated[
        str, typer.Argument(help="study TOML file, or 'thesis' for the built-in thesis §5.3 study")
    ],
    out: Annotated[Path, typer.Option("--out", help="study directory (re-running resumes it)")],
    workers: WorkersOption = None,
    scheduler: SchedulerOption = None,
    n_fields: Annotated[int, typer.Option("--n-fields", help="random fields per point (thesis study)")] = 4,
    profile: Annotated[str, typer.Option("--profile", help="default | thesis (thesis study)")] = "default",
) -> None:
    """Run a parameter study / Monte Carlo ensemble; each run writes its own run directory."""
    from floebreak.studies.aggregate import aggregate
    from floebreak.studies.design import check_n_fields, expand, load_study, thesis_study
    from floebreak.studies.executors import make_executor
    from floebreak.studies.runner import run_study

    if workers is not None and workers < 1:
        raise InputError("workers", f"{workers} < 1", value=workers, allowed="an integer ≥ 1")
    if spec == "thesis":
        if profile not in ("default", "thesis"):
            raise InputError("profile", f"unknown profile {profile!r}", allowed="default, thesis")
        check_n_fields(n_fields)
        study_spec, base_dir = thesis_study(n_fields=n_fields, profile=profile), None
    else:
        study_spec, base_dir = load_study(spec)
    runs, members = expand(study_spec, base_dir)  # validates every combination before anything runs
    out = out.absolute()  # the runs' directories reach workers, whose working directory may be another
    prepare_study_directory(out)  # a file, a foreign directory: exit 2; read-only, full: exit 3
    executor = make_executor(workers, scheduler)
    console.print(f"study {study_spec.name!r}: {len(runs)} runs on {executor.description} → {out}")
    columns = (
        TextColumn("runs"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
    )
    try:
        with Progress(*columns, console=console) as bar:
            task = bar.add_task("runs", total=len(runs), info="")

            def progress(state) -> None:
                info = f"failed {state.failed}, resumed {state.skipped}"
                if state.fields:
                    info = f"common fields {state.fields}, {info}"
                bar.update(task, completed=state.done, info=info)

            state = run_study(study_spec, runs, members, out, executor, progress)
    finally:
        executor.close()
    counts = aggregate(out)
    console.print(
        f"complete {counts['complete']}, failed {counts['failed']}: tables in {out}/tables, "
        f"figures in {out}/figures, all runs in {out}/study_runs.parquet"
    )
    for failure in state.failures[:5]:
        console.print(f"[red]failed[/] {failure['run']}: {failure['error']}")
    if counts["failed"]:
        console.print(
            f"[bold red]{counts['failed']} of {len(runs)} runs failed[/] (records in {out}/failed/; "
            "running the study again retries them)",
            soft_wrap=True,
        )
        raise typer.Exit(EXIT_RUNS_FAILED)


EXIT_RUNS_FAILED = 4  # a study finished, but some of its runs failed (README, exit codes)


def aggregate_command(
    study_dir: Annotated[Path, typer.Argument(help="a study directory written by `floebreak study`")],
) -> None:
    """Re-build study_runs.parquet, the tables and the figures of a study without re-running it."""
    from floebreak.studies.aggregate import aggregate

    console.print(json.dumps(aggregate(study_dir)))


def voyage(
    log: Annotated[Path, typer.Argument(help="ice observation log CSV (docs/studies.md, Voyages)")],
    out: Annotated[Path, typer.Option("--out", help="voyage directory (re-running resumes it)")],
    n_fields: Annotated[int, typer.Option("--n-fields", help="random fields per period")] = 4,
    workers: WorkersOption = None,
    scheduler: SchedulerOption = None,
    seed: Annotated[int, typer.Option("--seed", help="root seed of the fields")] = 2023,
    overrides: Annotated[
        list[str] | None, typer.Option("--set", help="scenario override KEY=VALUE (repeatable)")
    ] = None,
    speed_m_s: Annotated[
        float | None,
        typer.Option("--speed-m-s", help="ship speed [m/s] where the log has none (default 3 m/s)"),
    ] = None,
    max_length_m: Annotated[
        float, typer.Option("--max-length-m", help="longest simulated field per period [m]")
    ] = 400.0,
    hours_per_year: Annotated[
        float | None, typer.Option("--hours-in-ice-per-year", help="operating profile [h/a]")
    ] = None,
    years: Annotated[
        float | None, typer.Option("--years", help="operating profile: years in service")
    ] = None,
    polar_class: PolarClassOption = None,
    fraction_reaching: FractionReachingOption = None,
    propellers: PropellersOption = None,
    shaft_line: ShaftLineOption = None,
    transport_parameters: TransportParameterOption = None,
) -> None:
    """Simulate a voyage from an ice observation log: per-period tables, time-weighted load spectra, the
    rule-form fit of the operated loads (extrapolated over the operating profile when given); the per-cusp
    load model and transport follow the scenario's profile, as in `floebreak propeller`. With --shaft-line,
    the shaft torque of every period's runs, pooled by time. Re-running with other propeller options
    resumes the runs and re-writes the results."""
    from floebreak.studies.executors import make_executor
    from floebreak.studies.voyage import check_out_dir, prepare_voyage, run_voyage
    from floebreak.studies.voyage_log import read_voyage_log
    from floebreak.studies.voyage_results import VoyageAnalysis

    if workers is not None and workers < 1:
        raise InputError("workers", f"{workers} < 1", value=workers, allowed="an integer ≥ 1")
    profile = operating_profile(hours_per_year, years)
    analysis = VoyageAnalysis(
        polar_class, fraction_reaching, propellers, shaft_line, transport_values(transport_parameters)
    ).checked()
    with Progress(TextColumn("reading {task.fields[name]}: {task.completed:,} rows"), console=console) as bar:
        reading = bar.add_task("log", total=None, name=log.name)
        voyage_log = read_voyage_log(log, progress=lambda rows: bar.update(reading, completed=rows))
    setup = prepare_voyage(  # everything validated before anything is written or started
        voyage_log,
        n_fields=n_fields,
        seed=seed,
        overrides=overrides or [],
        speed_m_s=speed_m_s,
        max_length_m=max_length_m,
        analysis=analysis,
    )
    check_out_dir(out, setup.identity)
    executor = make_executor(workers, scheduler)
    periods = len(setup.plans)
    console.print(
        f"voyage {log.name}: {periods} periods × {n_fields} fields on {executor.description} → {out}"
    )
    try:
        with Progress(*_progress_columns(), console=console) as bar:
            task = bar.add_task("generators", total=periods, info="circles or voronoi per period")

            def progress(stage: str, value) -> None:
                if stage == "fields":
                    bar.update(task, completed=value)
                else:
                    info = f"failed {value.failed}, resumed {value.skipped}"
                    bar.update(task, description="runs", total=value.total, completed=value.done, info=info)

            summary = run_voyage(setup, out, executor, progress, profile)
    finally:
        executor.close()
    _print_voyage(summary, out)


def _progress_columns() -> tuple:
    return (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
    )


def _fmt(value, spec: str) -> str:
    return "–" if value is None else format(value, spec)


def _load_model_name(summary: dict) -> str | None:
    model = summary.get("load_model") or {}
    return model.get("load_model") or model.get("name")


def _print_voyage(summary: dict, out: Path) -> None:
    from rich.markup import escape
    from rich.table import Table

    table = Table(title=f"voyage: {summary['hours_in_ice']:.3g} h in ice, {summary['distance_km']:.3g} km")
    fem = _load_model_name(summary) == "fem"  # the beyond-table share means something only with FEM tables
    columns = ["case", "loads/h per propeller", "per km", "max |F| [kN]", "max |Q| [kN·m]"]
    for column in columns + (["beyond FEM table"] if fem else []):
        # escaped: rich would take "[kN]" for markup and drop it; folded: piped output is 80 columns wide
        table.add_column(escape(column), justify="right", overflow="fold")
    for case, values in summary["cases"].items():
        cells = [
            case,
            _fmt(values["loads_per_hour"], ".0f"),
            _fmt(values["loads_per_km"], ".1f"),
            _fmt(values["max_force_kn"], ".0f"),
            _fmt(values["max_torque_knm"], ".0f"),
        ]
        table.add_row(*cells, *([_fmt(values["beyond_table_fraction"], ".0%")] if fem else []))
    console.print(table)
    console.print(
        f"periods simulated {summary['n_periods_simulated']} of {summary['n_periods']}; "
        f"tables, spectra and figures in {out / 'results'}",
        soft_wrap=True,
    )
    console.print(voyage_model_line(summary), soft_wrap=True, highlight=False)
    _print_rule_form(summary["rule_form"])
    if "shaft" in summary:
        console.print(voyage_shaft_line(summary["shaft"]), soft_wrap=True, highlight=False)
    fallback = [index for index, (generator, _) in summary["generators"].items() if generator != "circles"]
    if fallback:
        console.print(f"voronoi fields for periods {', '.join(fallback)} (circles could not; see periods.md)")
    for note in summary["notes"]:
        if note.startswith("warning"):
            console.print(f"[yellow]{note}[/]", soft_wrap=True)
    for failure in summary.get("failures", [])[:5]:
        console.print(f"[red]failed[/] {failure['run']}: {failure['error']}")


def voyage_model_line(summary: dict) -> str:
    """The per-cusp load model, the fraction of cusps reaching a propeller and the rule's Q_max."""
    model, transport = summary["load_model"], summary["transport"]
    fraction = transport.get("fraction_reaching")
    reach = "–" if fraction is None else f"{fraction:.3g}"
    source = {
        "flow": "flow transport",
        "hull": "kinematic transport",
        "all": "every cusp",
        "override": "override",
    }
    placement = f" ({model['placement']})" if model.get("placement") else ""
    line = (
        f"per-cusp loads: {model.get('load_model') or '–'} model{placement}; fraction of cusps reaching a "
        "propeller: "
        f"{reach} ({source.get(transport.get('rule'), '–')}); {summary['propeller']['count']} propellers"
    )
    if model.get("rated_torque_knm") is not None:
        line += f"; rated torque {model['rated_torque_knm']:.1f} kN·m"
    rule = summary.get("ice_class")
    if rule:
        line += f"; {rule['polar_class']} Q_max {rule['torque_knm']:.0f} kN·m, N_ice {rule['n_ice']:.3g}"
    return line


def voyage_shaft_line(shaft: dict) -> str:
    """The voyage's pooled shaft torque: extremes over the periods and rainflow cycles per hour."""
    top, low = shaft["max_shaft_torque_knm"], shaft["min_shaft_torque_knm"]
    cycles = shaft["cycles_per_hour"]
    if top is None:
        return f"shaft line {shaft['shaft_line']}: no complete runs"
    return (
        f"shaft line {shaft['shaft_line']} ({', '.join(shaft['model'])} model, station "
        f"{', '.join(shaft['station'])}): shaft torque {low:.0f} to {top:.0f} kN·m over "
        f"{shaft['hours']:.3g} h in ice; {cycles:.0f} rainflow cycles per hour of range "
        f"≥ {shaft['cycle_range_min_knm']:g} kN·m (results/shaft/)"
    )


def _print_rule_form(rule_form: dict) -> None:
    from rich.markup import escape
    from rich.table import Table

    from floebreak.studies.voyage_results import RULE_FORM_COLUMNS, rule_form_rows

    table = Table(title="rule-form fit of the operated loads (weighted; as recalled, verify with the rule)")
    for column in RULE_FORM_COLUMNS:
        table.add_column(escape(column), justify="right", overflow="fold")
    for row in rule_form_rows(rule_form):
        table.add_row(*(escape(cell) for cell in row))
    console.print(table)


def register(app: typer.Typer) -> None:
    """`floebreak study`, `aggregate` and `voyage`."""
    app.command("study")(study)
    app.command("aggregate")(aggregate_command)
    app.command("voyage")(voyage)
