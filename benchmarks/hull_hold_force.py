"""The force the hull passes on under ``simulation.ice_motion = "dynamic"`` (issue 29): for every hull contact
the coupled loop makes (`IceMotionEngine.hold_against_hull`, a slide joint with ``max_force`` = |F|, F the
contact model's crushing force of a zone at one search), the force the joint actually transmitted over the
interval to the next search — the sum of pymunk's ``Constraint.impulse`` after each engine step
(`IceMotionEngine.hold_impulses`) divided by the interval — against the |F| it was given.

Per run (the reference scenario, `examples/reference.toml`, with ``simulation.ice_motion=dynamic`` and the
concentration set):

- holds: the joints made; "at the limit" (the piece took the whole |F| in every step: jammed, or still
  being accelerated to the hull's speed) where the transmitted force is at least `AT_LIMIT` × |F|; the
  distribution of transmitted / |F| by count and by |F|;
- at the limit: the share of the transmitted impulse that went into the piece's own momentum (m·Δv along
  it; ≈ 1 a piece being accelerated, ≪ 1 one pushed against its neighbours);
- holds not made: zones of a piece the engine had not awake (frozen outside its window), given no joint;
- the mean longitudinal ice force on the bow over the transit (kN): recorded (the trapezoid of
  `benchmarks/ice_motion_sweep.py`, from the contact records' f_h_n), the joints' |F| along x (F_x, what they
  were given), what they transmitted along x (transmitted · F̂_x), the same as the run records it
  (`SimulationResult.hull_force_on_ice_xy_n`, the ship's ice force under `dynamic`), and the recorded one
  under `static`;
- failures: each evaluation that broke a piece or took it out whole, by the hold of the interval that ended at
  that search (the piece's contact at the search before): at the limit, below it (the floe was moving
  freely, yet failed on the full crushing force), or no hold (a piece born at that search, or one not in
  contact at the search before).

The engine methods are wrapped for the measurement (class attributes, restored afterwards); they call the
originals, so the runs are the ordinary ones. Run: ``PYTHONPATH=src OMP_NUM_THREADS=1 python
benchmarks/hull_hold_force.py [--seeds 3] [--concentrations 0.2 0.7] [--length 385] [--width 100]``
(about 1.5 min for the defaults); the figures of a run are in docs/model.md, "The force the hull passes on".
"""

from __future__ import annotations

import argparse
import contextlib
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floebreak.app.run import run
from floebreak.dynamics import IceMotionEngine
from floebreak.mechanics import compile_kernels
from floebreak.output.surge_file import recorded_ice_force_series_n

REFERENCE = Path(__file__).resolve().parents[1] / "examples" / "reference.toml"
AT_LIMIT = 0.999  # transmitted / |F| at or above this: the joint was at its limit throughout
BINS = (0.0, 0.1, 0.5, 0.9, AT_LIMIT, np.inf)


@dataclass
class Recorder:
    """The holds of one run: made at the search before `step`, released at `step`."""

    step: int = 1
    made: dict[int, list[tuple[float, float, float]]] = field(default_factory=lambda: defaultdict(list))
    velocity_made: dict[int, tuple[float, float]] = field(default_factory=dict)
    # step, pid, |F|, F_x, transmitted force, share of the piece's transmitted impulse that went into its own
    # momentum (≈ 1: the piece was being accelerated; ≪ 1: passed on to neighbours and water)
    holds: list[tuple[int, int, float, float, float, float]] = field(default_factory=list)
    not_made: list[tuple[int, int, float, float]] = field(default_factory=list)  # step, pid, |F|, F_x
    lost: int = 0  # released mid-interval (piece frozen or retired by the window)
    time_made_s: float = 0.0


@contextlib.contextmanager
def recording(recorder: Recorder):
    """Wrap `hold_against_hull` and `release_holds` to record each hold; the originals do the work."""
    hold, release = IceMotionEngine.hold_against_hull, IceMotionEngine.release_holds

    def hold_and_record(engine, piece_id, force_n, point_xy_m):
        before = len(engine.hold_impulses().get(piece_id, ()))
        hold(engine, piece_id, force_n, point_xy_m)
        made = len(engine.hold_impulses().get(piece_id, ())) > before
        force = float(np.hypot(*force_n))
        if force == 0.0:
            return
        recorder.time_made_s = engine.time_s
        if made:
            recorder.made[piece_id].append((force, float(force_n[0]), float(force_n[1])))
            state = engine.state(piece_id)
            recorder.velocity_made[piece_id] = (state.vx_m_s, state.vy_m_s)
        else:
            recorder.not_made.append((recorder.step - 1, piece_id, force, float(force_n[0])))

    def record_and_release(engine):
        duration = engine.time_s - recorder.time_made_s
        passed = engine.hold_impulses()
        for pid, made in recorder.made.items():
            joints = passed.get(pid, [])
            if len(joints) != len(made):
                recorder.lost += len(made)
                continue
            own = _own_momentum_share(engine, pid, recorder.velocity_made[pid], made, joints)
            for (force, fx, _), (_, impulse) in zip(made, joints, strict=True):
                recorder.holds.append((recorder.step, pid, force, fx, impulse / duration, own))
        recorder.made.clear()
        recorder.velocity_made.clear()
        recorder.step += 1
        release(engine)

    IceMotionEngine.hold_against_hull, IceMotionEngine.release_holds = hold_and_record, record_and_release
    try:
        yield recorder
    finally:
        IceMotionEngine.hold_against_hull, IceMotionEngine.release_holds = hold, release


