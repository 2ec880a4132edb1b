"""Moving ice in the stepping loop (``simulation.ice_motion = "dynamic"``; docs/model.md, "Ice motion",
"Coupling with breaking").

The bow position stays the loop's clock and contacts are still searched every `step_m`; between two
searches the rigid-body engine (`floebreak.dynamics.IceMotionEngine`) advances n = ⌈Δx/(V Δt)⌉ steps of
Δx/(nV), so the searches fall on engine steps. The loop drives this module at four points:

- `DynamicIce.advance_to(bow_x)` at the start of a search: the engine steps to `bow_x`, the pieces it moved
  get their current outlines (stored polygon, bounding box; their out-of-contact skip is reset), retired
  pieces their final outlines, and the floes the window's front reached enter the engine;
- `DynamicIce.contact(pid, contact, bow_x)` for a piece in contact: floebreak's crushing force (horizontal,
  at each zone's centre) acts on the piece over the next interval as a plastic hull contact (at most |F|,
  never faster than the hull closes in: `IceMotionEngine.hold_against_hull`);
- `DynamicIce.broken(pid, floe_children)`: the parent leaves the engine, the floe children enter with the
  parent's rigid-body velocity at their centroids and its angular velocity;
- `DynamicIce.leave(pid)`: a piece that left the field whole (cusp, flipped).

Over each interval the force the hull passed to the ice is recorded (`force_on_ice_xy_n`: the holds'
impulses along their F̂, the whole F of pieces held still, Chipmunk's own hull contacts), the force the
ship feels (docs/model.md, "The force the hull passes on"). With `params.propulsion` the ship's speed follows
from it (`floebreak.ship.surge.SurgeIntegrator`, per interval): the hull sails each interval at the speed the
ship had at its start, and a ship that stops ends the run (`stuck`).

A piece the engine has not moved keeps its stored polygon bit for bit, so a run with every piece pinned
(`IceMotionSettings.pin_all`) gives the static results exactly. The engine's window decides which pieces
are awake; pieces wholly behind it are retired. Nothing here draws random numbers. This module imports
nothing from `floebreak.engine.loop`; it drives a `_Run` through its `pieces` table.
"""

from __future__ import annotations

import dataclasses
import math
from array import array

import numpy as np
import shapely

from floebreak.dynamics import IceMotionEngine, IceMotionSettings
from floebreak.ship.propulsion import balance_speed_m_s
from floebreak.ship.surge import SurgeIntegrator


