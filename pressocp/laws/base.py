"""What a contact law gives `pressocp.contact.contact_force`: the normal force of a journal pressed
into its bearing, from the elastic force and the penetration's rate."""

from __future__ import annotations

from typing import Any, ClassVar

import casadi as ca


def softplus(x: Any, eps: float) -> Any:
    """Stable smooth positive part: max(x, 0) + eps log1p(exp(-|x|/eps)); C-infinity, never overflows."""
    return ca.fmax(x, 0) + eps * ca.log1p(ca.exp(-ca.fabs(x) / eps))


class ContactLaw:
    """A normal-force law F >= 0 (never a pull). A new law is one module in `pressocp.laws` with a
    subclass, and one line in `pressocp.laws.CONTACT_LAWS`.

    Attributes
    ----------
    name : str
        Its value of `pressocp.params.Bearing.law`.
    damping_unit : str
        The unit of `pressocp.params.Bearing.damping` under this law.
    """

    name: ClassVar[str]
    damping_unit: ClassVar[str]

    def default_damping(self, stiffness: float, exponent: float) -> float:
        """The damping when a bearing gives none, for its stiffness K (N/m^n) and exponent n."""
        raise NotImplementedError

    def normal_force(self, elastic: Any, delta: Any, delta_dot: Any, damping: Any, eps: float,
                     stiffness: Any, exponent: Any) -> Any:
        """F (N) from the elastic force K delta^n (N), the smoothed penetration delta (m), its rate
        (m/s), the damping, the smoothing width eps (m), K and n (numbers or CasADi symbols)."""
        raise NotImplementedError