def _own_momentum_share(engine, pid: int, velocity_made, made, joints) -> float:
    """m·Δv of the piece over the interval along its holds' summed impulse J, divided by |J|."""
    j = sum(
        impulse * np.array([fx, fy]) / force
        for (force, fx, fy), (_, impulse) in zip(made, joints, strict=True)
    )
    size = float(np.hypot(*j))
    if size == 0.0:
        return float("nan")
    state = engine.state(pid)
    dv = np.array([state.vx_m_s - velocity_made[0], state.vy_m_s - velocity_made[1]])
    return float(engine.mass_kg(pid) * dv @ j) / size**2


def trapezoid_mean(after: np.ndarray, arrival: np.ndarray) -> float:
    """The sweep's mean ice resistance: force after the breaks at one search, on arrival at the next."""
    return float(np.mean(0.5 * (after[:-1] + arrival[1:]))) if len(after) > 1 else 0.0


def measure(concentration: float, seed: int, size: tuple[float, float]) -> dict:
    overrides = [
        "simulation.ice_motion=dynamic",
        f"field.concentration={concentration}",
        f"field.length_m={size[0]}",
        f"field.width_m={size[1]}",
        f"seed={seed}",
    ]
    with recording(Recorder()) as rec:
        result = run(REFERENCE, overrides=overrides)
    n = result.simulation.n_steps
    holds = np.array(rec.holds, dtype=float).reshape(-1, 6)
    step, pid, force, fx, passed, own = holds.T
    ratio = passed / force
    intervals = max(n - 1, 1)
    # the hold made at search k acts over (k, k+1]: per interval, summed over the holds
    given_x = np.bincount((step - 1).astype(int), weights=fx, minlength=n)[: n - 1]
    passed_x = np.bincount((step - 1).astype(int), weights=passed * fx / force, minlength=n)[: n - 1]
    arrival, after = recorded_ice_force_series_n(result)
    return {
        "ratio": ratio,
        "force": force,
        "own": own,
        "not_made": len(rec.not_made),
        "lost": rec.lost,
        "recorded_kn": trapezoid_mean(after, arrival) / 1e3,
        "given_kn": float(given_x.sum()) / intervals / 1e3,
        "passed_kn": float(passed_x.sum()) / intervals / 1e3,
        # what the run itself records as the ship's ice force (SimulationResult.hull_force_on_ice_xy_n)
        "run_kn": float(np.mean(result.simulation.hull_force_on_ice_xy_n[1:, 0])) / 1e3,
        "failures": failures(
            result.contacts,
            np.asarray(result.simulation.parent_piece_id, dtype=np.int64),
            step.astype(int),
            pid.astype(int),
            force,
            passed,
            own,
        ),
        "static_kn": static_resistance_n(overrides) / 1e3,
    }


def static_resistance_n(overrides: list[str]) -> float:
    """The recorded mean ice resistance of the same scenario under `static` (the sweep's baseline)."""
    result = run(REFERENCE, overrides=[*overrides, "simulation.ice_motion=static"])
    arrival, after = recorded_ice_force_series_n(result)
    return trapezoid_mean(after, arrival)


def failures(contacts, parents, step, pid, force, passed, own) -> dict:
    """Each failed evaluation, split (the piece broke) or whole (it left as a cusp or flipped), by the piece's
    hold over the interval that ended at that search: transmitted / |F| summed over its zones (NaN: no hold),
    whether the piece was born at that search (a piece of a break there, never held), and the share of the
    transmitted impulse that went into the piece's own momentum."""
    share: dict[tuple[int, int], list[float]] = defaultdict(lambda: [0.0, 0.0, 0.0])
    for k, p, f, j, o in zip(
        step.tolist(), pid.tolist(), force.tolist(), passed.tolist(), own.tolist(), strict=True
    ):
        share[(k, p)][0] += j
        share[(k, p)][1] += f
        share[(k, p)][2] = o
    outcome = np.asarray(contacts["outcome"])
    failed = outcome != "no_failure"
    steps = np.asarray(contacts["step"], dtype=np.int64)[failed]
    pids = np.asarray(contacts["piece_id"], dtype=np.int64)[failed]
    break_step = np.full(len(parents), -1, dtype=np.int64)
    break_step[pids] = steps
    born = np.where(parents >= 0, break_step[np.maximum(parents, 0)], -1)
    rows = dict.fromkeys(zip(steps.tolist(), pids.tolist(), outcome[failed].tolist(), strict=True))
    out: dict[str, list[tuple[float, bool, float]]] = {"split": [], "whole": []}
    for k, p, label in rows:
        j, f, o = share.get((k, p), (np.nan, np.nan, np.nan))
        out["whole" if label in ("cusp", "flipped") else "split"].append((j / f, bool(born[p] == k), o))
    return {kind: np.array(values, dtype=float).reshape(-1, 3) for kind, values in out.items()}


