"""`pressocp.workers`: spawned workers run one native thread each, and a script with no main guard
is not run again in them."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

import pressocp.workers as workers
from pressocp.workers import THREAD_VARIABLES, WORKER_ENV, parallel_workers, process_pool


def thread_settings():
    return {k: os.environ.get(k) for k in (*THREAD_VARIABLES, WORKER_ENV)}


def workers_allowed():
    return parallel_workers(4)


def test_workers_run_one_native_thread_and_the_parent_keeps_its_environment(monkeypatch):
    for k in THREAD_VARIABLES:
        monkeypatch.delenv(k, raising=False)
    monkeypatch.setenv("MKL_NUM_THREADS", "3")  # a user's own setting is kept
    monkeypatch.delenv(WORKER_ENV, raising=False)
    pool = process_pool(1)
    try:
        seen = pool.submit(thread_settings).result()
        nested = pool.submit(workers_allowed).result()
    finally:
        pool.shutdown()
    assert seen["OMP_NUM_THREADS"] == "1" and seen["OPENBLAS_NUM_THREADS"] == "1" and seen["MKL_NUM_THREADS"] == "3"
    assert "OMP_NUM_THREADS" not in os.environ and os.environ["MKL_NUM_THREADS"] == "3"
    # a worker starts no pool of its own (a sweep's worker runs an optimum's candidates one by one)
    assert seen[WORKER_ENV] == "1" and nested == 1 and parallel_workers(4) == 4 and WORKER_ENV not in os.environ


def test_a_script_without_a_main_guard_runs_once(tmp_path):
    script = tmp_path / "unguarded.py"
    script.write_text(textwrap.dedent("""
        import os
        from pressocp.workers import process_pool
        print("top level ran", flush=True)
        pool = process_pool(2)
        print(sorted({pool.submit(os.getpid).result() for _ in range(4)}) != [os.getpid()], flush=True)
        pool.shutdown()
    """))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.count("top level ran") == 1 and "True" in out.stdout


def test_a_cancelling_shutdown_interrupts_the_running_task():
    """A shutdown with cancel_futures=True (after Ctrl-C in the main process alone, as a notebook's
    interrupt button sends it) interrupts the task still running instead of waiting for it."""
    pool = process_pool(1)
    try:
        assert pool.submit(os.getpid).result() != os.getpid()  # the worker is up
        running = pool.submit(time.sleep, 600)
        while not running.running():
            time.sleep(0.05)
        time.sleep(0.5)  # the worker has taken the task (running() is set as it is queued)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    with pytest.raises(KeyboardInterrupt):
        running.result()


def test_a_terminal_ctrl_c_leaves_idle_and_starting_workers_quiet(tmp_path):
    """Ctrl-C reaches every process of the terminal's group: workers that are starting (SIGINT held
    until their handler is in place) and idle workers ignore it, print no traceback and go on
    serving; the main process gets its KeyboardInterrupt."""
    script = tmp_path / "ctrl_c.py"
    script.write_text(textwrap.dedent("""
        import os, signal, time
        from pressocp.workers import process_pool
        if __name__ == "__main__":
            pool = process_pool(2)
            caught = 0
            for pause in (0.0, 3.0):  # while the workers start; then while they wait idle
                time.sleep(pause)
                try:
                    os.killpg(0, signal.SIGINT)
                    time.sleep(5)
                except KeyboardInterrupt:
                    caught += 1
            pids = {pool.submit(os.getpid).result() for _ in range(6)}
            pool.shutdown()
            print("caught", caught, "served", os.getpid() not in pids, flush=True)
    """))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, cwd=tmp_path,
                         start_new_session=True)
    assert out.returncode == 0, out.stderr
    assert "caught 2 served True" in out.stdout
    assert "Traceback" not in out.stderr and "KeyboardInterrupt" not in out.stderr, out.stderr


def test_a_ctrl_c_while_a_worker_starts_is_raised_once_it_has_started(monkeypatch):
    """A SIGINT whose handler runs in the middle of starting a worker (here: called there, as Python
    calls it in the main thread whichever thread the kernel gave the signal to) does not interrupt
    the start; `KeyboardInterrupt` comes after it, and the worker runs its task."""
    steps, start = [], workers.ProcessPoolExecutor.submit

    def interrupted_submit(self, fn, *args, **kwargs):
        signal.getsignal(signal.SIGINT)(signal.SIGINT, None)  # Ctrl-C arrives now
        steps.append("started")
        return start(self, fn, *args, **kwargs)

    pool = process_pool(1, start=0)
    try:
        monkeypatch.setattr(workers.ProcessPoolExecutor, "submit", interrupted_submit)
        with pytest.raises(KeyboardInterrupt):
            pool.submit(os.getpid)
        assert steps == ["started"]
        monkeypatch.undo()
        assert pool.submit(os.getpid).result(timeout=60) != os.getpid()
    finally:
        pool.shutdown(cancel_futures=True)
