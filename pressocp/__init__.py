"""pressocp: servo mechanical presses with joint clearance, and optimal crank-speed design.

    import pressocp as po
    problem = po.SpeedProblem(po.PressParams(), period=0.8)
    result = po.optimize_speed(problem)
"""

from .blas import set_casadi_blas_threads
from .casadi_clock import set_casadi_clock
from .design import DesignSettings, SpeedDesign, design_speed
from .drive import Drive, MotorCycle, motor_cycle
from .mechanism import (KnuckleJoint, KnucklePress, SixBar, SixBarPress, SliderCrank, WorkingZone,
                        constant_speed_zone)
from .journals import ContactLosses, contact_losses
from .model import ModelSpec, PressModel, build_model
from .objectives import OBJECTIVES, Objective
from .ocp import (Collocation, MultipleShooting, OcpResult, OptimumSensitivities, Rigid, SensitivityError,
                  StageResult, Strategy, Transcription, TranscriptionRecommendation, WarmStart, optimize_speed,
                  optimum_sensitivities, recommend_transcription)
from .params import Bearing, Counterbalance, PressParams, ProcessForce, hertz_internal_stiffness
from .problem import ReversalWarning, SpeedProblem
from .stroke_rate import RateSearch, max_stroke_rate
from .recommend import ModelRecommendation, recommend_model
from .result import SimResult
from .scenario import Scenario, ScenarioError
from .rigid import crank_angle_at_height, rigid_inverse_dynamics, rigid_kinematics, rigid_response
from .sensitivity import Sensitivities, sensitivities
from .simulate import Integrator, SimulationError, simulate
from .speed import FourierSpeed
from .sweeps import Continuation, sweep

__all__ = [
    "OBJECTIVES", "Bearing", "Collocation", "ContactLosses", "Continuation", "DesignSettings", "Drive", "FourierSpeed", "Integrator", "KnuckleJoint", "KnucklePress",
    "ModelRecommendation", "ModelSpec", "MotorCycle",
    "MultipleShooting", "Objective", "OcpResult", "OptimumSensitivities", "PressModel", "PressParams",
    "Counterbalance", "ProcessForce", "RateSearch", "ReversalWarning", "Rigid", "Scenario", "ScenarioError", "SensitivityError", "SimResult", "SimulationError",
    "SixBar", "SixBarPress", "SliderCrank",
    "SpeedDesign", "SpeedProblem", "StageResult", "Strategy", "Transcription", "TranscriptionRecommendation", "WarmStart", "WorkingZone", "build_model",
    "constant_speed_zone", "contact_losses", "crank_angle_at_height",
    "design_speed", "hertz_internal_stiffness", "max_stroke_rate", "motor_cycle", "optimize_speed", "optimum_sensitivities", "recommend_model", "recommend_transcription",
    "rigid_inverse_dynamics", "rigid_kinematics", "rigid_response", "sensitivities", "Sensitivities", "simulate",
    "set_casadi_blas_threads", "set_casadi_clock", "sweep",
]

#: One thread for CasADi's own OpenBLAS (IPOPT, MUMPS) in every process: the same answer on any core
#: count and on every path (`pressocp.blas`).
set_casadi_blas_threads(1)
#: CasADi's statistics without the process CPU clock (a system call in every call of an integrator's
#: inner functions: a third of an IDAS cycle), its numbers unchanged (`pressocp.casadi_clock`).
set_casadi_clock(False)
