"""Time simulation of a `PressModel`: SUNDIALS (IDAS, CVODES), CasADi fixed-step methods and
scipy baselines on the same equations, with an optional periodic steady state.
"""

from __future__ import annotations

import contextlib
import ctypes
import io
import re
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

from . import checks as chk
from .buffers import call, evaluate
from .compile_cache import check_jit, function_options, jit_options, use_jit
from .cvodes_fsa import ForwardSensitivities, FsaError, built
from .interrupt import compiling, interruptible
from .model import OUTPUT_NAMES, QUADRATURE_NAMES, PressModel
from .result import SimResult
from .speed import FourierSpeed

METHODS = ("idas", "cvodes", "cvodes-direct", "collocation", "rk", "scipy-radau", "scipy-bdf")
#: CVODES called from compiled code (`DirectCvodes`).
DIRECT = "cvodes-direct"
#: Where a model keeps its `direct_driver` (``PressModel.functions``).
DIRECT_DRIVER = "cvodes_direct"
#: The methods a periodic search shoots with as they are; it shoots with CVODES for the others.
SHOOTING = ("idas", "cvodes", DIRECT)
#: Default output samples per cycle (impacts last a fraction of a millisecond at T = 1 s).
OUTPUTS_PER_CYCLE = 4000
#: Default step of the fixed-step methods ("rk", "collocation"), s.
FIXED_STEP = 1e-5


#: Bound on an `Integrator`'s relative tolerance (itself refused): at 0.5 the design speed's periodic response on
#: press60 peaked 2 % off, at 5 (accepted before) 104 % off, with no sign of it.
MAX_RTOL = 1e-2


@dataclass(frozen=True)
class Integrator:
    """How a simulation integrates: the method, its tolerances and its step limits (checked here,
    before any integration).

    Attributes
    ----------
    method : {"idas", "cvodes", "cvodes-direct", "collocation", "rk", "scipy-radau", "scipy-bdf"}
        "idas" integrates the semi-explicit DAE (accelerations algebraic), the others the explicit
        ODE; "cvodes-direct" is CVODES called from code compiled with the model (`DirectCvodes`:
        a dense direct solver, no CasADi integrator between; no work quadratures, so ``work=False``;
        needs a C compiler and CasADi 3.8's CVODES library, and compiles whatever ``model.jit``
        says), "collocation" and "rk" are CasADi's fixed-step methods (step `step`), the scipy ones
        baselines.
    rtol : float
        Relative tolerance, in (0, `MAX_RTOL`).
    atol : float or None
        Absolute tolerance on the scaled states (eccentricity / clearance), > 0; None: `rtol`.
    max_steps : int
        Step limit of the adaptive integrators, 1..1e9.
    step : float
        Step of the fixed-step methods, s.
    periodic_tol : float or None
        How periodic a ``periodic=True`` run must be: the max-norm of x(T) - x(0) in scaled states
        (eccentricity / clearance; rates / (1000 clearance)), > 0. None: `periodic_state`'s default
        (1e-4), or max(1e-5, 1000 `rtol`) when the search's own last cycle is the answer (`simulate`'s
        `work`).
        That is enough for a check to 1e-3 but not for differences: on a worn (2 mm) wrist pin the
        contact transient dies slowly, and a residual of 1e-4 moved the peak torque by 1e-4 of itself
        (1e-2 N m), 1e-7 by 1e-6. For finite differences at rtol 1e-10 ask for about 1000 `rtol`.
        Tighter is slower and can fail where the response impacts (a periodic orbit it barely has).
    """

    method: str = "idas"
    rtol: float = 1e-6
    atol: float | None = None
    max_steps: int = 10**7
    step: float = FIXED_STEP
    periodic_tol: float | None = None

    def __post_init__(self) -> None:
        chk.choice("method", self.method, METHODS)
        chk.in_open_interval("rtol", self.rtol, 0.0, MAX_RTOL)
        if self.atol is not None:
            chk.positive("atol", self.atol)
        chk.integer("max_steps", self.max_steps, 1, 10**9)
        chk.positive("step", self.step, "s")
        if self.periodic_tol is not None:
            chk.positive("periodic_tol", self.periodic_tol)

    @property
    def abstol(self) -> float:
        """The absolute tolerance used: `atol`, or `rtol` when it is None."""
        return self.rtol if self.atol is None else self.atol


#: The periodic search's shots by default: CVODES at rtol 1e-8.
SHOTS = Integrator("cvodes", 1e-8)


class SimulationError(RuntimeError):
    """An integrator failed. Attributes: ``time`` reached (s, NaN if unknown), ``method``, ``hint``."""

    def __init__(self, message: str, time: float = float("nan"), method: str = "", hint: str = ""):
        self.time, self.method, self.hint = time, method, hint
        text = f"{method} failed"
        if np.isfinite(time):
            text += f" at t = {time:.6g} s"
        text += f": {message}"
        if hint:
            text += f"\nhint: {hint}"
        super().__init__(text)


HINT = (
    "the contact is stiff: try a larger bearing smoothing or damping, a softer contact stiffness, "
    "a looser rtol, more steps (Integrator.max_steps), or Integrator('cvodes')"
)


#: Integrators kept per model (`_integrator`), the oldest dropped first.
KEPT_INTEGRATORS = 8


