"""Rigid slider-crank with ideal joints: kinematics and inverse dynamics.

The inverse dynamics uses absolute coordinates q = (theta, x_G, y_G, phi, x_S, y_S) for crank,
rod and slider, the four pin constraints, the guide x_S = 0 and the driving constraint
theta = theta(t). With M qdd = Q + Phi_q^T lambda, the multipliers are the joint reactions and the
motor torque; CasADi derives M, Q and Phi_q from the energies and the constraints.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from . import checks as chk
from .buffers import evaluate
from . import mechanics as mech
from .params import PressParams
from .result import SimResult
from .speed import FourierSpeed


@lru_cache(maxsize=32)
def kinematics_function(params: PressParams) -> ca.Function:
    theta, omega, alpha = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
    pos = mech.slider_crank_positions(params, theta)
    h, phi = pos["ram_height"], pos["rod_angle"]
    hd, hdd = mech.time_derivatives(h, theta, omega, alpha)
    phid, phidd = mech.time_derivatives(phi, theta, omega, alpha)
    return ca.Function(
        "rigid_kinematics",
        [theta, omega, alpha],
        [h, hd, hdd, phi, phid, phidd],
        ["theta", "omega", "alpha"],
        ["ram_height", "ram_velocity", "ram_acceleration", "rod_angle", "rod_angular_velocity",
         "rod_angular_acceleration"],
    )


def evaluate_elementwise(f: ca.Function, *args: Any) -> dict[str, np.ndarray]:
    """Evaluate a scalar-input CasADi function elementwise over broadcast numpy arrays."""
    arrays = np.broadcast_arrays(*[np.asarray(a, dtype=float) for a in args])
    shape = arrays[0].shape
    flat = [a.reshape(1, -1) for a in arrays]
    out = evaluate(f.map(flat[0].shape[1]), *flat) if flat[0].size else [np.zeros((f.size1_out(i), 0))
                                                                          for i in range(f.n_out())]
    res = {}
    for i, o in enumerate(out):
        rows = f.size1_out(i)
        res[f.name_out(i)] = o.reshape(shape) if rows == 1 else o.reshape((rows,) + shape)
    return res


def rigid_kinematics(params: PressParams, theta: Any, omega: Any = 0.0, alpha: Any = 0.0) -> dict[str, np.ndarray]:
    """Ram and rod kinematics of the ideal slider-crank.

    Parameters
    ----------
    params : PressParams
        The press.
    theta, omega, alpha : array-like
        Crank angle (rad, 0 = top dead centre), speed (rad/s), acceleration (rad/s^2); broadcast.

    Returns
    -------
    dict of ndarray
        ``ram_height`` h (m above bottom dead centre), ``ram_velocity`` dh/dt (m/s),
        ``ram_acceleration`` (m/s^2), ``rod_angle`` phi (rad, A - B = l (sin phi, cos phi)),
        ``rod_angular_velocity`` (rad/s), ``rod_angular_acceleration`` (rad/s^2).
    """
    for name, v in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        chk.finite_array(name, v, ndim=None)
    return evaluate_elementwise(kinematics_function(params), theta, omega, alpha)


def crank_angle_at_height(params: PressParams, height: Any, stroke: str = "down") -> np.ndarray:
    """Crank angle (rad) at which the ram is at a given height above bottom dead centre.

    Parameters
    ----------
    params : PressParams
        The press.
    height : array-like
        Ram height h in [0, H], m.
    stroke : {"down", "up"}
        Downstroke (theta in [0, pi]) or upstroke (theta in [pi, 2 pi]).
    """
    chk.choice("stroke", stroke, ("down", "up"))
    h = chk.finite_array("height", height, ndim=None)
    r, l = params.crank_radius, params.rod_length
    if np.any(h < -1e-12) or np.any(h > params.stroke + 1e-12):
        raise ValueError(f"height must be in [0, {params.stroke:g}] m (the stroke)")
    y = np.clip(h, 0.0, params.stroke) - r - l  # wrist-pin y coordinate, always < 0
    # (r cos theta - y)^2 = l^2 - r^2 sin^2 theta  ->  cos theta = (y^2 + r^2 - l^2) / (2 r y)
    theta = np.arccos(np.clip((y**2 + r**2 - l**2) / (2 * r * y), -1.0, 1.0))
    return theta if stroke == "down" else 2 * np.pi - theta


#: Outputs of `inverse_dynamics`, in order.
INVERSE_DYNAMICS_OUTPUTS = ("torque", "crank_pin_force", "wrist_pin_force", "slider_normal_force", "ram_height",
                            "ram_velocity", "ram_acceleration", "kinetic_energy", "potential_energy",
                            "crank_pin_tension", "wrist_pin_tension")


@lru_cache(maxsize=32)
def inverse_dynamics_function(params: PressParams) -> ca.Function:
    """(theta, omega, alpha) -> `INVERSE_DYNAMICS_OUTPUTS` of the ideal press (SX, one sample)."""
    theta, omega, alpha = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
    out = inverse_dynamics(params, theta, omega, alpha)
    return ca.Function("rigid_inverse_dynamics", [theta, omega, alpha], [out[k] for k in INVERSE_DYNAMICS_OUTPUTS],
                       ["theta", "omega", "alpha"], list(INVERSE_DYNAMICS_OUTPUTS))


def inverse_dynamics(params: PressParams, theta: ca.SX, omega: ca.SX, alpha: ca.SX) -> dict[str, ca.SX]:
    """`INVERSE_DYNAMICS_OUTPUTS` of the ideal press as SX expressions of the crank motion (and of any
    parameter of `params` that is a symbol, `PressParams.with_symbols`)."""
    l, g = params.rod_length, params.gravity

    # Absolute coordinates and their rates.
    q = ca.SX.sym("q", 6)  # theta, xG, yG, phi, xS, yS
    qd = ca.SX.sym("qd", 6)
    th, G, phi, S = q[0], q[1:3], q[3], q[4:6]
    T_c, V_c = mech.crank_energy(params, th, qd[0])
    T_r, V_r = mech.body_energy(params.rod_mass, params.rod_inertia_value, g, G, qd[1:3], qd[3])
    T_s, V_s = mech.body_energy(params.slider_mass, 0.0, g, S, qd[4:6], 0)
    V_cb = mech.counterbalance_potential(params, S[1] + params.crank_radius + l)
    lag = mech.lagrangian(T_c + T_r + T_s, V_c + V_r + V_s + V_cb, q, qd)
    theta_d = ca.SX.sym("theta_d")  # prescribed crank angle
    phi_c = ca.vertcat(
        mech.crank_pin(params, th) - (G + 0.5 * l * mech.unit(phi)),  # crank pin A
        (G - 0.5 * l * mech.unit(phi)) - S,  # wrist pin B
        S[0],  # guide
        th - theta_d,  # driving constraint: multiplier = motor torque
    )
    Phi_q = ca.jacobian(phi_c, q)

    # Ideal-joint motion q(theta) and its rates from the closed-form positions.
    pos = mech.slider_crank_positions(params, theta)
    A, B = pos["pin"], pos["wrist"]
    q_of = ca.vertcat(theta, 0.5 * (A + B), pos["rod_angle"], B)
    qd_of, qdd_of = mech.time_derivatives(q_of, theta, omega, alpha)
    qdd_of = ca.densify(qdd_of)
    Q = lag.Q + ca.vertcat(0, 0, 0, 0, 0, mech.process_force(params, q[5] + params.crank_radius + l, qd[5]))
    subs = [q, qd]
    vals = [ca.densify(q_of), ca.densify(qd_of)]
    M, Q, Phi_q, T, V = ca.substitute([lag.M, Q, Phi_q, lag.T, lag.V], subs, vals)
    lam = ca.solve(Phi_q.T, M @ qdd_of - Q)
    h = pos["ram_height"]
    # component of each pin force along the rod, positive in tension: the slider hangs from the rod,
    # so without a process force its weight keeps the rod in tension until the ram's downward
    # acceleration exceeds g; the sign change is the joint-force reversal that makes journals impact
    e = mech.unit(pos["rod_angle"])
    values = [lam[5], ca.norm_2(lam[0:2]), ca.norm_2(lam[2:4]), lam[4], h, qd_of[5], qdd_of[5], T, V,
              -ca.dot(lam[0:2], e), -ca.dot(lam[2:4], e)]
    return dict(zip(INVERSE_DYNAMICS_OUTPUTS, values))


def rigid_inverse_dynamics(params: PressParams, theta: Any, omega: Any, alpha: Any) -> dict[str, np.ndarray]:
    """Motor torque, joint forces and energies of the ideal press at given crank motion.

    Returns
    -------
    dict of ndarray
        ``torque`` (N m), ``crank_pin_force``, ``wrist_pin_force`` (N, magnitudes),
        ``slider_normal_force`` (N, guide on slider, +x), ``ram_height`` (m), ``ram_velocity``
        (m/s), ``ram_acceleration`` (m/s^2), ``kinetic_energy``, ``potential_energy`` (J),
        ``crank_pin_tension``, ``wrist_pin_tension`` (N, axial pin forces on the rod, positive in
        tension; a sign change is a joint-force reversal).
    """
    for name, v in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        chk.finite_array(name, v, ndim=None)
    return evaluate_elementwise(inverse_dynamics_function(params), theta, omega, alpha)


def rigid_response(params: PressParams, speed: FourierSpeed, t: Any = None) -> SimResult:
    """Inverse dynamics of the ideal press over time for a crank speed.

    Parameters
    ----------
    params : PressParams
        The press.
    speed : FourierSpeed
        Crank speed.
    t : array-like, optional
        Times, s. Default: 2001 points over one period.

    Returns
    -------
    SimResult
        Same fields as a simulation of the full model; eccentricities and the rod deflection are zero.
    """
    chk.instance("params", params, PressParams)
    chk.instance("speed", speed, FourierSpeed)
    if t is None:
        t = np.linspace(0.0, speed.period, 2001)
    t = chk.finite_array("t", t)
    theta, omega, alpha = speed.evaluate(t)
    return ideal_result(t, theta, omega, rigid_inverse_dynamics(params, theta, omega, alpha))


def ideal_result(t: np.ndarray, theta: np.ndarray, omega: np.ndarray, out: dict[str, np.ndarray]) -> SimResult:
    """A `SimResult` of an ideal press: times (s), crank angle and speed, and the inverse dynamics'
    samples `out` (`INVERSE_DYNAMICS_OUTPUTS`); the eccentricities and the rod deflection are zero."""
    zeros = np.zeros_like(t)
    return SimResult(
        t=t, theta=theta, omega=omega, torque=out["torque"], ram_height=out["ram_height"],
        ram_velocity=out["ram_velocity"], ram_acceleration=out["ram_acceleration"],
        slider_normal_force=out["slider_normal_force"], crank_pin_force=out["crank_pin_force"],
        wrist_pin_force=out["wrist_pin_force"], crank_pin_eccentricity=zeros,
        wrist_pin_eccentricity=zeros, rod_midspan_deflection=zeros,
    )
