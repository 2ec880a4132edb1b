"""The floebreak command line: each command parses its options and calls the public or application-layer
functions (docs/architecture.md); help texts follow `_Command`'s conventions."""

from __future__ import annotations

import math
import re
import signal
import sys
from contextlib import contextmanager, nullcontext
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
import typer.core
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from floebreak import constants as c
from floebreak.cli_options import (
    FractionReachingOption,
    PolarClassOption,
    PropellersOption,
    ShaftLineOption,
    TransportParameterOption,
    operating_profile,
    transport_option,
)
from floebreak.errors import InputError, require_range
from floebreak.exit_codes import EXIT_INPUT, EXIT_INTERRUPTED, EXIT_STORAGE, interruption
from floebreak.ice.observations import Observation, get_observation, thesis_observations

DESCRIPTION = (
    "floebreak: a ship's bow breaking sea-ice floes (thesis model), the broken cusps' propeller-ice loads "
    "and the shaft torque they cause. Start with `floebreak demo --out demo-output`."
)


class _HelpConventions:
    """Every floebreak command's and group's help: texts printed as written (units such as [m] escaped, not
    read as rich markup), arguments named in capitals (RUN_OR_STUDY_DIR, LOG) without the braces typer
    puts around required ones in the usage line, and flags without a `<bool>` type."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.help = None if self.help is None else escape(self.help)
        for param in self.params:
            if getattr(param, "help", None):
                param.help = escape(param.help)

    def get_params(self, ctx):
        params = super().get_params(ctx)
        for param in params:
            if isinstance(param, typer.core.TyperArgument) and param.metavar is None:
                param.metavar = param.name.upper()
            elif getattr(param, "is_flag", False) and param.metavar is None:
                param.metavar = ""
        return params

    def collect_usage_pieces(self, ctx) -> list[str]:
        return [re.sub(r"^\{(.*)\}$", r"\1", piece) for piece in super().collect_usage_pieces(ctx)]


class _Command(_HelpConventions, typer.core.TyperCommand):
    pass


class _Group(_HelpConventions, typer.core.TyperGroup):
    pass


def _use_command_class(typer_app: typer.Typer) -> None:
    """`_Command` for every command of `typer_app` registered without a class of its own."""
    for info in typer_app.registered_commands:
        if info.cls in (None, typer.core.TyperCommand):
            info.cls = _Command


app = typer.Typer(
    cls=_Group,
    no_args_is_help=True,
    add_completion=False,
    help=DESCRIPTION,
    pretty_exceptions_enable=False,
)
console = Console()
err_console = Console(stderr=True)


@app.command()
def observations() -> None:
    """Print the built-in ice observations (thesis Table 1, expedition Agu19/20)."""
    table = Table(title="Ice observations Agu19/20 (thesis Table 1); diameter shares are % of floe count")
    table.add_column("key")
    table.add_column(r"concentration \[%]", justify="right")
    table.add_column(r"mean thickness \[m]", justify="right")
    table.add_column(r"diameter class \[m]: share of floes \[%]")
    for key, obs in thesis_observations().items():
        shares = ", ".join(
            f"{d:g}: {p:g}" for d, p in zip(obs.diameter_classes_m, obs.percentages, strict=True)
        )
        table.add_row(key, f"{100 * obs.concentration:g}", f"{obs.mean_thickness_m:g}", shares)
    console.print(table)


class GeneratorName(StrEnum):
    circles = "circles"
    voronoi = "voronoi"
    sqp = "sqp"


def _parse_floats(text: str | None, field: str) -> tuple[float, ...] | None:
    if text is None:
        return None
    try:
        return tuple(float(v) for v in text.replace(";", ",").split(",") if v.strip())
    except ValueError:
        raise InputError(field, f"{text!r} is not a comma-separated list of numbers") from None


@app.command()
def field(
    out: Annotated[Path, typer.Option("--out", help="output GeoParquet file (e.g. field.parquet)")],
    obs: Annotated[
        str | None, typer.Option("--obs", help="observation key from `floebreak observations`")
    ] = None,
    length: Annotated[
        float, typer.Option("--length", help="field length along x [m] (default: the thesis' field)")
    ] = c.REFERENCE_FIELD_LENGTH_M,
    width: Annotated[
        float, typer.Option("--width", help="field width along y [m] (default: the thesis' field)")
    ] = c.REFERENCE_FIELD_WIDTH_M,
    seed: Annotated[int, typer.Option("--seed", help="random seed")] = 1,
    generator: Annotated[GeneratorName, typer.Option("--generator")] = GeneratorName.circles,
    thickness: Annotated[float | None, typer.Option("--thickness", help="constant thickness [m]")] = None,
    thickness_range: Annotated[
        str | None, typer.Option("--thickness-range", help="random thickness range 'MIN,MAX' [m]")
    ] = None,
    concentration: Annotated[
        float | None, typer.Option("--concentration", help="user observation: ice concentration (0, 1]")
    ] = None,
    mean_thickness: Annotated[
        float | None, typer.Option("--mean-thickness", help="user observation: mean thickness [m]")
    ] = None,
    diameters: Annotated[
        str | None, typer.Option("--diameters", help="user observation: diameter classes 'D1,D2,...' [m]")
    ] = None,
    percentages: Annotated[
        str | None,
        typer.Option("--percentages", help="user observation: share of floes per class 'P1,P2,...' [%]"),
    ] = None,
    figure: Annotated[Path | None, typer.Option("--figure", help="also write a figure (PNG/PDF/SVG)")] = None,
    geojson: Annotated[Path | None, typer.Option("--geojson", help="also write GeoJSON")] = None,
    overwrite: Annotated[bool, typer.Option("--overwrite", help="replace existing output files")] = False,
) -> None:
    """Generate a random floe field from an ice observation and save it as GeoParquet."""
    from floebreak.ice.generation import generate_field
    from floebreak.io.field_files import export_geojson, save_field

    observation = _observation_from_options(obs, concentration, mean_thickness, diameters, percentages)
    trange = _parse_floats(thickness_range, "thickness_range")
    if trange is not None and len(trange) != 2:
        raise InputError(
            "thickness_range", f"{thickness_range!r} needs two values MIN,MAX", allowed="MIN,MAX [m]"
        )
    _check_field_options(length, width, thickness, trange)
    _check_field_outputs({"out": out, "figure": figure, "geojson": geojson}, overwrite)
    with _stage_progress("field") as progress:
        floe_field = generate_field(
            observation,
            length_m=length,
            width_m=width,
            rng=np.random.default_rng(seed),
            generator=generator.value,
            thickness_m=thickness,
            thickness_range_m=trange,
            seed=seed,
            progress=progress,
        )
    save_field(floe_field, out, field="out")
    written = [str(out)]
    if geojson is not None:
        export_geojson(floe_field, geojson, field="geojson")
        written.append(str(geojson))
    if figure is not None:
        from floebreak.api import plot_field_figure
        from floebreak.io.figures import save_figure

        save_figure(plot_field_figure(floe_field), figure, field="figure")
        written.append(str(figure))
    console.print(
        f"{floe_field.n_floes} floes, concentration {100 * floe_field.concentration:.2f} % "
        f"(target {100 * observation.concentration:g} %) → {', '.join(written)}"
    )


@contextmanager
def _stage_progress(label: str, quiet: bool = False):
    """A transient progress bar on stderr for a stage longer than about 2 s whose function takes a plain
    `progress(stage, done, total)` callback: `generate_field` (placement rounds; large fields take
    minutes), the shaft cases, the propeller analysis and the writing of its files and figures."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=err_console, transient=True, disable=quiet) as bar:
        task = bar.add_task(label, total=None)

        def progress(stage: str, done: int, total: int) -> None:
            bar.update(task, description=f"{label}: {stage}", completed=done, total=total or None)

        yield progress


