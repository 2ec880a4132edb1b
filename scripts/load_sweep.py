"""Propeller loads against ice thickness, ship speed and the transport's parameters.

The tables of docs/explanation/cusp-flow.md.

For each point: `floebreak run examples/reference.toml` on a short field (`--length-m`, default 120 m) with
the thickness and speed set, then `floebreak propeller RUN --shaft-line agulhas_ii --speed-m-s V
--polar-class PC5 --hours-in-ice-per-year 1000 --years 25` (the benchmark's operating profile); the rows are
loads per hour per propeller, the design ice torque of propeller 1 at the spec's pitch and the shaft's
Q_peak of excitation case 1, each as the analysis' own value and the median with its 5–95 % band over the
flow transport's parameter draws (summary.json "spread", shaft/summary.json "q_peak_spread"). The
sensitivity rows set each transport parameter to ±10 % on the h = 0.4 m, 3 m/s run (a range: both ends).
`--csv FILE` also writes every row (part, label, the numbers); `--reuse` keeps a point's propeller output
where one was written (to finish an interrupted sweep); `--check` prints the sweep's checks (`checks`) from
written CSVs.

    python scripts/load_sweep.py --out DIR [--length-m 120] [--part thickness|speed|sensitivity|all]
        [--transport flow|hull] [--csv FILE] [--reuse]
    python scripts/load_sweep.py --out DIR --check FILE.csv [FILE.csv …]
"""

from __future__ import annotations

import argparse
import itertools
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

THICKNESSES_M = [round(h, 1) for h in np.arange(0.3, 1.51, 0.1)]
SPEEDS_M_S = [round(v, 2) for v in np.arange(1.0, 4.01, 0.25)]
SENSITIVITY = {  # key: default value (floebreak.propeller.transport defaults); tuples: a range's two ends
    "slip_factor": 1.0,
    "hull.run_length_m": 15.0,
    "hull.bilge_radius_m": 2.5,
    "hull.draught_m": 7.65,
    "hull.propeller_plane_aft_of_stem_m": 115.0,
    "arrangement.tip_clearance_m": 0.86,
    "flow.drag_coefficient": (0.5, 1.5),
    "flow.friction": (0.05, 0.15),
    "flow.stem_angle_deg": 27.0,
}
DESIGN_ARGS = ("--polar-class", "PC5", "--hours-in-ice-per-year", "1000", "--years", "25")


def _settings(key: str, value, factor: float) -> list[str]:
    """`--transport-parameter` arguments setting `key` to `factor` × its default (slip factor at most 1)."""
    if isinstance(value, tuple):
        return [
            arg
            for end, v in zip(("min", "max"), value, strict=True)
            for arg in ("--transport-parameter", f"{key}_{end}={v * factor:g}")
        ]
    new = min(value * factor, 1.0) if key == "slip_factor" else value * factor
    return ["--transport-parameter", f"{key}={new:g}"]


def _floebreak(*args) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "floebreak", *map(str, args)], capture_output=True, text=True
    )
    if done.returncode != 0:
        raise SystemExit(f"floebreak {' '.join(map(str, args))} failed:\n{done.stderr}")


def _run(out: Path, thickness: float, speed: float, length: float) -> Path:
    run = out / f"run_h{thickness:g}_v{speed:g}"
    if not (run / "cusps.parquet").exists():
        _floebreak(
            "run", "examples/reference.toml", "--out", run, "--overwrite",
            "--set", f"ice.thickness_m={thickness}", "--set", f"ship.speed_m_s={speed}",
            "--set", f"field.length_m={length}",
        )  # fmt: skip
    return run


