"""The bad-input table: each kind of bad input or trouble a user meets, the exit code and the
message it gives, run through the command line in-process. Rows of refused input, a refusing machine and
Ctrl-C (exit codes 2, 3, 130) also check that nothing was written and that no traceback was printed.

The same table is README.md's "What a bad input gives" (between the markers below); after changing a row,
write it again with ``PYTHONPATH=src python tests/test_bad_inputs.py``.
"""

from __future__ import annotations

import errno
import importlib
import signal
import sys
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
BEGIN = "<!-- bad-input table: generated from tests/test_bad_inputs.py, do not edit here -->"
END = "<!-- end of the bad-input table -->"


@dataclass(frozen=True)
class Row:
    kind: str  # what the user did (the README's first column)
    example: str  # a command line that does it (paths shortened)
    code: int  # exit code
    message: str  # a fragment of the message (stderr, or stdout for a study's summary)
    args: Callable[[Path, pytest.MonkeyPatch], list[str]]  # prepares tmp_path, returns floebreak's args


def _scenario(folder: Path, text: str = "[field]\nlength_m = 60.0\n") -> str:
    (folder / "s.toml").write_text(text, encoding="utf-8")
    return str(folder / "s.toml")


def _run(*extra: str) -> Callable[[Path, pytest.MonkeyPatch], list[str]]:
    return lambda folder, _: ["run", _scenario(folder), "--out", str(folder / "out"), "-q", *extra]


def _field(*extra: str) -> Callable[[Path, pytest.MonkeyPatch], list[str]]:
    def args(folder: Path, _) -> list[str]:
        out = str(folder / "f.parquet")
        return ["field", "--out", out, "--obs", "2019-12-18T20:20", "--length", "60", *extra]

    return args


def _bow_csv(folder: Path, _) -> list[str]:
    (folder / "bow.csv").write_text("x_m,y_m,line\n0,0,upper\n1,2\n", encoding="utf-8")
    scenario = _scenario(folder, '[ship]\nfile = "bow.csv"\n[field]\nlength_m = 60.0\n')
    return ["run", scenario, "--out", str(folder / "out")]


def _voyage_log(folder: Path, _) -> list[str]:
    header = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d5m_percent,share_d20m_percent"
    rows = ["2020-01-01T00:00,2020-01-01T00:10,50,0.5,60,40", "2020-01-01T01:00,2020-01-01T01:30,150,1,100,0"]
    (folder / "log.csv").write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    return ["voyage", str(folder / "log.csv"), "--out", str(folder / "voyage"), "--workers", "1"]


def _voyage(*extra: str) -> Callable[[Path, pytest.MonkeyPatch], list[str]]:
    """A valid one-period voyage log with `extra` options (refused before anything is simulated)."""

    def args(folder: Path, _) -> list[str]:
        header = "start_utc,end_utc,concentration_percent,mean_thickness_m,share_d5m_percent"
        (folder / "log.csv").write_text(f"{header}\n2020-01-01T00:00,2020-01-01T00:10,50,0.5,100\n", "utf-8")
        return ["voyage", str(folder / "log.csv"), "--out", str(folder / "voyage"), "--workers", "1", *extra]

    return args


def _field_file_with_repeated_id(folder: Path, monkeypatch) -> list[str]:
    import json

    import pyarrow as pa
    import pyarrow.parquet as pq
    import shapely

    geo = {"version": "1.1.0", "primary_column": "geometry", "columns": {"geometry": {"encoding": "WKB"}}}
    geo["columns"]["geometry"]["crs"] = None
    wkb = [shapely.to_wkb(shapely.box(x, -5, x + 10, 5)) for x in (20, 40)]
    table = pa.table({"geometry": pa.array(wkb, pa.binary()), "floe_id": [4, 4], "thickness_m": [1.0, 1.0]})
    pq.write_table(table.replace_schema_metadata({"geo": json.dumps(geo)}), folder / "f.parquet")
    scenario = _scenario(folder, '[field]\nfile = "f.parquet"\n')
    return ["run", scenario, "--out", str(folder / "out"), "-q"]


