"""The coupled loop's savings under moving ice change nothing (docs/model.md, "Coupling with breaking", 1):
outlines stored when first read, and moved pieces apart from the hull skipped without a contact evaluation."""

from __future__ import annotations

import numpy as np
import shapely

from floebreak.app.build import build_bow, build_field, build_model_for, ice_motion_params
from floebreak.config.scenario import Scenario
from floebreak.engine import loop as simulation
from floebreak.engine.loop import SimulationParams, StepDone, _Run, simulate
from floebreak.engine.motion.dynamic import DynamicIce

SHORT = ["field.length_m=50"]  # the reference observation's floes, 50 m × 100 m


def _same_pieces(a, b) -> bool:
    return len(a.fate) == len(b.fate) and all(
        shapely.equals_exact(p, q, 0.0) for p, q in zip(a.polygon, b.polygon, strict=True)
    )


def _reference_run(*overrides: str, callbacks=()):
    """The reference scenario on SHORT, simulated with `callbacks`."""
    scenario = Scenario.reference([*SHORT, *overrides]).resolved()
    field = build_field(scenario, np.random.default_rng(scenario.seed))
    params = SimulationParams(step_m=scenario.ship.step_m, **ice_motion_params(scenario))
    return simulate(field, build_bow(scenario, field), build_model_for(scenario), params, callbacks=callbacks)


def test_outlines_stored_when_read_equal_outlines_stored_at_every_search(monkeypatch):
    """Moved pieces outside the contact sweep get their outline when the sweep takes them in or the run
    ends; storing every moved outline after every interval gives the same pieces to the bit, and the
    pieces the engine holds at the end are stored where the engine has them."""
    motions = []
    lazy = _reference_run("simulation.ice_motion=dynamic", callbacks=[lambda e: motions.append(e)])
    engine = next(e.ice_motion for e in motions if isinstance(e, StepDone)).engine
    held = [pid for pid in engine.piece_ids() if lazy.fate[pid] == "remaining"]
    assert held
    for pid in held:
        assert shapely.equals_exact(lazy.polygon[pid], engine.polygon(pid), 0.0)
        assert tuple(lazy.piece_bounds_m[pid]) == tuple(shapely.bounds(engine.polygon(pid)))
    advance_to = DynamicIce.advance_to

    def at_once(self, bow_x):
        advance_to(self, bow_x)
        self.flush()

    monkeypatch.setattr(DynamicIce, "advance_to", at_once)
    eager = _reference_run("simulation.ice_motion=dynamic")
    assert _same_pieces(lazy, eager)
    assert np.array_equal(lazy.piece_bounds_m, eager.piece_bounds_m)


def test_moved_pieces_apart_from_the_hull_skip_the_contact_evaluation_and_change_nothing(monkeypatch):
    """`_apart_after_moving` gives a moved piece its out-of-contact skip back without a contact evaluation;
    evaluating every moved piece instead gives the same pieces, with more contact evaluations."""
    evaluated = []
    evaluate = simulation.evaluate_contacts

    def counted(polygons, *args):
        evaluated.append(len(polygons))
        return evaluate(polygons, *args)

    monkeypatch.setattr(simulation, "evaluate_contacts", counted)
    skipped = _reference_run("simulation.ice_motion=dynamic")
    with_skip = sum(evaluated)
    evaluated.clear()
    monkeypatch.setattr(_Run, "_apart_after_moving", lambda self, pids, bow_x: pids)
    every = _reference_run("simulation.ice_motion=dynamic")
    assert sum(evaluated) > with_skip
    assert _same_pieces(skipped, every)
    assert np.array_equal(skipped.fate, every.fate)
    assert (skipped.n_contacts, skipped.n_breaks) == (every.n_contacts, every.n_breaks)
