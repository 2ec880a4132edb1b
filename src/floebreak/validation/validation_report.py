"""Running `floebreak validate thesis` and writing its outputs (the I/O edge of the scoreboard).

``OUT/study/`` (design points × configurations on common fields) and ``OUT/single_floe/`` are study
directories (resumable); ``OUT/scoreboard.csv``, ``OUT/fields.csv`` (each field's seed and checksum),
``OUT/scoreboard.md`` and ``OUT/figures/`` are rewritten from them at the end of every call, each file
atomically.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_path
from floebreak.studies.aggregate import collect_runs
from floebreak.studies.design import StudySpec, expand
from floebreak.studies.executors import Executor
from floebreak.studies.runner import StudyProgress, run_study
from floebreak.validation.inert import inert_flags
from floebreak.validation.scoreboard import (
    TABLE_OUTPUTS,
    MustHoldTally,
    must_hold_counts,
    per_100m_lines,
    run_metrics,
    scoreboard_csv,
    scoreboard_markdown_table,
    scoreboard_rows,
    single_floe_metrics,
    tally_text,
)
from floebreak.validation.statements import STATEMENTS
from floebreak.validation.validate import HOLDOUT_SUFFIX, POINTS, Config, Sample, split_group

FORCE_POINTS = ("reference", "polarstern")
TORQUE_POINTS = ("h0.4",)
_SINGLE = re.compile(r"^single d([\d.]+) h([\d.]+) ([a-e])$")


@dataclass(frozen=True)
class ValidationSettings:
    """What a `validate thesis` call ran (written into scoreboard.md): the scenario every run of the main
    sample starts from (`base`), and the holdout sample with its own, if one was run."""

    command: str
    length_m: float
    width_m: float
    thesis_length_m: float  # inferred for width_m
    n_fields: int
    seed: int
    sets: tuple[str, ...]
    base: dict = field(default_factory=dict)
    holdout: Sample | None = None
    holdout_base: dict = field(default_factory=dict)
    sample_name: str = ""  # the registered sample scored (validation/samples.toml), if one was named


def check_out_dir(out: Path) -> None:
    """`out` is new, empty, or an earlier `validate` output (which is resumed)."""
    if out.exists() and not out.is_dir():
        raise InputError("--out", f"{str(out)!r} is not a directory", allowed="a new or validate directory")
    if out.exists() and any(out.iterdir()) and not (out / "study").exists() and not (out / "sweep").exists():
        raise InputError(
            "--out",
            f"{str(out)!r} exists and is not a validate directory",
            allowed="a new or validate directory",
        )


def run_spec(
    spec: StudySpec, out_dir: Path, executor: Executor, progress: Callable[[StudyProgress], None] | None
) -> StudyProgress:
    runs, members = expand(spec)  # validates every combination before anything runs
    out_dir.mkdir(parents=True, exist_ok=True)
    return run_study(spec, runs, members, out_dir, executor, progress)


def collect_data(study_dir: Path) -> tuple[dict[str, dict[str, dict[int, dict[str, float]]]], dict]:
    """Per configuration, point and field: the run's metrics; and the pooled cusp volumes and bending
    forces per configuration and point (for the figures)."""
    import pyarrow.parquet as pq

    from floebreak.validation.scoreboard import bending_forces_kn

    data: dict[str, dict[str, dict[int, dict[str, float]]]] = {}
    pooled: dict[str, dict[str, dict[str, list[np.ndarray]]]] = {"volumes": {}, "forces": {}}
    for record in collect_runs(study_dir):
        if record["status"] != "complete":
            continue
        config, point = split_group(record["group"])
        run_dir = study_dir / "runs" / record["run"]
        forces, torque = point in FORCE_POINTS, point in TORQUE_POINTS
        data.setdefault(config, {}).setdefault(point, {})[record["field_index"]] = run_metrics(
            run_dir, forces=forces, torque=torque
        )
        volumes = pq.read_table(run_dir / "cusps.parquet", columns=["volume_m3"]).column(0).to_numpy()
        pooled["volumes"].setdefault(config, {}).setdefault(point, []).append(volumes)
        if torque:
            pooled.setdefault("torque_runs", {}).setdefault(config, []).append(run_dir)
        if forces:
            contacts = pq.read_table(
                run_dir / "contacts.parquet", columns=["step", "piece_id", "zone", "f_c_n", "outcome"]
            )
            pooled["forces"].setdefault(config, {}).setdefault(point, []).append(
                bending_forces_kn(contacts.to_pydict())
            )
    return data, pooled


def collect_single_floes(study_dir: Path) -> dict[str, dict[str, float]]:
    """Per configuration: the §5.2 pattern metrics of its single-floe cases."""
    cases: dict[str, dict[tuple[float, float, str], dict[str, float]]] = {}
    for record in collect_runs(study_dir):
        config, point = split_group(record["group"])
        found = _SINGLE.match(point)
        if record["status"] != "complete" or found is None:
            continue
        key = (float(found.group(1)), float(found.group(2)), found.group(3))
        cases.setdefault(config, {})[key] = run_metrics(study_dir / "runs" / record["run"])
    return {config: single_floe_metrics(c) for config, c in cases.items()}


def write_text(path: Path, text: str) -> None:
    with atomic_path(path, field="--out") as temp:
        temp.write_text(text, encoding="utf-8")


def scored_columns(out: Path, configs: list[Config], settings: ValidationSettings):
    """The scoreboard's columns — per configuration, and per configuration on the holdout
    (``NAME@holdout``) — as ({column: per-point, per-field metrics}, {column: profile}, {column: inert
    flags}, pooled data of the main sample, {column: torque run directories})."""
    data, pooled = collect_data(out / "study")
    for config, metrics in collect_single_floes(out / "single_floe").items():
        data.setdefault(config, {})["single_floe"] = {0: metrics}
    columns = {c.name: data.get(c.name, {}) for c in configs}
    profiles = {c.name: c.profile for c in configs}
    inert = {c.name: inert_flags(STATEMENTS, settings.base, c.profile, c.overrides, POINTS) for c in configs}
    torque_runs = {c.name: pooled.get("torque_runs", {}).get(c.name, []) for c in configs}
    if settings.holdout is not None:
        holdout, holdout_pooled = collect_data(out / "holdout")
        for c in configs:
            name = c.name + HOLDOUT_SUFFIX
            # the single floes are the same runs on every sample (no random field)
            columns[name] = {**holdout.get(c.name, {}), "single_floe": columns[c.name].get("single_floe", {})}
            profiles[name] = c.profile
            inert[name] = inert_flags(STATEMENTS, settings.holdout_base, c.profile, c.overrides, POINTS)
            torque_runs[name] = holdout_pooled.get("torque_runs", {}).get(c.name, [])
    return columns, profiles, inert, pooled, torque_runs


def field_checksum(path: Path) -> str:
    """sha256 of one field's floes: per floe, in the file's order, its id (int64) and the (x, y) of its
    exterior ring (float64), little-endian — what a referee regenerating the field with the same seed
    compares, whatever the file's metadata."""
    import hashlib

    from floebreak.output.field_files import load_field

    floes = load_field(path, field="--out")
    digest = hashlib.sha256()
    for floe_id, polygon in zip(floes.floe_id, floes.polygons, strict=True):
        digest.update(np.int64(floe_id).astype("<i8").tobytes())
        digest.update(np.asarray(polygon.exterior.coords, dtype="<f8").tobytes())
    return digest.hexdigest()


