"""The stepping engine (thesis §3.2, Figs. 3–4): the bow advances in fixed steps through a floe field.

Each step: find the floes near the bow with a spatial index (cost grows with the floes near the bow, not
with the field size), evaluate contact for each, classify, let the failure mode act, and re-classify new
pieces in contact at the same bow position until nothing more fails. Pieces leave the field as cusps or
flipped floes; everything else remains. The loop does no I/O: it reports through callbacks (events).

A failure happens at the step's bow position (``event_location = "step_end"``, thesis §3.2) or, with
``"root"``, at the bow position located between two steps (`floebreak.engine.events`): then the step only
sets how often contacts are searched.

Initial ice area = cusps + flipped + remaining is checked at the end of every run.
"""

from __future__ import annotations

import hashlib
import time
from array import array
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Literal

import numpy as np
import shapely

from floebreak import constants as c
from floebreak.engine.events import EVENT_LOCATIONS, EVENT_TOLERANCE_M, locate_step
from floebreak.engine.motion import IceMotion, check_ice_motion, create_ice_motion
from floebreak.errors import InputError, require_range
from floebreak.failure import (
    FailureContext,
    FailureInput,
    FailureModel,
    Fate,
    Outcome,
    bow_region,
    resolve_failure,
)
from floebreak.failure.base import polygon_parts
from floebreak.ice.budget import check_transit_length
from floebreak.ice.field import FloeField
from floebreak.ice.generation import GENERATORS
from floebreak.mechanics.classify import Classification, ClassificationParams, classify
from floebreak.mechanics.contact import (
    BowContactGeometry,
    Contact,
    ContactParams,
    evaluate_contacts,
)
from floebreak.mechanics.polygon_kernel import advance_to_contact, ring_arrays

AREA_BALANCE_TOLERANCE = 1e-9  # relative; breaks split polygons with GEOS overlay (exact up to rounding)
# A piece found out of contact is not evaluated again until the bow has advanced to where its outline could
# first touch the hull (`polygon_kernel.advance_to_contact`), less this margin [m] against rounding; pieces
# closer than the clearance [m] are evaluated every step.
QUIET_MARGIN_M = 1e-6
QUIET_CLEARANCE_M = 1e-9
# Every piece a run creates (initial floes, broken, transient) costs memory until the run ends: ≈ 1.2 kB per
# piece in a long transit (its polygon, as WKB once finished, its numbers, its share of the row groups
# written; benchmarks/README.md, memory), so a million pieces stay within ≈ 1.2 GB. A 100 km × 200 m transit
# of the reference ice makes ≈ 0.34 million; runaway breaking of very thin ice is stopped.
MAX_PIECES_DEFAULT = 1_000_000
# Wall-clock guard (`SimulationParams.max_wall_s`): by default a run may take this much time plus this much
# per km of transit. Measured runs take 1–10 s per km (a 100 km transit 300–990 s, benchmarks/README.md),
# so the default is ≥ 6 × the slowest and stops only a runaway (ice breaking without end at one place, a
# transit of empty water millions of steps long).
WALL_S_BASE = 600.0
WALL_S_PER_KM = 60.0


class AreaBalanceError(RuntimeError):
    """Initial ice area ≠ cusps + flipped + remaining: a bug, never a user error."""


class PieceBudgetError(InputError):
    """The run would create more pieces than `SimulationParams.max_pieces` (memory guard; a user choice)."""

    def __init__(self, max_pieces: int, bow_x_m: float, thickness_m: float):
        super().__init__(
            "simulation.max_pieces",
            f"the ice breaks into more than {max_pieces:,} pieces (bow at x = {bow_x_m:.2f} m; a floe "
            f"{thickness_m:g} m thick is breaking; thin ice breaks into many small pieces, and each piece "
            "is kept in memory until the run ends)",
            value=max_pieces,
            allowed="raise simulation.max_pieces, or use a shorter field or thicker ice",
        )


class WallTimeError(InputError):
    """The run took longer than `SimulationParams.max_wall_s` (runaway guard; a user choice)."""

    def __init__(self, limit_s: float, bow_x_m: float, n_pieces: int, n_cusps: int):
        super().__init__(
            "simulation.max_wall_s",
            f"the run took more than {limit_s:g} s of wall time and was stopped (bow at x = {bow_x_m:.2f} m, "
            f"{n_pieces:,} pieces, {n_cusps:,} cusps so far; ice that keeps breaking at one place, or a long "
            "transit through open water, can run without end)",
            value=limit_s,
            allowed="raise simulation.max_wall_s, or use a shorter field, a coarser ship.step_m or "
            "thicker ice",
        )


