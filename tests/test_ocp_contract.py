"""The transcription contract: `Rigid`, `MultipleShooting` (IDAS and CVODES) and `Collocation` solve one
small smooth problem (T = 1 s, -0.15 m/s, 2 harmonics, both clearances with a soft contact: K/1e4) to
the same optimum, each verified by an independent periodic re-simulation of its answer on the
clearance model. The rigid transcription solves the ideal press: its answer is checked on the same
clearance model, where the journals add less than 0.5 % to its objective here."""

import numpy as np
import pytest

from pressocp import (Collocation, MultipleShooting, PressParams, Rigid, SpeedProblem, Strategy, build_model,
                      optimize_speed, simulate)
from pressocp.ocp.strategy import soft_params

PROBLEM = SpeedProblem(soft_params(PressParams(), 1e4), period=1.0, ram_speed=-0.15, n_harmonics=2)
#: How close each transcription's verified optimum must be to the others', relative.
AGREEMENT = 5e-3


def verified_peak(speed):
    """Peak torque of a speed on the clearance model: periodic IDAS re-simulation at rtol 1e-9, ram
    speed over the simulated ram's window (written out here), and contact everywhere."""
    model = build_model(PROBLEM.press, n_harmonics=2)
    sim = simulate(model, speed, periodic=True, method="idas", rtol=1e-9, n_out=20001)
    h1, h2 = PROBLEM.window_heights
    mask = (np.mod(sim.theta, 2 * np.pi) < np.pi) & (sim.ram_height <= h1) & (sim.ram_height >= h2)
    assert np.max(np.abs(sim.ram_velocity[mask] - PROBLEM.ram_speed)) <= PROBLEM.tol * (1 + 1e-6)
    return sim.peak("torque")


@pytest.fixture(scope="module")
def answers():
    strategy = Strategy("all", rigid=Rigid(samples=300), verify_rtol=1e-8)
    # the ideal press, its window widened by the clearance model's ram drop (as the chain does)
    rigid = Rigid(samples=300).solve(PROBLEM, build_model(PROBLEM.press, n_harmonics=2))
    out = {"rigid": (rigid.success, rigid.status, rigid.speed, rigid.objective)}
    for name, tr in (("collocation", Collocation(elements=200, jit=False)),
                     ("shooting_cvodes", MultipleShooting("cvodes", intervals=8, samples=25)),
                     ("shooting_idas", MultipleShooting("idas", intervals=8, samples=25))):
        r = optimize_speed(PROBLEM, transcription=tr, strategy=strategy, progress=False)
        out[name] = (r.success, r.status, r.speed, r.objective_value)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rigid", "collocation", "shooting_cvodes", "shooting_idas"])
def test_every_transcription_reaches_the_same_verified_optimum(answers, name):
    success, status, speed, reported = answers[name]
    assert success, status
    peak = verified_peak(speed)
    assert peak == pytest.approx(reported, rel=AGREEMENT)  # it reports what it delivers
    reference = verified_peak(answers["collocation"][2])
    assert peak == pytest.approx(reference, rel=AGREEMENT)
