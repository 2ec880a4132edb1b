"""The thesis' quantitative statements, loaded from data, and how each one is scored.

The statements themselves are data: ``floebreak/data/thesis_statements.toml`` holds one entry per number or
trend that thesis §5.1, §5.2, §5.3 (Tables 5–8 and the percentages in the text) and §6.2 state, and the
end-to-end chain rows of the `default` profile (§6.2's measured shaft torque, the PC5 ice-class rule). Each
names the design point it is measured at (`point`, see `floebreak.validation.validate.POINTS`), the per-run
metric by its key (`metric`; the metric computations are code, `floebreak.validation.scoreboard.run_metrics`
and `floebreak.validation.chain_statements`), the statistic, the thesis' value, a tolerance and the
profiles in which it must hold. This module loads and checks that file (`load_statements`, cached) into typed
`Statement`s and scores them (`verdict`, `mean_se`, `paired_relative_change`).

Statistics over the random fields (the thesis averages four fields, Fig. 1):

- ``level``: the metric at `point`; mean ± standard error over the fields.
- ``change``: the *paired* relative change at `point` against `against` on the same field,
  r_i = x_i / y_i − 1; mean ± standard error of the r_i. Pairing on common fields removes the
  field-to-field spread from trends (the thesis compares its parameters on the same four fields).

Thesis values of changes are computed from the thesis' own table entries (``thesis_change = [new, old]``,
e.g. Table 6: n_cusp 149 with line load vs 125 with tensile stress → +19.2 %, the "19 % more cusps" of
§5.3.2).

Must-hold rows follow the thesis' own judgement of its uncertainty (§5.3.5: "especially the small influences
detected in this parameter study are somewhat uncertain. The influences of the ice thickness and the
difference between the force-based and stress-based cracking criteria are so large that they are outside of
the range of stochastic uncertainties"): the directions of the large effects must hold in every profile; small
effects must stay small (≤ 5 %); levels and rough sizes must hold in the ``thesis`` profile, whose purpose is
to reproduce the published numbers.

A statement our model does not hold for a documented reason keeps its must-hold profiles and carries the
reason (`Statement.explained`), which the scoreboard shows as a note: a failing row fails, explained or not.
A change row that a model with no effect at all passes (`Statement.weak`, from `null_verdict`) is weak
evidence and counted apart; whether a row can fail at all under a configuration is computed in
`floebreak.validation.inert`.
"""

from __future__ import annotations

import functools
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np

from floebreak.config.profiles import PROFILES

ToleranceKind = Literal["rel", "abs", "direction", "rough", "max_abs", "at_least", "range", "info"]
Verdict = Literal["pass", "fail", "info", "missing"]
TOLERANCE_KINDS = ("rel", "abs", "direction", "rough", "max_abs", "at_least", "range", "info")
STATISTICS = ("level", "change")
STATEMENTS_RESOURCE = "thesis_statements.toml"  # in the package `floebreak.data`


@dataclass(frozen=True)
class Tolerance:
    """How close our value must be to the thesis' (the thesis value is `Statement.thesis_value`).

    - ``rel``: |ours / thesis − 1| ≤ value;  ``abs``: |ours − thesis| ≤ value;
    - ``direction``: ours has the thesis' sign (a trend);
    - ``rough``: same sign and ours / thesis within [1/value, value] (a trend's rough size);
    - ``max_abs``: |ours| ≤ value (an effect the thesis calls small);
    - ``at_least``: ours ≥ value;  ``range``: low ≤ ours ≤ high;  ``info``: no verdict.
    """

    kind: ToleranceKind
    value: float = math.nan
    high: float = math.nan  # upper bound of ``range`` (``value`` is the lower one)

    def describe(self, unit: str = "") -> str:
        pct = unit == "%"

        def num(x: float) -> str:
            return f"{100 * x:g} %" if pct else f"{x:g}{(' ' + unit) if unit and unit != '-' else ''}"

        return {
            "rel": f"±{100 * self.value:g} % of the thesis",
            "abs": f"±{num(self.value)}",
            "direction": "same sign",
            "rough": f"same sign, within ×{self.value:g}",
            "max_abs": f"|ours| ≤ {num(self.value)}",
            "at_least": f"≥ {num(self.value)}",
            "range": f"{num(self.value)} … {num(self.high)}",
            "info": "—",
        }[self.kind]


