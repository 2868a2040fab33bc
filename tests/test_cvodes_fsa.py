"""Forward sensitivities through CVODES compiled with the model (`pressocp.cvodes_fsa`), both ways (the
directions integrated with the states as one system, and CVODES's staggered sensitivity module):
against the closed-form sensitivities of a linear and of a nonlinear ODE, and against CasADi's forward
integrator (a separate implementation) on the press."""

import json
import sys
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from scipy.linalg import expm

import pressocp as po
import pressocp.cvodes_fsa as cvodes_fsa
import pressocp.sensitivity as sens
from pressocp.cvodes_fsa import ForwardSensitivities, FsaError, available

pytestmark = pytest.mark.skipif(not available(), reason="needs a C compiler and CasADi's CVODES library")

OPTIMUM = Path(__file__).parent / "references" / "press75_optimum_speed.json"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")


def linear_ode(directions: int | None = None):
    """x' = A x + B q, with A a damped oscillator and a third state that decays, and one speed-like
    parameter before q (not differentiated)."""
    A = np.array([[0.0, 1.0, 0.0], [-40.0, -0.8, 0.3], [0.0, 0.5, -3.0]])
    B = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    t, x, p = ca.SX.sym("t"), ca.SX.sym("x", 3), ca.SX.sym("p", 3)
    ode = ca.mtimes(A, x) + ca.mtimes(B, p[1:]) + 0 * p[0]
    return A, B, ForwardSensitivities.build({"t": t, "x": x, "p": p, "ode": ode}, 2, directions)


@pytest.fixture(scope="module")
def linear():
    """`linear_ode` through CVODES's staggered sensitivities."""
    return linear_ode()


@pytest.fixture(scope="module")
def linear_fused():
    """`linear_ode` with its 5 directions integrated with the states as one system."""
    return linear_ode(5)


@pytest.mark.parametrize("way", ["linear", "linear_fused"])
def test_linear_ode_sensitivities_match_the_closed_form(way, request):
    """x(t) = e^{At} x0 + A^-1 (e^{At} - I) B q: the states, the directions of x0 (e^{At}) and those
    of q (A^-1 (e^{At} - I) B, scaled by the directions' Q) at three times, within 2e-7 (the global
    error at rtol 1e-10 reaches 3e-8), both ways."""
    A, B, fsa = request.getfixturevalue(way)
    x0, q = np.array([0.1, -0.2, 0.3]), np.array([0.5, -1.5])
    S0 = np.hstack([np.eye(3), np.zeros((3, 2))])
    Q = np.hstack([np.zeros((2, 3)), np.diag([2.0, 0.5])])
    grid = np.array([0.1, 0.7, 2.0])
    x, S, stats = fsa.run(x0, np.r_[7.0, q], S0, Q, grid, rtol=1e-10)
    for k, tk in enumerate(grid):
        E = expm(A * tk)
        forced = np.linalg.solve(A, (E - np.eye(3)) @ B)
        np.testing.assert_allclose(x[:, k], E @ x0 + forced @ q, atol=2e-7)
        np.testing.assert_allclose(S[:, :3, k], E, atol=2e-7)
        np.testing.assert_allclose(S[:, 3:, k], forced @ np.diag([2.0, 0.5]), atol=2e-7)
    assert stats["steps"] > 0 and (stats["sensitivity_jacobians"] > 0) == (fsa.directions is None)


def test_one_system_takes_its_number_of_directions_only(linear_fused):
    _, _, fsa = linear_fused
    with pytest.raises(ValueError, match=r"S0 shape \(3, 5\)"):
        fsa.run(np.ones(3), np.zeros(3), np.eye(3), np.zeros((2, 3)), np.array([1.0]), rtol=1e-8)


def test_without_directions_it_integrates_the_states(linear):
    A, B, fsa = linear
    x, S, _ = fsa.run(np.ones(3), np.zeros(3), np.zeros((3, 0)), np.zeros((2, 0)), np.array([1.0]), rtol=1e-10)
    np.testing.assert_allclose(x[:, 0], expm(A) @ np.ones(3), atol=2e-7)
    assert S.shape == (3, 0, 1)


