"""Symbolic mechanics shared by the models: body kinematics, energies, Lagrange's equations.

Equations of motion are never written out by hand: each model states its kinetic energy
T(q, qd), potential energy V(q) and constraints, and CasADi differentiates them here.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .laws import softplus
from .params import PressParams


@dataclass
class Lagrangian:
    """Terms of Lagrange's equations  M(q) qdd = Q(q, qd) (+ constraint forces).

    Attributes
    ----------
    M : ca.SX
        Mass matrix d^2 T / d qd^2.
    Q : ca.SX
        Generalised forces without the constraint forces:
        dT/dq - (d^2 T / d qd dq) qd - dV/dq (+ applied forces added by the model).
    T, V : ca.SX
        Kinetic and potential energy, J.
    """

    M: ca.SX
    Q: ca.SX
    T: ca.SX
    V: ca.SX


def lagrangian(T: ca.SX, V: ca.SX, q: ca.SX, qd: ca.SX) -> Lagrangian:
    """Derive the mass matrix and the velocity/potential generalised forces from energies.

    Parameters
    ----------
    T : ca.SX
        Kinetic energy as a function of q and qd, J.
    V : ca.SX
        Potential energy as a function of q, J.
    q, qd : ca.SX
        Generalised coordinates and their rates (column vectors).
    """
    p = ca.gradient(T, qd)  # generalised momenta
    M = ca.jacobian(p, qd)
    Q = ca.gradient(T, q) - ca.jacobian(p, q) @ qd - ca.gradient(V, q)
    return Lagrangian(M=M, Q=Q, T=T, V=V)


def crank_pin(params: PressParams, theta: ca.SX) -> ca.SX:
    """Crank-pin position r (sin theta, cos theta), m, in the press frame (y away from the bed)."""
    r = params.crank_radius
    return ca.vertcat(r * ca.sin(theta), r * ca.cos(theta))


def unit(angle: ca.SX) -> ca.SX:
    """Unit vector (sin angle, cos angle): angle measured from +y toward +x."""
    return ca.vertcat(ca.sin(angle), ca.cos(angle))


def crank_energy(params: PressParams, theta: ca.SX, omega: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Kinetic and potential energy of the crank (inertia about its axis, centre of mass on the crank)."""
    T = 0.5 * params.crank_inertia * omega**2
    V = params.crank_mass * params.gravity * params.crank_com * ca.cos(theta)
    return T, V


def body_energy(mass: float, inertia: float, gravity: float, r: ca.SX, v: ca.SX, rate: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Kinetic and potential energy of a planar rigid body.

    Parameters
    ----------
    mass, inertia : float
        kg and kg m^2 about the centre of mass.
    gravity : float
        m/s^2 toward the bed (-y).
    r, v : ca.SX
        Position and velocity of the centre of mass, m and m/s.
    rate : ca.SX
        Angular velocity, rad/s.
    """
    T = 0.5 * mass * ca.dot(v, v) + 0.5 * inertia * rate**2
    V = mass * gravity * r[1]
    return T, V


def slider_crank_positions(params: PressParams, theta: ca.SX) -> dict[str, ca.SX]:
    """Ideal-joint slider-crank positions as functions of the crank angle.

    Returns
    -------
    dict
        ``pin`` crank pin A, ``wrist`` wrist pin B = (0, y_B), ``rod_angle`` phi with
        A - B = l (sin phi, cos phi), ``ram_height`` h = y_B + r + l (m, rad).
    """
    r, l = params.crank_radius, params.rod_length
    A = crank_pin(params, theta)
    yB = r * ca.cos(theta) - ca.sqrt(l**2 - (r * ca.sin(theta)) ** 2)
    phi = ca.asin(r * ca.sin(theta) / l)
    return {"pin": A, "wrist": ca.vertcat(0, yB), "rod_angle": phi, "ram_height": yB + r + l}


def time_derivatives(expr: ca.SX, theta: ca.SX, omega: ca.SX, alpha: ca.SX) -> tuple[ca.SX, ca.SX]:
    """First and second time derivatives of expr(theta) for a given crank speed and acceleration."""
    d1 = ca.jacobian(expr, theta)
    d2 = ca.jacobian(d1, theta)
    return d1 * omega, d2 * omega**2 + d1 * alpha


def process_force(params: PressParams, h: ca.SX, v: ca.SX) -> ca.SX:
    """Forming force on the ram (+y, resisting the downstroke), N; zero when it is off
    (`pressocp.params.ProcessForce`). The piecewise-linear curve through the knots, zero outside
    them, is a sum of smoothed steps s(u / edge) at its two ends and of their integrals (ramps,
    softplus(u, edge / 2)) at its corners, so it is C-infinity and exact a few edges away from any
    knot; a constant force between two heights is the curve of two knots."""
    pf = params.process_force
    if not pf.active:
        return ca.SX(0)
    heights, forces = pf.knots()
    e = pf.edge

    def step(u):
        return 0.5 * (1 + ca.tanh(u / e))

    def ramp(u):  # the integral of step
        return softplus(u, 0.5 * e)

    curve = forces[0] * step(h - heights[0]) - forces[-1] * step(h - heights[-1])
    for h0, h1, f0, f1 in zip(heights[:-1], heights[1:], forces[:-1], forces[1:]):
        if f1 != f0:
            curve += (f1 - f0) / (h1 - h0) * (ramp(h - h0) - ramp(h - h1))
    return curve * 0.5 * (1 + ca.tanh(-v / pf.speed_edge))


def counterbalance_potential(params: PressParams, h: ca.SX) -> ca.SX:
    """Potential energy of the slide counterbalance at ram height h (m above bottom dead centre), J,
    zero at bottom dead centre: minus the integral of its upward force F (1 + h/L)^-n from 0 to h
    (`pressocp.params.Counterbalance`)."""
    cb = params.counterbalance
    F, L, n = cb.force, cb.gas_length, cb.exponent
    if n == 0.0:
        return -F * h
    if n == 1.0:
        return -F * L * ca.log1p(h / L)
    return -F * L / (1.0 - n) * ((1.0 + h / L) ** (1.0 - n) - 1.0)

