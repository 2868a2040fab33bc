"""Baseline for the optimiser benchmark only: single shooting with scipy SLSQP and finite-difference
gradients around the periodic simulation (the seed paper's approach). Where a speed has no periodic
steady state (impacting, chaotic journals), the fourth cycle from rest stands in for it.

Variables: the 2n Fourier coefficients and the epigraph variable s. Every function evaluation is
a periodic simulation of the clearance model (warm-started from the last periodic state); every
gradient is 2n forward differences, i.e. 2n more simulations. The window is a fixed time interval
[t1, t1 + (h1 - h2)/|v|] (SLSQP needs a fixed number of constraints): t1 is held at the value given
(the optimum's: when its re-simulated ram enters the window) with the ideal press's ram at
``h_start`` then (h1 H plus the model's ram drop: the clearance model's ram hangs that much lower),
and the clearance model's ram speed is held at the samples in that interval.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import minimize

from pressocp.model import PressModel
from pressocp.ocp.nlp import ram_function
from pressocp.verify import settled_state
from pressocp.problem import SpeedProblem
from pressocp.simulate import Integrator, SimulationError, simulate
from pressocp.speed import FourierSpeed


class _Stop(Exception):
    pass


def slsqp_baseline(model: PressModel, problem: SpeedProblem, initial: FourierSpeed, t1: float, target: float,
                   time_cap: float = 1800.0, samples: int = 400, rtol: float = 1e-6, fd_step: float = 1e-5,
                   h_start: float | None = None) -> dict:
    """Run SLSQP until the objective is within 1 % of `target` (feasible) or `time_cap` s pass.

    ``h_start`` (m) is the ideal press's ram height at t1; default the window's h1 H (t1 then is the
    ideal press's window start, as the optimiser held it before the window moved onto the model's
    own ram).

    Returns a dict: reached (bool), wall_time (s), evaluations (simulations), iterations,
    best feasible objective, history [(time, objective, max violation)].
    """
    P, T, n = problem, problem.period, problem.n_harmonics
    t = np.linspace(0.0, T, samples, endpoint=False)
    t2 = t1 + P.window_duration
    win = (t >= t1) & (t <= t2)
    f_kin = ram_function(P)
    h0 = P.window_heights[0] if h_start is None else float(h_start)
    to = np.linspace(0.0, T, 1000, endpoint=False)
    state = {"x0": None, "evals": 0, "cache": {}}
    t_start = time.perf_counter()
    hist: list = []
    best = [np.inf]

    def loads(c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = c.tobytes()
        if key not in state["cache"]:
            if time.perf_counter() - t_start > time_cap:
                raise _Stop
            sp = FourierSpeed.from_coefficients(T, c)
            try:
                r = simulate(model, sp, periodic=True, integrator=Integrator(method="cvodes", rtol=rtol), n_out=samples + 1, x0=state["x0"])
                state["x0"] = r.states[:, 0] / model.x_scale
            except SimulationError:  # no periodic state (impacting, chaotic): the 4th cycle, as the seed did
                r = simulate(model, sp, integrator=Integrator(method="cvodes", rtol=rtol), n_out=samples + 1,
                             x0=settled_state(model, sp, 3, rtol))
            out = (r.torque[:-1], r.ram_velocity[:-1])
            state["evals"] += 1
            state["cache"] = {key: out}
        return state["cache"][key]

    def cons(y: np.ndarray) -> np.ndarray:
        c, s = y[:-1], y[-1]
        tau, v = loads(c)
        sp = FourierSpeed.from_coefficients(T, c)
        h1 = float(f_kin(t1, c)[0])
        return np.concatenate([(s - tau) / s0, (s + tau) / s0, 1.0 - np.abs(v[win] - P.ram_speed) / P.tol,
                               (sp.omega(to) - P.omega_lower) / (2 * np.pi / T),
                               [1e3 * (h1 - h0) / P.press.stroke]])

    def cons_jac(y: np.ndarray) -> np.ndarray:
        g0 = cons(y)
        J = np.empty((g0.size, y.size))
        for i in range(y.size):
            yp = y.copy()
            h = fd_step * max(1.0, abs(y[i]))
            yp[i] += h
            J[:, i] = (cons(yp) - g0) / h
        return J

    def callback(y: np.ndarray) -> None:
        g = cons(y)
        viol = float(max(0.0, -np.min(g[:-1]), abs(g[-1])))
        hist.append((time.perf_counter() - t_start, float(y[-1]), viol))
        if viol < 1e-3:
            best[0] = min(best[0], float(y[-1]))
        if best[0] <= 1.01 * target:
            raise _Stop

    c0 = initial.padded(n).coefficients
    s0 = float(np.max(np.abs(loads(c0)[0])))
    y0 = np.concatenate([c0, [s0]])
    n_eq = 1
    constraints = [{"type": "ineq", "fun": lambda y: cons(y)[:-n_eq], "jac": lambda y: cons_jac(y)[:-n_eq]},
                   {"type": "eq", "fun": lambda y: cons(y)[-n_eq:], "jac": lambda y: cons_jac(y)[-n_eq:]}]
    status = "time cap"
    try:
        res = minimize(lambda y: y[-1] / s0, y0, jac=lambda y: np.eye(y.size)[-1] / s0, method="SLSQP",
                       constraints=constraints, callback=callback, options={"maxiter": 500, "ftol": 1e-8})
        status = res.message
    except _Stop:
        status = "reached" if best[0] <= 1.01 * target else "time cap"
    return {"reached": bool(best[0] <= 1.01 * target), "status": str(status),
            "wall_time": time.perf_counter() - t_start, "evaluations": state["evals"], "iterations": len(hist),
            "best_feasible_objective": best[0], "target": target, "history": hist}
