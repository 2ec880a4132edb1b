"""Failure events located between contact searches (`simulation.event_location = "root"`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from floebreak.config.profiles import build_model
from floebreak.engine.events import locate_event
from floebreak.engine.loop import SimulationParams, simulate
from floebreak.errors import InputError
from floebreak.ice.field import FloeField
from floebreak.ship.hulls import agulhas_ii
from floebreak.studies.single_floe import SingleFloeCase, single_floe_field


def _counting(outcome_at, trials):
    """A trial that records its positions: outcome_at(x) → (evaluation or None, margin)."""

    def trial(x):
        trials.append(x)
        return outcome_at(x)

    return trial


def test_without_margins_the_search_tries_the_lower_end_then_bisects():
    """No margin at either end (rotation of a piece too small to break has no criterion): the first trial
    is τ·0.95 above the lower end (such a piece leaves where it first touches the hull), then bisection."""
    threshold, trials = 0.3141, []
    outcome = lambda x: (("failed at", x) if x >= threshold else None, None)  # noqa: E731
    x, value = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), 0.01)
    assert threshold <= x <= threshold + 0.01
    assert value == ("failed at", x)  # the evaluation of the position returned, not of the bracket's end
    assert trials[0] == pytest.approx(0.0095)
    # then halving the remaining 0.9905 m to 1 cm: ⌈log₂(99.05)⌉ = 7 trials
    assert len(trials) == 1 + math.ceil(math.log2(0.9905 / 0.01))
    again = []  # the trial positions are a function of the bracket alone
    locate_event(0.0, 1.0, None, _counting(outcome, again), 0.01)
    assert again == trials
    at_touch = []
    first_touch = lambda x: (("failed at", x) if x >= 0.002 else None, None)  # noqa: E731
    assert locate_event(0.0, 1.0, None, _counting(first_touch, at_touch), 0.01)[0] == pytest.approx(0.0095)
    assert len(at_touch) == 1


def _square_law_margin(threshold, contact_start):
    """ln(driving/resistance) of a load that grows as the square of the indentation (contact since
    `contact_start`), against a constant resistance, met at `threshold`."""
    return lambda x: 2.0 * math.log((x - contact_start) / (threshold - contact_start))


def test_a_load_growing_as_the_square_of_the_indentation_is_located_in_one_trial():
    """√(driving/resistance) is then straight in the bow position: with the margins of both ends the first
    estimate is exact, the trial τ·0.3 above it fails, and the secant through it and the lower end meets
    zero at the same place: the failure is located with one evaluation (bisection: seven)."""
    threshold, trials = 0.3141, []
    margin = _square_law_margin(threshold, -0.2)

    def outcome(x):
        return ("failed at", x) if margin(x) > 0.0 else None, margin(x)

    ends = margin(1.0), margin(0.0)
    x, value = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), 0.01, *ends)
    assert threshold < x <= threshold + 0.01
    assert value == ("failed at", x)
    assert trials == [pytest.approx(threshold + 0.003)]
    without_lower = []  # no margin at the lower end: a midpoint first
    locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, without_lower), 0.01, margin(1.0))
    assert len(without_lower) <= 4


def test_a_linear_margin_is_located_in_fewer_trials_than_bisection():
    """A margin linear in x (ln(driving/resistance) of a criterion that grows steadily over the bracket)."""
    threshold = 0.3141
    for slope in (2.0, 5.0):
        trials = []

        def outcome(x, slope=slope):
            margin = slope * (x - threshold)
            return ("failed at", x) if margin > 0.0 else None, margin

        ends = slope * (1.0 - threshold), -slope * threshold
        x, value = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), 0.01, *ends)
        assert threshold < x <= threshold + 0.01
        assert value == ("failed at", x)
        assert len(trials) <= 5
        assert all(0.0 < t < 1.0 for t in trials)


@pytest.mark.parametrize("power", [1.0, 1.5, 2.0, 3.0])
@pytest.mark.parametrize("contact_start", [-0.5, -0.05])
def test_a_confirmed_trial_lies_within_the_tolerance_of_the_first_failure(power, contact_start):
    """A load growing as indentation^power (contact since `contact_start`) against a constant resistance:
    √(driving/resistance) is curved unless power = 2, and the more so the closer the contact started.
    Wherever a failed trial is accepted on the secant's confirmation, the position lies within τ above
    the exact threshold, as a bracket closed to τ would."""
    threshold, tolerance = 0.3141, 0.01

    def margin(x):
        return power * math.log((x - contact_start) / (threshold - contact_start))

    def outcome(x):
        return ("failed at", x) if margin(x) > 0.0 else None, margin(x)

    trials = []
    ends = margin(1.0), margin(0.0)
    x, value = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), tolerance, *ends)
    assert threshold < x <= threshold + tolerance
    assert value == ("failed at", x)
    assert len(trials) <= 5


def test_a_failed_trial_that_the_secant_does_not_confirm_is_not_accepted():
    """A margin straight below the threshold and ten times steeper above it: the estimate from the ends
    lies far below the threshold and the trial there is intact; the estimates that follow disagree until
    the bracket is closed, and the position lies within τ above the threshold."""
    threshold, tolerance, trials = 0.6, 0.01, []

    def margin(x):
        return (x - threshold) * (10.0 if x > threshold else 1.0)

    def outcome(x):
        return ("failed at", x) if margin(x) > 0.0 else None, margin(x)

    ends = margin(1.0), margin(0.0)
    x, _ = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), tolerance, *ends)
    assert threshold < x <= threshold + tolerance
    assert len(trials) >= 2


def test_a_margin_that_disagrees_with_the_outcome_does_not_move_the_bracket_wrongly():
    """The outcome, not the margin, decides: a margin that says "fails" where the outcome is intact (a
    split that separates nothing) is not used, and the first failure is still bracketed."""
    threshold, trials = 0.7, []

    def outcome(x):
        return ("failed at", x) if x >= threshold else None, 1.0  # always "met", failing only from 0.7

    x, _ = locate_event(0.0, 1.0, ("failed at", 1.0), _counting(outcome, trials), 0.01, 1.0)
    assert threshold <= x <= threshold + 0.01


def test_a_bracket_within_the_tolerance_is_not_searched():
    assert locate_event(0.0, 0.01, "hi", lambda x: pytest.fail("searched"), 0.01) == (0.01, "hi")


def _single_floe(diameter_m=20.0, thickness_m=1.0, position="a"):
    bow = agulhas_ii(ice_thickness_m=thickness_m)
    field = single_floe_field(SingleFloeCase(position, diameter_m, thickness_m), float(bow.half_breadth_m))
    return field, bow, float(field.domain_m[2] + bow.length_bow_m + 2.0)


def _first_break_m(field, bow, x_end_m, **params) -> float:
    result = simulate(field, bow, build_model("default"), SimulationParams(x_end_m=x_end_m, **params))
    gone = result.fate != "remaining"
    return float(np.nanmin(result.bow_x_m[gone & (result.parent_piece_id >= 0)]))


def test_the_located_first_break_is_where_fine_literal_stepping_finds_it():
    """The first break of a 20 m floe, located from 0.5 m and from 0.25 m contact searches, lies within the
    tolerance of where the literal stepping finds it with steps of a quarter of the tolerance; the literal
    stepping with 0.5 m steps breaks it later (at its step's end)."""
    field, bow, x_end = _single_floe()
    tolerance = 0.02
    fine = _first_break_m(field, bow, x_end, step_m=tolerance / 4)
    coarse_literal = _first_break_m(field, bow, x_end, step_m=0.5)
    for step in (0.5, 0.25):
        located = _first_break_m(
            field, bow, x_end, step_m=step, event_location="root", event_tolerance_m=tolerance
        )
        assert abs(located - fine) <= tolerance + 1e-9
    assert coarse_literal - fine > tolerance  # the case is one the step's end gets wrong


@pytest.mark.parametrize("step_m", [1.0, 0.25])
def test_located_events_conserve_area_and_repeat_exactly(step_m):
    field, bow, x_end = _single_floe(diameter_m=30.0)
    params = SimulationParams(step_m=step_m, x_end_m=x_end, event_location="root")
    a = simulate(field, bow, build_model("default"), params)
    b = simulate(field, bow, build_model("default"), params)
    assert a.n_breaks > 3
    assert a.area_balance_rel_error < 1e-9
    assert list(a.fate) == list(b.fate)
    np.testing.assert_array_equal(a.bow_x_m, b.bow_x_m)


@pytest.mark.parametrize("profile", ["default", "thesis"])
@pytest.mark.parametrize("diameter_m", [10.0, 20.0])
def test_located_events_are_port_starboard_symmetric(profile, diameter_m):
    field, bow, x_end = _single_floe(diameter_m=diameter_m, position="b")
    mirrored = FloeField(
        shapely.transform(field.polygons, lambda xy: xy * np.array([1.0, -1.0])),
        field.thickness_m,
        field.diameter_class_m,
        field.floe_id,
        field.domain_m,
    )
    model = build_model(profile)
    params = SimulationParams(step_m=0.5, x_end_m=x_end, event_location="root")
    port, starboard = simulate(field, bow, model, params), simulate(mirrored, bow, model, params)
    for fate in ("cusp", "flipped", "remaining"):
        assert port.mask(fate).sum() == starboard.mask(fate).sum(), fate
        assert starboard.area_m2(fate) == pytest.approx(port.area_m2(fate), abs=1e-9 * field.ice_area_m2)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"event_location": "midpoint"}, "simulation.event_location"),
        ({"event_tolerance_m": 0.0}, "simulation.event_tolerance_m"),
    ],
)
def test_bad_event_settings_name_their_key(kwargs, key):
    with pytest.raises(InputError) as error:
        SimulationParams(**kwargs)
    assert error.value.field == key