@dataclass(frozen=True)
class SimulationParams:
    """Stepping parameters (thesis §3.2). Positions: upper-waterline stem tip, in the field frame."""

    step_m: float = 0.25
    x_start_m: float = 0.0
    x_end_m: float | None = None  # default: until the whole modelled hull has passed the field
    dist_bow_max_m: float = c.DIST_BOW_MAX_M
    initial_contact: Literal["shift_field", "shift_floes"] = "shift_field"
    initial_clearance_m: float = 1e-3
    max_evaluations_per_floe_step: int = 256  # guard against endless re-breaking at one position
    max_pieces: int = MAX_PIECES_DEFAULT  # memory guard: `PieceBudgetError` beyond this many pieces
    # time guard: `WallTimeError` beyond this many seconds, checked at every step and every evaluation;
    # None: WALL_S_BASE + WALL_S_PER_KM per km of transit
    max_wall_s: float | None = None
    # where a failure happens between two contact searches (`floebreak.engine.events`): at the search
    # position ("step_end", thesis §3.2) or located to within `event_tolerance_m` ("root")
    event_location: Literal["step_end", "root"] = "step_end"
    event_tolerance_m: float = EVENT_TOLERANCE_M
    # how the ice moves (`floebreak.engine.motion.dynamic`, docs/model.md "Ice motion"): never ("static", the
    # thesis) or as rigid bodies pushed by the hull ("dynamic", with `ice_motion_settings`, an
    # `IceMotionSettings`, and the hull moving at `speed_m_s`)
    ice_motion: str = "static"  # a name of `floebreak.engine.motion.ice_motion_names()`
    ice_motion_settings: Any = None
    speed_m_s: float = c.SHIP_SPEED_IN_ICE_M_S
    # under "dynamic": a `floebreak.ship.propulsion.Propulsion`, whose surge sets the hull's speed per search
    # interval (`engine.motion.dynamic`; docs/model.md "Ship surge"); None: the constant `speed_m_s`
    propulsion: Any = None

    def __post_init__(self) -> None:
        if self.max_wall_s is not None:
            require_range("simulation.max_wall_s", self.max_wall_s, low=0.0, unit="s")
        require_range("ship.step_m", self.step_m, low=0.0, unit="m")
        require_range("simulation.dist_bow_max_m", self.dist_bow_max_m, low=0.0, low_inclusive=True, unit="m")
        if self.x_end_m is not None and not self.x_end_m > self.x_start_m:
            raise InputError(
                "simulation.x_end_m",
                f"{self.x_end_m:g} m is not after x_start_m = {self.x_start_m:g} m",
                allowed=f"> {self.x_start_m:g} m",
            )
        if self.event_location not in EVENT_LOCATIONS:
            raise InputError(
                "simulation.event_location", repr(self.event_location), allowed=", ".join(EVENT_LOCATIONS)
            )
        require_range("simulation.event_tolerance_m", self.event_tolerance_m, low=0.0, unit="m")
        check_ice_motion(self.ice_motion)
        if self.ice_motion == "dynamic":
            require_range("ship.speed_m_s", self.speed_m_s, low=0.0, unit="m/s")
            if self.event_location != "step_end":
                raise InputError(
                    "simulation.ice_motion",
                    "'dynamic' with simulation.event_location = 'root': located events would re-advance "
                    "the ice motion between contact searches, which is not implemented yet",
                    value="dynamic",
                    allowed="simulation.ice_motion = static, or simulation.event_location = step_end",
                )
        if self.initial_contact not in ("shift_field", "shift_floes"):
            raise InputError(
                "simulation.initial_contact", repr(self.initial_contact), allowed="shift_field, shift_floes"
            )


@dataclass(frozen=True)
class Model:
    """The physics of a run: contact, classification and failure modes."""

    contact: ContactParams = field(default_factory=ContactParams)
    classification: ClassificationParams = field(default_factory=ClassificationParams)
    failure: FailureModel = field(default_factory=FailureModel)

    def fingerprint(self) -> str:
        """SHA-256 of every setting (the frozen dataclasses' repr). A scenario's runs agree only under one
        fingerprint: a resumed study re-runs a run whose model changed although its scenario did not (a
        profile's value changed by an upgrade, say; `floebreak.studies.runner.is_complete`)."""
        return hashlib.sha256(repr(self).encode("utf-8")).hexdigest()


# --- events reported to callbacks ---------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RunStarted:
    n_steps: int
    x_start_m: float
    x_end_m: float
    step_m: float
    n_floes: int
    field_shift_m: float


@dataclass(frozen=True, eq=False)
class ContactEvaluated:
    """One evaluation of a floe in contact (one row per floe–panel pair in the contact records)."""

    step: int
    bow_x_m: float
    piece_id: int
    parent_floe_id: int
    thickness_m: float
    contact: Contact  # bow frame
    classification: Classification
    outcome: Outcome


@dataclass(frozen=True, eq=False)
class StepDone:
    step: int
    bow_x_m: float
    n_candidates: int
    n_cusps: int
    n_flipped: int
    # the run's ice motion where pieces move (`IceMotion.moves`), to be read, not changed (the pieces' poses,
    # recorded by `floebreak.output.pose_file`); None for static ice
    ice_motion: IceMotion | None = None


Event = RunStarted | ContactEvaluated | StepDone
Callback = Callable[[Event], None]