def _integrator(model: PressModel, integ: Integrator, grid: np.ndarray, work: bool = True) -> ca.Function:
    """The CasADi integrator of `model` over `grid`, built once per model and settings and kept in
    ``model.functions`` (the last `KEPT_INTEGRATORS`): building one took 20 ms on the rigid rod and
    0.1 s on a 2-element rod (2026-11-26), paid again by every call of a sweep or a repeated check.
    With ``model.jit`` the SUNDIALS integrators evaluate the compiled right-hand side
    (`integrator_dae`)."""
    grid = np.asarray(grid, float)
    if integ.method == DIRECT:
        return DirectCvodes(direct_driver(model, work), grid, integ)
    key = ("integrator", integ.method, grid.tobytes(), float(integ.rtol), float(integ.abstol), int(integ.max_steps),
           float(integ.step), bool(work), str(model.jit))
    kept = model.functions.setdefault("integrators", {})
    if key not in kept:
        if len(kept) >= KEPT_INTEGRATORS:
            kept.pop(next(iter(kept)))
        with compiling():  # SUNDIALS's Jacobian of a compiled DAE is compiled here
            kept[key] = _build_integrator(model, integ, grid, work)
    return kept[key]


def direct_driver(model: PressModel, work: bool) -> ForwardSensitivities:
    """The compiled CVODES driver of `model`'s explicit ODE (`pressocp.cvodes_fsa`, no directions),
    built once and kept with it (compiled whatever ``model.jit`` says). Raises ValueError (before any
    integration) when the run asks for the work quadratures, which it does not integrate, or when it
    cannot be built here (no C compiler, no CasADi 3.8 CVODES library, a failed compile or load)."""
    if work:
        raise ValueError(f'integrator "{DIRECT}" integrates no work quadratures: simulate with work=False, '
                         'or use "cvodes"')
    if DIRECT_DRIVER not in model.functions:
        driver, why = built(model.dae(explicit=True, work=False), 0)
        if driver is None:
            raise ValueError(f'integrator "{DIRECT}" cannot run here ({why}): use "cvodes"')
        model.functions[DIRECT_DRIVER] = driver
    return model.functions[DIRECT_DRIVER]


class DirectCvodes:
    """CVODES over `grid` through the compiled driver (`direct_driver`), called where CasADi's
    integrator is (`first_try`: inputs ``x0`` and ``p``, one column per run; outputs ``xf`` and an
    empty ``qf``). `map` runs the columns in threads: the driver holds no global state and releases
    the GIL; a Ctrl-C meanwhile stops every run. On the 75 spm seed optimum a period at rtol 3e-9 took
    0.035 s against 0.100 s through CasADi's CVODES (`benchmarks/results/sensitivity_seed.json`,
    ``engine_periods``); the states agree to the integration error, not to the bit (another linear
    solver and Jacobian policy)."""

    def __init__(self, driver: ForwardSensitivities, grid: np.ndarray, integ: Integrator, threads: int = 1) -> None:
        self.driver, self.grid, self.integ, self.threads = driver, np.asarray(grid, float), integ, threads
        # the driver integrates to increasing times after 0: repeated ones and 0 are filled in
        self.times, self.index = np.unique(self.grid, return_inverse=True)

    def map(self, n: int, parallelization: str = "serial", threads: int = 1) -> DirectCvodes:
        """The same runs, the columns in `threads` threads when ``parallelization == "thread"``."""
        return DirectCvodes(self.driver, self.grid, self.integ, threads if parallelization == "thread" else 1)

    def run(self, stats: dict, x0: np.ndarray, p: np.ndarray, **unused: np.ndarray) -> dict[str, np.ndarray]:
        """The states at the grid of the runs from the columns of `x0` (or from `x0`), with the
        parameters `p` (a column, or one per run); CVODES's steps and right-hand sides summed into
        `stats`. Raises FsaError (a RuntimeError) with the time reached in ``stats["tcur"]``."""
        x0, p = np.asarray(x0, float), np.asarray(p, float)
        cols = x0.reshape(self.driver.nx, -1, order="F")
        ps = np.broadcast_to(p.reshape(self.driver.n_p, -1, order="F"), (self.driver.n_p, cols.shape[1]))
        none = (np.zeros((self.driver.nx, 0)), np.zeros((self.driver.n_parameters, 0)))
        after = self.times > 0.0
        stop = ctypes.c_int(0)

        def one(k: int) -> tuple[np.ndarray, dict]:
            X, st = np.repeat(cols[:, [k]], self.times.size, axis=1), {"steps": 0, "rhs": 0}
            if after.any():
                X[:, after], _, st = self.driver.run(cols[:, k], ps[:, k], *none, self.times[after], self.integ.rtol,
                                                     self.integ.max_steps, self.integ.abstol, stop)
            return X[:, self.index], st

        try:
            if self.threads > 1 and cols.shape[1] > 1:
                pool = ThreadPoolExecutor(self.threads)
                try:
                    runs = list(pool.map(one, range(cols.shape[1])))
                except BaseException:  # a Ctrl-C here: the running calls stop at their next step
                    stop.value = 1
                    raise
                finally:
                    pool.shutdown(wait=True, cancel_futures=True)
            else:
                runs = [one(k) for k in range(cols.shape[1])]
        except FsaError as err:
            stats["tcur"] = err.time
            raise
        stats["nsteps"] = int(sum(st["steps"] for _, st in runs))
        stats["nfevals"] = int(sum(st["rhs"] for _, st in runs))
        X = np.hstack([X for X, _ in runs]) if x0.ndim > 1 else runs[0][0]
        return {"xf": X, "qf": np.zeros((0, X.shape[1]))}


