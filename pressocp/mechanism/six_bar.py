"""The six-bar drag-link press: a drag-link four-bar drives the crank of an in-line slider-crank.

The input crank turns at the motor's speed; the four-bar's output link is keyed to the press crank,
which drives the rod and the slider as in `SliderCrank`. Frame and angles: the press frame of the
package (``y`` up along the slide, the output axis at the origin, the ram below it); every link
angle of the four-bar is a clock angle (from +y, clockwise positive), and the input angle theta is 0
with the ram at top dead centre. The coordinates are the slider-crank's with the input-crank angle
in place of the press-crank angle psi: ``Q = [theta, x_S, e_A (2), e_B (2), w]``, and psi(theta)
follows from the four-bar's closure in closed form, so no constraint is added. Clearances may sit
in the press crank's pin and the wrist pin; the four-bar's own joints are ideal.

The default dimensions (`SixBarPress`) were found by ``benchmarks/design_sixbar.py``: at constant
input speed the ram speed stays within +-2.0 % of its mean (0.123 m/s at a 1 s cycle) from 0.35 H
down to 0.1 H, a zone that takes 20.3 % of the cycle, 2.2 times as long as in a plain crank press of
the same stroke and cycle time. The transmission angle stays within 31.0..102.1 deg and the output
over input speed ratio within 0.40..1.86 (fast approach and return, bottom dead centre at 64 % of
the cycle).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from functools import cached_property, lru_cache
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import checks as chk
from .. import rigid
from ..params import PressParams
from .base import Linkage
from .slider_crank import SLIDER_CRANK


@dataclass(frozen=True)
class SixBarPress:
    """Dimensions of a six-bar drag-link press (all lengths in m, angles in rad).

    Parameters
    ----------
    ground_length : float
        Distance between the input-crank axis and the output axis, m.  Must be
        the shortest of the four-bar links (drag-link).  Default 0.0500 m.
    ground_angle : float
        Clock angle (from ``+y``, clockwise positive) of the vector pointing
        from the input axis to the output axis, rad.  Default ``pi`` (input
        axis directly above the output axis).  Note that for the ram motion
        versus input angle only ``arm_phase`` relative to this direction
        matters; rotating the four-bar and the arm phase together leaves
        ``h(theta)`` unchanged.
    input_crank : float
        Input-crank length (input axis to coupler joint A), m.  Default 0.1656 m.
    coupler : float
        Coupler length (joint A to joint B), m.  Default 0.1805 m.
    output_link : float
        Output-link length (output axis to joint B), m.  Default 0.0860 m.
    arm_phase : float
        Clock angle of the press-crank arm minus the clock angle of the
        output link (both about the output axis), rad.  Default
        ``radians(108.43)``.
    assembly : int
        Four-bar assembly branch, ``+1`` or ``-1``: sign of the angle from the
        output-axis-to-A direction to the output link (``+1`` means the output
        link is clockwise of line O4-A).  Default ``+1``.
    crank_radius : float
        Press (slider-crank) crank radius ``r``, m; the stroke is ``H = 2 r``.
        Default 0.05 m.
    rod_length : float
        Press connecting-rod length ``l``, m, ``l > r``.  Default 0.25 m.

    Raises
    ------
    ValueError
        On non-finite or non-positive lengths, a four-bar that is not a
        drag-link (the ground must be the shortest link and
        ``s + l < p + q`` strictly — the change-point case ``s + l = p + q``
        has a folded, singular position and is rejected), ``assembly`` not in
        ``{-1, +1}``, or ``rod_length <= crank_radius``.
    """

    ground_length: float = 0.0500
    ground_angle: float = math.pi
    input_crank: float = 0.1656
    coupler: float = 0.1805
    output_link: float = 0.0860
    arm_phase: float = math.radians(108.43)
    assembly: int = 1
    crank_radius: float = 0.05
    rod_length: float = 0.25

    def __post_init__(self) -> None:
        for name in ("ground_length", "input_crank", "coupler", "output_link", "crank_radius", "rod_length"):
            chk.positive(name, getattr(self, name), "m")
        chk.finite("ground_angle", self.ground_angle)
        chk.finite("arm_phase", self.arm_phase)
        if isinstance(self.assembly, bool) or self.assembly not in (1, -1):
            raise ValueError(f"assembly must be one of +1, -1; got {self.assembly!r}")
        g = float(self.ground_length)
        others = {"input_crank": float(self.input_crank), "coupler": float(self.coupler),
                  "output_link": float(self.output_link)}
        shortest_other = min(others.values())
        if not g < shortest_other:
            raise ValueError(
                f"ground_length must be in (0, {shortest_other:g}) m: a drag-link four-bar needs the ground "
                f"to be the shortest link, got {g!r}"
            )
        # Grashof with the strict inequality: g + longest < sum of the other two moving links
        # (the change-point case has a folded, singular position).
        longest_name = max(others, key=others.__getitem__)
        longest = others[longest_name]
        rest = sum(others.values()) - longest
        if not g + longest < rest:
            g_max = rest - longest
            if g_max > 0.0:
                raise ValueError(
                    f"ground_length must be in (0, {g_max:g}) m for a drag-link four-bar (Grashof: "
                    f"ground_length + {longest_name} < sum of the other two links), got {g!r}"
                )
            raise ValueError(
                f"{longest_name} must be in (0, {rest - g:g}) m for a drag-link four-bar (Grashof: "
                f"ground_length + {longest_name} < sum of the other two links), got {longest!r}"
            )
        if not float(self.rod_length) > float(self.crank_radius):
            raise ValueError(
                f"rod_length must be in ({float(self.crank_radius):g}, inf) m (longer than crank_radius), "
                f"got {self.rod_length!r}"
            )

    # ------------------------------------------------------------------ derived
    @property
    def stroke(self) -> float:
        """Ram stroke ``H = 2 r``, m."""
        return 2.0 * float(self.crank_radius)

    @property
    def input_axis(self) -> np.ndarray:
        """Position (x, y) of the input-crank axis relative to the output axis, m."""
        g, gam = float(self.ground_length), float(self.ground_angle)
        return -g * np.array([math.sin(gam), math.cos(gam)])

    @cached_property
    def input_at_top_dead_centre(self) -> float:
        """Input-crank clock angle (rad) at which the ram is at top dead centre: the input angle
        ``theta`` is measured from it. The output link's clock angle is then -arm_phase; of the two
        input-crank positions that close the loop there, the one on the `assembly` branch."""
        g, a, b, c = self.ground_length, self.input_crank, self.coupler, self.output_link
        o2 = -g * np.array([math.cos(self.ground_angle), math.sin(self.ground_angle)])  # clock frame (u, v)
        phi = -float(self.arm_phase)
        rel = c * np.array([math.cos(phi), math.sin(phi)]) - o2  # joint B from the input axis
        e = math.hypot(*rel)
        half = math.acos(min(1.0, max(-1.0, (a * a + e * e - b * b) / (2 * a * e))))
        candidates = math.atan2(rel[1], rel[0]) + np.array([half, -half])
        pin = o2[:, None] + a * np.stack([np.cos(candidates), np.sin(candidates)])  # joint A
        d = np.hypot(*pin)
        out = np.arctan2(pin[1], pin[0]) + self.assembly * np.arccos(np.clip((c * c + d * d - b * b) / (2 * c * d), -1, 1))
        miss = np.abs(np.angle(np.exp(1j * (out - phi))))
        return float(np.angle(np.exp(1j * candidates[np.argmin(miss)])))


def fourbar(drive: SixBarPress, theta):
    """The four-bar at input angle `theta` (rad, 0 with the ram at top dead centre): the press-crank
    angle psi (rad, wrapped), the coupler's clock angle (rad) and its centre (x, y) in the press
    frame (m), as CasADi expressions (the position analysis in the clock frame). `drive` is any
    four-bar geometry with `SixBarPress`'s link fields, ``assembly``, ``arm_phase`` and
    ``input_at_top_dead_centre``; the output axis is the press frame's origin."""
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


