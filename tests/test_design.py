"""Rigid speed design and the inverse 'speed for a ram motion'."""

import casadi as ca
import numpy as np
import pytest

from pressocp import DesignSettings, FourierSpeed, KnuckleJoint, KnucklePress, PressParams, SpeedProblem
from pressocp.design import design_nlp, design_speed, speed_for_ram_motion
from pressocp.problem import ram_speed_range
from tests.references.press import exact_height


@pytest.fixture(scope="module")
def default_design():
    return design_speed(SpeedProblem(PressParams()))


def test_default_design_holds_ram_speed(default_design):
    d, p = default_design, PressParams()
    assert d.converged, d.status
    # independent check on a dense grid with the hand-written kinematics
    t = np.linspace(d.t1, d.t2, 5001)
    dt = 1e-6
    v = (exact_height(p, d.speed.theta(t + dt)) - exact_height(p, d.speed.theta(t - dt))) / (2 * dt)
    assert np.max(np.abs(v / -0.1 - 1)) < 0.01
    assert d.max_error < 0.01 and d.rms_error <= d.max_error
    # the window sits where asked: h(t1) = 0.7 H and h(t2) = 0.3 H on the downstroke
    assert exact_height(p, d.speed.theta(d.t1)) == pytest.approx(0.07, abs=1e-6)
    assert exact_height(p, d.speed.theta(d.t2)) == pytest.approx(0.03, abs=2e-4)
    assert 0 < d.speed.theta(d.t1) < d.speed.theta(d.t2) < np.pi


def test_default_design_no_crank_reversal(default_design):
    t = np.linspace(0, 1, 20001)
    assert np.min(default_design.speed.omega(t)) > 0
    assert default_design.min_omega > 0


def test_design_other_speed_and_harmonics():
    d = design_speed(SpeedProblem(PressParams(), period=0.8, ram_speed=-0.2, window=(0.6, 0.2), n_harmonics=10))
    assert d.converged and d.max_error < 0.01 and d.speed.n_harmonics == 10
    assert d.t2 - d.t1 == pytest.approx(0.04 / 0.2)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(ram_speed=0.1), "ram_speed must be negative"),
        (dict(ram_speed=-0.001), r"ram_speed must be in \[-"),
        (dict(ram_speed=-50.0), r"ram_speed must be in \[-"),
        (dict(ram_speed=float("nan")), "ram_speed"),
        (dict(window=(0.3, 0.7)), "window"),
        (dict(window=(1.2, 0.3)), r"window\[0\]"),
        (dict(window=(0.7, 0.0)), r"window\[1\]"),
        (dict(window=(0.7,)), "window"),
        (dict(period=0.0), "period"),
        (dict(period=-1.0), "period"),
        (dict(n_harmonics=0), "n_harmonics"),
    ],
)
def test_design_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        design_speed(SpeedProblem(PressParams(), **kwargs))


@pytest.mark.parametrize("kwargs, match", [(dict(band=0.0), "band"), (dict(samples=5), "samples"),
                                           (dict(smoothing_weight=-1.0), "smoothing_weight")])
def test_design_settings_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        DesignSettings(**kwargs)


def test_reachable_range_is_consistent():
    fast, slow = ram_speed_range(PressParams(), 1.0, (0.7, 0.3))
    assert fast < slow < 0
    assert slow == pytest.approx(-0.04 / 0.8)


def test_speed_for_ram_motion_recovers_known_speed():
    p = PressParams()
    true = FourierSpeed(1.2, [0.8, -0.3, 0.1, 0.05], [0.4, 0.2, -0.1, 0.02], theta0=0.4)
    t = np.linspace(0, 1.2, 1201)
    h = exact_height(p, true.theta(t))
    fit = speed_for_ram_motion(p, t, h, n_harmonics=4)
    assert np.allclose(fit.a, true.a, atol=1e-6) and np.allclose(fit.b, true.b, atol=1e-6)
    assert fit.theta0 == pytest.approx(0.4, abs=1e-7)
    # more harmonics than the data: the extra ones stay ~0
    fit15 = speed_for_ram_motion(p, t, h)
    assert np.max(np.abs(fit15.coefficients[[*range(4, 15), *range(19, 30)]])) < 1e-6


def test_speed_for_ram_motion_bad_input():
    p = PressParams()
    t = np.linspace(0, 1, 101)
    with pytest.raises(ValueError, match="h must be within"):
        speed_for_ram_motion(p, t, np.full(101, 0.2))
    with pytest.raises(ValueError, match="same length"):
        speed_for_ram_motion(p, t, np.zeros(50))
    with pytest.raises(ValueError, match="increasing"):
        speed_for_ram_motion(p, t[::-1], np.zeros(101))
    with pytest.raises(ValueError, match="h must contain only finite"):
        speed_for_ram_motion(p, t, np.full(101, np.nan))


@pytest.mark.parametrize("case", ["slider_crank", "knuckle"])
def test_the_design_nlps_own_derivatives_are_casadis(case):
    """`design_nlp` hands IPOPT a Jacobian and a Lagrangian Hessian assembled from per-sample kernels;
    at a random point with random multipliers they equal CasADi's AD of the assembled objective and
    constraints (a mistake in the assembly, a missing term or sample, would show here, not as a
    slower or different optimum)."""
    if case == "knuckle":
        drive = KnucklePress()
        press = PressParams(crank_radius=drive.upper_link, rod_length=drive.lower_link, crank_com=0.5 * drive.upper_link)
        problem = SpeedProblem(press, period=1.5, ram_speed=-0.02, mechanism=KnuckleJoint(drive), n_harmonics=4)
    else:
        problem = SpeedProblem(PressParams(), period=0.8, ram_speed=-0.1, n_harmonics=5)
    nlp = design_nlp(problem, DesignSettings(samples=12))
    x, g = nlp.problem["x"], nlp.problem["g"]
    lam_f, lam_g = ca.MX.sym("lf"), ca.MX.sym("lg", g.numel())
    ad = ca.Function("ad", [x, lam_f, lam_g], [ca.jacobian(g, x), ca.hessian(lam_f * nlp.problem["f"] + ca.dot(lam_g, g), x)[0]])
    rng = np.random.default_rng(7)
    n = problem.n_harmonics
    z = np.concatenate([rng.normal(scale=0.5, size=2 * n), [0.2 * problem.period]])
    lf, lg = 0.7, rng.normal(size=g.numel())
    jac_ad, hess_ad = (np.asarray(ca.densify(v)) for v in ad(z, lf, lg))
    g_own, jac_own = nlp.jac_g(z, [])
    hess_own = np.asarray(ca.densify(nlp.hess_lag(z, [], lf, lg)))
    np.testing.assert_allclose(np.asarray(ca.densify(jac_own)), jac_ad, rtol=1e-10, atol=1e-10 * np.abs(jac_ad).max())
    np.testing.assert_allclose(hess_own, np.triu(hess_ad), rtol=1e-9, atol=1e-10 * np.abs(hess_ad).max())
    np.testing.assert_allclose(np.asarray(g_own).ravel(), np.asarray(ca.Function("g", [x], [g])(z)).ravel(), rtol=1e-14)
    assert np.abs(np.triu(hess_ad, 1)).max() > 0  # the Hessian couples the coefficients: a real check
