"""Optimal control of the crank speed (rockit style): the problem (`pressocp.SpeedProblem`), the
transcriptions (`Rigid`, `MultipleShooting`, `Collocation`), the stage chain (`Strategy`) and the
result (`OcpResult`)."""

from .choice import TranscriptionRecommendation, recommend_transcription
from .collocation import Collocation, CollocationGrid
from .optimize import optimize_speed
from .ocp_result import OcpResult
from .rigid_stage import Rigid
from .optimum_sensitivity import OptimumSensitivities, SensitivityError, optimum_sensitivities
from .shooting import MultipleShooting, ShootingError, ShootingGrid
from .stage import Check, StageResult, Transcription, WarmStart, transcription_from
from .strategy import VERIFY_RTOL_RANGE, Strategy

__all__ = ["Check", "Collocation", "CollocationGrid", "MultipleShooting", "OcpResult", "OptimumSensitivities", "Rigid",
           "SensitivityError", "ShootingError", "ShootingGrid", "StageResult", "Strategy", "Transcription",
           "TranscriptionRecommendation", "VERIFY_RTOL_RANGE", "WarmStart", "optimize_speed", "optimum_sensitivities",
           "recommend_transcription", "transcription_from"]
