"""Rigid-model transcription: the press has no states, so the loads are closed-form functions of the
crank motion at sample times, which is lifted into variables tied linearly to the Fourier
coefficients (`add_crank_motion`). IPOPT with the exact Hessian solves it in seconds; its optimum
is the floor the clearance stages compare with and their warm start.
"""

from __future__ import annotations

import time

import casadi as ca
import numpy as np

from .. import _checks as chk
from ..design import design_speed, window_error
from ..rigid import _inverse_dynamics_function, _kinematics_function, crank_angle_at_height, rigid_response
from ..speed import FourierSpeed, series
from .constraints import (Constraints, add_crank_motion, add_epigraph, add_speed_bounds, add_window, crank_motion,
                          crank_scale)
from .problem import SpeedProblem
from .result import OcpResult

#: Fraction of the ram-speed tolerance enforced at the rigid stage's window samples.
RAM_SPEED_BACKOFF = 0.9
#: Outputs of `_loads_function`.
LOAD_OUTPUTS = ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force", "crank_pin_tension",
                "wrist_pin_tension")
IPOPT_DEFAULTS = {"ipopt.print_level": 0, "ipopt.sb": "yes", "print_time": False, "ipopt.max_iter": 300,
                  "ipopt.tol": 1e-8, "ipopt.linear_solver": "mumps"}


def _loads_function(problem: SpeedProblem) -> ca.Function:
    """(theta, omega, alpha) -> torque, slider normal force, pin forces and rod tensions at both pins
    (inverse dynamics of the ideal press), an SX function of one sample."""
    th, om, al = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
    dyn = _inverse_dynamics_function(problem.params)(theta=th, omega=om, alpha=al)
    return ca.Function("loads", [th, om, al], [dyn[k] for k in LOAD_OUTPUTS])


def _ram_function(problem: SpeedProblem) -> ca.Function:
    """(t, c) -> (ram height, ram velocity, theta) of the Fourier speed with coefficients c, an SX
    function."""
    n, T = problem.n_harmonics, problem.period
    t, c = ca.SX.sym("t"), ca.SX.sym("c", 2 * n)
    th, om, al = series(t, c[:n], c[n:], T)
    kin = _kinematics_function(problem.params)(theta=th, omega=om, alpha=al)
    return ca.Function("ram", [t, c], [kin["ram_height"], kin["ram_velocity"], th])


