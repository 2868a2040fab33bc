"""Optimal control of the crank speed: problem statement, transcriptions, results (rockit style)."""

from .collocation import CollocationGrid, solve_collocation
from .optimize import optimize_speed
from .problem import OBJECTIVES, SpeedProblem
from .result import OcpResult
from .rigid import solve_rigid
from .shooting import ShootingError, ShootingGrid, solve_shooting

__all__ = ["OBJECTIVES", "CollocationGrid", "OcpResult", "ShootingError", "ShootingGrid", "SpeedProblem",
           "optimize_speed", "solve_collocation", "solve_rigid", "solve_shooting"]
