"""PressParams / Bearing validation and derived values."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pressocp import Bearing, PressParams, ProcessForce, SpeedProblem, hertz_internal_stiffness
from pressocp.checks import PlausibilityWarning


def test_default_press_values():
    p = PressParams()
    assert p.stroke == pytest.approx(0.1)
    # 40 x 40 mm steel rod, 0.25 m: mass and area moment
    assert p.rod_mass == pytest.approx(0.04 * 0.04 * 0.25 * 7850, rel=1e-3)
    assert p.rod_area_moment == pytest.approx(0.04**4 / 12, rel=2e-3)
    assert p.rod_inertia_value == pytest.approx(3.14 * 0.25**2 / 12)


def test_hertz_stiffness_reference():
    # benchmarks.md section 3: steel, Rb = 10.5 mm, Rj = 10 mm, E = 207 GPa -> K = 6.95e10 N/m^1.5
    K = hertz_internal_stiffness(0.010, 0.0005, youngs_modulus=207e9, poisson=0.3)
    assert K == pytest.approx(6.95e10, rel=2e-3)
    # default crank pin (R 40 mm, c 0.1 mm, E = 2.1e11): 6.16e11 (prototype findings)
    assert PressParams().crank_pin.contact_stiffness == pytest.approx(6.16e11, rel=2e-3)
    assert PressParams().wrist_pin.contact_stiffness == pytest.approx(3.85e11, rel=3e-3)


def test_bearing_defaults_and_restitution():
    b = Bearing(clearance=2e-4)
    assert b.smoothing_width == pytest.approx(2e-7)
    assert b.damping_value == pytest.approx(3.0)
    hc = Bearing.from_restitution(0.9, 0.05)
    assert hc.damping_value == pytest.approx(3 * (1 - 0.9) / (2 * 0.05))
    ln = Bearing.from_restitution(0.8, 0.1, model="lankarani-nikravesh")
    assert ln.damping_value == pytest.approx(0.75 * (1 - 0.64) / 0.1)
    kv = Bearing(law="kelvin-voigt")
    assert kv.damping_value == pytest.approx(3.0 * kv.contact_stiffness * 1e-6**1.5)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(rod_length=0.05), "rod_length"),
        (dict(rod_length=0.01), "rod_length"),
        (dict(crank_radius=0.0), "crank_radius"),
        (dict(crank_radius=-0.05), "crank_radius"),
        (dict(slider_mass=0.0), "slider_mass"),
        (dict(rod_mass=-1.0), "rod_mass"),
        (dict(crank_inertia=0.0), "crank_inertia"),
        (dict(gravity=float("nan")), "gravity"),
        (dict(rod_youngs_modulus=float("inf")), "rod_youngs_modulus"),
        (dict(crank_com=float("nan")), "crank_com"),
    ],
)
def test_bad_press_params(kwargs, field):
    with pytest.raises(ValueError, match=field):
        PressParams(**kwargs)


def test_bad_press_params_message_names_range():
    with pytest.raises(ValueError, match=r"rod_length must be in \[1.5 x crank_radius = 0.075, 5\] m, got 0.04"):
        PressParams(rod_length=0.04)


@pytest.mark.parametrize("make, match", [
    (lambda: PressParams(crank_radius=80, rod_length=400), r"crank_radius must be in \[0.001, 5\] m, got 80.*80 mm is 0.08 m"),
    (lambda: PressParams(rod_length=250.0), r"rod_length must be in .*250 mm is 0.25 m"),
    (lambda: PressParams(rod_length=0.06), r"rod_length must be in \[1.5 x crank_radius"),
    (lambda: PressParams(slider_mass=150000.0), r"slider_mass must be in \[0.001, 100000\] kg.*150000 g is 150 kg"),
    (lambda: Bearing(clearance=0.15), r"clearance must be in \[1e-06, 0.004\] m \(10% of journal_radius=0.04 m\), got 0.15: "
                                       r"a clearance in mm\? 0.15 mm is 0.00015 m"),
    (lambda: Bearing(journal_radius=25.0), r"journal_radius must be in .*25 mm is 0.025 m"),
    (lambda: Bearing(clearance=0.0026, journal_radius=0.025), r"got 0.0026$"),
    (lambda: Bearing(stiffness=10.0), r"stiffness must be in \[10000, 1e\+16\]"),
    (lambda: Bearing(clearance=5e-324), r"clearance must be in \[1e-06, 0.004\] m .*got 5e-324: below a micrometre"),
    (lambda: Bearing(clearance=1e-7), r"got 1e-07: below a micrometre the joint is ideal"),
    (lambda: PressParams(gravity=9810), r"gravity must be in \[0, 100\] m/s\^2.*9810 mm/s\^2 is 9.81 m/s\^2"),
    (lambda: PressParams(rod_youngs_modulus=210), r"rod_youngs_modulus must be in .*210 GPa is 2.1e\+11 Pa"),
    (lambda: PressParams(rod_youngs_modulus=210e3), r"210000 MPa is 2.1e\+11 Pa"),
    (lambda: PressParams(crank_com=25), r"crank_com must be in .*25 mm is 0.025 m"),
    (lambda: PressParams(crank_inertia=5e5), r"crank_inertia must be in .*500000 kg mm\^2 is 0.5 kg m\^2"),
    (lambda: PressParams(rod_area_moment=213), r"rod_area_moment must be in .*213 mm\^4 is 2.13e-10 m\^4; "
                                                r"213 cm\^4 is 2.13e-06 m\^4"),
    (lambda: PressParams(process_force=ProcessForce(force=1e4, h_top=12.7, h_bottom=0.0)),
     r"process_force.h_top must be in .*12.7 mm is 0.0127 m"),
])
def test_implausible_values_name_the_likely_unit_slip(make, match):
    """A press described in mm (or grams) is refused at construction, with the value in metres."""
    with pytest.raises(ValueError, match=match):
        make()


def test_a_bound_itself_is_allowed_despite_rounding():
    """rod_length = 1.5 x crank_radius exactly (0.075 against 1.5 x 0.05 = 0.07500000000000001)."""
    assert PressParams(rod_length=0.075).rod_length == 0.075


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(clearance=0.0), "clearance"),
        (dict(clearance=-1e-4), "clearance"),
        (dict(clearance=1e-4, smoothing=1e-4), "smoothing"),
        (dict(clearance=1e-4, smoothing=2e-4), "smoothing"),
        (dict(journal_radius=float("nan")), "journal_radius"),
        (dict(exponent=0.5), "exponent"),
        (dict(law="elastic"), "law"),
        (dict(damping=-1.0), "damping"),
        (dict(stiffness=float("inf")), "stiffness"),
    ],
)
def test_bad_bearing(kwargs, field):
    with pytest.raises(ValueError, match=field):
        Bearing(**kwargs)


def test_bad_process_force():
    with pytest.raises(ValueError, match="h_bottom"):
        ProcessForce(force=1e3, h_top=0.01, h_bottom=0.02)
    with pytest.raises(ValueError, match="restitution"):
        Bearing.from_restitution(1.5, 0.1)


@settings(max_examples=60, deadline=None)
@given(
    field=st.sampled_from(["crank_radius", "rod_length", "crank_inertia", "rod_mass", "slider_mass",
                           "rod_youngs_modulus", "rod_area_moment"]),
    value=st.one_of(st.just(float("nan")), st.just(float("inf")), st.just(-float("inf")),
                    st.floats(max_value=0.0, allow_nan=False)),
)
def test_fuzz_nonpositive_or_nonfinite_rejected(field, value):
    with pytest.raises(ValueError, match=field):
        PressParams(**{field: value})


@settings(max_examples=40, deadline=None)
@given(r=st.floats(0.01, 0.5), ratio=st.floats(1.5, 10.0))
def test_fuzz_valid_geometry_accepted(r, ratio):
    p = PressParams(crank_radius=r, rod_length=r * ratio)
    assert math.isclose(p.stroke, 2 * r)
    assert np.isfinite(p.rod_inertia_value)


def test_a_parameter_set_by_its_dotted_name():
    press = PressParams()
    worn = press.with_value("wrist_pin.clearance", 2e-4).with_value("slider_mass", 180.0)
    assert worn.value("wrist_pin.clearance") == 2e-4 and worn.value("slider_mass") == 180.0
    assert worn.crank_pin == press.crank_pin and press.value("wrist_pin.clearance") == 1e-4
    with pytest.raises(ValueError, match="slider_mass"):
        press.with_value("slider_mas", 1.0)
    with pytest.raises(ValueError):
        press.with_value("wrist_pin.clearance", -1e-4)


def test_numbers_are_converted_at_the_door():
    """Strings, ints and numpy scalars become floats (so arithmetic is arithmetic); a bool or a word
    is refused with the field's name."""
    import numpy as np

    from pressocp import Bearing, PressParams, SpeedProblem

    b = Bearing(stiffness="1e11", clearance=np.float32(1e-4))
    assert b.contact_stiffness * 2 == 2e11 and type(b.stiffness) is float and type(b.clearance) is float
    p = PressParams(crank_inertia="0.5", slider_mass=150)
    assert p.crank_inertia == 0.5 and type(p.crank_inertia) is float and type(p.slider_mass) is float
    assert SpeedProblem(p, ram_speed="-0.1").ram_speed == -0.1
    with pytest.raises(ValueError, match="gravity must be a finite real number, got the bool True"):
        PressParams(gravity=True)
    with pytest.raises(ValueError, match="rod_mass must be a finite real number, got 'heavy'"):
        PressParams(rod_mass="heavy")