@pytest.mark.parametrize("directions", [None, 3])
def test_a_time_dependent_nonlinear_ode_matches_its_closed_form(directions):
    """x' = -q t x, x = x0 exp(-q t^2 / 2): dx/dx0 = exp(-q t^2 / 2), dx/dq = -t^2 / 2 x
    (the Jacobian changes with t and x, so it is refreshed along the run), and a second state
    y' = -y^2 + q (nonlinear, y = sqrt(q) tanh(sqrt(q) t + atanh(y0 / sqrt(q)))) with its directions
    from the derivative of that closed form. Another state count than `linear`'s, in the same process;
    both ways (`directions`)."""
    t, x, p = ca.SX.sym("t"), ca.SX.sym("x", 2), ca.SX.sym("p", 1)
    fsa = ForwardSensitivities.build({"t": t, "x": x, "p": p, "ode": ca.vertcat(-p[0] * t * x[0], -x[1] ** 2 + p[0])},
                                     n_parameters=1, directions=directions)
    grid = np.array([0.3, 1.0, 2.5])
    q, x0 = 1.7, np.array([0.8, 0.2])
    X, S, stats = fsa.run(x0, np.array([q]), np.eye(2, 3), np.array([[0.0, 0.0, 1.0]]), grid, rtol=1e-10)

    def closed(tk, x0, q):
        r = np.sqrt(q)
        return np.array([x0[0] * np.exp(-q * tk ** 2 / 2), r * np.tanh(r * tk + np.arctanh(x0[1] / r))])

    for k, tk in enumerate(grid):
        np.testing.assert_allclose(X[:, k], closed(tk, x0, q), atol=2e-8)
        h = 1e-6  # the closed form's derivatives by central differences of the closed form itself
        d_x0 = [(closed(tk, x0 + h * e, q) - closed(tk, x0 - h * e, q)) / (2 * h) for e in np.eye(2)]
        d_q = (closed(tk, x0, q + h) - closed(tk, x0, q - h)) / (2 * h)
        np.testing.assert_allclose(S[:, :2, k], np.column_stack(d_x0), atol=2e-7)
        np.testing.assert_allclose(S[:, 2, k], d_q, atol=2e-7)
        assert S[0, 2, k] == pytest.approx(-tk ** 2 / 2 * X[0, k], abs=2e-7)
    assert stats["jacobians"] > 1


def test_a_failed_run_raises_with_cvodes_flag_and_time(linear):
    _, _, fsa = linear
    with pytest.raises(FsaError, match="CV_TOO_MUCH_WORK") as err:
        fsa.run(np.ones(3), np.zeros(3), np.eye(3), np.zeros((2, 3)), np.array([50.0]), rtol=1e-10, max_steps=20)
    assert err.value.flag == -1 and 0.0 < err.value.time < 50.0


@pytest.mark.parametrize("x0, p, S0, grid", [
    (np.ones(3), np.zeros(3), np.eye(2), [1.0]),  # S0 of 2 states
    (np.ones(2), np.zeros(3), np.eye(3), [1.0]),  # x0 of 2
    (np.ones(3), np.zeros(4), np.eye(3), [1.0]),  # p of 4
    (np.ones(3), np.zeros(3), np.eye(3), [0.0, 1.0]),  # a grid from 0
    (np.ones(3), np.zeros(3), np.eye(3), [1.0, 0.5]),  # a decreasing grid
])
def test_wrong_inputs_fail_before_integrating(linear, x0, p, S0, grid):
    _, _, fsa = linear
    with pytest.raises(ValueError, match="x0 must have 3 entries, p 3|grid must increase"):
        fsa.run(x0, p, S0, np.zeros((2, S0.shape[1])), np.array(grid), rtol=1e-8)


def test_where_it_cannot_be_built_casadis_forward_integrator_runs_and_a_warning_says_why(monkeypatch):
    """A failed compile (here: a stand-in build that raises) leaves the sensitivities to CasADi's
    forward integrator, with a warning naming the cause, and the result says which ran."""
    def fails(cls, *args):
        raise RuntimeError("compiling fsa.c failed (exit 1): error: something")

    monkeypatch.setattr(ForwardSensitivities, "build", classmethod(fails))
    model = po.build_model(po.PressParams(), clearance=("wrist_pin",))
    with pytest.warns(RuntimeWarning, match="compiled forward sensitivities unavailable.*exit 1"):
        s = sens.sensitivities(model, po.FourierSpeed.constant(0.8), ("slider_mass",), rtol=1e-8,
                               error_estimate=False)
    assert s.engine == sens.ENGINE_CASADI and 0.4 < s.table["derivative"].iloc[0] < 0.6


