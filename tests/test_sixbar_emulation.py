"""The four-bar with a fitted 15-harmonic speed reproduces the six-bar drag-link stroke (Fig. 5 of the source paper)."""

import numpy as np

from pressocp import PressParams
from pressocp.design import emulate_sixbar
from pressocp.mechanism import SixBar, SixBarPress, constant_speed_zone
from pressocp.plots import plot_sixbar_emulation, save
from tests.references.press import exact_height
from tests.references.sixbar import (
    sixbar_kinematics,
    working_zone_interval,
    working_zone_speed,
)


def test_fourbar_follows_sixbar(tmp_path):
    p = PressParams()
    e = emulate_sixbar(p, period=1.0)
    # independent re-evaluation of the four-bar stroke with the hand-written closed form
    h4 = exact_height(p, e["speed"].theta(e["t"]))
    assert np.max(np.abs(h4 - e["h_sixbar"])) < 0.005 * p.stroke
    assert e["speed"].min_speed() > 0  # no crank reversal needed
    # the reference itself has the slow, nearly constant working zone
    zone = constant_speed_zone(PressParams(), SixBar(), 1.0)
    assert zone.max_deviation <= 0.05
    fig = plot_sixbar_emulation(e, zone_times=(zone.t_start, zone.t_end))
    save(fig, tmp_path / "sixbar.png")
    assert (tmp_path / "sixbar.png").stat().st_size > 10_000


def test_fewer_harmonics_converge():
    errs = [emulate_sixbar(PressParams(), n_harmonics=n)["max_position_error"] for n in (3, 6, 12)]
    assert errs[0] > errs[1] > errs[2]


def test_the_six_bar_side_of_the_emulation_is_its_model():
    """The six-bar's stroke in the emulation equals the numpy kinematics, and its torque on ideal joints
    is the power balance of the slider-crank part driven through the four-bar: with only the press
    crank's inertia and no gravity, tau = J psi' psi'' / theta' (constant input speed)."""
    p = PressParams(rod_mass=1e-3, slider_mass=1e-3, gravity=0.0)  # the lightest allowed
    e = emulate_sixbar(p, SixBar(), period=1.0, n=401)
    k = sixbar_kinematics(SixBarPress(), 2 * np.pi * e["t"])
    assert np.allclose(e["h_sixbar"], k["ram_height"], rtol=0, atol=1e-12)
    w = 2 * np.pi
    tau = p.crank_inertia * k["dpsi_dtheta"] * k["d2psi_dtheta2"] * w**2
    assert np.allclose(e["torque_sixbar"], tau, rtol=0, atol=2e-4 * np.max(np.abs(tau)))  # 1 g rod and slider


def test_the_working_zone_equals_the_numpy_reference():
    """`constant_speed_zone` through the CasADi six-bar against the numpy reference's zone functions,
    and its input angle at top dead centre against the reference's inverse four-bar."""
    from tests.references.sixbar import theta_offset

    other = SixBarPress(ground_length=0.03, ground_angle=0.4, input_crank=0.12, coupler=0.11, output_link=0.09,
                        arm_phase=2.0, assembly=-1, crank_radius=0.03, rod_length=0.2)
    for drive in (SixBarPress(), other):
        press = PressParams(crank_radius=drive.crank_radius, rod_length=drive.rod_length)
        zone = constant_speed_zone(press, SixBar(drive), 0.9, (0.3, 0.15))
        assert np.allclose((zone.t_start, zone.t_end), working_zone_interval(drive, 0.9, (0.3, 0.15)), rtol=0,
                           atol=1e-12)
        assert np.allclose((zone.mean_speed, zone.max_deviation), working_zone_speed(drive, 0.9, (0.3, 0.15)),
                           rtol=1e-9, atol=1e-12)
        assert abs(np.angle(np.exp(1j * (drive.input_at_top_dead_centre - theta_offset(drive))))) < 1e-12
