"""The rigid-body engine of moving ice: a pymunk (Chipmunk2D) space with a kinematic hull and the pieces.

Field frame (x forward, y to port), metres, seconds. Each piece is a dynamic body at its centroid with mass
(1 + C_a)·ρ_i·A·h and moment (1 + C_a,ψ)·ρ_i·h·∫r²dA, its convex parts as collision shapes; the water forces
(`forces.py`) are applied at the start of every step. Only pieces whose bounding box meets the awake window
around the hull are dynamic; the others are static bodies (frozen where they are, still obstacles to the
awake ones), pinned pieces are static always, and pieces wholly behind the window are retired: removed,
their last state kept for `drain_retired`. Nothing here draws random numbers: the same calls give the same
states (Chipmunk is deterministic for the same sequence of operations).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import pymunk
import pymunk.batch
import shapely

from floebreak.dynamics.bodies import BodyGeometry, body_geometry, centroid_and_radius
from floebreak.dynamics.bodies import compile_now as _compile_bodies
from floebreak.dynamics.forces import DragTable, drag_constants, drag_table, water_loads_into
from floebreak.dynamics.forces import compile_now as _compile_water
from floebreak.dynamics.settings import IceMotionSettings

ICE_COLLISION_TYPE = 1
# a hull contact's anchor on the hull lies this far behind the contact point [m], so that the direction of
# the hold stays F̂ while the piece turns and slides by metres during an interval
_HOLD_REACH_M = 1.0e4
HULL_COLLISION_TYPE = 2


@dataclass(frozen=True)
class PieceState:
    """A piece's rigid-body state: centroid position, rotation from its shape when added, velocities."""

    piece_id: int
    x_m: float
    y_m: float
    angle_rad: float
    vx_m_s: float
    vy_m_s: float
    angular_velocity_rad_s: float
    awake: bool
    pinned: bool


@dataclass(frozen=True)
class _Entering:
    """A piece added since the engine last stepped, not yet a body (`IceMotionEngine._materialize`)."""

    polygon: shapely.Polygon
    thickness_m: float
    velocity_m_s: tuple[float, float]
    angular_velocity_rad_s: float
    pinned: bool
    centroid_xy_m: tuple[float, float]
    radius_m: float


class _Piece:
    __slots__ = (
        "awake",
        "body",
        "drag",
        "geometry",
        "mass_kg",
        "moment_kg_m2",
        "pinned",
        "radius_m",
        "reported",
        "shapes",
        "thickness_m",
    )

    def __init__(self, geometry: BodyGeometry, thickness_m: float, settings: IceMotionSettings):
        self.geometry = geometry
        self.thickness_m = thickness_m
        self.radius_m = float(np.hypot(geometry.ring_xy_m[:, 0], geometry.ring_xy_m[:, 1]).max())
        areal = settings.ice_density_kg_m3 * thickness_m
        self.mass_kg = (1.0 + settings.added_mass_coefficient) * areal * geometry.area_m2
        self.moment_kg_m2 = (1.0 + settings.added_inertia_coefficient) * areal * geometry.polar_moment_m4
        self.drag = drag_constants(geometry, thickness_m, settings)
        self.body = pymunk.Body(self.mass_kg, self.moment_kg_m2)
        self.shapes = [pymunk.Poly(self.body, [tuple(v) for v in part]) for part in geometry.convex_parts]
        for shape in self.shapes:
            shape.collision_type = ICE_COLLISION_TYPE
            # Chipmunk multiplies the two shapes' values: √ on each gives μ and e of an ice–ice pair
            shape.friction = math.sqrt(settings.ice_ice_friction)
            shape.elasticity = math.sqrt(settings.ice_ice_restitution)
        self.pinned = False
        self.awake = True
        # (x, y, angle) when `changed_poses` last reported the piece (on entry: where it was added)
        self.reported = (*geometry.centroid_xy_m, 0.0)

    def box(self) -> tuple[float, float, float, float]:
        """Centroid ± the largest radius: holds the piece in any orientation (the window needs no more)."""
        x, y = self.body.position
        r = self.radius_m
        return (x - r, y - r, x + r, y + r)