@pytest.mark.parametrize("call, match", [
    (lambda p, prob, s: __import__("pressocp").design_speed(p), "problem must be a SpeedProblem, got PressParams: wrap"),
    (lambda p, prob, s: __import__("pressocp").build_model(prob), "params must be a PressParams, got SpeedProblem: pass"),
    (lambda p, prob, s: __import__("pressocp").rigid_response(prob, s), "params must be a PressParams, got SpeedProblem"),
    (lambda p, prob, s: __import__("pressocp").optimize_speed(p), "problem must be a SpeedProblem, got PressParams"),
    (lambda p, prob, s: __import__("pressocp").simulate(p, s), "model must be a PressModel, got PressParams: build"),
])
def test_the_wrong_object_is_a_type_error_that_says_what_to_pass(call, match):
    """Passing the press where the problem belongs (and the like) fails at once with a TypeError (also a
    ValueError, as bad input) naming the argument and what to pass instead; nothing is solved."""
    from pressocp import FourierSpeed, PressParams, SpeedProblem

    p = PressParams()
    prob, s = SpeedProblem(p, period=0.8), FourierSpeed.constant(0.8)
    with pytest.raises(TypeError, match=match) as err:
        call(p, prob, s)
    assert isinstance(err.value, ValueError)


@pytest.mark.parametrize("make, match", [
    (lambda: PressParams(rod_mass=3140.0), "rod_mass = 3140 kg .* a value in g\\? 3140 g is 3.14 kg"),
    (lambda: PressParams(crank_mass=20000.0), "crank_mass = 20000 kg .* a value in g\\?"),
    (lambda: PressParams(process_force=ProcessForce(force=1e9, h_top=0.05, h_bottom=0.0)),
     "process_force.force = 1e\\+09 N .* a value in mN\\?"),
    (lambda: Bearing(stiffness=6e8), "stiffness = 6e\\+08 N/m\\^1.5 is 0.000974 x the Hertz stiffness"),
    (lambda: SpeedProblem(PressParams(), period=0.8, omega_max=400.0), "omega_max = 400 rad/s .* in rpm\\? 400 rpm is 41.89"),
    # 75 strokes/min typed as the crank's speed in rad/s: 2 pi x 75 / 60 = 7.854 rad/s, a period of 60 / 7.854 s
    (lambda: SpeedProblem(PressParams(), period=60.0 / 7.854), r"period = 7.639 s is 7.85 strokes/min .* a crank "
     r"speed in rad/s\? 7.85 rad/s is 75 strokes/min \(period 0.8 s\)"),
])
def test_a_value_in_range_but_out_of_proportion_warns_of_its_unit(make, match):
    with pytest.warns(PlausibilityWarning, match=match):
        make()


