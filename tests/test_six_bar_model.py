"""The six-bar drag-link press as a model (`pressocp.mechanism.SixBar` through `build_model`).

References: the numpy kinematics of `tests/references/sixbar.py` (a separate implementation), and for the
dynamics the power balance of the ideal press at constant input speed, tau = dE/dtheta, with the
energy of every body summed from the numpy joint positions (velocities by central differences).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pressocp import FourierSpeed, PressParams
from pressocp.mechanism import (
    SixBar,
    SixBarPress,
    mechanism_from_dict,
    mechanism_to_dict,
)
from pressocp.model import ModelSpec, build_model
from pressocp.simulate import Integrator, simulate
from tests.references.power_balance import assert_torque_is_power_balance
from tests.references.sixbar import sixbar_kinematics, sixbar_positions

OTHER = SixBarPress(ground_length=0.03, ground_angle=0.4, input_crank=0.12, coupler=0.11, output_link=0.09,
                    arm_phase=2.0, assembly=-1, crank_radius=0.03, rod_length=0.2)


def press_for(drive: SixBarPress) -> PressParams:
    return PressParams(crank_radius=drive.crank_radius, rod_length=drive.rod_length, crank_com=0.01)


def samples(model, speed, t):
    """The model's outputs at times t of a rigid press (no states)."""
    n = len(t)
    out = model.outputs.map(n)(t[None, :], np.zeros((0, n)), np.tile(model.parameters(speed)[:, None], (1, n)))
    return {k: np.asarray(v).ravel() for k, v in zip(model.outputs.name_out(), out)}


@pytest.mark.parametrize("drive", [SixBarPress(), OTHER], ids=["default", "other"])
def test_six_bar_ram_motion_equals_the_numpy_kinematics(drive):
    model = build_model(press_for(drive), clearance=(), mechanism=SixBar(drive))
    period = 0.8
    speed = FourierSpeed.constant(period, n_harmonics=model.n_harmonics)
    t = np.linspace(0.0, period, 97)
    y = samples(model, speed, t)
    k = sixbar_kinematics(drive, 2 * math.pi * t / period)
    w = 2 * math.pi / period
    assert np.allclose(y["ram_height"], k["ram_height"], rtol=0, atol=1e-12)
    assert np.allclose(y["ram_velocity"], k["dh_dtheta"] * w, rtol=0, atol=1e-9)
    assert np.allclose(y["ram_acceleration"], k["d2h_dtheta2"] * w**2, rtol=0, atol=1e-9 * w**2)


@pytest.mark.parametrize("drive", [SixBarPress(), OTHER], ids=["default", "other"])
def test_six_bar_motor_torque_is_the_power_balance_of_its_bodies(drive):
    """At constant input speed tau = dE/dtheta; E from the numpy joint positions of every body."""
    p = press_for(drive)
    mech = SixBar(drive, input_inertia=0.3, coupler_mass=4.0, coupler_inertia=0.02)
    model = build_model(p, clearance=(), mechanism=mech)
    period = 0.8
    w = 2 * math.pi / period

    def energy(theta):
        h = 1e-5

        def pos(th):
            q = sixbar_positions(drive, th)
            return q, sixbar_kinematics(drive, th)["psi"]

        (q_m, psi_m), (q_0, psi_0), (q_p, psi_p) = pos(theta - h), pos(theta), pos(theta + h)

        def vel(key_or_values):  # d/dt at constant input speed
            a, b = key_or_values
            return (b - a) / (2 * h) * w

        def angle(q, a, b):
            d = q[b] - q[a]
            return np.arctan2(d[..., 0], d[..., 1])

        def centre(q, a, b):
            return (q[a] + q[b]) / 2

        T = 0.5 * mech.input_inertia * w**2 + 0.5 * p.crank_inertia * vel((psi_m, psi_p)) ** 2
        V = p.crank_mass * p.gravity * p.crank_com * np.cos(psi_0)
        for (a, b), m, J in ((("A", "B"), mech.coupler_mass, mech.coupler_inertia),
                             (("C", "D"), p.rod_mass, p.rod_inertia_value)):
            v = vel((centre(q_m, a, b), centre(q_p, a, b)))
            T = T + 0.5 * m * np.sum(v**2, axis=-1) + 0.5 * J * vel((angle(q_m, a, b), angle(q_p, a, b))) ** 2
            V = V + m * p.gravity * centre(q_0, a, b)[..., 1]
        v_s = vel((q_m["D"], q_p["D"]))
        T = T + 0.5 * p.slider_mass * np.sum(v_s**2, axis=-1)
        return T + V + p.slider_mass * p.gravity * q_0["D"][..., 1]

    assert_torque_is_power_balance(model, period, energy)


def test_six_bar_with_clearances_keeps_its_energy_balance():
    """W_motor = dT + dV + contact work over an impacting run of the six-bar with both clearances."""
    mech = SixBar(input_inertia=0.3, coupler_mass=4.0)
    model = build_model(press_for(mech.drive), mechanism=mech)
    speed = FourierSpeed.constant(0.5, n_harmonics=model.n_harmonics)
    r = simulate(model, speed, t_end=0.5, integrator=Integrator(method="cvodes", rtol=1e-10), work=True)
    E = r.energy
    dE = E["kinetic_end"] + E["potential_end"] - E["kinetic_start"] - E["potential_start"]
    imbalance = E["motor_work"] + E["process_work"] - dE - E["contact_work"] - E["rod_damping_work"]
    assert abs(imbalance) <= 1e-4 * max(abs(E["motor_work"]), abs(dE), abs(E["contact_work"]))
    assert E["contact_work"] - E["contact_elastic_work"] > 0  # the journals hit and dissipate


