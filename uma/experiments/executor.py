"""One executor interface over local processes and a Dask cluster.

`executor.map_unordered(fn, tasks)` yields `fn(task)` for every task as each finishes. Locally
that is a `concurrent.futures.ProcessPoolExecutor` (spawned processes: no state inherited from
the parent's threads); with a scheduler address, a `distributed.Client`, `client.map(fn, tasks,
pure=False)` and `distributed.as_completed`. Dask is imported only when a scheduler is given.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import Any, Protocol

from uma.errors import ConfigError

__all__ = ["Executor", "LocalExecutor", "DaskExecutor", "make_executor"]


class Executor(Protocol):
    workers: int

    def map_unordered(self, fn: Callable[[Any], Any], tasks: Iterable[Any]) -> Iterator[Any]: ...

    def close(self) -> None: ...


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
                max_workers=self.workers, mp_context=multiprocessing.get_context("spawn")
            )
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


class DaskExecutor:
    """Tasks on the Dask cluster whose scheduler listens at `address` (`tcp://host:port`)."""

    def __init__(self, address: str, *, timeout_s: float = 10.0) -> None:
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


def make_executor(
    *, workers: int | None = None, scheduler: str | None = None, timeout_s: float = 10.0
) -> Executor:
    """Dask when `scheduler` is an address, else local processes (default: 2, this machine's cores)."""
    if scheduler:
        return DaskExecutor(scheduler, timeout_s=timeout_s)
    import os

    return LocalExecutor(workers if workers is not None else min(2, os.cpu_count() or 1))