def solve_rigid(problem: SpeedProblem, initial: FourierSpeed | None = None, samples: int = 1000,
                window_samples: int = 200, ipopt_options: dict | None = None) -> OcpResult:
    """Solve the speed problem on the rigid press (ideal joints).

    Parameters
    ----------
    problem : SpeedProblem
        The problem.
    initial : FourierSpeed, optional
        Initial speed; default the rigid kinematic design (`design_speed`) of the same window.
    samples : int
        Uniform samples over the period for the load and speed constraints, 50..20000.
    window_samples : int
        Samples of the ram speed constraint inside [t1, t2], 10..5000.
    ipopt_options : dict, optional
        Extra CasADi/IPOPT options (e.g. ``{"ipopt.max_iter": 50}``).

    Returns
    -------
    OcpResult
        ``success`` False (with the last iterate) when IPOPT does not converge; never raises for that.
    """
    N = chk.integer("samples", samples, 50, 20000)
    m = chk.integer("window_samples", window_samples, 10, 5000)
    P, T, n = problem, problem.period, problem.n_harmonics
    t_start = time.perf_counter()
    if initial is None:
        d = design_speed(P.params, period=T, ram_speed=P.ram_speed, window=P.window, n_harmonics=n)
        initial, t1_0 = d.speed, d.t1
    else:
        if not np.isclose(initial.period, T):
            raise ValueError(f"initial.period must equal the problem's period {T:g} s, got {initial.period:g}")
        padded = initial.padded(n)
        initial = FourierSpeed(T, padded.a, padded.b, 0.0)
        th1 = float(crank_angle_at_height(P.params, P.window[0] * P.params.stroke, "down"))
        tg = np.linspace(0, T, 20001)
        t1_0 = float(np.interp(th1, initial.theta(tg), tg))
    f_kin = _ram_function(P)
    tau_w = P.window_duration

    c = ca.MX.sym("c", 2 * n)
    s = ca.MX.sym("s")
    t1 = ca.MX.sym("t1")
    ts = np.linspace(0.0, T, N, endpoint=False)
    # the crank motion at the samples is lifted into variables (scaled rows) tied linearly to c: the
    # exact Hessian is then 3 x 3 blocks per sample instead of dense in c (measured on the seed case,
    # 15 harmonics: 0.43 s per Hessian before)
    w_scale = crank_scale(T)
    Wv = ca.MX.sym("W", 3, N)
    W = Wv * ca.DM(w_scale)
    om, al = W[1, :], W[2, :]
    tau, nf, fa, fb, tens_a, tens_b = _loads_function(P).map(N)(W[0, :], om, al)

    r0 = rigid_response(P.params, initial, ts)
    scale = {"peak_torque": r0.peak("torque"), "peak_slider_normal_force": r0.peak("slider_normal_force"),
             "peak_pin_force": max(r0.peak("crank_pin_force"), r0.peak("wrist_pin_force")),
             "rms_torque": float(np.sqrt(np.mean(r0.torque**2)))}[P.objective]
    cons = Constraints()
    if P.objective == "rms_torque":
        f = ca.sumsqr(tau) / N / scale**2
    else:
        f = s / scale
        loads = {"peak_torque": [tau], "peak_slider_normal_force": [nf], "peak_pin_force": [fa, fb]}[P.objective]
        add_epigraph(cons, loads, s, scale)
    # 10 % back-off: the bound holds at the samples, the verification checks the whole window, and the
    # clearance model adds the journals' motion to the ram velocity (at T = 0.8 s the no-reversal
    # optimum with 5 % reached 0.99 tol on the rigid rod and 1.001 tol on the flexible one)
    add_window(cons, P, f_kin, c, t1, m, RAM_SPEED_BACKOFF)
    add_speed_bounds(cons, P, om, al)
    if P.min_tension is not None:  # no joint-force reversal
        cons.add((ca.vertcat(tens_a, tens_b) - P.min_tension) / P.hanging_weight, 0.0, np.inf, "rod_tension")
    add_crank_motion(cons, W, c, T, ts)
    x = ca.vertcat(c, s, t1, ca.vec(Wv))
    # adaptive barrier update: with the monotone one the 15-harmonic default case stalled (300 iterations)
    opts = {**IPOPT_DEFAULTS, "ipopt.mu_strategy": "adaptive", **(ipopt_options or {})}
    solver = ca.nlpsol("rigid_speed_ocp", "ipopt", {"x": x, "f": f, "g": cons.g}, opts)
    W0 = (crank_motion(initial, ts) / w_scale[:, None]).ravel(order="F")
    x0 = np.concatenate([initial.coefficients, [scale, t1_0], W0])
    lbx = np.concatenate([-np.inf * np.ones(2 * n), [0.0, 0.0], np.full(W0.size, -np.inf)])
    ubx = np.concatenate([np.inf * np.ones(2 * n), [np.inf, T - tau_w], np.full(W0.size, np.inf)])
    sol = solver(x0=x0, lbx=lbx, ubx=ubx, lbg=cons.lbg, ubg=cons.ubg)
    st = solver.stats()
    xo = np.asarray(sol["x"]).ravel()
    speed = FourierSpeed(T, xo[:n], xo[n : 2 * n])
    t1v = float(xo[2 * n + 1])
    wall = time.perf_counter() - t_start
    dense = np.linspace(0.0, T, 20001)
    resp = rigid_response(P.params, speed, dense)
    init_resp = rigid_response(P.params, initial, dense)
    max_err, _ = window_error(P.params, speed, t1v, t1v + tau_w, P.ram_speed)
    history = [float(v) * scale for v in st.get("iterations", {}).get("obj", [])]
    if P.objective == "rms_torque":
        history = [float(np.sqrt(max(h, 0.0) * scale)) for h in history]
        value = float(np.sqrt(np.mean(resp.torque**2)))
    else:
        value = float(xo[2 * n])
    return OcpResult(
        speed=speed, objective=P.objective, peak_torque=resp.peak("torque"),
        initial_peak_torque=init_resp.peak("torque"), rigid_peak_torque=resp.peak("torque"),
        objective_value=value, t1=t1v, t2=t1v + tau_w, success=bool(st["success"]),
        status=str(st["return_status"]), iterations=int(st.get("iter_count", 0)), wall_time=wall,
        max_ram_speed_violation=max(max_err * abs(P.ram_speed) - P.tol, 0.0), min_omega=speed.min_speed(),
        objective_history=history,
        stages=[{"name": "rigid", "status": str(st["return_status"]), "iterations": int(st.get("iter_count", 0)),
                 "wall_time": wall, "objective": value}],
        simulation=resp,
    )