#: What `started_consistently` records in a run's statistics (``initial_conditions``).
CALC_IC_FAILED = "IDACalcIC failed ({}); started without it from the model's consistent accelerations and rates"


def calc_ic_failed(err: BaseException) -> bool:
    """Whether `err` is IDAS failing to correct its start (IDACalcIC), the failure
    `started_consistently` restarts from."""
    return "IDACalcIC" in str(err)


def first_try(F: ca.Function, stats: dict, args: dict) -> dict[str, np.ndarray]:
    """`call` of the integrator `F` on `args`, interruptible, with what SUNDIALS prints meanwhile (CasADi
    writes it to Python's ``sys.stderr``) held back: written out afterwards, unless the run failed in
    IDACalcIC. That failure's messages ("The linesearch algorithm failed with too small a step.", once
    per attempt: six to nine lines per periodic search on the 8-element rod) are dropped, because
    `started_consistently` restarts the run and records the failure in its statistics."""
    if isinstance(F, DirectCvodes):  # compiled code: it says nothing, and a Ctrl-C stops it in C
        return F.run(stats, **args)
    held, drop = io.StringIO(), False
    try:
        with contextlib.redirect_stderr(held), interruptible():
            return call(F, stats=stats, **args)
    except RuntimeError as err:
        drop = calc_ic_failed(err)
        raise
    finally:
        if not drop and held.getvalue():
            sys.stderr.write(held.getvalue())


def started_consistently(model: PressModel, integ: Integrator, grid: np.ndarray, work: bool, err: RuntimeError,
                         args: dict, stats: dict) -> dict[str, np.ndarray] | None:
    """The run of `args` again without IDACalcIC, from the model's consistent accelerations and state
    derivatives, when `err` is IDAS failing to correct its start (else None).

    The DAE's algebraic states are the free accelerations, which `PressModel.accelerations` gives
    exactly for any state, and with them the state derivatives, so IDACalcIC's correction is not
    needed. From mid-cycle states of the 8-element rod and of one mode of it its Newton iteration
    failed (IDA_CONV_FAIL from zero accelerations, IDA_LINESEARCH_FAIL from the consistent ones) at
    every rtol from 1e-6 to 1e-10; started from zero state derivatives instead, IDAS failed its first
    step on an impacting cycle (IDA_ERR_FAIL). Each column of `args` gets its own integrator (the
    start's derivatives are a construction option), not kept. The failure and the restart are
    recorded in `stats` under ``initial_conditions``."""
    if integ.method != "idas" or not calc_ic_failed(err):
        return None
    x0 = np.asarray(args["x0"], float)
    cols = x0.reshape(model.nx, -1, order="F")
    ps = np.asarray(args["p"], float).reshape(-1, cols.shape[1], order="F")
    if "rates" not in model.functions:  # on the 8-element rod every run comes here: built once per model
        dae = model.dae(explicit=False, work=False)
        model.functions["rates"] = ca.Function("rates", [dae["t"], dae["x"], dae["z"], dae["p"]], [dae["ode"]])
    rates = model.functions["rates"]
    code = re.search(r"IDA_[A-Z_]+", str(err))
    stats["initial_conditions"] = CALC_IC_FAILED.format(code.group(0) if code else first_line(err))
    runs = []
    for x, p in zip(cols.T, ps.T):
        z = model.z0(x, p)
        F = _build_integrator(model, integ, grid, work, start=np.asarray(rates(0.0, x, z, p)).ravel())
        try:
            with interruptible():
                runs.append(call(F, stats=stats, x0=x, z0=z, p=p))
        except RuntimeError as again:
            raise SimulationError(f"{first_line(again)} (started without IDACalcIC, which had failed: "
                                  f"{first_line(err)})", time=float(stats.get("tcur", np.nan)), method="idas",
                                  hint=HINT) from None
    return {k: np.hstack([np.asarray(r[k]) for r in runs]) if x0.ndim > 1 else runs[0][k] for k in runs[0]}


def compiled_dae(dae: dict, derivatives: str = "same") -> ca.Function:
    """The DAE dict as a `casadi.Function` in the integrator's own form (inputs `casadi.dyn_in`,
    outputs `casadi.dyn_out`), compiled with its derivatives through the compile cache
    (``derivatives="quick"``: those at `pressocp.compile_cache.QUICK_FLAGS`). Given to an integrator
    as it is, only its derivatives run compiled: the integrator re-expands an SX function into its own
    right-hand side (`integrator_dae` wraps it so that the compiled code is called)."""
    sym = type(dae["x"])
    empty = sym(0, 1)
    ins = [dae["t"], dae["x"], dae.get("z", empty), dae["p"], empty]
    outs = [dae["ode"], dae.get("alg", empty), dae.get("quad", empty), empty]
    with compiling():
        return ca.Function("press_dae", ins, outs, ca.dyn_in(), ca.dyn_out(), function_options(True, derivatives))