@dataclass(frozen=True)
class _Rows:
    """The pieces held, one row each in the order they were added, and the map from Chipmunk's body ids
    (the order `pymunk.batch` reads them in) to rows; rebuilt when a piece enters or leaves."""

    ids: tuple[int, ...]
    pieces: tuple[_Piece, ...]
    row_of_id: dict[int, int]
    drag: DragTable
    radius_m: np.ndarray
    awake: np.ndarray  # kept equal to the pieces' `awake`
    pinned: np.ndarray
    reported: np.ndarray  # (n, 3) the pieces' `reported`
    last_speed_m_s: np.ndarray  # each piece's speed at the last step (∞ after a rebuild): the rest stop
    body_ids: np.ndarray  # sorted
    row_of_body: np.ndarray  # the row of each of body_ids

    @classmethod
    def of(cls, pieces: dict[int, _Piece]) -> _Rows:
        held = tuple(pieces.values())
        body_ids = np.array([p.body.id for p in held], dtype=np.uintp)
        order = np.argsort(body_ids, kind="stable")
        table = (
            drag_table(
                [p.geometry.ring_xy_m for p in held],
                [p.drag for p in held],
                [p.mass_kg for p in held],
                [p.moment_kg_m2 for p in held],
            )
            if held
            else None
        )
        return cls(
            tuple(pieces),
            held,
            {pid: row for row, pid in enumerate(pieces)},
            table,
            np.array([p.radius_m for p in held], dtype=float),
            np.array([p.awake for p in held], dtype=bool),
            np.array([p.pinned for p in held], dtype=bool),
            np.array([p.reported for p in held], dtype=float).reshape(-1, 3),
            np.full(len(held), np.inf),
            body_ids[order],
            order,
        )


# x, y, angle, vx, vy, ω of every body, read in one call (pymunk's batch API; per-body attribute access
# costs about 70 times more)
_READ_FIELDS = (
    pymunk.batch.BodyFields.BODY_ID
    | pymunk.batch.BodyFields.POSITION
    | pymunk.batch.BodyFields.ANGLE
    | pymunk.batch.BodyFields.VELOCITY
    | pymunk.batch.BodyFields.ANGULAR_VELOCITY
)

_FORCE_FIELDS = pymunk.batch.BodyFields.FORCE | pymunk.batch.BodyFields.TORQUE


