"""Reproducible studies built on the model: the seed's impact phenomenon."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .design import SpeedDesign, design_speed
from .model import build_model
from .params import PressParams
from .result import SimResult
from .rigid import rigid_response
from .simulate import simulate
from .speed import FourierSpeed

#: The impact scenario: at the default 60 strokes/min the rigid design of -0.1 m/s keeps the
#: wrist-pin force above ~490 N (no reversal, no impact); 75 strokes/min (T = 0.8 s) is the smallest
#: step of the scan 1.0/0.8/0.7/0.6/0.5 s at which it reverses.
IMPACT_PERIOD = 0.8
IMPACT_RAM_SPEED = -0.1


@dataclass
class ImpactStudy:
    """Constant versus rigid-designed speed, clearance model against rigid inverse dynamics."""

    design: SpeedDesign
    constant: SimResult
    constant_rigid: SimResult
    designed: SimResult
    designed_rigid: SimResult

    def ratios(self) -> dict[str, dict[str, float]]:
        """Peak clearance / peak rigid value for each load, for both speeds."""
        names = ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force")
        return {
            label: {n: clr.peak(n) / rig.peak(n) for n in names}
            for label, clr, rig in (("constant", self.constant, self.constant_rigid),
                                    ("designed", self.designed, self.designed_rigid))
        }


def impact_study(params: PressParams | None = None, period: float = IMPACT_PERIOD,
                 ram_speed: float = IMPACT_RAM_SPEED, rtol: float = 1e-8, method: str = "cvodes") -> ImpactStudy:
    """Periodic responses of the clearance model (rigid rod, both clearances) at constant speed and at
    the rigid-designed speed, with the rigid inverse dynamics on the same time grid."""
    p = PressParams() if params is None else params
    model = build_model(p)
    d = design_speed(p, period=period, ram_speed=ram_speed)
    const = FourierSpeed.constant(period)
    rc = simulate(model, const, periodic=True, method=method, rtol=rtol)
    rd = simulate(model, d.speed, periodic=True, method=method, rtol=rtol)
    return ImpactStudy(d, rc, rigid_response(p, const, rc.t), rd, rigid_response(p, d.speed, rd.t))