def integrator_dae(model: PressModel, explicit: bool, work: bool) -> ca.Function:
    """The model's DAE for a SUNDIALS integrator, evaluated by compiled code: an MX function calling
    the compiled `compiled_dae` (its derivatives compiled quickly), kept in ``model.functions``.

    CasADi builds an integrator's right-hand side and Jacobian from its DAE; from an SX function
    (compiled or not) it re-expands the expressions and evaluates them on its virtual machine, where a
    flexible rod's impacting cycle spent nine tenths of its time. Through the MX call the compiled
    code runs: 0.2 s of the rigid rod's impacting design took 0.65 s with IDAS interpreted and 0.38 s
    compiled, the 4-element rod 2.09 s and 0.90 s (docs/decisions/2026-11-26-compiled-integrator.md).
    The first compile for a press takes seconds (the rigid rod 1.6 s with IDAS, the 4-element rod
    5 s; with CVODES's explicit form 2.7 and 23 s); the compile cache keeps it for the next process.
    """
    key = ("integrator_dae", bool(explicit), bool(work))
    if key not in model.functions:
        model.functions[key] = calling(compiled_dae(model.dae(explicit=explicit, work=work), derivatives="quick"))
    return model.functions[key]


def calling(f: ca.Function) -> ca.Function:
    """An MX function of `f`'s inputs and outputs whose only node calls `f`: what an integrator needs to
    evaluate a compiled DAE function as compiled code (`integrator_dae`)."""
    ins = [ca.MX.sym(f.name_in(i), f.sparsity_in(i)) for i in range(f.n_in())]
    return ca.Function(f.name() + "_call", ins, f(*ins), f.name_in(), f.name_out())


def for_repeated_use(model: PressModel) -> PressModel:
    """`model` with its SUNDIALS integrators compiled when its ``jit`` is "auto" and a C compiler is
    found, else `model` itself (also a model without states: nothing to integrate). For a caller that
    re-simulates one model many times: the optimiser's checks and its verification. "auto" alone
    leaves a rigid rod interpreted, because one check costs less than its compile; an optimisation
    re-simulates the same model ten times or more, and the compile (about 0.7 s for the rigid rod,
    once per press and DAE form: the compile cache keeps it for later processes) pays back in the
    first. On press75 (2026-11-28): the rigid optimum's screen 2.7 s compiled against 5.0 s, the
    seed optimum's verification at rtol 1e-9 1.2 against 2.6 s, the same peak to 8 digits. The
    functions built of it are shared with `model`
    (docs/decisions/2026-11-28-compiled-checks.md)."""
    if model.is_rigid or model.jit != "auto" or not use_jit("auto", "the optimiser's re-simulations"):
        return model
    return model if runs_compiled(model) else replace(model, jit=True)


def runs_compiled(model: PressModel) -> bool:
    """Whether `model`'s SUNDIALS integrators call compiled code: ``model.jit`` True, or "auto" on a
    flexible rod, when a C compiler is found (else a warning says the virtual machine runs them).
    Raises ValueError when ``model.jit`` is none of True, False, "auto"."""
    check_jit(model.jit)
    wanted = model.jit is True or (model.jit == "auto" and model.rod == "flexible")
    return wanted and use_jit("auto", "the simulation")


def _build_integrator(model: PressModel, integ: Integrator, grid: np.ndarray, work: bool,
                      start: np.ndarray | None = None) -> ca.Function:
    """The integrator of `_integrator`; IDAS starts from the state derivatives `start` (scaled, 1/s)
    instead of correcting its start by IDACalcIC when they are given (`started_consistently`)."""
    method = integ.method
    explicit = method != "idas"
    sundials = method in ("idas", "cvodes")
    dae = (integrator_dae(model, explicit, work) if sundials and runs_compiled(model)
           else model.dae(explicit=explicit, work=work))
    opts: dict[str, Any] = {}
    if sundials:
        opts.update(reltol=integ.rtol, abstol=integ.abstol, max_num_steps=integ.max_steps)
        if method == "idas":
            opts.update(calc_ic=start is None, suppress_algebraic=True)
            if start is not None:
                opts.update(init_xdot=list(start))
    else:
        # CasADi takes the number of steps over the whole run [0, grid[-1]] (at least one per output)
        opts.update(number_of_finite_elements=max(grid.size, int(np.ceil(float(grid[-1]) / integ.step))))
        if method == "collocation":
            opts.update(interpolation_order=3, collocation_scheme="radau")
    return ca.integrator("press_" + method.replace("-", "_"), method, dae, 0.0, grid, opts)


def _stats(raw: dict, wall: float) -> dict:
    keys = {"nsteps": "steps", "nfevals": "rhs_evaluations", "nresevals": "rhs_evaluations",
            "netfails": "error_test_failures", "nncfails": "convergence_failures", "nniters": "newton_iterations"}
    out = {"wall_time": wall}
    for k, v in raw.items():
        if k in keys and np.isscalar(v):
            out[keys[k]] = int(v)
    if "initial_conditions" in raw:
        out["initial_conditions"] = raw["initial_conditions"]
    return out


def integrate(model: PressModel, integ: Integrator, x0: np.ndarray, p: np.ndarray, grid: np.ndarray,
              work: bool = True) -> tuple[np.ndarray, np.ndarray, dict]:
    """Integrate the scaled states from `x0` at t = 0 over `grid` (s, the first entry > 0) with the
    parameter vector `p`. Returns (X, Qf, stats); Qf has no rows without `work` (no quadratures
    integrated, by any method)."""
    method = integ.method
    if method.startswith("scipy"):
        return _run_scipy(model, integ, x0, p, grid, work)
    F = _integrator(model, integ, grid, work)
    args = {"x0": x0, "p": p}
    if method == "idas":
        args["z0"] = model.z0(x0, p)
    t0, raw = time.perf_counter(), {}
    try:
        res = first_try(F, raw, args)
    except RuntimeError as err:
        res = started_consistently(model, integ, grid, work, err, args, raw)
        if res is None:
            raise SimulationError(first_line(err), time=float(raw.get("tcur", np.nan)), method=method,
                                  hint=HINT) from None
    wall = time.perf_counter() - t0
    X, Qf = res["xf"], res["qf"]
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(Qf))):
        raise SimulationError("non-finite state", method=method, hint=HINT)
    return X, Qf, _stats(raw, wall)


