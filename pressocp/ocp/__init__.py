"""Optimal control of the crank speed: problem statement, transcriptions, results (rockit style)."""

from .problem import OBJECTIVES, SpeedProblem
from .result import OcpResult
from .rigid import solve_rigid

__all__ = ["OBJECTIVES", "OcpResult", "SpeedProblem", "solve_rigid"]