def field_checksum_rows(study_dir: Path, sample: str) -> list[dict]:
    """One row per configuration and field of a study: its field seed, number of floes and checksum (the
    fields of the reference point; every design point of a field index shares its floes)."""
    rows = []
    for record in collect_runs(study_dir):
        config, point = split_group(record["group"])
        if record["status"] != "complete" or point != "reference":
            continue
        path = study_dir / "runs" / record["run"] / "field.parquet"
        rows.append({"sample": sample, "config": config, "field_index": record["field_index"],
                     "seed": record["seed"], "field_sha256": field_checksum(path)})  # fmt: skip
    return sorted(rows, key=lambda r: (r["config"], r["field_index"]))


def write_field_checksums(out: Path, settings: ValidationSettings) -> None:
    """``fields.csv``: the checksum of every field scored (main sample and, if run, the holdout)."""
    from floebreak.io.writers import csv_text

    rows = field_checksum_rows(out / "study", settings.sample_name or "main")
    if settings.holdout is not None:
        rows += field_checksum_rows(out / "holdout", "holdout")
    columns = ("sample", "config", "field_index", "seed", "field_sha256")
    write_text(out / "fields.csv", csv_text({c: [r[c] for r in rows] for c in columns}))


def write_outputs(
    out: Path, configs: list[Config], settings: ValidationSettings, elapsed_s: float, failures: list[dict]
) -> dict[str, MustHoldTally]:
    """scoreboard.csv, fields.csv, scoreboard.md and figures/ from the study directories; each column's
    `MustHoldTally`."""
    columns, profiles, inert, pooled, torque_runs = scored_columns(out, configs, settings)
    names = list(columns)
    rows = scoreboard_rows(columns, profiles, inert=inert)
    write_text(out / "scoreboard.csv", scoreboard_csv(rows, names))
    write_field_checksums(out, settings)
    counts = {name: must_hold_counts(rows, name) for name in names}
    lines = scoreboard_header(configs, settings, elapsed_s, counts, failures)
    lines += scoreboard_markdown_table(rows, names)
    lines += explained_and_inert_lines(rows, names)
    lines += ["", "## Totals per 100 m of transit (reference point)", ""]
    lines += per_100m_lines(columns, settings.length_m, settings.thesis_length_m)
    lines += ["", "## Torque spectrum at h = 0.4 m (thesis §6.2)", ""]
    lines += torque_range_lines({name: dirs for name, dirs in torque_runs.items() if dirs})
    lines += ["", "## The statements (thesis words)", ""]
    lines += [f"- **{st.id}** ({st.source}): “{st.quote}”" for st in STATEMENTS]
    write_text(out / "scoreboard.md", "\n".join(lines) + "\n")
    main = [c.name for c in configs]  # the figures show the main sample
    write_figures(out / "figures", {name: columns[name] for name in main}, pooled, main)
    return counts


