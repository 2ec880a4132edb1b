"""Ice that does not move (the thesis, §3.2): the explicit "off" variant of `IceMotion`, so that the loop
calls its motion unconditionally."""

from __future__ import annotations

from typing import Any


class StaticIce:
    """No piece moves; the ship keeps its speed; nothing is recorded."""

    moves = False

    def __init__(self, run: Any = None):
        self.last_contact_x_m: dict[int, float] = {}

    @property
    def stuck(self) -> bool:
        return False

    def advance_to(self, bow_x: float) -> None:
        pass

    def flush(self, pids: list[int] | None = None) -> None:
        pass

    def failure_contact(self, pid: int, contact: Any) -> Any:
        return contact

    def contact(self, pid: int, contact: Any, bow_x: float) -> None:
        pass

    def leave(self, pid: int) -> None:
        pass

    def broken(self, pid: int, floe_children: list[int]) -> None:
        pass

    def outputs(self, n_steps: int) -> dict[str, Any]:
        return {}