def output_function(model: PressModel, samples: int) -> ca.Function:
    """`PressModel.outputs` mapped over `samples` columns, compiled by the system C compiler when
    there is one (through the on-disk compile cache, `pressocp.compile_cache`: 0.2 s for the rigid
    rod and 2.7 s for a 4-element rod the first time, then a link), else CasADi's virtual machine
    with a warning. Kept in ``model.functions``. Over 20 001 samples it evaluates in 0.13 s instead
    of 0.25 s on the rigid rod, 0.23 s instead of 1.15 s on the 4-element rod, to the same bits."""
    key = ("outputs", "compiled")
    if key not in model.functions:
        f = model.outputs
        with compiling():
            model.functions[key] = ca.Function(f.name(), f.sx_in(), f.call(f.sx_in()), f.name_in(), f.name_out(),
                                               jit_options()) if use_jit("auto", "the simulation's outputs") else f
    mapped = ("outputs", "compiled", samples)
    if mapped not in model.functions:
        model.functions[mapped] = model.functions[key].map(samples)
    return model.functions[mapped]


def first_line(err: Exception) -> str:
    lines = [s for s in str(err).splitlines() if s.strip()]
    useful = [s for s in lines if any(k in s for k in ("IDA_", "CV_", "failed", "Maximum", "error"))]
    return (useful or lines or ["integrator error"])[-1].strip()[:500]


def _run_scipy(model: PressModel, integ: Integrator, x0: np.ndarray, p: np.ndarray, grid: np.ndarray,
               work: bool = True) -> tuple[np.ndarray, np.ndarray, dict]:
    from scipy.integrate import BDF, Radau  # baseline only

    method, max_steps = integ.method, integ.max_steps
    nx, nq = model.nx, (model.quad.numel() if work else 0)
    rhs = ca.Function("rhs", [model.t, model.x, model.p],
                      [ca.vertcat(model.ode_explicit, model.quad) if work else model.ode_explicit])
    xa = ca.SX.sym("xa", nx + nq)
    # a compiled model's baseline calls compiled code too, as the SUNDIALS integrators do
    opts = function_options(True, "quick") if runs_compiled(model) else {}
    with compiling():
        rhs_aug = ca.Function("rhs_aug", [model.t, xa], [rhs(model.t, xa[:nx], p)], opts)
        jac = ca.Function("rhs_jacobian", [model.t, xa], [ca.jacobian(rhs_aug(model.t, xa), xa)], opts)
    solver_cls = Radau if method == "scipy-radau" else BDF
    t0 = time.perf_counter()
    solver = solver_cls(lambda t, y: np.asarray(rhs_aug(t, y)).ravel(), 0.0, np.concatenate([x0, np.zeros(nq)]),
                        float(grid[-1]), rtol=integ.rtol, atol=integ.abstol, jac=lambda t, y: np.asarray(jac(t, y)))
    Y = np.empty((nx + nq, grid.size))
    k, steps = 0, 0
    while k < grid.size:
        if solver.status != "running" and solver.t < grid[-1]:
            raise SimulationError(str(solver.status), time=float(solver.t), method=method, hint=HINT)
        if steps >= max_steps:
            raise SimulationError(f"maximum number of steps ({max_steps}) reached", time=float(solver.t),
                                  method=method, hint=HINT)
        t_prev = solver.t
        msg = solver.step()
        steps += 1
        if solver.status == "failed":
            raise SimulationError(str(msg), time=float(solver.t), method=method, hint=HINT)
        dense = solver.dense_output()
        while k < grid.size and grid[k] <= solver.t:
            Y[:, k] = dense(grid[k]) if grid[k] > t_prev else solver.y
            k += 1
    wall = time.perf_counter() - t0
    return Y[:nx], Y[nx:], {"wall_time": wall, "steps": steps, "rhs_evaluations": int(solver.nfev),
                            "jacobian_evaluations": int(solver.njev), "lu_decompositions": int(solver.nlu)}


def periodic_state(model: PressModel, speed: FourierSpeed, integrator: Integrator = SHOTS,
                   x_start: np.ndarray | None = None, tol: float | None = None, max_settle: int = 12,
                   max_newton: int = 8) -> tuple[np.ndarray, dict]:
    """Periodic steady state x(T) = x(0) of the scaled states.

    First it simulates cycle by cycle (the bearings' normal and film damping make the periodic
    orbit attracting, typically within a few cycles); if the change per cycle is still above
    ``tol`` after ``max_settle`` cycles, it switches to Newton's method on one-period shooting with
    a finite-difference Jacobian (the nx + 1 shots run in 2 threads) and a backtracking line
    search. (Forward sensitivities give the same Jacobian but took 3.5x longer here.)

    Parameters
    ----------
    model : PressModel
    speed : FourierSpeed
    integrator : Integrator
        Integrator of the shots ("idas", "cvodes" or "cvodes-direct"; any other method shoots with
        CVODES), default
        CVODES at rtol 1e-8 (`SHOTS`).
    x_start : ndarray, optional
        Scaled start state; default the model's initial state.
    tol : float, optional
        Max-norm of x(T) - x(0) in scaled states (eccentricity/clearance; rates/(1000 clearance));
        default max(1e-4, 100 rtol) (the integrator's rtol): 1e-8 m and 1e-5 m/s at a 0.1 mm clearance.
    max_settle, max_newton : int
        Cycle and Newton-step limits.

    Returns
    -------
    x0 : ndarray
        Scaled periodic state.
    info : dict
        ``cycles`` settled, ``newton`` steps, ``residual``.

    Raises
    ------
    SimulationError
        When neither settling nor Newton reach ``tol``.
    """
    X, info = periodic_orbit(model, speed, np.zeros(1), integrator, x_start, tol, max_settle, max_newton)
    info.pop("last_cycle")
    return X[:, 0], info


