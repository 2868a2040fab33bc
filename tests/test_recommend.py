"""`po.recommend_model`: which model level a scene needs, and why."""

import numpy as np
import pytest

import pressocp as po
from pressocp.recommend import HARMONIC_SHARE, highest_harmonic


def test_seed_press_with_its_rigid_design_at_75_spm_needs_clearance(impact_speed):
    r = po.recommend_model(po.PressParams(), impact_speed)
    assert r.level == "clearance"
    assert r.min_rod_tension < 0 and "reverses" in r.reason
    assert r.mode_ratio > 10


def test_default_press_at_constant_speed_is_rigid():
    r = po.recommend_model(po.PressParams(), po.FourierSpeed.constant(1.0))
    assert r.level == "rigid"
    # hanging weight (150 kg slider + 3.14 kg rod) less the rod's own share at the crank pin: the rod stays
    # in tension by about the slider's weight less its centripetal share; at least half the weight here
    assert r.min_rod_tension > 0.5 * 150.0 * 9.81
    assert "stays in tension" in r.reason


def test_simeon_slider_crank_at_150_rad_s_is_flexible():
    r = po.recommend_model(po.PressParams.simeon(), po.FourierSpeed.constant(2 * np.pi / 150.0))
    assert r.level == "flexible"
    assert r.mode_ratio < 10 and "first bending mode" in r.reason


def test_first_bending_mode_of_a_pinned_steel_bar():  # the mode recommend_model uses
    # Blevins, Formulas for natural frequency and mode shape, pinned-pinned beam: f1 = pi/(2 L^2) sqrt(EI/m');
    # a steel bar 1 m long, 20 mm square: EI = 2.1e11 * 1.333e-8 = 2800 N m^2, m' = 7850 * 4e-4 = 3.14 kg/m,
    # sqrt(2800 / 3.14) = 29.86 1/s -> f1 = 1.5708 * 29.86 = 46.9 Hz
    press = po.PressParams().replace(rod_length=1.0, rod_mass=7850 * 0.02**2, rod_area_moment=0.02**4 / 12,
                                     rod_youngs_modulus=2.1e11)
    assert press.rod_first_bending_frequency / (2 * np.pi) == pytest.approx(46.9, rel=2e-3)


def test_highest_harmonic_of_a_known_signal():
    T = 0.5
    t = np.linspace(0, T, 1000, endpoint=False)
    x = 3 + np.sin(2 * np.pi * t / T) + 0.2 * np.cos(2 * np.pi * 5 * t / T) + 0.5 * HARMONIC_SHARE * np.sin(
        2 * np.pi * 9 * t / T)
    assert highest_harmonic(x, T) == pytest.approx(10.0)  # the 5th harmonic of 2 Hz; the 9th is below the share
    assert highest_harmonic(np.full(100, 2.0), T) == 0.0


def test_bad_input():
    with pytest.raises(ValueError, match="FourierSpeed"):
        po.recommend_model(po.PressParams(), 0.8)
    with pytest.raises(ValueError, match="PressParams"):
        po.recommend_model({}, po.FourierSpeed.constant(1.0))


def test_slender_rod_scene_is_flexible():
    """The bundled slender-rod scene (Simeon's rod at 100 rad/s), even at constant speed: the loads of the
    plain slider crank (r/l = 0.5: strong 2nd-4th harmonics of 15.9 Hz) reach within a factor 10 of the
    rod's first mode. That mode, pinned-pinned (Blevins):
    f1 = pi/(2 L^2) sqrt(EI/m') with EI = 2e11 * 0.008^4/12 = 68.27 N m^2, m' = 0.151104/0.3 = 0.5037 kg/m:
    17.453 * 11.642 = 203.2 Hz."""
    sc = po.Scenario.load("slender_rod")
    r = po.recommend_model(sc.press, po.FourierSpeed.constant(sc.problem.period))
    assert r.level == "flexible" and "first bending mode" in r.reason
    assert r.first_mode == pytest.approx(203.2, rel=1e-3)
    assert r.mode_ratio < 10



@pytest.mark.parametrize("scenario, solve, refinement", [
    ("press75", po.Collocation, None),  # clearance joints: shooting did not converge on the map
    ("slender_rod", po.Collocation, po.MultipleShooting),  # smooth: shooting refines collocation's optimum
])
def test_the_transcription_follows_the_model_level(scenario, solve, refinement):
    spec = po.Scenario.load(scenario).build_model().spec
    r = po.recommend_transcription(spec)
    assert type(r.transcription) is solve
    assert (r.refinement is None) if refinement is None else type(r.refinement) is refinement
    if refinement is not None:  # through IDAS, sampled finely enough to hold the window where it is
        assert r.refinement.integrator == "idas" and r.refinement.samples >= 100
    assert ("clearance joints" in r.reason) == bool(spec.clearance)


def test_the_ideal_press_is_solved_by_the_rigid_transcription():
    r = po.recommend_transcription(po.ModelSpec("rigid", ()))
    assert type(r.transcription) is po.Rigid and r.refinement is None and "no states" in r.reason
    with pytest.raises(ValueError, match="PressModel or a ModelSpec"):
        po.recommend_transcription("flexible")


def test_each_level_names_a_model_to_build(impact_speed):
    """`ModelRecommendation.spec`: the ideal press, the rigid rod with both clearance joints, and the
    flexible rod as the 8-element rod reduced to 2 bending modes (with the joints)."""
    from pressocp.model import ModelSpec

    press = po.PressParams()
    assert po.recommend_model(press, po.FourierSpeed.constant(1.0)).spec == ModelSpec("rigid", ())
    assert po.recommend_model(press, impact_speed).spec == ModelSpec("rigid", ("crank_pin", "wrist_pin"))
    sc = po.Scenario.load("slender_rod")
    r = po.recommend_model(sc.press, po.FourierSpeed.constant(sc.problem.period))
    assert r.spec == ModelSpec("flexible", ("crank_pin", "wrist_pin"), 8, 2)
    assert "8 elements, 2 modes" in r.reason
    model = r.spec.build(sc.press, sc.problem.n_harmonics)
    assert model.rod == "flexible" and model.clearance == ("crank_pin", "wrist_pin")


@pytest.mark.slow
def test_the_named_reduced_rod_matches_the_eight_element_rod_on_the_slender_scene():
    """The reduction `recommend_model` names (8 elements, 2 modes) against the 8-element rod itself
    (the full finite-element model, another code path: no modal basis), on the slender-rod scene's
    kinematic design with its ideal joints, each periodic at IDAS rtol 1e-9: peak torque and pin
    forces within 1e-3 (1.1e-4 measured at rtol 1e-10; the 4-element rod is 8.7e-4 off on torque and
    1.3e-3 on the wrist pin)."""
    from pressocp.model import ModelSpec
    from pressocp.recommend import REDUCED_ROD
    from pressocp.simulate import Integrator, periodic_state, simulate

    sc = po.Scenario.load("slender_rod")
    speed = po.design_speed(sc.problem).speed
    peaks = []
    for spec in (ModelSpec("flexible", (), 8), ModelSpec("flexible", (), *REDUCED_ROD)):
        model = spec.build(sc.press, sc.problem.n_harmonics)
        x0, _ = periodic_state(model, speed, Integrator("idas", rtol=1e-9))
        sim = simulate(model, speed, integrator=Integrator("idas", rtol=1e-9), x0=x0, n_out=4001, work=False)
        peaks.append([sim.peak(n) for n in ("torque", "crank_pin_force", "wrist_pin_force")])
    np.testing.assert_allclose(peaks[1], peaks[0], rtol=1e-3)