def _check_field_options(length: float, width: float, thickness, thickness_range) -> None:
    """The scenario's ranges (`floebreak.scenario`, one place) for the options, named as options."""
    from floebreak.scenario import Scenario

    options = {"field.length_m": "length", "field.width_m": "width", "ice.thickness_m": "thickness"}
    data = {"field": {"length_m": length, "width_m": width}, "ice": {}}
    if thickness is not None:
        data["ice"]["thickness_m"] = thickness
    if thickness_range is not None:
        data["ice"]["thickness_range_m"] = list(thickness_range)
    try:
        Scenario.from_dict(data)
    except InputError as error:
        key = options.get(error.field, "thickness_range" if "thickness_range" in error.field else error.field)
        message = str(error).split(": ", 1)[1]
        raise InputError(key, message, value=error.value, allowed=error.allowed) from None


def _check_field_outputs(paths: dict[str, Path | None], overwrite: bool) -> None:
    """Refuse, before anything is generated, an existing output without --overwrite, a missing directory,
    an unknown figure format; StorageError (exit 3) for a directory the machine will not write."""
    from matplotlib.figure import Figure

    from floebreak.io.storage import probe_directory

    for name, path in paths.items():
        if path is None:
            continue
        if path.exists() and not overwrite:
            allowed = "a new path, or overwrite=True (--overwrite)"
            raise InputError(name, f"{str(path)!r} exists", allowed=allowed)
        if not path.parent.is_dir():
            raise InputError(
                name, f"directory {str(path.parent)!r} does not exist", allowed="an existing directory"
            )
        probe_directory(path.parent, path)
    figure = paths.get("figure")
    if figure is not None:
        formats = Figure().canvas.get_supported_filetypes()
        if (figure.suffix.lstrip(".").lower() or "png") not in formats:
            raise InputError(
                "figure", f"unknown figure format {figure.suffix!r}", allowed=", ".join(sorted(formats))
            )


def _observation_from_options(obs, concentration, mean_thickness, diameters, percentages) -> Observation:
    user_values = (concentration, mean_thickness, diameters, percentages)
    if obs is not None:
        if any(v is not None for v in user_values):
            raise InputError("obs", "give either --obs or a user observation, not both")
        return get_observation(obs)
    if any(v is None for v in user_values):
        raise InputError(
            "obs",
            "no observation given",
            allowed="--obs KEY, or all of --concentration --mean-thickness --diameters --percentages",
        )
    return Observation(
        concentration=concentration,
        mean_thickness_m=mean_thickness,
        diameter_classes_m=_parse_floats(diameters, "diameters"),
        percentages=_parse_floats(percentages, "percentages"),
    )


# --- run, demo, schema, report ----------------------------------------------------------------------


class _Progress:
    """Callback for `simulate`: a rich progress bar with the bow position and the cusps so far."""

    def __init__(self, progress) -> None:
        self.progress = progress
        self.task = None
        self.n_steps = 0

    def __call__(self, event) -> None:
        from floebreak.simulation import RunStarted, StepDone

        if isinstance(event, RunStarted):
            self.n_steps = event.n_steps
            self.task = self.progress.add_task(
                "transit", total=event.n_steps, bow_x=event.x_start_m, cusps=0, flipped=0
            )
        elif isinstance(event, StepDone) and self.task is not None:
            if event.step % 16 == 0 or event.step == self.n_steps - 1:
                self.progress.update(
                    self.task,
                    completed=event.step + 1,
                    bow_x=event.bow_x_m,
                    cusps=event.n_cusps,
                    flipped=event.n_flipped,
                )


def _failed_scenario_path(out: Path) -> Path:
    return out.parent / f"{out.name}.failed-scenario.toml"


def _save_failed_scenario(out: Path, scenario, error: BaseException) -> Path | None:
    """Write the scenario and the traceback next to `out` for a bug report (best effort, atomic: a full disk
    leaves no empty file)."""
    import traceback

    from floebreak.io.atomic import atomic_path

    path = _failed_scenario_path(out)
    lines = traceback.format_exception(type(error), error, error.__traceback__)
    comment = "".join("# " + line + "\n" for line in "".join(lines).rstrip().splitlines())
    text = "# floebreak internal error — please attach this file to a bug report\n" + comment + "\n"
    try:
        with atomic_path(path, field="out") as temp:
            temp.write_text(text + scenario.to_toml(), encoding="utf-8")
    except (OSError, InputError):
        return None
    return path


def _interrupted(error: BaseException) -> bool:
    """Whether `error` is, or was raised while handling, a KeyboardInterrupt (Ctrl-C inside a numba kernel
    surfaces as ``SystemError: CPUDispatcher(...) returned a result with an exception set``)."""
    seen: set[int] = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False