def test_plausible_values_do_not_warn():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        PressParams(rod_mass=20.0, crank_mass=100.0, crank_pin=Bearing(stiffness=1e11),
                    process_force=ProcessForce(force=5e4, h_top=0.05, h_bottom=0.0))
        SpeedProblem(PressParams(), period=0.8, omega_max=15.0)
        SpeedProblem(PressParams(), period=3.9, ram_speed=-0.05)  # 15.4 strokes/min: slow, but plausible


def test_a_process_force_window_outside_the_stroke_warns():
    with pytest.warns(PlausibilityWarning, match=r"process_force acts for heights in \[0.12, 0.15\] m, outside"):
        PressParams(process_force=ProcessForce(force=1e4, h_top=0.15, h_bottom=0.12))  # stroke 0.1 m


def window_needs(press, v, tol, window):
    """Crank speeds the window needs, from the slider-crank's height written out here (the wrist pin
    below the crank axis, at y = r cos th - sqrt(l^2 - r^2 sin^2 th); h = y + r + l), on the downstroke
    th in (0, pi)."""
    r, l = press.crank_radius, press.rod_length
    th = np.linspace(1e-6, np.pi - 1e-6, 200001)
    root = np.sqrt(l**2 - r**2 * np.sin(th) ** 2)
    h = r * np.cos(th) - root + r + l
    dh = np.abs(-r * np.sin(th) + r**2 * np.sin(th) * np.cos(th) / root)
    inside = (h <= window[0] * 2 * r) & (h >= window[1] * 2 * r)
    return ((abs(v) - tol) / dh[inside]).max(), ((abs(v) + tol) / dh[inside]).min()