def test_press_peak_derivatives_match_casadis_forward_integrator(monkeypatch):
    """The seed optimum's 11 directions over a period at rtol 1e-10, from one state on one grid,
    through the compiled driver (as `po.sensitivities` runs them) and through CasADi's forward integrator:
    within 1e-5 of their largest entry. Then the peak-torque derivatives (3 parameters, 4 rival
    peaks, rtol 1e-9) of each engine's `sensitivities`: within 2e-3 of each other (each is within
    2e-3 of central differences at rtol 1e-12, `benchmarks/results/sensitivity_seed.json`; the
    states at the peaks, and the periodic searches, come from the driver and from CasADi's CVODES)."""
    speed = po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text()))
    model = replace(po.build_model(po.PressParams()), jit=True)
    native = sens.sensitivities(model, speed, PARAMETERS, rtol=1e-9, error_estimate=False)
    # the directions themselves, on one grid from one state, against CasADi's augmented system
    msym = sens.sensitivity_model(model, PARAMETERS)
    pv = msym.parameters(speed)
    scale = sens.parameter_scale(pv[-3:])
    grid = [0.1, 0.4, speed.period]
    x0 = po.simulate(model, speed, periodic=True, work=False,
                     integrator=po.Integrator("cvodes", 1e-10, periodic_tol=1e-7)).states[:, 0] / model.x_scale
    Q = np.hstack([np.zeros((3, msym.nx)), np.diag(scale)])
    _, S, _ = sens.kept_fsa(msym, 3).run(x0, pv, np.eye(msym.nx, msym.nx + 3), Q, np.array(grid), 1e-10)
    S_casadi = sens.casadi_forward(msym, grid, x0, pv, scale, 1e-10)
    assert np.max(np.abs(S - S_casadi)) <= 1e-5 * np.max(np.abs(S_casadi))  # 1.7e-7 measured (staggered: 9.9e-7)
    monkeypatch.setattr(cvodes_fsa, "unavailable", lambda: "switched off by the test")
    other = replace(po.build_model(po.PressParams()), jit=True)
    with pytest.warns(RuntimeWarning, match="switched off by the test"):
        casadi = sens.sensitivities(other, speed, PARAMETERS, rtol=1e-9, error_estimate=False)
    assert native.engine == sens.ENGINE_FSA and casadi.engine == sens.ENGINE_CASADI
    a, b = native.per_peak, casadi.per_peak
    assert len(a) == len(b) == 12
    np.testing.assert_allclose(a["time"], b["time"], atol=1e-6)  # 5e-8 s measured (a sample is 4e-5 s)
    np.testing.assert_allclose(a["value"], b["value"], rtol=2e-6)  # the states at the peaks, two integrations
    np.testing.assert_allclose(a["derivative"], b["derivative"], rtol=2e-3)


def test_ctrl_c_stops_a_run_and_leaves_pythons_handler():
    """A SIGINT during a long run (an undamped oscillator over 1e5 s at rtol 1e-12: about 1e7 steps,
    a minute) ends it within a right-hand side and raises KeyboardInterrupt; the process's own
    SIGINT handler is in place again afterwards."""
    import os
    import signal
    import threading
    import time

    t, x, p = ca.SX.sym("t"), ca.SX.sym("x", 2), ca.SX.sym("p", 1)
    fsa = ForwardSensitivities.build({"t": t, "x": x, "p": p, "ode": ca.vertcat(x[1], -100 * x[0] + 0 * p[0])}, 0)
    before = signal.getsignal(signal.SIGINT)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    started = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        fsa.run(np.ones(2), np.zeros(1), np.eye(2), np.zeros((0, 2)), np.array([1e5]), rtol=1e-12, max_steps=10**9)
    timer.join()
    assert time.perf_counter() - started < 3.0
    assert signal.getsignal(signal.SIGINT) is before


@pytest.fixture(scope="module")
def seed():
    """The seed optimum on the default model (compiled)."""
    return replace(po.build_model(po.PressParams()), jit=True), po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text()))


