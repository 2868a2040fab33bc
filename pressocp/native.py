"""CasADi's own BLAS runs one thread: IPOPT's linear solver (MUMPS) gains nothing from more here.

The CasADi wheel bundles an OpenBLAS (``libcasadi-tp-openblas``) that MUMPS calls for its dense
fronts. It starts a thread per core. On the press models the fronts are small, and the BLAS threads
spin for work: on 2 cores the 60 spm scenario's call (`Scenario.optimize`, the rigid and relaxed
stages, 212 IPOPT iterations) took 36 s with two BLAS threads and 27-28 s with one, with the same
answer, and the system time fell from 24 s to 5 s. See ``docs/decisions/2026-11-26-blas-threads.md``.

So importing pressocp sets that library to one thread, unless the user has chosen a count through
the environment (``OPENBLAS_NUM_THREADS``, ``GOTO_NUM_THREADS`` or ``OMP_NUM_THREADS``, which OpenBLAS
reads itself). Only CasADi's copy is touched; numpy's BLAS is left as it is.
"""

from __future__ import annotations

import ctypes
import os
from pathlib import Path

import casadi as ca

#: Environment variables through which a user sets OpenBLAS's thread count (read by OpenBLAS at load).
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def casadi_blas() -> ctypes.CDLL | None:
    """CasADi's bundled OpenBLAS, or None where the wheel has none (another platform or build).

    It is loaded with ``libcasadi`` itself, so opening it again returns the same library."""
    folder = Path(ca.__file__).parent
    for path in sorted(folder.glob("libcasadi-tp-openblas*")):
        try:
            lib = ctypes.CDLL(str(path))
            lib.openblas_get_num_threads.restype = ctypes.c_int
            lib.openblas_set_num_threads.argtypes = [ctypes.c_int]
            return lib
        except (OSError, AttributeError):
            continue
    return None


def casadi_blas_threads() -> int | None:
    """The number of threads of CasADi's OpenBLAS (None when it has none)."""
    lib = casadi_blas()
    return None if lib is None else int(lib.openblas_get_num_threads())


def limit_casadi_blas(threads: int = 1) -> int | None:
    """Set CasADi's OpenBLAS to `threads` threads unless the environment sets a count.

    Returns
    -------
    int or None
        The thread count in force afterwards (None when CasADi has no OpenBLAS of its own).
    """
    lib = casadi_blas()
    if lib is None:
        return None
    if not any(os.environ.get(k) for k in BLAS_THREAD_VARIABLES):
        lib.openblas_set_num_threads(int(threads))
    return int(lib.openblas_get_num_threads())