@lru_cache(maxsize=16)
def press_crank_function(drive: SixBarPress) -> ca.Function:
    """theta -> the press crank's angle psi (rad, wrapped) and dpsi/dtheta, of the four-bar."""
    theta = ca.SX.sym("theta")
    psi = fourbar(drive, theta)[0]
    return ca.Function("press_crank", [theta], [psi, ca.jacobian(psi, theta)], ["theta"], ["psi", "ratio"])


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
    #: The class of `drive` (a subclass with another four-bar names its own).
    geometry: ClassVar[type] = SixBarPress
    joints: ClassVar[tuple[str, ...]] = SLIDER_CRANK.joints
    rods: ClassVar[tuple[str, ...]] = SLIDER_CRANK.rods

    def __post_init__(self) -> None:
        chk.instance("drive", self.drive, self.geometry)
        chk.nonnegative("input_inertia", self.input_inertia, "kg m^2")
        chk.nonnegative("coupler_mass", self.coupler_mass, "kg")
        if self.coupler_inertia is not None:
            chk.nonnegative("coupler_inertia", self.coupler_inertia, "kg m^2")

    def check_press(self, params: PressParams) -> None:
        """ValueError unless the press's crank radius and rod length are the drive's (the same part)."""
        for name in ("crank_radius", "rod_length"):
            if getattr(params, name) != getattr(self.drive, name):
                raise ValueError(f"{name} = {getattr(params, name):g} m of the press differs from the {self.name} "
                                 f"drive's {getattr(self.drive, name):g} m: they are the same part")

    def to_dict(self) -> dict:
        """The drive's geometry and the four-bar's inertias as plain data."""
        return {"drive": asdict(self.drive), "input_inertia": self.input_inertia, "coupler_mass": self.coupler_mass,
                "coupler_inertia": self.coupler_inertia}

    @classmethod
    def from_dict(cls, data: dict) -> "SixBar":
        return cls(cls.geometry(**data.get("drive", {})), data.get("input_inertia", 0.0), data.get("coupler_mass", 0.0),
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

    def stroke(self, params: PressParams) -> float:
        """2 r, m: the press crank turns full circle."""
        return params.stroke

    def bottom_dead_centre(self, params: PressParams) -> float:
        """The input angle at bottom dead centre, rad (the downstroke is [0, it))."""
        return float(self.input_angle_at_height(params, 0.0))

    def input_angle_at_height(self, params: PressParams, height, stroke: str = "down") -> np.ndarray:
        """Input angle (rad, in [0, 2 pi)) with the ram at `height` (m) on the down- or upstroke: the
        press crank's angle from the slider-crank's closed form, the input angle from the four-bar by
        Newton's method from a tabulated start, to round-off."""
        psi = np.asarray(rigid.crank_angle_at_height(params, height, stroke), float)
        f = press_crank_function(self.drive)
        grid = np.linspace(0.0, 2 * np.pi, 2049)
        table = np.unwrap(rigid.evaluate_elementwise(f, grid)["psi"])
        theta = np.interp(psi, table - table[0], grid)
        for _ in range(8):
            k = rigid.evaluate_elementwise(f, theta)
            theta = theta - np.angle(np.exp(1j * (k["psi"] - psi))) / k["ratio"]
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
