"""The scoreboard of `floebreak validate thesis`: per-run metrics, every statement scored.

`run_metrics` reads what one run directory holds (summary.json, cusps.parquet, contacts.parquet); the
metric functions below it are pure. `evaluate` applies a statement's statistic (level or paired relative
change, `floebreak.validation.statements`) to the per-field metrics of one configuration; `scoreboard_rows`
scores every statement for every configuration; `write_scoreboard` writes ``scoreboard.csv`` and
``scoreboard.md`` (atomically).

A must-hold row has one status per configuration: pass, fail, weak-pass (a change row that the null variant,
no change at all, passes too: `Statement.weak`), inert (it cannot fail there: `floebreak.validation.inert`),
info or missing. The tally counts the passes of the rows that can tell, with weak and inert rows apart; an
explanation a statement carries is a note and never changes a status.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from floebreak.validation.chain_statements import chain_metrics
from floebreak.validation.statements import (
    STATEMENTS,
    TABLE5_REFERENCE,
    Statement,
    mean_se,
    null_verdict,
    paired_relative_change,
    verdict,
)

FORCE_BAND_KN = 2500.0  # thesis §5.1: "mainly in the range F_c = [0 kN, 2500 kN]"
POLARSTERN_BAND_KN = 3000.0  # thesis §5.1 (Erceg et al.): "most of the forces below F_c = 3000 kN"
SMALL_CUSP_M3, LARGE_CUSP_M3 = 4.0, 11.0  # thesis §5.3.1, Fig. 17
TABLE_OUTPUTS = (  # the columns of thesis Tables 5–8, in their order
    "mean_cusp_volume_m3",
    "mean_cusp_area_m2",
    "n_cusps",
    "n_flipped",
    "cusp_area_m2",
    "flipped_area_m2",
)
SUMMARY_METRICS = (*TABLE_OUTPUTS, "remaining_ice_area_m2", "initial_ice_area_m2")


def summary_metrics(summary: dict[str, Any]) -> dict[str, float]:
    """Table 5 columns of one run, their sum (affected area) and the ratios n_cusp/n_flip, A_flip/A_cusp."""
    out = {key: float(summary[key]) if summary.get(key) is not None else math.nan for key in SUMMARY_METRICS}
    out["affected_area_m2"] = out["cusp_area_m2"] + out["flipped_area_m2"]
    out["cusp_flip_count_ratio"] = out["n_cusps"] / out["n_flipped"] if out["n_flipped"] else math.nan
    out["flip_cusp_area_ratio"] = (
        out["flipped_area_m2"] / out["cusp_area_m2"] if out["cusp_area_m2"] else math.nan
    )
    return out


def cusp_volume_metrics(volumes_m3: np.ndarray) -> dict[str, float]:
    """Largest cusp and the shares of small (≤ 4 m³) and large (> 11 m³) cusps (thesis Fig. 17)."""
    v = np.asarray(volumes_m3, dtype=float)
    if v.size == 0:
        return {
            "max_cusp_volume_m3": math.nan,
            "share_cusps_le_4m3": math.nan,
            "share_cusps_gt_11m3": math.nan,
        }
    return {
        "max_cusp_volume_m3": float(v.max()),
        "share_cusps_le_4m3": float(np.mean(v <= SMALL_CUSP_M3)),
        "share_cusps_gt_11m3": float(np.mean(v > LARGE_CUSP_M3)),
    }


def bending_forces_kn(contacts: dict[str, np.ndarray]) -> np.ndarray:
    """Crushing force F_c [kN] of every contact evaluation that ended in a bending failure (thesis Fig. 13):
    the panels' F_c summed per (step, piece, zone)."""
    outcome = np.asarray(contacts["outcome"], dtype=object)
    keep = outcome == "bending"
    if not keep.any():
        return np.zeros(0)
    keys = np.stack([np.asarray(contacts[k])[keep] for k in ("step", "piece_id", "zone")], axis=1)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    return np.bincount(inverse.reshape(-1), weights=np.asarray(contacts["f_c_n"], dtype=float)[keep]) / 1e3