def _not_a_bug(error: BaseException, out: Path) -> BaseException | None:
    """What to report instead of an internal error: Ctrl-C, or a problem of the machine (StorageError)."""
    from floebreak.io.storage import as_storage_error

    if _interrupted(error):
        return KeyboardInterrupt()
    return as_storage_error(error, out)


def _prepare_kernels(quiet: bool) -> None:
    """Load the numba kernels before the progress bar starts: ≈ 0.2 s from numba's on-disk cache, but a
    machine's first run compiles them (≈ 10–20 s), which would otherwise look like a run stuck at 0 %."""
    import time

    from floebreak.mechanics import compile_kernels

    message = "loading the compiled kernels (a machine's first run compiles them once, ≈ 10–20 s)"
    started = time.perf_counter()
    with nullcontext() if quiet else err_console.status(message):
        compile_kernels()
    seconds = time.perf_counter() - started
    if seconds > 3.0 and not quiet:
        err_console.print(f"compiled the numba kernels in {seconds:.0f} s (cached for later runs)")


def _execute(scenario, out: Path, overwrite: bool, quiet: bool, label: str, then=None, engine_loaded=None):
    """Run a (validated) scenario with a progress bar, write the run directory, print the summary.

    `then(run_dir, run_id)`, if given, adds to the run directory before it appears under `out` (the whole
    directory stays atomic); its return value is returned. `engine_loaded()`, if given, is called once the
    engine is imported (`main`).
    """
    from floebreak.api import check_output_directory
    from floebreak.app.figure_process import figure_worker

    check_output_directory(out, overwrite)  # refuse before spending the run time
    resolved = scenario.resolved()
    with figure_worker() as worker:  # forked now, it imports matplotlib while the engine runs
        return _run_and_write(resolved, out, overwrite, quiet, label, then, engine_loaded, worker)


def _run_and_write(
    resolved, out: Path, overwrite: bool, quiet: bool, label: str, then, engine_loaded, worker
):
    """`_execute`'s run and write, with the figure worker forked before it (or None)."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from floebreak.api import run as run_scenario
    from floebreak.io.atomic import atomic_directory, scratch_directory

    _prepare_kernels(quiet)
    if engine_loaded is not None:
        engine_loaded()  # the console's hook (`main`)
    try:
        progress = Progress(
            TextColumn("[progress.description]{task.description}"),
            BarColumn(),
            TextColumn("bow x = {task.fields[bow_x]:7.1f} m"),
            TextColumn("cusps {task.fields[cusps]:5d}  flipped {task.fields[flipped]:4d}"),
            TimeElapsedColumn(),
            console=err_console,
            disable=quiet,
            transient=False,
        )
        # the contact records stream to a scratch folder next to `out` while the run goes on (bounded
        # memory), and are copied into the run directory: a failure leaves neither behind
        with scratch_directory(out) as spool:
            with progress:
                result = run_scenario(
                    resolved, callbacks=[_Progress(progress)], spool=spool, figure_worker=worker
                )
            if then is None:
                result.write(out, overwrite=overwrite, figure_worker=worker)
                added = None
            else:
                with atomic_directory(out, overwrite=overwrite, field="out") as temp:
                    # replaces the empty temporary directory; the report names the final directory
                    result.write(temp, overwrite=True, directory_name=out.name, figure_worker=worker)
                    added = then(temp, out.name)
    except InputError:
        raise
    except Exception as error:
        instead = _not_a_bug(error, out)
        if instead is not None:
            raise instead from None
        saved = _save_failed_scenario(out, resolved, error)
        where = f"; scenario and traceback saved to {saved}" if saved else ""
        err_console.print(
            f"[bold red]internal error:[/] {escape(f'{type(error).__name__}: {error}{where}')} "
            "— please report this bug",
            soft_wrap=True,
            markup=True,
            highlight=False,
        )
        raise typer.Exit(1) from None
    if not quiet:
        console.print(_summary_table(result.summary, label))
    for warning in result.summary.get("warnings", []):
        err_console.print(f"[bold yellow]warning:[/] {escape(warning)}", soft_wrap=True, highlight=False)
    console.print(f"written: {out}/ (summary.json, *.parquet, figures/, report.html)", soft_wrap=True)
    return added


def _summary_table(summary: dict, label: str) -> Table:
    table = Table(title=label)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = (
        ("floes (initial)", "n_floes_initial", "{:d}"),
        (r"initial ice area \[m²]", "initial_ice_area_m2", "{:.1f}"),
        ("cusps n_cusp", "n_cusps", "{:d}"),
        (r"cusp area A_cusp^tot \[m²]", "cusp_area_m2", "{:.1f}"),
        (r"mean cusp volume \[m³]", "mean_cusp_volume_m3", "{:.2f}"),
        ("flipped n_flip", "n_flipped", "{:d}"),
        (r"flipped area A_flip^tot \[m²]", "flipped_area_m2", "{:.1f}"),
        (r"remaining ice area \[m²]", "remaining_ice_area_m2", "{:.1f}"),
        ("area balance (rel. error)", "area_balance_rel_error", "{:.1e}"),
        (r"max crushing force \[MN]", "crushing_force_max_n", "{:.2f}"),
        (r"wall time \[s]", "wall_time_s", "{:.1f}"),
    )
    for name, key, fmt in rows:
        value = summary.get(key)
        if key == "crushing_force_max_n" and value is not None:
            value = value / 1e6
        text = "–" if value is None or value != value else fmt.format(value)
        table.add_row(name, text)
    return table


SetOption = Annotated[
    list[str] | None,
    typer.Option("--set", help="override a scenario key, e.g. --set ice.thickness_m=0.8 (repeatable)"),
]
OverwriteOption = Annotated[bool, typer.Option("--overwrite", help="replace an existing output directory")]
QuietOption = Annotated[bool, typer.Option("--quiet", "-q", help="no progress bar and no summary table")]


@app.command("run")
def run_command(
    ctx: typer.Context,
    scenario_file: Annotated[Path, typer.Argument(metavar="SCENARIO", help="scenario file (TOML)")],
    out: Annotated[Path, typer.Option("--out", help="run directory to write (must not exist)")],
    overrides: SetOption = None,
    overwrite: OverwriteOption = False,
    quiet: QuietOption = False,
) -> None:
    """Run a scenario file and write a complete run directory (see `floebreak schema` for the keys)."""
    from floebreak.scenario import Scenario

    scenario = Scenario.from_toml(scenario_file, overrides=overrides or ())
    _execute(scenario, out, overwrite, quiet, f"floebreak run: {scenario_file.name}", engine_loaded=ctx.obj)


@app.command()
def demo(
    ctx: typer.Context,
    out: Annotated[Path, typer.Option("--out", help="output directory")] = Path("demo-output"),
    overwrite: OverwriteOption = False,
    seed: Annotated[
        int | None, typer.Option("--seed", help="random seed (default: the scenario's, 1)")
    ] = None,
    overrides: SetOption = None,
    quiet: QuietOption = False,
    no_propeller: Annotated[
        bool, typer.Option("--no-propeller", help="skip the propeller spectra (OUT/propeller/)")
    ] = False,
) -> None:
    """Run the reference scenario (thesis §5.3: obs 2019-12-18T20:20, 385 m × 100 m, h = 1 m, Agulhas II).

    Writes a run directory into OUT and, inside it, the propeller force and torque spectra of its cusps
    (OUT/propeller/, as `floebreak propeller OUT`: Agulhas II, pitch 0 % and 95 %). Atomic: a failed demo
    leaves nothing. No scenario file needed.
    """
    from floebreak.scenario import Scenario

    extra = [*(overrides or ()), *([f"seed={seed}"] if seed is not None else [])]
    scenario = Scenario.reference(overrides=extra)
    label = f"floebreak demo: reference scenario, seed {scenario.seed}"
    then = None if no_propeller else _demo_propeller
    propeller_summary = _execute(scenario, out, overwrite, quiet, label, then=then, engine_loaded=ctx.obj)
    if propeller_summary is not None:
        _print_propeller_summary(propeller_summary, out / DEMO_PROPELLER_DIR, quiet)


DEMO_PROPELLER_DIR = "propeller"


def _demo_propeller(run_dir: Path, run_id: str) -> dict:
    """Propeller analysis (defaults: Agulhas II; the profile's load model and transport, the scenario's
    speed, fraction reaching and propellers) of `run_dir` into `run_dir/propeller`; returns its summary.
    `run_id` names the run (the folder is still temporary)."""
    from floebreak.app.propeller import analyse_propeller, read_runs, write_propeller
    from floebreak.propeller.load_models import profile_defaults
    from floebreak.report import write_report

    inputs = read_runs(run_dir)
    cusps = inputs.cusps.set_column(
        inputs.cusps.column_names.index("run_id"), "run_id", pa_array([run_id] * inputs.cusps.num_rows)
    )
    exposures = None if inputs.exposures is None else {run_id: next(iter(inputs.exposures.values()))}
    load_model, transport = profile_defaults(inputs.profile)
    result = analyse_propeller(cusps, exposures=exposures, load_model=load_model, transport=transport)
    written = write_propeller(result, run_dir / DEMO_PROPELLER_DIR, record={"runs": [run_id]})
    write_report(run_dir, directory_name=run_id)  # again, now with the propeller section
    return _written_summary(written)


def _written_summary(folder: Path) -> dict:
    """An analysis folder's summary.json as written (the terminal shows what the files hold)."""
    import json

    return json.loads((Path(folder) / "summary.json").read_text(encoding="utf-8"))


