"""The console entry point alone changes the garbage collector: a test process or a script that
calls `floebreak.cli.main` runs with Python's defaults."""

from __future__ import annotations

import gc
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_the_command_line_in_process_keeps_the_collector_defaults(tmp_path, monkeypatch, capsys):
    from floebreak.cli import main

    threshold, frozen = gc.get_threshold(), gc.get_freeze_count()
    calls = []
    args = ["floebreak", "run", str(EXAMPLES / "single_floe.toml"), "--out", str(tmp_path / "run"), "-q"]
    monkeypatch.setattr(sys, "argv", args)
    try:
        main(engine_loaded=lambda: calls.append("loaded"))
    except SystemExit as exit_:
        assert not exit_.code, capsys.readouterr().err
    assert (tmp_path / "run" / "summary.json").is_file()
    assert calls == ["loaded"]  # the hook, once the engine is imported
    assert gc.get_threshold() == threshold and gc.get_freeze_count() == frozen
    monkeypatch.setattr(sys, "argv", [*args[:4], str(tmp_path / "again"), "-q"])
    try:
        main()  # without a hook (as tests call it): nothing frozen
    except SystemExit as exit_:
        assert not exit_.code
    assert gc.get_threshold() == threshold and gc.get_freeze_count() == frozen


def test_the_console_command_sets_the_lazier_collector():
    code = (
        "import gc, sys\n"
        "sys.argv = ['floebreak', 'observations']\n"
        "from floebreak.__main__ import main\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print(gc.get_threshold())\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "(50000, 20, 10)"
    # and a plain interpreter has Python's default, which the test above compares against
    assert gc.get_threshold() != (50000, 20, 10)
