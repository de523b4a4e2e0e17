"""One executor interface over local processes and a Dask cluster.

`executor.map_unordered(fn, tasks)` yields `fn(task)` for every task as each finishes. Locally
that is a `concurrent.futures.ProcessPoolExecutor` (spawned processes: no state inherited from
the parent's threads) that end with their parent: on Linux the kernel kills each when the
parent dies (`PR_SET_PDEATHSIG`), and everywhere a thread in each polls the parent's pid, so a
SIGKILLed sweep leaves no worker behind. `terminate()` ends the workers at once (a SIGTERM or
Ctrl-C of the sweep). With a scheduler address: a `distributed.Client` after
`uma.experiments.scheduler.check_scheduler` has seen a Dask greeting there within the timeout,
then `client.map(fn, tasks, pure=False)` and `distributed.as_completed`. Dask is imported only
when a scheduler is given.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any, Protocol

from uma.errors import ConfigError

_PARENT_POLL_S = 0.5
_PR_SET_PDEATHSIG = 1  # linux/prctl.h

__all__ = ["Executor", "LocalExecutor", "DaskExecutor", "make_executor", "end_with_parent"]


class Executor(Protocol):
    workers: int

    def map_unordered(self, fn: Callable[[Any], Any], tasks: Iterable[Any]) -> Iterator[Any]: ...

    def close(self) -> None: ...

    def terminate(self) -> None: ...


def end_with_parent(parent_pid: int) -> None:
    """Worker initializer: this process exits when process `parent_pid` is no longer its parent."""
    import signal
    import threading
    import time

    if sys.platform.startswith("linux"):
        import ctypes

        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass  # the polling thread below still ends this worker
    if os.getppid() != parent_pid:  # the parent died before the watch was set
        os._exit(1)
    # Ctrl-C reaches the whole process group: the parent decides (it ends the workers), a
    # worker interrupted while it waits for work would print a traceback of its own. It was
    # spawned with SIGINT and SIGTERM blocked (`_signals_held`): a held Ctrl-C is dropped.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, (signal.SIGINT, signal.SIGTERM))

    def watch() -> None:
        while True:
            time.sleep(_PARENT_POLL_S)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="uma-parent-watch", daemon=True).start()


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM until the block ends, then deliver them to their own handlers.

    They are also blocked in this thread, so a worker spawned inside the block starts with
    them blocked (a mask survives `exec`): a Ctrl-C to the whole group while the worker is
    still importing waits until its initializer ignores it (`end_with_parent`).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    held = (signal.SIGINT, signal.SIGTERM)
    previous = {number: signal.signal(number, lambda n, _f: caught.append(n)) for number in held}
    blocking = hasattr(signal, "pthread_sigmask")
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, held) if blocking else None
    try:
        yield
    finally:
        if blocking:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # what came is caught here
        for number, handler in previous.items():
            signal.signal(number, handler)
        for number in dict.fromkeys(caught):
            signal.raise_signal(number)


@contextlib.contextmanager
def _quiet_pool_breaking() -> Iterator[None]:
    """While the workers are killed, a pool's manager thread that marks the already cancelled
    futures broken (CPython 3.11's `terminate_broken` sets an exception on each) raises
    `InvalidStateError`, and the thread's traceback would follow the sweep's one line. That
    exception alone is dropped; any other still reaches the previous hook."""
    from concurrent.futures import InvalidStateError

    previous = threading.excepthook

    def hook(args) -> None:
        if not issubclass(args.exc_type, InvalidStateError):
            previous(args)

    threading.excepthook = hook
    try:
        yield
    finally:
        threading.excepthook = previous


class LocalExecutor:
    """`workers` processes on this machine (1: one worker process, still apart from the caller)."""

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise ConfigError(f"--workers: expected a positive integer, got {workers}")
        self.workers = workers
        self._pool = None

    def map_unordered(self, fn, tasks):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor, as_completed

        tasks = list(tasks)
        if not tasks:
            return
        if self._pool is None:
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=multiprocessing.get_context("spawn"),
                initializer=end_with_parent,
                initargs=(os.getpid(),),
            )
        # Submitting spawns the workers; a signal handler that raised half-way through writing a
        # worker's start-up data would leave it printing an EOFError traceback.
        with _signals_held():
            futures = [self._pool.submit(fn, task) for task in tasks]
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:
            for future in futures:
                future.cancel()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def terminate(self) -> None:
        """End the workers now, running tasks and all (their results are lost)."""
        if self._pool is None:
            return
        # The pool has no public way to stop a running task; its processes are in `_processes`.
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        with _quiet_pool_breaking():
            for process in processes:
                process.kill()
            for process in processes:
                process.join(5.0)
            self._pool.shutdown(wait=True, cancel_futures=True)  # joins its manager thread
        self._pool = None


class DaskExecutor:
    """Tasks on the Dask cluster whose scheduler listens at `address` (`tcp://host:port`)."""

    def __init__(self, address: str, *, timeout_s: float = 10.0) -> None:
        from uma.experiments.scheduler import check_scheduler

        check_scheduler(address, timeout_s=timeout_s)
        from distributed import Client

        try:
            self._client = Client(address, timeout=f"{timeout_s}s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as err:
            raise ConfigError(
                f"--scheduler: cannot reach a Dask scheduler at {address!r} ({err})"
            ) from None
        self.workers = max(1, sum(self._client.nthreads().values()))

    def map_unordered(self, fn, tasks):
        from distributed import as_completed

        tasks = list(tasks)
        if not tasks:
            return
        futures = self._client.map(fn, tasks, pure=False)
        try:
            done = as_completed(futures, loop=self._client.loop, with_results=True)
            for _future, result in done:
                yield result
        finally:
            self._client.cancel(futures)

    def close(self) -> None:
        self._client.close()

    def terminate(self) -> None:
        """Leave the cluster: this client's tasks are cancelled as it disconnects."""
        self.close()


def make_executor(
    *, workers: int | None = None, scheduler: str | None = None, timeout_s: float = 10.0
) -> Executor:
    """Dask when `scheduler` is an address, else local processes (default: 2, this machine's cores)."""
    if scheduler:
        return DaskExecutor(scheduler, timeout_s=timeout_s)
    return LocalExecutor(workers if workers is not None else min(2, os.cpu_count() or 1))
