"""Forward sensitivities through CVODES, compiled with the model.

CasADi 3.8 differentiates an integrator through its own interface to CVODES, with the overhead of
its function calls at every step; CVODES's own forward-sensitivity module (staggered or simultaneous
corrector) is not reached through that interface. This module drives CVODES 2.6.1 as exported by
CasADi's own ``libcasadi_integrator_cvodes`` (`csrc/cvodes_fsa.c`, headers in `csrc/sundials`,
copied from CasADi's sources) with CasADi-generated C code of the model's right-hand side and
Jacobians and a dense direct linear solver, the library compiled through the compile cache. Two
ways (`ForwardSensitivities.build`):

* the directions integrated with the states as one system under one error control, each Newton
  step solved block by block with the states' factorisation (the Newton matrix of CVODES's
  simultaneous corrector, its vector operations on one vector);
* CVODES's staggered sensitivity module, the directions corrected once the state has converged,
  each a vector of its own.

On the seed optimum (8 states, 11 directions, one period at rtol 3e-9) one system took 0.18 s, the
staggered module 0.41 s and CasADi's forward integrator 0.74 s in one run, the directions the same
to 2e-5
(`benchmarks/results/sensitivity_seed.json`, ``engine_periods``;
docs/decisions/2026-12-01-fused-sensitivities.md).

    if not unavailable():                                    # a C compiler, CasADi 3.8's CVODES
        fsa = ForwardSensitivities.build(dae, n_parameters=3, directions=11)
        x, S, stats = fsa.run(x0, p, S0, Q, grid, rtol)
"""

from __future__ import annotations

import atexit
import ctypes
import hashlib
import shutil
import tempfile
import threading
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import casadi as ca
import numpy as np

from .compile_cache import QUICK_FLAGS, c_compiler, compile_library
from .interrupt import compiling

SOURCE = Path(__file__).with_name("csrc") / "cvodes_fsa.c"
HEADERS = Path(__file__).with_name("csrc") / "sundials"
#: The library that exports CVODES (CasADi's CVODES plugin).
CVODES_LIBRARY = "libcasadi_integrator_cvodes.so"
#: CasADi's SUNDIALS support library beside it (the serial vectors).
SUNDIALS_COMMON = "libcasadi_sundials_common.so"
#: CVODES's return flags (cvodes.h), for the messages of a failed run.
FLAGS = {-1: "CV_TOO_MUCH_WORK", -2: "CV_TOO_MUCH_ACC", -3: "CV_ERR_FAILURE", -4: "CV_CONV_FAILURE",
         -5: "CV_LINIT_FAIL", -6: "CV_LSETUP_FAIL", -7: "CV_LSOLVE_FAIL", -8: "CV_RHSFUNC_FAIL",
         -9: "CV_FIRST_RHSFUNC_ERR", -10: "CV_REPTD_RHSFUNC_ERR", -11: "CV_UNREC_RHSFUNC_ERR",
         -20: "CV_MEM_FAIL", -22: "CV_ILL_INPUT", -27: "CV_TOO_CLOSE", -41: "CV_SRHSFUNC_FAIL", -42: "CV_FIRST_SRHSFUNC_ERR",
         -43: "CV_REPTD_SRHSFUNC_ERR", -44: "CV_UNREC_SRHSFUNC_ERR"}
_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


class FsaError(RuntimeError):
    """A run of `ForwardSensitivities` failed. Attributes: ``flag`` (CVODES's), ``time`` reached (s; not
    in the message, which `pressocp.simulate.SimulationError` completes with it)."""

    def __init__(self, flag: int, time: float):
        self.flag, self.time = flag, time
        super().__init__(f"CVODES returned {flag} ({FLAGS.get(flag, 'unknown flag')})")