# --- result ------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Every piece that existed in the run, with its fate, plus counters and the area balance.

    ``fate`` is one of "remaining" (still in the field at the end), "cusp", "flipped" or "broken"
    (replaced by its children). ``step``/``bow_x_m`` are those of the piece's creation (initial floes:
    −1 / NaN) or, for cusps and flipped pieces, of the moment they left the field.
    """

    field: FloeField  # the initial field as simulated (after any shift for initial contact)
    bow: Any
    model: Model
    params: SimulationParams
    x_end_m: float
    n_steps: int
    piece_id: np.ndarray
    # each piece's polygon: a shapely geometry, or its WKB for a piece the run finished with (see `_Pieces`);
    # `polygon` / `polygons` give geometries; empty for a transient piece (created and broken in one step:
    # at one bow position, or between two contact searches with located events)
    stored_polygon: np.ndarray
    piece_bounds_m: np.ndarray  # (n, 4) bounds of each piece (NaN for an empty one) [m]
    piece_area_m2: np.ndarray  # every piece's area, transient ones included
    thickness_m: np.ndarray
    parent_floe_id: np.ndarray
    parent_piece_id: np.ndarray
    ended_by: np.ndarray  # mode that broke the piece or took it out whole; "" if none (see `failure_chain`)
    fate: np.ndarray
    step: np.ndarray
    bow_x_m: np.ndarray
    n_contacts: int
    n_breaks: int
    breaks_by_mode: Mapping[str, int]
    # under "dynamic" (`engine.motion.dynamic`): per step, the mean force the hull passed to the ice over the
    # interval ending there, (n_steps, 2) [N], field frame (x: the ice resistance); None for static ice
    hull_force_on_ice_xy_n: np.ndarray | None = None
    # under "dynamic" with `params.propulsion`: the `floebreak.ship.surge.SurgeResult` of the loop
    surge: Any = None

    def mask(self, fate: str) -> np.ndarray:
        return self.fate == fate

    def polygons(self, index: Any = slice(None)) -> np.ndarray:
        """The polygons of the pieces `index` selects (numpy indexing) as shapely geometries."""
        stored = np.asarray(self.stored_polygon[index], dtype=object).reshape(-1)
        encoded = np.fromiter((type(g) is bytes for g in stored), dtype=bool, count=len(stored))
        if encoded.any():
            stored = stored.copy()
            stored[encoded] = shapely.from_wkb(stored[encoded])
        return stored

    @cached_property
    def polygon(self) -> np.ndarray:
        """Every piece's polygon (field frame) as a shapely geometry; a long run's pieces are held once more
        while this result lives: `polygons` gives a selection."""
        return self.polygons()

    def failure_chain(self, piece: int) -> tuple[str, ...]:
        """The failure modes from the initial floe to `piece`: the mode that broke each ancestor, then the
        mode that ended `piece` (broke it or took it out whole), if one did. Rebuilt from the parent ids:
        lineage is stored once (``parent_piece_id``, ``ended_by``), not as a per-piece history whose length
        grows with the number of breaks (thin ice: thousands of entries per cusp)."""
        return lineage_chain(piece, self.parent_piece_id, self.ended_by)

    @cached_property
    def failure_mode(self) -> np.ndarray:
        """Per piece, the last entry of its failure chain ("" for an initial floe never touched)."""
        return last_failure_mode(self.parent_piece_id, self.ended_by)

    def area_m2(self, fate: str) -> float:
        return float(self.piece_area_m2[self.mask(fate)].sum())  # each = shapely.area of its polygon

    @property
    def initial_ice_area_m2(self) -> float:
        return self.field.ice_area_m2

    @property
    def area_balance_rel_error(self) -> float:
        """|initial − (cusps + flipped + remaining)| / initial."""
        initial = self.initial_ice_area_m2
        final = self.area_m2("cusp") + self.area_m2("flipped") + self.area_m2("remaining")
        return abs(initial - final) / initial if initial > 0 else 0.0


def lineage_chain(piece: int, parent_piece_id, ended_by) -> tuple[str, ...]:
    """The failure chain of `piece` from the lineage columns (see `SimulationResult.failure_chain`)."""
    chain = [ended_by[piece]] if ended_by[piece] else []
    parent = int(parent_piece_id[piece])
    while parent >= 0:
        chain.append(ended_by[parent])
        parent = int(parent_piece_id[parent])
    return tuple(reversed(chain))


def last_failure_mode(parent_piece_id: np.ndarray, ended_by: np.ndarray) -> np.ndarray:
    """Per piece, the last entry of its failure chain: the mode that ended it, else the mode that broke its
    parent ("" for an initial floe that nothing ended)."""
    parents = np.asarray(parent_piece_id, dtype=np.int64)
    own = np.asarray(ended_by, dtype=object)
    last = own.copy()
    inherit = (own == "") & (parents >= 0)
    last[inherit] = own[parents[inherit]]
    return last


# --- the engine --------------------------------------------------------------------------------------


class _Pieces:
    """Mutable piece table of one run (internal).

    The bow only advances in +x, so candidates come from a sweep: initial floes sorted by their minimum x
    enter the active set when the search box reaches them (only those whose y-range meets the box's fixed
    y-range ever can), pieces created later enter it at birth, and pieces the hull has passed, or that left
    the field, drop out. Each step costs O(active pieces), i.e. grows with the ice near the bow, not with the
    field size.
    """

    def __init__(self, floe_field: FloeField, y_range: tuple[float, float], max_pieces: int):
        n = floe_field.n_floes
        self.max_pieces = max_pieces
        if n > max_pieces:
            raise InputError(
                "simulation.max_pieces",
                f"the field has {n:,} floes, more than the budget of {max_pieces:,} pieces",
                allowed="raise simulation.max_pieces, or use a smaller field",
            )
        # numbers in typed arrays (8 bytes a value, not a list slot and an object: a long transit makes
        # ≈ 3 400 pieces per km)
        self.n_floes = n
        self.polygon: list[shapely.Geometry | bytes] = list(floe_field.polygons)
        self.area = array("d", floe_field.area_m2.tolist())
        self.thickness = array("d", floe_field.thickness_m.tolist())
        self.parent_floe = array("q", floe_field.floe_id.tolist())
        self.parent_piece = array("q", [-1] * n)
        self.ended_by: list[str] = [""] * n
        self.crack_count = array("q", [0] * n)
        self.fate: list[str] = ["remaining"] * n
        self.step = array("q", [-1] * n)
        self.bow_x = array("d", [float("nan")] * n)
        self.quiet_until = array("d", [-np.inf] * n)  # bow x [m] before which a piece cannot touch the hull
        bounds = shapely.bounds(floe_field.polygons).reshape(-1, 4)
        self.bounds = array("d", bounds.ravel().tolist())  # 4 a piece
        in_band = (bounds[:, 1] <= y_range[1]) & (bounds[:, 3] >= y_range[0])
        order = np.flatnonzero(in_band)
        order = order[np.argsort(bounds[order, 0], kind="stable")]
        self._waiting = [(tuple(bounds[i].tolist()), int(i)) for i in order.tolist()]  # by minimum x
        self._next_waiting = 0
        self.active: dict[int, tuple[float, float, float, float]] = {}
        self.on_enter = None  # called with a floe's id as the sweep takes it in (moving ice: its outline)

    def add(self, polygon, thickness, parent: int, crack_count: int, step: int, bow_x: float) -> int:
        pid = len(self.polygon)
        if pid >= self.max_pieces:
            raise PieceBudgetError(self.max_pieces, bow_x, thickness)
        self.polygon.append(polygon)
        self.area.append(float(shapely.area(polygon)))
        self.thickness.append(thickness)
        self.parent_floe.append(self.parent_floe[parent])
        self.parent_piece.append(parent)
        self.ended_by.append("")
        self.crack_count.append(crack_count)
        self.fate.append("remaining")
        self.step.append(step)
        self.bow_x.append(bow_x)
        self.quiet_until.append(-np.inf)
        bounds = tuple(shapely.bounds(polygon).tolist())
        self.bounds.extend(bounds)
        self.active[pid] = bounds
        return pid

    def retire(self, pid: int, fate: str, step: int, bow_x: float) -> None:
        self.fate[pid] = fate
        self.active.pop(pid, None)
        if fate == "broken" and self.step[pid] == step:  # transient (initial floes have step −1)
            self.polygon[pid] = _EMPTY
        else:
            self._finish(pid)
        if fate != "broken":
            self.step[pid] = step
            self.bow_x[pid] = bow_x

    def candidates(self, box: tuple[float, float, float, float]) -> list[int]:
        x0, y0, x1, y1 = box
        waiting = self._waiting
        while self._next_waiting < len(waiting) and waiting[self._next_waiting][0][0] <= x1:
            pid = waiting[self._next_waiting][1]
            if self.on_enter is not None:
                self.on_enter(pid)
            self.active[pid] = tuple(self.bounds[4 * pid : 4 * pid + 4])  # moving ice: its current box
            self._next_waiting += 1
        return sorted(
            pid for pid, (a, b, cc, d) in self.active.items() if a <= x1 and cc >= x0 and b <= y1 and d >= y0
        )

    def due(self, pids: list[int], box: tuple[float, float, float, float], bow_x: float) -> list[int]:
        """The pieces among `pids` whose bounding box overlaps `box` with positive area and that may touch
        the hull at `bow_x` (same order)."""
        x0, y0, x1, y1 = box
        active, quiet_until = self.active, self.quiet_until
        return [pid for pid in pids if quiet_until[pid] <= bow_x and _overlaps(active[pid], x0, y0, x1, y1)]

    def prune_behind(self, x_min: float) -> None:
        for pid in [pid for pid, bounds in self.active.items() if bounds[2] < x_min]:
            del self.active[pid]
            self._finish(pid)

    def _finish(self, pid: int) -> None:
        """A piece the run will not touch again (broken, gone, or passed by the hull) keeps its polygon as
        WKB, ≈ half the memory of a GEOS geometry: a long transit makes ≈ 2 400 such pieces per km. Initial
        floes are the field's own polygons, held by the field anyway."""
        if pid >= self.n_floes and type(self.polygon[pid]) is not bytes:
            self.polygon[pid] = shapely.to_wkb(self.polygon[pid], output_dimension=2)