def _loads(run: Path, speed: float, tag: str, *extra, reuse: bool = False) -> dict:
    out = run / f"p_{tag}"
    done = (out / "summary.json").exists() and (out / "shaft" / "summary.json").exists()
    if not (reuse and done):
        _floebreak(
            "propeller", run, "--out", out, "--overwrite", "--quiet", "--shaft-line", "agulhas_ii",
            "--speed-m-s", speed, *DESIGN_ARGS, *extra,
        )  # fmt: skip
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    shaft = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))
    spread = summary.get("spread") or {}
    rate = spread.get("loads_per_hour_per_propeller") or {}
    design = next(e for e in summary["design_loads"] if e["propeller"] == "propeller 1")
    row = max(design["rows"], key=lambda r: r["pitch_percent"])
    q_band = row.get("design_torque_band_kn_m") or [None] * 3
    shaft_band = (shaft.get("q_peak_spread") or {}).get("q_peak_knm") or {}
    return {
        "n_cusps": summary["n_cusps"],
        "fraction_reaching": summary["transport"].get("fraction_reaching"),
        "loads_per_hour": summary["rates"]["loads_per_hour_per_propeller"],
        "loads_per_hour_median": rate.get("median"),
        "loads_per_hour_p5": rate.get("p5"),
        "loads_per_hour_p95": rate.get("p95"),
        "design_q_knm": None if summary.get("no_load_reason") else row["design_torque_kn_m"],
        "design_q_p5_knm": q_band[0],
        "design_q_median_knm": q_band[1],
        "design_q_p95_knm": q_band[2],
        "shaft_q_peak_knm": shaft["q_peak_knm"]["1"]["q_peak_knm"],
        "shaft_q_peak_median_knm": shaft_band.get("median"),
        "shaft_q_peak_p5_knm": shaft_band.get("p5"),
        "shaft_q_peak_p95_knm": shaft_band.get("p95"),
        "samples": rate.get("n_samples"),
    }


def _band(r, key: str) -> str:
    """The median (5–95 %) cell of `key` (loads_per_hour, design_q_knm, shaft_q_peak_knm)."""
    base, unit = (key[: -len("_knm")], "_knm") if key.endswith("_knm") else (key, "")
    median, low, high = (r.get(f"{base}_{s}{unit}") for s in ("median", "p5", "p95"))
    if median is None:
        return "–"
    return f"{median:.0f} ({low:.0f}–{high:.0f})"


def _row(label, r) -> str:
    q = "–" if r["design_q_knm"] is None else f"{r['design_q_knm']:.0f}"
    cells = (
        label,
        r["n_cusps"],
        f"{r['fraction_reaching']:.2f}",
        f"{r['loads_per_hour']:.0f}",
        _band(r, "loads_per_hour"),
        q,
        _band(r, "design_q_knm"),
        f"{r['shaft_q_peak_knm']:.0f}",
        _band(r, "shaft_q_peak_knm"),
    )
    return "| " + " | ".join(map(str, cells)) + " |"


HEADER = (
    "| {} | cusps | fraction reaching | loads/h per propeller | median (5–95 %) | design Q, propeller 1 "
    "[kN·m] | median (5–95 %) | shaft Q_peak case 1 [kN·m] | median (5–95 %) |\n"
    "|---|---|---|---|---|---|---|---|---|"
)


def _emit(rows: list, part: str, label, result: dict) -> None:
    rows.append({"part": part, "label": str(label), **result})
    print(_row(label, result), flush=True)


def _write_csv(path: Path, rows: list) -> None:
    import csv

    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _verdict(ok: bool) -> str:
    return "PASS" if ok else "FAIL"


def _ratio(a: float, b: float) -> float:
    return max(a, b) / min(a, b) if min(a, b) > 0 else float("inf")