@lru_cache(maxsize=1)
def library_folder() -> Path:
    """This process's folder of built libraries, removed at exit. A loaded library stays on disk while
    the process runs: the dynamic linker knows a library by its file, and a deleted one's file could
    be reused by the next build and taken for the loaded library."""
    folder = Path(tempfile.mkdtemp(prefix="pressocp_fsa_"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    return folder


def cvodes_library() -> Path | None:
    """CasADi's CVODES plugin library, or None when this CasADi has none (not on Linux)."""
    path = Path(ca.__file__).parent / CVODES_LIBRARY
    return path if path.is_file() else None


#: The CasADi versions whose CVODES the headers in `HEADERS` describe (CasADi's sources have not changed
#: them since 2023; the driver writes into CVODES's internal memory, so another layout would be unsafe).
CASADI_VERSIONS = ("3.8.",)


def unavailable() -> str:
    """Why `ForwardSensitivities` cannot be built here, or "" when it can: it needs a C compiler and
    CasADi's CVODES library, of a version in `CASADI_VERSIONS`."""
    if c_compiler() is None:
        return "no C compiler (cc) found"
    if cvodes_library() is None:
        return f"CasADi has no {CVODES_LIBRARY}"
    if not ca.__version__.startswith(CASADI_VERSIONS):
        return f"CasADi {ca.__version__} is not {' or '.join(v + 'x' for v in CASADI_VERSIONS)}"
    return ""


def available() -> bool:
    """Whether `ForwardSensitivities` can be built here (`unavailable`)."""
    return not unavailable()


def built(dae: dict, n_parameters: int, directions: int | None = None) -> tuple[ForwardSensitivities | None, str]:
    """`ForwardSensitivities.build` of `dae`, or None and why it cannot be built here (`unavailable`,
    a failed compile or load: the first line of the error)."""
    why = unavailable()
    if why:
        return None, why
    try:
        return ForwardSensitivities.build(dae, n_parameters, directions), ""
    except (RuntimeError, OSError) as err:
        return None, str(err).splitlines()[0]


def model_source(dae: dict, n_parameters: int, directions: int | None = None) -> tuple[str, str]:
    """C sources of the model functions the driver calls (`csrc/cvodes_fsa.c`), for the explicit ODE
    `dae` (``x``, ``p``, ``t``, ``ode``; SX) whose last `n_parameters` parameters have directions:
    the right-hand side (and with CVODES's own directions the Jacobian with respect to the states and
    those parameters, evaluated at every step) followed by the driver and a line that names the
    headers' content (the compile cache keys by the source); and apart, the Jacobian the linear solver
    evaluates every few dozen steps, compiled at `QUICK_FLAGS` (`ForwardSensitivities.build`).

    With `directions` the right-hand side is that of the states and that many directions as one
    system, x' = f and S' = f_x S + f_q Q, its parameters followed by the directions' parameter
    components Q (n_parameters x directions, column major); the linear solver's Jacobian is f_x."""
    t, x, p, ode = dae["t"], dae["x"], dae["p"], dae["ode"]
    nx = x.numel()
    q = p[p.numel() - n_parameters:]
    if directions is None:
        step = [ca.Function("f_ode", [t, x, p], [ode])]
        if n_parameters:  # without parameter directions df/d[x; q] is df/dx: the Jacobian serves
            step.append(ca.Function("f_jfull", [t, x, p], [ca.densify(ca.jacobian(ode, ca.vertcat(x, q)))],
                                    {"cse": True}))
        args, blocks = [t, x, p], {}
    else:
        S, Q = ca.SX.sym("S", nx, directions), ca.SX.sym("Q", n_parameters, directions)
        args = [t, ca.vertcat(x, ca.vec(S)), ca.vertcat(p, ca.vec(Q))]
        # f_x S as a product with the Jacobian: its forward derivatives (jtimes) took 1.8 x as long
        S_dot = ca.mtimes(ca.jacobian(ode, x), S) + ca.mtimes(ca.jacobian(ode, q), Q)
        step = [ca.Function("f_ode", args, [ca.vertcat(ode, ca.vec(S_dot))], {"cse": True})]
        blocks = {"NB": 1 + directions, "NXB": nx}
    jac = ca.Function("f_jac", args, [ca.densify(ca.jacobian(ode, x))])
    functions = [*step, jac]
    sizes = {"NX": args[1].numel(), "NQ": n_parameters if directions is None else 0, **blocks,
             "SZ_ARG": max(f.sz_arg() for f in functions), "SZ_RES": max(f.sz_res() for f in functions),
             "SZ_IW": max(f.sz_iw() for f in functions), "SZ_W": max(f.sz_w() for f in functions)}
    headers = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(HEADERS.rglob("*.h")))).hexdigest()
    main, apart = (ca.CodeGenerator(name, {"with_header": False, "casadi_int": "long long int"})
                   for name in ("model.c", "jacobian.c"))
    for f in step:
        main.add(f)
    apart.add(jac)
    signature = "(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem)"
    return ("\n".join([f"/* pressocp forward sensitivities; SUNDIALS headers {headers} */",
                       *(f"#define {k} {v}" for k, v in sizes.items()), main.dump(), f"int f_jac{signature};",
                       "" if len(step) > 1 else "#define f_jfull f_jac", SOURCE.read_text()]),
            apart.dump())


