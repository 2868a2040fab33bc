"""Kelvin-Voigt (Dubowsky's impact pair): F = s pos(K delta^n + c delta_dot s), c in N s/m."""

from __future__ import annotations

from typing import Any

from .base import ContactLaw, softplus
from .hunt_crossley import DEFAULT_HYSTERESIS

#: Penetration (m) at which the default damping force equals the default Hunt-Crossley one.
REFERENCE_PENETRATION = 1e-6


class KelvinVoigt(ContactLaw):
    """F = s pos(K delta^n + c delta_dot s), s = delta / (delta + eps) a smooth contact indicator, so
    that the damper acts only in contact and the force vanishes out of it (Dubowsky and Freudenstein,
    J. Eng. Ind. 93, 1971)."""

    name = "kelvin-voigt"
    damping_unit = "N s/m"

    def default_damping(self, stiffness: float, exponent: float) -> float:
        """The c whose force equals the default Hunt-Crossley damping force at a penetration of 1 um."""
        return DEFAULT_HYSTERESIS * stiffness * REFERENCE_PENETRATION**exponent

    def normal_force(self, elastic: Any, delta: Any, delta_dot: Any, damping: Any, eps: float,
                     stiffness: Any, exponent: Any) -> Any:
        indicator = delta / (delta + eps)
        return indicator * softplus(elastic + damping * delta_dot * indicator, stiffness * eps**exponent)
