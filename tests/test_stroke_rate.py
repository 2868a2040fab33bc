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