_EMPTY = shapely.Polygon()


def _object_array(items: list) -> np.ndarray:
    """`items` as a 1-d object array (``np.array`` would try to nest bytes and geometries)."""
    out = np.empty(len(items), dtype=object)
    out[:] = items
    return out


def _overlaps(bounds: tuple[float, float, float, float], x0: float, y0: float, x1: float, y1: float) -> bool:
    a, b, cc, d = bounds
    return a < x1 and cc > x0 and b < y1 and d > y0


def _translate(geometry, dx: float):
    return shapely.transform(geometry, lambda xy: xy + np.array([dx, 0.0]))


def _translate_pieces(polygons: np.ndarray, dx: float, check: np.ndarray | None = None) -> np.ndarray:
    """Pieces moved between the field and the bow frame, each a valid polygon.

    The translation rounds every coordinate; a valid but nearly degenerate piece (a thin crescent between
    two bending arcs whose ends cross within rounding) can come out self-intersecting, and GEOS overlays on
    an invalid polygon raise or, worse, return wrong areas. Such a piece is replaced by the largest part of
    its repair: what is dropped is the tiny loop of the self-intersection, of rounding size. The repair
    re-nodes the outline (``make_valid`` "linework"): the "structure" method rebuilds the area from the ring's
    orientation, which for a crescent 0.7 mm wide crossed at one end kept 1e-16 of its 1e-3 m² (an
    AreaBalanceError of 1.9e-8). Costs `is_valid` per piece, ≈ 10 µs, so only the pieces flagged in `check`
    are looked at (default all): a generated floe is far from degenerate.
    """
    moved = _translate(polygons, dx)
    looked_at = np.arange(len(moved)) if check is None else np.flatnonzero(check)
    if looked_at.size == 0:
        return moved
    invalid = looked_at[~shapely.is_valid(moved[looked_at])]
    for i in invalid.tolist():
        repaired = _repaired_parts(moved[i])
        if repaired:
            moved[i] = max(repaired, key=shapely.area)
    return moved


