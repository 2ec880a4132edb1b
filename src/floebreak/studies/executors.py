"""One executor interface for studies: a local process pool, or a Dask distributed cluster
(Dask is the optional extra ``floebreak[cluster]``).

`Executor.run(fn, items)` yields ``(item, result, error)`` as tasks finish, in completion order. `fn` must be
a module-level function (picklable); it receives one item and returns a small result. Large outputs never
travel back: each task writes its own run directory and returns its summary only.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Protocol

from floebreak.errors import InputError

SCHEDULER_TIMEOUT_S = 10.0


class Executor(Protocol):
    description: str

    def run(
        self, fn: Callable[[Any], Any], items: Iterable[Any]
    ) -> Iterator[tuple[Any, Any, BaseException | None]]: ...

    def close(self) -> None: ...


class SerialExecutor:
    """In-process, one task after the other (tests, debugging, `--workers 1`)."""

    description = "serial"

    def run(self, fn, items):
        for item in items:
            try:
                yield item, fn(item), None
            except Exception as error:  # a failing run is recorded; the study goes on
                yield item, None, error

    def close(self) -> None:
        pass


# Each worker runs one thread: the workers already occupy the cores, and a worker whose BLAS / OpenMP / numba
# started one thread per core oversubscribed them (a user's explicit setting is kept). Set before the worker
# imports numpy: this module imports none.
WORKER_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")


def one_thread_per_worker() -> None:
    """One BLAS / OpenMP / numba thread per worker process."""
    for name in WORKER_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


# A worker whose parent died (SIGKILL, the out-of-memory killer) would otherwise live on, holding its
# memory (≈ 370 MB with the modules a run imports): it polls its parent and ends itself.
PARENT_POLL_S = 0.5
EXIT_PARENT_GONE = 1


def exit_with_parent(parent_pid: int, poll_s: float = PARENT_POLL_S) -> threading.Thread:
    """End this process (exit code `EXIT_PARENT_GONE`, no clean-up: its run is half-done and runs are
    written atomically) as soon as its parent `parent_pid` is gone: a daemon thread compares
    ``os.getppid()`` with it every `poll_s` seconds (a dead parent's children are re-parented, to init or a
    subreaper). Portable: where ``getppid`` keeps a dead parent's id (Windows), it never fires. Not Linux's
    ``PR_SET_PDEATHSIG``: that fires when the parent's *thread* that started the worker ends, which is not
    the parent's death when a pool is created from a thread."""

    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(poll_s)
        os._exit(EXIT_PARENT_GONE)

    thread = threading.Thread(target=watch, name="floebreak-parent-watchdog", daemon=True)
    thread.start()
    return thread


def prepare_worker(parent_pid: int | None = None) -> None:
    """Worker initializer: exit with the parent (`exit_with_parent`, when `parent_pid` is given), one
    thread, then the modules a run imports (matplotlib for its figures) and the numba kernels loaded.

    Done here, at the pool's creation, a spawned worker's start overlaps the parent's own preparation
    (checking resumed runs, generating the common fields) instead of delaying its first run
    (benchmarks/README.md, parallel efficiency)."""
    if parent_pid is not None:
        exit_with_parent(parent_pid)
    one_thread_per_worker()
    # what `execute_run` imports, and the modules of the run's figures
    import floebreak.app.run
    import floebreak.plotting.field
    import floebreak.plotting.pattern
    import floebreak.plotting.spectra  # noqa: F401
    from floebreak.mechanics import compile_kernels

    compile_kernels()


def _worker_pid() -> int:
    return os.getpid()


class ProcessPoolExecutor:
    """A local pool of worker processes (default: one per core), started and prepared at creation."""

    def __init__(self, workers: int | None = None):
        self.workers = workers or os.cpu_count() or 1
        if self.workers < 1:
            raise InputError("workers", f"{workers} < 1", value=workers, allowed="an integer ≥ 1")
        self.description = f"local process pool ({self.workers} workers)"
        # spawn, not fork: forking a parent that runs threads (BLAS, rich's progress, a notebook's kernel)
        # can deadlock the child; the start this costs is overlapped with the parent's work instead
        # (benchmarks/README.md, parallel efficiency)
        # the parent's id is passed, not read in the worker: a parent killed before the worker starts is
        # noticed too. multiprocessing's resource tracker needs nothing: it ends when the last process
        # holding its pipe (the parent and the workers) is gone
        self._pool = cf.ProcessPoolExecutor(
            self.workers,
            mp_context=multiprocessing.get_context("spawn"),
            initializer=prepare_worker,
            initargs=(os.getpid(),),
        )
        before = set(multiprocessing.active_children())
        for _ in range(self.workers):  # the pool spawns a worker per submitted task: start them all now
            self._pool.submit(_worker_pid)
        self._processes = [p for p in multiprocessing.active_children() if p not in before]

    def run(self, fn, items):
        futures = {self._pool.submit(fn, item): item for item in items}
        for future in cf.as_completed(futures):
            item = futures[future]
            error = future.exception()
            yield item, (None if error else future.result()), error

    def close(self) -> None:
        """Shut the pool down: after the last run, wait for the workers to end; while Ctrl-C or SIGTERM
        unwinds (this is called from a ``finally``), end them at once instead of letting each finish its
        run (runs are written atomically: an ended run leaves nothing half-written, and is run again on
        resume)."""
        if isinstance(sys.exc_info()[1], KeyboardInterrupt):
            for process in self._processes:
                if process.is_alive():
                    process.terminate()
            self._pool.shutdown(wait=True, cancel_futures=True)
            return
        self._pool.shutdown(cancel_futures=True)


class DaskExecutor:
    """Dask distributed: ``address = "local"`` starts a LocalCluster, else ``tcp://host:port`` connects."""

    def __init__(self, address: str, workers: int | None = None, timeout_s: float = SCHEDULER_TIMEOUT_S):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise InputError(
                "scheduler",
                f"{address!r} needs Dask distributed, which is not installed",
                value=address,
                allowed="no --scheduler (local process pool), or install the extra: "
                "pip install 'floebreak[cluster]'",
            ) from None
        self._cluster = None
        if address == "local":
            self._cluster = LocalCluster(
                n_workers=workers or os.cpu_count() or 1,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
            )
            self._client = Client(self._cluster)
        else:
            try:
                self._client = Client(address, timeout=timeout_s)
            except (OSError, TimeoutError) as error:
                raise InputError(
                    "scheduler",
                    f"cannot reach the Dask scheduler at {address!r} within {timeout_s:g} s ({error})",
                    value=address,
                    allowed="tcp://HOST:PORT of a running `dask scheduler`, or 'local'",
                ) from None
        self.description = f"dask distributed ({address})"

    def run(self, fn, items):
        from distributed import as_completed

        items = list(items)
        futures = self._client.map(fn, items, pure=False)
        index = {future.key: item for future, item in zip(futures, items, strict=True)}
        for future in as_completed(futures):
            item = index[future.key]
            if future.status == "error":
                yield item, None, future.exception()
            else:
                yield item, future.result(), None

    def close(self) -> None:
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def make_executor(workers: int | None = None, scheduler: str | None = None) -> Executor:
    if scheduler:
        return DaskExecutor(scheduler, workers)
    if workers == 1:
        return SerialExecutor()
    return ProcessPoolExecutor(workers)
