"""The readers' fuzz campaign (`make fuzz`): hostile texts from `fuzz.adversarial` — scenarios nested
thousands deep, FEM tables with extreme finite cells, measured torque files from no sample to past the row
bound — each read by floebreak's own reader. A text must be read, or refused with an InputError naming its
file; any other exception is a violation, kept in OUT/violations.jsonl with the text's seed.

    python -m fuzz.readers --n 200 --seed 1 --out fuzz-report/readers
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import floebreak.propeller.measured as measured
from floebreak.config.scenario import Scenario
from floebreak.errors import InputError
from floebreak.propeller.loads.fem import parse_fem_table
from fuzz.adversarial import deep_toml_text, fem_table_texts, torque_csv_texts

READERS = {
    "scenario": (
        lambda rng: deep_toml_text(rng),
        lambda text: Scenario.from_toml_text(text, source="s.toml"),
    ),
    "fem_table": (fem_table_texts, lambda text: parse_fem_table(text, "t.csv")),
    "torque_csv": (
        lambda rng: torque_csv_texts(rng, measured.MAX_TORQUE_ROWS),
        lambda text: measured.parse_torque_csv(text, "m.csv"),
    ),
}
SOURCES = {"scenario": "s.toml", "fem_table": "t.csv", "torque_csv": "m.csv"}


def check_text(reader: str, seed: int) -> dict:
    """One hostile text for `reader` from `seed`, read: its outcome (read, refused or violation)."""
    draw, read = READERS[reader]
    text = draw(np.random.default_rng(seed))
    try:
        read(text)
    except InputError as error:
        named = SOURCES[reader] in str(error)
        return {
            "reader": reader,
            "seed": seed,
            "outcome": "refused" if named else "violation",
            "error": str(error),
        }
    except Exception as error:  # the campaign's finding: anything but a clear InputError
        return {"reader": reader, "seed": seed, "outcome": "violation", "error": repr(error)}
    return {"reader": reader, "seed": seed, "outcome": "read"}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200, help="texts per reader")
    parser.add_argument("--seed", type=int, default=1, help="the campaign's first seed")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    records = [check_text(r, args.seed + k) for r in READERS for k in range(args.n)]
    args.out.mkdir(parents=True, exist_ok=True)
    violations = [r for r in records if r["outcome"] == "violation"]
    lines = "".join(json.dumps(r) + "\n" for r in violations)
    (args.out / "violations.jsonl").write_text(lines, encoding="utf-8")
    counts = {r: {o: 0 for o in ("read", "refused", "violation")} for r in READERS}
    for record in records:
        counts[record["reader"]][record["outcome"]] += 1
    (args.out / "summary.json").write_text(json.dumps(counts, indent=2) + "\n", encoding="utf-8")
    print(json.dumps(counts))
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
