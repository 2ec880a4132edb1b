"""`floebreak run`, `demo` and `field`: a scenario (or the reference one, or an observation) run or
generated and written."""

from __future__ import annotations

from contextlib import nullcontext
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
import typer.core
from rich.markup import escape

from floebreak import constants as c
from floebreak.app.unexpected import interrupted
from floebreak.cli.common import console, err_console, parse_floats, stage_progress
from floebreak.cli.options import (
    GeneratorName,
    OverwriteOption,
    QuietOption,
    SetOption,
)
from floebreak.cli.tables import print_propeller_summary, summary_table
from floebreak.errors import InputError
from floebreak.ice.observations import Observation, get_observation


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
    from floebreak.ice.budget import FieldBudget
    from floebreak.ice.generation import generate_field
    from floebreak.output.field_files import export_geojson, save_field

    observation = _observation_from_options(obs, concentration, mean_thickness, diameters, percentages)
    trange = parse_floats(thickness_range, "thickness_range")
    if trange is not None and len(trange) != 2:
        raise InputError(
            "thickness_range", f"{thickness_range!r} needs two values MIN,MAX", allowed="MIN,MAX [m]"
        )
    _check_field_options(length, width, thickness, trange)
    _check_field_outputs({"out": out, "figure": figure, "geojson": geojson}, overwrite)
    with stage_progress("field") as progress:
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
            budget=FieldBudget(size_keys="--length/--width"),
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


def _check_field_options(length: float, width: float, thickness, thickness_range) -> None:
    """The scenario's ranges (`floebreak.config.scenario`, one place) for the options, named as options."""
    from floebreak.config.scenario import Scenario

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
        diameter_classes_m=parse_floats(diameters, "diameters"),
        percentages=parse_floats(percentages, "percentages"),
    )


class _Progress:
    """Callback for `simulate`: a rich progress bar with the bow position and the cusps so far."""

    def __init__(self, progress) -> None:
        self.progress = progress
        self.task = None
        self.n_steps = 0

    def __call__(self, event) -> None:
        from floebreak.engine.loop import RunStarted, StepDone

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


def _not_a_bug(error: BaseException, out: Path) -> BaseException | None:
    """What to report instead of an internal error: Ctrl-C, or a problem of the machine (StorageError)."""
    from floebreak.io.storage import as_storage_error

    if interrupted(error):
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
    from floebreak.io.output_lock import output_lock
    from floebreak.output.figure_process import figure_worker

    check_output_directory(out, overwrite)  # refuse before spending the run time
    resolved = scenario.resolved()
    # one writer per --out; the figure worker, forked now, imports matplotlib while the engine runs
    with output_lock(out), figure_worker() as worker:
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
        console.print(summary_table(result.summary, label))
    for warning in result.summary.get("warnings", []):
        err_console.print(f"[bold yellow]warning:[/] {escape(warning)}", soft_wrap=True, highlight=False)
    console.print(f"written: {out}/ (summary.json, *.parquet, figures/, report.html)", soft_wrap=True)
    return added


def run_command(
    ctx: typer.Context,
    scenario_file: Annotated[Path, typer.Argument(metavar="SCENARIO", help="scenario file (TOML)")],
    out: Annotated[Path, typer.Option("--out", help="run directory to write (must not exist)")],
    overrides: SetOption = None,
    overwrite: OverwriteOption = False,
    quiet: QuietOption = False,
) -> None:
    """Run a scenario file and write a complete run directory (see `floebreak schema` for the keys)."""
    from floebreak.config.scenario import Scenario

    scenario = Scenario.from_toml(scenario_file, overrides=overrides or ())
    _execute(scenario, out, overwrite, quiet, f"floebreak run: {scenario_file.name}", engine_loaded=ctx.obj)


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
    from floebreak.config.scenario import Scenario

    extra = [*(overrides or ()), *([f"seed={seed}"] if seed is not None else [])]
    scenario = Scenario.reference(overrides=extra)
    label = f"floebreak demo: reference scenario, seed {scenario.seed}"
    then = None if no_propeller else _demo_propeller
    propeller_summary = _execute(scenario, out, overwrite, quiet, label, then=then, engine_loaded=ctx.obj)
    if propeller_summary is not None:
        print_propeller_summary(propeller_summary, out / DEMO_PROPELLER_DIR, quiet)


DEMO_PROPELLER_DIR = "propeller"


def _demo_propeller(run_dir: Path, run_id: str) -> dict:
    """Propeller analysis (defaults: Agulhas II; the profile's load model and transport, the scenario's
    speed, fraction reaching and propellers) of `run_dir` into `run_dir/propeller`; returns its summary.
    `run_id` names the run (the folder is still temporary)."""
    from floebreak.app.propeller import analyse_propeller, read_runs, write_propeller
    from floebreak.config.analysis import propeller_defaults
    from floebreak.output.report import write_report

    inputs = read_runs(run_dir)
    cusps = inputs.cusps.set_column(
        inputs.cusps.column_names.index("run_id"), "run_id", pa_array([run_id] * inputs.cusps.num_rows)
    )
    exposures = None if inputs.exposures is None else {run_id: next(iter(inputs.exposures.values()))}
    load_model, transport = propeller_defaults(inputs.profile)
    result = analyse_propeller(cusps, exposures=exposures, load_model=load_model, transport=transport)
    written = write_propeller(result, run_dir / DEMO_PROPELLER_DIR, record={"runs": [run_id]})
    write_report(run_dir, directory_name=run_id)  # again, now with the propeller section
    return written_summary(written)


def written_summary(folder: Path) -> dict:
    """An analysis folder's summary.json as written (the terminal shows what the files hold)."""
    import json

    return json.loads((Path(folder) / "summary.json").read_text(encoding="utf-8"))


def pa_array(values: list[str]):
    import pyarrow as pa

    return pa.array(values, pa.string())


def register(app: typer.Typer) -> None:
    """Add this module's commands to `app`."""
    app.command()(field)
    app.command("run")(run_command)
    app.command()(demo)
