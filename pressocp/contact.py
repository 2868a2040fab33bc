"""C1-smooth, numerically stable contact law of a journal in a bearing with radial clearance.

With the eccentricity e (bearing centre minus journal centre), the smoothed quantities are

* |e|_s = sqrt(ex^2 + ey^2 + eps^2)                       (finite derivatives at e = 0)
* delta = pos_eps(|e|_s - c),  pos_eps(x) = max(x, 0) + eps log1p(exp(-|x|/eps))   (stable softplus)
* delta_dot = (e . e_dot) / |e|_s

and the normal force magnitude (never a pull) of the bearing's law (`pressocp.laws`):

* Hunt-Crossley:  F = K delta^n  pos(1 + chi delta_dot)
* Kelvin-Voigt (Dubowsky impact pair):  F = s pos(K delta^n + c delta_dot s),
  s = delta / (delta + eps) a smooth contact indicator, so the damper acts only in contact
  and the force vanishes out of contact.

The force pushes the bearing back toward the journal: on the bearing body -F n, on the journal
+F n, with n = e / |e|_s. A viscous lubricant-film force -c_t s (e_dot . t) t along the surface
(t perpendicular to n, s the contact indicator) damps the journal's tangential motion in contact. ``delta^n`` is evaluated as ``exp(n log(delta + tiny))`` with a tiny floor
so that the derivative stays finite where the softplus underflows to exactly zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .laws import CONTACT_LAWS, softplus
from .params import Bearing

#: Floor under delta (m) in delta^n: far below any physical penetration, keeps log/sqrt finite.
TINY = 1e-30


@dataclass
class ContactForce:
    """Symbolic contact quantities of one bearing.

    Attributes
    ----------
    force : ca.SX
        Normal force magnitude F >= 0, N.
    vector_on_bearing : ca.SX
        Force on the bearing body, -F n minus the tangential film force, N (2-vector).
    penetration, penetration_rate : ca.SX
        delta (m) and d delta/dt (m/s).
    elastic_force : ca.SX
        The conservative part K delta^n, N (its power integrates to the stored contact energy).
    eccentricity_ratio : ca.SX
        |e|_s / c.
    """

    force: ca.SX
    vector_on_bearing: ca.SX
    penetration: ca.SX
    penetration_rate: ca.SX
    elastic_force: ca.SX
    eccentricity_ratio: ca.SX


def contact_force(bearing: Bearing, e: ca.SX, e_dot: ca.SX) -> ContactForce:
    """Contact force of a journal in a bearing.

    Parameters
    ----------
    bearing : Bearing
        Clearance, stiffness, exponent, law, damping and smoothing.
    e, e_dot : ca.SX
        Eccentricity (bearing centre minus journal centre, m) and its rate (m/s), 2-vectors.
    """
    c, eps = bearing.clearance, bearing.smoothing_width
    K, n = bearing.contact_stiffness, bearing.exponent
    rho = ca.sqrt(ca.sumsqr(e) + eps**2)
    normal = e / rho
    delta = softplus(rho - c, eps)
    delta_dot = ca.dot(e, e_dot) / rho
    elastic = K * ca.exp(n * ca.log(delta + TINY))
    force = CONTACT_LAWS[bearing.law].normal_force(elastic, delta, delta_dot, bearing.damping_value, eps, K, n)
    tangent = ca.vertcat(-normal[1], normal[0])
    film = bearing.tangential_damping * delta / (delta + eps) * ca.dot(e_dot, tangent)
    return ContactForce(
        force=force,
        vector_on_bearing=-force * normal - film * tangent,
        penetration=delta,
        penetration_rate=delta_dot,
        elastic_force=elastic,
        eccentricity_ratio=rho / c,
    )
