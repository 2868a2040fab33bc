"""Optimal control of the crank speed: problem statement, transcriptions, results (rockit style)."""

from .optimize import optimize_speed
from .problem import OBJECTIVES, SpeedProblem
from .result import OcpResult
from .rigid import solve_rigid
from .shooting import ShootingError, ShootingGrid, solve_shooting

__all__ = ["OBJECTIVES", "OcpResult", "ShootingError", "ShootingGrid", "SpeedProblem", "optimize_speed",
           "solve_rigid", "solve_shooting"]
