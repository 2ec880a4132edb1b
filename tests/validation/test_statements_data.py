"""The thesis' statements loaded from data equal the statements the Python module held before they became
data (tests/studies/data/thesis_statements_frozen.json, dumped from that module) but for what was removed on
purpose since, and the loader refuses malformed data with a message naming the statement and the key."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import pytest

from floebreak.validation.chain_statements import MEASURED_ABOVE_KNM
from floebreak.validation.statements import (
    STATEMENTS,
    TABLE5_REFERENCE,
    load_statements,
    parse_statements,
)

FROZEN = Path(__file__).parent / "data" / "thesis_statements_frozen.json"
# removed after the conversion: the explanation bands (`recorded`), drawn around values measured before them;
# not compared: the notes (`explained`), measured causes that change with the chain they describe
REMOVED = ("recorded", "explained")


def plain(x):
    """A statement as the frozen dump writes it: dataclasses as dicts, sets as sorted lists."""
    if isinstance(x, frozenset):
        return sorted(x)
    if isinstance(x, tuple | list):
        return [plain(v) for v in x]
    if dataclasses.is_dataclass(x):
        return {f.name: plain(getattr(x, f.name)) for f in dataclasses.fields(x)}
    return x


def same(a, b) -> bool:
    """Equality with NaN equal to NaN (an unset tolerance bound, a band-only thesis value)."""
    if isinstance(a, float) and isinstance(b, float | int) and math.isnan(a):
        return math.isnan(b)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return a == b


def test_the_loaded_statements_equal_the_frozen_copy_of_the_module():
    frozen = [
        {k: v for k, v in st.items() if k not in REMOVED}
        for st in json.loads(FROZEN.read_text(encoding="utf-8"))
    ]
    loaded = [{k: v for k, v in plain(st).items() if k not in REMOVED} for st in STATEMENTS]
    assert [st["id"] for st in loaded] == [st["id"] for st in frozen]  # same rows, same order
    for ours, theirs in zip(loaded, frozen, strict=True):
        assert same(ours, theirs), ours["id"]


def test_the_loader_is_cached_and_table5_is_the_thesis_row():
    assert load_statements() is load_statements() is STATEMENTS
    table5 = (8.14, 8.14, 125.0, 83.0, 1019.48, 2426.90)  # V̄, Ā, n_cusp, n_flip, A_cusp^tot, A_flip^tot
    assert tuple(TABLE5_REFERENCE.values()) == table5


def test_the_chain_rows_limits_agree_with_the_measured_range_the_metrics_use():
    by_id = {st.id: st for st in STATEMENTS}
    low, high = MEASURED_ABOVE_KNM
    assert by_id["S62.chain.end"].thesis_value == high
    assert by_id["S62.chain.overlap"].thesis_value == high - low


MINIMAL = {
    "id": "X.1",
    "source": "§5",
    "quote": "q",
    "quantity": "n",
    "metric": "n_cusps",
    "point": "reference",
    "thesis_value": 125,
    "tolerance": {"kind": "rel", "value": 0.35},
}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"colour": "red"}, "unknown keys ['colour']"),
        ({"thesis_change": [149, 125]}, "exactly one of thesis_value"),
        ({"tolerance": {"kind": "roughly"}}, "tolerance must be"),
        ({"tolerance": {"kind": "range", "value": 1.0}}, "needs finite value and high"),
        ({"must_hold": ["fast"]}, "must_hold must list profiles"),
        ({"statistic": "change"}, "change with `against`"),
        ({"explained": "nowhere"}, "not a key of [explanations]"),
        ({"metric": ""}, "metric must be a non-empty string"),
        ({"thesis_value": "many"}, "thesis_value must be a number"),
    ],
)
def test_malformed_statements_are_refused_naming_the_statement_and_key(change, message):
    with pytest.raises(ValueError, match=r"statement 'X\.1'") as caught:
        parse_statements({"statement": [MINIMAL | change]})
    assert message in str(caught.value)


def test_a_change_from_two_thesis_numbers_and_a_summed_area():
    entry = MINIMAL | {"statistic": "change", "against": "reference", "thesis_value": None}
    del entry["thesis_value"]
    (st,) = parse_statements({"statement": [entry | {"thesis_change": [[983.52, 2464.64], 3446.38]}]})
    assert st.thesis_value == pytest.approx((983.52 + 2464.64) / 3446.38 - 1.0, rel=1e-15)
    assert st.unit == "%" and st.statistic == "change"
    with pytest.raises(ValueError, match="unique"):
        parse_statements({"statement": [MINIMAL, MINIMAL]})