@dataclass(frozen=True)
class Statement:
    """One quantitative thesis statement and how it is scored."""

    id: str
    source: str  # section / table / figure
    quote: str  # the thesis' words, briefly
    quantity: str  # what is compared
    metric: str  # per-run metric key (floebreak.validation.scoreboard.run_metrics)
    point: str  # design point (floebreak.validation.validate.POINTS)
    thesis_value: float  # in the statement's unit: fractions for changes and shares
    tolerance: Tolerance
    must_hold: frozenset[str] = frozenset()  # profiles in which the statement must pass
    statistic: Literal["level", "change"] = "level"
    against: str | None = None  # reference point of a change
    unit: str = "-"  # "%" marks a fraction shown in per cent
    thesis_text: str = ""  # the thesis' value in words where it is a band or a direction, not a number
    # why our model does not hold the statement, where docs/model.md says so and which test shows the
    # mechanism: a note next to the row; the row keeps its must-hold profiles and a failure stays a failure
    explained: str = ""

    @property
    def weak(self) -> bool:
        """Whether a model with no effect at all passes the row: a change whose tolerance a change of exactly
        0 passes (e.g. |ours| ≤ 5 %). Its pass shows the effect is not large, not that the model has the
        thesis' effect (levels have no such null model)."""
        return self.statistic == "change" and null_verdict(self) == "pass"


def null_verdict(st: Statement) -> Verdict | None:
    """The verdict of the null variant — no change between the two design points (0 %) — computed, not run;
    None for a level."""
    return verdict(0.0, st.thesis_value, st.tolerance) if st.statistic == "change" else None


def verdict(value: float, thesis_value: float, tolerance: Tolerance) -> Verdict:
    """pass / fail of our value against the thesis' value (info rows have no verdict; NaN is missing)."""
    if tolerance.kind == "info":
        return "info"
    if value is None or not math.isfinite(value):
        return "missing"
    ok = {
        "rel": lambda: abs(value / thesis_value - 1.0) <= tolerance.value,
        "abs": lambda: abs(value - thesis_value) <= tolerance.value,
        "direction": lambda: np.sign(value) == np.sign(thesis_value) != 0,
        "rough": lambda: (
            value * thesis_value > 0 and 1.0 / tolerance.value <= value / thesis_value <= tolerance.value
        ),
        "max_abs": lambda: abs(value) <= tolerance.value,
        "at_least": lambda: value >= tolerance.value,
        "range": lambda: tolerance.value <= value <= tolerance.high,
    }[tolerance.kind]()
    return "pass" if ok else "fail"