@dataclass
class ForwardSensitivities:
    """A compiled forward-sensitivity integrator of one explicit ODE (`build`).

    Attributes
    ----------
    nx, n_p : int
        Number of states and of parameters of the ODE.
    n_parameters : int
        The last parameters, which directions may have components in.
    library : ctypes.CDLL
        The compiled driver and model (kept loaded, and on disk, for the process's life).
    directions : int or None
        The number of directions integrated with the states as one system (`build`), or None:
        CVODES's staggered sensitivities, any number.
    """

    nx: int
    n_p: int
    n_parameters: int
    library: ctypes.CDLL
    directions: int | None = None

    @classmethod
    def build(cls, dae: dict, n_parameters: int, directions: int | None = None) -> ForwardSensitivities:
        """Generate, compile (through the compile cache) and load the integrator of `dae` (an explicit
        ODE dict of SX: ``t``, ``x``, ``p``, ``ode``) with directions in its last `n_parameters`
        parameters. Raises RuntimeError when there is no C compiler or CVODES library, or the compile
        fails; OSError when the library cannot be loaded.

        With `directions` (a number), every run has that many directions, integrated with the states
        as one system of nx (1 + directions) equations under one error control, each Newton step
        solved block by block with the states' factorisation (the Newton matrix of CVODES's
        simultaneous corrector); without, CVODES's staggered sensitivity module integrates any
        number of directions beside the states, each a vector of its own. On the seed optimum (8
        states, 11 directions, one period at rtol 3e-9) the one system took 0.14 s against 0.30 s,
        the directions the same to 2e-7 at the peaks
        (docs/decisions/2026-12-01-fused-sensitivities.md)."""
        lib, why = cvodes_library(), unavailable()
        if lib is None or why:
            raise RuntimeError(f"compiled forward sensitivities cannot be built: {why}")
        main, jacobian = model_source(dae, n_parameters, directions)
        name = f"fsa_{hashlib.sha256((main + jacobian).encode()).hexdigest()[:24]}"
        library = library_folder() / f"{name}.so"
        if not library.exists():
            paths = (library_folder() / f"{name}.c", library_folder() / f"{name}_jacobian.c")
            for path, text in zip(paths, (main, jacobian)):
                path.write_text(text)
            common = lib.with_name(SUNDIALS_COMMON)
            with compiling():  # a Ctrl-C during the compile raises KeyboardInterrupt, once
                compile_library(((paths[0], (f"-I{HEADERS}",)), (paths[1], QUICK_FLAGS)), library,
                                link_flags=(f"-L{lib.parent}", f"-l:{lib.name}", f"-l:{common.name}", "-lm",
                                            f"-Wl,-rpath,{lib.parent}", "-Wl,-z,defs"))
        handle = ctypes.CDLL(str(library))
        handle.fsa_run.restype = ctypes.c_int
        handle.fsa_run.argtypes = [_DOUBLE_P, _DOUBLE_P, ctypes.c_int, _DOUBLE_P, _DOUBLE_P, ctypes.c_int,
                                   _DOUBLE_P, ctypes.c_double, ctypes.c_double, ctypes.c_long, ctypes.c_int,
                                   ctypes.POINTER(ctypes.c_int), _DOUBLE_P, _DOUBLE_P, _DOUBLE_P]
        return cls(int(dae["x"].numel()), int(dae["p"].numel()), n_parameters, handle, directions)

    def run(self, x0: np.ndarray, p: np.ndarray, S0: np.ndarray, Q: np.ndarray, grid: np.ndarray, rtol: float,
            max_steps: int = 10**7, atol: float | None = None,
            stop: ctypes.c_int | None = None) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        """Integrate from t = 0.

        Parameters
        ----------
        x0 : ndarray, shape (nx,)
            Start state (the ODE's own states, as scaled in `dae`).
        p : ndarray
            Every parameter of the ODE.
        S0 : ndarray, shape (nx, ns)
            The directions' start values (ns = `directions` when that is set).
        Q : ndarray, shape (n_parameters, ns)
            The directions' parameter components (constant).
        grid : ndarray
            Output times, increasing, > 0 (s).
        rtol : float
            Relative tolerance of the states, and of the directions (which are in the states' units).
        max_steps : int
        atol : float, optional
            Absolute tolerance of the states; None: `rtol`.
        stop : ctypes.c_int, optional
            Another thread sets it nonzero to stop the run (KeyboardInterrupt), as Ctrl-C does in the main
            thread.

        Returns
        -------
        x : ndarray, shape (nx, len(grid))
        S : ndarray, shape (nx, ns, len(grid))
            ``x`` and ``S`` are views of the driver's output buffers, not copies (a dense grid of
            20 001 samples of 8 states and 88 directions is 15 MB): either keeps the buffer alive.
        stats : dict
            ``steps``, ``rhs`` (right-hand sides), ``jacobians`` (of the linear solver),
            ``sensitivity_jacobians`` (of CVODES's staggered directions).

        Raises
        ------
        ValueError
            An input of the wrong size, or a grid that does not increase from above 0.
        FsaError
            CVODES failed (its flag and the time reached).
        KeyboardInterrupt
            Ctrl-C (in the main thread), or `stop` set: the run stops at its next right-hand side.
        """
        S0, Q = np.asarray(S0, float), np.asarray(Q, float)
        x0, p, grid = (np.ascontiguousarray(np.ravel(a), float) for a in (x0, p, grid))
        ns = S0.shape[1] if S0.ndim == 2 else -1
        fixed = self.directions is not None  # one system: its number of directions is compiled in
        if S0.shape[0] != self.nx or Q.shape != (self.n_parameters, ns) or x0.size != self.nx or p.size != self.n_p \
                or (fixed and ns != self.directions):
            raise ValueError(f"x0 must have {self.nx} entries, p {self.n_p}, S0 shape ({self.nx}, "
                             f"{self.directions if fixed else 'ns'}) and Q ({self.n_parameters}, ns); got {x0.size}, "
                             f"{p.size}, {S0.shape}, {Q.shape}")
        if grid.size == 0 or grid[0] <= 0.0 or np.any(np.diff(grid) <= 0.0):
            raise ValueError(f"grid must increase from above 0 s; got {grid}")
        if fixed:  # the directions are states, their parameter components parameters
            x, _, stats = self._integrate(np.concatenate([x0, S0.ravel(order="F")]),
                                          np.concatenate([p, Q.ravel(order="F")]), np.zeros((0, 0)), Q, grid,
                                          rtol, atol, max_steps, stop)
            # views of the driver's output (a dense grid of 20 001 samples of 96 entries is 15 MB)
            return x[:self.nx], x[self.nx:].reshape(self.nx, ns, grid.size, order="F"), stats
        return self._integrate(x0, p, S0, Q, grid, rtol, atol, max_steps, stop)

    def _integrate(self, x0: np.ndarray, p: np.ndarray, S0: np.ndarray, Q: np.ndarray, grid: np.ndarray,
                   rtol: float, atol: float | None, max_steps: int,
                   stop: ctypes.c_int | None) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
        """`run` on the driver's own states `x0` (with `directions`, the states and directions as one
        vector, and `S0` empty) and parameters `p`, the inputs checked."""
        n, ns = x0.size, S0.shape[1]
        x = np.empty((grid.size, n))
        S = np.empty((grid.size, ns, n))
        stats = np.zeros(6)
        args = [x0, p, np.asfortranarray(S0), np.asfortranarray(Q)]
        # a Ctrl-C is caught in C (Python's handler cannot run until the call returns) in the main thread
        main = threading.current_thread() is threading.main_thread()
        flag = self.library.fsa_run(*(a.ctypes.data_as(_DOUBLE_P) for a in args[:2]), ns,
                                    *(a.ctypes.data_as(_DOUBLE_P) for a in args[2:]), grid.size,
                                    grid.ctypes.data_as(_DOUBLE_P), float(rtol), float(rtol if atol is None else atol),
                                    int(max_steps), int(main), None if stop is None else ctypes.byref(stop),
                                    x.ctypes.data_as(_DOUBLE_P), S.ctypes.data_as(_DOUBLE_P),
                                    stats.ctypes.data_as(_DOUBLE_P))
        if stats[5]:
            raise KeyboardInterrupt
        if flag < 0:
            raise FsaError(flag, float(stats[4]))
        return x.T, S.transpose(2, 1, 0), dict(zip(
            ("steps", "rhs", "jacobians", "sensitivity_jacobians"), map(float, stats[:4])))


__all__ = ["FsaError", "ForwardSensitivities", "available", "built", "unavailable"]