def checks(rows: list[dict]) -> list[str]:
    """The sweep's checks on the CSV rows (medians; numbers as text): loads per hour > 0 at every thickness
    and speed; the design torque's median at no thickness below the 5 % end of a thinner point's band;
    neighbouring thickness or speed points within 2× in loads per hour and shaft Q_peak; each sensitivity
    row within 2× of the default in all three outputs. One line per check: PASS or FAIL, with the worst
    case."""
    out = []
    by_part: dict[str, list[dict]] = {}
    for r in rows:
        by_part.setdefault(r["part"], []).append(r)
    sweeps = {k: v for k, v in by_part.items() if k != "sensitivity"}
    lowest = min(
        (float(r["loads_per_hour_median"]), r["part"], r["label"]) for v in sweeps.values() for r in v
    )
    out.append(
        f"{_verdict(lowest[0] > 0)} loads per hour > 0: lowest median {lowest[0]:.0f} "
        f"({lowest[1]} {lowest[2]})"
    )
    thick = by_part.get("thickness", [])
    falls = [
        (float(b["design_q_median_knm"]), float(a["design_q_p5_knm"]), a["label"], b["label"])
        for i, a in enumerate(thick)
        for b in thick[i + 1 :]
        if float(b["design_q_median_knm"]) < float(a["design_q_p5_knm"])
    ]
    worst = min(falls, key=lambda f: f[0] / f[1]) if falls else None
    out.append(
        "PASS design torque does not fall with thickness beyond its band"
        if not falls
        else f"FAIL design torque falls with thickness beyond its band at {len(falls)} pairs; worst: median "
        f"{worst[0]:.0f} kN·m at h = {worst[3]} m < 5 % end {worst[1]:.0f} kN·m at h = {worst[2]} m"
    )
    for key, name in (
        ("loads_per_hour_median", "loads per hour"),
        ("shaft_q_peak_median_knm", "shaft Q_peak"),
    ):
        pairs = [
            (_ratio(float(a[key]), float(b[key])), part, a["label"], b["label"])
            for part, v in sweeps.items()
            for a, b in itertools.pairwise(v)
        ]
        r = max(pairs)
        out.append(
            f"{_verdict(r[0] <= 2.0)} neighbours within 2× in {name}: largest {r[0]:.2f} "
            f"({r[1]} {r[2]}→{r[3]})"
        )
    sens = by_part.get("sensitivity", [])
    if sens:
        base = sens[0]
        keys = ("loads_per_hour_median", "design_q_median_knm", "shaft_q_peak_median_knm")
        moves = [(_ratio(float(r[k]), float(base[k])), r["label"], k) for r in sens[1:] for k in keys]
        m = max(moves)
        out.append(
            f"{_verdict(m[0] <= 2.0)} no sensitivity output moves > 2×: largest {m[0]:.2f} ({m[1]}, {m[2]})"
        )
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--length-m", type=float, default=120.0)
    parser.add_argument("--part", choices=("thickness", "speed", "sensitivity", "all"), default="all")
    parser.add_argument("--transport", choices=("hull", "flow"), default="flow")
    parser.add_argument("--csv", type=Path, default=None)
    parser.add_argument("--reuse", action="store_true", help="keep a point's propeller output if written")
    parser.add_argument("--check", type=Path, nargs="+", default=None, help="only check these CSVs")
    args = parser.parse_args(argv)
    if args.check:
        import csv

        rows = [
            r
            for path in args.check
            for r in csv.DictReader(line for line in path.open(encoding="utf-8") if not line.startswith("#"))
        ]
        print("\n".join(checks(rows)))
        return
    transport, rows = ("--transport", args.transport), []
    args.out.mkdir(parents=True, exist_ok=True)
    if args.part in ("thickness", "all"):
        print(HEADER.format("h [m] at 3 m/s"))
        for h in THICKNESSES_M:
            run = _run(args.out, h, 3.0, args.length_m)
            _emit(rows, "thickness", h, _loads(run, 3.0, args.transport, *transport, reuse=args.reuse))
    if args.part in ("speed", "all"):
        for h in (0.4, 1.0):
            print(HEADER.format(f"V [m/s] at h = {h} m"))
            for v in SPEEDS_M_S:
                run = _run(args.out, h, v, args.length_m)
                _emit(rows, f"speed_h{h:g}", v, _loads(run, v, args.transport, *transport, reuse=args.reuse))
    if args.part in ("sensitivity", "all"):
        run = _run(args.out, 0.4, 3.0, args.length_m)
        print(HEADER.format("parameter at h = 0.4 m, 3 m/s"))
        _emit(
            rows,
            "sensitivity",
            "default",
            _loads(run, 3.0, f"{args.transport}_default", *transport, reuse=args.reuse),
        )
        for key, value in SENSITIVITY.items():
            for factor in (0.9, 1.1):
                tag = f"{args.transport}_{key}_{factor:g}"
                result = _loads(run, 3.0, tag, *transport, *_settings(key, value, factor), reuse=args.reuse)
                _emit(rows, "sensitivity", f"{key} × {factor:g}", result)
    if args.csv is not None and rows:
        _write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
