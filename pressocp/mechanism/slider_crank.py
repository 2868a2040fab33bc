"""The in-line slider-crank press: crank, connecting rod (rigid or flexible), slider.

Coordinates ``Q = [theta, x_S, e_A (2), e_B (2), w]``: crank angle, slider position across the
slide, the eccentricities of the crank-pin and wrist-pin journals (bearing centre in the rod minus
journal centre) and the rod's elastic coordinates (`pressocp.beam`: element DOFs, or modal
coordinates of a reduced rod). The slider position along the slide follows from the rod-length
closure, so no index-3 constraint is left.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import beam
from .. import mechanics as mech
from .. import rigid
from ..params import PressParams
from .base import Linkage

#: Transverse acceleration (m/s^2) whose static deflection of the pinned-pinned rod sets the scale of
#: the elastic states: w_s = rho A a l^4 / (76.8 EI) (midspan deflection under a uniform load),
#: slopes w_s * 3.2 / l (end slope of the same load case).
ELASTIC_SCALE_ACCELERATION = 1.0e3


def rod_kinematics(params: PressParams, theta, xs, eA, eB):
    """Bearing centres A and B, slider pin S, unit chord d (from B to A) and its normal, from the
    coordinates (m)."""
    l = params.rod_length
    A_rod = mech.crank_pin(params, theta) + eA  # big-end bearing centre
    dx = A_rod[0] - xs - eB[0]
    ys = A_rod[1] - eB[1] - ca.sqrt(l**2 - dx**2)  # slider pin on the slide
    S = ca.vertcat(xs, ys)
    B_rod = S + eB  # small-end bearing centre
    d = (A_rod - B_rod) / l  # unit vector from B to A
    normal = ca.vertcat(-d[1], d[0])  # rod's transverse direction
    return A_rod, B_rod, S, d, normal


def flexible_rod_energies(P: PressParams, n_elements: int, A, A_dot, d, phi_dot, u, u_dot) -> tuple:
    """Kinetic, gravitational and strain energy of the flexible rod in its chord frame (J), from the
    rod integrals (`pressocp.beam.integrals`) instead of sums over quadrature points.

    A point at xi from the big-end bearing centre A sits at r = A - xi d + w n (d the unit chord
    from B to A, n = (-d_y, d_x), w = N(xi) . u). With d' = -phi' n and n' = phi' d its velocity is
    A' + (xi phi' + w') n + w phi' d, so with rho A the mass per length, a = int N, b = int xi N and
    M = int N N^T:  2 T / (rho A) = l |A'|^2 + 2 A'.n (phi' l^2/2 + a.u') + 2 A'.d phi' a.u
    + phi'^2 (l^3/3 + u.M u) + 2 phi' b.u' + u'.M u',  V_g / (rho A g) = l A_y - l^2/2 d_y + a.u n_y,
    and the strain energy EI u.K u / 2. These are the quadrature sums' own values (the Gauss rule is
    exact on these polynomials) as expressions whose size does not grow with the quadrature points:
    on the 4-element rod with both clearances the right-hand side has 6 318 nodes instead of 14 712.

    Parameters
    ----------
    P : PressParams
        The press (its rod's length, mass, bending stiffness; the gravity), numbers or CasADi symbols.
    n_elements : int
        Hermite elements of the rod.
    A, A_dot : ca.SX or array (2,)
        Big-end bearing centre (m) and its velocity (m/s).
    d : ca.SX or array (2,)
        Unit vector of the chord from the small end to the big end.
    phi_dot : ca.SX or float
        The chord's angular velocity, rad/s (d = (sin phi, cos phi)).
    u, u_dot : ca.SX or array (2 N,)
        The element DOFs (`pressocp.beam`) and their rates.

    Returns
    -------
    T, V_g, strain
        Kinetic, gravitational and strain energy, J (CasADi expressions).
    """
    l, rho_a, g = P.rod_length, P.rod_mass / P.rod_length, P.gravity
    normal = ca.vertcat(-d[1], d[0])
    rod = beam.integrals(l, n_elements)
    a, b, M, K = (v if isinstance(v, ca.SX) else ca.DM(v) for v in (rod.first, rod.moment, rod.mass, rod.stiffness))
    au, Mu = ca.dot(a, u), ca.mtimes(M, u)
    twice_t = (l * ca.dot(A_dot, A_dot) + 2 * ca.dot(A_dot, normal) * (phi_dot * l**2 / 2 + ca.dot(a, u_dot))
               + 2 * ca.dot(A_dot, d) * phi_dot * au + phi_dot**2 * (l**3 / 3 + ca.dot(u, Mu))
               + 2 * phi_dot * ca.dot(b, u_dot) + ca.dot(u_dot, ca.mtimes(M, u_dot)))
    V_g = rho_a * g * (l * A[1] - l**2 / 2 * d[1] + au * normal[1])
    strain = 0.5 * P.rod_youngs_modulus * P.rod_area_moment * ca.dot(u, ca.mtimes(K, u))
    return 0.5 * rho_a * twice_t, V_g, strain


def elastic_coordinates(params: PressParams, n_elements: int, n_modes: int | None) -> tuple[list[str], list[float],
                                                                                            np.ndarray | None]:
    """Names and scales of the rod's elastic coordinates, and the mode shapes of a reduced rod
    (`pressocp.beam.modes`; None: every element DOF), from the press's values."""
    l, ne = params.rod_length, n_elements
    bending = params.rod_youngs_modulus * params.rod_area_moment
    w_s = (params.rod_mass / l) * ELASTIC_SCALE_ACCELERATION * l**4 / (76.8 * bending)
    if n_modes is not None:  # modal coordinates: each mode's largest deflection
        shapes, _ = beam.modes(l, ne, params.rod_mass / l, bending, n_modes)
        return [f"eta_{k + 1}" for k in range(n_modes)], [w_s] * n_modes, shapes
    # beam DOF order: w'_0, w_1, w'_1, ..., w_{N-1}, w'_{N-1}, w'_N
    names = ["w'_0"] + [n for i in range(1, ne) for n in (f"w_{i}", f"w'_{i}")] + [f"w'_{ne}"]
    return names, [w_s * 3.2 / l if n.startswith("w'") else w_s for n in names], None


@dataclass(frozen=True)
class SliderCrank:
    """The in-line slider-crank press (`pressocp.mechanism.Mechanism`): clearances may sit in the
    crank pin and the wrist pin; the rod is rigid or an Euler-Bernoulli rod of Hermite elements in
    its chord frame (axially rigid), whose midspan deflection is an output."""

    name: ClassVar[str] = "slider_crank"
    joints: ClassVar[tuple[str, ...]] = ("crank_pin", "wrist_pin")
    rods: ClassVar[tuple[str, ...]] = ("rigid", "flexible")

    def check_press(self, params: PressParams) -> None:
        """Any press is a slider-crank: nothing to check."""

    def to_dict(self) -> dict:
        """No settings of its own: the press is `PressParams`."""
        return {}

    # The ideal press (closed forms, `pressocp.rigid`) ---------------------------------------------
    def kinematics_function(self, params: PressParams) -> ca.Function:
        """(theta, omega, alpha) -> ram and rod kinematics (`pressocp.rigid.kinematics_function`)."""
        return rigid.kinematics_function(params)

    def inverse_dynamics(self, values: PressParams, theta, omega, alpha) -> dict:
        """`pressocp.rigid.INVERSE_DYNAMICS_OUTPUTS` of the ideal press (SX) at the crank motion."""
        return rigid.inverse_dynamics(values, theta, omega, alpha)

    def stroke(self, params: PressParams) -> float:
        """2 r, m."""
        return params.stroke

    def bottom_dead_centre(self, params: PressParams) -> float:
        """The crank angle at bottom dead centre, pi (the downstroke is [0, pi))."""
        return np.pi

    def input_angle_at_height(self, params: PressParams, height, stroke: str = "down") -> np.ndarray:
        """Crank angle (rad) with the ram at `height` (m) (`pressocp.rigid.crank_angle_at_height`)."""
        return rigid.crank_angle_at_height(params, height, stroke)

    @classmethod
    def from_dict(cls, data: dict) -> "SliderCrank":
        return cls()

    def linkage(self, params: PressParams, values: PressParams, rod: str, n_elements: int,
                n_modes: int | None) -> Linkage:
        """The slider-crank's coordinates and energies (`Mechanism.linkage`)."""
        P, flexible = values, rod == "flexible"
        names, scales, shapes = elastic_coordinates(params, n_elements, n_modes) if flexible else ([], [], None)
        nw = len(names)
        Q, Qd = ca.SX.sym("Q", 6 + nw), ca.SX.sym("Qd", 6 + nw)
        theta, xs, eA, eB, w = Q[0], Q[1], Q[2:4], Q[4:6], Q[6:]
        A_rod, B_rod, S, d, _ = rod_kinematics(P, theta, xs, eA, eB)

        def rate(expr):
            return ca.jtimes(expr, Q, Qd)

        T_c, V_c = mech.crank_energy(P, theta, Qd[0])
        T_s, V_s = mech.body_energy(P.slider_mass, 0.0, P.gravity, S, rate(S), 0)
        phi = ca.atan2(d[0], d[1])  # rod angle: A - B = l (sin phi, cos phi)
        forces, dissipated, outputs = ca.SX.zeros(6 + nw), ca.SX(0), {"rod_midspan_deflection": ca.SX(0)}
        if flexible:
            w_dofs = w if shapes is None else ca.mtimes(ca.DM(shapes), w)  # the element DOFs
            T_r, V_r, strain = flexible_rod_energies(P, n_elements, A_rod, rate(A_rod), d, rate(phi), w_dofs,
                                                     rate(w_dofs))
            V_r += strain
            # a rod inertia other than m l^2/12 is kept as a rigid-body correction
            T_r += 0.5 * (P.rod_inertia_value - P.rod_mass * P.rod_length**2 / 12) * rate(phi) ** 2
            outputs["rod_midspan_deflection"] = beam.deflection_at_share(P.rod_length, n_elements, w_dofs, 0.5)
            beta = 2 * P.rod_damping_ratio / P.rod_first_bending_frequency  # Rayleigh: D = beta K
            rod_damping = -beta * ca.jtimes(ca.gradient(strain, w), w, Qd[6:])
            forces = ca.vertcat(ca.SX.zeros(6), rod_damping)
            dissipated = -ca.dot(rod_damping, Qd[6:])
        else:
            G = 0.5 * (A_rod + B_rod)
            T_r, V_r = mech.body_energy(P.rod_mass, P.rod_inertia_value, P.gravity, G, rate(G), rate(phi))
        return Linkage(
            Q=Q, Qd=Qd, names=["theta", "x_slider", "crank_pin_ex", "crank_pin_ey", "wrist_pin_ex", "wrist_pin_ey",
                               *names],
            kinetic=T_c + T_r + T_s, potential=V_c + V_r + V_s, forces=forces, dissipated=dissipated,
            joints={"crank_pin": (2, 3), "wrist_pin": (4, 5)}, elastic={6 + k: s for k, s in enumerate(scales)},
            ram_height=S[1] + P.crank_radius + P.rod_length, reactions={"slider_normal_force": 1},
            outputs=outputs, details={"rod_modes": shapes})


#: The slider-crank press.
SLIDER_CRANK = SliderCrank()
