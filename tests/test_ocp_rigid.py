"""`Rigid` transcription (smoke size): constraints hold when re-checked with hand-written references,
the objective drops, the pin-force cap and the tension bound hold between the samples, and bad
requests are rejected before solving."""

from dataclasses import replace

import numpy as np
import pytest

from pressocp import PressParams, Rigid, SpeedProblem, WarmStart, build_model, rigid_response
from pressocp.params import ProcessForce
from tests.references.press import exact_height, newton_euler


@pytest.fixture(scope="module")
def small():
    prob = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=6)
    return prob, Rigid(samples=200, window_samples=40).solve(prob)


def test_rigid_optimum_constraints_and_improvement(small):
    prob, r = small
    assert r.success, r.status
    p = prob.press
    t_all = np.linspace(0, 1, 20001)
    from pressocp.design import design_speed

    initial = rigid_response(p, design_speed(prob).speed, t_all).peak("torque")
    dense = rigid_response(p, r.speed, t_all)
    assert dense.peak("torque") < 0.95 * initial
    # ram speed re-checked with the hand-written kinematics on a dense grid
    t2 = r.t1 + prob.window_duration
    t = np.linspace(r.t1, t2, 3001)
    dt = 1e-6
    v = (exact_height(p, r.speed.theta(t + dt)) - exact_height(p, r.speed.theta(t - dt))) / (2 * dt)
    assert np.max(np.abs(v - prob.ram_speed)) <= prob.tol * 1.05  # samples are 40; allow 5 % between them
    assert exact_height(p, r.speed.theta(r.t1)) == pytest.approx(0.7 * p.stroke, abs=1e-6)
    assert np.min(r.speed.omega(np.linspace(0, 1, 5001))) >= prob.omega_lower * 0.99
    # the reported value is the sampled peak; the dense peak is within a few per cent of it
    assert dense.peak("torque") == pytest.approx(r.objective, rel=0.03)
    assert r.speed.n_harmonics == 6 and r.history and r.history[-1] == pytest.approx(r.objective, rel=1e-6)


def test_a_warm_start_with_multipliers_stays_and_follows_moved_bounds(small):
    """From its own optimum with its multipliers the same NLP is solved again in a few iterations
    at the same objective; holding more of the ram-speed tolerance (backoff 0.99 instead of 0.9)
    the warm start reaches an objective no higher, with the window still held on a dense grid of
    the hand-written kinematics; a point of another grid is not used."""
    prob, r = small
    assert r.nlp is not None and r.nlp.grid == ("rigid", 200, 40)
    settings = Rigid(samples=200, window_samples=40)
    again = settings.solve(prob, start=WarmStart(r.speed, point=r.nlp))
    assert again.success and again.details["warm"] and again.iterations <= 10
    assert again.objective == pytest.approx(r.objective, rel=1e-6)
    moved = Rigid(samples=200, window_samples=40, backoff=0.99).solve(prob, start=WarmStart(r.speed, point=r.nlp))
    assert moved.success and moved.details["warm"] and moved.objective <= r.objective * (1 + 1e-9)
    p = prob.press
    t = np.linspace(moved.t1, moved.t1 + prob.window_duration, 3001)
    dt = 1e-6
    v = (exact_height(p, moved.speed.theta(t + dt)) - exact_height(p, moved.speed.theta(t - dt))) / (2 * dt)
    assert np.max(np.abs(v - prob.ram_speed)) <= prob.tol * 1.05
    other = Rigid(samples=300, window_samples=40).solve(prob, start=WarmStart(r.speed, point=r.nlp))
    assert not other.details["warm"]


def test_relaxed_is_the_same_grid_holding_more_tolerance(small):
    """`Rigid.relaxed`: the stage's own grid at backoff 0.99 with an iteration cap; nothing for a
    stage that held that much already, has no NLP point, or comes from another grid."""
    _, r = small
    settings = Rigid(samples=200, window_samples=40)
    loose = settings.relaxed(r)
    assert loose.grid() == r.nlp.grid and loose.backoff == 0.99 and "ipopt.max_iter" in loose.ipopt
    assert loose.relaxed(replace(r, details={**r.details, "backoff": 0.99})) is None
    assert settings.relaxed(replace(r, nlp=None)) is None
    assert Rigid(samples=300, window_samples=40).relaxed(r) is None


def test_window_widened_by_the_ram_drop_of_a_clearance_model():
    """For a clearance model the rigid window starts the model's ram drop (the two clearances) higher
    and is that much longer, so the model's lower-hanging ram is covered from its window entry on."""
    prob = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)
    model = build_model(prob.press, n_harmonics=4)
    assert model.ram_drop == pytest.approx(2e-4)
    r = Rigid(samples=200, window_samples=40).solve(prob, model)
    assert r.success
    h1 = exact_height(prob.press, r.speed.theta(r.t1))
    assert h1 == pytest.approx(0.7 * prob.press.stroke + 2e-4, abs=1e-6)
    t = np.linspace(r.t1, r.t1 + prob.window_duration + 2e-4 / 0.15, 2001)
    v = (exact_height(prob.press, r.speed.theta(t + 1e-6)) - exact_height(prob.press, r.speed.theta(t - 1e-6))) / 2e-6
    assert np.max(np.abs(v - prob.ram_speed)) <= prob.tol * 1.05