def bending_force_metrics(forces_kn: np.ndarray) -> dict[str, float]:
    """Count, median, mean, 95th percentile and the shares ≤ 2500 kN and ≤ 3000 kN of the bending forces."""
    f = np.asarray(forces_kn, dtype=float)
    if f.size == 0:
        keys = ("median", "mean", "p95", "share_le_2500kn", "share_le_3000kn")
        out = {f"bending_force_{k}" + ("" if k.startswith("share") else "_kn"): math.nan for k in keys}
        return {**out, "n_bending_failures": 0.0}
    return {
        "n_bending_failures": float(f.size),
        "bending_force_median_kn": float(np.median(f)),
        "bending_force_mean_kn": float(np.mean(f)),
        "bending_force_p95_kn": float(np.percentile(f, 95)),
        "bending_force_share_le_2500kn": float(np.mean(f <= FORCE_BAND_KN)),
        "bending_force_share_le_3000kn": float(np.mean(f <= POLARSTERN_BAND_KN)),
    }


def torque_metrics(cusps) -> dict[str, float]:
    """Largest and smallest |Q| [kN·m] per pitch of one run's cusps (thesis §6.2; `floebreak.propeller`
    with the defaults of `floebreak propeller`: Tables 10/11, Newton interpolation in the box volume)."""
    from floebreak.app.inputs import shipped_fem_tables
    from floebreak.propeller.cusps import cusp_columns
    from floebreak.propeller.loads.fem import propeller_loads

    columns = cusp_columns(cusps)
    loads = propeller_loads(columns, shipped_fem_tables())
    out = {}
    for label in ("p0", "p95"):
        q = np.abs(np.asarray(loads.get(f"torque_nm_{label}", np.zeros(0)), dtype=float)) / 1e3
        out[f"torque_max_knm_{label}"] = float(q.max()) if q.size else math.nan
        out[f"torque_min_knm_{label}"] = float(q.min()) if q.size else math.nan
    return out


def run_metrics(run_dir: Path, forces: bool = False, torque: bool = False) -> dict[str, float]:
    """Every metric of one complete run directory (the contacts and the propeller only when asked)."""
    import pyarrow.parquet as pq

    out = summary_metrics(json.loads((run_dir / "summary.json").read_text(encoding="utf-8")))
    cusps = pq.read_table(run_dir / "cusps.parquet")
    out.update(cusp_volume_metrics(cusps.column("volume_m3").to_numpy()))
    if forces:
        contacts = pq.read_table(
            run_dir / "contacts.parquet", columns=["step", "piece_id", "zone", "f_c_n", "outcome"]
        )
        out.update(bending_force_metrics(bending_forces_kn(contacts.to_pydict())))
    if torque:
        out.update(torque_metrics(cusps))
    out.update(chain_metrics(run_dir, torque=torque, forces=forces))  # the chain rows (chain_statements)
    return out


def single_floe_metrics(cases: dict[tuple[float, float, str], dict[str, float]]) -> dict[str, float]:
    """§5.2 pattern metrics of the single-floe cases {(d, h, position): run metrics}: share of midship floes
    (e) that give cusps; the flipped share of the broken ice (cusps + flipped) at the shoulders (a, c) minus
    at midship (e), over the cases that broke — the thesis' colours, orange against red; the ice a floe
    leaves in the field ("not changed", blue) is not part of that comparison; the largest port/starboard
    difference (a/c, b/d) of cusp or flipped area, relative to the floe's area."""

    def flipped_share(m):
        return m["flipped_area_m2"] / (m["cusp_area_m2"] + m["flipped_area_m2"])

    def broke(m):
        return m["cusp_area_m2"] + m["flipped_area_m2"] > 0.0

    midship = [m for (_, _, p), m in cases.items() if p == "e"]
    shoulders = [m for (_, _, p), m in cases.items() if p in ("a", "c") and broke(m)]
    midship_broken = [m for m in midship if broke(m)]
    mirror = []
    for (d, h, p), m in cases.items():
        other = cases.get((d, h, {"a": "c", "b": "d"}.get(p, "")))
        if other is not None:
            for key in ("cusp_area_m2", "flipped_area_m2"):
                mirror.append(abs(m[key] - other[key]) / m["initial_ice_area_m2"])
    return {
        "single_floe_midship_cusp_share": float(np.mean([m["n_cusps"] > 0 for m in midship]))
        if midship
        else math.nan,
        "single_floe_shoulder_flip_excess": float(
            np.mean([flipped_share(m) for m in shoulders])
            - np.mean([flipped_share(m) for m in midship_broken])
        )
        if shoulders and midship_broken
        else math.nan,
        "single_floe_mirror_difference": max(mirror) if mirror else math.nan,
    }


