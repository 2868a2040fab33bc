"""Ctrl-C stops a solve: a real SIGINT sent to a child process while IPOPT iterates, and while CVODES
integrates, ends the program with KeyboardInterrupt instead of a returned result.

The IPOPT case solves without JIT: a SIGINT sent to the process alone while CasADi runs the C
compiler is lost (POSIX ``system()`` ignores SIGINT in its caller), so with compiled functions the
signal could land in a compile and the solve return (seen under load in CI). A terminal's Ctrl-C
reaches the compiler's process too, which records it for the caller (tested below)."""

import os
import shlex
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

CHILD = """
import signal, sys, time
signal.signal(signal.SIGINT, signal.default_int_handler)  # as in an interactive session
import pressocp as po
if sys.argv[1] == "ipopt":
    problem = po.SpeedProblem(po.PressParams(), period=0.8)
    print("solving", flush=True)
    po.Rigid(samples=20000, jit=False, ipopt={"ipopt.max_iter": 3000}).solve(problem)
else:
    model = po.build_model(po.PressParams())
    print("solving", flush=True)
    po.simulate(model, po.FourierSpeed.constant(0.8), cycles=200, integrator=po.Integrator("cvodes", rtol=1e-10))
print("returned", flush=True)
"""


@pytest.mark.parametrize("where", ["ipopt", "cvodes"])
def test_ctrl_c_raises_keyboard_interrupt(where):
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-c", CHILD, where], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    try:
        assert proc.stdout.readline().strip() == "solving"
        time.sleep(3.0)
        assert proc.poll() is None, "the solve finished before the interrupt"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=600)  # a guard against a hang, not a measurement
    finally:
        if proc.poll() is None:
            proc.kill()
    assert "returned" not in out
    assert "KeyboardInterrupt" in err, err[-2000:]
    assert proc.returncode != 0


def test_a_ctrl_c_during_a_compile_is_not_lost(tmp_path):
    """CasADi runs the compiler through system(), which ignores SIGINT in the caller; the caching
    compiler (pressocp/jitcc.py) records a SIGINT in the caller's flag file and exits 130, and
    `compiling` turns the flag into KeyboardInterrupt, whether the CasADi call failed or returned."""
    from pressocp import compile_cache
    from pressocp.interrupt import compiling

    flag = tmp_path / "interrupted"
    script = Path(compile_cache.__file__).with_name("jitcc.py")
    env = {**os.environ, compile_cache.INTERRUPT_ENV: str(flag)}
    proc = subprocess.Popen([sys.executable, "-s", str(script), str(tmp_path / "cache"), "sleep", "30"], env=env,
                            start_new_session=True)
    try:
        time.sleep(1.0)
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C reaches the whole group
        assert proc.wait(timeout=120) == 130 and flag.exists()  # timeout: a guard against a hang
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    own = compile_cache.interrupt_flag()
    for failed in (False, True):
        own.write_text("")
        with pytest.raises(KeyboardInterrupt):
            with compiling():
                if failed:
                    raise RuntimeError("Compilation failed")
        assert not own.exists()
    with pytest.raises(RuntimeError, match="not a compile"):  # no flag: the error stands
        with compiling():
            raise RuntimeError("not a compile")


@pytest.mark.skipif(os.name != "posix" or shutil.which("cc") is None and shutil.which("gcc") is None,
                    reason="needs /bin/sh and a C compiler")
def test_a_compile_killed_before_its_shell_set_its_trap_is_a_ctrl_c(tmp_path, monkeypatch):
    """A Ctrl-C in the compile shell's first milliseconds, before its trap of SIGINT is set, kills the
    shell: CasADi reports "Compilation failed" and its system() hid the signal from this process. Here
    the shell sends itself SIGINT before the trap. No exit code was recorded for that command, so
    `compiling` raises KeyboardInterrupt. A compiler that runs and fails records its code, and its
    error stands; so does a failure after other compiles succeeded."""
    import casadi as ca

    from pressocp import compile_cache
    from pressocp.interrupt import compiling

    monkeypatch.setenv(compile_cache.CACHE_ENV, str(tmp_path / "cache"))
    options = compile_cache.jit_options()
    command = options["jit_options"]["compiler"]
    script = Path(compile_cache.__file__).with_name("jitcc.py")
    failing = compile_cache.RECORD_INTERRUPT + " ".join(
        shlex.quote(str(a)) for a in (sys.executable, "-I", "-S", script, compile_cache.NO_CACHE, "false"))
    x = ca.SX.sym("x")

    def build(name: str, compiler: str) -> ca.Function:
        jit = {**options["jit_options"], "compiler": compiler}
        return ca.Function(name, [x], [ca.sin(x) * x], {**options, "jit_options": jit})

    with pytest.raises(KeyboardInterrupt):
        with compiling():
            build("killed_at_start", "kill -INT $$; " + command)
    with pytest.raises(RuntimeError, match="Compilation failed"):
        with compiling():
            build("fails", failing)
    with compiling():  # a compile that works: its code is recorded, nothing is raised
        assert float(build("works", command)(2.0)) == pytest.approx(2.0 * np.sin(2.0))
    assert compile_cache.compile_statuses()[-2:] == [0, 0]  # its compile and its link
    with pytest.raises(RuntimeError, match="Compilation failed"):
        with compiling():
            build("fails_later", failing)


def test_a_ctrl_c_before_the_compiler_handles_it_is_recorded_by_its_shell(tmp_path):
    """CasADi runs the compile command through /bin/sh; the command starts with SIGINT ignored until
    pressocp/jitcc.py installs its handler (tens of milliseconds of Python start-up, most of a cached
    compile). A SIGINT in that time is recorded by the shell's trap (`RECORD_INTERRUPT`) once the
    command ends: exit 130 and the flag file, with no traceback. Here the command is ``sleep``, which
    never installs a handler, so the whole command is that window."""
    from pressocp import compile_cache

    flag = tmp_path / "interrupted"
    env = {**os.environ, compile_cache.INTERRUPT_ENV: str(flag)}
    proc = subprocess.Popen(["/bin/sh", "-c", compile_cache.RECORD_INTERRUPT + "sleep 2"], env=env,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        time.sleep(0.5)
        os.killpg(proc.pid, signal.SIGINT)
        assert proc.wait(timeout=120) == 130  # timeout: a guard against a hang
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    assert flag.exists() and "Traceback" not in proc.stderr.read()


def test_a_deferred_interrupt_lets_the_block_finish_then_stops():
    """`interrupt_deferred` (an output folder's commit): a SIGINT during the block is raised when the
    block ends, also while another thread, which the kernel may deliver the signal to, is running."""
    import threading

    from pressocp.interrupt import interrupt_deferred

    stop = threading.Event()
    other = threading.Thread(target=stop.wait, daemon=True)
    other.start()
    finished = []
    try:
        with pytest.raises(KeyboardInterrupt):
            with interrupt_deferred():
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(0.2)  # the handler runs here, in Python code of the block
                finished.append(True)
    finally:
        stop.set()
    assert finished == [True]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