def _repaired_parts(polygon) -> list:
    """The valid polygons of an outline that a translation made self-intersecting, re-noded by ``make_valid``
    "linework" (see `_translate_pieces` for why not "structure")."""
    return polygon_parts(shapely.make_valid(polygon, method="linework"))


def _into_field(polygon_bf, bow_x: float) -> list[tuple[Any, Any]]:
    """A new piece moved from the bow frame into the field, as [(field polygon, bow-frame polygon)]: one pair,
    or, if the move made it invalid, one per part of its repair.

    The translation rounds every coordinate, and a valid piece with a pinch (two lobes joined by a neck of
    rounding width) can come out self-intersecting. Its repair (`_repaired_parts`) separates the lobes;
    each becomes a piece of its own, so no area is lost (keeping the largest part only broke the area
    balance; regression test in tests/test_simulation.py). A valid move (the usual case) keeps the piece's
    own bow-frame polygon."""
    world = _translate(polygon_bf, bow_x)
    if shapely.is_valid(world):
        return [(world, polygon_bf)]
    parts = _repaired_parts(world)
    return list(zip(parts, _translate_pieces(np.array(parts, dtype=object), -bow_x), strict=True))


def clear_initial_contact(
    floe_field: FloeField, hull_upper: shapely.Polygon, x_start_m: float, mode: str, clearance_m: float
) -> tuple[FloeField, float]:
    """Shift the field (or only the touching floes) forward until no floe touches the bow at x_start.

    Returns the new field and the field shift applied [m] (0 for "shift_floes"); shifts are recorded in the
    field metadata. Thesis §3.2 / Table 2: no initial contact between bow and ice.
    """
    hull = _translate(hull_upper, x_start_m)
    shapely.prepare(hull)
    touching = np.flatnonzero(shapely.intersects(hull, floe_field.polygons))
    if touching.size == 0:
        return floe_field, 0.0

    def needed_shift(polygon) -> float:
        high = 1.0
        while shapely.intersects(hull, _translate(polygon, high)):
            high *= 2.0
        low = 0.0
        while high - low > 1e-4:
            mid = 0.5 * (low + high)
            low, high = (mid, high) if shapely.intersects(hull, _translate(polygon, mid)) else (low, mid)
        return high + clearance_m

    if mode == "shift_field":
        shift = max(needed_shift(floe_field.polygons[i]) for i in touching)
        return floe_field.shifted(shift, reason="no initial contact with the bow (thesis §3.2)"), shift
    polygons = floe_field.polygons.copy()
    moved = []
    for i in touching:
        dx = needed_shift(polygons[i])
        polygons[i] = _translate(polygons[i], dx)
        moved.append({"floe_id": int(floe_field.floe_id[i]), "dx_m": dx})
    metadata = {**floe_field.metadata, "floes_shifted_m": moved}
    return replace(floe_field, polygons=polygons, metadata=metadata), 0.0


def simulate(
    floe_field: FloeField,
    bow,
    model: Model | None = None,
    params: SimulationParams | None = None,
    callbacks: Iterable[Callback] = (),
) -> SimulationResult:
    """Run the bow through `floe_field` and return every piece with its fate (thesis Fig. 4).

    `bow` is a `floebreak.ship.bow.Bow` (bow frame: upper stem tip at the origin at x_start = 0).
    """
    model = model or Model()
    params = params or SimulationParams()
    floe_field, shift = clear_initial_contact(
        floe_field, bow.hull_upper, params.x_start_m, params.initial_contact, params.initial_clearance_m
    )
    run = _Run(floe_field, bow, model, params, tuple(callbacks))
    run.emit(RunStarted(run.n_steps, params.x_start_m, run.x_end, params.step_m, floe_field.n_floes, shift))
    for step in range(run.n_steps):
        run.advance(step)
        if run.motion.stuck:
            break
    result = run.result()
    if result.area_balance_rel_error > AREA_BALANCE_TOLERANCE:
        raise AreaBalanceError(
            f"ice area not conserved: relative error {result.area_balance_rel_error:.3e} "
            f"> {AREA_BALANCE_TOLERANCE:g} (initial {result.initial_ice_area_m2:.6f} m²)"
        )
    return result


