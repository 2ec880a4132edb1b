"""Zero propeller loads for want of cusps are said, with the reason: no cusps produced, or none reached a
propeller (with where the transport sent them)."""

from __future__ import annotations

from floebreak.propeller.reach_warnings import NO_CUSPS, NONE_REACHED, no_load_reason, no_load_warning

PATHS = {"propeller": 0, "shoulder": 7, "bilge": 3, "missed": 0}


def test_no_cusps_produced():
    assert no_load_reason(0, {}) == NO_CUSPS
    assert no_load_warning(0, {}).startswith("no cusps produced: the run(s) broke no cusp")


def test_no_cusp_reached_names_the_paths():
    info = {"n_reaching": 0, "paths": PATHS}
    assert no_load_reason(10, info) == NONE_REACHED
    text = no_load_warning(10, info)
    assert text.startswith("no cusp reached a propeller: of 10 cusps the transport sent 7 shoulder, 3 bilge")


def test_no_warning_when_some_reach_or_the_fraction_is_given():
    assert no_load_warning(10, {"n_reaching": 2, "paths": {**PATHS, "propeller": 2}}) is None
    assert no_load_warning(10, {"fraction_reaching": 0.3}) is None  # an override: no transport counts