class DynamicIce:
    """The rigid-body engine of one run and its bookkeeping against the run's piece table."""

    moves = True

    def __init__(self, run):
        params = run.params
        self.settings: IceMotionSettings = params.ice_motion_settings or IceMotionSettings()
        self.speed_m_s = float(params.speed_m_s)
        self.pieces = run.pieces
        _, y0, x1, y1 = run.hull_box
        hull = shapely.transform(run.bow.hull_upper, lambda xy: xy + np.array([params.x_start_m, 0.0]))
        self.engine = IceMotionEngine(hull, (self.speed_m_s, 0.0), self.settings)
        self.bow_x = params.x_start_m
        # moved pieces whose stored outline is older than their pose (`_write_back`); the sweep flushes a
        # floe as it takes it in
        self._stale: set[int] = set()
        run.pieces.on_enter = self._flush_one
        self.last_contact_x_m: dict[int, float] = {}  # bow x of each piece's last contact
        # floes enter when the window's front reaches their minimum x (sorted, then by id); at least the
        # contact search's reach, so that every piece floebreak evaluates is in the engine
        s, d = self.settings, params.dist_bow_max_m
        self.front_offset_m = x1 + max(s.window_ahead_m, d)
        side = max(s.window_side_m, d)
        bounds = shapely.bounds(run.field.polygons).reshape(-1, 4)
        in_band = (bounds[:, 1] <= y1 + side) & (bounds[:, 3] >= y0 - side)
        order = np.flatnonzero(in_band)
        self._waiting = order[np.argsort(bounds[order, 0], kind="stable")].tolist()
        self._min_x = bounds[:, 0]
        self._next = 0
        self.origin: dict[int, tuple[float, float]] = {}  # centroid when added: unmoved pieces keep polygons
        self.forces: dict[int, list[tuple[float, float, float, float]]] = {}
        # per search: the mean force the hull passed to the ice over the interval ending there [N], field
        # frame (the ship receives the opposite; the x part is the ice resistance); none before the first.
        # flat (x, y) pairs in a typed array: one series entry per search, so memory per km matters
        self.force_on_ice_xy_n = array("d", (0.0, 0.0))
        # per piece held over the last interval: Σ transmitted / Σ |F|·time of its holds (`failure_contact`)
        self.load_share: dict[int, float] = {}
        # with `params.propulsion` the ship's speed follows from its net thrust and that force
        self.surge = None
        if params.propulsion is not None:
            self.surge = SurgeIntegrator(params.propulsion, self.speed_m_s, params.x_start_m)
            # the fastest the ship can sail: its entry speed, or the open-water speed it accelerates to
            self.settings.check_time_step(max(self.speed_m_s, balance_speed_m_s(params.propulsion)))

    @property
    def stuck(self) -> bool:
        """The ship stopped before the last search (ship surge under `params.propulsion`)."""
        return self.surge is not None and self.surge.stuck_at_bow_x_m is not None

    def outputs(self, n_steps: int) -> dict:
        """The run's transmitted forces per search and, with propulsion, its surge (`SimulationResult`)."""
        forces = np.frombuffer(self.force_on_ice_xy_n, dtype=float).reshape(-1, 2)[:n_steps].copy()
        return {
            "hull_force_on_ice_xy_n": forces,
            "surge": None if self.surge is None else self.surge.result(0.0),
        }

    # --- between searches ---------------------------------------------------------------------------
    def advance_to(self, bow_x: float) -> None:
        """Step the engine from the last search to `bow_x`, write the moved outlines back, add new floes."""
        dx = bow_x - self.bow_x
        if dx > 0.0:
            speed = self.speed_m_s
            n = max(1, math.ceil(dx / (speed * self.settings.time_step_s) - 1e-9))
            dt = dx / (n * speed)
            resisted = self._push()
            contact_x = contact_y = 0.0  # Chipmunk's own hull contacts (``hull_contact = "engine"``)
            for _ in range(n):
                self.engine.step(dt)
                for ix, iy in self.engine.hull_impulses().values():
                    contact_x, contact_y = contact_x + ix, contact_y + iy
            duration = dx / speed
            held_x, held_y = self._held_impulse_n_s(duration)
            force = (
                (held_x + contact_x) / duration + resisted[0],
                (held_y + contact_y) / duration + resisted[1],
            )
            self.force_on_ice_xy_n.extend(force)
            self.engine.release_holds()
            self.forces.clear()
            self.bow_x = bow_x
            self._write_back()
            if self.surge is not None:
                self._sail(bow_x, force[0])
        front = bow_x + self.front_offset_m
        while self._next < len(self._waiting) and self._min_x[self._waiting[self._next]] <= front:
            pid = self._waiting[self._next]
            self._next += 1
            if self.pieces.fate[pid] == "remaining":
                self._add(pid, (0.0, 0.0), 0.0)

    def _push(self) -> tuple[float, float]:
        """The crushing forces of the last search, each as a plastic hull contact over the interval
        (`IceMotionEngine.hold_against_hull`): at most |F|, and never pushing the piece's point faster than
        the hull closes in along F̂. Held as a plain force, a light piece would leave at up to
        V + |F|Δt/m, faster the larger the engine step (docs/model.md, "Coupling", 2). Returns the force of
        the pieces held still (`_resisted_force_n`)."""
        for pid, loads in self.forces.items():
            for fx, fy, px, py in loads:
                self.engine.hold_against_hull(pid, (fx, fy), (px, py))
        return self._resisted_force_n()

    def _resisted_force_n(self) -> tuple[float, float]:
        """Σ F of the pieces in contact the engine holds still (pinned: static bodies, given no hold): such
        a piece resists the whole crushing force over the interval."""
        held = self.engine.hold_impulses()
        fx = fy = 0.0
        for pid, loads in self.forces.items():
            if pid not in held:
                for load in loads:
                    fx, fy = fx + load[0], fy + load[1]
        return fx, fy

    def _held_impulse_n_s(self, duration_s: float) -> tuple[float, float]:
        """Σ of the impulses the holds made by `_push` transmitted over the interval of `duration_s` (N·s,
        field frame), each along its F̂ (the hull anchor is `_HOLD_REACH_M` away along −F̂: the direction
        turns by less than 1e-4 rad as the piece slides by metres); the holds of a piece follow its non-zero
        loads in order. Sets `load_share`, each held piece's Σ impulse / (Σ |F|·duration)."""
        jx = jy = 0.0
        self.load_share = {}
        for pid, holds in self.engine.hold_impulses().items():
            loads = [(fx, fy) for fx, fy, _, _ in self.forces[pid] if fx != 0.0 or fy != 0.0]
            for (size, impulse), (fx, fy) in zip(holds, loads, strict=True):
                jx, jy = jx + impulse * fx / size, jy + impulse * fy / size
            given = sum(size for size, _ in holds) * duration_s
            self.load_share[pid] = sum(impulse for _, impulse in holds) / given
        return jx, jy

    def failure_contact(self, pid: int, contact):
        """The contact the failure criteria see (``ice_motion.failure_force``): as found, or, under
        "lagged_transmitted", every zone's forces times the share of the crushing force the piece's holds
        passed on over the interval before (capped at 1; the whole force for a piece not held then)."""
        share = self.load_share.get(pid, 1.0)
        if self.settings.failure_force == "crushing" or share >= 1.0:
            return contact
        zones = tuple(
            dataclasses.replace(
                z,
                f_c_n=z.f_c_n * share,
                f_v_n=z.f_v_n * share,
                f_h_n=z.f_h_n * share,
                force_on_ice_xy_n=z.force_on_ice_xy_n * share,
            )
            for z in contact.zones
        )
        return dataclasses.replace(contact, zones=zones)

    def _sail(self, bow_x: float, force_x_n: float) -> None:
        """The ship's speed over the next interval: the energy equation of `floebreak.ship.surge` from the
        last search to `bow_x` under the force the hull passed on over the interval (constant in it), the
        hull's speed in the engine over the interval being the ship's speed at its start."""
        if self.surge.advance(bow_x, force_x_n, force_x_n):
            self.speed_m_s = self.surge.speed_m_s
            self.engine.set_hull_velocity((self.speed_m_s, 0.0))

    def _write_back(self) -> None:
        """Retired pieces get their final outlines. Of the pieces the engine moved, those the contact sweep
        holds (`pieces.active`) get their outlines' boxes now (the sweep's search reads them), the outlines
        themselves when the search finds them touching the hull's box (`flush`, called by the loop), the
        sweep takes them in, they leave or the run ends: nothing reads them before, and most moved pieces
        are beside, behind or ahead of the hull."""
        outlines = self.engine.drain_retired_outlines()
        retired = self.engine.drain_retired()
        moved = [s.piece_id for s in retired if self._has_moved(s.piece_id, (s.x_m, s.y_m, s.angle_rad))]
        self._store(moved, [outlines[pid] for pid in moved])
        for state in retired:
            self._forget(state.piece_id)
        ids, _ = self.engine.changed_poses()
        self._stale.update(ids)
        active = self.pieces.active
        changed = sorted(pid for pid in ids if pid in active)
        self._store_boxes(changed, self.engine.boxes(changed).tolist())

    def flush(self, pids=None) -> None:
        """Store the current outlines of the moved pieces among `pids` (all if None) not stored yet."""
        stale = sorted(self._stale if pids is None else self._stale.intersection(pids))
        if stale:
            self._stale.difference_update(stale)
            self._store(stale, self.engine.polygons(stale))

    def _has_moved(self, pid: int, pose: tuple[float, float, float]) -> bool:
        return (pose[0], pose[1]) != self.origin[pid] or pose[2] != 0.0

    def _store_boxes(self, pids: list[int], boxes: list[list[float]]) -> None:
        """The boxes of moved pieces the sweep holds, as `_store` would set them from their outlines."""
        pieces = self.pieces
        for pid, bounds in zip(pids, boxes, strict=True):
            bounds = tuple(bounds)
            pieces.bounds[4 * pid : 4 * pid + 4] = type(pieces.bounds)("d", bounds)
            pieces.active[pid] = bounds
            pieces.quiet_until[pid] = -np.inf

    def _store(self, pids: list[int], outlines: list[shapely.Polygon]) -> None:
        """Each outline becomes its piece's polygon and box (the contact sweep's box too, where it holds
        the piece); the piece's out-of-contact skip no longer holds."""
        pieces = self.pieces
        boxes = shapely.bounds(outlines).reshape(-1, 4).tolist()
        for pid, outline, bounds in zip(pids, outlines, boxes, strict=True):
            pieces.polygon[pid] = outline
            bounds = tuple(bounds)
            pieces.bounds[4 * pid : 4 * pid + 4] = type(pieces.bounds)("d", bounds)
            if pid in pieces.active:
                pieces.active[pid] = bounds
            else:  # not (or no longer) searched for contact: kept compact as the loop keeps such pieces
                pieces._finish(pid)
            pieces.quiet_until[pid] = -np.inf

    def _add(self, pid: int, velocity_m_s: tuple[float, float], angular_velocity_rad_s: float) -> None:
        self.engine.add_piece(
            pid,
            self.pieces.polygon[pid],
            self.pieces.thickness[pid],
            velocity_m_s=velocity_m_s,
            angular_velocity_rad_s=angular_velocity_rad_s,
            pinned=self.settings.pin_all,
        )
        state = self.engine.state(pid)
        self.origin[pid] = (state.x_m, state.y_m)

    # --- at a search --------------------------------------------------------------------------------
    def contact(self, pid: int, contact, bow_x: float) -> None:
        """floebreak's horizontal crushing force on the piece (bow frame → field frame: + bow_x), at each
        zone's centre, acts over the next interval."""
        if pid not in self.origin:
            return
        self.forces[pid] = [
            (*map(float, z.force_on_ice_xy_n), float(z.centre_xy_m[0]) + bow_x, float(z.centre_xy_m[1]))
            for z in contact.zones
        ]
        self.last_contact_x_m[pid] = bow_x

    def broken(self, pid: int, floe_children: list[int]) -> None:
        """The parent leaves the engine; each child that stays a floe enters with the parent's rigid-body
        velocity at the child's centroid and the parent's angular velocity (docs/model.md, coupling 4)."""
        if pid not in self.origin:
            return
        omega = self.engine.state(pid).angular_velocity_rad_s
        centroids = shapely.centroid([self.pieces.polygon[child] for child in floe_children])
        velocities = [self.engine.velocity_at(pid, (c.x, c.y)) for c in centroids]
        self.leave(pid)
        for child, velocity in zip(floe_children, velocities, strict=True):
            self._add(child, velocity, omega)

    def leave(self, pid: int) -> None:
        """A piece leaves the engine (broken, cusp, flipped); its stored polygon is its current outline."""
        if pid in self.origin:
            self._flush_one(pid)
            self._forget(pid)
            self.engine.remove_piece(pid)

    def _flush_one(self, pid: int) -> None:
        if pid in self._stale:
            self.flush((pid,))

    def _forget(self, pid: int) -> None:
        self._stale.discard(pid)
        self.last_contact_x_m.pop(pid, None)
        del self.origin[pid]
        self.forces.pop(pid, None)
