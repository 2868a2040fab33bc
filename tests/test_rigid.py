"""Rigid slider-crank against independent references.

* kinematics against finite differences of positions written out here by hand;
* inverse dynamics against a separately written Newton-Euler solution (tests/references) and the
  published Flores & Ambrosio extremes (shared/reference/benchmarks.md, section 2);
* energy: the motor work over a cycle is zero at constant speed and gravity 0.
"""

import numpy as np
import pytest

from pressocp import FourierSpeed, PressParams, crank_angle_at_height, rigid_kinematics, rigid_response
from pressocp.rigid import rigid_inverse_dynamics
from tests.references.press import exact_height, newton_euler

FLORES_RPM = 5000.0


def test_dead_centres():
    p = PressParams()
    k = rigid_kinematics(p, np.array([0.0, np.pi]))
    assert k["ram_height"] == pytest.approx([p.stroke, 0.0], abs=1e-15)


def test_kinematics_against_finite_differences():
    p = PressParams(crank_radius=0.07, rod_length=0.2)
    s = FourierSpeed(0.9, [1.0, -0.4, 0.2], [0.5, 0.3, -0.1])
    t = np.linspace(0, 0.9, 61)
    d = 1e-5
    th, om, al = s.evaluate(t)
    k = rigid_kinematics(p, th, om, al)
    hp, hm, h0 = (exact_height(p, s.theta(t + x)) for x in (d, -d, 0.0))
    assert np.allclose(k["ram_height"], h0, atol=1e-15)
    assert np.allclose(k["ram_velocity"], (hp - hm) / (2 * d), atol=1e-8)
    assert np.allclose(k["ram_acceleration"], (hp - 2 * h0 + hm) / d**2, atol=2e-4)
    # rod angle: sin phi = r sin theta / l
    assert np.allclose(np.sin(k["rod_angle"]), p.crank_radius * np.sin(th) / p.rod_length, atol=1e-14)
    phip = np.arcsin(p.crank_radius * np.sin(s.theta(t + d)) / p.rod_length)
    phim = np.arcsin(p.crank_radius * np.sin(s.theta(t - d)) / p.rod_length)
    assert np.allclose(k["rod_angular_velocity"], (phip - phim) / (2 * d), atol=1e-7)


def test_crank_angle_at_height_inverts_kinematics():
    p = PressParams()
    th = np.linspace(0.0, np.pi, 50)
    h = exact_height(p, th)
    assert np.allclose(crank_angle_at_height(p, h, "down"), th, atol=1e-7)
    assert np.allclose(crank_angle_at_height(p, h, "up"), 2 * np.pi - th, atol=1e-7)
    with pytest.raises(ValueError, match="height"):
        crank_angle_at_height(p, 0.2)
    with pytest.raises(ValueError, match="stroke"):
        crank_angle_at_height(p, 0.05, "sideways")


@pytest.mark.parametrize("press", ["flores", "default", "default-heavy-crank"])
def test_inverse_dynamics_againstnewton_euler(press):
    p = {"flores": PressParams.flores(), "default": PressParams(),
         "default-heavy-crank": PressParams(crank_com=0.02, gravity=9.81)}[press]
    s = FourierSpeed(0.7, [2.0, -1.0, 0.4], [1.0, 0.5, -0.3], theta0=0.2)
    t = np.linspace(0, 0.7, 301)
    r = rigid_response(p, s, t)
    ref = newton_euler(p, *s.evaluate(t))
    for name in ("torque", "crank_pin_force", "wrist_pin_force", "slider_normal_force", "ram_height",
                 "ram_velocity", "ram_acceleration"):
        scale = np.max(np.abs(ref[name]))
        assert np.max(np.abs(getattr(r, name) - ref[name])) <= 1e-10 * scale, name
    out = rigid_inverse_dynamics(p, *s.evaluate(t))
    for name in ("crank_pin_tension", "wrist_pin_tension"):
        scale = np.max(np.abs(ref[name]))
        assert np.max(np.abs(out[name] - ref[name])) <= 1e-10 * scale, name


