"""Forward sensitivities through CVODES's own sensitivity module, compiled with the model.

CasADi 3.8 differentiates an integrator by integrating an augmented system: the states and every
direction as ordinary states, all of them iterated in every Newton iteration. CVODES's own forward
sensitivity module (staggered corrector: the directions are corrected once the state has converged,
with the state's factorisation) is not reached through CasADi's interface. This module reaches it:
CasADi generates C code of the model's right-hand side and Jacobians, `csrc/cvodes_fsa.c` drives
CVODES 2.6.1 as exported by CasADi's own ``libcasadi_integrator_cvodes`` (headers in
`csrc/sundials`, copied from CasADi's sources), with a dense direct linear solver, and the library is
compiled through the compile cache.

On the seed optimum (8 states, 11 directions, one period at rtol 3e-9) it took 0.36-0.42 s against
0.60-0.76 s for CasADi's forward integrator in the same runs, the sensitivities the same to 2e-5
(docs/decisions/2026-12-01-cvodes-staggered-sensitivities.md).

    fsa = ForwardSensitivities.build(dae, n_parameters=3)   # None: no C compiler or no CVODES library
    x, S, stats = fsa.run(x0, p, S0, Q, grid, rtol)
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np

from .compile_cache import c_compiler, compile_library

SOURCE = Path(__file__).with_name("csrc") / "cvodes_fsa.c"
HEADERS = Path(__file__).with_name("csrc") / "sundials"
#: The library that exports CVODES (CasADi's CVODES plugin).
CVODES_LIBRARY = "libcasadi_integrator_cvodes.so"
#: CVODES's return flags (cvodes.h), for the messages of a failed run.
FLAGS = {-1: "CV_TOO_MUCH_WORK", -2: "CV_TOO_MUCH_ACC", -3: "CV_ERR_FAILURE", -4: "CV_CONV_FAILURE",
         -5: "CV_LINIT_FAIL", -6: "CV_LSETUP_FAIL", -7: "CV_LSOLVE_FAIL", -8: "CV_RHSFUNC_FAIL",
         -9: "CV_FIRST_RHSFUNC_ERR", -10: "CV_REPTD_RHSFUNC_ERR", -11: "CV_UNREC_RHSFUNC_ERR",
         -20: "CV_MEM_FAIL", -22: "CV_ILL_INPUT", -41: "CV_SRHSFUNC_FAIL", -42: "CV_FIRST_SRHSFUNC_ERR",
         -43: "CV_REPTD_SRHSFUNC_ERR", -44: "CV_UNREC_SRHSFUNC_ERR"}
_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


class FsaError(RuntimeError):
    """A run of `ForwardSensitivities` failed. Attributes: ``flag`` (CVODES's), ``time`` reached (s)."""

    def __init__(self, flag: int, time: float):
        self.flag, self.time = flag, time
        super().__init__(f"CVODES returned {flag} ({FLAGS.get(flag, 'unknown flag')}) at t = {time:.6g} s")


def cvodes_library() -> Path | None:
    """CasADi's CVODES plugin library, or None when this CasADi has none (not on Linux)."""
    path = Path(ca.__file__).parent / CVODES_LIBRARY
    return path if path.is_file() else None


def available() -> bool:
    """Whether `ForwardSensitivities` can be built here: a C compiler, and CasADi's CVODES library."""
    return c_compiler() is not None and cvodes_library() is not None


def model_source(dae: dict, n_parameters: int) -> str:
    """C source of the model functions the driver calls (`csrc/cvodes_fsa.c`), for the explicit ODE
    `dae` (``x``, ``p``, ``t``, ``ode``; SX) whose last `n_parameters` parameters have directions,
    followed by the driver and a line that names the headers' content (the compile cache keys by the
    source)."""
    t, x, p, ode = dae["t"], dae["x"], dae["p"], dae["ode"]
    q = p[p.numel() - n_parameters:]
    functions = [ca.Function("f_ode", [t, x, p], [ode]),
                 ca.Function("f_jac", [t, x, p], [ca.densify(ca.jacobian(ode, x))]),
                 ca.Function("f_jfull", [t, x, p], [ca.densify(ca.jacobian(ode, ca.vertcat(x, q)))],
                             {"cse": True})]
    cg = ca.CodeGenerator("model.c", {"with_header": False, "casadi_int": "long long int"})
    for f in functions:
        cg.add(f)
    sizes = {"NX": x.numel(), "NQ": n_parameters, "SZ_ARG": max(f.sz_arg() for f in functions),
             "SZ_RES": max(f.sz_res() for f in functions), "SZ_IW": max(f.sz_iw() for f in functions),
             "SZ_W": max(f.sz_w() for f in functions)}
    headers = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(HEADERS.rglob("*.h")))).hexdigest()
    return "\n".join([f"/* pressocp forward sensitivities; SUNDIALS headers {headers} */",
                      *(f"#define {k} {v}" for k, v in sizes.items()), cg.dump(), SOURCE.read_text()])