def test_each_profile_resolves_its_event_location():
    from floebreak.app.run import event_location
    from floebreak.config.profiles import DEFAULT_EVENT_LOCATION
    from floebreak.config.scenario import Scenario

    assert event_location(Scenario.from_dict({"profile": "thesis"})) == "step_end"
    assert event_location(Scenario.from_dict({"profile": "default"})) == DEFAULT_EVENT_LOCATION
    stated = Scenario.from_dict({"profile": "thesis", "simulation": {"event_location": "root"}})
    assert event_location(stated) == "root"


def _summary(scenario: dict) -> tuple:
    import floebreak

    summary = floebreak.run(scenario).summary
    return tuple(summary[k] for k in ("n_cusps", "n_flipped", "n_breaks", "cusp_area_m2", "flipped_area_m2"))


def test_the_run_summary_records_its_event_location():
    """The summary says where failures were placed, also when the profile chose it (not in the scenario)."""
    import floebreak
    from floebreak.config.profiles import DEFAULT_EVENT_LOCATION

    small = {"profile": "default", "seed": 3, "field": {"length_m": 30.0, "width_m": 20.0}}
    assert floebreak.run(small).summary["event_location"] == DEFAULT_EVENT_LOCATION
    located = floebreak.run({**small, "simulation": {"event_location": "root", "event_tolerance_m": 0.02}})
    assert located.summary["event_location"] == "root"
    assert located.summary["event_tolerance_m"] == 0.02


