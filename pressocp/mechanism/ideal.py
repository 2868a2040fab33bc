"""The ideal press (ideal joints, rigid rod) of any mechanism, evaluated at numbers: kinematics,
inverse dynamics and the response to a crank speed, from the mechanism's own (for the slider-crank
the closed forms of `pressocp.rigid`)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from .. import checks as chk
from .. import rigid
from ..params import PressParams
from ..result import SimResult
from ..speed import FourierSpeed
from .base import Mechanism


@lru_cache(maxsize=32)
def inverse_dynamics_function(params: PressParams, mechanism: Mechanism) -> ca.Function:
    """(theta, omega, alpha) -> `pressocp.rigid.INVERSE_DYNAMICS_OUTPUTS` of the ideal press (one sample)."""
    theta, omega, alpha = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
    out = mechanism.inverse_dynamics(params, theta, omega, alpha)
    return ca.Function("ideal_inverse_dynamics", [theta, omega, alpha],
                       [out[k] for k in rigid.INVERSE_DYNAMICS_OUTPUTS], ["theta", "omega", "alpha"],
                       list(rigid.INVERSE_DYNAMICS_OUTPUTS))


@lru_cache(maxsize=32)
def kinematics_function(params: PressParams, mechanism: Mechanism) -> ca.Function:
    """`Mechanism.kinematics_function`, built once per press and mechanism (a six-bar's or a toggle's
    took 10-20 ms to build, and the problem's checks and the design ask for it many times)."""
    return mechanism.kinematics_function(params)


def ideal_kinematics(params: PressParams, mechanism: Mechanism, theta: Any, omega: Any = 0.0,
                     alpha: Any = 0.0) -> dict[str, np.ndarray]:
    """Ram and rod kinematics of the ideal press at the driven crank's motion (arrays broadcast)."""
    for name, v in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        chk.finite_array(name, v, ndim=None)
    return rigid.evaluate_elementwise(kinematics_function(params, mechanism), theta, omega, alpha)


def ideal_inverse_dynamics(params: PressParams, mechanism: Mechanism, theta: Any, omega: Any,
                           alpha: Any) -> dict[str, np.ndarray]:
    """Motor torque, joint forces and energies of the ideal press (`pressocp.rigid.rigid_inverse_dynamics`)."""
    for name, v in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        chk.finite_array(name, v, ndim=None)
    return rigid.evaluate_elementwise(inverse_dynamics_function(params, mechanism), theta, omega, alpha)


def ideal_response(params: PressParams, mechanism: Mechanism, speed: FourierSpeed, t: Any = None) -> SimResult:
    """The ideal press's response to `speed` at times `t` (s; default 2001 over a period), as a
    `SimResult` whose eccentricities and rod deflection are zero (`pressocp.rigid.rigid_response`)."""
    chk.instance("speed", speed, FourierSpeed)
    t = chk.finite_array("t", np.linspace(0.0, speed.period, 2001) if t is None else t)
    theta, omega, alpha = speed.evaluate(t)
    return rigid.ideal_result(t, theta, omega, ideal_inverse_dynamics(params, mechanism, theta, omega, alpha))


@dataclass(frozen=True)
class WorkingZone:
    """The ram's passage through a height band on the downstroke at constant input speed.

    Attributes
    ----------
    t_start, t_end : float
        Times (s from top dead centre) at which the ram enters and leaves the band.
    mean_speed : float
        The band's height over the time it takes, m/s (positive).
    max_deviation : float
        max | |dh/dt| - mean_speed | / mean_speed over the band, - (0.05: within +-5 %).
    """

    t_start: float
    t_end: float
    mean_speed: float
    max_deviation: float


def constant_speed_zone(params: PressParams, mechanism: Mechanism, period: float,
                        zone: tuple[float, float] = (0.35, 0.1), n: int = 2001) -> WorkingZone:
    """How the ideal press at constant input speed 2 pi / `period` (s) crosses the band `zone` (ram
    heights as fractions h/H of the stroke, each in (0, 1), in either order) on the downstroke, with
    the speed's deviation sampled at `n` (>= 2) instants evenly spaced in time across it."""
    period = chk.positive("period", period, "s")
    n = chk.integer("n", n, 2, 10_000_000)
    if len(zone) != 2:
        raise ValueError(f"zone must be a pair (h/H start, h/H end) in (0, 1), got {zone!r}")
    fractions = [chk.in_open_interval(f"zone[{i}]", z, 0.0, 1.0) for i, z in enumerate(zone)]
    if fractions[0] == fractions[1]:
        raise ValueError(f"zone bounds must differ (h/H in (0, 1)), got {zone!r}")
    hi, lo = max(fractions), min(fractions)
    H = mechanism.stroke(params)
    th0, th1 = mechanism.input_angle_at_height(params, np.array([hi, lo]) * H, "down")
    omega = 2 * np.pi / period
    mean = (hi - lo) * H * omega / (th1 - th0)
    v = ideal_kinematics(params, mechanism, np.linspace(th0, th1, n), omega)["ram_velocity"]
    return WorkingZone(float(th0 / omega), float(th1 / omega), float(mean),
                       float(np.max(np.abs(-v - mean)) / mean))