def periodic_orbit(model: PressModel, speed: FourierSpeed, times: np.ndarray, integrator: Integrator = SHOTS,
                   x_start: np.ndarray | None = None, tol: float | None = None, max_settle: int = 12,
                   max_newton: int = 8, from_rest: bool = False) -> tuple[np.ndarray, dict]:
    """Scaled states at `times` along the periodic steady state (`periodic_state`), found and sampled
    in the same integrations: a settling cycle expected to settle is integrated on `times`, and the
    first cycle that ends within `tol` of where it started is the answer (its states at `times`, the
    start state being the periodic one). A cycle that is not expected to settle integrates only its
    end state: a dense output grid can make CVODES take more steps (12 152 against 6 770 for 20 001
    and 201 samples on one scene; none more at the 75 spm seed optimum, 27 000 either way).
    Expected to settle: the first cycle unless `from_rest`, the
    second, and later ones whose residual, shrunk by the last cycle's contraction, would be within
    `tol`. When a cycle without the grid settles, or Newton's method had to finish the search, one
    more cycle is integrated on `times` from its state.

    Parameters
    ----------
    times : ndarray
        Non-decreasing sample times in [0, T], the first 0 (s); T is appended for the shots when the
        last one is earlier.
    integrator, x_start, tol, max_settle, max_newton
        As in `periodic_state`.
    from_rest : bool
        The start is far from the orbit (the model's rest state: the journals centred, the rod
        undeformed), so the first cycle is a transient that cannot be the answer.

    Returns
    -------
    X : ndarray, nx x len(times)
        Scaled states; ``X[:, 0]`` is the periodic state.
    info : dict
        ``cycles`` settled, ``newton`` steps, ``residual``, and ``last_cycle``: the integrator's
        statistics of the cycle returned (as in ``SimResult.stats``).
    """
    times = np.asarray(times, float)
    T = speed.period
    if times.ndim != 1 or times.size < 1 or times[0] != 0.0 or np.any(np.diff(times) < -1e-12 * T) \
            or times[-1] > T * (1 + 1e-12):
        raise ValueError(f"times must not decrease, from 0 to at most the period {T:g} s")
    if model.is_rigid:
        return np.zeros((0, times.size)), {"cycles": 0, "newton": 0, "residual": 0.0}
    chk.instance("integrator", integrator, Integrator)
    shots = replace(integrator, method=integrator.method if integrator.method in SHOOTING else "cvodes",
                    max_steps=10**8, step=FIXED_STEP)
    tol = max(1e-4, 100 * shots.rtol) if tol is None else tol
    sh = PeriodicShots(model, speed, times, shots)
    x = model.x0 if x_start is None else np.asarray(x_start, float)
    res, residuals = np.inf, []
    for cycle in range(1, max_settle + 1):
        dense = expect_settled(residuals, tol, from_rest)
        X = sh.shoot(x, sh.F if dense else sh.end_only())
        res = float(np.max(np.abs(X[:, -1] - x)))
        if res <= tol:
            X = X if dense else sh.shoot(x)
            return sh.sampled(x, X), {"cycles": cycle, "newton": 0, "residual": res, "last_cycle": sh.last_cycle()}
        residuals.append(res)
        x = X[:, -1]
    x, res, it = newton_periodic(sh, x, res, tol, max_newton)
    if res <= tol:
        X = sh.shoot(x) if times.size > 1 else np.zeros((model.nx, 1))
        return sh.sampled(x, X), {"cycles": max_settle, "newton": it, "residual": res, "last_cycle": sh.last_cycle()}
    raise SimulationError(
        f"periodic steady state not found: residual {res:.3g} (tol {tol:.3g}) after {max_settle} cycles and "
        f"{it} Newton steps{'' if it == max_newton else ', the last finding no lower residual along its direction'}",
        method=shots.method + " (periodic shooting)",
        hint="more bearing damping (damping, tangential_damping) or a looser tol")