def require_floes_in_path(
    floe_field: FloeField,
    hull_box: tuple[float, float, float, float],
    x_start_m: float,
    dist_bow_max_m: float,
) -> None:
    """InputError (key ``field``) when the field has floes but none reaches into the lane the bow sweeps
    (the y-range of the hull's bounding box widened by `dist_bow_max_m`, ahead of the hull's aft end at
    `x_start_m`): such a run would step through open water and break nothing — typically a file in other
    coordinates (UTM-like eastings and northings of 10⁶–10⁷ m) than the field frame (the bow's stem tip at
    the origin at the start). Floes beyond an explicit `x_end_m` are the user's choice, not refused."""
    if floe_field.n_floes == 0:
        return
    x0, y0, _, y1 = hull_box
    lane = (x_start_m + x0 - dist_bow_max_m, y0 - dist_bow_max_m, y1 + dist_bow_max_m)
    bounds = shapely.bounds(floe_field.polygons).reshape(-1, 4)
    if np.any((bounds[:, 2] >= lane[0]) & (bounds[:, 1] <= lane[2]) & (bounds[:, 3] >= lane[1])):
        return
    source = floe_field.metadata.get("source_file")
    name = "the field" if source is None else repr(str(source))
    fx0, fy0 = np.nanmin(bounds[:, 0]), np.nanmin(bounds[:, 1])
    fx1, fy1 = np.nanmax(bounds[:, 2]), np.nanmax(bounds[:, 3])
    raise InputError(
        "field",
        f"no floe of {name} lies in the bow's path: its {floe_field.n_floes:,} floes span x ∈ [{fx0:.6g}, "
        f"{fx1:.6g}] m, y ∈ [{fy0:.6g}, {fy1:.6g}] m; the bow sweeps y ∈ [{lane[1]:.6g}, {lane[2]:.6g}] m "
        f"from x = {lane[0]:.6g} m forward (field frame: the bow's stem tip at the origin at the start, x "
        "forward, y to port)",
        allowed="floes in the field frame: move the field (subtract its origin), or set ship.x_start_m",
    )


def _transit_end_m(floe_field: FloeField, params: SimulationParams, hull_x0: float) -> float:
    """Stem position of the last step: `x_end_m`, or where the aft end of the modelled hull has passed the
    field (thesis §3.2)."""
    if params.x_end_m is not None:
        return params.x_end_m
    field_x_max = floe_field.domain_m[2]
    if floe_field.n_floes:
        field_x_max = max(field_x_max, float(shapely.total_bounds(floe_field.polygons)[2]))
    return field_x_max - hull_x0


