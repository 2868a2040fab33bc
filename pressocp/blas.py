"""CasADi's own OpenBLAS runs one thread in every process of the package.

IPOPT and its linear solver MUMPS call the OpenBLAS that CasADi ships (``libcasadi-tp-openblas``,
built for one CPU target, so its kernels are the same on every x86-64 machine), not numpy's. By
default it starts a thread per core, and with two threads it sums some products in another order
than with one: IPOPT's iterates then differ in their last bits with the core count, and the hard
scenes' chains, which pass stages stopped at their iteration limits, turn that into another verified
optimum (press75: 145.14407 N·m on two threads, 145.14371 on one). With one thread in every process,
a default call, a sweep's point (the package's workers) and a machine with another core count take
the same path to the same answer. Another CPU model can still take another path: numpy's OpenBLAS
picks its kernels by CPU (``docs/decisions/2026-12-02-answers-by-cpu.md``). MUMPS's fronts here are
small (a banded collocation KKT system), so a second thread buys little.

`pressocp` sets this when it is imported; `set_casadi_blas_threads` changes it. numpy's OpenBLAS is
a separate library, left alone here. See ``docs/decisions/2026-11-29-casadi-blas-one-thread.md``.
"""

from __future__ import annotations

import ctypes
import sys
from pathlib import Path

import casadi as ca

#: CasADi's OpenBLAS as IPOPT and MUMPS link it on Linux (their DT_NEEDED name). The wheel holds
#: copies under other names too (``.so``, ``.so.0.3``); loading one of those would load a second,
#: separate instance that IPOPT does not use.
LIBRARY_NAME = "libcasadi-tp-openblas.so.0"


def casadi_blas() -> ctypes.CDLL | None:
    """CasADi's own OpenBLAS, loaded (the instance IPOPT uses, whether IPOPT is loaded before or
    after), or None off Linux or when this CasADi build ships none under `LIBRARY_NAME`."""
    path = Path(ca.__file__).parent / LIBRARY_NAME
    if not sys.platform.startswith("linux") or not path.exists():
        return None
    try:
        return ctypes.CDLL(str(path))
    except OSError:
        return None


def set_casadi_blas_threads(threads: int = 1) -> bool:
    """Run CasADi's OpenBLAS (IPOPT's and MUMPS's BLAS) on `threads` threads in this process.

    Parameters
    ----------
    threads : int
        At least 1. More than 1 makes IPOPT's iterates, and on hard scenes the optimum, depend on the
        thread count (see the module's docstring).

    Returns
    -------
    bool
        Whether CasADi's OpenBLAS was found and set (False: not Linux, or this CasADi build has none
        under `LIBRARY_NAME`; its BLAS then runs as many threads as its environment says).
    """
    if int(threads) < 1:
        raise ValueError(f"threads = {threads}: must be at least 1")
    lib = casadi_blas()
    if lib is None or not hasattr(lib, "openblas_set_num_threads"):
        return False
    lib.openblas_set_num_threads(int(threads))
    return True


def casadi_blas_threads() -> int | None:
    """The thread count of CasADi's OpenBLAS in this process, or None when it has none."""
    lib = casadi_blas()
    if lib is None or not hasattr(lib, "openblas_get_num_threads"):
        return None
    return int(lib.openblas_get_num_threads())