class PeriodicShots:
    """One-period shots of the periodic search (`periodic_orbit`): the integrator on the sample grid
    `F`, the one that returns only the end state (built when first needed), the samples of a cycle
    and the integrator's statistics of the last shot.

    Parameters
    ----------
    times : ndarray
        Sample times in [0, T] from 0, s; T is appended for the shots when the last one is earlier.
    shots : Integrator
        IDAS, CVODES or CVODES direct (`SHOOTING`).
    """

    def __init__(self, model: PressModel, speed: FourierSpeed, times: np.ndarray, shots: Integrator) -> None:
        T = speed.period
        self.model, self.shots, self.period, self.p = model, shots, T, model.parameters(speed)
        self.ends_at_T = bool(times[-1] >= T * (1 - 1e-12))
        grid = np.append(times[1:-1], T) if self.ends_at_T else np.append(times[1:], T)
        self.grid = grid
        self.F = _integrator(model, shots, grid, work=False)
        self.started, self.last = time.perf_counter(), {}  # the last shot's statistics
        self.end = self.F if grid.size == 1 else None

    def shoot(self, xs: np.ndarray, F: ca.Function | None = None) -> np.ndarray:
        """The states at `F`'s grid (default `F`) of the shots from the columns of `xs` (or from `xs`);
        a shot whose IDACalcIC fails starts again from consistent accelerations (`started_consistently`)."""
        F = self.F if F is None else F
        self.started, self.last = time.perf_counter(), {}
        p = np.tile(self.p[:, None], (1, xs.shape[1])) if xs.ndim > 1 else self.p
        try:
            return first_try(F, self.last, {"x0": xs, "p": p})["xf"]
        except RuntimeError as err:
            grid = self.grid if F is self.F else np.array([self.period])
            res = started_consistently(self.model, self.shots, grid, False, err, {"x0": xs, "p": p}, self.last)
            if res is None:
                raise SimulationError(first_line(err), time=float(self.last.get("tcur", np.nan)),
                                      method=self.shots.method + " (periodic shooting)", hint=HINT) from None
            return res["xf"]

    def end_only(self) -> ca.Function:
        """The integrator of one period that returns only its end state."""
        if self.end is None:
            self.end = _integrator(self.model, self.shots, np.array([self.period]), work=False)
        return self.end

    def sampled(self, x_from: np.ndarray, X: np.ndarray) -> np.ndarray:
        """The states at the sample times of the shot from `x_from` whose grid states are `X`."""
        return np.hstack([x_from[:, None], X if self.ends_at_T else X[:, :-1]])

    def last_cycle(self) -> dict:
        """The statistics of the last shot (as in ``SimResult.stats``)."""
        return _stats(self.last, time.perf_counter() - self.started)


def newton_periodic(sh: PeriodicShots, x: np.ndarray, res: float, tol: float,
                    max_newton: int) -> tuple[np.ndarray, float, int]:
    """Newton's method on x(T) - x(0) from `x` (residual `res`): a finite-difference Jacobian from
    nx + 1 shots run in 2 threads, and a backtracking line search. Returns the state with the lowest
    residual, that residual and the steps taken. It stops at `tol`, after `max_newton` steps, or at a
    step whose line search finds no lower residual down to a thousandth of the Newton step: there the
    map is not smooth enough for Newton (on the 75 spm kinematic design the Jacobians of successive
    iterates had Floquet multipliers of 17 to 70, and the steps that followed such a failure never
    reached the tolerance: 131 s for 8 steps)."""
    nx = sh.model.nx
    F1 = sh.end_only()
    Fmap = F1.map(nx + 1, "thread", 2)
    h = 1e-6
    for it in range(1, max_newton + 1):
        Y = sh.shoot(np.hstack([x[:, None], x[:, None] + h * np.eye(nx)]), Fmap)
        J = (Y[:, 1:] - Y[:, [0]]) / h
        dx = np.linalg.lstsq(J - np.eye(nx), -(Y[:, 0] - x), rcond=None)[0]
        step = 1.0
        while True:
            xn = x + step * dx
            rn = float(np.max(np.abs(sh.shoot(xn, F1).ravel() - xn)))
            if rn < res:
                break
            step /= 2
            if step <= 1e-3:
                return x, res, it
        x, res = xn, rn
        if res <= tol:
            return x, res, it
    return x, res, max_newton


def expect_settled(residuals: list[float], tol: float, from_rest: bool) -> bool:
    """Whether the next settling cycle is expected to end within `tol` (`periodic_orbit`), given the
    residuals (max-norm of x(T) - x(0)) of the cycles so far: the first cycle unless it starts from
    rest, the second, and a later one when the last residual times the last contraction
    (its ratio to the one before) is within `tol`."""
    if not residuals:
        return not from_rest
    if len(residuals) == 1:
        return True
    return residuals[-1] * (residuals[-1] / residuals[-2]) <= tol