def mean_se(values) -> tuple[float, float, int]:
    """Mean, standard error of the mean (sample std / √n; 0 for one value) and n of the finite values."""
    x = np.asarray([v for v in values if v is not None], dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return math.nan, math.nan, 0
    se = float(np.std(x, ddof=1) / math.sqrt(x.size)) if x.size > 1 else 0.0
    return float(np.mean(x)), se, int(x.size)


def paired_relative_change(values: dict[int, float], reference: dict[int, float]) -> tuple[float, float, int]:
    """Mean ± standard error over the common fields of r_i = x_i / y_i − 1 (fields keyed by index)."""
    common = sorted(set(values) & set(reference))
    changes = [
        values[i] / reference[i] - 1.0
        for i in common
        if values[i] is not None and reference[i] not in (None, 0.0)
    ]
    return mean_se(changes)


def _where(entry: dict[str, Any]) -> str:
    return f"statement {entry.get('id', '?')!r}"


STATEMENT_KEYS = frozenset(
    {"id", "source", "quote", "quantity", "metric", "point", "statistic", "against", "thesis_value",
     "thesis_change", "thesis_ratio", "tolerance", "must_hold", "unit", "thesis_text", "explained"}
)  # fmt: skip
REQUIRED_TEXT = ("id", "source", "quote", "quantity", "metric", "point")


def _number(value: Any, where: str, key: str) -> float:
    """A thesis number; a list of numbers is their sum (e.g. A_cusp^tot + A_flip^tot)."""
    if isinstance(value, list):
        return sum((_number(v, where, key) for v in value), 0.0)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{where}: {key} must be a number or a list of numbers, got {value!r}")
    return float(value)


def _thesis_value(entry: dict[str, Any], where: str) -> float:
    given = [key for key in ("thesis_value", "thesis_change", "thesis_ratio") if key in entry]
    if len(given) != 1:
        raise ValueError(f"{where}: give exactly one of thesis_value, thesis_change, thesis_ratio ({given})")
    key = given[0]
    if key == "thesis_value":
        return _number(entry[key], where, key)
    pair = entry[key]
    if not isinstance(pair, list) or len(pair) != 2:
        raise ValueError(f"{where}: {key} must be [a, b], got {pair!r}")
    a, b = (_number(v, where, key) for v in pair)
    if b == 0.0:
        raise ValueError(f"{where}: {key} divides by 0")
    return a / b - 1.0 if key == "thesis_change" else a / b


def _tolerance(raw: Any, where: str) -> Tolerance:
    if (
        not isinstance(raw, dict)
        or raw.get("kind") not in TOLERANCE_KINDS
        or set(raw) - {"kind", "value", "high"}
    ):
        raise ValueError(f"{where}: tolerance must be {{kind, value, high}} with kind in {TOLERANCE_KINDS}")
    value, high = (
        _number(raw[k], where, f"tolerance.{k}") if k in raw else math.nan for k in ("value", "high")
    )
    needs = {"direction": (), "info": (), "range": ("value", "high")}.get(raw["kind"], ("value",))
    if any(not math.isfinite(x) for x, k in ((value, "value"), (high, "high")) if k in needs):
        raise ValueError(f"{where}: a {raw['kind']!r} tolerance needs finite {' and '.join(needs)}")
    return Tolerance(raw["kind"], value, high)


def _statement(entry: dict[str, Any], explanations: dict[str, str]) -> Statement:
    """One `Statement` from one checked [[statement]] entry."""
    where = _where(entry)
    unknown = set(entry) - STATEMENT_KEYS
    if unknown:
        raise ValueError(f"{where}: unknown keys {sorted(unknown)} (allowed: {sorted(STATEMENT_KEYS)})")
    for key in REQUIRED_TEXT:
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ValueError(f"{where}: {key} must be a non-empty string")
    statistic = entry.get("statistic", "level")
    if statistic not in STATISTICS or (statistic == "change") != isinstance(entry.get("against"), str):
        raise ValueError(f"{where}: statistic must be level, or change with `against` (its reference point)")
    must_hold = entry.get("must_hold", [])
    if not isinstance(must_hold, list) or not set(must_hold) <= set(PROFILES):
        raise ValueError(f"{where}: must_hold must list profiles of {sorted(PROFILES)}, got {must_hold!r}")
    explained = entry.get("explained", "")
    if explained and explained not in explanations:
        raise ValueError(f"{where}: explained = {explained!r} is not a key of [explanations]")
    return Statement(
        id=entry["id"],
        source=entry["source"],
        quote=entry["quote"],
        quantity=entry["quantity"],
        metric=entry["metric"],
        point=entry["point"],
        thesis_value=_thesis_value(entry, where),
        tolerance=_tolerance(entry.get("tolerance"), where),
        must_hold=frozenset(must_hold),
        statistic=statistic,
        against=entry.get("against"),
        unit=entry.get("unit", "%" if statistic == "change" else "-"),
        thesis_text=entry.get("thesis_text", ""),
        explained=explanations[explained] if explained else "",
    )


def parse_statements(data: dict[str, Any]) -> tuple[Statement, ...]:
    """The `Statement`s of parsed statement data (the TOML's tables), checked: known keys, one thesis value,
    a valid tolerance, profiles that exist, explanations that exist, unique ids."""
    explanations = data.get("explanations", {})
    statements = tuple(_statement(entry, explanations) for entry in data.get("statement", []))
    ids = [st.id for st in statements]
    repeated = sorted({i for i in ids if ids.count(i) > 1})
    if repeated or not statements:
        raise ValueError(f"statement ids must be unique and at least one given (repeated: {repeated})")
    return statements


def _read(path: Path | None) -> dict[str, Any]:
    from floebreak.io.text_files import read_package_data, read_text_file

    text = read_package_data(STATEMENTS_RESOURCE) if path is None else read_text_file(path, "statements")
    return tomllib.loads(text)


@functools.cache
def load_statements(path: Path | None = None) -> tuple[Statement, ...]:
    """The statements of `path` (default: the thesis', shipped as package data), parsed once."""
    return parse_statements(_read(path))


@functools.cache
def load_table5_reference(path: Path | None = None) -> dict[str, float]:
    """Thesis Table 5's reference row (K_Ic = 145.7 kN m^-3/2), the reference of Tables 5–8."""
    return {key: float(value) for key, value in _read(path)["table5_reference"].items()}


STATEMENTS: tuple[Statement, ...] = load_statements()
TABLE5_REFERENCE: dict[str, float] = load_table5_reference()
