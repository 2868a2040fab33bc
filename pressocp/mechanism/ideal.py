"""The ideal press (ideal joints, rigid rod) of any mechanism, evaluated at numbers: kinematics,
inverse dynamics and the response to a crank speed, from the mechanism's own (for the slider-crank
the closed forms of `pressocp.rigid`)."""

from __future__ import annotations

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


def ideal_kinematics(params: PressParams, mechanism: Mechanism, theta: Any, omega: Any = 0.0,
                     alpha: Any = 0.0) -> dict[str, np.ndarray]:
    """Ram and rod kinematics of the ideal press at the driven crank's motion (arrays broadcast)."""
    for name, v in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        chk.finite_array(name, v, ndim=None)
    return rigid.evaluate_elementwise(mechanism.kinematics_function(params), theta, omega, alpha)


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