def evaluate(statement: Statement, data: dict[str, dict[int, dict[str, float]]]) -> tuple[float, float, int]:
    """Our value of `statement` (mean, standard error, number of fields) from one configuration's
    per-point, per-field metrics ``data[point][field_index][metric]``."""

    def series(point: str) -> dict[int, float]:
        return {i: m.get(statement.metric, math.nan) for i, m in data.get(point, {}).items()}

    values = series(statement.point)
    if statement.statistic == "level":
        return mean_se(values.values())
    return paired_relative_change(values, series(statement.against or "reference"))


def row_status(verdict_: str, weak: bool, inert: bool) -> str:
    """pass | fail | weak-pass | inert | info | missing: a row that cannot fail is inert whatever its verdict;
    a pass of a row that the null variant passes too is weak; a failure is a failure, explained or not."""
    if inert and verdict_ in ("pass", "fail"):
        return "inert"
    if verdict_ == "pass" and weak:
        return "weak-pass"
    return verdict_


def scoreboard_rows(
    data_by_config: dict[str, dict[str, dict[int, dict[str, float]]]],
    profiles: dict[str, str],
    statements: tuple[Statement, ...] = STATEMENTS,
    inert: dict[str, dict[str, Any]] | None = None,
) -> list[dict[str, Any]]:
    """One row per statement: the statement and, per configuration, value, s.e., n, verdict, must-hold,
    the inert reason (`inert` maps a configuration to {statement id: `floebreak.validation.inert.Inert`}; a
    flag whose reason the measured value contradicts is dropped, so it cannot hide a failure) and the status
    (`row_status`); `profiles` maps a configuration to its profile, whose must-hold flags it takes."""
    inert = inert or {}
    rows = []
    for st in statements:
        row: dict[str, Any] = {"statement": st}
        for config, data in data_by_config.items():
            value, se, n = evaluate(st, data)
            flag = inert.get(config, {}).get(st.id)
            contradicted = flag.reason if flag is not None and not flag.holds(value) else ""
            flag = None if contradicted else flag
            result = verdict(value, st.thesis_value, st.tolerance)
            row[config] = {
                "value": value,
                "se": se,
                "n": n,
                "verdict": result,
                "must_hold": profiles[config] in st.must_hold,
                "inert": flag,
                "inert_contradicted": contradicted,
                "status": row_status(result, st.weak, flag is not None),
            }
        rows.append(row)
    return rows


def _fmt(x: float, unit: str, signed: bool = False) -> str:
    if x is None or not math.isfinite(x):
        return "–"
    if unit == "%":
        sign = "+" if signed else ""
        return f"{100 * x:{sign}.1f} %" if abs(x) < 10 else f"{100 * x:{sign}.0f} %"
    return f"{x:.3g}" if abs(x) < 100 else f"{x:.0f}"


def thesis_cell(st: Statement) -> str:
    return st.thesis_text or _fmt(st.thesis_value, st.unit, st.statistic == "change")


def ours_cell(result: dict[str, Any], st: Statement) -> str:
    if result["n"] == 0:
        return "–"
    se = result["se"]
    se_text = f" ± {_fmt(abs(se), st.unit)}" if math.isfinite(se) and result["n"] > 1 else ""
    return f"{_fmt(result['value'], st.unit, st.statistic == 'change')}{se_text}"


CSV_STATEMENT_COLUMNS = ("id", "source", "quote", "quantity", "unit", "point", "against", "statistic",
                         "thesis_value", "thesis_text", "tolerance", "null_verdict", "weak",
                         "note")  # fmt: skip
CSV_CONFIG_COLUMNS = ("ours", "se", "n_fields", "verdict", "must_hold", "status", "inert")


def scoreboard_csv(rows: list[dict[str, Any]], configs: list[str]) -> str:
    """One line per statement, its columns and each configuration's (`CSV_CONFIG_COLUMNS`), in the one CSV
    format (`floebreak.io.writers`)."""
    from floebreak.io.writers import csv_text

    names = list(CSV_STATEMENT_COLUMNS) + [f"{c}_{k}" for c in configs for k in CSV_CONFIG_COLUMNS]
    lines = []
    for row in rows:
        st: Statement = row["statement"]
        cells = [st.id, st.source, st.quote, st.quantity, st.unit, st.point, st.against or "", st.statistic,
                 st.thesis_value, st.thesis_text, st.tolerance.describe(st.unit), null_verdict(st) or "",
                 "yes" if st.weak else "no", st.explained]  # fmt: skip
        for c in configs:
            r = row[c]
            flag = r.get("inert")
            must = "yes" if r["must_hold"] else "no"
            reason = flag.reason if flag else ""
            cells += [r["value"], r["se"], r["n"], r["verdict"], must, r["status"], reason]
        lines.append(cells)
    return csv_text({name: [cells[i] for cells in lines] for i, name in enumerate(names)})


