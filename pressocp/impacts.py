"""The impact phenomenon of the source paper: a constant and a rigid-designed crank speed on a model
with clearance, each against the rigid inverse dynamics on the same time grid (the ``impacts`` job
and sweep task)."""

from __future__ import annotations

from dataclasses import dataclass

from .design import SpeedDesign, design_speed
from .model import ModelSpec
from .series import PEAK_SERIES
from .verify import is_periodic, settled_response
from .params import PressParams
from .problem import SpeedProblem
from .result import SimResult
from .simulate import for_repeated_use
from .mechanism.ideal import ideal_response
from .speed import FourierSpeed

#: The impact scenario of the source paper's Figs. 6 and 9: at 60 strokes/min the rigid design of
#: -0.1 m/s keeps the wrist-pin force above ~490 N (no reversal, no impact); 75 strokes/min (T = 0.8 s)
#: is the smallest step of the scan 1.0/0.8/0.7/0.6/0.5 s at which it reverses.
IMPACT_PERIOD = 0.8
IMPACT_RAM_SPEED = -0.1


@dataclass
class ImpactStudy:
    """Constant versus rigid-designed speed, a model with clearance against rigid inverse dynamics."""

    design: SpeedDesign
    constant: SimResult
    constant_rigid: SimResult
    designed: SimResult
    designed_rigid: SimResult

    def not_periodic(self) -> dict[str, str]:
        """The responses (``constant``, ``designed``) that are not periodic steady states, each with
        the reason (`pressocp.verify.is_periodic`); empty when both are."""
        found = {"constant": is_periodic(self.constant), "designed": is_periodic(self.designed)}
        return {k: v for k, v in found.items() if v is not True}

    def ratios(self) -> dict[str, dict[str, float]]:
        """Peak model value / peak rigid value for each load, for both speeds."""
        return {
            label: {n: clr.peak(n) / rig.peak(n) for n in PEAK_SERIES}
            for label, clr, rig in (("constant", self.constant, self.constant_rigid),
                                    ("designed", self.designed, self.designed_rigid))
        }


def impact_study(problem: SpeedProblem | None = None, model: ModelSpec | None = None,
                 rtol: float = 1e-8) -> ImpactStudy:
    """Responses of `model` (default: rigid rod, both clearances) at constant speed and at the rigid
    design of `problem` (default: the default press at 75 strokes/min, -0.1 m/s over h/H 0.7 -> 0.3),
    with the rigid inverse dynamics on the same time grid.

    The responses are periodic steady states (CVODES at `rtol`) when one is found, else the 6th cycle
    from rest (``stats["periodic"]`` says why; `settled_response`: no search where a screen shows the
    response impacts and does not settle)."""
    problem = SpeedProblem(PressParams(), period=IMPACT_PERIOD, ram_speed=IMPACT_RAM_SPEED) \
        if problem is None else problem
    # compiled: two periodic searches of up to 12 cycles each (through impacts they do not settle);
    # the default scene's study took 28 s interpreted and 18 s compiled (2026-11-29)
    m = for_repeated_use((ModelSpec(mechanism=problem.mechanism) if model is None else model)
                         .build(problem.press, problem.n_harmonics))
    d = design_speed(problem)
    const = FourierSpeed.constant(problem.period)
    rc, rd = (settled_response(problem, m, speed, rtol) for speed in (const, d.speed))
    return ImpactStudy(d, rc, ideal_response(problem.press, problem.mechanism, const, rc.t), rd,
                       ideal_response(problem.press, problem.mechanism, d.speed, rd.t))