def pa_array(values: list[str]):
    import pyarrow as pa

    return pa.array(values, pa.string())


def _fmt(value, spec: str) -> str:
    return "–" if value is None or value != value else format(value, spec)


def _propeller_table(summary: dict) -> Table:
    """Per pitch: cusps with a load, beyond the FEM table, the |Q| ranges with density > 0.1 % per kN·m
    (thesis §6.2) and the maximum |Q|."""
    options = summary["options"]
    if options.get("load_model", "fem") == "fem":
        title = f"propeller spectra (FEM, {options['interpolation']}, beyond table: {options['beyond']})"
    else:
        title = "propeller spectra (blade milling model)"
    table = Table(title=title)
    for name in (r"pitch \[%]", "cusps", "beyond table", r"|Q| density > 0.1 %/kN·m \[kN·m]"):
        table.add_column(name, justify="left" if "density" in name else "right")
    table.add_column(r"max |Q| \[kN·m]", justify="right")
    for label, info in summary["pitches"].items():
        intervals = summary["simulated_torque_above_threshold"][label]["intervals_knm"]
        ranges = "–" if not intervals else f"{intervals[0][0]:g}–{intervals[-1][1]:g}"
        if len(intervals) > 1:  # bins below the threshold inside the envelope
            ranges += f" ({len(intervals)} parts)"
        q_range = info["torque_range_knm"]
        table.add_row(
            f"{info['pitch_percent']:g}",
            str(summary["n_cusps"] - info["n_without_load"]),
            f"{info['n_beyond_table']} ({100 * info['fraction_beyond_table']:.0f} %)",
            ranges,
            "–" if q_range is None else f"{q_range[1]:.0f}",
        )
    return table


def _rule_form_table(summary: dict) -> Table | None:
    """Per pitch: the rule-form fit of |Q| (k with 95 % interval against the rule's k) and the expected
    largest |Q| per hour and over the operating profile (notes §7.3)."""
    rule_form = summary.get("rule_form") or {}
    table = Table(title="rule form P(Q ≥ q) = exp(−(q/q_max)^k ln N) fitted to |Q|, one propeller")
    for name in (
        r"pitch \[%]",
        "k (95 % CI)",
        "rule k",
        r"fitted |Q| \[kN·m]",
        r"q_max per h \[kN·m]",
        r"q_max profile \[kN·m]",
    ):
        table.add_column(name, justify="right")
    rows = 0
    for label, info in summary["pitches"].items():
        fit = (rule_form.get(label) or {}).get("torque_knm") or {}
        if "k" not in fit:
            continue
        rows += 1
        table.add_row(
            f"{info['pitch_percent']:g}",
            f"{fit['k']:.2f} ({fit['k_ci95'][0]:.2f}–{fit['k_ci95'][1]:.2f})",
            f"{fit['rule_k']:g}",
            "–" if not fit.get("validity_range") else "{:.0f}–{:.0f}".format(*fit["validity_range"]),
            _fmt(fit.get("x_max_per_hour"), ".0f"),
            _fmt(fit.get("x_max_lifetime"), ".0f"),
        )
    return table if rows else None


