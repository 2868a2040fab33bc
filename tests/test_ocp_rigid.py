"""Rigid-stage speed optimisation (smoke size): constraints hold when re-checked independently,
the peak torque drops, and bad requests are rejected before solving."""

import numpy as np
import pytest

from pressocp import PressParams, rigid_response
from pressocp.ocp import SpeedProblem, solve_rigid
from tests.test_design import exact_height
from tests.test_rigid import _newton_euler


@pytest.fixture(scope="module")
def small():
    prob = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=6)
    return prob, solve_rigid(prob, samples=200, window_samples=40)


def test_rigid_optimum_constraints_and_improvement(small):
    prob, r = small
    assert r.success, r.status
    assert r.peak_torque < 0.95 * r.initial_peak_torque
    # ram speed re-checked with the hand-written kinematics on a dense grid
    p = prob.params
    t = np.linspace(r.t1, r.t2, 3001)
    dt = 1e-6
    v = (exact_height(p, r.speed.theta(t + dt)) - exact_height(p, r.speed.theta(t - dt))) / (2 * dt)
    assert np.max(np.abs(v - prob.ram_speed)) <= prob.tol * 1.05  # samples are 40; allow 5 % between them
    assert exact_height(p, r.speed.theta(r.t1)) == pytest.approx(0.7 * p.stroke, abs=1e-6)
    assert np.min(r.speed.omega(np.linspace(0, 1, 5001))) >= prob.omega_lower * 0.99
    # the epigraph value is the sampled peak; the dense peak is within a few per cent of it
    dense = rigid_response(p, r.speed, np.linspace(0, 1, 20001))
    assert dense.peak("torque") == pytest.approx(r.objective_value, rel=0.03)
    assert r.amplitude.shape == (6,) and r.objective_history


def test_rms_objective_runs():
    prob = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4, objective="rms_torque")
    r = solve_rigid(prob, samples=100, window_samples=20)
    assert r.success and r.objective_value > 0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(ram_speed=0.1), "ram_speed must be negative"),
        (dict(ram_speed=-0.01), "cannot deliver"),
        (dict(window=(0.3, 0.7)), "window"),
        (dict(objective="peak_power"), "objective"),
        (dict(omega_min=100.0), "omega_min"),
        (dict(ram_speed_tol=0.5), "ram_speed_tol"),
        (dict(n_harmonics=0), "n_harmonics"),
    ],
)
def test_bad_problems_rejected_before_solving(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SpeedProblem(PressParams(), **kwargs)


@pytest.fixture(scope="module")
def free_075():
    """The rigid optimum at 75 spm (10 harmonics: with 6 or 8, IPOPT finds no speed without reversal)."""
    return solve_rigid(SpeedProblem(PressParams(), period=0.8, n_harmonics=10), samples=300, window_samples=40)


@pytest.mark.parametrize("bound", [20.0, -300.0])
def test_tension_bound_holds_on_an_independent_newton_euler_solution(free_075, bound):
    """At 75 spm the rigid optimum lets the rod go into compression (the joint forces reverse, by
    about 1.7 kN); with ``min_tension`` the tension, recomputed by the hand-written Newton-Euler
    reference, stays above the bound between the samples too (20 N: no reversal; -300 N: a shallow
    one), and the peak torque pays for it."""
    p = PressParams()
    free = free_075
    prob = SpeedProblem(p, period=0.8, n_harmonics=10, min_tension=bound)
    held = solve_rigid(prob, free.speed, samples=300, window_samples=40)
    assert free.success and held.success, (free.status, held.status)
    t = np.linspace(0, 0.8, 8001)

    def tension(speed):
        ne = _newton_euler(p, *speed.evaluate(t))
        return np.minimum(ne["crank_pin_tension"], ne["wrist_pin_tension"])

    assert tension(free.speed).min() < bound  # the free optimum reverses deeper: the bound is active
    # 300 samples (2.7 ms apart): between them it may dip by a fraction of a per cent of the weight
    assert tension(held.speed).min() >= bound - 0.005 * prob.hanging_weight
    assert held.peak_torque > free.peak_torque


@pytest.mark.parametrize("value, match", [(2000.0, r"min_tension must be in \(-inf, 1502"),
                                          (float("nan"), "min_tension must be finite")])
def test_min_tension_range(value, match):
    with pytest.raises(ValueError, match=match):
        SpeedProblem(PressParams(), min_tension=value)


def test_min_tension_needs_no_process_force():
    from pressocp.params import ProcessForce

    with pytest.raises(ValueError, match="process_force"):
        SpeedProblem(PressParams(process_force=ProcessForce(force=1e4)), min_tension=10.0)
