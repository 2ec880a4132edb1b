"""CLI of `floebreak validate thesis | sensitivity | convergence` (a thin layer)."""

from __future__ import annotations

import math
import shlex
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from floebreak.cli.common import Group, use_command_class
from floebreak.cli.options import (
    EveryRunSetOption,
    FieldsOption,
    LengthOption,
    OutOption,
    OverwriteOption,
    SchedulerOption,
    SeedOption,
    WorkersOption,
)
from floebreak.errors import InputError

console = Console()


def _check(n_fields: int, workers: int | None, length_m: float | None) -> None:
    if n_fields < 1:
        raise InputError("--n-fields", f"{n_fields} < 1", value=n_fields, allowed="an integer ≥ 1")
    if workers is not None and workers < 1:
        raise InputError("--workers", f"{workers} < 1", value=workers, allowed="an integer ≥ 1")
    if length_m is not None and not (length_m > 0 and math.isfinite(length_m)):
        raise InputError("--length-m", f"{length_m}", value=length_m, allowed="a field length > 0 m")


def _progress_bar():
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
    )
    return Progress(*columns, console=console)


def _run(out: Path, specs: dict, workers, scheduler, finish):
    """Run the study specs (validated first) into `out` with a progress bar per study; `finish()` writes."""
    from floebreak.studies.design import expand
    from floebreak.studies.executors import make_executor
    from floebreak.validation.validation_report import check_out_dir, run_spec

    check_out_dir(out)
    total = {name: len(expand(spec)[0]) for name, spec in specs.items()}  # validates before anything runs
    out.mkdir(parents=True, exist_ok=True)
    executor = make_executor(workers, scheduler)
    console.print(f"{sum(total.values())} runs on {executor.description} → {out}")
    failures = []
    try:
        with _progress_bar() as bar:
            for name, spec in specs.items():
                task = bar.add_task(name, total=total[name], info="")

                def progress(state, task=task) -> None:
                    bar.update(
                        task, completed=state.done, info=f"failed {state.failed}, resumed {state.skipped}"
                    )

                failures += run_spec(spec, out / name, executor, progress).failures
    finally:
        executor.close()
    for failure in failures[:5]:
        console.print(f"[red]failed[/] {failure['run']}: {failure['error']}")
    return finish(failures)


def _command(name: str, out: Path, options: list[tuple[str, object]]) -> str:
    """The command line that reproduces these results (options that were given; not --workers/--scheduler)."""
    words = ["floebreak", "validate", name, "--out", str(out)]
    for option, value in options:
        if value is not None:
            words += [option, f"{value:g}" if isinstance(value, float) else str(value)]
    return shlex.join(words)


def _registered(samples: Path, name: str, given: dict[str, object]):
    """The sample `name` of the registry file `samples`; the options it fixes may not be given too."""
    from floebreak.io.text_files import read_text_file
    from floebreak.validation.validate import parse_samples

    registry = parse_samples(read_text_file(samples, "--samples"), f"--samples {samples}")
    if name not in registry:
        raise InputError("--sample", f"{name!r} is not registered in {samples}", allowed=", ".join(registry))
    clash = [option for option, value in given.items() if value not in (None, False, [])]
    if clash:
        raise InputError("--sample", f"the sample fixes {', '.join(clash)}", allowed="--sample without them")
    return registry[name]


def _thesis_inputs(sample_name, samples: Path, profile, n_fields, seed, length_m, sets: list[str], holdout,
                   holdout_n_fields):  # fmt: skip
    """(profile, n_fields, seed, length_m, sets, options shown in the command) of a `validate thesis` call:
    the registered sample's where `--sample` names one, else the options' (default both, 4, 2023)."""
    if holdout_n_fields is not None and holdout_n_fields < 1:
        raise InputError(
            "--holdout-n-fields", f"{holdout_n_fields} < 1", value=holdout_n_fields, allowed="an integer ≥ 1"
        )
    options = [("--profile", profile), ("--n-fields", n_fields), ("--seed", seed), ("--length-m", length_m)]
    options += [("--set", s) for s in sets]
    from floebreak.validation.validate import SCOREBOARD_STEPPING

    user_sets, sets = sets, [*SCOREBOARD_STEPPING, *sets]  # the user's --set after the scoreboard's stepping
    if sample_name is not None:
        given = {"--profile": profile, "--n-fields": n_fields, "--seed": seed, "--length-m": length_m,
                 "--holdout": holdout, "--holdout-n-fields": holdout_n_fields,
                 "--set field.*": [s for s in user_sets if s.strip().startswith("field.")]}  # fmt: skip
        registered = _registered(samples, sample_name, given)
        profile = "both" if len(registered.profiles) > 1 else registered.profiles[0]
        n_fields, seed, length_m = registered.n_fields, registered.seed, registered.length_m
        options = [("--samples", samples), ("--sample", sample_name)] + [("--set", s) for s in user_sets]
        sets = [
            *sets,
            f'field.observation="{registered.observation}"',
            f"field.width_m={registered.width_m:g}",
            *([f'field.generator="{registered.generator}"'] if registered.generator != "circles" else []),
        ]
    return (
        "both" if profile is None else profile,
        4 if n_fields is None else n_fields,
        2023 if seed is None else seed,
        length_m,
        sets,
        options,
    )


