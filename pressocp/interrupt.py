"""Ctrl-C through CasADi: SUNDIALS and IPOPT run in C++ and poll Python for signals; CasADi turns a
KeyboardInterrupt raised there into an integrator failure or IPOPT's "User_Requested_Stop". Inside
`interruptible` a SIGINT is remembered, and `interruptible` raises `KeyboardInterrupt` when the call
returns, so a Ctrl-C always stops the program instead of becoming a failed or stopped result.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from .compile_cache import compile_interrupted, compile_statuses


@contextmanager
def sigint_held() -> Iterator[None]:
    """Within the block SIGINT is blocked in the calling thread, and so in every process it starts (a
    blocked signal stays blocked across fork and exec). A SIGINT that arrives meanwhile is not lost: it
    waits, and this thread receives it when the block ends (another thread of the process may take it
    at once). A child receives it when it unblocks SIGINT, which the workers of
    `pressocp.workers.process_pool` do once their handler is installed (``/bin/sh`` clears the mask
    at its start, so a command run through ``system()`` is not protected). No-op where the platform
    has no signal masks."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextmanager
def interrupt_deferred() -> Iterator[None]:
    """Ctrl-C held back while the block runs: a SIGINT that arrives meanwhile raises `KeyboardInterrupt`
    when the block ends (as it does in Python code, whichever thread the kernel delivered it to).
    Outside the main thread, or where SIGINT is ignored, it changes nothing."""
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous in (signal.SIG_IGN, None):
        yield
        return
    hit: list = []
    signal.signal(signal.SIGINT, lambda signum, frame: hit.append(True))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if hit:
        raise KeyboardInterrupt


#: CasADi's errors for a compile or link command that did not exit with 0.
COMPILE_FAILURES = ("Compilation failed", "Linking failed")


def killed_before_it_ran(error: RuntimeError, before: int) -> bool:
    """Whether `error` is a compile or link command's failure (`COMPILE_FAILURES`) whose command never
    recorded an exit code: none of the codes recorded since the first `before` ones
    (`pressocp.compile_cache.compile_statuses`) is the failure. The command's shell was then killed
    before it ran the caching compiler, in its first milliseconds, before its trap of SIGINT was set:
    by a Ctrl-C that reached the whole process group, which CasADi's ``system()`` hid from this
    process."""
    if not any(text in str(error) for text in COMPILE_FAILURES):
        return False
    since = compile_statuses()[before:]
    return not since or since[-1] == 0


@contextmanager
def compiling() -> Iterator[None]:
    """Around a CasADi call that may run the C compiler (a JIT function's construction, or an NLP's
    whose derivatives are compiled): a Ctrl-C that stopped the compile, which the caller cannot see
    (`pressocp.compile_cache.compile_interrupted`, or a compile killed before it ran:
    `killed_before_it_ran`), raises `KeyboardInterrupt`, whether the call failed ("Compilation
    failed", "Linking failed") or returned."""
    before = len(compile_statuses())
    try:
        yield
    except RuntimeError as err:
        if compile_interrupted() or killed_before_it_ran(err, before):
            raise KeyboardInterrupt from None
        raise
    if compile_interrupted():
        raise KeyboardInterrupt


@contextmanager
def interruptible() -> Iterator[list]:
    """Context manager around one CasADi call: yields a list that holds True once SIGINT arrived;
    on leaving, raises `KeyboardInterrupt` if it did (also when the call raised something else).

    Outside the main thread, or where SIGINT is ignored, it changes nothing."""
    hit: list = []
    if compile_interrupted():  # a Ctrl-C during a compile before this call (see `compile_interrupted`)
        raise KeyboardInterrupt
    if threading.current_thread() is not threading.main_thread():
        yield hit
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous in (signal.SIG_IGN, None):
        yield hit
        return

    def handler(signum, frame):
        hit.append(True)
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, handler)
    try:
        yield hit
    except Exception:
        if hit:
            raise KeyboardInterrupt from None
        raise
    finally:
        signal.signal(signal.SIGINT, previous)
    if hit or compile_interrupted():
        raise KeyboardInterrupt
