"""The warning a propeller analysis gives when its loads are zero for want of cusps: the runs produced none
(moving ice pushed aside by a slow ship, a hull-contact model that breaks nothing), or the transport sent
none of them to a propeller (and where it sent them). Zero loads are then not a result but an absence."""

from __future__ import annotations

NO_CUSPS = "no cusps produced"
NONE_REACHED = "no cusp reached a propeller"


def no_load_reason(n_cusps: int, transport_info: dict) -> str | None:
    """Why no cusp loads a propeller (`NO_CUSPS` or `NONE_REACHED`), or None if some do (or the fraction
    reaching is the user's override)."""
    if n_cusps == 0:
        return NO_CUSPS
    if "n_reaching" in transport_info and transport_info["n_reaching"] == 0:
        return NONE_REACHED
    return None


def no_load_warning(n_cusps: int, transport_info: dict) -> str | None:
    """The summary's and the terminal's warning for `no_load_reason`, with the transport's paths."""
    reason = no_load_reason(n_cusps, transport_info)
    if reason == NO_CUSPS:
        return (
            f"{NO_CUSPS}: the run(s) broke no cusp, so every propeller load, rate and design value is zero "
            "for want of ice, not a result (moving ice pushed aside by a slow ship, or a hull-contact model "
            "that broke nothing)"
        )
    if reason == NONE_REACHED:
        paths = transport_info.get("paths", {})
        where = ", ".join(f"{count} {name}" for name, count in paths.items() if count)
        return (
            f"{NONE_REACHED}: of {n_cusps} cusps the transport sent {where or 'none anywhere'}, so every "
            "propeller load is zero for want of cusps, not a result"
        )
    return None