def note_status(result: dict) -> str:
    """A column's status next to a note: a failure stays a failure, the note says why."""
    return {"fail": "FAIL", "weak-pass": "weak pass"}.get(result["status"], result["status"])


def explained_and_inert_lines(rows: list[dict], names: list[str]) -> list[str]:
    """The rows with a documented deviation, their status per column next to the reason, the weak rows, and
    the rows that cannot fail (inert), with the reason, per column."""
    title = "## Notes: deviations with a documented mechanism (a note; a failing row still fails)"
    lines = ["", title, ""]
    for row in rows:
        st = row["statement"]
        if st.explained:
            status = ", ".join(f"`{n}` {note_status(row[n])}" for n in names)
            lines.append(f"- **{st.id}** ({status}): {st.explained}")
    lines += [
        "",
        "## Weak rows (a model with no effect passes them too; counted apart)",
        "",
        "The null variant — no change between the two design points, 0 % — passes these change rows, so "
        "their pass shows that the effect is small, not that the model has the thesis' effect: "
        + ", ".join(row["statement"].id for row in rows if row["statement"].weak)
        + ".",
    ]
    lines += ["", "## Inert rows (cannot fail in this configuration; not counted in the tally)", ""]
    reasons: dict[tuple[str, str], list[str]] = {}
    for row in rows:
        for n in names:
            flag = row[n].get("inert")
            if flag is not None:
                reasons.setdefault((row["statement"].id, flag.reason), []).append(n)
    for (sid, why), cols in reasons.items():
        lines.append(f"- **{sid}** ({', '.join(f'`{n}`' for n in cols)}): {why}")
    contradicted = [
        f"- **{row['statement'].id}** (`{n}`): flagged inert ({row[n]['inert_contradicted']}), but the "
        "measured value contradicts that reason, so the row is scored as any other"
        for row in rows
        for n in names
        if row[n].get("inert_contradicted")
    ]
    return lines + contradicted if reasons or contradicted else [*lines, "none"]


