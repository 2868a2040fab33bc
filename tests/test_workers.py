"""`pressocp.workers`: spawned workers run one native thread each, and a script with no main guard
is not run again in them."""

import os
import subprocess
import sys
import textwrap

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