def thesis_command(
    out: OutOption,
    profile: Annotated[str | None, typer.Option("--profile", help="default | thesis | both")] = None,
    n_fields: Annotated[
        int | None, typer.Option("--n-fields", help="common random fields per design point (≥ 1; default 4)")
    ] = None,
    seed: Annotated[int | None, typer.Option("--seed", help="root seed of the fields (default 2023)")] = None,
    workers: WorkersOption = None,
    scheduler: SchedulerOption = None,
    sets: EveryRunSetOption = None,
    variants: Annotated[
        list[str] | None,
        typer.Option("--variant", help="a named reading NAME:KEY=VALUE[,KEY=VALUE], scored on each profile"),
    ] = None,
    length_m: LengthOption = None,
    holdout: Annotated[
        bool,
        typer.Option(
            "--holdout", help="also score the holdout sample (a seed and observation used for no choice)"
        ),
    ] = False,
    holdout_n_fields: Annotated[
        int | None, typer.Option("--holdout-n-fields", help="fields of the holdout sample (default: its own)")
    ] = None,
    sample_name: Annotated[
        str | None,
        typer.Option(
            "--sample", help="score a registered sample: its seed, observation, fields and profiles"
        ),
    ] = None,
    samples: Annotated[
        Path, typer.Option("--samples", help="the samples registry (TOML) --sample reads")
    ] = Path("validation/samples.toml"),
) -> None:
    """Score every quantitative statement of thesis §5.1–§5.3 and §6.2: scoreboard.md/.csv, fields.csv
    (each field's checksum) and figures."""
    import dataclasses
    import time

    from floebreak.studies.field_size import thesis_field_length_m, thesis_scenario
    from floebreak.validation.scoreboard import tally_text
    from floebreak.validation.validate import HOLDOUT_SAMPLE, make_configs, thesis_validation_spec
    from floebreak.validation.validation_report import ValidationSettings, write_outputs

    profile, n_fields, seed, length_m, sets, options = _thesis_inputs(
        sample_name, samples, profile, n_fields, seed, length_m, list(sets or []), holdout, holdout_n_fields
    )
    _check(n_fields, workers, length_m)
    configs = make_configs(profile, list(variants or []))
    base = thesis_scenario(sets, length_m)
    specs = _thesis_specs(configs, base, n_fields, seed)
    options += [("--variant", v) for v in variants or []]
    sample, holdout_base = None, {}
    if holdout:  # the holdout's observation after the user's --set: it is what defines the sample
        sample = dataclasses.replace(HOLDOUT_SAMPLE, n_fields=holdout_n_fields or HOLDOUT_SAMPLE.n_fields)
        holdout_base = thesis_scenario([*sets, f'field.observation="{sample.observation}"'], length_m)
        specs["holdout"] = thesis_validation_spec(configs, holdout_base, sample.n_fields, sample.seed)
        options += [("--holdout-n-fields", holdout_n_fields)]
    command = _command("thesis", out, options) + (" --holdout" if holdout else "")
    field = base["field"]
    settings = ValidationSettings(command, field["length_m"], field["width_m"],
                                  thesis_field_length_m(field["width_m"]), n_fields, seed, tuple(sets), base,
                                  sample, holdout_base, sample_name or "")  # fmt: skip
    console.print("\n".join(_sample_lines(samples, n_fields, seed, field)), soft_wrap=True, highlight=False)
    started = time.perf_counter()

    def finish(failures):
        counts = write_outputs(out, configs, settings, time.perf_counter() - started, failures)
        for name, tally in counts.items():
            console.print(f"{name}: {tally_text(tally)}", soft_wrap=True)
        console.print(f"written: {out}/scoreboard.md, scoreboard.csv, fields.csv, figures/", soft_wrap=True)

    _run(out, specs, workers, scheduler, finish)


def _thesis_specs(configs, base: dict, n_fields: int, seed: int) -> dict:
    """The single-floe cases and the study of `validate thesis` (the holdout is added to them)."""
    from floebreak.validation.validate import single_floe_spec, thesis_validation_spec

    return {
        "single_floe": single_floe_spec(configs, base),
        "study": thesis_validation_spec(configs, base, n_fields, seed),
    }


