"""What a scenario profile sets for the analyses of a run (the propeller's load model and transport), kept
apart from the profiles' `Model` so that an analysis resolves it without importing the engine."""

from __future__ import annotations


def propeller_defaults(profile: str | None) -> tuple[str, str]:
    """(load model, transport) of the propeller analysis under a scenario profile: thesis → the FEM tables,
    every cusp reaches; otherwise (default) → the milling model and the kinematic transport model ("flow",
    the cusps followed under the hull, is chosen with `--transport flow` until its sweep is checked)."""
    return ("fem", "all") if profile == "thesis" else ("milling", "hull")
