"""What a simulation reports (`settled_response`): the periodic response where there is one to find,
else, when a cheap screen shows the response impacts and does not settle, a cycle from rest that says
so, instead of a periodic search that cannot succeed (over 28 minutes on the flexible rod)."""

import numpy as np
import pytest

from pressocp import PressParams, Scenario, SpeedProblem, build_model, design_speed
from pressocp.simulate import Integrator, simulate
from pressocp.speed import FourierSpeed
from pressocp.verify import is_periodic, rigid_reference, settled_response, verify_speed


def constant(T: float) -> tuple[SpeedProblem, FourierSpeed]:
    return (SpeedProblem(PressParams(), period=T, ram_speed=-0.5, n_harmonics=4),
            FourierSpeed(T, np.zeros(4), np.zeros(4)))


def test_a_response_that_impacts_and_does_not_settle_is_reported_as_a_cycle_from_rest():
    """At 200 strokes/min and constant crank speed the journals hit their walls every cycle and the
    state at the end of each cycle keeps moving: checked here at rtol 1e-9 over 8 cycles, each end
    more than 1e-2 (scaled) from the one before."""
    problem, speed = constant(0.3)
    model = build_model(problem.press, n_harmonics=4)
    ends = simulate(model, speed, cycles=8, integrator=Integrator("cvodes", 1e-9), n_out=9, work=False).states
    change = np.max(np.abs(np.diff(ends / model.x_scale[:, None], axis=1)), axis=0)
    assert np.all(change[2:] > 1e-2)
    ideal = rigid_reference(problem, speed)
    sim = settled_response(problem, model, speed, 1e-9, problem.objective_value(ideal))
    reason = is_periodic(sim)
    assert reason is not True and reason.startswith("not searched")
    assert "cycle 6 from rest" in reason and sim.stats["periodic"]["cycle"] == 6
    # the reported cycle impacts: its torque peak well above the ideal press's
    assert sim.peak("torque") > 1.1 * ideal.peak("torque")
    assert sim.t[-1] - sim.t[0] == pytest.approx(problem.period, rel=1e-12)


def test_a_response_that_settles_is_the_periodic_one_as_verify_speed_finds_it():
    """Searched from the screen's state, not from rest: the same periodic response to the search's
    tolerance (1e-4 of the scaled state), the peak torque to 1e-4 (3e-5 apart here: the journals'
    lightly damped motion stays within that tolerance, not below it)."""
    problem, speed = constant(1.0)
    model = build_model(problem.press, n_harmonics=4)
    sim = settled_response(problem, model, speed)  # rtol 1e-9 and the ideal press's objective by default
    assert is_periodic(sim) is True
    ref = verify_speed(model, speed, 1e-9)
    assert np.max(np.abs(sim.states - ref.states) / np.asarray(model.x_scale)[:, None]) <= 1e-4
    assert sim.peak("torque") == pytest.approx(ref.peak("torque"), rel=1e-4)


def test_an_impacting_periodic_response_is_searched_from_rest_as_before():
    """press75's rigid design impacts (4 x the ideal press's torque) and has a periodic response; its
    peaks depend on where the search starts, so it starts from rest, as `verify_speed` does."""
    scenario = Scenario.load("press75")
    problem, model = scenario.problem, scenario.build_model()
    speed = design_speed(problem).speed
    ideal = rigid_reference(problem, speed)
    sim = settled_response(problem, model, speed, 1e-9, problem.objective_value(ideal))
    assert is_periodic(sim) is True and sim.peak("torque") > 3 * ideal.peak("torque")
    np.testing.assert_array_equal(sim.states, verify_speed(model, speed, 1e-9).states)