def test_a_six_bar_model_level_reads_back_from_plain_data():
    mech = SixBar(OTHER, input_inertia=0.3, coupler_mass=4.0)
    spec = ModelSpec("rigid", ("wrist_pin",), mechanism=mech)
    assert ModelSpec.from_dict(spec.to_dict()) == spec
    assert mechanism_from_dict(mechanism_to_dict(mech)) == mech
    assert spec.describe() == "six-bar press, rigid rod, clearance in wrist_pin"
    assert "mechanism" not in ModelSpec().to_dict()  # a slider-crank level reads as before


def test_a_six_bar_whose_press_crank_differs_from_the_press_fails_before_building():
    with pytest.raises(ValueError, match=r"crank_radius = 0.05 m of the press differs .* 0.03 m"):
        build_model(PressParams(), mechanism=SixBar(OTHER))
    with pytest.raises(ValueError, match="coupler_mass"):
        SixBar(coupler_mass=-1.0)


def six_bar_problem(mech: SixBar, **kwargs):
    from pressocp import SpeedProblem

    return SpeedProblem(press_for(mech.drive), period=0.8, ram_speed=-0.1, mechanism=mech, **kwargs)


def test_a_model_of_another_mechanism_than_the_problem_fails_before_any_solve():
    from pressocp import optimize_speed

    problem = six_bar_problem(SixBar())
    with pytest.raises(ValueError, match="model.mechanism must be the problem's"):
        optimize_speed(problem, build_model(problem.press))


@pytest.mark.slow  # 10-19 s; the six-bar's kinematics by default
def test_the_six_bar_kinematic_design_holds_the_ram_speed_in_its_window():
    """The design's ram speed over the window, from the numpy kinematics of the input speed, within
    the design's band (half the tolerance) of the asked speed."""
    from pressocp import design_speed

    mech = SixBar()
    problem = six_bar_problem(mech)
    d = design_speed(problem)
    assert d.converged
    t = np.linspace(d.t1, d.t2, 2001)
    theta, omega, _ = d.speed.evaluate(t)
    v = sixbar_kinematics(mech.drive, theta)["dh_dtheta"] * omega
    assert np.max(np.abs(v - problem.ram_speed)) <= 0.5 * problem.tol * (1 + 1e-3)
    h = sixbar_kinematics(mech.drive, theta[[0, -1]])["ram_height"]
    h1, h2 = problem.window_heights
    assert h[0] == pytest.approx(h1, abs=1e-9)  # the window starts at h1 on the downstroke
    assert h[1] == pytest.approx(h2, abs=0.5 * problem.tol * problem.window_duration)


@pytest.mark.slow  # 26 s
def test_the_six_bar_rigid_optimum_is_verified_on_its_own_model():
    """optimize_speed on the ideal six-bar: converged and verified, its peak torque that of the six-bar's
    Lagrangian model (`PressModel.ideal_series`, a derivation apart from the closed forms the NLP uses),
    the ram speed in the window by the numpy kinematics, and the peak lower than the design's."""
    from pressocp import Rigid, Strategy, design_speed, optimize_speed

    mech = SixBar(input_inertia=0.3, coupler_mass=4.0)
    problem = six_bar_problem(mech)
    model = build_model(problem.press, clearance=(), mechanism=mech)
    r = optimize_speed(problem, model, strategy=Strategy(rigid=Rigid(samples=400)), progress=False)
    assert r.success and r.verified
    t = np.linspace(0.0, problem.period, 8001)
    peak = np.max(np.abs(model.ideal_series(r.speed, t)["torque"]))
    assert r.peak_torque == pytest.approx(peak, rel=1e-4)
    assert peak < 0.8 * np.max(np.abs(model.ideal_series(design_speed(problem).speed, t)["torque"]))
    tw = np.linspace(r.t1, r.t2, 2001)
    theta, omega, _ = r.speed.evaluate(tw)
    v = sixbar_kinematics(mech.drive, theta)["dh_dtheta"] * omega
    assert np.max(np.abs(v - problem.ram_speed)) <= problem.tol * (1 + 1e-3)


@pytest.mark.slow  # about 4 minutes on 2 cores
def test_the_six_bar_clearance_optimum_is_verified():
    """The default chain on the six-bar with both clearances (collocation on the clearance model):
    converged, verified by periodic re-simulation, the ram speed within tolerance."""
    from pressocp import optimize_speed

    r = optimize_speed(six_bar_problem(SixBar(input_inertia=0.3, coupler_mass=4.0)), progress=False)
    assert r.success and r.verified and r.periodic
    assert r.max_ram_speed_violation == 0.0


@pytest.mark.slow  # 7-12 s
def test_sensitivities_of_a_six_bar_differentiate_the_six_bar():
    """The peak the sensitivities differentiate is the six-bar's own (its model rebuilt with the
    parameter carried keeps its mechanism), and the derivative matches central differences of its
    periodic peak."""
    from pressocp import sensitivities

    mech = SixBar(input_inertia=0.3, coupler_mass=4.0)
    press = press_for(mech.drive)
    speed = FourierSpeed.constant(0.8)

    def peak(mass):
        m = build_model(press.with_value("slider_mass", mass), clearance=("wrist_pin",), mechanism=mech)
        return simulate(m, speed, periodic=True, integrator=Integrator("cvodes", rtol=1e-10), n_out=8001).peak("torque")

    s = sensitivities(build_model(press, clearance=("wrist_pin",), mechanism=mech), speed, ("slider_mass",), rtol=1e-9)
    row = s.table.iloc[0]
    assert row["value"] == pytest.approx(peak(press.slider_mass), rel=1e-4)
    h = 0.01 * press.slider_mass
    fd = (peak(press.slider_mass + h) - peak(press.slider_mass - h)) / (2 * h)
    assert row["derivative"] == pytest.approx(fd, rel=2e-3)
