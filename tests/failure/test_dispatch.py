"""Which mode handles a classified floe (thesis Alg. 2, §4.3, §4.4): the policy of `failure.dispatch`."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

import pytest

from floebreak.errors import InputError
from floebreak.failure import (
    DirectRotation,
    FailureModel,
    Fate,
    NewPiece,
    Outcome,
    Status,
    complete_policy,
    resolve_failure,
)


@dataclass(frozen=True)
class Scripted:
    """A stand-in mode that returns a fixed status and counts its calls."""

    name: ClassVar[str] = "scripted"
    mode: str
    status: Status
    calls: list  # shared by the modes of a test: the order in which they were asked

    def evaluate(self, inp, ctx) -> Outcome:
        self.calls.append(self.mode)
        pieces = (NewPiece(inp.polygon, Fate.FLOE),) if self.status is Status.FAILED else ()
        return Outcome(self.mode, self.status, pieces)


def model_with(statuses: dict[str, Status], flip: bool = True) -> tuple[FailureModel, list]:
    """The default policy with scripted bending, local cracking and cracking, and the real rotation."""
    calls: list = []
    modes = {name: Scripted(name, status, calls) for name, status in statuses.items()}
    policy = complete_policy(flip_uncracked_at_shoulder=flip)
    return FailureModel({**modes, "rotation": DirectRotation()}, policy), calls


ALL_PASS = dict.fromkeys(("bending", "local_cracking", "cracking"), Status.PASS_ON)


def floe(make_input, kit, failure_class: str, region: str):
    # a box at the midbody is in contact at the "shoulder" region; the region is set explicitly here
    inp = make_input(kit.midbody_box(20.0, 40.0, 0.1))
    return replace(
        inp, classification=replace(inp.classification, failure_class=failure_class), region=region
    )


def test_a_floe_within_the_breaking_radius_goes_on_to_cracking(make_input, kit, context):
    model, calls = model_with({**ALL_PASS, "cracking": Status.FAILED})
    for region, first in (("stem", "bending"), ("shoulder", "local_cracking")):
        calls.clear()
        outcome = resolve_failure(model, floe(make_input, kit, "bending", region), context)
        assert (outcome.mode, outcome.status, calls) == ("cracking", Status.FAILED, [first, "cracking"])


def test_bending_that_merely_holds_does_not_fall_through_to_cracking(make_input, kit, context):
    model, calls = model_with({**ALL_PASS, "bending": Status.INTACT, "local_cracking": Status.INTACT})
    for region, first in (("stem", "bending"), ("shoulder", "local_cracking")):
        calls.clear()
        outcome = resolve_failure(model, floe(make_input, kit, "bending", region), context)
        assert (outcome.mode, outcome.status, calls) == (first, Status.INTACT, [first])


@pytest.mark.parametrize("failure_class", ["bending", "cracking"])
def test_no_crack_at_the_shoulder_flips_the_floe_and_at_the_stem_leaves_it(
    make_input, kit, context, failure_class
):
    # thesis §4.4, second case: a floe whose crack cannot start at the aft part of the bow is rotated aside
    model, _ = model_with(ALL_PASS)
    shoulder = resolve_failure(model, floe(make_input, kit, failure_class, "shoulder"), context)
    assert shoulder.mode == "rotation" and [p.fate for p in shoulder.pieces] == [Fate.FLIPPED]
    stem = resolve_failure(model, floe(make_input, kit, failure_class, "stem"), context)
    assert (stem.mode, stem.failed) == ("cracking", False)
    unflipped, _ = model_with(ALL_PASS, flip=False)
    assert not resolve_failure(unflipped, floe(make_input, kit, failure_class, "shoulder"), context).failed


def test_unbreakable_floes_become_cusps_without_asking_other_modes(make_input, kit, context):
    model, calls = model_with(dict.fromkeys(("bending", "local_cracking", "cracking"), Status.FAILED))
    outcome = resolve_failure(model, floe(make_input, kit, "unbreakable", "stem"), context)
    assert [p.fate for p in outcome.pieces] == [Fate.CUSP] and calls == []


def test_a_stated_policy_replaces_the_default_for_its_class(make_input, kit, context):
    # no local cracking: bending at the shoulder too
    calls: list = []
    modes = {name: Scripted(name, Status.INTACT, calls) for name in ("bending", "local_cracking", "cracking")}
    policy = complete_policy({"bending": {"shoulder": ("bending",)}})
    model = FailureModel({**modes, "rotation": DirectRotation()}, policy)
    resolve_failure(model, floe(make_input, kit, "bending", "shoulder"), context)
    resolve_failure(model, floe(make_input, kit, "bending", "stem"), context)
    assert calls == ["bending", "bending"]


@pytest.mark.parametrize(
    ("policy", "key"),
    [
        ({"bending": {"shoulder": ("toy",)}}, "failure.policy.bending.shoulder"),
        ({"bending": {"shoulder": ()}}, "failure.policy.bending.shoulder"),
        ({"crushing": {"stem": ("rotation",)}}, "failure.policy.crushing"),
        ({"cracking": {"bow": ("rotation",)}}, "failure.policy.cracking.bow"),
    ],
)
def test_a_policy_must_name_known_modes_classes_and_regions(policy, key):
    modes = {"bending": None, "local_cracking": None, "cracking": None, "rotation": DirectRotation()}
    with pytest.raises(InputError) as info:
        FailureModel(modes, complete_policy(policy))
    assert info.value.field == key