class _Run:
    """One transit, step by step as the thesis' Fig. 4: advance the bow, gather the pieces near it, and for
    each piece in contact: contact → classification → failure → new pieces, re-evaluated at the same bow
    position (internal; `simulate` is the entry point)."""

    def __init__(self, floe_field: FloeField, bow, model: Model, params: SimulationParams, callbacks):
        self.field, self.bow, self.model, self.params, self.callbacks = (
            floe_field,
            bow,
            model,
            params,
            callbacks,
        )
        self.geometry = BowContactGeometry.from_bow(bow)
        self.hull_box = tuple(shapely.bounds(bow.hull_upper).tolist())
        self.x_end = _transit_end_m(floe_field, params, self.hull_box[0])
        self.n_steps = int(np.floor((self.x_end - params.x_start_m) / params.step_m + 1e-9)) + 1
        d = params.dist_bow_max_m
        require_floes_in_path(floe_field, self.hull_box, params.x_start_m, d)
        given_end = params.x_end_m is not None
        source = floe_field.metadata.get("source_file")
        check_transit_length(
            floe_field.polygons, floe_field.domain_m, source, params.x_start_m, self.x_end, given_end
        )
        self.pieces = _Pieces(floe_field, (self.hull_box[1] - d, self.hull_box[3] + d), params.max_pieces)
        transit_km = max(self.x_end - params.x_start_m, 0.0) / 1000.0
        self.max_wall_s = (
            params.max_wall_s if params.max_wall_s is not None else WALL_S_BASE + WALL_S_PER_KM * transit_km
        )
        self.deadline = time.monotonic() + self.max_wall_s
        self.context = FailureContext(bow=bow, bow_geometry=self.geometry)
        self.bow_length = float(getattr(bow, "length_bow_m", -self.hull_box[0]))
        self.counters = {"contacts": 0, "breaks": 0, "cusps": 0, "flipped": 0}
        self.breaks_by_mode: dict[str, int] = {}
        # broken pieces may be nearly degenerate, and so may floes that no generator of ours made (a file,
        # inline floes): those are checked after every translation (`_translate_pieces`); generated ones not
        self.check_floes = floe_field.metadata.get("generator") not in GENERATORS
        # event_location = "root": the margins of the pieces judged intact at the last contact search, by
        # piece id, as (bow x, margin): where the next search's brackets start (`engine.events`)
        self.search_margins: dict[int, tuple[float, float | None]] = {}
        self.motion: IceMotion = create_ice_motion(params.ice_motion, self)

    def emit(self, event: Event) -> None:
        for callback in self.callbacks:
            callback(event)

    def check_time(self, bow_x: float) -> None:
        """Stop a runaway: `WallTimeError` once the run has taken more than its wall-time budget."""
        if time.monotonic() > self.deadline:
            raise WallTimeError(self.max_wall_s, bow_x, len(self.pieces.polygon), self.counters["cusps"])

    # --- one step: the bow at x_start + step·Δx ------------------------------------------------------
    def advance(self, step: int) -> None:
        bow_x = self.params.x_start_m + step * self.params.step_m
        self.check_time(bow_x)
        self.motion.advance_to(bow_x)
        if self.motion.stuck:  # the ship stopped before reaching this search: the transit ends
            self.n_steps = step
            return
        x0, y0, x1, y1 = self.hull_box
        d = self.params.dist_bow_max_m
        candidates = self.pieces.candidates((bow_x + x0 - d, y0 - d, bow_x + x1 + d, y1 + d))
        # only pieces whose box overlaps the hull's box can share area with it, and a piece found out of
        # contact cannot touch the hull before the bow reaches its `quiet_until`: the others have no contact
        # (neither path counts an overlap of zero area), so they are neither translated nor evaluated
        touching = self.pieces.due(candidates, (bow_x + x0, y0, bow_x + x1, y1), bow_x)
        if touching and self.motion.moves:
            self.motion.flush(touching)  # moved pieces' outlines, kept as boxes until they may touch
            touching = self._apart_after_moving(touching, bow_x)
        if touching and self.params.event_location == "root":
            x_before = max(bow_x - self.params.step_m, self.params.x_start_m)
            locate_step(self, step, x_before, bow_x, touching, len(candidates) - len(touching))
        elif touching:
            self._evaluate_queue(step, bow_x, touching, len(candidates) - len(touching))
        self.pieces.prune_behind(bow_x + x0 - d)
        counters = self.counters
        motion = self.motion if self.motion.moves else None
        self.emit(StepDone(step, bow_x, len(candidates), counters["cusps"], counters["flipped"], motion))

    def _apart_after_moving(self, pids: list[int], bow_x: float) -> list[int]:
        """Moving ice: of `pids`, the pieces whose skip moving reset (`quiet_until` −∞) and that were not in
        contact at the last search get it again now, as an out-of-contact evaluation would set it (`quiet`
        on the same bow-frame polygon; a hull that stays apart makes no contact zone); those it puts beyond
        `bow_x` are not evaluated. Most moved pieces near the hull drift beside it."""
        quiet, last_contact = self.pieces.quiet_until, self.motion.last_contact_x_m
        recent = bow_x - 1.5 * self.params.step_m  # pieces in contact since are likely in contact still
        moved = [pid for pid in pids if quiet[pid] == -np.inf and last_contact.get(pid, -np.inf) < recent]
        if not moved or self.geometry.hull_rings is None:
            return pids
        for pid, polygon_bf in zip(moved, self.bow_frame(moved, bow_x), strict=True):
            self.quiet(pid, polygon_bf, bow_x)
        return [pid for pid in pids if quiet[pid] <= bow_x]

    def _evaluate_queue(self, step: int, bow_x: float, touching: list[int], evaluations: int) -> None:
        """Evaluate the pieces in contact, then the new pieces of their breaks, until nothing more fails.

        Contact is evaluated in batches (vectorised GEOS calls): the floes queued at the start of the step,
        then, whenever the queue reaches pieces not evaluated yet, all pieces queued by then. A piece's
        contact depends only on its own polygon and the bow position: batching changes nothing.
        `evaluations` starts at the candidates not in contact (the guard counts every candidate).
        """
        pieces = self.pieces
        in_field = np.array([pieces.polygon[i] for i in touching], dtype=object)
        check = (np.array(touching) >= self.field.n_floes) | self.check_floes
        queue = deque(zip(touching, _translate_pieces(in_field, -bow_x, check), strict=True))
        batch: deque[Contact] = deque()
        while queue:
            if not batch:
                polygons = np.array([poly for _, poly in queue], dtype=object)
                thickness = [pieces.thickness[pid] for pid, _ in queue]
                batch.extend(evaluate_contacts(polygons, thickness, self.geometry, self.model.contact))
            pid, polygon_bf = queue.popleft()
            evaluations += 1
            self.check_time(bow_x)
            children = self._evaluate_piece(step, bow_x, pid, polygon_bf, batch.popleft())
            if evaluations < self.params.max_evaluations_per_floe_step:
                queue.extend(children)

    def bow_frame(self, pids: list[int], bow_x: float) -> np.ndarray:
        """The pieces `pids` moved into the bow frame at `bow_x` (checked as in `_translate_pieces`)."""
        in_field = np.array([self.pieces.polygon[i] for i in pids], dtype=object)
        check = (np.array(pids) >= self.field.n_floes) | self.check_floes
        return _translate_pieces(in_field, -bow_x, check)

    def contacts(self, pids: list[int], polygons_bf) -> list[Contact]:
        """The contacts of the pieces `pids` (bow-frame polygons `polygons_bf`, one vectorised call)."""
        thickness = [self.pieces.thickness[pid] for pid in pids]
        return evaluate_contacts(
            np.array(polygons_bf, dtype=object), thickness, self.geometry, self.model.contact
        )

    # --- one piece: contact → classification → failure (thesis Fig. 4, inner loop) ---------------------
    def _evaluate_piece(self, step: int, bow_x: float, pid: int, polygon_bf, contact: Contact) -> list:
        """Classify a piece, let the failure mode act, apply the outcome; the new floe pieces to evaluate
        at this bow position, as (piece id, bow-frame polygon)."""
        if not contact.in_contact:
            self.quiet(pid, polygon_bf, bow_x)
            return []
        judged = self.judge(pid, polygon_bf, contact)
        return self.apply(step, bow_x, pid, contact, judged)

    def judge(self, pid: int, polygon_bf, contact: Contact) -> tuple[Classification, Outcome]:
        """Classification and failure outcome of a piece in contact (pure: nothing is applied)."""
        thickness = self.pieces.thickness[pid]
        contact = self.motion.failure_contact(pid, contact)  # the force the piece can take
        zone = contact.dominant
        classification = classify(
            polygon_bf,
            thickness,
            zone.centre_normal,
            self.model.classification,
            zone.floe_extent_m,
            contact.floe_area_m2,
        )
        region = bow_region(
            float(zone.centre_xy_m[0]), self.bow_length, self.model.failure.shoulder_region_start
        )
        inp = FailureInput(
            polygon_bf, thickness, self.pieces.crack_count[pid], classification, contact, zone, region
        )
        return classification, resolve_failure(self.model.failure, inp, self.context)

    def apply(self, step: int, bow_x: float, pid: int, contact: Contact, judged) -> list:
        """Report a judged evaluation and apply its outcome at `bow_x`; the new floe pieces (see
        `_evaluate_piece`)."""
        classification, outcome = judged
        thickness = self.pieces.thickness[pid]
        self.counters["contacts"] += 1
        parent_floe = self.pieces.parent_floe[pid]
        self.emit(
            ContactEvaluated(step, bow_x, pid, parent_floe, thickness, contact, classification, outcome)
        )
        self.motion.contact(pid, contact, bow_x)
        if not outcome.failed:
            return []
        self.breaks_by_mode[outcome.mode] = self.breaks_by_mode.get(outcome.mode, 0) + 1
        if len(outcome.pieces) == 1 and outcome.pieces[0].fate != Fate.FLOE:
            self._leave_whole(pid, outcome, step, bow_x)
            return []
        return self._break(pid, outcome, thickness, step, bow_x)

    def quiet(self, pid: int, polygon_bf, bow_x: float) -> None:
        """Out of contact: skip the piece until the bow could first touch it."""
        hull_rings = self.geometry.hull_rings
        if hull_rings is not None:
            advance = advance_to_contact(*ring_arrays(polygon_bf), *hull_rings, QUIET_CLEARANCE_M)
            self.pieces.quiet_until[pid] = bow_x + advance - QUIET_MARGIN_M

    def _leave_whole(self, pid: int, outcome: Outcome, step: int, bow_x: float) -> None:
        """The piece leaves the field whole (direct rotation) as a cusp or flipped floe."""
        fate = str(outcome.pieces[0].fate)
        self.pieces.ended_by[pid] = outcome.mode
        self.pieces.retire(pid, fate, step, bow_x)
        self.counters["cusps" if fate == "cusp" else "flipped"] += 1
        self.motion.leave(pid)

    def _break(self, pid: int, outcome: Outcome, thickness: float, step: int, bow_x: float) -> list:
        """Replace the piece by its children: cusps and flipped pieces leave, floes stay (returned)."""
        pieces = self.pieces
        self.counters["breaks"] += 1
        pieces.retire(pid, "broken", step, bow_x)
        pieces.ended_by[pid] = outcome.mode
        stay = []
        for new in outcome.pieces:
            for child_world, child_bf in _into_field(new.polygon, bow_x):
                child = pieces.add(child_world, thickness, pid, new.crack_count, step, bow_x)
                if new.fate == Fate.FLOE:
                    stay.append((child, child_bf))
                else:
                    pieces.retire(child, str(new.fate), step, bow_x)
                    self.counters["cusps" if new.fate == Fate.CUSP else "flipped"] += 1
        self.motion.broken(pid, [child for child, _ in stay])
        return stay

    def result(self) -> SimulationResult:
        self.motion.flush()
        pieces = self.pieces
        return SimulationResult(
            field=self.field,
            bow=self.bow,
            model=self.model,
            params=self.params,
            x_end_m=float(self.x_end),
            n_steps=self.n_steps,
            piece_id=np.arange(len(pieces.polygon)),
            stored_polygon=_object_array(pieces.polygon),
            piece_bounds_m=np.array(pieces.bounds, dtype=float).reshape(-1, 4),
            piece_area_m2=np.array(pieces.area, dtype=float),
            thickness_m=np.array(pieces.thickness, dtype=float),
            parent_floe_id=np.array(pieces.parent_floe, dtype=np.int64),
            parent_piece_id=np.array(pieces.parent_piece, dtype=np.int64),
            ended_by=np.array(pieces.ended_by, dtype=object),
            fate=np.array(pieces.fate, dtype=object),
            step=np.array(pieces.step, dtype=np.int64),
            bow_x_m=np.array(pieces.bow_x, dtype=float),
            n_contacts=self.counters["contacts"],
            n_breaks=self.counters["breaks"],
            breaks_by_mode=dict(self.breaks_by_mode),
            **self.motion.outputs(self.n_steps),
        )
