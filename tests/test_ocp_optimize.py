"""`optimize_speed` on the seed's impact case (default press, T = 0.8 s): the rigid-designed speed
impacts in the clearance bearings; the optimum designs the impact out. Everything is re-checked
outside the optimiser: the loads on the clearance model (a separate simulation), the rod tension
with the hand-written Newton-Euler reference, the ram speed on a dense grid."""

import numpy as np
import pytest

from pressocp import PressParams
from pressocp.model import build_model
from pressocp.ocp import optimize_speed
from pressocp.simulate import simulate
from tests.test_rigid import _newton_euler

T = 0.8


@pytest.fixture(scope="module")
def seed():
    model = build_model(PressParams())
    return model, optimize_speed(model, period=T, rigid_samples=300, verify_rtol=1e-8, progress=False)


def test_rigid_optimum_impacts_and_the_no_reversal_optimum_does_not(seed):
    _, r = seed
    assert r.success, r.status
    names = [s["name"] for s in r.stages]
    assert names == ["rigid", "no_reversal", "target"], names
    assert r.stages[0]["clearance_ratio"] > 2.0  # the rigid optimum impacts on the clearance model
    assert r.stages[1]["periodic"] is True and r.stages[1]["clearance_ratio"] <= 1.02
    assert r.stages[2]["status"].startswith("skipped")


def test_seed_story_loads_drop_and_ram_speed_holds(seed):
    model, r = seed
    si, so = r.initial_simulation, r.simulation
    assert r.peak_torque < 0.3 * r.initial_peak_torque
    assert so.peak("slider_normal_force") < 0.3 * si.peak("slider_normal_force")
    # the optimiser's reported value (rigid model) against the clearance-model re-simulation
    assert r.peak_torque == pytest.approx(r.objective_value, rel=0.02)
    # ram speed on the whole window, from an independent simulation started at the periodic state
    x0 = so.states[:, 0] / model.x_scale
    check = simulate(model, r.speed, method="idas", rtol=1e-8, n_out=8001, x0=x0)
    w = (check.t >= r.t1) & (check.t <= r.t2)
    assert np.max(np.abs(check.ram_velocity[w] + 0.1)) <= 0.001
    assert check.peak("torque") == pytest.approx(r.peak_torque, rel=5e-3)


def test_optimum_keeps_the_rod_in_tension(seed):
    """No joint-force reversal, recomputed with the Newton-Euler reference on a dense grid."""
    _, r = seed
    p = PressParams()
    t = np.linspace(0.0, T, 8001)
    ne = _newton_euler(p, *r.speed.evaluate(t))
    weight = (p.slider_mass + p.rod_mass) * p.gravity
    bound = r.stages[1]["min_tension"]
    assert min(ne["crank_pin_tension"].min(), ne["wrist_pin_tension"].min()) >= bound - 0.005 * weight
    ne0 = _newton_euler(p, *r.rigid.speed.evaluate(t))
    assert ne0["wrist_pin_tension"].min() < 0.0  # the rigid optimum reverses
    # the stages report the same minimum tension (their grid is not this one: 1 % of the weight)
    for stage, ne_ in ((r.stages[0], ne0), (r.stages[1], ne)):
        expected = min(ne_["crank_pin_tension"].min(), ne_["wrist_pin_tension"].min())
        assert stage["min_rod_tension"] == pytest.approx(expected, abs=0.01 * weight)


@pytest.mark.slow
def test_seed_by_collocation_improves_on_the_no_reversal_answer_and_keeps_contact(seed):
    """The seed case with the clearance stage run as collocation (0.5 ms elements, journals kept on
    their walls), a few minutes: it converges, and the independent periodic re-simulation of its
    optimum keeps contact everywhere, has the reported peak, holds the ram speed and lowers the peak
    of the verified no-reversal answer (the default call's)."""
    model, auto = seed
    r = optimize_speed(model, period=T, method="collocation", stages="all", rigid_samples=300,
                       verify_rtol=1e-8, progress=False)
    assert r.success, r.status
    assert r.stages[-1]["name"] == "target" and r.stages[-1]["method"] == "collocation"
    so = r.simulation
    assert so.stats["periodic"].get("found", True) is True
    assert min(so.crank_pin_eccentricity.min(), so.wrist_pin_eccentricity.min()) > 0.999
    assert r.peak_torque == pytest.approx(r.objective_value, rel=0.01)
    assert r.max_ram_speed_violation == 0.0
    assert r.rigid_peak_torque < r.peak_torque < auto.peak_torque