def torque_range_lines(run_dirs: dict[str, list[Path]]) -> list[str]:
    """Per configuration and pitch: the envelope of the torques whose density (mean of the fields' densities,
    10 kN·m bins) exceeds 0.1 % per kN·m — `floebreak propeller`'s reading of the thesis' "probability
    density above 0.1 %"."""
    import pyarrow as pa

    from floebreak.app.inputs import shipped_fem_tables
    from floebreak.output.run_files import load_cusps
    from floebreak.propeller.cusps import cusp_columns
    from floebreak.propeller.loads.fem import propeller_loads
    from floebreak.propeller.pipeline import load_spectra, torque_ranges_above

    lines = [
        "| source | pitch 0 %: torque with density > 0.1 %/kN·m [kN·m] | pitch 95 % [kN·m] |",
        "|---|---|---|",
        "| thesis §6.2 | 58–208 (all 20–210) | most of the torques > 900 (all 0–1575) |",
    ]
    tables = shipped_fem_tables()
    for config, dirs in run_dirs.items():
        cusps = pa.concat_tables([load_cusps(d) for d in dirs])
        ranges = torque_ranges_above(load_spectra(propeller_loads(cusp_columns(cusps), tables), tables))
        cells = []
        for label in ("p0", "p95"):
            envelope = ranges.get(label, {}).get("envelope_knm")
            parts = len(ranges.get(label, {}).get("intervals_knm", []))
            cells.append(f"{envelope[0]:g}–{envelope[1]:g} ({parts} parts)" if envelope else "none")
        lines.append(f"| `{config}` | " + " | ".join(cells) + " |")
    return lines


def scoreboard_header(configs, settings: ValidationSettings, elapsed_s, counts, failures) -> list[str]:
    variants = [
        f"`{c.name}`: " + ", ".join(f"{k} = {v!r}" for k, v in c.overrides.items())
        for c in configs
        if c.variant
    ]
    holdout = settings.holdout
    observation = settings.base.get("field", {}).get("observation", "–")
    lines = [
        "# Thesis scoreboard",
        "",
        f"Generated by `{settings.command}` ({elapsed_s:.0f} s for this call; complete runs are reused).",
        "",
        (f"Registered sample `{settings.sample_name}`. " if settings.sample_name else "")
        + f"Reference configuration of thesis §5.3 (observation {observation}, "
        f"h = 1 m, K_Ic = 145.7 kPa√m, tensile stress, BZ, Agulhas II) on {settings.n_fields} common random "
        f"fields of "
        f"{settings.length_m:g} m × {settings.width_m:g} m (root seed {settings.seed}). The thesis' field "
        f"length, inferred in docs/validation.md for this width, is {settings.thesis_length_m:g} m."
        + (f" Overrides: {', '.join(f'`{s}`' for s in settings.sets)}." if settings.sets else ""),
        "",
    ]
    if holdout is not None:
        lines += [
            f"Columns `…{HOLDOUT_SUFFIX}`: the holdout sample, used for no choice of the ice model; its "
            "results were shown while propeller choices 4 and 5 were made, so it is not clean for the chain "
            "rows (docs/validation.md, selection log): "
            f"the same configurations on {holdout.n_fields} fields of observation {holdout.observation} "
            f"(root seed {holdout.seed}); the single floes of §5.2 are the same runs in both samples.",
            "",
        ]
    lines += [
        "Ours: mean ± standard error over the fields; changes (%) are paired on the same field, "
        "r = x/x_ref − 1 per field. A must-hold row that fails is in **bold**, with a note below where a "
        "mechanism is documented; “weak pass”: the null variant (no change) passes the row too, counted "
        "apart; “inert” cannot fail in that configuration (below) and is not counted.",
        "",
    ]
    if variants:
        lines += ["Variants: " + "; ".join(variants), ""]
    for name, tally in counts.items():
        lines.append(f"- `{name}`: {tally_text(tally)}")
    if failures:
        lines += [
            "",
            f"**{len(failures)} runs failed** (see OUT/*/failed/): the rows that need them are missing.",
        ]
    return [*lines, ""]


THESIS_V = {"reference": 8.14, "K120": 8.16, "K230": 8.05, "point_load": 7.84, "line_load": 8.24,
            "flexural_stress": 8.04, "h0.8": 5.50, "h1.2": 11.21, "BZ1": 8.19, "BZ2": 8.24}  # fmt: skip
