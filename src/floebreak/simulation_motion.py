"""Moving ice in the stepping loop (``simulation.ice_motion = "dynamic"``; docs/model.md, "Ice motion",
"Coupling with breaking"; issue 29 item 2).

The bow position stays the loop's clock and contacts are still searched every `step_m`; between two
searches the rigid-body engine (`floebreak.dynamics.IceMotionEngine`) advances n = ⌈Δx/(V Δt)⌉ steps of
Δx/(nV), so the searches fall on engine steps. The loop drives this module at four points:

- `IceMotion.advance_to(bow_x)` at the start of a search: the engine steps to `bow_x`, the pieces it moved
  get their current outlines (stored polygon, bounding box; their out-of-contact skip is reset), retired
  pieces their final outlines, and the floes the window's front reached enter the engine;
- `IceMotion.contact(pid, contact, bow_x)` for a piece in contact: floebreak's crushing force (horizontal,
  at each zone's centre) acts on the piece over the next interval as a plastic hull contact (at most |F|,
  never faster than the hull closes in: `IceMotionEngine.hold_against_hull`);
- `IceMotion.broken(pid, floe_children)`: the parent leaves the engine, the floe children enter with the
  parent's rigid-body velocity at their centroids and its angular velocity;
- `IceMotion.leave(pid)`: a piece that left the field whole (cusp, flipped).

A piece the engine has not moved keeps its stored polygon bit for bit, so a run with every piece pinned
(`IceMotionSettings.pin_all`) gives the static results exactly. The engine's window decides which pieces
are awake; pieces wholly behind it are retired. Nothing here draws random numbers. This module imports
nothing from `floebreak.simulation`; it drives a `_Run` through its `pieces` table.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from floebreak.dynamics import IceMotionEngine, IceMotionSettings


class IceMotion:
    """The rigid-body engine of one run and its bookkeeping against the run's piece table."""

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

    # --- between searches ---------------------------------------------------------------------------
    def advance_to(self, bow_x: float) -> None:
        """Step the engine from the last search to `bow_x`, write the moved outlines back, add new floes."""
        dx = bow_x - self.bow_x
        if dx > 0.0:
            n = max(1, math.ceil(dx / (self.speed_m_s * self.settings.time_step_s) - 1e-9))
            dt = dx / (n * self.speed_m_s)
            self._push()
            for _ in range(n):
                self.engine.step(dt)
            self.engine.release_holds()
            self.forces.clear()
            self.bow_x = bow_x
            self._write_back()
        front = bow_x + self.front_offset_m
        while self._next < len(self._waiting) and self._min_x[self._waiting[self._next]] <= front:
            pid = self._waiting[self._next]
            self._next += 1
            if self.pieces.fate[pid] == "remaining":
                self._add(pid, (0.0, 0.0), 0.0)

    def _push(self) -> None:
        """The crushing forces of the last search, each as a plastic hull contact over the interval
        (`IceMotionEngine.hold_against_hull`): at most |F|, and never pushing the piece's point faster than
        the hull closes in along F̂. Held as a plain force, a light piece would leave at up to
        V + |F|Δt/m, faster the larger the engine step (docs/model.md, "Coupling", 2)."""
        for pid, loads in self.forces.items():
            for fx, fy, px, py in loads:
                self.engine.hold_against_hull(pid, (fx, fy), (px, py))

    def _write_back(self) -> None:
        """Retired pieces get their final outlines; of the pieces the engine moved, those the contact sweep
        holds (`pieces.active`) their current ones now, the others when the sweep takes them in or the run
        ends (`flush`): nothing reads them before, and most moved pieces are beside or ahead of the sweep."""
        outlines = self.engine.drain_retired_outlines()
        retired = self.engine.drain_retired()
        moved = [s.piece_id for s in retired if self._has_moved(s.piece_id, (s.x_m, s.y_m, s.angle_rad))]
        self._store(moved, [outlines[pid] for pid in moved])
        for state in retired:
            self._forget(state.piece_id)
        ids, _ = self.engine.changed_poses()
        active = self.pieces.active
        changed = sorted(pid for pid in ids if pid in active)
        self._stale.update(pid for pid in ids if pid not in active)
        self._store(changed, self.engine.polygons(changed))

    def flush(self, pids=None) -> None:
        """Store the current outlines of the moved pieces among `pids` (all if None) not stored yet."""
        stale = sorted(self._stale if pids is None else self._stale.intersection(pids))
        if stale:
            self._stale.difference_update(stale)
            self._store(stale, self.engine.polygons(stale))

    def _has_moved(self, pid: int, pose: tuple[float, float, float]) -> bool:
        return (pose[0], pose[1]) != self.origin[pid] or pose[2] != 0.0

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