def _design_load_tables(summary: dict) -> list[Table]:
    """Per propeller, one column per pitch: the design ice torque and blade force against the rule's
    Q_max and F_b, their ratios and the loads over the profile against N_ice (the basis of each number:
    `_design_basis_lines`). Quantities as rows, so that the table fits 80 columns."""
    out = []
    for entry in summary.get("design_loads") or []:
        table = Table(title=f"design loads, {entry['propeller']}, against IACS UR I3 {entry['polar_class']}")
        table.add_column("quantity", overflow="fold")
        for row in entry["rows"]:
            table.add_column(f"pitch {row['pitch_percent']:g} %", justify="right", overflow="fold")
        table.add_column("unit", overflow="fold")
        for label, key, spec, unit in _DESIGN_ROWS:
            table.add_row(label, *(_fmt(row[key], spec) for row in entry["rows"]), unit)
        origin = []
        for row in entry["rows"]:
            basis = row["basis"]["design Q"]
            n_sim = basis.split(" simulated loads")[0].rsplit(" ", 1)[-1]
            origin.append("x_max over profile" if basis.startswith("rule-form") else f"largest of {n_sim}")
        table.add_row("design values from", *origin, "")
        out.append(table)
    return out


_DESIGN_ROWS = (  # label, key of summary.json's design_loads rows, format, unit
    ("design ice torque Q", "design_torque_kn_m", ".0f", "kN·m"),
    ("rule Q_max", "rule_max_torque_kn_m", ".0f", "kN·m"),
    ("Q / Q_max", "torque_ratio", ".2f", "-"),
    ("design blade force F", "design_force_kn", ".0f", "kN"),
    ("rule F_b (backward)", "rule_backward_force_kn", ".0f", "kN"),
    ("F / F_b", "force_ratio", ".2f", "-"),
    ("loads over the profile", "n_loads_profile", ".3g", "-"),
    ("rule N_ice", "rule_n_ice", ".3g", "-"),
    ("loads / N_ice", "loads_ratio", ".2f", "-"),
)


def _design_basis_lines(summary: dict) -> list[str]:
    """The basis of the design-load tables' numbers, each distinct text once; the design values' by kind
    (extrapolated, or why not), the counts stripped (full texts per row: summary.json "design_loads")."""
    seen: dict[str, None] = {}
    for entry in summary.get("design_loads") or []:
        for row in entry["rows"]:
            for key in ("rule Q_max", "rule F_b", "rule N_ice", "loads over profile"):
                seen.setdefault(f"{key}: {row['basis'][key]}", None)
            for key in ("design Q", "design F"):
                text = row["basis"][key]
                if text.startswith("rule-form"):
                    text = "rule-form x_max over the operating profile's loads (notes §7.3)"
                else:
                    text = "largest simulated load (not extrapolated" + text.split("(not extrapolated", 1)[1]
                seen.setdefault(f"design values: {text}", None)
    return list(seen)


def _model_line(summary: dict) -> str:
    """The per-cusp torque model and which cusps reach a propeller (fractions per propeller)."""
    model = summary.get("load_model") or {}
    transport = summary.get("transport") or {}
    rule = transport.get("rule")
    fraction = transport.get("fraction_reaching")
    reach = "–" if fraction is None else f"{fraction:.3g}"
    if rule in ("hull", "flow"):
        per = ", ".join(f"{f:.3g}" for f in transport.get("fraction_reaching_per_propeller", []))
        reach = f"{reach} (transport model; per propeller {per})"
    elif rule == "override":
        reach += " (override)"
    else:
        reach += " (every cusp)"
    placement = f" ({model['placement']})" if model.get("placement") else ""
    return (
        f"per-cusp loads: {model.get('name', '–')} model{placement}; fraction of cusps reaching a propeller: "
        f"{reach}; rated torque {model.get('rated_torque_knm', math.nan):.1f} kN·m"
    )


def _print_propeller_summary(summary: dict, folder: Path, quiet: bool) -> None:
    """The propeller summary table, the time base, warnings (always) and the files written."""
    if not quiet:
        console.print(_propeller_table(summary))
        rule_table = _rule_form_table(summary)
        if rule_table is not None:
            console.print(rule_table)
        for table in _design_load_tables(summary):
            console.print(table)
        for line in _design_basis_lines(summary):
            console.print(f"  {line}", highlight=False, soft_wrap=True)
        if summary.get("ice_class") is None:
            console.print("design-load table: add --polar-class (e.g. PC5)", highlight=False)
        console.print(_model_line(summary), highlight=False, soft_wrap=True)
        rates = summary.get("rates")
        if rates:
            console.print(
                f"time base: {rates['transit_m']:.0f} m of transit, {rates['hours_in_ice']:.3f} h in ice; "
                f"{rates['loads_per_hour_per_propeller']:.0f} loads per hour and "
                f"{rates['loads_per_km_per_propeller']:.0f} per km on one propeller",
                highlight=False,
            )
        for label, info in (summary.get("rule_form") or {}).items():
            miner = info.get("miner") if isinstance(info, dict) else None
            if miner:
                life = miner["damage_lifetime"]
                over = "" if life is None else f", {life:.3g} over the operating profile"
                console.print(
                    f"Miner sum ({miner['quantity']}, pitch {label[1:]} %): "
                    f"{miner['damage_per_hour']:.3g} per hour{over}",
                    highlight=False,
                )
    for warning in summary.get("warnings", []):
        err_console.print(f"[bold yellow]warning:[/] {escape(warning)}", soft_wrap=True, highlight=False)
    console.print(
        f"written: {folder}/ (spectra.nc, load_/torque_spectrum.csv, *_exceedance.csv, cusp_loads.csv, "
        "summary.json, figures/)",
        soft_wrap=True,
        highlight=False,
    )


@app.command()
def schema() -> None:
    """Print the JSON schema of scenario files (units in the descriptions)."""
    import json

    from floebreak.scenario import json_schema

    typer.echo(json.dumps(json_schema(), indent=2, ensure_ascii=False))


