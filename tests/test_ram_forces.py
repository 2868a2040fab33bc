"""The forces on the ram besides gravity: the process-force curve and the slide counterbalance.

The reference is the virtual work of a force F(h) on the ram: on the ideal press it changes the
motor torque by -F(h) dh/dtheta, with dh/dtheta of the slider-crank written out here by hand. The
gas law and the curve's interpolation are written here too (numpy), not taken from the package."""

import math

import numpy as np
import pytest

import pressocp as po

R, L = 0.05, 0.25


def dh_dtheta(theta):
    """Slider-crank: h = r cos th - sqrt(l^2 - r^2 sin^2 th) + r + l, differentiated by hand."""
    s = np.sin(theta)
    return -R * s + R**2 * s * np.cos(theta) / np.sqrt(L**2 - (R * s) ** 2)


def height(theta):
    return R * np.cos(theta) - np.sqrt(L**2 - (R * np.sin(theta)) ** 2) + R + L


def torque(press, theta, omega, alpha):
    return np.asarray(po.rigid_inverse_dynamics(press, theta, omega, alpha)["torque"], float).ravel()


THETA = np.linspace(0.05, 2 * np.pi - 0.05, 41)
OMEGA = 6.0 + np.sin(THETA)  # positive: the ram goes down for theta in (0, pi)
ALPHA = 3.0 * np.cos(THETA)


@pytest.mark.parametrize("exponent", [0.0, 1.0, 1.4])
def test_counterbalance_torque_is_its_virtual_work(exponent):
    bare = po.PressParams(crank_radius=R, rod_length=L)
    cb = po.Counterbalance(force=1800.0, gas_length=0.4, exponent=exponent)
    with_cb = bare.replace(counterbalance=cb)
    h = height(THETA)
    force = 1800.0 * (0.4 / (0.4 + h)) ** exponent  # pV^n = const with V proportional to gas_length + h
    expected = -force * dh_dtheta(THETA)
    got = torque(with_cb, THETA, OMEGA, ALPHA) - torque(bare, THETA, OMEGA, ALPHA)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_counterbalance_potential_is_zero_at_bdc_and_falls_with_height():
    cb = po.PressParams(counterbalance=po.Counterbalance(force=1000.0, gas_length=0.5, exponent=1.0))
    pe = po.rigid_inverse_dynamics(cb, np.array([np.pi, 0.0]), 0.0, 0.0)["potential_energy"]
    bare = po.rigid_inverse_dynamics(po.PressParams(), np.array([np.pi, 0.0]), 0.0, 0.0)["potential_energy"]
    extra = np.asarray(pe, float).ravel() - np.asarray(bare, float).ravel()
    # isothermal: -F L ln(1 + h / L); at BDC h = 0, at TDC h = 0.1 m
    np.testing.assert_allclose(extra, [0.0, -1000.0 * 0.5 * math.log(1 + 0.1 / 0.5)], atol=1e-9)


def test_constant_force_equals_its_two_point_curve():
    pf = po.ProcessForce(force=4000.0, h_top=0.06, h_bottom=0.02)
    curve = po.ProcessForce(heights=(0.02, 0.06), forces=(4000.0, 4000.0))
    a = torque(po.PressParams(process_force=pf), THETA, OMEGA, ALPHA)
    b = torque(po.PressParams(process_force=curve), THETA, OMEGA, ALPHA)
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-9)


def test_constant_force_is_the_product_of_smoothed_steps():
    """The constant force as first written: F s((h - h_bottom)/edge) s((h_top - h)/edge) s(-v/speed_edge)."""
    pf = po.ProcessForce(force=4000.0, h_top=0.06, h_bottom=0.02, edge=2e-3)
    theta = np.linspace(0.05, 2 * np.pi - 0.05, 301)
    omega, alpha = 5.0 + np.cos(theta), np.zeros_like(theta)
    press = po.PressParams(crank_radius=R, rod_length=L, process_force=pf)
    extra = torque(press, theta, omega, alpha) - torque(po.PressParams(crank_radius=R, rod_length=L), theta, omega,
                                                         alpha)
    h = height(theta)
    v = dh_dtheta(theta) * omega

    def s(x):
        return 0.5 * (1 + np.tanh(x))

    force = 4000.0 * s((h - 0.02) / 2e-3) * s((0.06 - h) / 2e-3) * s(-v / 1e-3)
    np.testing.assert_allclose(extra, -force * dh_dtheta(theta), rtol=1e-9, atol=1e-9)


def test_curve_follows_its_points_away_from_the_knots():
    heights, forces = (0.01, 0.03, 0.05, 0.07), (0.0, 6000.0, 2500.0, 1000.0)
    press = po.PressParams(process_force=po.ProcessForce(heights=heights, forces=forces, edge=2e-4))
    theta = np.linspace(0.3, np.pi - 0.3, 60)  # downstroke, omega > 0
    h = height(theta)
    away = np.min(np.abs(h[:, None] - np.asarray(heights)[None, :]), axis=1) > 5 * 2e-4
    omega, alpha = np.full_like(theta, 8.0), np.zeros_like(theta)
    extra = torque(press, theta, omega, alpha) - torque(po.PressParams(), theta, omega, alpha)
    force = -extra / dh_dtheta(theta)
    expected = np.where((h > heights[0]) & (h < heights[-1]), np.interp(h, heights, forces), 0.0)
    np.testing.assert_allclose(force[away], expected[away], rtol=1e-6, atol=1e-3)
    # off on the upstroke
    up = torque(press, 2 * np.pi - theta, omega, alpha) - torque(po.PressParams(), 2 * np.pi - theta, omega, alpha)
    assert np.max(np.abs(up)) < 1e-6