def _share(mask: np.ndarray, weights: np.ndarray | None = None) -> float:
    w = np.ones(mask.size) if weights is None else weights
    return 100.0 * float(w[mask].sum()) / float(w.sum()) if w.sum() > 0 else float("nan")


def report(concentration: float, runs: list[dict]) -> str:
    """The pooled figures of one concentration (all seeds), as Markdown lines."""
    ratio = np.concatenate([r["ratio"] for r in runs])
    force = np.concatenate([r["force"] for r in runs])
    bins = np.digitize(ratio, BINS[1:-1])
    labels = ("< 0.1", "0.1–0.5", "0.5–0.9", f"0.9–{AT_LIMIT}", f"≥ {AT_LIMIT} (at the limit)")
    lines = [
        f"concentration {concentration:g}: {ratio.size} holds, {sum(r['not_made'] for r in runs)} zones of "
        f"pieces not awake (no joint), {sum(r['lost'] for r in runs)} holds released mid-interval",
        "| transmitted / abs(F) | share of holds % | share weighted by abs(F) % |",
        "|---|---|---|",
    ]
    for b, label in enumerate(labels):
        lines.append(f"| {label} | {_share(bins == b):.1f} | {_share(bins == b, force):.1f} |")
    lines.append(
        f"median transmitted / abs(F) {np.median(ratio):.3f}, max {ratio.max():.6f}; "
        f"Σ transmitted / Σ abs(F) {float((ratio * force).sum() / force.sum()):.3f}"
    )
    own = np.concatenate([r["own"] for r in runs])
    limit = (ratio >= AT_LIMIT) & ~np.isnan(own)
    lines.append(
        f"at the limit: share of the transmitted impulse that went into the piece's own momentum "
        f"{float((own * ratio * force)[limit].sum() / (ratio * force)[limit].sum()):.2f} (median per hold "
        f"{np.median(own[limit]):.2f}); the rest went on to neighbours and water"
    )
    for key, label in (
        ("recorded_kn", "recorded (f_h_n)"),
        ("given_kn", "joints' F_x"),
        ("passed_kn", "transmitted"),
        ("run_kn", "transmitted as the run records it"),
        ("static_kn", "recorded under static"),
    ):
        values = [r[key] for r in runs]
        lines.append(
            f"mean longitudinal ice force, {label}: {np.mean(values):.0f} kN "
            f"(seeds: {', '.join(f'{v:.0f}' for v in values)})"
        )
    for kind in ("split", "whole"):
        table = np.concatenate([r["failures"][kind] for r in runs])
        shares, born, own = table[:, 0], table[:, 1] > 0.5, table[:, 2]
        held = shares[~np.isnan(shares)]
        own_at_limit = own[~np.isnan(shares) & (shares >= AT_LIMIT) & ~np.isnan(own)]
        lines.append(
            f"failures ({kind}): {shares.size}; born at that search {_share(born):.0f} %, otherwise no hold "
            f"before {_share(np.isnan(shares) & ~born):.0f} %; held {_share(~np.isnan(shares)):.0f} %, of "
            f"those below the limit {_share(held < AT_LIMIT):.0f} % (< 0.1: {_share(held < 0.1):.0f} %), "
            f"at the limit {_share(held >= AT_LIMIT):.0f} % (median own-momentum share "
            f"{np.median(own_at_limit) if own_at_limit.size else float('nan'):.2f})"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--concentrations", type=float, nargs="+", default=[0.2, 0.7])
    parser.add_argument("--length", type=float, default=385.0, help="field length [m]")
    parser.add_argument("--width", type=float, default=100.0, help="field width [m]")
    args = parser.parse_args()
    compile_kernels()
    for concentration in args.concentrations:
        runs = [measure(concentration, seed, (args.length, args.width)) for seed in range(1, args.seeds + 1)]
        print(report(concentration, runs), "\n", flush=True)


if __name__ == "__main__":
    main()