@app.command()
def report(
    run_dir: Annotated[Path, typer.Argument(metavar="DIR", help="run directory")],
) -> None:
    """Write DIR/report.html: summary, figures, scenario and provenance on one self-contained page."""
    from floebreak.report import write_report

    console.print(f"written: {write_report(run_dir)}", soft_wrap=True)


@app.command()
def animate(
    run_dir: Annotated[Path, typer.Argument(metavar="DIR", help="run directory (floebreak run / demo)")],
    out: Annotated[
        Path | None, typer.Option("--out", help="animation file (default DIR/animation.gif or .mp4)")
    ] = None,
    fps: Annotated[int, typer.Option("--fps", help="frames per second (1 … 60)")] = 10,
    every: Annotated[
        int | None,
        typer.Option(
            "--every",
            help="one frame every K bow steps (default: K for at most 200 frames; a dynamic run: a multiple "
            "of its simulation.pose_interval_steps)",
        ),
    ] = None,
    fmt: Annotated[
        str | None,
        typer.Option("--format", help="gif | mp4 (mp4 needs ffmpeg; default: from --out, else gif)"),
    ] = None,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="replace an existing animation file")
    ] = False,
    quiet: QuietOption = False,
) -> None:
    """Write an animation of the transit (bow advancing, floes breaking, cusps and flipped pieces appearing),
    replayed from DIR/pieces.parquet; the ice of a dynamic run moves, drawn from the poses it recorded
    (DIR/poses.parquet, simulation.pose_interval_steps). Written atomically; nothing written on bad input."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from floebreak.replay import animate_run_directory

    progress = Progress(
        TextColumn("frames"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=err_console,
        disable=quiet,
    )
    tasks = []

    def advance(done: int, total: int) -> None:
        if not tasks:  # started with the first frame: bad input fails before, without a bar
            progress.start()
            tasks.append(progress.add_task("frames", total=total))
        progress.update(tasks[0], completed=done)

    try:
        path, n_frames = animate_run_directory(
            run_dir, out, fps=fps, every=every, fmt=fmt, overwrite=overwrite, progress=advance
        )
    finally:
        progress.stop()
    console.print(f"written: {path} ({n_frames} frames at {fps} fps)", soft_wrap=True, highlight=False)


validate_app = typer.Typer(cls=_Group, no_args_is_help=True, help="Validation studies (thesis §5).")
app.add_typer(validate_app, name="validate")


@validate_app.command("single-floe")
def validate_single_floe(
    out: Annotated[Path, typer.Option("--out", help="output directory")],
    overwrite: OverwriteOption = False,
) -> None:
    """Single-floe validation matrix (thesis §5.2, Figs. 14–16): diameters × thicknesses × positions."""
    from floebreak.studies.single_floe import write_single_floe_matrix

    path = write_single_floe_matrix(out, overwrite=overwrite)
    console.print(f"written: {path}", soft_wrap=True)


def _register_studies() -> None:
    from floebreak.studies.cli import aggregate_command, study, voyage
    from floebreak.studies.validate_cli import convergence_command, sensitivity_command, thesis_command

    app.command("study")(study)
    app.command("aggregate")(aggregate_command)
    app.command("voyage")(voyage)
    validate_app.command("thesis")(thesis_command)
    validate_app.command("sensitivity")(sensitivity_command)
    validate_app.command("convergence")(convergence_command)


_register_studies()


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


def _print_pooling(inputs) -> None:
    n_runs = len(inputs.run_dirs)
    differing = f" (differing in {', '.join(inputs.differing_keys)})" if inputs.differing_keys else ""
    console.print(f"pooled {n_runs} runs{differing}" if n_runs > 1 else "1 run", highlight=False)


def _load_options(load_model, transport, rated_torque_knm, geometry, transport_parameters=None):
    """The `propeller` command's load-model options, checked before anything is read: a function of the
    runs' profile giving `analyse_propeller`'s load_model, transport, propeller, rated torque and transport
    settings (`--transport-parameter`)."""
    from floebreak.propeller.load_models import LOAD_MODELS, TRANSPORTS, check_choice, profile_defaults

    if load_model is not None:
        check_choice("--load-model", load_model, LOAD_MODELS)
    if transport is not None:
        check_choice("--transport", transport, TRANSPORTS)
    if rated_torque_knm is not None:
        require_range("--rated-torque-knm", rated_torque_knm, low=0.0, unit="kN m")
    spec = _propeller_spec(geometry)
    settings = transport_option(transport_parameters)

    def for_profile(profile: str) -> dict:
        default_model, default_transport = profile_defaults(profile)
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

    keys = [f.name for f in fields(PropellerSpec)]
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


# the `propeller` command's options (named here so that its signature stays readable)
_FemTableOption = Annotated[
    list[str] | None,
    typer.Option(
        "--fem-table",
        help="own FEM table CSV as PITCH=FILE (pitch in %; repeatable, one per pitch); FILE alone if it "
        "has a '# pitch_percent:' line",
    ),
]
_BeyondOption = Annotated[str, typer.Option("--beyond", help="power_law | clamp | extrapolate | flag")]
_PoolOption = Annotated[
    bool, typer.Option("--pool", help="pool runs whose scenarios differ in more than seed and field")
]
_SpeedOption = Annotated[
    float | None, typer.Option("--speed-m-s", help="ship speed in ice [m/s] (default: the scenario's)")
]
_LoadModelOption = Annotated[
    str | None,
    typer.Option(
        "--load-model",
        help="per-cusp loads: milling (blade milling model) | fem (FEM tables); default: the runs' profile "
        "(default → milling, thesis → fem); --fem-table implies fem",
    ),
]
_TransportOption = Annotated[
    str | None,
    typer.Option(
        "--transport",
        help="which cusps reach a propeller: hull (transport model) | all (every cusp); default: the runs' "
        "profile (default → hull, thesis → all); --fraction-reaching overrides both",
    ),
]
_RatedTorqueOption = Annotated[
    float | None,
    typer.Option(
        "--rated-torque-knm",
        help="the drive's rated torque [kN m] for the warnings (default: 4.5 MW / (2π · rpm), the built-in "
        "Agulhas II line: 306.9 kN m)",
    ),
]
_GeometryOption = Annotated[
    list[str] | None,
    typer.Option(
        "--propeller-geometry",
        help="propeller as KEY=VALUE (repeatable): radius_m, max_pitch_m, pitch_percent, rpm, blades, "
        "expanded_area_ratio, hub_ratio, blade_thickness_07_m, bollard_pitch_m (default: Agulhas II)",
    ),
]
_HoursPerYearOption = Annotated[
    float | None, typer.Option("--hours-in-ice-per-year", help="operating profile [h/a]")
]
_YearsOption = Annotated[float | None, typer.Option("--years", help="operating profile: years in service")]
_SnCurveOption = Annotated[
    str | None,
    typer.Option(
        "--sn-curve",
        help="Basquin S–N curve for Miner's sum, QUANTITY,M,AMPLITUDE,CYCLES, e.g. torque,5,1000,1e7 "
        "(N = CYCLES·(AMPLITUDE/x)^M; amplitude in kN·m for torque, kN for force)",
    ),
]
_StationOption = Annotated[
    str | None, typer.Option("--station", help="shaft measurement station (default: the line's)")
]
_RpmOption = Annotated[float | None, typer.Option("--rpm", help="propeller speed [1/min] (shaft analysis)")]
_MeanTorqueOption = Annotated[
    float | None, typer.Option("--mean-torque-knm", help="mean hydrodynamic torque [kN m] (shaft)")
]
_ShaftModelOption = Annotated[
    str | None,
    typer.Option(
        "--shaft-model",
        help="drive (transport + milling + torque-limited motor) | linear (every cusp, FEM, constant rpm); "
        "default: the run's profile's (default → drive, thesis → linear)",
    ),
]
_TorqueLimitOption = Annotated[
    float | None,
    typer.Option("--torque-limit-knm", help="motor torque limit [kN m] (drive model; default 1.6 × rated)"),
]
_ExcitationCasesOption = Annotated[
    str, typer.Option("--excitation-cases", help="ice excitation cases, first plotted, e.g. 1,2,3,4")
]


@app.command()
def propeller(
    run_or_study_dir: Annotated[Path, typer.Argument(help="a run directory or a study directory")],
    out: Annotated[Path, typer.Option("--out", help="output directory")],
    fem_table: _FemTableOption = None,
    torque_csv: Annotated[Path | None, typer.Option("--torque-csv", help="measured shaft torque CSV")] = None,
    polar_class: PolarClassOption = None,
    interpolation: Annotated[str, typer.Option("--interpolation", help="newton | pchip")] = "newton",
    beyond: _BeyondOption = "power_law",
    pool: _PoolOption = False,
    speed: _SpeedOption = None,
    fraction_reaching: FractionReachingOption = None,
    propellers: PropellersOption = None,
    load_model: _LoadModelOption = None,
    transport: _TransportOption = None,
    transport_parameters: TransportParameterOption = None,
    rated_torque_knm: _RatedTorqueOption = None,
    geometry: _GeometryOption = None,
    hours_per_year: _HoursPerYearOption = None,
    years: _YearsOption = None,
    sn_curve: _SnCurveOption = None,
    overwrite: OverwriteOption = False,
    quiet: QuietOption = False,
    shaft_line: ShaftLineOption = None,
    station: _StationOption = None,
    rpm: _RpmOption = None,
    mean_torque_knm: _MeanTorqueOption = None,
    cases: _ExcitationCasesOption = "1,2,3,4",
    shaft_model: _ShaftModelOption = None,
    torque_limit_knm: _TorqueLimitOption = None,
) -> None:
    """Propeller–ice force and torque spectra, rates and rule-form fit of the cusps of a run or study
    (thesis chapter 6; docs/propeller.md); with --shaft-line also the shaft torque at a measurement
    station of a run (docs/shaft.md)."""
    from floebreak.app.figure_process import figure_worker
    from floebreak.app.propeller import analyse_runs, read_runs

    models = _load_options(load_model, transport, rated_torque_knm, geometry, transport_parameters)
    profile = operating_profile(hours_per_year, years)
    curve = None if sn_curve is None else _sn_curve(sn_curve)
    tables = _fem_tables(fem_table)
    with _stage_progress("shaft", quiet) as progress:
        shaft = _shaft_analysis(
            run_or_study_dir,
            shaft_line,
            station,
            rpm,
            speed,
            mean_torque_knm,
            cases,
            tables,
            torque_csv,
            interpolation,
            beyond,
            shaft_model,
            torque_limit_knm,
            sn_curve=curve,
            transport_settings=transport_option(transport_parameters),
            progress=progress,
        )
    # forked after the shaft analysis, whose openTorsion imports matplotlib: the workers inherit it; one
    # for the propeller's figures, one for the shaft's
    with figure_worker() as first, figure_worker() if shaft is not None else nullcontext() as second:
        overrides = {"speed_m_s": speed, "fraction_reaching": fraction_reaching, "n_propellers": propellers}
        inputs = read_runs(run_or_study_dir, pool=pool, **overrides)
        with _stage_progress("propeller analysis", quiet) as progress:
            result = analyse_runs(
                inputs,
                **models(inputs.profile),
                fem_table=tables,
                torque_csv=torque_csv,
                polar_class=polar_class,
                interpolation=interpolation,
                beyond=beyond,
                operating_profile=profile,
                sn_curve=curve,
                progress=progress,
            )
        _write_propeller_outputs(result, inputs, shaft, out, overwrite, quiet, (first, second))


def _write_propeller_outputs(result, inputs, shaft, out: Path, overwrite: bool, quiet: bool, workers) -> None:
    """Write the propeller analysis `result` of `inputs` and the prepared `shaft` analysis (if any) and
    print their summaries; of the two figure `workers` (or None) the first draws the propeller's figures,
    the second the shaft's."""
    from floebreak.app.propeller import write_propeller

    record = {"runs": sorted(inputs.run_dirs), "pooled_differing_keys": list(inputs.differing_keys)}
    mine, theirs = workers
    with _stage_progress("writing", quiet) as progress:
        written = write_propeller(
            result, out, overwrite=overwrite, record=record, progress=progress, figure_worker=mine
        )
    _print_pooling(inputs)
    _print_propeller_summary(_written_summary(written), written, quiet)
    if shaft is not None:
        _write_shaft(shaft, Path(written) / "shaft", overwrite, quiet, theirs)