LOCATED = {
    "profile": "default",
    "seed": 3,
    "field": {"length_m": 80.0, "width_m": 40.0},
    "ship": {"step_m": 0.5},
    "simulation": {"event_location": "root"},
}


def test_a_located_run_gives_the_same_result_in_a_worker_process():
    from concurrent.futures import ProcessPoolExecutor

    here = _summary(LOCATED)
    assert here[2] > 10  # the ice breaks
    with ProcessPoolExecutor(1) as pool:
        assert pool.submit(_summary, LOCATED).result() == here


def test_a_failed_trial_confirms_only_an_estimate_it_agrees_with():
    """`_confirms`' agreement check: a failed trial whose secant with the last intact position meets zero
    within τ below it, but more than τ/2 from the estimate that placed the trial, does not locate the
    failure (the two estimates of the crossing disagree). Worked by hand: the line through (9.9 m, −0.5)
    and (10.003 m, +0.01) meets zero at 9.9 + 0.103 · 0.5 / 0.51 = 10.00098 m, within τ = 0.01 m below
    10.003 m; an estimate of 10.000 m lies 0.001 m from it (agrees), one of 9.990 m 0.011 m (does not).
    Other: a crossing more than τ below the failed trial does not locate it either."""
    from floebreak.engine.events import _confirms

    intact, failed, tolerance_m = (9.9, -0.5), (10.003, 0.01), 0.01
    assert _confirms(10.0, intact, failed, tolerance_m)
    assert not _confirms(9.99, intact, failed, tolerance_m)
    # the line through (9.9, −0.5) and (10.05, +0.3) meets zero at 10.05 − 0.3 · 0.15 / 0.8 = 9.99375 m,
    # more than τ below 10.05 m: not located there, though the estimate agrees
    assert not _confirms(9.99375, intact, (10.05, 0.3), tolerance_m)
