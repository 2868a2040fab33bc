"""Multiple-shooting transcription on a model with states (bearing clearance, flexible rod).

The period is cut into N equal intervals. One interval integrator (IDAS on the semi-explicit DAE,
or CVODES on the explicit ODE) takes the node state, the speed parameters and the interval's start
time, and returns the end state and the loads at S output samples inside the interval. It is
built once, given forward-mode sensitivities (the backward IDAS pass fails on clearance contact)
and mapped over the intervals in threads. The NLP variables are the Fourier coefficients, the
node states and the epigraph variable; IPOPT uses a limited-memory Hessian.

The working window [t1, t2] is held at the warm start's (h(t1) = h1 H becomes a constraint on the
crank angle at the fixed t1), so the set of samples inside it does not jump between iterations.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from .. import _checks as chk
from ..model import OUTPUT_NAMES, PressModel
from ..simulate import HINT, SimulationError, _first_line, _run
from ..speed import FourierSpeed
from .constraints import Constraints, add_epigraph, add_speed_bounds, add_window, crank_map, violation
from .problem import SpeedProblem
from .rigid import IPOPT_DEFAULTS, _ram_function

#: Outputs each objective bounds at every sample.
LOADS = {"peak_torque": ("torque",), "peak_slider_normal_force": ("slider_normal_force",),
         "peak_pin_force": ("crank_pin_force", "wrist_pin_force"), "rms_torque": ("torque",)}
SHOOTING_METHODS = ("idas", "cvodes")


class ShootingError(SimulationError):
    """An interval integrator failed. Attributes: ``stage``, ``interval`` (0-based), ``t_start``, ``t_end``."""

    def __init__(self, message: str, stage: str, interval: int, t_start: float, t_end: float, method: str):
        self.stage, self.interval, self.t_start, self.t_end = stage, interval, t_start, t_end
        super().__init__(f"stage {stage!r}, shooting interval {interval} (t = {t_start:.4g}..{t_end:.4g} s): "
                         f"{message}", method=method, hint=HINT)


@dataclass(frozen=True)
class ShootingGrid:
    """Equal shooting intervals with S output samples each (the last one at the interval's end).

    Attributes
    ----------
    period : float
        s.
    intervals : int
        N.
    samples : int
        S per interval.
    """

    period: float
    intervals: int
    samples: int

    @property
    def h(self) -> float:
        """Interval length, s."""
        return self.period / self.intervals

    @property
    def nodes(self) -> np.ndarray:
        """Start times of the intervals, s."""
        return self.h * np.arange(self.intervals)

    @property
    def local(self) -> np.ndarray:
        """Sample times inside an interval, measured from its start, s."""
        return self.h * np.arange(1, self.samples + 1) / self.samples

    @property
    def times(self) -> np.ndarray:
        """All sample times in the order of the mapped outputs, s."""
        return (self.nodes[:, None] + self.local[None, :]).ravel()


def interval_function(model: PressModel, grid: ShootingGrid, names: tuple[str, ...], method: str = "idas",
                      rtol: float = 1e-6, atol: float | None = None, max_steps: int = 10**6) -> ca.Function:
    """One shooting interval as a CasADi Function with forward-mode derivatives.

    Returns
    -------
    ca.Function
        ``(x0 [nx], p [np], t0) -> (xf [nx], y [len(names) x S])``: scaled end state and the outputs
        `names` (see `pressocp.model.OUTPUT_NAMES`) at ``t0 + grid.local``.
    """
    chk.choice("method", method, SHOOTING_METHODS)
    tau, t0 = ca.SX.sym("tau"), ca.SX.sym("t0")
    explicit = method != "idas"
    dae = model.dae(explicit=explicit)
    dae.pop("quad")
    for k in ("ode", "alg"):
        if k in dae:
            dae[k] = ca.substitute(dae[k], model.t, tau + t0)
    dae.update(t=tau, p=ca.vertcat(model.p, t0))
    opts = {"reltol": rtol, "abstol": rtol if atol is None else atol, "max_num_steps": max_steps}
    if method == "idas":
        opts.update(calc_ic=True, suppress_algebraic=True)
    F = ca.integrator("shooting_" + method, method, dae, 0.0, grid.local, opts)
    x0, p, ts = ca.MX.sym("x0", model.nx), ca.MX.sym("p", model.p.numel()), ca.MX.sym("t0")
    args = {"x0": x0, "p": ca.vertcat(p, ts)}
    if method == "idas":
        args["z0"] = model.accelerations(ts, x0, p)
    X = F(**args)["xf"]
    S = grid.samples
    out = model.outputs.map(S)(ts + ca.DM(grid.local).T, X, ca.repmat(p, 1, S))
    idx = [OUTPUT_NAMES.index(n) for n in names]
    y = ca.vertcat(*[out[i] for i in idx])
    return ca.Function("interval", [x0, p, ts], [X[:, -1], y], ["x0", "p", "t0"], ["xf", "y"],
                       {"ad_weight": 0.0, "ad_weight_sp": 0.0})


def states_at(model: PressModel, speed: FourierSpeed, x_start: np.ndarray, times: np.ndarray,
              method: str = "cvodes", rtol: float = 1e-6) -> np.ndarray:
    """Scaled states at ``times`` (the first 0), integrated from ``x_start`` at t = 0 (nx x len(times))."""
    x_start = np.asarray(x_start, float)[:, None]
    if len(times) == 1:
        return x_start
    X, _, _ = _run(model, method, x_start[:, 0], model.parameters(speed), np.asarray(times)[1:], rtol, rtol,
                   10**7, 1e-5)
    return np.hstack([x_start, X])


def node_states(model: PressModel, speed: FourierSpeed, x_start: np.ndarray, grid: ShootingGrid,
                method: str = "idas", rtol: float = 1e-6) -> np.ndarray:
    """Scaled states at the shooting nodes, integrated from ``x_start`` at t = 0 (nx x N)."""
    return states_at(model, speed, x_start, grid.nodes, method, rtol)


def locate_failure(G: ca.Function, X: np.ndarray, p: np.ndarray, grid: ShootingGrid, stage: str,
                   method: str) -> ShootingError | None:
    """Integrate every interval separately; the first failure as a `ShootingError`, or None."""
    for k, t0 in enumerate(grid.nodes):
        try:
            xf, y = G(X[:, k], p, t0)
            if not (np.all(np.isfinite(np.asarray(xf))) and np.all(np.isfinite(np.asarray(y)))):
                raise RuntimeError("non-finite state or output")
        except RuntimeError as err:
            return ShootingError(_first_line(err), stage, k, float(t0), float(t0 + grid.h), method)
    return None


class _Iterations(ca.Callback):
    """IPOPT iteration callback: objective history, the least-infeasible iterate, optional tqdm bar."""

    def __init__(self, nx: int, ng: int, lbg: np.ndarray, ubg: np.ndarray, bar=None):
        ca.Callback.__init__(self)
        self.nx, self.ng, self.lbg, self.ubg, self.bar = nx, ng, lbg, ubg, bar
        self.history: list[float] = []
        self.best: tuple[float, float, np.ndarray] | None = None
        self.construct("iterations", {})

    def get_n_in(self):
        return ca.nlpsol_n_out()

    def get_n_out(self):
        return 1

    def get_name_in(self, i):
        return ca.nlpsol_out(i)

    def get_name_out(self, i):
        return "ret"

    def get_sparsity_in(self, i):
        n = ca.nlpsol_out(i)
        if n == "f":
            return ca.Sparsity.scalar()
        if n in ("x", "lam_x"):
            return ca.Sparsity.dense(self.nx)
        if n in ("g", "lam_g"):
            return ca.Sparsity.dense(self.ng)
        return ca.Sparsity(0, 0)

    def eval(self, arg):
        f = float(arg[1])
        g = np.asarray(arg[2]).ravel()
        viol = float(np.max(violation(g, self.lbg, self.ubg), initial=0.0))
        self.history.append(f)
        if self.best is None or (viol, f) < (self.best[0], self.best[1]) or (viol <= 1e-6 and f < self.best[1]):
            self.best = (viol, f, np.asarray(arg[0]).ravel().copy())
        if self.bar is not None:
            self.bar.update(1)
            self.bar.set_postfix(objective=f"{f:.4g}", infeasibility=f"{viol:.2g}")
        return [0]


@dataclass
class ShootingSolution:
    """Raw output of one shooting (or collocation) stage (turned into an `OcpResult` by `optimize_speed`).

    ``speed`` and ``nodes`` are the solution, or when IPOPT did not succeed its least infeasible
    iterate; ``last_speed`` is IPOPT's final iterate either way."""

    speed: FourierSpeed
    nodes: np.ndarray
    value: float
    success: bool
    status: str
    iterations: int
    wall_time: float
    history: list
    barrier: list
    last_speed: FourierSpeed
    violations_start: dict
    violations: dict
    failure: ShootingError | None


def solve_shooting(problem: SpeedProblem, model: PressModel, initial: FourierSpeed, nodes: np.ndarray,
                   t1: float, grid: ShootingGrid, stage: str = "clearance", periodic: bool = True,
                   method: str = "idas", rtol: float = 1e-6, window_samples: int = 200,
                   omega_samples: int = 1000, ipopt_options: dict | None = None, progress: bool = False,
                   scale: float | None = None, max_steps: int = 10**6,
                   coefficient_step: float | None = None,
                   min_eccentricity: float | None = None) -> ShootingSolution:
    """One multiple-shooting stage of the speed problem on `model`, warm-started at (initial, nodes).

    Parameters
    ----------
    problem : SpeedProblem
    model : PressModel
        A model with states; its ``n_harmonics`` must equal the problem's.
    initial : FourierSpeed
        Warm-start speed (period = problem's period).
    nodes : ndarray
        Warm-start scaled node states, nx x N (e.g. `node_states` from its periodic state).
    t1 : float
        Window start, s, held fixed (t2 = t1 + window duration).
    grid : ShootingGrid
    stage : str
        Name used in reports and errors.
    periodic : bool
        x(T) = x(0); otherwise the first node is held at ``nodes[:, 0]``.
    method : {"idas", "cvodes"}
    rtol : float
        Integrator tolerance (atol = rtol on the scaled states).
    window_samples, omega_samples : int
        Dense samples of the closed-form kinematic ram speed in the window and of the crank speed
        over the period (they cost no integration).
    ipopt_options : dict, optional
    progress : bool
        Show a tqdm bar over IPOPT iterations.
    scale : float, optional
        Objective scale (the load's unit size); default the warm start's peak at the samples.
    max_steps : int
        Step limit of each interval integration.
    coefficient_step : float, optional
        Trust region, rad/s: every Fourier coefficient stays within this distance of the warm
        start's (an outer loop re-centres it on each verified iterate; see the README).
    min_eccentricity : float, optional
        Keep contact at the output samples (as in `solve_collocation`), in [0, 1].

    Raises
    ------
    ShootingError
        When the warm start itself cannot be integrated (no iterate to return).
    """
    P, T, n, N, S = problem, problem.period, problem.n_harmonics, grid.intervals, grid.samples
    nodes = check_start(P, model, nodes, N, "nodes", coefficient_step)
    t_start = time.perf_counter()
    names = LOADS[P.objective] + ("ram_velocity",)
    ecc = contact_outputs(model, min_eccentricity)
    G = interval_function(model, grid, names + ecc, method, rtol, max_steps=max_steps)
    p0 = model.parameters(initial)
    Gm = G.map(N, "thread", 2)
    try:
        y0 = np.asarray(Gm(nodes, np.tile(p0[:, None], (1, N)), grid.nodes[None, :])[1])[: len(names)]
    except RuntimeError:
        y0 = None
    if y0 is None or not np.all(np.isfinite(y0)):  # find the interval, one at a time
        raise locate_failure(G, nodes, p0, grid, stage, method) or SimulationError(
            f"stage {stage!r}: the mapped intervals failed, each alone integrates", method=method, hint=HINT)

    c = ca.MX.sym("c", 2 * n)
    s = ca.MX.sym("s")
    X = ca.MX.sym("X", model.nx, N)
    p = ca.vertcat(c, T, 0.0)
    Xf, Y = Gm(X, ca.repmat(p, 1, N), ca.DM(grid.nodes).T)
    cons = Constraints()
    nxt = ca.horzcat(X[:, 1:], X[:, :1]) if periodic else X[:, 1:]
    cons.add((Xf if periodic else Xf[:, :-1]) - nxt, 0.0, 0.0, "continuity")
    Y = keep_contact(cons, Y, len(names), min_eccentricity)
    r = solve_states_nlp(P, initial, c, s, X, nodes, Y, y0, grid.times, t1, cons, scale, periodic,
                         f"shooting_{stage}", f"{stage} ({N}x{S} {method})", window_samples, omega_samples,
                         ipopt_options, progress, coefficient_step)
    failure = None if r["success"] else locate_failure(G, r["states"], model.parameters(r["speed"]), grid, stage,
                                                       method)
    status = r["status"] if failure is None else f"{r['status']}; {failure}"
    return to_solution(r, nodes=r["states"], status=status, wall_time=time.perf_counter() - t_start,
                       violations=r["violations"] if failure is None else {}, failure=failure)


def contact_outputs(model: PressModel, min_eccentricity: float | None) -> tuple[str, ...]:
    """Output names of the contact-keeping constraint: the eccentricity of every clearance joint
    when `min_eccentricity` is given (checked: in [0, 1]), else none."""
    if min_eccentricity is None:
        return ()
    chk.in_closed_interval("min_eccentricity", min_eccentricity, 0.0, 1.0)
    return tuple(f"{j}_eccentricity" for j in model.clearance)


def keep_contact(cons: Constraints, Y, n_rows: int, min_eccentricity: float | None):
    """Constrain the rows of `Y` after the first `n_rows` (the `contact_outputs`) to at least
    `min_eccentricity`; returns the first `n_rows`."""
    if Y.shape[0] > n_rows:
        cons.add(Y[n_rows:, :], min_eccentricity, np.inf, "eccentricity")
    return Y[:n_rows, :]


def check_start(P: SpeedProblem, model: PressModel, states: np.ndarray, columns: int, name: str,
                coefficient_step: float | None) -> np.ndarray:
    """Checks shared by the state transcriptions, before any solve; ``states`` as a float array."""
    n = P.n_harmonics
    if model.n_harmonics != n:
        raise ValueError(f"model.n_harmonics ({model.n_harmonics}) must equal the problem's n_harmonics ({n})")
    states = np.asarray(states, float)
    if states.shape != (model.nx, columns):
        raise ValueError(f"{name} must have shape ({model.nx}, {columns}), got {states.shape}")
    if coefficient_step is not None:
        chk.positive("coefficient_step", coefficient_step, "rad/s")
    return states


def solve_states_nlp(P: SpeedProblem, initial: FourierSpeed, c, s, X, X0: np.ndarray, Y, y0: np.ndarray,
                     ts: np.ndarray, t1: float, cons: Constraints, scale: float | None, periodic: bool, name: str,
                     desc: str, window_samples: int, omega_samples: int, ipopt_options: dict | None,
                     progress: bool, coefficient_step: float | None, backoff: float = 1.0,
                     n_fixed: int | None = None) -> dict:
    """The part a state transcription shares: given its state variables ``X`` (warm start ``X0``),
    its output rows ``Y`` (loads, then the ram velocity; ``y0`` at the warm start) at times ``ts``
    and its own state constraints in ``cons``, add the sample constraints (`sampled_problem`) and
    solve (`solve_nlp`). Without `periodic`, the first ``n_fixed`` rows (default: all) of the first
    column stay at ``X0``. Returns `solve_nlp`'s record plus ``states`` (the solution's X)."""
    n, nx = P.n_harmonics, X0.shape[0] if n_fixed is None else n_fixed
    nl = Y.shape[0] - 1
    if scale is None:
        scale = float(np.sqrt(np.mean(y0[0] ** 2))) if P.objective == "rms_torque" else float(np.max(np.abs(y0[:nl])))
    f = sampled_problem(cons, P, c, s, Y[:nl, :], Y[nl, :], ts, t1, scale, window_samples, omega_samples, backoff)
    s0 = float(np.max(np.abs(y0[:nl]))) if P.objective != "rms_torque" else 0.0
    w0 = np.concatenate([initial.padded(n).coefficients, [s0], X0.ravel(order="F")])
    fixed = slice(2 * n + 1, 2 * n + 1 + nx) if not periodic else None
    r = solve_nlp(P, ca.vertcat(c, s, ca.vec(X)), f, cons, w0, scale, name, desc, ipopt_options, progress,
                  coefficient_step, fixed)
    r["states"] = r["w"][2 * n + 1 :].reshape(X0.shape, order="F")
    return r


def to_solution(r: dict, **rest) -> ShootingSolution:
    """A `ShootingSolution` from a `solve_states_nlp` record and the fields it does not hold (nodes,
    status, wall_time, violations, failure)."""
    return ShootingSolution(speed=r["speed"], value=r["value"], success=r["success"], iterations=r["iterations"],
                            history=r["history"], barrier=r["barrier"], last_speed=r["last_speed"],
                            violations_start=r["violations_start"], **rest)


def sampled_problem(cons: Constraints, P: SpeedProblem, c, s, Yl, v, ts: np.ndarray, t1: float, scale: float,
                    window_samples: int, omega_samples: int, backoff: float = 1.0):
    """Objective and the constraints a state transcription puts on its output samples and on the
    coefficients: epigraph (or RMS) of the loads ``Yl`` at times ``ts``, ram speed ``v`` at the
    samples inside the window and the kinematic ram speed on the window, both within ``backoff`` x
    tol, h(t1) = h1 H, crank speed bounds.
    Returns the objective."""
    n, T = P.n_harmonics, P.period
    if P.objective == "rms_torque":
        f = ca.sumsqr(Yl) / Yl.numel() / scale**2
    else:
        f = s / scale
        add_epigraph(cons, [Yl], s, scale)
    inside = np.nonzero((ts >= t1) & (ts <= t1 + P.window_duration))[0]
    if inside.size:
        cons.add((v[:, inside] - P.ram_speed) / P.tol, -backoff, backoff, "ram_speed_samples")
    add_window(cons, P, _ram_function(P), c, t1, window_samples, backoff)
    m0, A = crank_map(n, T, np.linspace(0.0, T, omega_samples, endpoint=False))
    motion = ca.reshape(ca.mtimes(ca.DM(A), c) + m0, 3, omega_samples)  # theta, omega, alpha rows
    add_speed_bounds(cons, P, motion[1, :], motion[2, :])
    return f


def solve_nlp(P: SpeedProblem, w, f, cons: Constraints, w0: np.ndarray, scale: float, name: str, desc: str,
              ipopt_options: dict | None, progress: bool, coefficient_step: float | None = None,
              fixed: slice | None = None) -> dict:
    """IPOPT (limited-memory Hessian, monotone barrier) on a state transcription whose variables
    ``w`` start with the 2n coefficients and the epigraph variable. ``fixed`` variables stay at
    ``w0``. Returns the solution (or the least-infeasible iterate when IPOPT fails) and its record."""
    n, T = P.n_harmonics, P.period
    lbg_a, ubg_a = cons.lbg, cons.ubg
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(desc=desc, unit="it", leave=True)
    cb = _Iterations(w.numel(), lbg_a.size, lbg_a, ubg_a, bar)
    # Warm start: a small initial barrier parameter and bound push keep IPOPT from pushing the epigraph
    # variable (and every other inequality) into the interior first. The monotone barrier strategy must
    # be asked for: with a limited-memory Hessian IPOPT defaults to the adaptive one, which ignores
    # mu_init (measured: mu rose to 0.25 and the second step left the smooth region).
    opts = {**IPOPT_DEFAULTS, "ipopt.hessian_approximation": "limited-memory", "ipopt.mu_strategy": "monotone",
            "ipopt.tol": 1e-6,
            "ipopt.acceptable_tol": 1e-4, "ipopt.acceptable_iter": 5, "ipopt.max_iter": 200,
            "ipopt.mu_init": 1e-4, "ipopt.bound_push": 1e-6, "ipopt.bound_frac": 1e-6, "iteration_callback": cb,
            **(ipopt_options or {})}
    gall = cons.g
    solver = ca.nlpsol(name, "ipopt", {"x": w, "f": f, "g": gall}, opts)
    g_fun = ca.Function("constraints", [w], [gall])
    lbw = np.full(w0.size, -np.inf)
    ubw = np.full(w0.size, np.inf)
    lbw[2 * n] = 0.0
    if coefficient_step is not None:
        lbw[: 2 * n], ubw[: 2 * n] = w0[: 2 * n] - coefficient_step, w0[: 2 * n] + coefficient_step
    if fixed is not None:
        lbw[fixed] = ubw[fixed] = w0[fixed]
    viol_start = cons.by_group(g_fun(w0))
    try:
        sol = solver(x0=w0, lbx=lbw, ubx=ubw, lbg=lbg_a, ubg=ubg_a)
        st = solver.stats()
        wo, success, status = np.asarray(sol["x"]).ravel(), bool(st["success"]), str(st["return_status"])
        iters = int(st.get("iter_count", len(cb.history)))
        barrier = [float(m) for m in st.get("iterations", {}).get("mu", [])]
    except RuntimeError as err:  # IPOPT itself raised (e.g. an evaluation error at the start)
        wo, success, status, iters = (cb.best[2] if cb.best else w0), False, _first_line(err), len(cb.history)
        barrier = []
    finally:
        if bar is not None:
            bar.close()
    last = FourierSpeed(T, wo[:n], wo[n : 2 * n])
    if not success and cb.best is not None:
        wo = cb.best[2]
    try:
        viol_end = cons.by_group(g_fun(wo))
    except RuntimeError:  # an integrator failing at the returned iterate: the caller locates it
        viol_end = {}
    value = float(wo[2 * n]) if P.objective != "rms_torque" else float(np.sqrt(max(cb.history[-1], 0.0)) * scale) \
        if cb.history else np.nan
    history = [h * scale for h in cb.history] if P.objective != "rms_torque" else \
        [float(np.sqrt(max(h, 0.0)) * scale) for h in cb.history]
    return {"w": wo, "speed": FourierSpeed(T, wo[:n], wo[n : 2 * n]), "last_speed": last, "value": value,
            "success": success, "status": status, "iterations": iters, "barrier": barrier, "history": history,
            "violations_start": viol_start, "violations": viol_end}
