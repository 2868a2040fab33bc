"""The six-bar drag-link press: a drag-link four-bar drives the crank of an in-line slider-crank.

The input crank turns at the motor's speed; the four-bar's output link is keyed to the press crank,
which drives the rod and the slider as in `SliderCrank`. Its geometry and conventions are those of
`pressocp.sixbar.SixBarPress` (clock angles from +y, clockwise positive; the input angle theta is 0
with the ram at top dead centre). The coordinates are the slider-crank's with the input-crank angle
in place of the press-crank angle psi: ``Q = [theta, x_S, e_A (2), e_B (2), w]``, and psi(theta)
follows from the four-bar's closure in closed form, so no constraint is added. Clearances may sit
in the press crank's pin and the wrist pin; the four-bar's own joints are ideal.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import checks as chk
from .. import rigid
from ..params import PressParams
from ..sixbar import SixBarPress, sixbar_kinematics
from .base import Linkage
from .slider_crank import SLIDER_CRANK


def fourbar(drive: SixBarPress, theta):
    """The four-bar at input angle `theta` (rad, 0 with the ram at top dead centre): the press-crank
    angle psi (rad, wrapped), the coupler's clock angle (rad) and its centre (x, y) in the press
    frame (m), as CasADi expressions (`pressocp.sixbar`'s position analysis)."""
    g, a, b, c = drive.ground_length, drive.input_crank, drive.coupler, drive.output_link
    th = theta + drive.input_at_top_dead_centre
    # in the clock frame (u, v) = (y, x), the output axis at the origin
    au = -g * ca.cos(drive.ground_angle) + a * ca.cos(th)
    av = -g * ca.sin(drive.ground_angle) + a * ca.sin(th)
    d2 = au**2 + av**2
    phi = ca.atan2(av, au) + drive.assembly * ca.acos((c**2 + d2 - b**2) / (2 * c * ca.sqrt(d2)))
    bu, bv = c * ca.cos(phi), c * ca.sin(phi)
    beta = ca.atan2(bv - av, bu - au)
    return phi + drive.arm_phase, beta, ca.vertcat(av + bv, au + bu) / 2


@dataclass(frozen=True)
class SixBar:
    """The six-bar drag-link press (`pressocp.mechanism.Mechanism`).

    The slider-crank part (press crank, rod, slider, bearings) is the press's `PressParams`, whose
    ``crank_inertia`` is then that of everything keyed to the output shaft (the output link with the
    press crank); the four-bar adds the input crank and the coupler.

    Attributes
    ----------
    drive : SixBarPress
        The geometry; its ``crank_radius`` and ``rod_length`` must be the press's.
    input_inertia : float
        Moment of inertia about the input axis of the input crank and what turns with it, kg m^2
        (>= 0; its centre of mass on the axis).
    coupler_mass : float
        kg (>= 0).
    coupler_inertia : float or None
        About its centre of mass, which is midway between its joints, kg m^2 (>= 0); None: a slender
        bar, m b^2 / 12.
    """

    drive: SixBarPress = field(default_factory=SixBarPress)
    input_inertia: float = 0.0
    coupler_mass: float = 0.0
    coupler_inertia: float | None = None
    name: ClassVar[str] = "six_bar"
    joints: ClassVar[tuple[str, ...]] = SLIDER_CRANK.joints
    rods: ClassVar[tuple[str, ...]] = SLIDER_CRANK.rods

    def __post_init__(self) -> None:
        chk.instance("drive", self.drive, SixBarPress)
        chk.nonnegative("input_inertia", self.input_inertia, "kg m^2")
        chk.nonnegative("coupler_mass", self.coupler_mass, "kg")
        if self.coupler_inertia is not None:
            chk.nonnegative("coupler_inertia", self.coupler_inertia, "kg m^2")

    def check_press(self, params: PressParams) -> None:
        """ValueError unless the press's crank radius and rod length are the drive's (the same part)."""
        for name in ("crank_radius", "rod_length"):
            if getattr(params, name) != getattr(self.drive, name):
                raise ValueError(f"{name} = {getattr(params, name):g} m of the press differs from the six-bar "
                                 f"drive's {getattr(self.drive, name):g} m: they are the same part")

    def to_dict(self) -> dict:
        """The drive's geometry and the four-bar's inertias as plain data."""
        return {"drive": asdict(self.drive), "input_inertia": self.input_inertia, "coupler_mass": self.coupler_mass,
                "coupler_inertia": self.coupler_inertia}

    @classmethod
    def from_dict(cls, data: dict) -> "SixBar":
        return cls(SixBarPress(**data.get("drive", {})), data.get("input_inertia", 0.0), data.get("coupler_mass", 0.0),
                   data.get("coupler_inertia"))

    # The ideal press: the slider-crank's closed forms at the press crank's motion ---------------
    def crank_motion(self, theta: ca.SX, omega: ca.SX, alpha: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
        """The press crank's angle, rate and acceleration (rad, rad/s, rad/s^2) at the input crank's
        motion (`theta` a symbol), and the velocity ratio dpsi/dtheta."""
        psi = fourbar(self.drive, theta)[0]
        d1 = ca.jacobian(psi, theta)
        return psi, d1 * omega, ca.jacobian(d1, theta) * omega**2 + d1 * alpha, d1

    def fourbar_energies(self, values: PressParams, theta: ca.SX, omega: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX]:
        """The input crank's and coupler's kinetic and potential energy (J) and their generalised
        mass about the input axis M(theta) (kg m^2: T = M omega^2 / 2)."""
        _, beta, G = fourbar(self.drive, theta)
        dG, dbeta = ca.jacobian(G, theta), ca.jacobian(beta, theta)
        J_c = self.coupler_mass * self.drive.coupler**2 / 12 if self.coupler_inertia is None else self.coupler_inertia
        mass = self.input_inertia + self.coupler_mass * ca.sumsqr(dG) + J_c * dbeta**2
        return 0.5 * mass * omega**2, self.coupler_mass * values.gravity * G[1], mass

    def kinematics_function(self, params: PressParams) -> ca.Function:
        """(theta, omega, alpha) of the input crank -> ram and rod kinematics (the outputs of
        `pressocp.rigid.kinematics_function`)."""
        th, om, al = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
        psi, psi_d, psi_dd, _ = self.crank_motion(th, om, al)
        f = rigid.kinematics_function(params)
        out = f(psi, psi_d, psi_dd)
        return ca.Function("six_bar_kinematics", [th, om, al], list(out), ["theta", "omega", "alpha"], f.name_out())

    def inverse_dynamics(self, values: PressParams, theta, omega, alpha) -> dict:
        """`pressocp.rigid.INVERSE_DYNAMICS_OUTPUTS` of the ideal six-bar (SX) at the input crank's motion:
        the slider-crank's at the press crank's motion, the torque brought to the input axis
        (tau psi') plus the four-bar links' own, M alpha + M' omega^2 / 2 + dV/dtheta, and their
        energies added."""
        psi, psi_d, psi_dd, ratio = self.crank_motion(theta, omega, alpha)
        crank = ca.SX.sym("psi", 3)  # the closed forms differentiate with respect to a symbol
        at_crank = rigid.inverse_dynamics(values, crank[0], crank[1], crank[2])
        out = dict(zip(at_crank, ca.substitute(list(at_crank.values()), [crank], [ca.vertcat(psi, psi_d, psi_dd)])))
        T4, V4, mass = self.fourbar_energies(values, theta, omega)
        links = mass * alpha + 0.5 * ca.jacobian(mass, theta) * omega**2 + ca.jacobian(V4, theta)
        out["torque"] = out["torque"] * ratio + links
        out["kinetic_energy"] = out["kinetic_energy"] + T4
        out["potential_energy"] = out["potential_energy"] + V4
        return out

    def bottom_dead_centre(self, params: PressParams) -> float:
        """The input angle at bottom dead centre, rad (the downstroke is [0, it))."""
        return float(self.input_angle_at_height(params, 0.0))

    def input_angle_at_height(self, params: PressParams, height, stroke: str = "down") -> np.ndarray:
        """Input angle (rad, in [0, 2 pi)) with the ram at `height` (m) on the down- or upstroke: the
        press crank's angle from the slider-crank's closed form, the input angle from the four-bar by
        Newton's method on the numpy kinematics (`pressocp.sixbar`), to round-off."""
        psi = np.asarray(rigid.crank_angle_at_height(params, height, stroke), float)
        grid = np.linspace(0.0, 2 * np.pi, 2049)
        theta = np.interp(psi, sixbar_kinematics(self.drive, grid)["psi"], grid)
        for _ in range(6):
            k = sixbar_kinematics(self.drive, theta)
            theta = theta - (k["psi"] - psi) / k["dpsi_dtheta"]
        return theta

    def linkage(self, params: PressParams, values: PressParams, rod: str, n_elements: int,
                n_modes: int | None) -> Linkage:
        """The slider-crank's linkage with psi(theta) in place of its crank angle, plus the input
        crank's and the coupler's energies (`Mechanism.linkage`)."""
        self.check_press(params)
        sc = SLIDER_CRANK.linkage(params, values, rod, n_elements, n_modes)
        Q, Qd = ca.SX.sym("Q", sc.Q.numel()), ca.SX.sym("Qd", sc.Q.numel())
        Q_sc = ca.vertcat(fourbar(self.drive, Q[0])[0], Q[1:])
        J = ca.jacobian(Q_sc, Q)

        def sub(expr):  # from the slider-crank's coordinates to these
            return ca.substitute(expr, ca.vertcat(sc.Q, sc.Qd), ca.vertcat(Q_sc, J @ Qd))

        T4, V4, _ = self.fourbar_energies(values, Q[0], Qd[0])
        return Linkage(Q=Q, Qd=Qd, names=["theta", *sc.names[1:]], kinetic=sub(sc.kinetic) + T4,
                       potential=sub(sc.potential) + V4,
                       forces=J.T @ sub(sc.forces), dissipated=sub(sc.dissipated), joints=sc.joints,
                       elastic=sc.elastic, ram_height=sub(sc.ram_height), reactions=sc.reactions,
                       outputs={k: sub(v) for k, v in sc.outputs.items()}, details=sc.details)