FIGURE_GROUPS = {
    "fig17_fracture_toughness": ("K120", "reference", "K230"),
    "fig19_crack_criterion": ("point_load", "line_load", "reference", "flexural_stress"),
    "fig21_ice_thickness": ("h0.8", "reference", "h1.2", "h_random"),
    "fig23_size_effect_law": ("reference", "BZ1", "BZ2"),
}
TREND_LABELS = ("V̄_cusp", "Ā_cusp", "n_cusp", "n_flip", "A_cusp^tot", "A_flip^tot")
THESIS_ROWS = {  # Tables 5–8: V̄, Ā, n_cusp, n_flip, A_cusp^tot, A_flip^tot
    "reference": (8.14, 8.14, 125, 83, 1019.48, 2426.90),
    "K120": (8.16, 8.16, 129, 82, 1053.03, 2391.07),
    "K230": (8.05, 8.05, 127, 82, 1024.01, 2432.66),
    "point_load": (7.84, 7.84, 125, 86, 983.52, 2464.64),
    "line_load": (8.24, 8.24, 149, 78, 1233.53, 2210.96),
    "flexural_stress": (8.04, 8.04, 122, 84, 983.03, 2473.95),
    "h0.8": (5.50, 6.87, 161, 95, 1110.09, 2251.49),
    "h1.2": (11.21, 9.34, 119, 73, 1111.99, 2424.23),
    "BZ1": (8.19, 8.19, 127, 82, 1042.14, 2413.51),
    "BZ2": (8.24, 8.24, 127, 83, 1051.12, 2391.07),
}


def _paired_changes(data: dict[str, dict[int, dict[str, float]]], point: str) -> dict[str, float]:
    from floebreak.validation.statements import paired_relative_change

    out = {}
    for key, label in zip(TABLE_OUTPUTS, TREND_LABELS, strict=True):
        values = {i: m[key] for i, m in data.get(point, {}).items()}
        reference = {i: m[key] for i, m in data.get("reference", {}).items()}
        out[label] = paired_relative_change(values, reference)[0]
    return out


def write_figures(folder: Path, data, pooled, names: list[str]) -> None:
    from floebreak.io.figures import save_figure
    from floebreak.plotting.validation import (
        plot_bending_forces,
        plot_trend_spider,
        plot_volume_spectra_vs_thesis,
    )

    folder.mkdir(parents=True, exist_ok=True)
    forces = {
        f"{name}, {point}": np.concatenate(pooled["forces"][name][point])
        for name in names
        for point in FORCE_POINTS
        if pooled["forces"].get(name, {}).get(point)
    }
    save_figure(plot_bending_forces(forces), folder / "fig13_bending_forces.png", field="--out")
    thesis_changes = {
        p: {lab: row[i] / THESIS_ROWS["reference"][i] - 1.0 for i, lab in enumerate(TREND_LABELS)}
        for p, row in THESIS_ROWS.items()
        if p != "reference"
    }
    for name in names:
        volumes = pooled["volumes"].get(name, {})
        for stem, points in FIGURE_GROUPS.items():
            spectra = {p: np.concatenate(volumes[p]) for p in points if volumes.get(p)}
            figure_number = stem.split("_")[0].replace("fig", "Fig. ")
            title = f"Cusp-volume spectrum, `{name}` (thesis {figure_number} analogue)"
            save_figure(
                plot_volume_spectra_vs_thesis(spectra, THESIS_V, title),
                folder / f"{stem}_{name}.png",
                field="--out",
            )
        changes = {
            p: _paired_changes(data.get(name, {}), p) for p in thesis_changes if p in data.get(name, {})
        }
        figure = plot_trend_spider(
            changes, thesis_changes, list(TREND_LABELS), f"Trends, `{name}` (thesis Fig. 25)"
        )
        save_figure(figure, folder / f"fig25_trends_{name}.png", field="--out")


def run_thesis_validation(
    out: Path,
    configs: list[Config],
    specs: dict[str, StudySpec],
    settings: ValidationSettings,
    executor: Executor,
    progress: Callable[[str, StudyProgress], None] | None = None,
) -> tuple[dict[str, tuple[int, int]], list[dict]]:
    """Run the studies `specs` ({subdirectory: spec}) into `out`, then write the scoreboard and figures."""
    started = time.perf_counter()
    for spec in specs.values():  # validate everything before the first run starts
        expand(spec)
    failures: list[dict] = []
    for subdir, spec in specs.items():
        state = run_spec(
            spec, out / subdir, executor, (lambda s, d=subdir: progress(d, s)) if progress else None
        )
        failures += state.failures
    counts = write_outputs(out, configs, settings, time.perf_counter() - started, failures)
    return counts, failures
