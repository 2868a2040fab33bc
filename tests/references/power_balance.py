"""The motor torque of an ideal press at constant input speed from its energy alone: tau = dE/dtheta
(the motor's power tau omega is the rate of the total energy E = T + V when nothing dissipates)."""

import math

import numpy as np

from pressocp import FourierSpeed


def assert_torque_is_power_balance(model, period: float, energy, rel: float = 1e-5) -> None:
    """The torque of `model` (ideal joints) at constant input speed 2 pi / `period` equals the central
    difference (step 1e-3 rad) of `energy(theta)`, the press's total energy at input angles theta
    (J, an independent sum over its bodies), to `rel` of the largest torque."""
    w = 2 * math.pi / period
    t = np.linspace(0.0, period, 41)
    H = 1e-3
    reference = (energy(w * t + H) - energy(w * t - H)) / (2 * H)
    torque = model.ideal_series(FourierSpeed.constant(period, n_harmonics=model.n_harmonics), t)["torque"]
    assert np.max(np.abs(torque - reference)) <= rel * np.max(np.abs(reference))