def simulate(
    model: PressModel,
    speed: FourierSpeed,
    t_end: float | None = None,
    cycles: int = 1,
    periodic: bool = False,
    integrator: Integrator = Integrator(),
    n_out: int | None = None,
    x0: np.ndarray | None = None,
    work: bool = True,
) -> SimResult:
    """Simulate the press over time.

    Parameters
    ----------
    model : PressModel
        From `build_model`.
    speed : FourierSpeed
        Prescribed crank speed.
    t_end : float, optional
        End time, s (> 0); default ``cycles * speed.period``.
    cycles : int
        Cycles to simulate when ``t_end`` is not given, 1..1000.
    periodic : bool
        First find the periodic steady state (`periodic_state`), then return ``cycles`` cycles from it.
    integrator : Integrator
        Method, tolerances and step limits, e.g. ``Integrator("cvodes", rtol=1e-9)``; default IDAS at
        rtol 1e-6.
    n_out : int, optional
        Output samples; default 4000 per cycle + 1.
    x0 : ndarray, optional
        Scaled initial state; default the model's consistent initial state (journals centred).
    work : bool
        Integrate the work quadratures (motor, contact, process and damping work in ``energy``); they
        cost 30-48 % of an integration, so a run that reads no work should say False. Without them,
        a periodic run of one cycle at rtol <= 1e-8 by a `SHOOTING` method (atol = rtol) is the periodic
        search's own last cycle (`periodic_orbit`), not a cycle integrated again. Either way the
        cycle is periodic to `Integrator.periodic_tol`.

    Returns
    -------
    SimResult
        Includes ``stats`` (wall_time, steps, rhs evaluations, failures) and ``energy`` (kinetic and
        potential energy at both ends, and with `work` the motor, contact, process and damping work, J).

    Raises
    ------
    ValueError
        Bad arguments.
    SimulationError
        The integrator failed.
    """
    if isinstance(integrator, str):
        raise ValueError(f"integrator must be an Integrator, e.g. Integrator({integrator!r}, rtol=1e-8); got the "
                         f"string {integrator!r}")
    chk.instance("integrator", integrator, Integrator)
    chk.instance("model", model, PressModel)
    chk.instance("speed", speed, FourierSpeed)
    ncyc = chk.integer("cycles", cycles, 1, 1000)
    T_end = ncyc * speed.period if t_end is None else chk.positive("t_end", t_end, "s")
    n = max(2, int(round(OUTPUTS_PER_CYCLE * T_end / speed.period)) + 1) if n_out is None else chk.integer("n_out", n_out, 2, 10**8)
    p = model.parameters(speed)
    t = np.linspace(0.0, T_end, n)
    stats: dict = {}
    x_init = model.x0 if x0 is None else chk.finite_array("x0", x0)
    if x_init.size != model.nx:
        raise ValueError(f"x0 must have {model.nx} entries (the model's states), got {x_init.size}")
    X = None
    if periodic and not model.is_rigid:
        X, x_init = periodic_start(model, speed, integrator, t, x_init, x0 is None, work, stats)
    Qf = None
    if model.is_rigid:
        X = np.zeros((0, n))
        stats["wall_time"] = 0.0
    elif X is None:
        X, Qf, run_stats = integrate(model, integrator, x_init, p, t[1:], work)
        X = np.hstack([x_init[:, None], X])
        stats.update(run_stats)
    return sim_result(model, p, t, X, Qf, stats, integrator.method)


def periodic_start(model: PressModel, speed: FourierSpeed, integrator: Integrator, t: np.ndarray, x_init: np.ndarray,
                   from_rest: bool, work: bool, stats: dict) -> tuple[np.ndarray | None, np.ndarray]:
    """The periodic state of a periodic `simulate` run, searched from `x_init`, and the run's states at
    `t` when the search's own last cycle is the answer (no work, one cycle, a `SHOOTING` method at rtol
    <= 1e-8 with atol = rtol), else None; periodic to `Integrator.periodic_tol` either way. The search's
    statistics go to ``stats["periodic"]`` (and its last cycle's to `stats`)."""
    if integrator.method == DIRECT:  # work=True, or a driver it cannot build, refused before searching
        direct_driver(model, work)
    t0, r = time.perf_counter(), integrator.rtol
    search = integrator.method if integrator.method in SHOOTING else "cvodes"
    X = None
    if not work and integrator.method == search and r <= 1e-8 and integrator.abstol == r and t[-1] == speed.period:
        X, info = periodic_orbit(model, speed, t, Integrator(search, r), x_start=x_init,
                                 tol=max(1e-5, 1000 * r) if integrator.periodic_tol is None else integrator.periodic_tol,
                                 from_rest=from_rest)
        x_init = X[:, 0]
        stats.update(info.pop("last_cycle"))
    else:
        x_init, info = periodic_state(model, speed, Integrator(search, min(r, 1e-8)), x_start=x_init,
                                      tol=integrator.periodic_tol)  # None: periodic_state's default
    stats["periodic"] = {**info, "wall_time": time.perf_counter() - t0}
    return X, x_init


def sim_result(model: PressModel, p: np.ndarray, t: np.ndarray, X: np.ndarray, Qf: np.ndarray | None, stats: dict,
               method: str) -> SimResult:
    """The `SimResult` of scaled states `X` at times `t` (s) with the parameter vector `p`: the outputs
    (a non-finite one raises `SimulationError`), the energies at both ends and the work integrals
    `Qf` (None or no rows: not integrated)."""
    n = t.size
    out = evaluate(output_function(model, n), t, X if X.size else np.zeros((0, n)), np.tile(p[:, None], (1, n)))
    series = {name: v.ravel() for name, v in zip(OUTPUT_NAMES, out)}
    for name, v in series.items():
        if not np.all(np.isfinite(v)):
            raise SimulationError(f"non-finite {name}", method=method, hint=HINT)
    x_start, x_end = (X[:, 0], X[:, -1]) if X.size else (model.x0, model.x0)
    E0 = [float(v) for v in model.energy(0.0, x_start, p)]
    E1 = [float(v) for v in model.energy(t[-1], x_end, p)]
    energy = {"kinetic_start": E0[0], "potential_start": E0[1], "kinetic_end": E1[0], "potential_end": E1[1]}
    if Qf is not None and Qf.shape[0]:
        energy.update({k: float(Qf[i, -1]) for i, k in enumerate(QUADRATURE_NAMES)})
    states = X * model.x_scale[:, None] if X.size else X
    return SimResult(t=t, stats=stats, energy=energy, states=states, **{k: series[k] for k in OUTPUT_NAMES})
