"""The failure-mode interface (thesis §3.2, chapter 4).

A failure mode is a small frozen dataclass holding its own settings, with one method::

    evaluate(inp: FailureInput, ctx: FailureContext) -> Outcome

Given the floe (bow frame), its classification and its contact with the bow, it returns an `Outcome` with a
`Status`: the floe failed (new pieces, each with its fate — back into the field as a floe (and
re-classified), a cusp (passes under the hull to the propeller) or flipped (stays beside the hull)), it
stays intact, or the mode passes it on to the next mode of the dispatch policy (`failure.dispatch`). Modes
never raise for physical situations; they return status values, and the engine decides. Modes work in the
bow frame and never see the bow position, files or the clock.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any, ClassVar, Literal, Protocol

import numpy as np
import shapely

from floebreak.mechanics.classify import Classification
from floebreak.mechanics.contact import BowContactGeometry, Contact, ContactZone

BowRegion = Literal["stem", "shoulder"]


class Fate(StrEnum):
    FLOE = "floe"  # stays in the field (re-classified while in contact)
    CUSP = "cusp"  # unbreakable piece in contact: passes under the hull to the propeller
    FLIPPED = "flipped"  # rotated aside by its position at the bow: stays beside the hull


@dataclass(frozen=True, eq=False)
class FailureInput:
    """Everything a mode may look at for one floe at one bow position (bow frame, SI)."""

    polygon: shapely.Polygon
    thickness_m: float
    crack_count: int  # cracks in this piece's ancestry (thesis §4.2.3: later cracks rotate by α_nextcrack)
    classification: Classification
    contact: Contact
    zone: ContactZone  # the zone where failure is evaluated (the dominant one)
    region: BowRegion  # where on the bow the zone centre lies


@dataclass(frozen=True, eq=False)
class FailureContext:
    """The bow, prepared for geometry queries."""

    bow: Any  # floebreak.ship.bow.Bow
    bow_geometry: BowContactGeometry


@dataclass(frozen=True, eq=False)
class NewPiece:
    polygon: shapely.Polygon  # bow frame
    fate: Fate
    crack_count: int = 0


class Status(StrEnum):
    """What a mode did with a floe; the dispatch policy (`failure.dispatch`) reads it."""

    FAILED = "failed"  # the floe broke or left whole: `Outcome.pieces` replace it; the policy stops
    INTACT = "intact"  # the floe withstands this mode (e.g. F_v ≤ P_f in bending); the policy stops
    PASS_ON = "pass_on"  # this mode does not break the floe here: the policy's next mode is tried


@dataclass(frozen=True, eq=False)
class Outcome:
    """What a mode did: its status and, if the floe failed, the pieces that replace it."""

    mode: str
    status: Status
    pieces: tuple[NewPiece, ...] = ()
    # the deciding criterion's margin ln(driving / resistance) (> 0: met), where the mode has one (bending:
    # F_v / P_f, cracking: its criterion's); None otherwise. It decides nothing: located events
    # (`floebreak.engine.events`) use it to place their trial positions (regula falsi)
    margin: float | None = None

    @property
    def failed(self) -> bool:
        return self.status is Status.FAILED


class FailureMode(Protocol):
    name: ClassVar[str]

    def evaluate(self, inp: FailureInput, ctx: FailureContext) -> Outcome: ...


def intact(mode: str, margin: float | None = None) -> Outcome:
    """The floe withstands `mode`: nothing changes and no further mode is tried."""
    return Outcome(mode, Status.INTACT, margin=margin)


def pass_on(mode: str, margin: float | None = None) -> Outcome:
    """`mode` does not break the floe here: the dispatch policy tries its next mode."""
    return Outcome(mode, Status.PASS_ON, margin=margin)


def failed(mode: str, pieces, margin: float | None = None) -> Outcome:
    """The floe failed in `mode` and is replaced by `pieces` (`NewPiece`s)."""
    return Outcome(mode, Status.FAILED, tuple(pieces), margin)


def log_margin(driving: float, resistance: float) -> float | None:
    """ln(driving / resistance), the `Outcome.margin` of a criterion "driving > resistance"; None where it
    has no finite value (a zero or infinite term)."""
    if driving > 0.0 and 0.0 < resistance < float("inf"):
        return float(np.log(driving / resistance))
    return None


MIN_PIECE_AREA_M2 = 1e-6  # split parts at or below this are slivers of the cut, merged into a neighbour


def polygon_parts(geometry) -> list:
    """All polygon parts of a geometry with positive area (points and lines of an overlay are dropped)."""
    if shapely.get_type_id(geometry) == 3:  # one polygon, the usual result of a cut
        return [geometry] if shapely.area(geometry) > 0.0 else []
    parts = shapely.get_parts(geometry)
    return list(parts[(shapely.get_type_id(parts) == 3) & (shapely.area(parts) > 0.0)])


def is_sliver(part, thickness_m: float) -> bool:
    """A split part that is no plate piece: area ≤ `MIN_PIECE_AREA_M2`, or a hydraulic diameter 4A/P below the
    ice thickness (a strip narrower than h/2, a square smaller than h × h). The failure modes are thin-plate
    theory (Nevel's wedge, plane-stress LEFM), which describes pieces much wider than they are thick; a cut
    that runs within half a thickness of a free edge — a bending arc or crack beside an earlier one — leaves a
    sliver of crushed rubble, not an ice floe."""
    area = shapely.area(part)
    return area <= MIN_PIECE_AREA_M2 or 4.0 * area < thickness_m * shapely.length(part)


def split_parts(*sides, thickness_m: float = 0.0) -> tuple[list, ...]:
    """The polygon parts of each side of a split (e.g. F ∩ D and F − D), with slivers merged, not dropped.

    A sliver (`is_sliver`: a cut grazing a corner or a bump, or a strip thinner than the ice) is not a piece
    of ice, but its area must not vanish either (area conservation, thesis §3.2): it is merged into the
    non-sliver part, of either side, with which it shares the longest stretch of boundary. A sliver that
    shares no boundary with any larger part (or whose union would not be one polygon) stays a piece of its
    own. In a split in which every part is a sliver (rubble split again, or any piece of ice thicker than it
    is wide) only the dust is merged: parts of at most `MIN_PIECE_AREA_M2`, whose vertices are rounding
    apart (they would not survive a move as valid polygons). A cut that leaves every piece of ice on one side
    separates nothing: the other sides come back empty and the slivers unmerged — every mode then keeps the
    floe whole, so the parts returned are not pieces (and their areas need not add up).
    """
    parts = [polygon_parts(side) for side in sides]
    if all(is_sliver(p, thickness_m) for side in parts for p in side):
        return _merged(parts, lambda part: shapely.area(part) <= MIN_PIECE_AREA_M2)
    return _merged(parts, lambda part: is_sliver(part, thickness_m))


def _merged(parts: list[list], small) -> tuple[list, ...]:
    """`split_parts` for the parts of each side: each part that is `small` merged into a neighbour."""
    slivers = [(k, p) for k, side in enumerate(parts) for p in side if small(p)]
    if not slivers or len(slivers) == sum(len(side) for side in parts):
        return tuple(parts)
    result = [[p for p in side if not small(p)] for side in parts]
    if sum(1 for side in result if side) == 1:
        # every piece of ice lies on one side: the cut separates nothing, and the modes treat a split with an
        # empty side as no split, so the slivers need not be merged back (that union is the floe itself)
        return tuple(result)
    for side, sliver in slivers:
        owners = [(k, i) for k, ps in enumerate(result) for i in range(len(ps))]
        bigs = np.array([result[k][i] for k, i in owners], dtype=object)
        shared = shapely.length(shapely.intersection(shapely.boundary(bigs), sliver.boundary))
        best = int(np.argmax(shared))
        if shared[best] > 0.0:
            k, i = owners[best]
            merged = shapely.union(result[k][i], sliver)
            if shapely.get_type_id(merged) == 3:
                result[k][i] = merged
                continue
        result[side].append(sliver)
    return tuple(result)