def test_curve_from_csv(tmp_path):
    path = tmp_path / "draw.csv"
    path.write_text("height_m,force_N\n0.05,0\n0.01,3000\n0.03,5000\n")
    pf = po.ProcessForce.from_csv(path, edge=1e-4)
    assert pf.heights == (0.01, 0.03, 0.05) and pf.forces == (3000.0, 5000.0, 0.0) and pf.edge == 1e-4
    (tmp_path / "bad.csv").write_text("h,F,x\n0,1,2\n1,2,3\n")
    with pytest.raises(ValueError, match="2 columns"):
        po.ProcessForce.from_csv(tmp_path / "bad.csv")


@pytest.mark.parametrize("kwargs, match", [
    (dict(heights=(0.02, 0.01), forces=(1.0, 2.0)), r"heights must increase, got 0.02 then 0.01"),
    (dict(heights=(0.01, 0.02), forces=(1.0,)), "same length"),
    (dict(heights=(0.01,), forces=(1.0,)), "at least 2"),
    (dict(heights=(0.01, 0.02), forces=(1.0, -2.0)), "forces must be >= 0"),
    (dict(force=10.0, heights=(0.01, 0.02), forces=(1.0, 2.0)), "force must be 0 when a curve"),
    (dict(heights=(0.01, float("nan")), forces=(1.0, 2.0)), "heights must contain only finite"),
])
def test_bad_curve_names_the_field(kwargs, match):
    with pytest.raises(ValueError, match=match):
        po.ProcessForce(**kwargs)


def test_curve_in_mm_names_the_slip():
    with pytest.raises(ValueError, match=r"process_force.heights must be in .* got 10.0: a value in mm\? 10 mm is 0.01 m"):
        po.PressParams(process_force=po.ProcessForce(heights=(10.0, 30.0), forces=(1e3, 1e3)))


@pytest.mark.parametrize("kwargs, match", [
    (dict(force=-1.0), "force must be"),
    (dict(gas_length=0.0), "gas_length must be"),
    (dict(exponent=3.0), r"exponent must be in \[0, 2\]"),
])
def test_bad_counterbalance_names_the_field(kwargs, match):
    with pytest.raises(ValueError, match=match):
        po.Counterbalance(**kwargs)


def test_scenario_round_trips_curve_and_counterbalance(tmp_path):
    text = po.Scenario.load("press75").to_toml() + ""
    sc = po.Scenario.from_toml(text).with_overrides({
        "press.process_force.heights": [0.02, 0.04, 0.06], "press.process_force.forces": [0.0, 3000.0, 0.0],
        "press.counterbalance.force": 1500.0, "press.counterbalance.exponent": 1.4})
    back = po.Scenario.from_toml(sc.to_toml())
    assert back.press == sc.press
    assert back.press.process_force.forces == (0.0, 3000.0, 0.0)
    assert back.press.counterbalance == po.Counterbalance(force=1500.0, exponent=1.4)


def test_scenario_with_bad_counterbalance_names_the_key():
    with pytest.raises(po.ScenarioError, match="counterbalance.exponent"):
        po.Scenario.load("press75").with_overrides({"press.counterbalance.exponent": 5.0})


def test_a_window_in_h_over_stroke_sets_the_heights_for_the_stroke():
    """`ProcessForce(window=(a, b))` on a press: h_top = a x 2 r and h_bottom = b x 2 r (H = 2 r for
    the slider-crank), again for another crank radius; the force then equals the one given in
    metres at the same heights."""
    r = 0.06
    press = po.PressParams(crank_radius=r, process_force=po.ProcessForce(force=4000.0, window=(0.3, 0.05)))
    assert press.process_force.h_top == pytest.approx(0.3 * 2 * r, rel=1e-15)
    assert press.process_force.h_bottom == pytest.approx(0.05 * 2 * r, rel=1e-15)
    longer = press.with_value("crank_radius", 0.08)
    assert longer.process_force.h_top == pytest.approx(0.3 * 0.16, rel=1e-15)
    metres = po.PressParams(crank_radius=r, process_force=po.ProcessForce(force=4000.0, h_top=0.036, h_bottom=0.006))
    np.testing.assert_allclose(torque(press, THETA, OMEGA, ALPHA), torque(metres, THETA, OMEGA, ALPHA),
                               rtol=1e-12, atol=1e-9)


def test_scenario_round_trips_a_window_and_refuses_a_bad_one():
    sc = po.Scenario.load("forming40")
    assert sc.press.process_force.window == (0.5, 0.15)
    back = po.Scenario.from_toml(sc.to_toml())
    assert back.press == sc.press and "window = [0.5, 0.15]" in sc.to_toml()
    with pytest.raises(po.ScenarioError, match=r"window must be .*got \[15.0, 50.0\]"):
        sc.with_overrides({"press.process_force.window": [15.0, 50.0]})
    with pytest.raises(po.ScenarioError, match=r"values in %\? 50 % is 0.5"):
        sc.with_overrides({"press.process_force.window": [50.0, 15.0]})
    with pytest.raises(ValueError, match="a curve .* gives its own heights"):
        po.ProcessForce(heights=(0.0, 0.01), forces=(1.0, 2.0), window=(0.1, 0.0))
