"""CVODES's own forward sensitivities, compiled with the model (`pressocp.cvodes_fsa`): against the
closed-form sensitivities of a linear ODE, and against CasADi's forward integrator (a separate
implementation: the augmented system) on the press."""

import json
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from scipy.linalg import expm

import pressocp as po
import pressocp.sensitivity as sens
from pressocp.cvodes_fsa import ForwardSensitivities, FsaError, available

pytestmark = pytest.mark.skipif(not available(), reason="needs a C compiler and CasADi's CVODES library")

OPTIMUM = Path(__file__).parent / "references" / "press75_optimum_speed.json"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")


@pytest.fixture(scope="module")
def linear():
    """x' = A x + B q, with A a damped oscillator and a third state that decays, and one speed-like
    parameter before q (not differentiated)."""
    A = np.array([[0.0, 1.0, 0.0], [-40.0, -0.8, 0.3], [0.0, 0.5, -3.0]])
    B = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    t, x, p = ca.SX.sym("t"), ca.SX.sym("x", 3), ca.SX.sym("p", 3)
    ode = ca.mtimes(A, x) + ca.mtimes(B, p[1:]) + 0 * p[0]
    return A, B, ForwardSensitivities.build({"t": t, "x": x, "p": p, "ode": ode}, n_parameters=2)


def test_linear_ode_sensitivities_match_the_closed_form(linear):
    """x(t) = e^{At} x0 + A^-1 (e^{At} - I) B q: the states, the directions of x0 (e^{At}) and those
    of q (A^-1 (e^{At} - I) B, scaled by the directions' Q) at three times, within 2e-7 (the global error at rtol 1e-10 reaches 3e-8)."""
    A, B, fsa = linear
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
    assert stats["steps"] > 0 and stats["sensitivity_jacobians"] > 0


def test_without_directions_it_integrates_the_states(linear):
    A, B, fsa = linear
    x, S, _ = fsa.run(np.ones(3), np.zeros(3), np.zeros((3, 0)), np.zeros((2, 0)), np.array([1.0]), rtol=1e-10)
    np.testing.assert_allclose(x[:, 0], expm(A) @ np.ones(3), atol=2e-7)
    assert S.shape == (3, 0, 1)


def test_a_failed_run_raises_with_cvodes_flag_and_time(linear):
    _, _, fsa = linear
    with pytest.raises(FsaError, match="CV_TOO_MUCH_WORK") as err:
        fsa.run(np.ones(3), np.zeros(3), np.eye(3), np.zeros((2, 3)), np.array([50.0]), rtol=1e-10, max_steps=20)
    assert err.value.flag == -1 and 0.0 < err.value.time < 50.0


def test_wrong_shapes_fail_before_integrating(linear):
    _, _, fsa = linear
    with pytest.raises(ValueError, match=r"S0 must be \(3, ns\)"):
        fsa.run(np.ones(3), np.zeros(3), np.eye(2), np.zeros((2, 2)), np.array([1.0]), rtol=1e-8)


def test_press_peak_derivatives_match_casadis_forward_integrator(monkeypatch):
    """The seed optimum's peak-torque derivatives (3 parameters, 4 rival peaks, rtol 1e-9) through
    CVODES's staggered sensitivities and through CasADi's augmented forward integrator: within
    2e-3 of each other (each is within 2e-3 of central differences at rtol 1e-12,
    `benchmarks/results/sensitivity_seed.json`)."""
    speed = po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text()))
    model = replace(po.build_model(po.PressParams()), jit=True)
    native = sens.sensitivities(model, speed, PARAMETERS, rtol=1e-9, error_estimate=False)
    monkeypatch.setattr(sens, "available", lambda: False)
    other = replace(po.build_model(po.PressParams()), jit=True)
    casadi = sens.sensitivities(other, speed, PARAMETERS, rtol=1e-9, error_estimate=False)
    assert native.engine == sens.ENGINE_FSA and casadi.engine == sens.ENGINE_CASADI
    a, b = native.per_peak, casadi.per_peak
    assert len(a) == len(b) == 12
    np.testing.assert_allclose(a["time"], b["time"], atol=1e-9)
    np.testing.assert_allclose(a["value"], b["value"], rtol=2e-6)  # the states at the peaks, two integrations
    np.testing.assert_allclose(a["derivative"], b["derivative"], rtol=2e-3)
