"""The flexible rod reduced to a few bending modes (`ModelSpec.n_modes`): its mode shapes and
frequencies against the Euler-Bernoulli pinned-pinned beam, Simeon's slider crank (shared/reference
benchmarks.md section 1), and the element rod it is reduced from (every mode kept).

References: the closed-form beam (sin(k pi x / l), (k pi / l)^2 sqrt(EI / rho A)), Simeon's
reference values, and the element model it is reduced from.
"""

import numpy as np
import pytest

from pressocp import PressParams, beam
from pressocp.model import ModelSpec
from pressocp.studies import SIMEON_REFERENCE, simeon_crank


def test_modes_are_the_pinned_pinned_beam_modes():
    """8 elements: the first two modes' frequencies within 5e-4 of the closed form (2.6e-4 measured for the second), their shapes
    within 1e-3 of sin(k pi x / l) (scaled to a largest deflection of 1; the sign of an
    antisymmetric mode is either), and mass-orthogonal."""
    p = PressParams()
    L, rho_a, ei = p.rod_length, p.rod_mass / p.rod_length, p.rod_youngs_modulus * p.rod_area_moment
    shapes, freqs = beam.modes(L, 8, rho_a, ei, 2)
    exact = np.array([(k * np.pi / L) ** 2 * np.sqrt(ei / rho_a) for k in (1, 2)])
    np.testing.assert_allclose(freqs, exact, rtol=5e-4)
    x = np.linspace(0.0, L, 161)
    for k in range(2):
        w = np.array([beam.deflection_at(L, 8, shapes[:, k], xi) for xi in x])
        ref = np.sin((k + 1) * np.pi * x / L) / np.max(np.abs(np.sin((k + 1) * np.pi * x / L)))
        assert min(np.max(np.abs(w - ref)), np.max(np.abs(w + ref))) < 1e-3  # an antisymmetric mode: either sign
    mass, _ = beam.pinned_pinned_matrices(L, 8, rho_a, ei)
    gram = shapes.T @ mass @ shapes
    assert abs(gram[0, 1]) < 1e-9 * np.sqrt(gram[0, 0] * gram[1, 1])
    # a DOF vector of one mode has that mode's coordinate only
    np.testing.assert_allclose(beam.modal_coordinates(shapes, mass, 0.3 * shapes[:, 1]), [0.0, 0.3], atol=1e-12)


def test_model_spec_of_a_reduced_rod():
    spec = ModelSpec("flexible", ("crank_pin", "wrist_pin"), 8, 2)
    assert spec.describe() == "flexible rod (8 elements, 2 modes), clearance in crank_pin and wrist_pin"
    assert ModelSpec.from_dict(spec.to_dict()) == spec
    assert "n_modes" not in ModelSpec("flexible").to_dict()
    with pytest.raises(ValueError, match="n_modes"):
        ModelSpec("rigid", n_modes=2)
    with pytest.raises(ValueError, match="n_modes"):
        ModelSpec("flexible", n_elements=2, n_modes=5)
    m = spec.build(PressParams(), 4)
    assert m.spec == spec and m.nx == 2 * (4 + 2) and m.rod_modes.shape == (16, 2)
    assert m.state_names[4:6] == ["eta_1", "eta_2"]


def test_simeon_slider_crank_on_two_modes():
    """Simeon's reference at 0.1 s: the slider within 1e-4, its velocity within 1e-3, the midspan
    deflection and its extremes within 2 % (as the element rod, tests/test_model.py)."""
    r = simeon_crank(n_elements=8, n_modes=2)
    p = PressParams.simeon()
    ref = SIMEON_REFERENCE
    assert p.crank_radius + p.rod_length - r.ram_height[-1] == pytest.approx(ref["slider_position"], rel=1e-4)
    assert -r.ram_velocity[-1] == pytest.approx(ref["slider_velocity"], rel=1e-3)
    assert r.rod_midspan_deflection[-1] == pytest.approx(ref["midspan_deflection"], rel=0.02)
    assert np.max(r.rod_midspan_deflection) == pytest.approx(ref["midspan_extremes"], rel=0.02)
    assert np.min(r.rod_midspan_deflection) == pytest.approx(-ref["midspan_extremes"], rel=0.02)


def test_every_mode_is_the_element_rod_itself():
    """All 2N modes span the element rod's DOFs, so the reduced model is the element model in other
    coordinates: Simeon's slider crank on 4 elements agrees with it to 1e-6 (slider, midspan)."""
    full = simeon_crank(n_elements=4, t_end=0.05, n_out=501)
    every = simeon_crank(n_elements=4, t_end=0.05, n_out=501, n_modes=8)
    np.testing.assert_allclose(every.ram_height, full.ram_height, rtol=0, atol=1e-9)
    scale = np.max(np.abs(full.rod_midspan_deflection))
    assert np.max(np.abs(every.rod_midspan_deflection - full.rod_midspan_deflection)) <= 1e-6 * scale


