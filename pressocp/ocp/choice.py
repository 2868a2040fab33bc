"""Which transcription a scene should be solved with (`recommend_transcription`), from what the
transcriptions did on the bundled scenes (`benchmarks/bench_transcriptions.py`; the numbers below).

`recommend_model` says which model level a scene needs; this says how to solve on it:

* **No states** (ideal joints, rigid rod): `Rigid`, the loads in closed form at samples, exact
  Hessian, seconds.
* **Clearance joints**: `Collocation` (the journals kept on their walls). Multiple shooting through
  IDAS or CVODES did not converge within its wall-time cap at any point of the map (60 and 75 spm x
  0.05 and 0.2 mm clearances: 2-13 iterations in 600-800 s each) nor on the 75 spm seed (12
  iterations in 31 min), where collocation converged in 11-16 s (2026-11-23 and 2026-11-25).
* **A flexible rod between ideal joints** (a smooth scene): `Collocation` for the solve, then, when
  minutes more are worth 1-2 % of the objective, `MultipleShooting("idas")` started from its
  optimum (16 intervals x 100 samples). On the slender-rod scene the default call (collocation,
  about 100 s) verified at 70.335 N m, and IDAS shooting from there converged in 81 iterations and
  464 s to 69.160 N m verified (2026-11-27). Started from the rigid press's optimum instead, IDAS
  shooting did not converge in 15 min and CVODES stopped at 73.85 after 836 s (2026-11-24): shooting
  refines, it does not find.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..model import ModelSpec, PressModel
from .collocation import Collocation
from .rigid_stage import Rigid
from .shooting import MultipleShooting
from .stage import Transcription

#: Output samples per interval of the recommended shooting refinement: the ram speed is held at the
#: samples that bracket the working window, and 25 (the default) held it too far outside on the
#: slender-rod scene (`MultipleShooting.samples`).
REFINE_SAMPLES = 100


@dataclass(frozen=True)
class TranscriptionRecommendation:
    """The transcription a scene's model should be solved with, and why.

    Attributes
    ----------
    transcription : Transcription
        The solve (`optimize_speed`'s ``transcription``; the default chain's stages on models with
        states use it).
    refinement : Transcription or None
        A re-solve started from the solve's answer (`Transcription.solve` with its speed), worth its
        cost when a lower optimum matters more than minutes; None where none helped.
    reason : str
        The measurements behind it.
    """

    transcription: Transcription
    refinement: Transcription | None
    reason: str


def recommend_transcription(model: PressModel | ModelSpec) -> TranscriptionRecommendation:
    """The transcription for a model level (see the module's notes).

    Parameters
    ----------
    model : PressModel or ModelSpec
        The model the answer is meant for (``recommend_model(...).level`` and the press's clearance
        joints name it).

    Returns
    -------
    TranscriptionRecommendation
    """
    spec = model.spec if isinstance(model, PressModel) else model
    if not isinstance(spec, ModelSpec):
        raise ValueError(f"model must be a PressModel or a ModelSpec, got {type(model).__name__}")
    if spec.rod == "rigid" and not spec.clearance:
        return TranscriptionRecommendation(Rigid(), None, "no states (ideal joints, rigid rod): the loads in closed "
                                           "form at samples, exact Hessian, seconds")
    if spec.clearance:
        return TranscriptionRecommendation(
            Collocation(), None,
            f"clearance joints ({', '.join(spec.clearance)}): collocation with the journals kept on their walls; "
            "multiple shooting (IDAS or CVODES) did not converge within its wall-time cap on any of the 75 spm "
            "scenario's map points (2-13 iterations in 600-800 s each), where collocation converged in 11-16 s")
    return TranscriptionRecommendation(
        Collocation(), MultipleShooting("idas", samples=REFINE_SAMPLES),
        "a flexible rod between ideal joints (smooth): collocation solves it (slender rod: about 100 s, 70.335 N m "
        f"verified); IDAS shooting (16 x {REFINE_SAMPLES}) started from that optimum converged in 81 iterations, "
        "464 s, 1.7 % lower (69.160 N m verified); from the rigid press's optimum shooting did not converge")


__all__ = ["REFINE_SAMPLES", "TranscriptionRecommendation", "recommend_transcription"]
