"""Aggregation of a study: one table of all runs, thesis-style tables and figures.

`aggregate(study_dir)` reads `study.json` and every run's `summary.json` (and `cusps.parquet` for the
spectra) and writes ``study_runs.parquet`` (one row per run and sweep group, with its swept parameters),
``tables/<group>.csv|.md`` (thesis
Tables 5–8: means over the fields plus their spread — the thesis gives none) and ``figures/`` (cusp-volume
spectra per sweep group, thesis Figs. 17/19/21/23, and the spider diagram of Fig. 25). It can be re-run at any
time without re-running anything (`floebreak aggregate DIR`).
"""

from __future__ import annotations

import json
import math
import statistics
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from floebreak.errors import InputError
from floebreak.io.atomic import atomic_path
from floebreak.io.writers import write_csv

METRICS = (  # (summary key, table header) — thesis Tables 5–8 columns
    ("mean_cusp_volume_m3", "V̄_cusp [m³]"),
    ("mean_cusp_area_m2", "Ā_cusp [m²]"),
    ("n_cusps", "n_cusp"),
    ("n_flipped", "n_flip"),
    ("cusp_area_m2", "A_cusp^tot [m²]"),
    ("flipped_area_m2", "A_flip^tot [m²]"),
)
SUMMARY_COLUMNS = (
    "n_floes_initial",
    "initial_ice_area_m2",
    "n_cusps",
    "cusp_area_m2",
    "mean_cusp_area_m2",
    "mean_cusp_volume_m3",
    "n_flipped",
    "flipped_area_m2",
    "remaining_ice_area_m2",
    "area_balance_rel_error",
    "n_contacts",
    "n_breaks",
    "crushing_force_max_n",
    "wall_time_s",
    "scenario_hash",
)


def _point_label(point: dict[str, Any]) -> str:
    if not point:
        return "base"
    return ", ".join(f"{key.split('.')[-1]}={_fmt(value)}" for key, value in point.items())


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    return str(value)


def collect_runs(study_dir: Path) -> list[dict[str, Any]]:
    """One record per run of the study: group, point, field, seed, status and the summary numbers."""
    study_file = study_dir / "study.json"
    if not study_file.exists():
        raise InputError(
            "study_dir", f"{str(study_dir)!r} has no study.json", allowed="a floebreak study directory"
        )
    study = json.loads(study_file.read_text(encoding="utf-8"))
    seeds = {run["name"]: run["seed"] for run in study["runs"]}
    records = []
    for member in study["members"]:
        name = member["run"]
        summary_file = study_dir / "runs" / name / "summary.json"
        failed_file = study_dir / "failed" / f"{name}.json"
        record = {
            "run": name,
            "group": member["group"],
            "point": _point_label(member["point"]),
            "field_index": member["field_index"],
            "seed": seeds[name],
            "parameters_json": json.dumps(member["point"], sort_keys=True),
        }
        if summary_file.exists():
            summary = json.loads(summary_file.read_text(encoding="utf-8"))
            record["status"] = "complete"
            record.update({key: summary.get(key) for key in SUMMARY_COLUMNS})
        else:
            record["status"] = "failed" if failed_file.exists() else "missing"
        records.append(record)
    return records


def _mean_spread(values: list[float]) -> tuple[float, float]:
    values = [v for v in values if v is not None and not (isinstance(v, float) and math.isnan(v))]
    if not values:
        return float("nan"), float("nan")
    return statistics.fmean(values), (statistics.stdev(values) if len(values) > 1 else 0.0)


def group_tables(records: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """Per sweep group, per design point: mean and standard deviation over the fields of each metric."""
    tables: dict[str, list[dict[str, Any]]] = {}
    study_points: dict[str, dict[str, list[dict[str, Any]]]] = {}
    for record in records:
        if record["status"] != "complete":
            continue
        study_points.setdefault(record["group"], {}).setdefault(record["point"], []).append(record)
    for group, points in study_points.items():
        rows = []
        for point, runs in points.items():
            row: dict[str, Any] = {"point": point, "n_fields": len(runs)}
            for key, _ in METRICS:
                mean, spread = _mean_spread([r[key] for r in runs])
                row[f"{key}_mean"], row[f"{key}_std"] = mean, spread
            rows.append(row)
        tables[group] = rows
    return tables


def _markdown(group: str, rows: list[dict[str, Any]]) -> str:
    lines = [
        f"### {group}",
        "",
        "| point | fields | " + " | ".join(h for _, h in METRICS) + " |",
        "|---|---|" + "---|" * len(METRICS),
    ]
    for row in rows:
        cells = [f"{row[f'{k}_mean']:.2f} ± {row[f'{k}_std']:.2f}" for k, _ in METRICS]
        lines.append(f"| {row['point']} | {row['n_fields']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _slug(text: str) -> str:
    return "".join(ch if ch.isalnum() else "_" for ch in text.lower()).strip("_") or "group"


def aggregate(study_dir: str | Path) -> dict[str, Any]:
    """Write study_runs.parquet, tables/ and figures/ of a study directory; returns counts."""
    study_dir = Path(study_dir)
    records = collect_runs(study_dir)
    columns = sorted({key for record in records for key in record})
    table = pa.table({key: [record.get(key) for record in records] for key in columns})
    with atomic_path(study_dir / "study_runs.parquet") as temp:
        pq.write_table(table, temp)
    tables = group_tables(records)
    (study_dir / "tables").mkdir(exist_ok=True)
    markdown = ["# Study tables (mean ± standard deviation over the random fields)", ""]
    for group, rows in tables.items():
        name = _slug(group)
        header = ["point", "n_fields"] + [f"{k}_{s}" for k, _ in METRICS for s in ("mean", "std")]
        write_csv(study_dir / "tables" / f"{name}.csv", {h: [row[h] for row in rows] for h in header})
        markdown.append(_markdown(group, rows))
    (study_dir / "tables" / "tables.md").write_text("\n".join(markdown), encoding="utf-8")
    _figures(study_dir, records, tables)
    counts = {
        status: sum(r["status"] == status for r in records) for status in ("complete", "failed", "missing")
    }
    return {"runs": len(records), **counts, "groups": list(tables)}


def _cusp_volumes(study_dir: Path, run: str) -> np.ndarray:
    path = study_dir / "runs" / run / "cusps.parquet"
    if not path.exists():
        return np.zeros(0)
    return np.asarray(pq.read_table(path, columns=["volume_m3"]).column("volume_m3").to_numpy(), dtype=float)


def _figures(study_dir: Path, records: list[dict[str, Any]], tables: dict[str, list[dict[str, Any]]]) -> None:
    from floebreak.io.figures import save_figure
    from floebreak.plotting.study import plot_spider, plot_volume_spectra

    figures = study_dir / "figures"
    figures.mkdir(exist_ok=True)
    for group in tables:
        volumes: dict[str, list[np.ndarray]] = {}
        for record in records:
            if record["group"] == group and record["status"] == "complete":
                volumes.setdefault(record["point"], []).append(_cusp_volumes(study_dir, record["run"]))
        spectra = {point: np.concatenate(v) if v else np.zeros(0) for point, v in volumes.items()}
        save_figure(
            plot_volume_spectra(spectra, title=f"Cusp-volume spectrum: {group}"),
            figures / f"cusp_volume_spectrum_{_slug(group)}.png",
        )
    if tables:
        save_figure(plot_spider(tables, METRICS), figures / "spider.png")