def _verdict_mark(result: dict[str, Any]) -> str:
    text = {"pass": "pass", "fail": "FAIL", "weak-pass": "weak pass", "inert": "inert", "info": "info",
            "missing": "missing"}[result["status"]]  # fmt: skip
    return f"**{text}**" if result["must_hold"] and result["status"] in ("fail", "missing") else text


def scoreboard_markdown_table(rows: list[dict[str, Any]], configs: list[str]) -> list[str]:
    lines = [
        "| id | source | quantity | thesis | tolerance | must hold in | "
        + " | ".join(f"`{c}`" for c in configs)
        + " |",
        "|---|---|---|---|---|---|" + "---|" * len(configs),
    ]
    for row in rows:
        st: Statement = row["statement"]
        must = ", ".join(sorted(st.must_hold)) or "—"
        if st.weak:
            must += " (weak)"
        if st.explained:
            must += " (note below)"
        cells = [f"{ours_cell(row[c], st)} {_verdict_mark(row[c])}" for c in configs]
        unit = "" if st.unit in ("-", "%") or st.thesis_text else f" {st.unit}"
        lines.append(
            f"| {st.id} | {st.source} | {st.quantity} | {thesis_cell(st)}{unit} "
            f"| {st.tolerance.describe(st.unit)} | {must} | " + " | ".join(cells) + " |"
        )
    return lines


class MustHoldTally(NamedTuple):
    """The must-hold rows of one configuration by status (ids): the rows that can tell (passed, failed) are
    counted, the weak passes and the inert rows apart; a failure with a documented reason is a failure."""

    passed: tuple[str, ...]
    weak: tuple[str, ...]  # weak-pass: the null variant passes them too
    failed: tuple[str, ...]  # failures (explained or not) and missing rows
    inert: tuple[str, ...]

    @property
    def counted(self) -> int:
        return len(self.passed) + len(self.failed)


def must_hold_counts(rows: list[dict[str, Any]], config: str) -> MustHoldTally:
    """The `MustHoldTally` of one configuration (a missing row counts as a failure)."""
    by_status: dict[str, list[str]] = {"pass": [], "weak-pass": [], "fail": [], "inert": []}
    for row in rows:
        result = row[config]
        if result["must_hold"]:
            status = result["status"] if result["status"] in by_status else "fail"
            by_status[status].append(row["statement"].id)
    return MustHoldTally(*(tuple(by_status[k]) for k in ("pass", "weak-pass", "fail", "inert")))


def tally_text(tally: MustHoldTally) -> str:
    """The tally as one line, e.g. ``21 of 22 must-hold rows pass; 8 weak; 6 inert; fail: PC5.rate`` (with
    the ids of the failing rows, to look at)."""
    text = (
        f"{len(tally.passed)} of {tally.counted} must-hold rows pass; {len(tally.weak)} weak; "
        f"{len(tally.inert)} inert"
    )
    return text + (f"; fail: {', '.join(tally.failed)}" if tally.failed else "")


def per_100m_lines(
    data_by_config: dict[str, dict[str, dict[int, dict[str, float]]]], length_m: float, thesis_length_m: float
) -> list[str]:
    """Totals of the reference point per 100 m of transit (the bow crosses the whole field)."""
    keys = (("n_cusps", "n_cusp"), ("n_flipped", "n_flip"), ("cusp_area_m2", "A_cusp^tot [m²]"),
            ("flipped_area_m2", "A_flip^tot [m²]"))  # fmt: skip
    lines = [
        "| per 100 m of transit | " + " | ".join(label for _, label in keys) + " |",
        "|---|" + "---|" * len(keys),
        f"| thesis (Table 5 / {thesis_length_m / 100:g}) | "
        + " | ".join(f"{100 * TABLE5_REFERENCE[k] / thesis_length_m:.1f}" for k, _ in keys)
        + " |",
    ]
    for config, data in data_by_config.items():
        cells = []
        for key, _ in keys:
            mean, se, _n = mean_se([m[key] for m in data.get("reference", {}).values()])
            cells.append(f"{100 * mean / length_m:.1f} ± {100 * se / length_m:.1f}")
        lines.append(f"| `{config}` | " + " | ".join(cells) + " |")
    return lines
