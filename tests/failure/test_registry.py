"""A failure mode that plugs in from outside the package: defined here, registered through the
public API, selected by name in a scenario and run through `floebreak.run` — no package file touched.
docs/architecture.md ("Failure modes") shows this code."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
import shapely

import floebreak
from floebreak.errors import InputError
from floebreak.failure import Fate, NewPiece, Outcome, Status


@dataclass(frozen=True)
class HalvingSettings:
    min_area_m2: float = 1.0
    """floes larger than this are halved [m²]"""


@dataclass(frozen=True)
class Halving:
    """A toy mode: cut the floe in two across its bounding box (bow frame), or pass it on."""

    name: ClassVar[str] = "halving"
    settings: HalvingSettings = HalvingSettings()

    def evaluate(self, inp, ctx) -> Outcome:
        if inp.polygon.area <= self.settings.min_area_m2:
            return Outcome(self.name, Status.PASS_ON)
        x0, y0, x1, y1 = inp.polygon.bounds
        middle = 0.5 * (x0 + x1)
        halves = [shapely.box(x0 - 1, y0 - 1, middle, y1 + 1), shapely.box(middle, y0 - 1, x1 + 1, y1 + 1)]
        pieces = [NewPiece(shapely.intersection(inp.polygon, half), Fate.FLOE) for half in halves]
        return Outcome(self.name, Status.FAILED, tuple(pieces))


SCENARIO = """
[field]
floes = [{ x_m = 20.0, y_m = 0.0, diameter_m = 10.0 }]

[ice]
thickness_m = 1.0

[ship]
step_m = 0.5

[failure.policy]
bending = ["halving"]
cracking = ["halving"]

[failure.halving]
min_area_m2 = 2.0
"""


@pytest.fixture
def halving():
    with floebreak.registered_mode(Halving, settings=HalvingSettings) as spec:
        yield spec
    assert "halving" not in floebreak.mode_names()  # nothing leaks into other tests


def scenario(text: str = SCENARIO) -> floebreak.Scenario:
    return floebreak.Scenario.from_toml_text(text)


def test_a_registered_mode_runs_when_the_scenario_names_it(halving):
    result = floebreak.run(scenario())
    # the toy mode broke the floe; every other floe piece came from it
    assert result.simulation.breaks_by_mode.get("halving", 0) > 0
    assert set(result.simulation.breaks_by_mode) <= {"halving", "rotation"}
    cusps = result.cusps
    assert len(cusps["area_m2"]) > 1
    chains = [result.simulation.failure_chain(int(i)) for i in cusps["piece_id"]]  # from the parent ids
    assert all(chain[0] == "halving" for chain in chains)
    # halving continues until a piece is unbreakable (thesis Eq. 5: A ≤ 1 m × 13.5 h^(3/4) = 13.5 m² at
    # h = 1 m, then rotated into a cusp) or passed on (≤ min_area_m2 = 2 m²)
    assert np.all(cusps["area_m2"] <= 13.5 + 1e-9)


def test_the_mode_reads_its_table(halving):
    # halving nothing: every floe larger than 1e6 m² — the mode passes the floe on and nothing breaks
    text = SCENARIO.replace("min_area_m2 = 2.0", "min_area_m2 = 1e6")
    assert floebreak.run(scenario(text)).simulation.breaks_by_mode == {}
    assert scenario().failure.mode_tables() == {"halving": {"min_area_m2": 2.0}}
    # the same through the profiles: built with its settings when the policy names it, else not at all
    policy = {"cracking": ["halving"]}
    modes = {"halving": {"min_area_m2": 5.0}}
    failure = floebreak.build_model(modes=modes, failure={"policy": policy}).failure
    assert failure.modes["halving"] == Halving(HalvingSettings(min_area_m2=5.0))
    assert "halving" not in floebreak.build_model().failure.modes


def test_the_table_is_validated_against_the_settings(halving):
    with pytest.raises(InputError) as info:
        scenario(SCENARIO.replace("min_area_m2 = 2.0", "min_area = 2.0"))
    assert info.value.field == "failure.halving.min_area" and "min_area_m2" in str(info.value)
    with pytest.raises(InputError) as info:
        scenario(SCENARIO.replace("min_area_m2 = 2.0", "min_area_m2 = 'large'"))
    assert info.value.field == "failure.halving.min_area_m2"


def test_an_unregistered_mode_is_an_unknown_name():
    with pytest.raises(InputError) as info:
        scenario(SCENARIO.replace("[failure.halving]\nmin_area_m2 = 2.0\n", ""))
    assert info.value.field == "failure.policy.bending" and "halving" in str(info.value)
    with pytest.raises(InputError) as info:
        scenario()
    assert info.value.field == "failure.halving"


def test_a_name_is_registered_once(halving):
    with pytest.raises(ValueError, match="halving"):
        floebreak.register_mode(Halving)
    with pytest.raises(ValueError, match="policy"):
        floebreak.register_mode(type("Policy", (Halving,), {"name": "policy"}))


def test_the_architecture_doc_shows_this_code():
    doc = (Path(__file__).resolve().parents[2] / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = re.search(r"```python\n(.*?)```", doc[doc.index("## Failure modes") :], re.S).group(1)
    this_file = Path(__file__).read_text(encoding="utf-8")
    # the mode, its settings and the scenario are this file's, character for character
    start, end = "@dataclass(frozen=True)\nclass HalvingSettings", 'min_area_m2 = 2.0\n"""\n'
    assert block[block.index(start) : block.index(end) + len(end)] in this_file
    assert "floebreak.registered_mode(Halving, settings=HalvingSettings)" in block


@dataclass(frozen=True)
class NoDefault:
    min_area_m2: float


def test_a_registration_is_checked_against_the_settings():
    with pytest.raises(TypeError, match="min_area_m2"):
        floebreak.register_mode(Halving, settings=NoDefault)  # a scenario could not leave it out
    with pytest.raises(ValueError, match="area_m2"):
        floebreak.register_mode(Halving, settings=HalvingSettings, thesis={"area_m2": 3.0})
    with pytest.raises(TypeError, match="failure mode"):
        floebreak.register_mode(HalvingSettings)  # no name, no evaluate
    assert "halving" not in floebreak.mode_names()