def _existing_run(folder: Path, monkeypatch) -> list[str]:
    (folder / "out").mkdir()
    (folder / "out" / "keep.txt").write_text("mine", encoding="utf-8")
    return _run()(folder, monkeypatch)


def _existing_field(folder: Path, monkeypatch) -> list[str]:
    (folder / "f.parquet").write_bytes(b"keep me")
    return _field()(folder, monkeypatch)


def _pseudo_file_system(folder: Path, monkeypatch) -> list[str]:
    api = importlib.import_module("floebreak.app.run")
    monkeypatch.setattr(api, "simulate", lambda *a, **k: pytest.fail("the run started"))  # refused before
    return ["run", _scenario(folder), "--out", "/proc/floebreak-run", "-q"]


def _disk_full(folder: Path, monkeypatch) -> list[str]:
    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(importlib.import_module("floebreak.output.run_directory"), "write_geoparquet", full)
    return _run()(folder, monkeypatch)


def _interrupted(folder: Path, monkeypatch) -> list[str]:
    def ctrl_c(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(importlib.import_module("floebreak.app.run"), "simulate", ctrl_c)
    return _run()(folder, monkeypatch)


def _far_field(folder: Path, _) -> list[str]:
    text = "[field]\nfloes = [{ x_m = 20.0, y_m = 500.0, diameter_m = 10.0 }]\n[ice]\nthickness_m = 1.0\n"
    return ["run", _scenario(folder, text), "--out", str(folder / "out"), "-q"]


def _semicolon_log(folder: Path, _) -> list[str]:
    header = "start_utc;end_utc;concentration_percent;mean_thickness_m;share_d5m_percent;share_d20m_percent"
    (folder / "log.csv").write_text(header + "\n2020-01-01T00:00;2020-01-01T00:10;50;0,5;60;40\n", "utf-8")
    return ["voyage", str(folder / "log.csv"), "--out", str(folder / "voyage"), "--workers", "1"]


def _terminated(folder: Path, monkeypatch) -> list[str]:
    from floebreak.exit_codes import Terminated, record_signal

    def sigterm(*args, **kwargs):
        record_signal(signal.SIGTERM)  # what floebreak.__main__'s handler records before it raises
        raise Terminated

    monkeypatch.setattr(importlib.import_module("floebreak.app.run"), "simulate", sigterm)
    return _run()(folder, monkeypatch)


def _bug(folder: Path, monkeypatch) -> list[str]:
    def broken(*args, **kwargs):
        raise RuntimeError("a bug")

    monkeypatch.setattr(importlib.import_module("floebreak.app.run"), "simulate", broken)
    return _run()(folder, monkeypatch)


STUDY = (
    'name = "s"\nn_fields = 1\n[base]\nseed = 1\n[base.field]\nobservation = "2019-12-18T20:20"\n'
    "length_m = 50.0\nwidth_m = 30.0\n"
)


def _relative_study_out(folder: Path, monkeypatch) -> list[str]:
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    monkeypatch.chdir(folder)
    return ["study", "study.toml", "--out", "relative", "--workers", "1"]


def _damaged_study(folder: Path, monkeypatch) -> list[str]:
    from floebreak.studies.design import expand, study_from_dict
    from floebreak.studies.runner import run_study

    spec = study_from_dict(tomllib.loads(STUDY))
    runs, members = expand(spec)
    run_study(spec, runs, members, folder / "study")
    cusps = folder / "study" / "runs" / "run-00000" / "cusps.parquet"
    cusps.write_bytes(cusps.read_bytes()[:300])  # truncated next to an intact summary.json
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    return ["study", str(folder / "study.toml"), "--out", str(folder / "study"), "--workers", "1"]


def _edited_summary_study(folder: Path, monkeypatch) -> list[str]:
    import json

    from floebreak.studies.design import expand, study_from_dict
    from floebreak.studies.runner import run_study

    spec = study_from_dict(tomllib.loads(STUDY))
    run_study(spec, *expand(spec), folder / "study")
    summary_file = folder / "study" / "runs" / "run-00000" / "summary.json"
    summary = json.loads(summary_file.read_text(encoding="utf-8"))
    summary_file.write_text(json.dumps({**summary, "n_cusps": 123456}), encoding="utf-8")  # files intact
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    return ["study", str(folder / "study.toml"), "--out", str(folder / "study"), "--workers", "1"]


def _failing_study(folder: Path, monkeypatch) -> list[str]:
    def broken(task):
        raise RuntimeError("worker lost")

    monkeypatch.setattr(importlib.import_module("floebreak.studies.runner"), "execute_run", broken)
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    return ["study", str(folder / "study.toml"), "--out", str(folder / "study"), "--workers", "1"]


ROWS = [
    Row(
        "non-finite number",
        "`run s.toml --set ice.youngs_modulus_pa=inf`",
        2,
        "error: ice.youngs_modulus_pa: Input should be a finite number (got inf)",
        _run("--set", "ice.youngs_modulus_pa=inf"),
    ),
    Row(
        "number outside its physical range",
        "`run s.toml --set field.length_m=1e9`",
        2,
        "error: field.length_m: Input should be less than or equal to 1000000 (got 1000000000.0) "
        "(allowed: [1, 1e+06])",
        _run("--set", "field.length_m=1e9"),
    ),
    Row(
        "failure-mode setting outside its range",
        "`run s.toml --set failure.bending.foundation_modulus_n_m3=-5`",
        2,
        "error: failure.bending.foundation_modulus_n_m3: Input should be greater than or equal to 1000 "
        "(got -5) (allowed: [1000, 100000])",
        _run("--set", "failure.bending.foundation_modulus_n_m3=-5"),
    ),
    Row(
        "concentration the generator cannot reach",
        "`run s.toml --set field.concentration=1.0`",
        2,
        "error: field.concentration: 1 (100 %) cannot be reached by 'circles': circular floes always leave "
        "gaps between them",
        _run("--set", "field.concentration=1.0"),
    ),
    Row(
        "non-finite option",
        "`field --out f.parquet --length inf`",
        2,
        "error: length: Input should be a finite number (got inf)",
        _field("--length", "inf"),
    ),
    Row(
        "unknown key",
        "`run s.toml --set ice.thicknes_m=1.0`",
        2,
        "error: ice.thicknes_m: unknown key (allowed: thickness_m, thickness_range_m,",
        _run("--set", "ice.thicknes_m=1.0"),
    ),
    Row(
        "bad row in a bow CSV file (file, row and line kept)",
        '`run s.toml` with `[ship] file = "bow.csv"`',
        2,
        "error: ship.file: <folder>/bow.csv, row 2 (line 3): has 2 values, the header has 3 columns",
        _bow_csv,
    ),
    Row(
        "bad value in a voyage log (file, row and column kept)",
        "`voyage log.csv --out voyage`",
        2,
        "log.csv, row 2 (line 3), column 'concentration_percent': 150 is outside (0, 100] %",
        _voyage_log,
    ),
    Row(
        "cusp transport setting outside its range (`propeller` and `voyage`)",
        "`voyage log.csv --out voyage --transport-parameter slip_factor=1.5`",
        2,
        "error: transport.slip_factor: 1.5 is outside (0, 1]",
        _voyage("--transport-parameter", "slip_factor=1.5"),
    ),
    Row(
        "unknown cusp transport setting",
        "`propeller run --out p --transport-parameter hull.draft_m=7`",
        2,
        "error: transport.hull.draft_m: unknown key (allowed: slip_factor, drag_coefficient,",
        lambda folder, _: [
            "propeller",
            str(folder / "run"),
            "--out",
            str(folder / "p"),
            "--transport-parameter",
            "hull.draft_m=7",
        ],
    ),
    Row(
        "polar class that does not exist (`propeller` and `voyage`)",
        "`voyage log.csv --out voyage --polar-class PC8`",
        2,
        "error: polar_class: unknown polar class 'PC8'",
        _voyage("--polar-class", "PC8"),
    ),
    Row(
        "fraction reaching outside (0, 1] (`propeller` and `voyage`)",
        "`voyage log.csv --out voyage --fraction-reaching 1.5`",
        2,
        "error: propeller.fraction_reaching: 1.5 is outside (0, 1]",
        _voyage("--fraction-reaching", "1.5"),
    ),
    Row(
        "unknown shaft line (`propeller` and `voyage`)",
        "`voyage log.csv --out voyage --shaft-line nowhere`",
        2,
        "error: shaft_line: 'nowhere' is neither a built-in line nor a TOML file",
        _voyage("--shaft-line", "nowhere"),
    ),
    Row(
        "bad field file (file, row and column named; also text ids or thickness, no rows, a bad `domain_m`, "
        "overlapping floes, a geographic CRS)",
        '`run s.toml` with `[field] file = "f.parquet"` (floe_id 4 twice)',
        2,
        "error: field.file: '<folder>/f.parquet', row 2, column 'floe_id': 4 repeats row 1",
        _field_file_with_repeated_id,
    ),
    Row(
        "concentration whose circles would cover more than the field (`floe_area_factor` below ¼)",
        "`run s.toml --set field.floe_area_factor=0.1`",
        2,
        "error: field.concentration: 0.44 (44 %) cannot be reached by 'circles' with "
        "field.floe_area_factor = 0.1: a floe of diameter d counts as 0.1·π d² but is placed as a circle "
        "(0.25·π d²), so the circles would have to cover 110 % of the field",
        _run("--set", "field.floe_area_factor=0.1"),
    ),
    Row(
        "field whose whole floes miss the concentration",
        "`run s.toml --set field.width_m=40`",
        2,
        "error: field.length_m: whole floes cannot give concentration 44 % (±1 pp) in this 60 m × 40 m "
        "field: its 12 floes (2 × 2.5 m, 5 × 7.5 m, 5 × 15 m, the observation's shares rounded to whole "
        "floes) cover 46.4 %",
        _run("--set", "field.width_m=40"),
    ),
    Row(
        "hull flare that folds the lower waterline",
        "`run s.toml --set ship.hull_parameters.shoulder_frame_angle_deg=89.999`",
        2,
        "error: ship.hull_parameters.shoulder_frame_angle_deg: 89.999° flares the hull side so much that",
        _run("--set", "ship.hull_parameters.shoulder_frame_angle_deg=89.999"),
    ),
    Row(
        "a setting that would make a count unbounded (wedge rays, thickness summands)",
        "`run s.toml --set failure.bending.wedge_angle_deg=0.001`",
        2,
        "error: failure.bending.wedge_angle_deg: Input should be greater than or equal to 1 (got 0.001) "
        "(allowed: [1, 60])",
        _run("--set", "failure.bending.wedge_angle_deg=0.001"),
    ),
    Row(
        "a field with no floe in the bow's path (e.g. UTM coordinates), refused before stepping",
        "`run s.toml` with one floe at y = 500 m",
        2,
        "error: field: no floe of the field lies in the bow's path",
        _far_field,
    ),
    Row(
        "voyage log separated by semicolons (decimal commas)",
        "`voyage log.csv --out voyage`",
        2,
        "log.csv, header (line 1): the columns are separated by semicolons, not by commas",
        _semicolon_log,
    ),
    Row(
        "existing run directory",
        "`run s.toml --out out` (out exists)",
        2,
        "error: out: '<folder>/out' exists (allowed: a new path, or overwrite=True (--overwrite))",
        _existing_run,
    ),
    Row(
        "existing field file",
        "`field --out f.parquet` (f.parquet exists)",
        2,
        "error: out: '<folder>/f.parquet' exists (allowed: a new path, or overwrite=True (--overwrite))",
        _existing_field,
    ),
    Row(
        "unknown figure format",
        "`field --out f.parquet --figure fig.xyz`",
        2,
        "error: figure: unknown figure format '.xyz' (allowed: avif, eps,",
        _field("--figure", "fig.xyz"),
    ),
    Row(
        "more pieces than the budget (thin ice)",
        "`run s.toml --set simulation.max_pieces=40`",
        2,
        "error: simulation.max_pieces: the ice breaks into more than 40 pieces",
        _run("--set", "simulation.max_pieces=40"),
    ),
    Row(
        "output on a pseudo file system (refused before the run)",
        "`run s.toml --out /proc/floebreak-run`",
        3,
        "error: cannot write '/proc/floebreak-run': No such file or directory",
        _pseudo_file_system,
    ),
    Row(
        "disk full while writing",
        "`run s.toml --out out` (ENOSPC)",
        3,
        "error: cannot write '<folder>/out': No space left on device",
        _disk_full,
    ),
    Row(
        "a study's runs failed",
        "`study study.toml --out study` (every run raises)",
        4,
        "1 of 1 runs failed (records in <folder>/study/failed/; running the study again retries them)",
        _failing_study,
    ),
    Row(
        "relative `--out` of a study (made absolute before it reaches a worker, local or Dask)",
        "`study study.toml --out relative`",
        0,
        "complete 1, failed 0: tables in <folder>/relative/tables",
        _relative_study_out,
    ),
    Row(
        "resuming a study with a damaged run (truncated `cusps.parquet`, intact `summary.json`)",
        "`study study.toml --out study` (again)",
        0,
        "failed 0, resumed 0",  # the damaged run is not trusted: run again
        _damaged_study,
    ),
    Row(
        "resuming a study with a hand-edited run `summary.json` (other files intact)",
        "`study study.toml --out study` (again)",
        0,
        "failed 0, resumed 0",  # the edited summary is not trusted: run again
        _edited_summary_study,
    ),
    Row(
        "Ctrl-C",
        "Ctrl-C during `run`",
        130,
        "interrupted (Ctrl-C); nothing half-written was kept",
        _interrupted,
    ),
    Row(
        "SIGTERM (e.g. a batch system's time limit)",
        "SIGTERM during `run`",
        143,
        "terminated (SIGTERM); nothing half-written was kept",
        _terminated,
    ),
    Row(
        "internal error (a bug)",
        "(none known)",
        1,
        "internal error: RuntimeError: a bug; scenario and traceback saved to "
        "<folder>/out.failed-scenario.toml — please report this bug",
        _bug,
    ),
]


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="the pseudo-file-system row needs Linux /proc")
@pytest.mark.parametrize("row", ROWS, ids=[row.kind for row in ROWS])
def test_bad_input_gives_its_exit_code_and_message(row, tmp_path, monkeypatch, cli):
    args = row.args(tmp_path, monkeypatch)
    before = {path: path.stat().st_mtime_ns for path in tmp_path.rglob("*")}
    code, out, err = cli(*args)
    # rich wraps long lines for an 80-column console, within words too: compared without white space
    text = "".join((out + err).split()).replace("".join(str(tmp_path).split()), "<folder>")
    assert code == row.code, err
    assert "".join(row.message.split()) in text, text
    if row.code in (2, 3, 130, 143):  # refused or stopped: nothing written, nothing half-written
        assert "Traceback" not in err
        assert {path: path.stat().st_mtime_ns for path in tmp_path.rglob("*")} == before


def markdown_table() -> str:
    lines = ["| what the user did | example | exit code | message (part) |", "|---|---|---|---|"]
    for row in ROWS:
        lines.append(f"| {row.kind} | {row.example} | {row.code} | `{row.message}` |")
    return "\n".join(lines)


def _readme_with_table(text: str) -> str:
    start, end = text.index(BEGIN) + len(BEGIN), text.index(END)
    return text[:start] + "\n" + markdown_table() + "\n" + text[end:]


def test_readme_shows_this_table():
    text = README.read_text(encoding="utf-8")
    assert text == _readme_with_table(text), "README.md's bad-input table is stale: run this file to write it"


if __name__ == "__main__":
    README.write_text(_readme_with_table(README.read_text(encoding="utf-8")), encoding="utf-8")
    sys.stdout.write(markdown_table() + "\n")
