"""The objective registry: every objective's value on a response against a hand computation, and a
registered objective (the motor's peak power |tau omega|) optimised by the rigid transcription,
checked with the hand-written Newton-Euler reference."""

import numpy as np
import pytest

from pressocp import OBJECTIVES, PressParams, Rigid, SpeedProblem, design_speed, rigid_response
from pressocp.objectives import Objective, register
from tests.references.press import newton_euler


def test_values_on_a_response():
    p = PressParams()
    speed = design_speed(SpeedProblem(p)).speed
    r = rigid_response(p, speed, np.linspace(0, 1, 4001))
    ne = newton_euler(p, *speed.evaluate(r.t))
    expected = {
        "peak_torque": np.max(np.abs(ne["torque"])),
        "peak_slider_normal_force": np.max(np.abs(ne["slider_normal_force"])),
        "peak_pin_force": max(ne["crank_pin_force"].max(), ne["wrist_pin_force"].max()),
        "rms_torque": np.sqrt(np.mean(ne["torque"] ** 2)),
        "peak_power": np.max(np.abs(ne["torque"] * speed.omega(r.t))),
    }
    for name, value in expected.items():
        assert OBJECTIVES[name].value(r) == pytest.approx(value, rel=1e-6), name


def test_registry_rejects_duplicates_and_unknown_kinds():
    with pytest.raises(ValueError, match="registered already"):
        register(Objective("peak_torque", ("torque",), lambda y: [y["torque"]], "N m"))
    with pytest.raises(ValueError, match="kind"):
        register(Objective("median_torque", ("torque",), lambda y: [y["torque"]], "N m", kind="median"))


@pytest.mark.slow  # 15 s
def test_peak_power_optimum():
    """peak |tau omega| minimised on the rigid press: lower than the kinematic design's, equal to the
    reported value (Newton-Euler torque times the crank speed, 20 000 samples), and not the same speed
    as the torque optimum."""
    p = PressParams()
    problem = SpeedProblem(p, period=1.0, ram_speed=-0.15, n_harmonics=6, objective="peak_power")
    r = Rigid(samples=400, window_samples=60).solve(problem)
    assert r.success, r.status
    t = np.linspace(0, 1, 20001)

    def power(speed):
        return np.max(np.abs(newton_euler(p, *speed.evaluate(t))["torque"] * speed.omega(t)))

    assert power(r.speed) < 0.9 * power(design_speed(problem).speed)
    assert power(r.speed) == pytest.approx(r.objective, rel=0.02)
    torque_opt = Rigid(samples=400, window_samples=60).solve(problem.replace(objective="peak_torque"))
    assert power(r.speed) < power(torque_opt.speed)
