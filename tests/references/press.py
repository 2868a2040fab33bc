"""Hand-written references on a `PressParams`: the exact ram height of the slider-crank and the
Newton-Euler inverse dynamics (`newton_euler.py`), written independently of pressocp's code."""

import numpy as np

from tests.references.newton_euler import slider_crank_newton_euler


def exact_height(p, theta):
    """Ram height above bottom dead centre, m: r cos(theta) - sqrt(l^2 - r^2 sin^2 theta) + r + l."""
    r, l = p.crank_radius, p.rod_length
    return r * np.cos(theta) - np.sqrt(l**2 - (r * np.sin(theta)) ** 2) + r + l


def newton_euler(p, th, om, al):
    """Joint forces, torque and rod tensions of the ideal press `p` at the crank motion (th, om, al)."""
    return slider_crank_newton_euler(
        p.crank_radius, p.rod_length, p.crank_mass, p.crank_com, p.crank_inertia, p.rod_mass,
        p.rod_inertia_value, p.slider_mass, p.gravity, th, om, al,
    )
