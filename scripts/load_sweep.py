"""Propeller loads against ice thickness, ship speed and the transport's parameters.

The tables of docs/explanation/cusp-flow.md.

For each point: `floebreak run examples/reference.toml` on a short field (`--length-m`, default 120 m) with
the thickness and speed set, then `floebreak propeller RUN --shaft-line agulhas_ii --speed-m-s V`; the
table rows are loads per hour per propeller, max |Q| per cusp at the spec's pitch and the shaft's Q_peak of
excitation case 1. The sensitivity rows set each transport parameter to ±10 % on the h = 0.4 m, 3 m/s run.

    python scripts/load_sweep.py --out DIR [--length-m 120] [--part thickness|speed|sensitivity]
        [--transport hull|flow]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

THICKNESSES_M = [round(h, 1) for h in np.arange(0.3, 1.51, 0.1)]
SPEEDS_M_S = [round(v, 2) for v in np.arange(2.0, 4.01, 0.25)]
SENSITIVITY = {  # key: default value (floebreak.propeller.transport defaults)
    "slip_factor": 1.0,
    "hull.run_length_m": 15.0,
    "hull.bilge_radius_m": 2.5,
    "hull.draught_m": 7.65,
    "hull.propeller_plane_aft_of_stem_m": 115.0,
    "arrangement.tip_clearance_m": 0.86,
}


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


def _loads(run: Path, speed: float, tag: str, *extra) -> dict:
    out = run / f"p_{tag}"
    _floebreak(
        "propeller",
        run,
        "--out",
        out,
        "--overwrite",
        "--shaft-line",
        "agulhas_ii",
        "--speed-m-s",
        speed,
        *extra,
    )
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    shaft = json.loads((out / "shaft" / "summary.json").read_text(encoding="utf-8"))
    pitch = max(summary["pitches"].values(), key=lambda p: p["pitch_percent"])
    q_range = pitch["torque_range_knm"]
    return {
        "loads_per_hour": summary["rates"]["loads_per_hour_per_propeller"],
        "fraction_reaching": summary["transport"].get("fraction_reaching"),
        "max_q_knm": None if q_range is None else q_range[1],
        "shaft_q_peak_knm": shaft["q_peak_knm"]["1"]["q_peak_knm"],
        "n_cusps": summary["n_cusps"],
    }


def _row(label, r) -> str:
    q = "–" if r["max_q_knm"] is None else f"{r['max_q_knm']:.0f}"
    cells = (label, r["n_cusps"], f"{r['fraction_reaching']:.2f}", f"{r['loads_per_hour']:.0f}", q)
    return "| " + " | ".join(map(str, cells)) + f" | {r['shaft_q_peak_knm']:.0f} |"


HEADER = (
    "| {} | cusps | fraction reaching | loads per hour per propeller | max \\|Q\\| per cusp [kN·m] "
    "| shaft Q_peak case 1 [kN·m] |\n|---|---|---|---|---|---|"
)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--length-m", type=float, default=120.0)
    parser.add_argument("--part", choices=("thickness", "speed", "sensitivity", "all"), default="all")
    parser.add_argument("--transport", choices=("hull", "flow"), default="hull")
    args = parser.parse_args(argv)
    transport = ("--transport", args.transport)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.part in ("thickness", "all"):
        print(HEADER.format("h [m] at 3 m/s"))
        for h in THICKNESSES_M:
            print(
                _row(h, _loads(_run(args.out, h, 3.0, args.length_m), 3.0, args.transport, *transport)),
                flush=True,
            )
    if args.part in ("speed", "all"):
        for h in (0.4, 1.0):
            print(HEADER.format(f"V [m/s] at h = {h} m"))
            for v in SPEEDS_M_S:
                print(
                    _row(v, _loads(_run(args.out, h, v, args.length_m), v, args.transport, *transport)),
                    flush=True,
                )
    if args.part in ("sensitivity", "all"):
        run = _run(args.out, 0.4, 3.0, args.length_m)
        print(HEADER.format("parameter at h = 0.4 m, 3 m/s"))
        print(_row("default", _loads(run, 3.0, args.transport, *transport)), flush=True)
        for key, value in SENSITIVITY.items():
            for factor in (0.9, 1.1):
                new = min(value * factor, 1.0) if key == "slip_factor" else value * factor
                tag = f"{args.transport}_{key}_{factor:g}"
                print(
                    _row(
                        f"{key} × {factor:g}",
                        _loads(run, 3.0, tag, *transport, "--transport-parameter", f"{key}={new:g}"),
                    ),
                    flush=True,
                )


if __name__ == "__main__":
    main()