class IceMotionEngine:
    """Pieces by id, a kinematic hull moving at a set velocity, `step(dt)` with the water forces."""

    def __init__(
        self,
        hull_polygon: shapely.Polygon,
        hull_velocity_m_s: tuple[float, float],
        settings: IceMotionSettings | None = None,
        *,
        water: bool = True,
    ):
        """`hull_polygon`: the ship's ice waterline, field frame, at time 0. `water=False` applies no water
        forces (checks of the collision mechanics alone)."""
        self.settings = settings if settings is not None else IceMotionSettings()
        self.water = water
        self.time_s = 0.0
        self.space = pymunk.Space()
        self.space.iterations = self.settings.solver_iterations
        self.hull = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self._hull_shapes = [
            pymunk.Poly(self.hull, [tuple(v) for v in part]) for part in body_geometry_parts(hull_polygon)
        ]
        for shape in self._hull_shapes:
            shape.collision_type = HULL_COLLISION_TYPE
            # Chipmunk takes a contact's restitution as the product of the shapes' (an arbiter's value set
            # in a callback does not reach the bounce); friction is set per hull contact in pre_solve
            shape.elasticity = _hull_shape_elasticity(self.settings)
            if self.settings.hull_contact == "crushing":  # the hull's force is the loop's crushing force
                shape.filter = pymunk.ShapeFilter(mask=0)
        self.space.add(self.hull, *self._hull_shapes)
        self._hull_bounds0 = hull_polygon.bounds
        self.set_hull_velocity(hull_velocity_m_s)
        self._pieces: dict[int, _Piece] = {}
        self._entering: dict[int, _Entering] = {}  # added, not yet bodies (`add_piece`)
        self._by_body: dict[pymunk.Body, int] = {}
        self._holds: dict[int, list[pymunk.SlideJoint]] = {}
        self._hold_impulses: dict[int, list[float]] = {}  # per hold of `_holds`, since it was made [N·s]
        self._impulses: dict[int, tuple[float, float]] = {}
        self._retired: list[PieceState] = []
        self._retired_outlines: dict[int, shapely.Polygon] = {}
        self._rows: _Rows | None = None  # the pieces held as rows; None once one entered or left
        # every body's (x, y, angle, vx, vy, ω) in Chipmunk's order, and by row; None once stale (`_read`)
        self._values: np.ndarray | None = None
        self._state: np.ndarray | None = None
        self._body_of_row = np.zeros(0, dtype=np.int64)
        self._force_values = np.zeros((0, 3))  # the force buffer's array, Chipmunk's order (`_map`)
        self._held_rows: np.ndarray | None = None  # by row, held by the hull (`_held`)
        self._buffer = pymunk.batch.Buffer()
        self._force_buffer = pymunk.batch.Buffer()
        # the body ids in the order of the last batch read, where the pieces' rows sit among them, which rows
        self._read_order: tuple[np.ndarray, np.ndarray, np.ndarray] = (np.zeros(0, np.uintp),) * 3
        self.space.on_collision(
            HULL_COLLISION_TYPE,
            ICE_COLLISION_TYPE,
            pre_solve=self._hull_contact_values,
            post_solve=self._record_hull_impulse,
        )

    # --- the hull ------------------------------------------------------------------------------------
    def set_hull_velocity(self, velocity_m_s: tuple[float, float]) -> None:
        """Set the hull's velocity; InputError if the time step cannot resolve its speed."""
        self.settings.check_time_step(math.hypot(*velocity_m_s))
        self.hull.velocity = (float(velocity_m_s[0]), float(velocity_m_s[1]))
        self._hull_speed_m_s = self.hull.velocity.length
        self._checked = (math.nan, math.nan)  # the (speed, step) `step` last checked

    @property
    def hull_offset_m(self) -> tuple[float, float]:
        """How far the hull has moved from its position at time 0."""
        return float(self.hull.position.x), float(self.hull.position.y)

    def window(self) -> tuple[float, float, float, float]:
        """The awake window (x_min, y_min, x_max, y_max) around the hull now."""
        x0, y0, x1, y1 = self._hull_bounds0
        dx, dy = self.hull_offset_m
        s = self.settings
        return (
            x0 + dx - s.window_behind_m,
            y0 + dy - s.window_side_m,
            x1 + dx + s.window_ahead_m,
            y1 + dy + s.window_side_m,
        )

    # --- pieces --------------------------------------------------------------------------------------
    def add_piece(
        self,
        piece_id: int,
        polygon: shapely.Polygon,
        thickness_m: float,
        *,
        velocity_m_s: tuple[float, float] = (0.0, 0.0),
        angular_velocity_rad_s: float = 0.0,
        pinned: bool = False,
    ) -> None:
        """Add a piece (a valid polygon without holes, field frame) moving at the given rigid-body velocity
        (of its centroid). A pinned piece never moves. Its body is built when the engine next needs it
        (`_materialize`): about half the pieces a break adds break again at the same contact search, and
        their state until then is this one."""
        if piece_id in self._pieces or piece_id in self._entering:
            raise ValueError(f"piece {piece_id} is in the engine already")
        centroid, radius = centroid_and_radius(polygon)
        velocity = (float(velocity_m_s[0]), float(velocity_m_s[1]))
        self._entering[piece_id] = _Entering(
            polygon, float(thickness_m), velocity, float(angular_velocity_rad_s), pinned, centroid, radius
        )

    def _materialize(self) -> None:
        """The bodies of the pieces added since the last call, in the order they were added."""
        entering, self._entering = self._entering, {}
        for piece_id, entry in entering.items():
            self._enter(piece_id, entry)

    def _enter(self, piece_id: int, entry: _Entering) -> None:
        geometry = body_geometry(entry.polygon)
        piece = _Piece(geometry, entry.thickness_m, self.settings)
        piece.body.position = geometry.centroid_xy_m
        piece.body.velocity = entry.velocity_m_s
        piece.body.angular_velocity = entry.angular_velocity_rad_s
        self.space.add(piece.body, *piece.shapes)
        self._pieces[piece_id] = piece
        self._by_body[piece.body] = piece_id
        self._rows = self._values = self._state = None
        if entry.pinned:
            self.set_pinned(piece_id, True)
        else:
            self._set_awake(piece, self._in_window(piece, self.window()))

    def remove_piece(self, piece_id: int) -> PieceState:
        """Remove a piece (broken, or leaving); returns its last state."""
        state = self.state(piece_id)
        if self._entering.pop(piece_id, None) is not None:
            return state
        piece = self._pieces.pop(piece_id)
        del self._by_body[piece.body]
        self._release(piece_id)
        self.space.remove(piece.body, *piece.shapes)
        self._rows = self._values = self._state = None
        return state

    def set_pinned(self, piece_id: int, pinned: bool) -> None:
        """Pin a piece (static: no motion, zero velocity) or release it."""
        self._materialize()
        piece = self._pieces[piece_id]
        piece.pinned = pinned
        self._rows = None
        self._set_awake(piece, not pinned and self._in_window(piece, self.window()))

    def hold_against_hull(
        self, piece_id: int, force_n: tuple[float, float], point_xy_m: tuple[float, float]
    ) -> None:
        """A plastic hull contact until `release_holds`: the hull pushes the piece at a field-frame point
        along F̂ with at most |F|, and never faster than the hull itself closes in along F̂ (the crushed
        ice does not bounce); the piece may move away freely. A Chipmunk slide joint from a hull anchor
        `_HOLD_REACH_M` behind the point along −F̂ to the point on the piece, its minimum length just
        above the present one (active from the first step), `max_force` = |F|, no position correction
        (`max_bias` 0: the overlap is crushed ice, not an error). Solved with the ice–ice contacts, so a
        piece jammed against others takes the whole force and a free one exactly the hull's speed,
        whatever the step. Nothing for a piece that is not awake."""
        self._materialize()
        piece = self._pieces[piece_id]
        force = math.hypot(force_n[0], force_n[1])
        if not piece.awake or force == 0.0:
            return
        px, py = float(point_xy_m[0]), float(point_xy_m[1])
        ax, ay = px - _HOLD_REACH_M * force_n[0] / force, py - _HOLD_REACH_M * force_n[1] / force
        joint = pymunk.SlideJoint(
            self.hull,
            piece.body,
            self.hull.world_to_local((ax, ay)),
            piece.body.world_to_local((px, py)),
            math.hypot(px - ax, py - ay) * (1.0 + 1e-12),
            math.inf,
        )
        joint.max_force, joint.max_bias = force, 0.0
        self.space.add(joint)
        self._holds.setdefault(piece_id, []).append(joint)
        self._held_rows = None
        self._hold_impulses.setdefault(piece_id, []).append(0.0)

    def hold_impulses(self) -> dict[int, list[tuple[float, float]]]:
        """Each hull contact of `hold_against_hull` in place now, by piece, in the order made: (|F| it was
        given [N], impulse it passed on since it was made [N·s], the sum of pymunk's `Constraint.impulse`
        after each step). Below |F|·(time held), the piece moved away and took less than |F|."""
        return {
            pid: [(j.max_force, impulse) for j, impulse in zip(joints, self._hold_impulses[pid], strict=True)]
            for pid, joints in self._holds.items()
        }

    def release_holds(self) -> None:
        """End every hull contact of `hold_against_hull`."""
        for piece_id in list(self._holds):
            self._release(piece_id)

    def _release(self, piece_id: int) -> None:
        joints = self._holds.pop(piece_id, ())
        self._hold_impulses.pop(piece_id, None)
        if joints:
            self.space.remove(*joints)
            self._held_rows = None

    def piece_ids(self) -> list[int]:
        self._materialize()
        return list(self._pieces)

    def awake_ids(self) -> list[int]:
        self._materialize()
        return [pid for pid, piece in self._pieces.items() if piece.awake]

    def mass_kg(self, piece_id: int) -> float:
        """The effective (with added mass) mass of a piece."""
        self._materialize()
        return self._pieces[piece_id].mass_kg

    def moment_kg_m2(self, piece_id: int) -> float:
        """The effective (with added inertia) moment of inertia of a piece about its centroid."""
        self._materialize()
        return self._pieces[piece_id].moment_kg_m2

    def state(self, piece_id: int) -> PieceState:
        entry = self._entering.get(piece_id)
        if entry is not None:  # as its body will start
            (x, y), (vx, vy), r = entry.centroid_xy_m, entry.velocity_m_s, entry.radius_m
            window = self.window()
            awake = not entry.pinned and x + r >= window[0] and x - r <= window[2]
            awake = awake and y + r >= window[1] and y - r <= window[3]
            return PieceState(piece_id, x, y, 0.0, vx, vy, entry.angular_velocity_rad_s, awake, entry.pinned)
        piece = self._pieces[piece_id]
        body = piece.body
        return PieceState(
            piece_id,
            float(body.position.x),
            float(body.position.y),
            float(body.angle),
            float(body.velocity.x),
            float(body.velocity.y),
            float(body.angular_velocity),
            piece.awake,
            piece.pinned,
        )

    def velocity_at(self, piece_id: int, point_xy_m: tuple[float, float]) -> tuple[float, float]:
        """The rigid-body velocity of a piece at a field-frame point, v + ω ẑ × (p − c) (a child's velocity
        at its centroid when the piece breaks)."""
        s = self.state(piece_id)
        rx, ry = point_xy_m[0] - s.x_m, point_xy_m[1] - s.y_m
        w = s.angular_velocity_rad_s
        return float(s.vx_m_s - w * ry), float(s.vy_m_s + w * rx)

    def pose(self, piece_id: int) -> tuple[float, float, float]:
        """(x, y, angle) of a piece's centroid and rotation now."""
        rows, state = self._current()
        x, y, angle = state[rows.row_of_id[piece_id], :3].tolist()
        return x, y, angle

    def changed_poses(self) -> tuple[list[int], np.ndarray]:
        """The pieces whose pose changed since the last call (since they entered, the first time), by id,
        and their poses (n, 3) now: the outlines to re-store. Pieces that did not move are not read."""
        rows, state = self._current()
        changed = np.flatnonzero((state[:, :3] != rows.reported).any(axis=1))
        rows.reported[changed] = state[changed, :3]
        ids = [rows.ids[i] for i in changed.tolist()]
        for i in changed.tolist():
            rows.pieces[i].reported = tuple(rows.reported[i].tolist())
        return ids, state[changed, :3]

    def polygon(self, piece_id: int) -> shapely.Polygon:
        """The piece's outline now, field frame (its ring rotated by the angle and moved to the centroid)."""
        return self.polygons([piece_id])[0]

    def polygons(self, piece_ids: list[int]) -> list[shapely.Polygon]:
        """The outlines of several pieces now (as `polygon`), built in one pass."""
        if not piece_ids:
            return []
        rows, state = self._current()
        return _outlines(
            [self._pieces[pid] for pid in piece_ids], state[[rows.row_of_id[pid] for pid in piece_ids], :3]
        )

    def boxes(self, piece_ids: list[int]) -> np.ndarray:
        """The bounding boxes (n, 4: x0, y0, x1, y1) of the outlines `polygons` would build, without
        building them: the same vertices, so the same numbers as their `shapely.bounds`."""
        if not piece_ids:
            return np.zeros((0, 4))
        rows, state = self._current()
        pieces = [self._pieces[pid] for pid in piece_ids]
        x, y, sizes = _outline_vertices(pieces, state[[rows.row_of_id[pid] for pid in piece_ids], :3])
        starts = np.cumsum([0, *sizes[:-1]])
        lows = np.column_stack([np.minimum.reduceat(x, starts), np.minimum.reduceat(y, starts)])
        highs = np.column_stack([np.maximum.reduceat(x, starts), np.maximum.reduceat(y, starts)])
        return np.hstack([lows, highs])

    def hull_impulses(self) -> dict[int, tuple[float, float]]:
        """Impulse of the hull on each piece during the last step [N·s], field frame; the ship receives the
        opposite. Divided by the step: the mean contact force."""
        return dict(self._impulses)

    def drain_retired(self) -> list[PieceState]:
        """The last states of the pieces retired (behind the window) since the last call."""
        retired, self._retired = self._retired, []
        return retired

    def drain_retired_outlines(self) -> dict[int, shapely.Polygon]:
        """The last outlines (field frame) of the pieces retired since the last call, by id."""
        outlines, self._retired_outlines = self._retired_outlines, {}
        return outlines

    # --- stepping ------------------------------------------------------------------------------------
    def step(self, dt_s: float | None = None) -> None:
        """Advance by `dt_s` (default `settings.time_step_s`): water and applied forces, contacts, window."""
        dt = self.settings.time_step_s if dt_s is None else float(dt_s)
        if (self._hull_speed_m_s, dt) != self._checked:  # the hull's speed changes only by a setter
            self.settings.check_time_step(self._hull_speed_m_s, dt)
            self._checked = (self._hull_speed_m_s, dt)
        self._impulses = {}
        rows, values = self._read()
        self._load(rows, values, dt)
        self.space.step(dt)
        for pid, joints in self._holds.items():
            passed = self._hold_impulses[pid]
            for k, joint in enumerate(joints):
                passed[k] += joint.impulse
        self._values = self._state = None
        self.time_s += dt
        self._update_window()

    def _read(self) -> tuple[_Rows, np.ndarray]:
        """The rows and every body's (x, y, angle, vx, vy, ω) in Chipmunk's order (the hull among them),
        read in one batch call if stale; `_body_of_row` maps the rows to it."""
        if self._entering:
            self._materialize()
        if self._rows is None:
            self._rows, self._values, self._held_rows = _Rows.of(self._pieces), None, None
            self._read_order = (np.zeros(0, np.uintp),) * 3
        if self._values is None:
            rows = self._rows
            self._buffer.clear()
            pymunk.batch.get_space_bodies(self.space, _READ_FIELDS, self._buffer)
            body_ids = np.frombuffer(self._buffer.int_buf(), dtype=np.uintp)
            if not np.array_equal(body_ids, self._read_order[0]):  # bodies in another order: map again
                self._map(rows, body_ids)
            self._values = np.frombuffer(self._buffer.float_buf(), dtype=np.float64).reshape(-1, 6).copy()
            self._state = None
        return self._rows, self._values

    def _map(self, rows: _Rows, body_ids: np.ndarray) -> None:
        """Where the rows sit among the bodies read (`body_ids`, in Chipmunk's order), and a force buffer
        in that order whose entries other than the rows' (the hull's) stay zero."""
        k = np.minimum(np.searchsorted(rows.body_ids, body_ids), max(len(rows.ids) - 1, 0))
        ours = rows.body_ids[k] == body_ids if len(rows.ids) else np.zeros(len(body_ids), bool)
        self._read_order = (body_ids.copy(), np.flatnonzero(ours), rows.row_of_body[k[ours]])
        self._body_of_row = np.empty(len(rows.ids), dtype=np.int64)
        self._body_of_row[self._read_order[2]] = self._read_order[1]
        self._force_values = np.zeros((len(body_ids), 3))
        self._force_buffer.set_float_buf(self._force_values.reshape(-1))

    def _current(self) -> tuple[_Rows, np.ndarray]:
        """The rows and every body's state now, by row (`_read`)."""
        rows, values = self._read()
        if self._state is None:
            self._state = values[self._body_of_row]
        return rows, self._state

    def _held(self, rows: _Rows) -> np.ndarray:
        """By row, whether the hull holds the piece (`hold_against_hull`); kept until a hold or row
        changes."""
        if self._held_rows is None:
            self._held_rows = np.zeros(len(rows.ids), dtype=bool)
            self._held_rows[[rows.row_of_id[pid] for pid in self._holds]] = True
        return self._held_rows

    def _load(self, rows: _Rows, values: np.ndarray, dt: float) -> None:
        """The water forces on the moving pieces (all rows in one compiled pass, written into the force
        buffer in Chipmunk's order and set in one batch call) and the rest speed's stop (not for pieces the
        hull holds). Pieces at rest (static ones among them) take no water force."""
        if not rows.ids:
            return
        status, stopped, moving = water_loads_into(
            self._force_values,
            self._body_of_row,
            rows.drag,
            values,
            rows.radius_m,
            self._held(rows),
            rows.last_speed_m_s,
            self.settings.rest_speed_m_s,
            dt,
            self.settings.water_density_kg_m3,
        )
        if stopped:
            for i in np.flatnonzero(status == 1).tolist():
                body = rows.pieces[i].body
                body.velocity, body.angular_velocity = (0.0, 0.0), 0.0
        if self.water and moving:  # water pulls nothing at rest; Chipmunk zeroes forces after each step
            pymunk.batch.set_space_bodies(self.space, _FORCE_FIELDS, self._force_buffer)

    def _update_window(self) -> None:
        """Wake, freeze or retire the pieces whose box (centroid ± largest radius, all rows at once) crossed
        the window's edges; the others are not touched."""
        rows, values = self._read()
        at = self._body_of_row
        changes = _window_changes(values, at, rows.radius_m, rows.awake, rows.pinned, *self.window())
        for i, change in changes.tolist():
            pid, piece = rows.ids[i], rows.pieces[i]
            if change == _RETIRE:
                self._retired_outlines[pid] = _outlines([piece], values[at[i] : at[i] + 1, :3])[0]
                self._retired.append(self.remove_piece(pid))
            else:
                self._set_awake(piece, change == _WAKE)

    def _in_window(self, piece: _Piece, window: tuple[float, float, float, float]) -> bool:
        x0, y0, x1, y1 = piece.box()
        return x1 >= window[0] and x0 <= window[2] and y1 >= window[1] and y0 <= window[3]

    def _set_awake(self, piece: _Piece, awake: bool) -> None:
        """Dynamic inside the window; static (frozen, at rest) outside it or when pinned."""
        piece.awake = awake
        if not awake:
            self._release(self._by_body[piece.body])
        if self._rows is not None:
            self._rows.awake[self._rows.row_of_id[self._by_body[piece.body]]] = awake
        body = piece.body
        wanted = pymunk.Body.DYNAMIC if awake else pymunk.Body.STATIC
        if body.body_type == wanted:
            return
        if not awake:
            body.velocity = (0.0, 0.0)
            body.angular_velocity = 0.0
        body.body_type = wanted
        if awake:  # Chipmunk recomputes the mass from the shapes (massless here): set ours again
            body.mass = piece.mass_kg
            body.moment = piece.moment_kg_m2
        self._values = self._state = None
        self.space.reindex_shapes_for_body(body)

    # --- contact callbacks ---------------------------------------------------------------------------
    def _hull_contact_values(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data) -> None:
        arbiter.friction = self.settings.ice_hull_friction

    def _record_hull_impulse(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data) -> None:
        pid = self._by_body.get(arbiter.shapes[1].body)
        if pid is None:
            return
        jx, jy = -arbiter.total_impulse  # total_impulse is the one on the first shape (the hull)
        old = self._impulses.get(pid, (0.0, 0.0))
        self._impulses[pid] = (old[0] + jx, old[1] + jy)