def test_rms_objective_runs():
    prob = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4, objective="rms_torque")
    r = Rigid(samples=100, window_samples=20).solve(prob)
    assert r.success and r.objective > 0
    dense = rigid_response(prob.press, r.speed, np.linspace(0, 1, 100, endpoint=False))
    assert r.objective == pytest.approx(np.sqrt(np.mean(dense.torque**2)), rel=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(ram_speed=0.1), "ram_speed must be negative"),
        (dict(ram_speed=-0.01), "cannot deliver"),
        (dict(window=(0.3, 0.7)), "window"),
        (dict(objective="peak_jerk"), "objective"),
        (dict(omega_min=100.0), "omega_min"),
        (dict(ram_speed_tol=0.5), "ram_speed_tol"),
        (dict(n_harmonics=0), "n_harmonics"),
        (dict(max_pin_force=100.0), r"max_pin_force must be in \(1502"),
    ],
)
def test_bad_problems_rejected_before_solving(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SpeedProblem(PressParams(), **kwargs)


@pytest.mark.parametrize("kwargs, match", [(dict(samples=10), "samples"), (dict(backoff=0.0), "backoff")])
def test_bad_settings_rejected(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Rigid(**kwargs)


@pytest.fixture(scope="module")
def free_075():
    """The rigid optimum at 75 spm (10 harmonics: with 6 or 8, IPOPT finds no speed without reversal)."""
    prob = SpeedProblem(PressParams(), period=0.8, n_harmonics=10)
    return prob, Rigid(samples=300, window_samples=40).solve(prob)


@pytest.mark.parametrize("bound", [20.0, -300.0])
def test_tension_bound_holds_on_an_independent_newton_euler_solution(free_075, bound):
    """At 75 spm the rigid optimum lets the rod go into compression (the joint forces reverse); with
    ``min_tension`` the tension, recomputed by the hand-written Newton-Euler reference, stays above
    the bound between the samples too, and the objective pays for it."""
    prob, free = free_075
    p = prob.press
    held = Rigid(samples=300, window_samples=40).solve(prob.replace(min_tension=bound), start=WarmStart(free.speed))
    assert free.success and held.success, (free.status, held.status)
    t = np.linspace(0, 0.8, 8001)

    def tension(speed):
        ne = newton_euler(p, *speed.evaluate(t))
        return np.minimum(ne["crank_pin_tension"], ne["wrist_pin_tension"])

    assert tension(free.speed).min() < bound  # the free optimum reverses deeper: the bound is active
    # 300 samples (2.7 ms apart): between them it may dip by a fraction of a per cent of the weight
    assert tension(held.speed).min() >= bound - 0.005 * prob.hanging_weight
    assert held.objective > free.objective


def test_pin_force_cap_holds_on_an_independent_newton_euler_solution(free_075):
    """`max_pin_force` below the free optimum's peak pin force: the capped optimum's pin forces,
    recomputed by the Newton-Euler reference on a dense grid, stay at the cap (to the sampling),
    and the peak torque rises."""
    prob, free = free_075
    p = prob.press
    t = np.linspace(0, 0.8, 8001)

    def pin_peak(speed):
        ne = newton_euler(p, *speed.evaluate(t))
        return max(ne["crank_pin_force"].max(), ne["wrist_pin_force"].max())

    cap = 0.9 * pin_peak(free.speed)
    capped = Rigid(samples=300, window_samples=40).solve(prob.replace(max_pin_force=cap), start=WarmStart(free.speed))
    assert capped.success, capped.status
    assert pin_peak(capped.speed) <= cap * 1.01
    assert capped.objective > free.objective


def test_min_tension_range():
    with pytest.raises(ValueError, match=r"min_tension must be in \(-inf, 1502"):
        SpeedProblem(PressParams(), min_tension=2000.0)
    with pytest.raises(ValueError, match="min_tension must be finite"):
        SpeedProblem(PressParams(), min_tension=float("nan"))
    with pytest.raises(ValueError, match=r"min_tension must be in \(-inf, -8497.7\) N .*less counterbalance and process "
                                         r"force"):  # 1502.3 N hanging less 10 kN forming
        SpeedProblem(PressParams(process_force=ProcessForce(force=1e4)), min_tension=10.0)


def test_an_acceptable_rigid_answer_is_continued_to_the_full_tolerance(small):
    """`Strategy.rigid_tight`: a rigid stage stopped at IPOPT's acceptable level (forced here by loose
    acceptable tolerances) is continued from its primal-dual point to the full tolerance, to the
    optimum of an independent cold solve at that tolerance (the fixture), in one record of both."""
    from pressocp.ocp.strategy import Strategy

    prob, full = small
    loose = {"ipopt.acceptable_tol": 1e2, "ipopt.acceptable_iter": 1, "ipopt.acceptable_constr_viol_tol": 1e2,
             "ipopt.acceptable_dual_inf_tol": 1e10, "ipopt.acceptable_compl_inf_tol": 1e2}
    early = Rigid(samples=200, window_samples=40, ipopt=loose).solve(prob)
    assert early.status == "Solved_To_Acceptable_Level" and early.iterations < full.iterations
    strategy = Strategy(rigid=Rigid(samples=200, window_samples=40))
    tight = strategy.rigid_tight(prob, None, early, False)
    assert tight.status == "Solve_Succeeded"
    assert tight.iterations > early.iterations and tight.details["acceptable_iterations"] == early.iterations
    assert len(tight.history) == tight.iterations + 2  # each solve logs its start and every iteration
    assert tight.objective == pytest.approx(full.objective, rel=1e-5)
    assert abs(early.objective - full.objective) > 1e-4 * full.objective  # the early stop was far from it
    assert strategy.rigid_tight(prob, None, full, False) is full  # a converged stage stands as it is
