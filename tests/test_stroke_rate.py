"""The highest stroke rate a drive allows: the search's bracket on the ideal press (seconds per
rate), and bad requests. The rate on the clearance model is in benchmarks/bench_stroke_rate.py."""

import numpy as np
import pytest

import pressocp as po
from pressocp.stroke_rate import try_rate

FAST = po.Strategy(rigid=po.Rigid(samples=200, window_samples=40, jit=False))
PRESS75 = po.Scenario.load("press75")


def problem(peak_torque: float) -> po.SpeedProblem:
    drive = po.Drive(gear_ratio=10.0, peak_torque=peak_torque, continuous_torque=0.7 * peak_torque,
                     max_speed=400.0, gear_efficiency=0.95, motor_inertia=8e-4)
    return PRESS75.problem.replace(n_harmonics=8, period=60.0 / 66.0, drive=drive)


@pytest.mark.slow  # 29 s (a search of optimised rates)
def test_the_rate_found_holds_and_the_next_step_fails():
    ideal = po.build_model(PRESS75.press, clearance=(), n_harmonics=8)
    search = po.RateSearch(tolerance_spm=2.0, strategy=FAST)
    found = po.max_stroke_rate(problem(11.0), ideal, search)
    assert found.rate_spm is not None and found.best.feasible
    assert found.above.rate_spm == pytest.approx(1.02 * found.rate_spm) and not found.above.feasible
    assert "peak_torque_margin" in found.above.failed  # this motor's peak curve limits it (RMS: 9 N m)
    # the bracket: a rate tried above the found one and within the tolerance failed
    failed = [t.rate_spm for t in found.trials if not t.feasible and t.rate_spm > found.rate_spm]
    assert min(failed) - found.rate_spm <= 2.0


def test_an_invalid_rate_is_a_failed_trial_not_a_crash():
    trial = try_rate(problem(9.0), None, 400.0)
    assert not trial.feasible and "problem" in trial.failed and np.isnan(trial.peak_torque)


def test_the_search_needs_a_drive():
    with pytest.raises(ValueError, match="problem.drive must be a Drive"):
        po.max_stroke_rate(PRESS75.problem)


@pytest.mark.parametrize("kw, match", [(dict(tolerance_spm=0.0), "tolerance_spm"), (dict(step=1.0), "step"),
                                       (dict(check_step=0.6), "check_step"), (dict(max_trials=1), "max_trials")])
def test_bad_search_settings_name_the_field(kw, match):
    with pytest.raises(ValueError, match=match):
        po.RateSearch(**kw)


def test_an_optimum_not_verified_fails_its_rate_saying_why(monkeypatch):
    """A rate whose optimum does not verify fails, and the trial says why from the re-simulation, not
    IPOPT's success status (the optimum's periodic search is made to fail here)."""
    import dataclasses

    from pressocp import stroke_rate

    real = stroke_rate.optimize_speed

    def not_periodic(*args, **kwargs):
        r = real(*args, **kwargs)
        r.simulation.stats["periodic"] = {"found": False, "reason": "periodic steady state not found: test"}
        return dataclasses.replace(r, periodic="periodic steady state not found: test")

    monkeypatch.setattr(stroke_rate, "optimize_speed", not_periodic)
    ideal = po.build_model(PRESS75.press, clearance=(), n_harmonics=8)
    trial = try_rate(problem(30.0), ideal, 66.0, FAST)
    assert not trial.feasible and trial.result.success
    assert trial.failed["verified"] == "its re-simulation is not periodic (periodic steady state not found: test)"


# press60 on the ideal press with a large rotor (J i^2 = 0.4 kg m^2, close to the crank's own inertia):
# its minimum-crank-torque optimum is flat in the rate (76.15 N m, lifting the ram), so the motor's
# RMS torque at that optimum is whatever the optimum happens to be, and it misses this motor's
# continuous rating at 52 strokes/min, where a speed that meets every rating exists.
PRESS60 = po.Scenario.load("press60")
BIG_ROTOR = po.Drive(gear_ratio=10.0, peak_torque=12.0, continuous_torque=6.0, max_speed=314.0, power_limit=2000.0,
                     gear_efficiency=0.95, motor_inertia=4e-3)