def _sample_lines(samples: Path, n_fields: int, seed: int, field: dict) -> list[str]:
    """`sample_lines` of a call, against the registry `samples` where it can be read (a checkout's
    validation/samples.toml; an installed package run elsewhere has none, then the size alone)."""
    from floebreak.validation.validate import parse_samples, sample_lines

    try:
        registry = parse_samples(samples.read_text(encoding="utf-8"), f"--samples {samples}")
    except (OSError, InputError):
        registry = {}
    observation = str(field.get("observation"))
    return sample_lines(n_fields, seed, observation, field["length_m"], field["width_m"], registry)


def _one_config(profile: str, length_m: float | None, sets: list[str] | None):
    from floebreak.studies.field_size import thesis_scenario
    from floebreak.validation.validate import SCOREBOARD_STEPPING, Config

    if profile not in ("default", "thesis"):
        raise InputError(
            "--profile", f"unknown profile {profile!r}", value=profile, allowed="default, thesis"
        )
    return Config(profile), thesis_scenario([*SCOREBOARD_STEPPING, *(sets or [])], length_m)


def _csv_text(rows: list[dict], columns: list[str]) -> str:
    """`columns` of `rows` (a missing key: an empty cell) in the one CSV format (`floebreak.io.writers`)."""
    from floebreak.io.writers import csv_text

    return csv_text({name: [row.get(name) for row in rows] for name in columns})


def _cell(value, se, percent: bool = False) -> str:
    if value is None or not math.isfinite(value):
        return "–"
    scale, unit = (100.0, " %") if percent else (1.0, "")
    text = f"{scale * value:+.{1 if percent else 3}f}"
    if se is not None and math.isfinite(se):
        text += f" ± {scale * se:.{1 if percent else 3}f}"
    return text + unit


def sensitivity_command(
    out: OutOption,
    profile: Annotated[str, typer.Option("--profile", help="default | thesis")] = "default",
    n_fields: FieldsOption = 4,
    seed: SeedOption = 2023,
    delta: Annotated[float, typer.Option("--delta", help="relative step δ of each input (0 < δ < 1)")] = 0.1,
    workers: WorkersOption = None,
    scheduler: SchedulerOption = None,
    sets: EveryRunSetOption = None,
    length_m: LengthOption = None,
) -> None:
    """One-at-a-time elasticities d ln(output)/d ln(input) of the Table-5 outputs (Fig. 25 generalised)."""
    from floebreak.io.figures import save_figure
    from floebreak.plotting.validation import plot_elasticities
    from floebreak.validation import sensitivity as sens
    from floebreak.validation.validation_report import collect_data, write_text

    _check(n_fields, workers, length_m)
    if not 0.0 < delta < 1.0:
        raise InputError("--delta", f"{delta}", value=delta, allowed="0 < δ < 1")
    config, base = _one_config(profile, length_m, sets)
    points = sens.sensitivity_points(base | {"profile": profile}, delta)
    options = [("--profile", profile), ("--n-fields", n_fields), ("--seed", seed), ("--delta", delta)]
    command = _command(
        "sensitivity", out, [*options, ("--length-m", length_m)] + [("--set", s) for s in sets or []]
    )
    spec = sens.one_config_spec("validate sensitivity", config, base, points, n_fields, seed)

    def finish(_failures):
        data = collect_data(out / "sweep")[0].get(config.name, {})
        rows = sens.sensitivity_rows(data, delta)
        columns = ["input", "key", "kind", "n_fields"] + [
            f"{k}_{s}" for k, _ in sens.OUTPUTS for s in ("value", "se")
        ]
        write_text(out / "sensitivity.csv", _csv_text(rows, columns))
        lines = [
            "# One-at-a-time sensitivity",
            "",
            f"Generated by `{command}`: profile `{profile}`, {n_fields} "
            f"common fields of {base['field']['length_m']:g} m × {base['field']['width_m']:g} m, "
            f"δ = {delta:g}. Elasticity "
            "d ln y / d ln x (central difference, per field; mean ± s.e.); categorical rows: paired relative "
            "change to the reference.",
            "",
            "| input | kind | " + " | ".join(label for _, label in sens.OUTPUTS) + " |",
            "|---|---|" + "---|" * len(sens.OUTPUTS),
        ]
        for row in rows:
            cells = [_cell(row.get(f"{k}_value"), row.get(f"{k}_se")) for k, _ in sens.OUTPUTS]
            lines.append(f"| {row['input']} | {row['kind']} | " + " | ".join(cells) + " |")
        write_text(out / "sensitivity.md", "\n".join(lines) + "\n")
        shown = [r for r in rows if "not exposed" not in r["kind"]]
        figure = plot_elasticities(
            shown, list(sens.OUTPUTS), f"Sensitivity of the Table-5 outputs (profile {profile})"
        )
        (out / "figures").mkdir(exist_ok=True)
        save_figure(figure, out / "figures" / "sensitivity.png", field="--out")
        console.print(
            f"written: {out}/sensitivity.md, sensitivity.csv, figures/sensitivity.png", soft_wrap=True
        )

    _run(out, {"sweep": spec}, workers, scheduler, finish)


