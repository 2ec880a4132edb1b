"""What a scenario profile sets for the analyses of a run (the propeller's load model and transport), kept
apart from the profiles' `Model` so that an analysis resolves it without importing the engine."""

from __future__ import annotations


def propeller_defaults(profile: str | None) -> tuple[str, str]:
    """(load model, transport) of the propeller analysis under a scenario profile: thesis → the FEM tables,
    every cusp reaches; otherwise (default) → the milling model and the flow transport (the cusps followed
    under the hull; the kinematic transport "hull" is chosen with `--transport hull`)."""
    return ("fem", "all") if profile == "thesis" else ("milling", "flow")