#: Scaled state of one mode of the 8-element rod on the seed optimum (tests/references), two
#: cycles from rest at IDAS rtol 1e-6: both journals in contact. IDACalcIC fails from it
#: (IDA_LINESEARCH_FAIL), although the model gives its consistent accelerations exactly.
CALC_IC_FAILS_HERE = [-0.009758755293709629, -1.0021191715013031, -0.010652881786521105, 1.0030807186448698,
                      0.0003349506274906177, -5.099435491398026e-05, 0.00029742998961979967, 0.004530297376810115,
                      -0.0002752964562420873, -0.00019804506871941966]


def test_idas_starts_where_its_initial_condition_correction_fails(capsys):
    """From a state where IDACalcIC fails, IDAS starts from the model's consistent accelerations, says
    so in its statistics, and ends where CVODES (the explicit ODE, which needs no correction) ends at
    rtol 1e-10. Before, the run raised SimulationError. The failed correction's SUNDIALS messages do
    not reach the user's stderr (they did, through CasADi). Several starts at once (the periodic
    search's shots) each get their own run, in their columns."""
    import json
    from pathlib import Path

    from pressocp import FourierSpeed
    from pressocp.simulate import Integrator, simulate, started_consistently

    d = json.loads((Path(__file__).parent / "references" / "press75_optimum_speed.json").read_text())
    speed = FourierSpeed(d["period"], d["a"], d["b"], d["theta0"])
    model = ModelSpec("flexible", n_elements=8, n_modes=1).build(PressParams(), len(d["a"]))
    model.jit = False
    x = np.array(CALC_IC_FAILS_HERE)
    idas = simulate(model, speed, t_end=0.02, integrator=Integrator("idas", rtol=1e-8), n_out=3, work=False, x0=x)
    assert "IDACalcIC failed" in idas.stats["initial_conditions"]
    assert capsys.readouterr().err == ""
    cvodes = simulate(model, speed, t_end=0.02, integrator=Integrator("cvodes", rtol=1e-10), n_out=3, work=False, x0=x)
    assert "initial_conditions" not in cvodes.stats
    scaled = np.abs(idas.states[:, -1] - cvodes.states[:, -1]) / model.x_scale
    assert scaled.max() < 1e-4  # 5.2e-6 measured, of states of order 1
    assert idas.torque[-1] == pytest.approx(cvodes.torque[-1], rel=1e-4)
    # several starts at once (the periodic search's Jacobian shots): each column its own run
    par = model.parameters(speed)
    xs = np.column_stack([x, 0.999 * x])
    err = RuntimeError('IDACalcIC returned "IDA_CONV_FAIL"')
    both = started_consistently(model, Integrator("idas", rtol=1e-8), np.array([0.02]), False, err,
                                {"x0": xs, "p": np.column_stack([par, par])}, {})["xf"]
    scaled_cvodes = cvodes.states[:, -1] / model.x_scale
    assert np.abs(both[:, 0] - scaled_cvodes).max() < 1e-4
    alone = started_consistently(model, Integrator("idas", rtol=1e-8), np.array([0.02]), False, err,
                                 {"x0": 0.999 * x, "p": par}, {})["xf"]
    np.testing.assert_allclose(both[:, 1], np.ravel(alone), rtol=0, atol=1e-12)
    assert np.abs(both[:, 1] - both[:, 0]).max() > 1e-4  # the two starts differ



@pytest.mark.slow
def test_periodic_search_on_the_eight_element_rod():
    """The periodic search on the 8-element rod with both clearances at IDAS rtol 1e-9 (seed optimum):
    its shots from zero accelerations failed in IDACalcIC (IDA_CONV_FAIL) and the search raised; they
    now start from consistent accelerations, and the periodic cycle's peak torque matches the 4-element
    rod's within 1e-4 (1e-8 measured: the rod's bending barely enters the torque at this speed)."""
    import json
    from pathlib import Path

    from pressocp import FourierSpeed
    from pressocp.simulate import Integrator, simulate

    d = json.loads((Path(__file__).parent / "references" / "press75_optimum_speed.json").read_text())
    speed = FourierSpeed(d["period"], d["a"], d["b"], d["theta0"])
    peaks = []
    for n in (8, 4):
        model = ModelSpec("flexible", n_elements=n).build(PressParams(), len(d["a"]))
        model.jit = False
        sim = simulate(model, speed, periodic=True, integrator=Integrator("idas", rtol=1e-9), n_out=4001, work=False)
        assert sim.stats["periodic"]["residual"] <= 1e-5
        peaks.append(sim.peak("torque"))
    assert peaks[0] == pytest.approx(peaks[1], rel=1e-4)
