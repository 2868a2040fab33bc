"""`MultipleShooting` (smoke size): the interval integrator reproduces a whole-cycle simulation, its
forward sensitivities match finite differences, failures are reported with stage and interval, the
trust region holds, and a stopped IPOPT is flagged, not hidden. The solves are marked slow: each
forward-sensitivity Jacobian of a 0.25 s interval takes about 8 s on the clearance model."""

import casadi as ca
import numpy as np
import pytest

from pressocp import (MultipleShooting, PressParams, Rigid, SpeedProblem, Strategy, WarmStart, build_model,
                      design_speed, optimize_speed)
from pressocp.ocp import ShootingError, ShootingGrid, transcription_from
from pressocp.ocp.shooting import interval_function
from pressocp.ocp.states import states_at
from pressocp.simulate import Integrator, periodic_state, simulate

N_HARM = 4
PROBLEM = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=N_HARM)


@pytest.fixture(scope="module")
def case():
    model = build_model(PROBLEM.press, n_harmonics=N_HARM)
    speed = design_speed(PROBLEM).speed
    x0, _ = periodic_state(model, speed, integrator=Integrator(method="cvodes", rtol=1e-9))
    return model, speed, x0


@pytest.mark.parametrize("integrator", ["idas", "cvodes"])
def test_intervals_reproduce_a_whole_cycle_simulation(case, integrator):
    """Time offsets, output grid and mapping: each interval started from the simulated state at its
    node ends where the (separately set up) whole-cycle simulation is, with the same torque."""
    model, speed, x0 = case
    grid = ShootingGrid(1.0, 5, 4)
    nodes = states_at(model, speed, x0, grid.nodes, 1e-10)
    G = interval_function(model, grid, ("torque", "wrist_pin_force", "ram_velocity"), integrator, rtol=1e-9)
    p = model.parameters(speed)
    xf, y = (np.asarray(v) for v in G.map(grid.intervals)(nodes, np.tile(p[:, None], (1, 5)), grid.nodes[None, :]))
    assert np.max(np.abs(xf - np.hstack([nodes[:, 1:], nodes[:, :1]]))) < 1e-4  # periodic: last wraps to first
    ref = simulate(model, speed, x0=x0, integrator=Integrator(method="cvodes", rtol=1e-10), n_out=21)  # t = 0, 0.05, ..., 1
    assert np.allclose(ref.t[1:], grid.times)
    assert np.allclose(y[0], ref.torque[1:], rtol=1e-4, atol=1e-3 * ref.peak("torque"))
    assert np.allclose(y[1], ref.wrist_pin_force[1:], rtol=1e-4, atol=1e-3 * ref.peak("wrist_pin_force"))
    assert np.allclose(y[2], ref.ram_velocity[1:], atol=1e-6)


@pytest.mark.parametrize("integrator", ["idas", "cvodes"])
def test_forward_sensitivities_match_finite_differences(case, integrator):
    model, speed, x0 = case
    grid = ShootingGrid(1.0, 10, 3)
    G = interval_function(model, grid, ("torque",), integrator, rtol=1e-10)
    p = model.parameters(speed)
    k = 2
    node = states_at(model, speed, x0, grid.nodes, 1e-10)[:, k]
    rng = np.random.default_rng(0)
    dx, dp = rng.normal(size=model.nx) * 1e-2, np.concatenate([rng.normal(size=2 * N_HARM) * 1e-2, [0.0, 0.0]])
    xs, ps = ca.MX.sym("x", model.nx), ca.MX.sym("p", p.size)
    out = ca.vertcat(*[ca.vec(o) for o in G(xs, ps, grid.nodes[k])])
    jv = ca.Function("jv", [xs, ps], [ca.jtimes(out, ca.vertcat(xs, ps), ca.vertcat(dx, dp))])
    d = np.asarray(jv(node, p)).ravel()
    # finite differences of the explicit-ODE (CVODES) interval, independent of the integrator under test
    G_fd = interval_function(model, grid, ("torque",), "cvodes", rtol=1e-11)
    f = ca.Function("f", [xs, ps], [ca.vertcat(*[ca.vec(o) for o in G_fd(xs, ps, grid.nodes[k])])])
    h = 1e-2
    fd = (np.asarray(f(node + h * dx, p + h * dp)) - np.asarray(f(node - h * dx, p - h * dp))).ravel() / (2 * h)
    assert np.allclose(d, fd, rtol=1e-3, atol=1e-4 * np.max(np.abs(fd)))


def test_integrator_failure_names_stage_and_interval(case):
    model, speed, x0 = case
    with pytest.raises(ShootingError, match=r"stage 'target', shooting interval 0 \(t = 0\.\.0\.25 s\)") as err:
        MultipleShooting(intervals=4, samples=2, max_steps=20).solve(PROBLEM, model, WarmStart(speed, x0), "target")
    assert err.value.interval == 0 and err.value.stage == "target"


@pytest.mark.parametrize("kwargs, match", [
    (dict(min_eccentricity=-0.1), r"min_eccentricity must be in \[0, 1\]"),
    (dict(intervals=0), "intervals"), (dict(integrator="euler"), "integrator"),
    (dict(coefficient_step=0.0), r"coefficient_step must be in \(0, inf\) rad/s")])
def test_bad_settings_rejected(kwargs, match):
    with pytest.raises(ValueError, match=match):
        MultipleShooting(**kwargs)


@pytest.mark.slow
def test_coefficient_trust_region_holds(case):
    """Every Fourier coefficient of the returned iterate stays within coefficient_step of the start."""
    model, speed, x0 = case
    step = 1e-4
    tr = MultipleShooting("cvodes", intervals=4, samples=4, coefficient_step=step, ipopt={"ipopt.max_iter": 3})
    sol = tr.solve(PROBLEM, model, WarmStart(speed, x0))
    assert transcription_from(sol.settings) == tr  # the stage records the transcription that solved it
    moved = np.abs(sol.speed.coefficients - speed.padded(N_HARM).coefficients)
    # IPOPT relaxes bounds by 1e-8 x max(1, |bound|): coefficients are below 10 rad/s here
    assert np.all(moved <= step + 1e-7) and np.max(moved) > 0.5 * step  # moved, up to the bound


@pytest.mark.slow
def test_stopped_ipopt_is_flagged_with_its_stage(case):
    """Few intervals, IPOPT stopped after 2 iterations, every stage forced: a result, not an exception,
    flagged not successful, naming the stage, holding a finite iterate and its re-simulation."""
    model, _, _ = case
    r = optimize_speed(PROBLEM, model, MultipleShooting(intervals=4, samples=4, ipopt={"ipopt.max_iter": 2}),
                       Strategy("all", rigid=Rigid(samples=200), verify_rtol=1e-7), progress=False)
    assert not r.success and r.status.startswith("stage 'target'") and "Maximum_Iterations" in r.status
    assert [s.name for s in r.stages] == ["rigid", "target"]  # no impact at 60 spm: no soft stage
    assert r.stages[0].check.ratio < 1.10
    assert np.all(np.isfinite(r.speed.coefficients)) and r.history
    assert r.simulation is not None and np.isfinite(r.peak_torque)
    # the warm start was the converged rigid optimum: the iterate stays near its floor
    assert r.peak_torque < 1.2 * r.rigid_peak_torque
    assert set(r.stages[1].violations) >= {"continuity", "epigraph", "ram_speed_samples", "window_phase", "omega"}
    # a warm start: the barrier starts small and only decreases
    mu = r.stages[1].barrier
    assert mu and mu[0] <= 1e-4 and np.all(np.diff(mu) <= 0.0)
