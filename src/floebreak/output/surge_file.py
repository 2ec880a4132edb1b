"""Ship surge of a run (``[ship.propulsion]``): the speed and ice-force series and its summary.

Without ``ship.propulsion`` the ship sails at the prescribed ``ship.speed_m_s`` and nothing here runs. With
it, the ship enters the field at ``ship.speed_m_s`` and its speed follows from the run's longitudinal ice
force (`floebreak.ship.surge`). Under ``simulation.ice_motion = "static"`` the breaking is quasi-static, so
the stepping loop is the same either way and the surge is integrated afterwards from the contact records'
force; under ``"dynamic"`` the hull's speed drives the ice, so the loop integrates it
(`engine.motion.dynamic`) from the force the hull passed to the ice, and this module reads it
(docs/model.md, "Ship surge").
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from floebreak.io.provenance import floebreak_version
from floebreak.io.writers import write_csv
from floebreak.output.record import RunRecord
from floebreak.ship.surge import SurgeResult, integrate_surge, longitudinal_ice_force_n

SURGE_FILE = "surge.csv"


def ice_force_series_n(result: RunRecord) -> tuple[np.ndarray, np.ndarray]:
    """The run's longitudinal ice force on the bow at each step [N], on arrival and after the step's breaks:
    under static ice from the contact records (`recorded_ice_force_series_n`), under dynamic ice the force
    the hull passed on (`transmitted_ice_force_series_n`)."""
    forces = result.simulation.hull_force_on_ice_xy_n
    if forces is None:
        return recorded_ice_force_series_n(result)
    return transmitted_ice_force_series_n(forces[:, 0])


def transmitted_ice_force_series_n(force_x_n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(on arrival, after the breaks) per step from the mean force over each interval (`force_x_n[k]`: over
    the interval ending at step k; [0] unused): constant in each interval, so on arrival at step k it is the
    force of the interval ending there and after the breaks that of the interval starting there (0 after
    the last step), and the trapezoid of `floebreak.ship.surge` integrates it exactly."""
    force = np.asarray(force_x_n, dtype=float)
    arrival = force.copy()
    arrival[:1] = 0.0
    return arrival, np.append(force[1:], 0.0)


def recorded_ice_force_series_n(result: RunRecord) -> tuple[np.ndarray, np.ndarray]:
    """The run's longitudinal ice force on the bow at each step from the contact records' crushing force
    f_h_n, on arrival and after the step's breaks (`floebreak.ship.surge.longitudinal_ice_force_n`) [N]."""
    sim = result.simulation
    contacts = result.contacts
    return longitudinal_ice_force_n(
        sim.n_steps,
        contacts["step"],
        contacts["piece_id"],
        contacts["panel"],
        contacts["f_h_n"],
        np.asarray(contacts["outcome"]) != "no_failure",
        sim.parent_piece_id,
        np.asarray(sim.bow.panel_normals, dtype=float)[:, 0],
    )


def surge_of(result: RunRecord) -> SurgeResult | None:
    """The ship's surge along the run's transit, None without ``ship.propulsion``."""
    section = result.scenario.ship.propulsion
    if section is None:
        return None
    sim = result.simulation
    if sim.surge is not None:  # dynamic ice: integrated in the loop
        return sim.surge
    propulsion = section.to_propulsion()
    arrival, after = ice_force_series_n(result)
    x = sim.params.x_start_m + sim.params.step_m * np.arange(sim.n_steps)
    return integrate_surge(x, arrival, after, propulsion, result.scenario.ship.speed_m_s)


def surge_summary(result: RunRecord) -> dict[str, Any]:
    """``{"surge": {...}}`` for the run summary (stuck, where, mean ice resistance, speeds), or {}."""
    surge = surge_of(result)
    return {} if surge is None else {"surge": surge.summary()}


def write_surge_file(result: RunRecord, run_dir: str | os.PathLike[str]) -> None:
    """Write ``surge.csv`` (bow position, time, speed, longitudinal ice force) into `run_dir` if the run
    has ``ship.propulsion``."""
    surge = surge_of(result)
    if surge is None:
        return
    comments = [
        f"ship surge under ship.propulsion (docs/model.md, Ship surge); floebreak {floebreak_version()}, "
        f"scenario_hash = {result.summary['scenario_hash']}",
        "ice_force_x_n: longitudinal ice force on the bow on arrival at bow_x_m (before the breaks there)",
        "ice_force_x_after_breaks_n: the same after the breaks at bow_x_m",
    ]
    if result.simulation.hull_force_on_ice_xy_n is not None:
        comments.append(
            "dynamic ice: the force the hull passed to the ice, the mean over each search interval "
            "(on arrival: the interval ending at bow_x_m; after the breaks: the one starting there)"
        )
    if surge.stuck:
        comments.append(f"stuck at bow_x_m = {surge.stuck_at_bow_x_m!r} (the last row)")
    columns = {
        "bow_x_m": surge.bow_x_m,
        "time_s": surge.time_s,
        "speed_m_s": surge.speed_m_s,
        "ice_force_x_n": surge.ice_force_x_n,
        "ice_force_x_after_breaks_n": surge.ice_force_x_after_breaks_n,
    }
    write_csv(Path(run_dir) / SURGE_FILE, columns, comments)
