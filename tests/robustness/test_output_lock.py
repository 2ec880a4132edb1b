"""One writer per --out: while one command holds the output's lock, a second `run` (or `propeller`) on the
same --out, even with --overwrite, is refused at once (exit 2) and the first one's output is untouched."""

from __future__ import annotations

import multiprocessing

import pytest

from floebreak.errors import InputError
from floebreak.io.output_lock import lock_path, output_lock


def _hold(out, ready, release):
    with output_lock(out):
        ready.set()
        release.wait(30)


@pytest.fixture
def held_elsewhere(tmp_path):
    """The lock of tmp_path/out held by another process (flock locks are per open file, so a second
    process is the honest test)."""
    out = tmp_path / "out"
    context = multiprocessing.get_context("fork")
    ready, release = context.Event(), context.Event()
    holder = context.Process(target=_hold, args=(out, ready, release))
    holder.start()
    assert ready.wait(30)
    yield out
    release.set()
    holder.join(30)


def test_a_second_run_on_a_locked_out_is_refused(cli, held_elsewhere):
    out = held_elsewhere
    code, stdout, err = cli(
        "run", "examples/reference.toml", "--set", "field.length_m=40", "--out", out, "--overwrite", "-q"
    )
    assert code == 2, err
    assert "is being written by another floebreak process" in err
    assert "written" not in stdout
    assert not out.exists()


def test_a_second_propeller_on_a_locked_out_is_refused(cli, held_elsewhere, small_run_dir):
    code, _, err = cli("propeller", small_run_dir, "--out", held_elsewhere, "--overwrite", "-q")
    assert code == 2, err
    assert "is being written by another floebreak process" in err


def test_the_lock_is_released_and_its_file_removed(tmp_path):
    out = tmp_path / "out"
    with output_lock(out):
        assert lock_path(out).exists()
    assert not lock_path(out).exists()
    with output_lock(out):  # free again
        pass


def test_a_lock_is_exclusive_across_processes(held_elsewhere):
    with pytest.raises(InputError, match="another floebreak process"):
        with output_lock(held_elsewhere):
            pass
