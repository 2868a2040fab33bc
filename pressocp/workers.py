"""Worker processes that own their cores: a process pool whose workers run one native thread each.

IPOPT (MUMPS) is not safe in threads, so the package parallelises solves and simulations over
processes. Each worker's BLAS/OpenMP pools would otherwise start a thread per core and *n* workers
would fight over the cores (measured: 8 simulations on 2 workers took as long as on 1). The workers
are spawned (a fresh interpreter: no forked native thread state) with the thread-count variables
below set to 1 unless the user set them.

Ctrl-C in a terminal reaches the workers too. A worker running a task raises `KeyboardInterrupt`
there (its caller receives it from the task's future); an idle worker, or one still starting, ignores
it and ends when the pool is shut down: no traceback of a worker reaches the user. Shutting the pool
down with ``cancel_futures=True`` also interrupts the tasks still running, whose results nobody will
read (a Ctrl-C sent to the main process alone, as a notebook's interrupt button does).
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from .interrupt import interrupt_deferred, sigint_held

#: Set (to "1") in every worker of `process_pool`: a worker owns one core and starts no pool of its own.
WORKER_ENV = "PRESSOCP_WORKER"
#: Environment variables that cap the native thread pools of a worker.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                    "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")

#: glibc's malloc settings of a worker: large blocks stay in the heap instead of being mapped and
#: unmapped at every use, and the heap is not trimmed. MUMPS allocates its work arrays anew at every
#: factorisation; with them, the 75 spm seed's no-reversal and target stages in one process took 24.1
#: against 25.5 s (target 13.0 against 13.8 s), the system time 0.4 against 1.9 s and the page faults
#: 85 000 against 1.2 million, the same answer to the last digit (neither setting alone helped).
MALLOC_VARIABLES = {"MALLOC_MMAP_THRESHOLD_": "4000000000", "MALLOC_TRIM_THRESHOLD_": "4000000000"}


def in_worker() -> bool:
    """Whether this process is a worker of `process_pool` (it then runs its tasks one at a time)."""
    return os.environ.get(WORKER_ENV) == "1"


def parallel_workers(requested: int) -> int:
    """How many worker processes a task here may start: `requested`, or 1 (none: run here) inside a
    worker, whose pool already gives every core a process."""
    return 1 if in_worker() else requested


@contextmanager
def single_threaded_children() -> Iterator[None]:
    """Within the block, processes started inherit one native thread each (`THREAD_VARIABLES` = 1 where
    the user has not set them), the worker's malloc settings (`MALLOC_VARIABLES`, where not set) and
    are marked as workers (`WORKER_ENV`); the parent's environment is restored afterwards."""
    values = {**{k: "1" for k in (*THREAD_VARIABLES, WORKER_ENV)}, **MALLOC_VARIABLES}
    added = [k for k in values if k not in os.environ]
    os.environ.update({k: values[k] for k in added})
    try:
        yield
    finally:
        for k in added:
            os.environ.pop(k, None)


@contextmanager
def main_module_hidden() -> Iterator[None]:
    """Within the block, processes spawned do not import the parent's ``__main__``: a script that
    optimises at its top level, with no ``if __name__ == "__main__":`` guard, would otherwise run again
    in every worker. The pool's tasks are functions of installed modules, so no worker needs it."""
    main = sys.modules.get("__main__")
    saved = {k: main.__dict__[k] for k in ("__file__", "__spec__") if main is not None and k in main.__dict__}
    if main is not None:
        main.__dict__.pop("__file__", None)
        main.__spec__ = None
    try:
        yield
    finally:
        if main is not None:
            main.__dict__.update(saved)


def die_with_parent(parent: int) -> None:
    """A worker's initializer: the worker ends when the process that started it dies, even by SIGKILL,
    instead of computing on as an orphan (Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``; elsewhere a
    worker notices only when it next reads from its pool). A worker whose parent died before this ran
    ends at once."""
    if sys.platform.startswith("linux"):
        import ctypes
        import signal

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1 = PR_SET_PDEATHSIG
    if os.getppid() != parent:
        os._exit(1)


class TaskState:
    """Whether this worker process runs a task now (`run_task`), read by its SIGINT handler."""

    busy = False


def run_task(fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Any:
    """``fn(*args, **kwargs)`` in a worker, marked busy meanwhile: a SIGINT then interrupts it."""
    TaskState.busy = True
    try:
        return fn(*args, **kwargs)
    finally:
        TaskState.busy = False


def interrupt_task(signum: int, frame: Any) -> None:
    """A worker's SIGINT handler: `KeyboardInterrupt` in the task it runs; ignored while idle."""
    if TaskState.busy:
        raise KeyboardInterrupt


def worker_started(parent: int) -> None:
    """A worker's initializer: it ends with its parent (`die_with_parent`), and Ctrl-C interrupts its
    tasks only (`interrupt_task`). The worker was started with SIGINT held (`WorkerPool.submit`); a
    SIGINT that came during its start-up is delivered once the handler is in place, and ignored."""
    die_with_parent(parent)
    signal.signal(signal.SIGINT, interrupt_task)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


class WorkerPool(ProcessPoolExecutor):
    """A `ProcessPoolExecutor` whose workers stop their task on Ctrl-C and are otherwise quiet (see the
    module's docstring); made by `process_pool`."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        """As `ProcessPoolExecutor.submit`. A worker started here (the pool starts them on demand)
        runs one native thread (`single_threaded_children`), does not import ``__main__``
        (`main_module_hidden`) and begins with SIGINT held until its handler is installed
        (`worker_started`). A Ctrl-C meanwhile raises `KeyboardInterrupt` once the worker has its
        start-up data (`interrupt_deferred`): holding SIGINT in this thread does not stop another
        thread from taking it, and raised between the worker's start and the write of that data it
        would leave the worker to die with a traceback."""
        with interrupt_deferred(), single_threaded_children(), main_module_hidden(), sigint_held():
            return super().submit(run_task, fn, *args, **kwargs)

    def interrupt(self) -> None:
        """Send SIGINT to every live worker: running tasks raise `KeyboardInterrupt`, idle workers
        ignore it."""
        for process in list((self._processes or {}).values()):  # ProcessPoolExecutor's own table
            try:
                if process.is_alive():
                    os.kill(process.pid, signal.SIGINT)
            except (OSError, ValueError):  # ended meanwhile
                pass

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """As `ProcessPoolExecutor.shutdown`; with `cancel_futures` the running tasks are interrupted
        too (`interrupt`), so a shutdown after Ctrl-C or an error does not wait for their ends."""
        if cancel_futures:
            self.interrupt()
        super().shutdown(wait=wait, cancel_futures=cancel_futures)


def process_pool(workers: int, start: int | None = None) -> WorkerPool:
    """A pool of at most `workers` spawned processes, one native thread each (`single_threaded_children`),
    that do not import the parent's ``__main__`` (`main_module_hidden`): its tasks must be functions
    of installed modules, that end when this process dies (`die_with_parent`), and whose tasks, not
    the workers themselves, a Ctrl-C interrupts (`WorkerPool`). `start` of them (default all) are
    started here, and import pressocp while the caller goes on; the others start when a task finds no
    idle worker."""
    pool = WorkerPool(workers, mp_context=multiprocessing.get_context("spawn"),
                      initializer=worker_started, initargs=(os.getpid(),))
    for _ in range(workers if start is None else min(start, workers)):
        pool.submit(os.getpid)
    return pool