def _write_shaft(shaft, out: Path, overwrite: bool, quiet: bool = False, figure_worker=None) -> None:
    """Write the prepared shaft analysis (with a progress bar; its figures drawn by `figure_worker` if
    given); print the design tables (`_shaft_tables`), the model's lines and warnings, and where it was
    written."""
    import json

    with _stage_progress("writing the shaft analysis", quiet) as progress:
        shaft_dir = shaft.write(out, overwrite=overwrite, progress=progress, figure_worker=figure_worker)
    summary = json.loads((Path(shaft_dir) / "summary.json").read_text(encoding="utf-8"))
    for table in _shaft_tables(summary):
        console.print(table)
    for line in shaft.messages():
        console.print(line, highlight=False, soft_wrap=True)
    console.print(
        f"shaft torque written to {shaft_dir}/ (shaft_series.nc/.csv, shaft_spectra.nc/.csv, modes.csv, "
        "rainflow.csv, summary.json, figures/ with campbell.png and rainflow_histogram.png)",
        highlight=False,
        soft_wrap=True,
    )


def _shaft_tables(summary: dict) -> tuple[Table, Table]:
    """The shaft line's design numbers (first natural frequency, blade-passage frequency, resonance margin,
    Miner's damage) and, per excitation case, Q_peak, the shaft minimum, the drive's min rpm and peak
    motor torque. Columns fold instead of cutting when the output is piped (80 columns)."""
    resonance, fatigue = summary["resonance"], summary["fatigue"]
    margin = min(min(row) for row in resonance["margin"])
    inside = margin < resonance["required_margin"]
    if fatigue["damage"] is not None:
        damage = (
            f"{fatigue['damage']:.3g} ({fatigue['histogram']['n_cycles']:g} cycles, case {fatigue['case']})"
        )
    else:
        damage = "no S–N curve given" if fatigue["sn_curve"] is None else fatigue["note"]
    line = Table(title=f"shaft line {summary['shaft_line']['name']}, station {summary['station']}")
    line.add_column("quantity", overflow="fold")
    line.add_column("value", justify="right", overflow="fold")
    line.add_column("unit", overflow="fold")
    op = summary["operating_point"]
    line.add_row(
        "first natural frequency", f"{summary['modes_free_free']['natural_frequencies_hz'][0]:.2f}", "Hz"
    )
    line.add_row(
        f"blade-passage frequency at {op['rpm']:g} rpm", f"{op['blade_passage_frequency_hz']:.2f}", "Hz"
    )
    line.add_row(
        f"resonance margin (required {100 * resonance['required_margin']:.0f} %)",
        f"{100 * margin:.1f}" + (" [bold yellow]WARNING[/]" if inside else ""),
        "%",
    )
    line.add_row("Miner's damage, shaft torque", escape(damage), "-")
    cases = Table(title=f"shaft torque per excitation case ({summary['shaft_model']} model)")
    for name in ("case", r"Q_peak \[kN·m]", r"shaft min \[kN·m]", r"min rpm \[1/min]", r"peak motor \[kN·m]"):
        cases.add_column(name, justify="right", overflow="fold")
    drive = (summary.get("drive") or {}).get("cases", {})
    for case, peak in summary["q_peak_knm"].items():
        d = drive.get(case) or {}
        cases.add_row(
            case,
            _fmt(peak["q_peak_knm"], ".0f"),
            _fmt(peak["q_min_knm"], ".0f"),
            _fmt(d.get("min_rpm"), ".1f"),
            _fmt(d.get("peak_motor_torque_knm"), ".0f"),
        )
    return line, cases