def convergence_command(
    out: OutOption,
    profile: Annotated[str, typer.Option("--profile", help="default | thesis")] = "default",
    n_fields: FieldsOption = 4,
    seed: SeedOption = 2023,
    workers: WorkersOption = None,
    scheduler: SchedulerOption = None,
    sets: EveryRunSetOption = None,
    length_m: LengthOption = None,
) -> None:
    """The Table-5 outputs at x_step 0.5/0.25/0.125/0.0625 m and φ 10/5/2.5°: where they converge (≤ 2 %)."""
    from floebreak.io.figures import save_figure
    from floebreak.plotting.validation import plot_convergence
    from floebreak.validation import sensitivity as sens
    from floebreak.validation.validation_report import collect_data, write_text

    _check(n_fields, workers, length_m)
    config, base = _one_config(profile, length_m, sets)
    spec = sens.one_config_spec(
        "validate convergence", config, base, sens.convergence_points(), n_fields, seed
    )
    options = [("--profile", profile), ("--n-fields", n_fields), ("--seed", seed), ("--length-m", length_m)]
    command = _command("convergence", out, options + [("--set", s) for s in sets or []])

    def finish(_failures):
        data = collect_data(out / "sweep")[0].get(config.name, {})
        table = sens.convergence_table(data)
        rows, lines = (
            [],
            [
                "# Convergence in x_step and the wedge angle φ",
                "",
                f"Generated by `{command}`: profile `{profile}`, {n_fields} common fields of "
                f"{base['field']['length_m']:g} m × {base['field']['width_m']:g} m. Each output as the "
                "paired relative difference to "
                f"the finest setting (mean ± s.e. over the fields); converged: ≤ "
                f"{100 * sens.CONVERGED_REL:g} %.",
                "",
            ],
        )
        for parameter, by_value in table.items():
            where = sens.converged_from(by_value)
            lines += [f"## {parameter}: " + (f"converged from {where:g}" if where else "not converged"), ""]
            lines += ["| value | " + " | ".join(lab for _, lab in sens.OUTPUTS) + " |", "|---|" + "---|" * 6]
            for value, entry in sorted(by_value.items(), reverse=True):
                cells = [
                    f"{entry[f'{k}_mean']:.4g} ({_cell(entry[k], entry[f'{k}_se'], percent=True)})"
                    for k, _ in sens.OUTPUTS
                ]
                lines.append(f"| {value:g} | " + " | ".join(cells) + " |")
                rows.append({"parameter": parameter, "value": value, **entry})
            lines.append("")
        columns = ["parameter", "value"] + [f"{k}{s}" for k, _ in sens.OUTPUTS for s in ("_mean", "", "_se")]
        write_text(out / "convergence.csv", _csv_text(rows, columns))
        write_text(out / "convergence.md", "\n".join(lines))
        (out / "figures").mkdir(exist_ok=True)
        save_figure(
            plot_convergence(table, list(sens.OUTPUTS)), out / "figures" / "convergence.png", field="--out"
        )
        console.print(
            f"written: {out}/convergence.md, convergence.csv, figures/convergence.png", soft_wrap=True
        )

    _run(out, {"sweep": spec}, workers, scheduler, finish)


def validate_single_floe(
    out: Annotated[Path, typer.Option("--out", help="output directory")],
    overwrite: OverwriteOption = False,
) -> None:
    """Single-floe validation matrix (thesis §5.2, Figs. 14–16): diameters × thicknesses × positions."""
    from floebreak.studies.single_floe import write_single_floe_matrix

    path = write_single_floe_matrix(out, overwrite=overwrite)
    console.print(f"written: {path}", soft_wrap=True)


def register(app: typer.Typer) -> None:
    """`floebreak validate` and its commands."""
    validate_app = typer.Typer(cls=Group, no_args_is_help=True, help="Validation studies (thesis §5).")
    validate_app.command("single-floe")(validate_single_floe)
    validate_app.command("thesis")(thesis_command)
    validate_app.command("sensitivity")(sensitivity_command)
    validate_app.command("convergence")(convergence_command)
    use_command_class(validate_app)
    app.add_typer(validate_app, name="validate")
