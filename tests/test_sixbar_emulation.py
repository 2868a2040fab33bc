"""The four-bar with a fitted 15-harmonic speed reproduces the six-bar drag-link stroke (Fig. 5 of the source paper)."""

import numpy as np

from pressocp import PressParams
from pressocp.design import emulate_sixbar
from pressocp.plots import plot_sixbar_emulation, save
from pressocp.sixbar import SixBarPress, working_zone_interval, working_zone_speed
from tests.references.press import exact_height


def test_fourbar_follows_sixbar(tmp_path):
    p = PressParams()
    e = emulate_sixbar(p, period=1.0)
    # independent re-evaluation of the four-bar stroke with the hand-written closed form
    h4 = exact_height(p, e["speed"].theta(e["t"]))
    assert np.max(np.abs(h4 - e["h_sixbar"])) < 0.005 * p.stroke
    assert e["speed"].min_speed() > 0  # no crank reversal needed
    # the reference itself has the slow, nearly constant working zone
    speed, dev = working_zone_speed(SixBarPress(), 1.0)
    assert dev <= 0.05
    fig = plot_sixbar_emulation(e, zone_times=working_zone_interval(SixBarPress(), 1.0))
    save(fig, tmp_path / "sixbar.png")
    assert (tmp_path / "sixbar.png").stat().st_size > 10_000


def test_fewer_harmonics_converge():
    errs = [emulate_sixbar(PressParams(), n_harmonics=n)["max_position_error"] for n in (3, 6, 12)]
    assert errs[0] > errs[1] > errs[2]


def test_the_six_bar_side_of_the_emulation_is_its_model():
    """The six-bar's stroke in the emulation equals the numpy kinematics, and its torque on ideal joints
    is the power balance of the slider-crank part driven through the four-bar: with only the press
    crank's inertia and no gravity, tau = J psi' psi'' / theta' (constant input speed)."""
    from pressocp.mechanism import SixBar
    from pressocp.sixbar import sixbar_kinematics

    p = PressParams(rod_mass=1e-3, slider_mass=1e-3, gravity=0.0)  # the lightest allowed
    e = emulate_sixbar(p, SixBar(), period=1.0, n=401)
    k = sixbar_kinematics(SixBarPress(), 2 * np.pi * e["t"])
    assert np.allclose(e["h_sixbar"], k["ram_height"], rtol=0, atol=1e-12)
    w = 2 * np.pi
    tau = p.crank_inertia * k["dpsi_dtheta"] * k["d2psi_dtheta2"] * w**2
    assert np.allclose(e["torque_sixbar"], tau, rtol=0, atol=2e-4 * np.max(np.abs(tau)))  # 1 g rod and slider