@dataclass
class ForwardSensitivities:
    """A compiled forward-sensitivity integrator of one explicit ODE (`build`)."""

    nx: int
    n_parameters: int
    library: ctypes.CDLL

    @classmethod
    def build(cls, dae: dict, n_parameters: int) -> ForwardSensitivities:
        """Generate, compile (through the compile cache) and load the integrator of `dae` (an explicit
        ODE dict of SX: ``t``, ``x``, ``p``, ``ode``) with directions in its last `n_parameters`
        parameters. Raises RuntimeError when there is no C compiler or CVODES library, or the compile
        fails."""
        lib = cvodes_library()
        if lib is None or c_compiler() is None:
            raise RuntimeError("compiled forward sensitivities need a C compiler and CasADi's "
                               f"{CVODES_LIBRARY}")
        source = model_source(dae, n_parameters)
        folder = Path(tempfile.mkdtemp(prefix="pressocp_fsa_"))
        try:
            path = folder / f"fsa_{hashlib.sha256(source.encode()).hexdigest()[:16]}.c"
            path.write_text(source)
            library = path.with_suffix(".so")
            compile_library(path, library, compile_flags=(f"-I{HEADERS}",),
                            link_flags=(f"-L{lib.parent}", f"-l:{lib.name}", f"-Wl,-rpath,{lib.parent}"))
            handle = ctypes.CDLL(str(library))
        finally:
            for f in folder.iterdir():
                f.unlink()
            os.rmdir(folder)
        handle.fsa_run.restype = ctypes.c_int
        handle.fsa_run.argtypes = [_DOUBLE_P, _DOUBLE_P, ctypes.c_int, _DOUBLE_P, _DOUBLE_P, ctypes.c_int,
                                   _DOUBLE_P, ctypes.c_double, ctypes.c_long, _DOUBLE_P, _DOUBLE_P, _DOUBLE_P]
        return cls(int(dae["x"].numel()), n_parameters, handle)

    def run(self, x0: np.ndarray, p: np.ndarray, S0: np.ndarray, Q: np.ndarray, grid: np.ndarray, rtol: float,
            max_steps: int = 10**7) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        """Integrate from t = 0.

        Parameters
        ----------
        x0 : ndarray, shape (nx,)
            Start state (the ODE's own states, as scaled in `dae`).
        p : ndarray
            Every parameter of the ODE.
        S0 : ndarray, shape (nx, ns)
            The directions' start values.
        Q : ndarray, shape (n_parameters, ns)
            The directions' parameter components (constant).
        grid : ndarray
            Output times, increasing, > 0 (s).
        rtol : float
            Relative and absolute tolerance, of the states and of the directions.
        max_steps : int

        Returns
        -------
        x : ndarray, shape (nx, len(grid))
        S : ndarray, shape (nx, ns, len(grid))
        stats : dict
            ``steps``, ``rhs`` (right-hand sides), ``jacobians`` (of the linear solver),
            ``sensitivity_jacobians``.

        Raises
        ------
        FsaError
            CVODES failed (its flag and the time reached).
        """
        S0, Q = np.asarray(S0, float), np.asarray(Q, float)
        ns = S0.shape[1]
        if S0.shape[0] != self.nx or Q.shape != (self.n_parameters, ns):
            raise ValueError(f"S0 must be ({self.nx}, ns) and Q ({self.n_parameters}, ns); got {S0.shape}, {Q.shape}")
        grid = np.ascontiguousarray(grid, float)
        x = np.zeros((grid.size, self.nx))
        S = np.zeros((grid.size, ns, self.nx))
        stats = np.zeros(5)
        args = [np.ascontiguousarray(x0, float), np.ascontiguousarray(p, float), np.asfortranarray(S0),
                np.asfortranarray(Q)]
        flag = self.library.fsa_run(*(a.ctypes.data_as(_DOUBLE_P) for a in args[:2]), ns,
                                    *(a.ctypes.data_as(_DOUBLE_P) for a in args[2:]), grid.size,
                                    grid.ctypes.data_as(_DOUBLE_P), float(rtol), int(max_steps),
                                    x.ctypes.data_as(_DOUBLE_P), S.ctypes.data_as(_DOUBLE_P),
                                    stats.ctypes.data_as(_DOUBLE_P))
        if flag < 0:
            raise FsaError(flag, float(stats[4]))
        return x.T.copy(), S.transpose(2, 1, 0).copy(), dict(zip(
            ("steps", "rhs", "jacobians", "sensitivity_jacobians"), map(float, stats[:4])))


__all__ = ["FsaError", "ForwardSensitivities", "available"]