def _shaft_analysis(
    run_dir,
    shaft_line,
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
    progress=None,
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
        cases=_parse_floats(cases, "excitation_cases"),
        fem_table=tables,
        torque_csv=torque_csv,
        interpolation=interpolation,
        beyond=beyond,
        shaft_model=shaft_model,
        torque_limit_knm=torque_limit_knm,
        sn_curve=sn_curve,
        transport_settings=transport_settings,
        progress=progress,
    )


def _print_version(value: bool) -> None:
    """`--version`: floebreak's version and what results depend on (libraries, BLAS kernels), for reports."""
    if not value:
        return
    import numpy  # noqa: F401  (loads numpy's BLAS)
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS, which the field packing uses)

    from floebreak.io.provenance import floebreak_version, library_versions

    console.print(f"floebreak {floebreak_version()}", highlight=False)
    for name, version in library_versions().items():
        console.print(f"  {name} {version}", highlight=False, soft_wrap=True)
    raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            callback=_print_version,
            is_eager=True,
            help="Print floebreak's version, the library versions and BLAS kernels results depend on.",
        ),
    ] = False,
) -> None:
    """floebreak: ship bow breaking sea-ice floes, and the cusps' propeller–ice loads."""


def main(engine_loaded=None) -> None:
    """The command line (the console command reaches it through `floebreak.__main__`). A user error
    (InputError) prints one line naming the field and exits with code 2. `engine_loaded()`, if given, is
    called once a run's engine is imported, before it runs (passed to the commands as the context's `obj`)."""
    from floebreak.io.storage import StorageError

    try:
        # Ctrl-C raises KeyboardInterrupt from here, reported below (`floebreak.__main__`: while loading)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        app(obj=engine_loaded)
    except InputError as error:
        err_console.print(f"[bold red]error:[/] {escape(str(error))}", soft_wrap=True, highlight=False)
        sys.exit(EXIT_INPUT)
    except StorageError as error:
        err_console.print(f"[bold red]error:[/] {escape(error.strerror)}", soft_wrap=True, highlight=False)
        sys.exit(EXIT_STORAGE)
    except KeyboardInterrupt:
        _report_interrupt()
    except SystemExit as exit_:
        if exit_.code == EXIT_INTERRUPTED:  # typer turns a KeyboardInterrupt into exit code 130, silently
            _report_interrupt()
        raise


def _report_interrupt() -> None:
    message, code = interruption()  # Ctrl-C's, or SIGTERM's (`floebreak.__main__`)
    err_console.print(message, highlight=False)
    sys.exit(code)


_use_command_class(app)  # once every command is registered
_use_command_class(validate_app)


if __name__ == "__main__":  # `python -m floebreak.cli`: the console command without its collector settings
    main()
