"""Failure events located between contact searches (docs/model.md §9, "Event location").

The stepping engine searches contacts every `step_m` with the bow position as its clock. With
``event_location = "step_end"`` (the thesis' literal stepping, §3.2) a piece that fails breaks at the search
position where its failure is first seen, so the indentation at failure — and with it the pieces' sizes —
depends on the step. With ``"root"`` a piece that had not failed at its last known position x₀ (the previous
search, the position where it was made, or where it could first touch the hull) and fails at the search
position x₁ breaks at the bow position x* ∈ (x₀, x₁] where its failure is first met, found to within
`event_tolerance_m` by narrowing a bracket on the outcome of the whole dispatch (failed / not failed). The
outcome alone moves the bracket; the deciding criterion's margin (`Outcome.margin`), where it has one of the
outcome's sign, places the trials (`locate_event`): its zero is estimated by a secant, the trial placed just
above it, and a failed trial whose own secant agrees with that estimate locates the failure (`_confirms`).
The margin at x₀ comes from the piece's evaluation there (kept from the previous search,
`_Run.search_margins`, or from the position where the piece was made), so a margin that behaves as the model
expects is located with one trial. The located evaluation is that failed trial, or the failed one at the
upper end of a bracket narrowed to the tolerance. Its children are evaluated
at x*, and those that survive there again at x₁, with the same location between x* and x₁; so `step_m` only
sets how often contacts are searched.

The search finds *a* crossing of the outcome in the bracket: the first one when the outcome changes once,
which is the usual case over a step (the indentation grows monotonically as the bow advances). The trial
positions are a function of the bracket and the margins found: runs stay deterministic and mirror-symmetric.
Trials are not reported to callbacks and do not count as evaluations; only the located failure (at x*) is.

The functions here drive a run of the loop through the small interface `Stepper` (the loop's `_Run` is
one) and import nothing from the loop.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from typing import Any, NamedTuple, Protocol

Trial = Callable[[float], tuple[Any, float | None]]


class Stepper(Protocol):
    """What event location needs of a run of the loop (`floebreak.engine.loop._Run`)."""

    params: Any  # `SimulationParams`
    pieces: Any  # the run's piece table
    search_margins: dict[int, tuple[float, float | None]]

    def check_time(self, bow_x: float) -> None:
        """Raise `WallTimeError` once the run is over its wall-time budget."""
        ...

    def bow_frame(self, pids: list[int], bow_x: float) -> Any:
        """The pieces `pids` in the bow frame of the bow at `bow_x`."""
        ...

    def contacts(self, pids: list[int], polygons_bf: Any) -> list:
        """The contact of each piece with the hull."""
        ...

    def judge(self, pid: int, polygon_bf: Any, contact: Any) -> tuple[Any, Any]:
        """(classification, outcome) of a piece in contact; changes nothing."""
        ...

    def apply(self, step: int, bow_x: float, pid: int, contact: Any, judged: tuple[Any, Any]) -> list:
        """Record a judged evaluation at `bow_x` and carry out its outcome; the new pieces."""
        ...

    def quiet(self, pid: int, polygon_bf: Any, bow_x: float) -> None:
        """A piece out of contact at `bow_x`: when the bow can touch it next."""
        ...


EVENT_LOCATIONS = ("step_end", "root")
# Bisection tolerance [m] of the located bow position: below it the paired outputs of the reference study
# move by less than their sampling error (docs/validation.md, convergence).
EVENT_TOLERANCE_M = 0.01


class _Item(NamedTuple):
    """A piece to evaluate at bow position `x` (`polygon_bf` in that bow frame), known not to have failed at
    any position up to `lo`; `margin_lo` its `Outcome.margin` at `lo` if it was judged intact there."""

    pid: int
    polygon_bf: Any
    x: float
    lo: float
    margin_lo: float | None = None


def locate_event(lo, hi, at_hi, trial, tolerance_m, margin_hi=None, margin_lo=None):
    """The first failure in (lo, hi] to within `tolerance_m`: the outcome does not fail at `lo` (its margin
    there `margin_lo`, if known), fails at `hi` with `at_hi` (margin `margin_hi`); `trial(x)` gives (the
    failed evaluation at x or None, its margin or None). Returns (x, evaluation at x), x a failed position:
    the upper end of a bracket narrowed to `tolerance_m`, or a failed trial that confirms the estimate which
    placed it (`_confirms`).

    The bracket is narrowed on the outcome alone; the margins (`Outcome.margin`, ln(driving/resistance) of
    the deciding criterion) place the next trial (`_next_trial`) and confirm a failed one. The trial
    positions are a function of the bracket and the margins found alone: runs stay deterministic."""
    ends = {"lo": _usable(margin_lo, False), "hi": _usable(margin_hi, True)}
    last: list = []  # the last two (position, usable margin)
    widths = [hi - lo]  # the bracket's width before each trial
    while hi - lo > tolerance_m:
        if len(widths) >= 4 and hi - lo > 0.5 * widths[-4]:
            x, zero = 0.5 * (lo + hi), None  # three trials did not halve the bracket: far from straight
        else:
            x, zero = _next_trial(lo, hi, ends, last, tolerance_m, len(widths) == 1)
        found, margin = trial(x)
        usable = _usable(margin, found is not None)
        if found is None:
            lo, ends["lo"] = x, usable
        else:
            if _confirms(zero, (lo, ends["lo"]), (x, usable), tolerance_m):
                return x, found
            hi, at_hi, ends["hi"] = x, found, usable
        last = [] if usable is None else [*last[-1:], (x, usable)]
        widths.append(hi - lo)
    return hi, at_hi


def _confirms(zero: float | None, intact: tuple, failed: tuple, tolerance_m: float) -> bool:
    """Whether a failed trial at `failed` = (x, usable margin), placed by the estimate `zero`, locates the
    failure: the secant through it and the last position found intact (`intact`, with its usable margin)
    meets zero within `tolerance_m` below x and within τ/2 of `zero`. Two estimates of the crossing then
    agree and one exact evaluation stands above both: the tolerance holds empirically, not by construction
    (how far accepted positions lie from the bisected first failure: benchmarks/README.md)."""
    if zero is None or intact[1] is None or failed[1] is None:
        return False
    crossing = _line_zero(intact, failed)
    return failed[0] - tolerance_m <= crossing and abs(crossing - zero) <= 0.5 * tolerance_m


def _usable(margin: float | None, failed: bool) -> float | None:
    """√(driving/resistance) − 1 = exp(margin/2) − 1 for the secant, or None where the margin is not of the
    outcome's sign (the outcome was decided by something else than the criterion, e.g. a split that
    separates nothing or a mode without a margin). The square root: the contact load grows about as the
    square of the indentation, so this is close to linear in the bow position over a step (fewer trials than
    the margin itself, benchmarks/README.md)."""
    if margin is None or (margin > 0.0) != failed:
        return None
    return math.expm1(0.5 * margin)


def _next_trial(lo: float, hi: float, ends: dict, last: list, tolerance_m: float, first: bool):
    """(the next trial, the estimate that placed it or None). The estimate is where the zero of the usable
    margin lies — regula falsi between the bracket's ends where both have one, else the secant through the
    last two trials with one; the trial is τ·0.3 above it, so that a failed trial there confirms it
    (`_confirms`) and an intact one leaves a bracket that a second trial closes; once the estimate is within
    τ of an end, at τ from that end. With no estimate: the midpoint, or, at the first trial with no margin
    at either end, just above `lo` (a mode without a criterion, rotation of an unbreakable piece, acts when
    the piece first touches the hull, at the bracket's lower end). Always at least τ/20 inside the bracket
    (wider than τ)."""
    zero = _secant_zero(lo, hi, ends, last)
    if zero is None:
        nothing_known = first and ends["lo"] is None and ends["hi"] is None
        x = lo + 0.95 * tolerance_m if nothing_known else 0.5 * (lo + hi)
    elif hi - zero <= 0.9 * tolerance_m:
        x = hi - 0.95 * tolerance_m  # an intact trial here closes the bracket
    elif zero - lo <= 0.9 * tolerance_m:
        x = lo + 0.95 * tolerance_m  # a failed trial here closes the bracket
    else:
        x = zero + 0.3 * tolerance_m
    return min(max(x, lo + 0.05 * tolerance_m), hi - 0.05 * tolerance_m), zero


def _secant_zero(lo: float, hi: float, ends: dict, last: list) -> float | None:
    """The zero of the line through the last two trials' usable margins if it lies in the bracket (they are
    the nearest to it), else through the bracket's ends'."""
    if len(last) == 2 and last[0][1] != last[1][1]:
        zero = _line_zero(*last)
        if lo < zero < hi:
            return zero
    if ends["lo"] is not None and ends["hi"] is not None:
        return _line_zero((lo, ends["lo"]), (hi, ends["hi"]))
    return None


def _line_zero(a: tuple[float, float], b: tuple[float, float]) -> float:
    (x0, m0), (x1, m1) = a, b
    return x1 - m1 * (x1 - x0) / (m1 - m0)


def locate_step(run: Stepper, step: int, x0: float, x1: float, touching: list[int], evaluations: int) -> None:
    """`_Run._evaluate_queue` with located events: the pieces in contact at the search position `x1` (the
    previous search at `x0`), their breaks at located positions, the children at theirs, until nothing more
    fails up to `x1`. Contacts are evaluated in batches as in `_evaluate_queue` (each item in its own bow
    frame: a contact depends on the piece's bow-frame polygon only). The margins of the pieces judged intact
    at `x1` are kept (`run.search_margins`) for the brackets of the next search, which start at `x1`."""
    pieces, previous = run.pieces, run.search_margins
    run.search_margins = {}
    queue = deque()
    for pid, polygon in zip(touching, run.bow_frame(touching, x1), strict=True):
        lo = max(x0, pieces.quiet_until[pid])
        known_x, margin = previous.get(pid, (math.nan, None))
        queue.append(_Item(pid, polygon, x1, lo, margin if abs(known_x - lo) <= 1e-9 else None))
    batch: deque = deque()
    while queue:
        if not batch:
            batch.extend(run.contacts([item.pid for item in queue], [item.polygon_bf for item in queue]))
        item = queue.popleft()
        evaluations += 1
        run.check_time(item.x)
        new = _settle(run, step, x1, item, batch.popleft())
        if evaluations < run.params.max_evaluations_per_floe_step:
            queue.extend(new)


def _settle(run: Stepper, step: int, x1: float, item: _Item, contact) -> list[_Item]:
    """Evaluate one item; a failure is located in (item.lo, item.x] and applied there. The items that
    follow: the children at the located position, or the piece itself at `x1` if it survived before it."""
    pid, polygon_bf, x, lo, margin_lo = item
    if not contact.in_contact:
        run.quiet(pid, polygon_bf, x)
        return _again(run, pid, x, x1, None)
    judged = run.judge(pid, polygon_bf, contact)
    tolerance_m = run.params.event_tolerance_m
    if judged[1].failed and x - lo > tolerance_m:
        trial = lambda trial_x: _failed_at(run, pid, trial_x)  # noqa: E731
        located = locate_event(lo, x, (contact, judged), trial, tolerance_m, judged[1].margin, margin_lo)
        x, (contact, judged) = located
    children = run.apply(step, x, pid, contact, judged)
    if judged[1].failed:
        return [_Item(child, child_bf, x, x) for child, child_bf in children]
    if x == x1:
        run.search_margins[pid] = (x1, judged[1].margin)
    return _again(run, pid, x, x1, judged[1].margin)


def _failed_at(run: Stepper, pid: int, x: float):
    """A trial of `locate_event`: ((contact, (classification, outcome)) of piece `pid` at bow position `x`
    if it fails there, else None; the outcome's margin). Nothing is applied or reported."""
    run.check_time(x)
    polygon_bf = run.bow_frame([pid], x)[0]
    contact = run.contacts([pid], [polygon_bf])[0]
    if not contact.in_contact:
        return None, None
    judged = run.judge(pid, polygon_bf, contact)
    return ((contact, judged) if judged[1].failed else None), judged[1].margin


def _again(run: Stepper, pid: int, x: float, x1: float, margin: float | None) -> list[_Item]:
    """A piece that did not fail at `x` (its margin there `margin`) before the search position `x1` is
    evaluated again at `x1`, unless it cannot touch the hull by then (`quiet_until`)."""
    quiet = run.pieces.quiet_until[pid]
    if x >= x1 or quiet > x1:
        return []
    lo = max(x, quiet)
    return [_Item(pid, run.bow_frame([pid], x1)[0], x1, lo, margin if lo == x else None)]