def test_speed_limits_that_leave_no_speed_for_the_window_are_refused_naming_the_need():
    """omega_max below the crank speed the window's ram speed needs (or omega_min above it) has no
    solution: refused before any solve, naming the need; 1 % under the need (the margin for
    clearances and a flexible rod) is accepted."""
    from pressocp.problem import ram_speed_range

    press = PressParams()
    fast = 0.8 * ram_speed_range(press, 0.8, (0.7, 0.3))[0]  # the window crossed at about 2.4 x the mean speed
    base = SpeedProblem(press, period=0.8, ram_speed=fast)
    most, _ = window_needs(press, base.ram_speed, base.tol, base.window)
    assert most > 2 * np.pi / 0.8  # omega_max must exceed the mean speed anyway
    SpeedProblem(press, period=0.8, ram_speed=fast, omega_max=0.995 * most)
    with pytest.raises(ValueError, match=rf"omega_max must be in \[{most:.4g}, inf\) rad/s, got .*raise omega_max"):
        SpeedProblem(press, period=0.8, ram_speed=fast, omega_max=0.98 * most)
    slow = SpeedProblem(press, period=0.8)
    _, least = window_needs(press, slow.ram_speed, slow.tol, slow.window)
    assert least < 2 * np.pi / 0.8  # omega_min must be below the mean speed anyway
    SpeedProblem(press, period=0.8, omega_min=1.005 * least)
    with pytest.raises(ValueError, match=rf"omega_min must be in \(0, {least:.4g}\] rad/s"):
        SpeedProblem(press, period=0.8, omega_min=1.02 * least)


def test_an_acceleration_limit_below_what_the_window_needs_is_refused():
    """Across the window the crank speed rises from at most (|v|+tol)/|h'| at its start to at least
    (|v|-tol)/|h'| at its end; no speed does that with |alpha| below the rise of omega^2 / 2 over the
    window's crank angle."""
    press = PressParams()
    p = SpeedProblem(press, period=0.8, window=(0.4, 0.05))  # near bottom dead centre: the speed must rise
    r, l, v = press.crank_radius, press.rod_length, abs(p.ram_speed)
    ang = [math.acos(((h - r - l) ** 2 + r**2 - l**2) / (2 * r * (h - r - l))) for h in p.window_heights]
    slope = [abs(-r * math.sin(a) + r**2 * math.sin(a) * math.cos(a) / math.sqrt(l**2 - r**2 * math.sin(a) ** 2))
             for a in ang]
    rise = (((v - p.tol) / slope[1]) ** 2 - ((v + p.tol) / slope[0]) ** 2) / (2 * (ang[1] - ang[0]))
    assert rise > 0
    p.replace(alpha_max=rise)
    with pytest.raises(ValueError, match=rf"alpha_max must be in \[{rise:.4g}, inf\) rad/s\^2"):
        p.replace(alpha_max=0.9 * rise)