def _hull_shape_elasticity(settings: IceMotionSettings) -> float:
    """The hull shapes' elasticity e_ih/√e_ii, so that its product with an ice shape's √e_ii is e_ih."""
    if settings.ice_hull_restitution == 0.0:
        return 0.0
    return settings.ice_hull_restitution / math.sqrt(settings.ice_ice_restitution)


_RETIRE, _WAKE, _FREEZE = 0, 1, 2


@numba.njit(cache=True, nogil=True)
def _window_changes(values, at, radius, awake, pinned, x0, y0, x1, y1):
    """(row, change) of the pieces whose box (centroid ± largest radius) is wholly behind the window
    (retire), or crossed its front or sides (wake, freeze: not for pinned pieces), in row order; row i's
    state is values[at[i]]."""
    out = []
    for i in range(len(radius)):
        x, y, r = values[at[i], 0], values[at[i], 1], radius[i]
        if x + r < x0:
            out.append((i, _RETIRE))
        elif not pinned[i]:
            inside = x - r <= x1 and y - r <= y1 and y + r >= y0
            if inside != awake[i]:
                out.append((i, _WAKE if inside else _FREEZE))
    result = np.empty((len(out), 2), dtype=np.int64)
    for k in range(len(out)):
        result[k, 0], result[k, 1] = out[k]
    return result


