"""How the ice moves in the stepping loop, behind one protocol (`IceMotion`). The loop creates the motion of
``simulation.ice_motion`` once per run (`create_ice_motion`) and calls it at fixed points: before a contact
search (`advance_to`), for a piece in contact (`failure_contact`, `contact`), when a piece leaves or breaks,
and at the end (`outputs`). The built-in motions are `static` (the thesis: the ice never moves) and
`dynamic` (rigid bodies pushed by the hull, docs/model.md "Ice motion"); an installed package adds one through
the entry point group ``floebreak.ice_motions`` (``name = "my_pkg.motion:MyMotion"``, a class taking the
run), and a scenario then names it (docs/architecture.md, "Extension points")."""

from __future__ import annotations

import functools
import importlib
from typing import Any, Protocol

from floebreak.errors import InputError

ENTRY_POINT_GROUP = "floebreak.ice_motions"
# name → "module:class" of the built-in motions (a list here, not entry points: a source checkout on the path
# has no installed entry points); the physics engine of "dynamic" is imported only when a run uses it
BUILTIN = {
    "static": "floebreak.engine.motion.static:StaticIce",
    "dynamic": "floebreak.engine.motion.dynamic:DynamicIce",
}


class IceMotion(Protocol):
    """The ice motion of one run, made by its class from the run (`engine.loop._Run`)."""

    moves: bool  # whether pieces move (their poses are then recorded by `output.pose_file.PoseRecorder`)
    last_contact_x_m: dict[int, float]  # bow x of each piece's last contact (pieces that moved only)

    @property
    def stuck(self) -> bool:
        """The ship stopped before the last contact search: the transit ends."""
        ...

    def advance_to(self, bow_x: float) -> None:
        """Move the ice (and the ship) from the last contact search to the bow at `bow_x`."""
        ...

    def flush(self, pids: list[int] | None = None) -> None:
        """Write the moved pieces' outlines (`pids`, or all) back to the run's piece table."""
        ...

    def failure_contact(self, pid: int, contact: Any) -> Any:
        """The contact the failure modes judge: the force the piece can take."""
        ...

    def contact(self, pid: int, contact: Any, bow_x: float) -> None:
        """A piece in contact, judged intact at `bow_x`."""
        ...

    def leave(self, pid: int) -> None:
        """A piece that left the field whole (cusp, flipped)."""
        ...

    def broken(self, pid: int, floe_children: list[int]) -> None:
        """A piece that broke; `floe_children` stay in the field."""
        ...

    def outputs(self, n_steps: int) -> dict[str, Any]:
        """Fields of `SimulationResult` the motion fills (none for ice that does not move)."""
        ...


@functools.cache
def _entry_points() -> dict[str, str]:
    from importlib.metadata import entry_points

    return {point.name: point.value for point in entry_points(group=ENTRY_POINT_GROUP)}


def ice_motion_names() -> tuple[str, ...]:
    """The built-in motions, then those of installed packages."""
    return (*BUILTIN, *(name for name in _entry_points() if name not in BUILTIN))


def check_ice_motion(name: str, key: str = "simulation.ice_motion") -> str:
    """`name` if it is a known motion; else an InputError on `key` listing the known ones."""
    if name not in BUILTIN and name not in _entry_points():
        raise InputError(key, repr(name), value=name, allowed=", ".join(ice_motion_names()))
    return name


def create_ice_motion(name: str, run: Any) -> IceMotion:
    """The motion `name` of one run."""
    module, _, attribute = (BUILTIN.get(name) or _entry_points()[check_ice_motion(name)]).partition(":")
    return getattr(importlib.import_module(module), attribute)(run)