def test_simulate_with_cvodes_direct_matches_cvodes(seed):
    """`Integrator("cvodes-direct")`: the seed optimum's periodic response at rtol 1e-9 by the compiled
    driver and by CasADi's CVODES, the same peaks to 1e-6 and states to 1e-5 (the integration error,
    another linear solver); the search and the run's statistics are reported."""
    model, speed = seed
    runs = {m: po.simulate(model, speed, periodic=True, work=False, n_out=4001,
                           integrator=po.Integrator(m, 1e-9, periodic_tol=1e-6)) for m in ("cvodes", "cvodes-direct")}
    a, b = runs["cvodes-direct"], runs["cvodes"]
    assert sys.modules["pressocp.simulate"].DIRECT_DRIVER in model.functions  # the driver ran, not CasADi's
    assert np.max(np.abs(a.torque)) == pytest.approx(np.max(np.abs(b.torque)), rel=1e-6)
    np.testing.assert_allclose(a.states / model.x_scale[:, None], b.states / model.x_scale[:, None], atol=1e-5)
    assert a.stats["steps"] > 1000 and a.stats["periodic"]["residual"] <= 1e-6


def test_cvodes_direct_takes_its_absolute_tolerance(seed):
    """atol 1e-6 against rtol 1e-10: the driver's steps and states follow CasADi's CVODES at the same
    tolerances, not at atol = rtol (0.2 s from the model's start: 9 808 steps against 9 389 for
    CasADi's; 33 076 and 32 720 at atol = rtol)."""
    model, speed = seed
    x0 = model.x0
    runs = {(m, a): po.simulate(model, speed, x0=x0, t_end=0.2, n_out=3, work=False,
                                integrator=po.Integrator(m, 1e-10, atol=a)) for m in ("cvodes", "cvodes-direct")
            for a in (1e-6, None)}
    loose, tight = runs["cvodes-direct", 1e-6], runs["cvodes-direct", None]
    assert loose.stats["steps"] < 0.8 * tight.stats["steps"]
    assert loose.stats["steps"] == pytest.approx(runs["cvodes", 1e-6].stats["steps"], rel=0.2)
    scaled = (loose.states - runs["cvodes", 1e-6].states) / model.x_scale[:, None]
    assert np.max(np.abs(scaled)) < 1e-2  # loose runs: their errors, not each other's digits


def test_cvodes_direct_refuses_work_and_a_missing_driver_before_integrating(seed, monkeypatch):
    model, speed = seed
    for periodic in (False, True):  # the periodic search does not run first
        with pytest.raises(ValueError, match="integrates no work quadratures: simulate with work=False"):
            po.simulate(po.build_model(po.PressParams()), speed, periodic=periodic,
                        integrator=po.Integrator("cvodes-direct", 1e-8))
    monkeypatch.setattr(cvodes_fsa, "unavailable", lambda: "no C compiler (cc) found")
    with pytest.raises(ValueError, match=r'"cvodes-direct" cannot run here \(no C compiler'):
        po.simulate(po.build_model(po.PressParams()), speed, work=False, integrator=po.Integrator("cvodes-direct"))


def test_cvodes_direct_runs_columns_in_threads_as_one_by_one(seed):
    """The periodic search's Newton shots: several start states in 2 threads give what each gives alone."""
    sim = sys.modules["pressocp.simulate"]
    model, speed = seed
    F = sim.DirectCvodes(sim.direct_driver(model, False), np.array([0.2, speed.period]), po.Integrator("cvodes-direct", 1e-8))
    p = model.parameters(speed)
    xs = model.x0[:, None] + 1e-3 * np.arange(3)[None, :]
    together = F.map(3, "thread", 2).run({}, xs, np.tile(p[:, None], (1, 3)))["xf"]
    alone = np.hstack([F.run({}, xs[:, k], p)["xf"] for k in range(3)])
    np.testing.assert_array_equal(together, alone)


def test_cvodes_direct_fills_in_repeated_times_and_zero(seed):
    """A periodic search's sample times may repeat (and start at 0): the driver integrates to the
    distinct times after 0 and the others are filled in."""
    sim = sys.modules["pressocp.simulate"]
    model, speed = seed
    p, integ = model.parameters(speed), po.Integrator("cvodes-direct", 1e-8)
    driver = sim.direct_driver(model, False)
    X = sim.DirectCvodes(driver, np.array([0.0, 0.1, 0.1, 0.3]), integ).run({}, model.x0, p)["xf"]
    Y = sim.DirectCvodes(driver, np.array([0.1, 0.3]), integ).run({}, model.x0, p)["xf"]
    np.testing.assert_array_equal(X, np.column_stack([model.x0, Y[:, 0], Y[:, 0], Y[:, 1]]))