def motor_by_hand(result: po.OcpResult, drive: po.Drive) -> tuple[float, float]:
    """(RMS motor torque, N m; the least share of the peak curve left, -) over the re-simulated cycle,
    written from the gear's torque balance here, apart from `pressocp.drive`: the motor gives crank
    torque / (i eta) while it drives and crank torque x eta / i while the crank drives it back, plus
    J i alpha for its rotor."""
    sim, speed = result.simulation, result.speed
    keep = sim.t - sim.t[0] <= speed.period * (1 + 1e-12)
    t, tau = sim.t[keep], sim.torque[keep]
    _, omega, alpha = speed.evaluate(t)
    i, eta = drive.gear_ratio, drive.gear_efficiency
    motor = np.where(tau >= 0, tau / (i * eta), tau * eta / i) + drive.motor_inertia * i * alpha
    rms = np.sqrt(np.trapezoid(motor**2, t) / (t[-1] - t[0]))
    envelope = np.minimum(drive.peak_torque, drive.power_limit / np.abs(omega * i))
    return float(rms), float(np.min(envelope - np.abs(motor)) / drive.peak_torque)


def test_a_rate_the_drive_runs_holds_when_its_limits_are_constraints():
    problem = PRESS60.problem.replace(n_harmonics=8, drive=BIG_ROTOR)
    ideal = po.build_model(PRESS60.press, clearance=(), n_harmonics=8)
    unconstrained = try_rate(problem, ideal, 52.0, FAST, hold_limits=False)
    assert not unconstrained.feasible and set(unconstrained.failed) == {"rms_margin"}
    assert motor_by_hand(unconstrained.result, BIG_ROTOR)[0] > 6.0  # the defect: this speed's RMS is over
    trial = try_rate(problem, ideal, 52.0, FAST)
    assert trial.feasible and trial.held and set(trial.unconstrained_failed) == {"rms_margin"}
    assert trial.result.verified and trial.optimisations == 2
    rms, peak_share = motor_by_hand(trial.result, BIG_ROTOR)
    assert rms <= 6.0 and peak_share >= 0.0
    assert trial.peak_torque == pytest.approx(76.15, abs=0.2)  # the crank's floor, near the flat optimum


def test_a_rate_the_ideal_press_cannot_run_fails_on_the_constrained_try_naming_the_drive():
    problem = PRESS60.problem.replace(n_harmonics=8, drive=BIG_ROTOR)
    ideal = po.build_model(PRESS60.press, clearance=(), n_harmonics=8)
    trial = try_rate(problem, ideal, 70.0, FAST)
    assert not trial.feasible and trial.held and "peak_torque_margin" in trial.unconstrained_failed
    assert "drive is too weak" in trial.failed["verified"]


def test_a_check_above_that_holds_moves_the_rate_up_until_one_fails(monkeypatch):
    """The bracket's feasible end is checked check_step above; when that holds (a verdict not monotone
    in the rate, or a bracket left at its tolerance), the check is repeated above it, so the rate
    reported has a failing rate check_step above it. The optimisations are replaced by a verdict."""
    from pressocp import stroke_rate

    limit = 57.5
    monkeypatch.setattr(stroke_rate, "try_rate", lambda problem, model, rate, *a: stroke_rate.RateTrial(
        rate, rate <= limit, {} if rate <= limit else {"rms_margin": -0.01}))
    problem = PRESS60.problem.replace(drive=BIG_ROTOR)
    found = po.max_stroke_rate(problem, None, po.RateSearch(tolerance_spm=2.0, max_trials=8))
    assert found.rate_spm <= limit < found.above.rate_spm
    assert found.above.rate_spm == pytest.approx(1.02 * found.rate_spm) and not found.above.feasible
    assert found.rate_spm > limit / 1.02 - 2.0
