"""Failure events located between contact searches (issue 32 item 4; docs/model.md §9, "Event location").

The stepping engine searches contacts every `step_m` with the bow position as its clock. With
``event_location = "step_end"`` (the thesis' literal stepping, §3.2) a piece that fails breaks at the search
position where its failure is first seen, so the indentation at failure — and with it the pieces' sizes —
depends on the step. With ``"root"`` a piece that had not failed at its last known position x₀ (the previous
search, the position where it was made, or where it could first touch the hull) and fails at the search
position x₁ breaks at the bow position x* ∈ (x₀, x₁] where its failure is first met, found by bisection on the
outcome of the whole dispatch (failed / not failed) to within `event_tolerance_m`. The failure modes expose
no continuous margin (the dispatch mixes bending, cracking and rotation, each with its own criterion and
`PASS_ON`), so the bracket is halved on the outcome itself; the located evaluation is the failed one at the
bracket's upper end. Its children are evaluated at x*, and those that survive there again at x₁, with the
same location between x* and x₁; so `step_m` only sets how often contacts are searched.

Bisection finds *a* crossing of the outcome in the bracket: the first one when the outcome changes once,
which is the usual case over a step (the indentation grows monotonically as the bow advances). The trial
positions are a function of the bracket alone: runs stay deterministic and mirror-symmetric. Trials are not
reported to callbacks and do not count as evaluations; only the located failure (at x*) is.

The functions here drive a `floebreak.simulation._Run` through its methods (`bow_frame`, `contacts`,
`_judge`, `_apply`, `_quiet`, `check_time`) and import nothing from it.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Any, NamedTuple

Trial = Callable[[float], tuple[Any, float | None]]

EVENT_LOCATIONS = ("step_end", "root")
# Bisection tolerance [m] of the located bow position: below it the paired outputs of the reference study
# move by less than their sampling error (docs/validation.md, convergence).
EVENT_TOLERANCE_M = 0.01


class _Item(NamedTuple):
    """A piece to evaluate at bow position `x` (`polygon_bf` in that bow frame), known not to have failed at
    any position up to `lo`."""

    pid: int
    polygon_bf: Any
    x: float
    lo: float


def locate_event(lo: float, hi: float, at_hi: Any, trial: Trial, tolerance_m: float, margin_hi=None):
    """The first failure in (lo, hi] to within `tolerance_m`: the outcome does not fail at `lo`, fails at
    `hi` with `at_hi`; `trial(x)` gives (the failed evaluation at x or None, its margin or None). Returns
    (x, evaluation at x), x the upper end of the final bracket (a failed position, never more than
    `tolerance_m` past the last position found intact).

    The bracket is narrowed on the outcome alone; the margins (`Outcome.margin`, ln(driving/resistance) of
    the deciding criterion) only place the next trial (`_next_trial`; Illinois-weighted regula falsi: an
    end that stays twice has its margin halved). The trial positions are a function of the bracket and the
    margins found alone: runs stay deterministic."""
    ends = {"lo": None, "hi": _signed(margin_hi, True)}  # usable margins at the bracket's ends
    last: list = []  # the last two (position, usable margin)
    previous = None
    while hi - lo > tolerance_m:
        x = _next_trial(lo, hi, ends, last, tolerance_m)
        found, margin = trial(x)
        side = "hi" if found is not None else "lo"
        if found is None:
            lo = x
        else:
            hi, at_hi = x, found
        other = "lo" if side == "hi" else "hi"
        if previous == side and ends[other] is not None:
            ends[other] *= 0.5  # Illinois: the other end stayed twice, so it pulls the next trial less
        ends[side] = usable = _signed(margin, found is not None)
        last = [] if usable is None else [*last[-1:], (x, usable)]
        previous = side
    return hi, at_hi


def _signed(margin: float | None, failed: bool) -> float | None:
    """A margin usable for the secant: of the outcome's sign, else None (the outcome was decided by
    something else than the criterion, e.g. a split that separates nothing or a mode without a margin)."""
    if margin is None or (margin > 0.0) != failed:
        return None
    return margin


def _next_trial(lo: float, hi: float, ends: dict, last: list, tolerance_m: float) -> float:
    """Regula falsi between the bracket's ends where both have a usable margin, else the secant's zero
    through the last two positions with one (the margin is near linear in the bow position over a step),
    else the midpoint; at least `tolerance_m`/2 inside the bracket (wider than `tolerance_m`), so each
    trial narrows it by that much."""
    if ends["lo"] is not None and ends["hi"] is not None:
        (x0, m0), (x1, m1) = (lo, ends["lo"]), (hi, ends["hi"])
    elif len(last) == 2 and last[0][1] != last[1][1]:
        (x0, m0), (x1, m1) = last
    else:
        return 0.5 * (lo + hi)
    x = x1 - m1 * (x1 - x0) / (m1 - m0)
    return min(max(x, lo + 0.5 * tolerance_m), hi - 0.5 * tolerance_m)


def locate_step(run, step: int, x0: float, x1: float, touching: list[int], evaluations: int) -> None:
    """`_Run._evaluate_queue` with located events: the pieces in contact at the search position `x1` (the
    previous search at `x0`), their breaks at located positions, the children at theirs, until nothing more
    fails up to `x1`. Contacts are evaluated in batches as in `_evaluate_queue` (each item in its own bow
    frame: a contact depends on the piece's bow-frame polygon only)."""
    pieces = run.pieces
    queue = deque(
        _Item(pid, polygon, x1, max(x0, pieces.quiet_until[pid]))
        for pid, polygon in zip(touching, run.bow_frame(touching, x1), strict=True)
    )
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


def _settle(run, step: int, x1: float, item: _Item, contact) -> list[_Item]:
    """Evaluate one item; a failure is located in (item.lo, item.x] and applied there. The items that
    follow: the children at the located position, or the piece itself at `x1` if it survived before it."""
    pid, polygon_bf, x, lo = item
    if not contact.in_contact:
        run._quiet(pid, polygon_bf, x)
        return _again(run, pid, x, x1)
    judged = run._judge(pid, polygon_bf, contact)
    tolerance_m = run.params.event_tolerance_m
    if judged[1].failed and x - lo > tolerance_m:
        trial = lambda trial_x: _failed_at(run, pid, trial_x)  # noqa: E731
        x, (contact, judged) = locate_event(lo, x, (contact, judged), trial, tolerance_m, judged[1].margin)
    children = run._apply(step, x, pid, contact, judged)
    if judged[1].failed:
        return [_Item(child, child_bf, x, x) for child, child_bf in children]
    return _again(run, pid, x, x1)


def _failed_at(run, pid: int, x: float):
    """A trial of `locate_event`: ((contact, (classification, outcome)) of piece `pid` at bow position `x`
    if it fails there, else None; the outcome's margin). Nothing is applied or reported."""
    run.check_time(x)
    polygon_bf = run.bow_frame([pid], x)[0]
    contact = run.contacts([pid], [polygon_bf])[0]
    if not contact.in_contact:
        return None, None
    judged = run._judge(pid, polygon_bf, contact)
    return ((contact, judged) if judged[1].failed else None), judged[1].margin


def _again(run, pid: int, x: float, x1: float) -> list[_Item]:
    """A piece that did not fail at `x` before the search position `x1` is evaluated again at `x1`, unless
    it cannot touch the hull by then (`quiet_until`)."""
    quiet = run.pieces.quiet_until[pid]
    if x >= x1 or quiet > x1:
        return []
    return [_Item(pid, run.bow_frame([pid], x1)[0], x1, max(x, quiet))]
