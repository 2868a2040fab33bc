"""Which way the rod's load can stay: the static tension with a counterbalance and a process force,
the no-reversal bounds on either side, the warning when the load must reverse, and the
counterbalance's force optimised with the speed on the ideal press.

References: the static tensions are the hanging weight less the forces, by hand; the optimised
force is checked to be a local minimum by solves with the force fixed on either side of it."""

import warnings

import pytest

import pressocp as po
from pressocp.ocp.optimize import checked_request
from pressocp.ocp.rigid_stage import Rigid
from pressocp.ocp.stage import WarmStart

PRESS75 = po.Scenario.load("press75")
W = (150.0 + 3.14) * 9.81  # hanging weight of ram and rod, N


def problem(counterbalance=po.Counterbalance(), process_force=po.ProcessForce(), **kw):
    press = PRESS75.press.replace(counterbalance=counterbalance, process_force=process_force)
    return PRESS75.problem.replace(press=press, **kw)


def test_static_tension_by_hand():
    assert problem().static_tension == pytest.approx((W, W))
    gas = po.Counterbalance(force=3000.0, gas_length=0.5, exponent=1.0)  # 3000 / (1 + 0.1 / 0.5) at the top
    assert problem(gas).static_tension == pytest.approx((W - 3000.0, W - 2500.0))
    drawing = po.ProcessForce(heights=(0.03, 0.05, 0.07), forces=(0.0, 1000.0, 0.0))
    assert problem(process_force=drawing).static_tension == pytest.approx((W - 1000.0, W))


def test_the_side_the_load_can_keep_and_its_bounds():
    p = problem()
    assert p.reversal_side() == "tension"
    assert p.without_reversal(0.05).min_tension == pytest.approx(0.05 * W)
    lifted = problem(po.Counterbalance(force=3000.0))
    assert lifted.reversal_side() == "compression"
    held = lifted.without_reversal(0.05)
    assert held.max_tension == pytest.approx(0.05 * (W - 3000.0)) and held.min_tension is None
    forming = problem(process_force=po.ProcessForce(heights=(0.03, 0.07), forces=(20e3, 20e3)))
    assert forming.reversal_side() is None and forming.without_reversal(0.05) is None
    assert problem(process_force=po.ProcessForce(heights=(0.03, 0.07), forces=(20e3, 20e3)),
                   counterbalance=po.Counterbalance(force=2000.0)).reversal_side() == "compression"


@pytest.mark.slow  # 17-34 s (the auto chain's models built); the bounds by default: the tests above
def test_a_reversal_no_speed_avoids_is_said_before_any_solve():
    forming = problem(process_force=po.ProcessForce(heights=(0.03, 0.07), forces=(20e3, 20e3)))
    with pytest.warns(po.ReversalWarning, match=r"process force reaches 20 kN.*press.counterbalance.force of about"):
        checked_request(forming, None, None, "auto", None)
    with warnings.catch_warnings():
        warnings.simplefilter("error", po.ReversalWarning)
        checked_request(problem(), None, None, "auto", None)
        # a counterbalance the optimiser may raise above the hanging weight: nothing to say
        checked_request(forming.replace(counterbalance_range=(0.0, 4000.0)), None, None, "auto", None)


def test_tension_bounds_beyond_the_static_load_name_it():
    with pytest.raises(ValueError, match=r"min_tension must be in \(-inf, 502.3.*least static tension"):
        problem(process_force=po.ProcessForce(heights=(0.03, 0.05, 0.07), forces=(0.0, 1000.0, 0.0)),
                min_tension=600.0)
    with pytest.raises(ValueError, match=r"max_tension must be in \(-1497.*greatest static tension"):
        problem(po.Counterbalance(force=3000.0), max_tension=-2000.0)


@pytest.mark.parametrize("value, match", [((5.0, 1.0), r"counterbalance_range\[1\] must be in \(5"),
                                          ((-1.0, 5.0), r"counterbalance_range\[0\] must be"),
                                          ((1.0,), "two numbers")])
def test_bad_counterbalance_range_names_it(value, match):
    with pytest.raises(ValueError, match=match):
        problem(counterbalance_range=value)


def test_counterbalance_range_round_trips_through_a_scenario():
    sc = PRESS75.with_overrides({"problem.counterbalance_range": [0.0, 8000.0]})
    assert sc.problem.counterbalance_range == (0.0, 8000.0)
    assert po.Scenario.from_toml(sc.to_toml()).problem == sc.problem
    with pytest.raises(po.ScenarioError, match=r"problem.counterbalance_range must be a list of two numbers"):
        PRESS75.with_overrides({"problem.counterbalance_range": 5.0})


@pytest.mark.slow  # 13 s (three solves)
def test_the_optimised_counterbalance_is_a_local_minimum():
    """The force chosen with the speed (rod in compression) against solves with the force fixed 3 %
    below and above it, each warm-started from the joint answer."""
    held = problem(po.Counterbalance(force=8000.0), max_tension=-0.05 * W)
    rigid = Rigid(samples=300, window_samples=50, jit=False)
    joint = rigid.solve(held.replace(counterbalance_range=(0.0, 8000.0)), name="counterbalance")
    assert joint.success
    force = joint.details["free"]["counterbalance.force"]
    assert 0.0 < force < 8000.0
    for f in (0.97 * force, 1.03 * force):
        fixed = rigid.solve(held.replace(press=held.press.with_value("counterbalance.force", f)),
                            start=WarmStart(joint.speed))
        assert fixed.success and fixed.objective > joint.objective + 1e-3, f
