"""The contract between a linkage and the model builder."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import casadi as ca
import numpy as np

from ..params import PressParams


@dataclass
class Linkage:
    """A mechanism's coordinates and energies, symbolic in ``Q`` and ``Qd``.

    The builder locks every coordinate that is not a state: the crank angle ``Q[0]`` follows the
    prescribed motion, every other locked coordinate is held at 0, and the Lagrange equation row of
    a locked coordinate gives its reaction (the motor torque for ``Q[0]``).

    Attributes
    ----------
    Q, Qd : ca.SX (n,)
        Generalised coordinates and their rates; ``Q[0]`` is the crank angle, rad.
    names : list of str
        The coordinates' names (a state is named after its coordinate).
    kinetic, potential : ca.SX
        Kinetic energy T(Q, Qd) and potential energy V(Q) (gravity and strain), J.
    forces : ca.SX (n,)
        Applied generalised forces other than contact and process (a rod's material damping).
    dissipated : ca.SX
        Power taken out by `forces`, W (0 without them).
    joints : dict of str to (int, int)
        Every joint where a clearance may sit: the indices in ``Q`` of its eccentricity (bearing
        centre minus journal centre, m, in the press frame). Locked at 0 when the joint is ideal.
    elastic : dict of int to float
        Elastic coordinates (always states) and their scales.
    ram_height : ca.SX
        Ram height above bottom dead centre, m (the process force acts along it).
    reactions : dict of str to int
        Outputs that are the reaction of one locked coordinate (the guide's normal force).
    outputs : dict of str to ca.SX
        Outputs of this linkage's own, in Q (a rod's midspan deflection, m).
    details : dict
        Data the model keeps (a reduced rod's mode shapes under ``"rod_modes"``).
    """

    Q: ca.SX
    Qd: ca.SX
    names: list[str]
    kinetic: ca.SX
    potential: ca.SX
    forces: ca.SX
    dissipated: ca.SX
    joints: dict[str, tuple[int, int]]
    elastic: dict[int, float]
    ram_height: ca.SX
    reactions: dict[str, int] = field(default_factory=dict)
    outputs: dict[str, ca.SX] = field(default_factory=dict)
    details: dict[str, Any] = field(default_factory=dict)

    def eccentricity(self, joint: str) -> ca.SX:
        """The eccentricity coordinates of `joint` (2,)."""
        i, j = self.joints[joint]
        return self.Q[[i, j]]

    def rate(self, expr: ca.SX) -> ca.SX:
        """d(expr)/dt along the coordinates' rates."""
        return ca.jtimes(expr, self.Q, self.Qd)


class Mechanism(Protocol):
    """A linkage the model builder can use.

    Attributes
    ----------
    name : str
        Its key in `pressocp.mechanism.MECHANISMS`.
    joints : tuple of str
        Joints where a clearance may sit, each a `pressocp.params.Bearing` of the press by that name.
    rods : tuple of str
        The rod models it offers ("rigid", and "flexible" when it has an elastic rod).
    """

    name: str
    joints: tuple[str, ...]
    rods: tuple[str, ...]

    def check_press(self, params: PressParams) -> None:
        """ValueError when the press does not fit this mechanism (before anything is built)."""
        ...

    def to_dict(self) -> dict:
        """Its settings as plain data."""
        ...

    def kinematics_function(self, params: PressParams) -> ca.Function:
        """The ideal press's (theta, omega, alpha) of the driven crank -> ``ram_height``,
        ``ram_velocity``, ``ram_acceleration``, ``rod_angle``, ``rod_angular_velocity``,
        ``rod_angular_acceleration`` (the outputs of `pressocp.rigid.kinematics_function`)."""
        ...

    def inverse_dynamics(self, values: PressParams, theta: ca.SX, omega: ca.SX, alpha: ca.SX) -> dict:
        """The ideal press's `pressocp.rigid.INVERSE_DYNAMICS_OUTPUTS` as SX expressions of the driven
        crank's motion (`theta` a symbol; `values` may hold symbols)."""
        ...

    def stroke(self, params: PressParams) -> float:
        """The ram's travel from top to bottom dead centre, m (the heights h of a window are fractions
        h/H of it)."""
        ...

    def bottom_dead_centre(self, params: PressParams) -> float:
        """The driven crank's angle at bottom dead centre, rad: the downstroke is [0, it)."""
        ...

    def input_angle_at_height(self, params: PressParams, height: Any, stroke: str = "down") -> np.ndarray:
        """The driven crank's angle (rad) with the ram at `height` (m) on the "down" or "up" stroke."""
        ...

    @classmethod
    def from_dict(cls, data: dict) -> "Mechanism":
        """The mechanism of `to_dict`'s data."""
        ...

    def linkage(self, params: PressParams, values: PressParams, rod: str, n_elements: int,
                n_modes: int | None) -> Linkage:
        """The coordinates and energies of the press `params` whose numbers in the expressions are
        `values` (the same press, some entries CasADi symbols); scales come from `params`."""
        ...

