"""pressocp: servo mechanical presses with joint clearance, and optimal crank-speed design."""

from .params import Bearing, PressParams, ProcessForce, hertz_internal_stiffness
from .result import SimResult
from .rigid import crank_angle_at_height, rigid_inverse_dynamics, rigid_kinematics, rigid_response
from .speed import FourierSpeed

__all__ = [
    "Bearing", "FourierSpeed", "PressParams", "ProcessForce", "SimResult", "crank_angle_at_height",
    "hertz_internal_stiffness", "rigid_inverse_dynamics", "rigid_kinematics", "rigid_response",
]
