"""What moving ice changes, measured against the ice concentration (issue 29 item 6): `static` against
`dynamic` on the reference observation's floe sizes, several seeds per cell, as a Markdown table.

The reference scenario (`default` profile, observation 2019-12-18T20:20 with its diameter classes, h = 1 m,
`agulhas_ii` at 3 m/s, 0.25 m searches) with ``field.concentration`` overridden. The circle placement
reaches about 0.76 in a 100 m wide field, so 0.9 is placed by the `voronoi` generator (angular floes, the
observation's floe count, the cells' own sizes); 0.7 is run with both generators to show what the placement
alone changes. Per run:

- touched: initial floes evaluated in contact at least once; "break": of those, the share that broke or left
  the field whole (cusp, flipped) — the rest were pushed aside (`dynamic`) or withstood the bow (`static`);
- cusps per km of transit;
- cusps reaching a propeller per km: the kinematic transport model (`floebreak.propeller.transport`,
  docs/model.md §13) with its defaults, on the run's cusps;
- mean ice resistance: the longitudinal ice force on the ship averaged over the transit at the prescribed
  speed, in kN, as `floebreak.ship.surge` integrates it
  (`floebreak.output.surge_file.ice_force_series_n`): under
  `static` the contact records' crushing force (trapezoid of the force after the breaks at one search and on
  arrival at the next), under `dynamic` the force the hull passed to the ice over each search interval
  (`SimulationResult.hull_force_on_ice_xy_n`, docs/model.md "The force the hull passes on");
- recorded crushing force: the same average of the contact records' crushing force under either motion (under
  `static` the resistance itself; under `dynamic` what the sweep reported as its resistance before the
  transmitted force was recorded).

Each cell: mean ± sample standard deviation over the seeds. Run (the table goes to stdout and, with
``--out``, to a file): ``PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/ice_motion_sweep.py
[--seeds 5] [--length 385] [--width 100] [--concentrations 0.2 0.7] [--motions dynamic]
[--set KEY=VALUE ...] [--out table.md]``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from floebreak.app.run import run
from floebreak.mechanics import compile_kernels
from floebreak.output.surge_file import ice_force_series_n, recorded_ice_force_series_n
from floebreak.propeller.transport import transport_cusp_table

# (concentration, generator): circles reach ≈ 0.76 at 100 m width, voronoi any concentration
CELLS = ((0.2, "circles"), (0.44, "circles"), (0.7, "circles"), (0.7, "voronoi"), (0.9, "voronoi"))
MOTIONS = ("static", "dynamic")
QUANTITIES = {
    "floes": ("floes", "{:.0f}"),
    "touched": ("touched", "{:.0f}"),
    "break_share": ("break, % of touched", "{:.0f}"),
    "cusps_per_km": ("cusps/km", "{:.0f}"),
    "reaching_per_km": ("cusps reaching a propeller /km", "{:.0f}"),
    "resistance_kn": ("mean ice resistance kN", "{:.0f}"),
    "recorded_kn": ("recorded crushing force kN", "{:.0f}"),
    "cpu_s": ("CPU s", "{:.1f}"),
}


def mean_ice_resistance_n(result, series=ice_force_series_n) -> float:
    """The longitudinal ice force averaged over the transit at constant speed (module docstring)."""
    arrival, after = series(result)
    if len(arrival) < 2:
        return 0.0
    return float(np.mean(0.5 * (after[:-1] + arrival[1:])))


def measure(
    concentration: float, generator: str, motion: str, seed: int, size: tuple[float, float], extra=()
) -> dict:
    overrides = [
        *extra,
        f"field.concentration={concentration}",
        f"field.generator={generator}",
        f"field.length_m={size[0]}",
        f"field.width_m={size[1]}",
        f"simulation.ice_motion={motion}",
        f"seed={seed}",
    ]
    start = time.process_time()
    result = run(None, overrides=overrides)
    cpu_s = time.process_time() - start
    sim = result.simulation
    n_floes = sim.field.n_floes
    touched = np.unique(np.asarray(result.contacts["piece_id"], dtype=np.int64))
    touched = touched[touched < n_floes]
    broke = np.count_nonzero(sim.fate[touched] != "remaining")
    transit_km = (sim.x_end_m - sim.params.x_start_m) / 1000.0
    transport = transport_cusp_table(result.cusps, speed_m_s=result.scenario.ship.speed_m_s)
    return {
        "floes": n_floes,
        "touched": touched.size,
        "break_share": 100.0 * broke / max(touched.size, 1),
        "cusps_per_km": int(sim.mask("cusp").sum()) / transit_km,
        "reaching_per_km": int(np.count_nonzero(transport.propeller_index >= 0)) / transit_km,
        "resistance_kn": mean_ice_resistance_n(result) / 1000.0,
        "recorded_kn": mean_ice_resistance_n(result, recorded_ice_force_series_n) / 1000.0,
        "cpu_s": cpu_s,
    }


def _cell(values: list[float], fmt: str) -> str:
    mean = float(np.mean(values))
    if len(values) < 2:
        return fmt.format(mean)
    return f"{fmt.format(mean)} ± {fmt.format(float(np.std(values, ddof=1)))}"


def table(rows: dict[tuple[float, str, str], list[dict]]) -> str:
    header = ["concentration", "placement", "motion", *(label for label, _ in QUANTITIES.values())]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for (concentration, generator, motion), runs in rows.items():
        cells = [_cell([r[key] for r in runs], fmt) for key, (_, fmt) in QUANTITIES.items()]
        lines.append(f"| {concentration:g} | {generator} | `{motion}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--length", type=float, default=385.0, help="field length [m]")
    parser.add_argument("--width", type=float, default=100.0, help="field width [m]")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this file")
    parser.add_argument(
        "--concentrations", type=float, nargs="+", default=None, help="only these cells' concentrations"
    )
    parser.add_argument("--motions", nargs="+", default=list(MOTIONS), choices=MOTIONS)
    parser.add_argument(
        "--set", dest="overrides", action="append", default=[], help="a scenario override for every run"
    )
    args = parser.parse_args()
    compile_kernels()
    size = (args.length, args.width)
    rows: dict[tuple[float, str, str], list[dict]] = {}
    cells = [cell for cell in CELLS if args.concentrations is None or cell[0] in args.concentrations]
    for concentration, generator in cells:
        for motion in args.motions:
            runs = []
            for seed in range(1, args.seeds + 1):
                runs.append(measure(concentration, generator, motion, seed, size, args.overrides))
                print(f"c = {concentration}, {generator}, {motion}, seed {seed}: {runs[-1]}", flush=True)
            rows[(concentration, generator, motion)] = runs
    text = (
        f"{args.length:g} m × {args.width:g} m field, seeds 1–{args.seeds}, "
        "mean ± sample standard deviation\n\n" + table(rows)
    )
    print(text)
    if args.out is not None:
        args.out.write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
