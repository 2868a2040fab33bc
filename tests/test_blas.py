"""CasADi's own OpenBLAS runs one thread in every process that imports pressocp (`pressocp.blas`)."""

import os
import subprocess
import sys

import pytest

from pressocp.blas import LIBRARY_NAME, casadi_blas, casadi_blas_threads, set_casadi_blas_threads

PROBE = ("import ctypes, pathlib, casadi\n"
         "{pre}\n"
         f"lib = ctypes.CDLL(str(pathlib.Path(casadi.__file__).parent / {LIBRARY_NAME!r}))\n"
         "print(lib.openblas_get_num_threads())\n")

needs_casadi_blas = pytest.mark.skipif(casadi_blas() is None, reason="this CasADi build ships no OpenBLAS of its own")


def threads_in_fresh_process(pre: str) -> int:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "2"}
    out = subprocess.run([sys.executable, "-c", PROBE.format(pre=pre)], env=env, capture_output=True, text=True,
                         check=True, timeout=120)
    return int(out.stdout.split()[-1])


@needs_casadi_blas
def test_importing_pressocp_leaves_casadis_blas_one_thread_whatever_the_environment_says():
    assert threads_in_fresh_process("") == 2  # the environment's count, without pressocp
    assert threads_in_fresh_process("import pressocp") == 1


@needs_casadi_blas
def test_the_thread_count_can_be_set_and_read_back():
    try:
        assert set_casadi_blas_threads(2)
        assert casadi_blas_threads() == 2
    finally:
        set_casadi_blas_threads(1)
    assert casadi_blas_threads() == 1


def test_fewer_than_one_thread_is_refused():
    with pytest.raises(ValueError, match="threads = 0"):
        set_casadi_blas_threads(0)
