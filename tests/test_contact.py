"""Contact law: finite values and derivatives everywhere, no tension, Hertz limit, C1 smoothness."""

import casadi as ca
import numpy as np
import pytest

from pressocp import Bearing
from pressocp.contact import contact_force

LAWS = [Bearing(), Bearing(law="kelvin-voigt"), Bearing(damping=30.0, tangential_damping=0.0)]


def _functions(b):
    e, ed = ca.SX.sym("e", 2), ca.SX.sym("ed", 2)
    cf = contact_force(b, e, ed)
    x = ca.vertcat(e, ed)
    out = ca.vertcat(cf.force, cf.vector_on_bearing)
    return ca.Function("f", [x], [out, ca.jacobian(out, x)])


@pytest.mark.parametrize("b", LAWS, ids=["hunt-crossley", "kelvin-voigt", "hc-no-film"])
def test_finite_values_and_derivatives_at_singular_points(b):
    f = _functions(b)
    c, eps = b.clearance, b.smoothing_width
    radii = [0.0, c, c - 1000 * eps, c + 1000 * eps, c - eps, c + eps, 1e-30, 1e-20]
    for rad in radii:
        for ang in (0.0, 1.0, np.pi):
            for rate in ((0.0, 0.0), (0.1, -0.3), (-5.0, 5.0)):
                x = [rad * np.cos(ang), rad * np.sin(ang), *rate]
                val, jac = (np.asarray(v) for v in f(x))
                assert np.all(np.isfinite(val)) and np.all(np.isfinite(jac)), (rad, ang, rate)
                assert val[0] >= 0.0  # no tension


@pytest.mark.parametrize("b", LAWS, ids=["hunt-crossley", "kelvin-voigt", "hc-no-film"])
def test_free_flight_has_no_force(b):
    f = _functions(b)
    for rad in (0.0, 0.5 * b.clearance, b.clearance - 50 * b.smoothing_width):
        val, _ = f([rad, 0.0, 0.2, 0.3])
        assert abs(float(val[0])) < 1e-12 * b.contact_stiffness * b.clearance**1.5


def test_hertz_force_at_rest_in_deep_contact():
    b = Bearing(tangential_damping=0.0)
    f = _functions(b)
    delta = 5e-6  # 50 smoothing widths: the smoothing is negligible
    val, _ = f([b.clearance + delta, 0.0, 0.0, 0.0])
    # penetration of the smoothed eccentricity sqrt(e^2 + eps^2) (the softplus adds < 1e-20 m here)
    pen = np.hypot(b.clearance + delta, b.smoothing_width) - b.clearance
    assert float(val[0]) == pytest.approx(b.contact_stiffness * pen**1.5, rel=1e-9)
    # force on the bearing points back toward the journal (-x)
    assert float(val[1]) == pytest.approx(-float(val[0]))


def test_hunt_crossley_damping_factor():
    b = Bearing(damping=3.0, tangential_damping=0.0)
    f = _functions(b)
    delta, rate = 4e-6, 0.05  # approaching: d delta/dt > 0
    val, _ = f([b.clearance + delta, 0.0, rate, 0.0])
    rho = np.hypot(b.clearance + delta, b.smoothing_width)
    pen, pen_rate = rho - b.clearance, (b.clearance + delta) * rate / rho
    assert float(val[0]) == pytest.approx(b.contact_stiffness * pen**1.5 * (1 + 3.0 * pen_rate), rel=1e-9)
    # separating fast: (1 + chi d) < 0 would pull; the law clips it to ~0
    val, _ = f([b.clearance + delta, 0.0, -2.0, 0.0])
    assert 0.0 <= float(val[0]) < 1e-2 * b.contact_stiffness * delta**1.5


def test_force_is_c1_across_contact_onset():
    b = Bearing()
    f = _functions(b)
    c, eps = b.clearance, b.smoothing_width
    r = np.linspace(c - 20 * eps, c + 20 * eps, 4001)
    F = np.array([float(f([x, 0, 0, 0])[0][0]) for x in r])
    dF = np.array([float(f([x, 0, 0, 0])[1][0, 0]) for x in r])
    assert np.all(np.diff(F) >= -1e-12)  # monotone in penetration
    # the derivative is continuous: neighbouring samples differ little relative to its range
    assert np.max(np.abs(np.diff(dF))) < 0.01 * np.max(np.abs(dF))
    # and it agrees with finite differences of the force
    assert np.allclose(np.gradient(F, r)[1:-1], dF[1:-1], rtol=1e-2, atol=1e-3 * np.max(dF))


def test_tangential_film_damping_only_in_contact():
    b = Bearing(tangential_damping=1e3)
    f = _functions(b)
    # in contact, tangential rate 0.01 m/s -> about -10 N along the tangent on the bearing
    val, _ = f([b.clearance + 5e-6, 0.0, 0.0, 0.01])
    assert float(val[2]) == pytest.approx(-1e3 * 0.01, rel=0.05)
    val, _ = f([0.5 * b.clearance, 0.0, 0.0, 0.01])
    assert abs(float(val[2])) < 1e-9


def test_a_new_contact_law_is_one_class_and_one_registry_line(monkeypatch):
    """A linear spring-dashpot law, written here as a user would add a module to `pressocp.laws`:
    registered, a bearing takes it by name (its default damping, its force in deep contact), a
    model builds with it and simulates; an unregistered name is refused with the valid ones."""
    from pressocp import FourierSpeed, PressParams, build_model, simulate
    from pressocp.laws import CONTACT_LAWS, ContactLaw, softplus

    class Linear(ContactLaw):
        name = "linear"
        damping_unit = "N s/m"

        def default_damping(self, stiffness, exponent):
            return 2e4

        def normal_force(self, elastic, delta, delta_dot, damping, eps, stiffness, exponent):
            return softplus(elastic + damping * delta_dot * delta / (delta + eps), stiffness * eps**exponent)

    with pytest.raises(ValueError, match="law must be one of 'hunt-crossley', 'kelvin-voigt'"):
        Bearing(law="linear")
    monkeypatch.setitem(CONTACT_LAWS, "linear", Linear())
    b = Bearing(law="linear", exponent=1.0, stiffness=2e8, tangential_damping=0.0)
    assert b.damping_value == 2e4
    val, _ = _functions(b)([b.clearance + 5e-6, 0.0, 0.0, 0.0])
    pen = np.hypot(b.clearance + 5e-6, b.smoothing_width) - b.clearance
    assert float(val[0]) == pytest.approx(2e8 * pen, rel=1e-9)
    model = build_model(PressParams(wrist_pin=Bearing(law="linear", exponent=1.0, stiffness=2e8,
                                                      journal_radius=0.025)), clearance=("wrist_pin",))
    run = simulate(model, FourierSpeed.constant(0.8), t_end=0.2)
    assert np.all(np.isfinite(run.wrist_pin_force)) and run.peak("wrist_pin_force") > 0