def compile_now() -> None:
    """Compile the engine's kernels (or load them from numba's cache) ahead of a run."""
    _compile_water()
    _compile_bodies()
    one = np.ones(1)
    _window_changes(np.zeros((1, 6)), np.zeros(1, np.int64), one, one > 0, one < 0, -1.0, -1.0, 1.0, 1.0)


def _outline_vertices(pieces: list[_Piece], poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """The vertices (x, y) of the pieces' outlines at `poses` (n, 3: x, y, angle), field frame, one piece
    after the other, and each piece's count: each body-frame ring rotated by its angle and moved to its
    centroid."""
    rings = [p.geometry.ring_xy_m for p in pieces]
    sizes = [len(r) for r in rings]
    ring = np.concatenate(rings)
    cos_sin = np.array([(math.cos(a), math.sin(a)) for a in poses[:, 2].tolist()]).reshape(-1, 2)
    per_vertex = np.repeat(np.column_stack([poses[:, :2], cos_sin]), sizes, axis=0)
    px, py, c, s = per_vertex.T
    return px + c * ring[:, 0] - s * ring[:, 1], py + s * ring[:, 0] + c * ring[:, 1], sizes


def _outlines(pieces: list[_Piece], poses: np.ndarray) -> list[shapely.Polygon]:
    """The pieces' outlines at `poses` (`_outline_vertices`) as polygons, built in one pass."""
    x, y, sizes = _outline_vertices(pieces, poses)
    owner = np.repeat(np.arange(len(pieces)), sizes)
    return list(shapely.polygons(shapely.linearrings(np.column_stack([x, y]), indices=owner)))


def body_geometry_parts(polygon: shapely.Polygon) -> tuple[np.ndarray, ...]:
    """The convex parts of a polygon in its own (field) frame: the hull's collision shapes."""
    geometry = body_geometry(polygon)
    return tuple(part + np.array(geometry.centroid_xy_m) for part in geometry.convex_parts)