def test_wrist_pin_tension_carries_the_slider():
    """Slider equilibrium: the rod pulls it with (-N, m_s (g + a)) (N the guide force, a the ram
    acceleration); the tension is that force along the rod axis (sin phi, cos phi)."""
    p = PressParams()
    th, om, al = np.linspace(0, 2 * np.pi, 13), 16.0, -30.0  # TDC: r w^2 (1 - r/l) > g
    out = rigid_inverse_dynamics(p, th, om, al)
    phi = rigid_kinematics(p, th, om, al)["rod_angle"]
    pull = -out["slider_normal_force"] * np.sin(phi) + p.slider_mass * (p.gravity + out["ram_acceleration"]) * np.cos(phi)
    np.testing.assert_allclose(out["wrist_pin_tension"], pull, rtol=1e-10, atol=1e-9)
    assert out["wrist_pin_tension"].min() < 0 < out["wrist_pin_tension"].max()  # this motion reverses


def test_flores_published_extremes():
    p = PressParams.flores()
    s = FourierSpeed.constant(60.0 / FLORES_RPM)
    r = rigid_response(p, s, np.linspace(0, s.period, 20001))
    assert r.torque.max() == pytest.approx(138.5, rel=2e-3)
    assert r.torque.min() == pytest.approx(-138.5, rel=2e-3)
    assert r.crank_pin_force.max() == pytest.approx(6.20e3, rel=2e-3)
    assert r.wrist_pin_force.max() == pytest.approx(2.72e3, rel=2e-3)
    assert r.peak("slider_normal_force") == pytest.approx(1.10e3, rel=3e-3)
    w = 2 * np.pi * FLORES_RPM / 60
    assert r.peak("ram_acceleration") == pytest.approx(0.05 * w**2 * (1 + 0.05 / 0.12), rel=1e-9)


def test_motor_work_vanishes_at_constant_speed_without_gravity():
    p = PressParams(gravity=0.0)
    s = FourierSpeed.constant(1.0)
    # uniform periodic grid with an arbitrary start: the trapezoid rule is spectrally accurate
    t = 0.1234 + np.linspace(0, 1, 4000, endpoint=False)
    r = rigid_response(p, s, t)
    power = r.torque * r.omega
    work = power.sum() * (t[1] - t[0])
    assert abs(work) <= 1e-9 * np.sum(np.abs(power)) * (t[1] - t[0])


def test_power_equals_rate_of_energy():
    p = PressParams(crank_com=0.01)
    s = FourierSpeed(1.0, [3.0, 1.0], [-2.0, 0.5])
    t = np.linspace(0.05, 0.95, 91)
    d = 1e-6
    e = lambda tt: sum(rigid_inverse_dynamics(p, *s.evaluate(tt))[k] for k in ("kinetic_energy", "potential_energy"))
    r = rigid_response(p, s, t)
    dE = (e(t + d) - e(t - d)) / (2 * d)
    assert np.allclose(r.torque * r.omega, dE, rtol=0, atol=1e-6 * np.max(np.abs(dE)))


def test_theta_advances_one_revolution():
    s = FourierSpeed(1.0, [3.0, 1.0], [-2.0, 0.5])
    r = rigid_response(PressParams(), s, np.array([0.0, 1.0]))
    assert r.theta[1] - r.theta[0] == pytest.approx(2 * np.pi, abs=1e-12)


def test_process_force_adds_torque_only_in_window():
    from pressocp import ProcessForce

    pf = ProcessForce(force=1e5, h_top=0.02, h_bottom=0.0)
    p0, p1 = PressParams(gravity=0.0), PressParams(gravity=0.0, process_force=pf)
    s = FourierSpeed.constant(1.0)
    t = np.linspace(0, 1, 2001)
    r0, r1 = rigid_response(p0, s, t), rigid_response(p1, s, t)
    dtau = r1.torque - r0.torque
    # static equivalence: extra torque = -F * dh/dtheta in the window on the downstroke
    inside = (r0.ram_height < 0.015) & (r0.ram_height > 0.005) & (r0.ram_velocity < -0.01)
    dh_dth = r0.ram_velocity / r0.omega
    assert np.allclose(dtau[inside], -1e5 * dh_dth[inside], rtol=1e-3)
    assert np.allclose(dtau[r0.ram_height > 0.03], 0.0, atol=1e-6)
    assert np.allclose(dtau[r0.ram_velocity > 0.01], 0.0, atol=1e-3)


@pytest.mark.parametrize("name", ["theta", "omega", "alpha"])
def test_nonfinite_motion_rejected(name):
    args = {"theta": 0.1, "omega": 1.0, "alpha": 0.0}
    args[name] = float("nan")
    with pytest.raises(ValueError, match=name):
        rigid_inverse_dynamics(PressParams(), **args)
