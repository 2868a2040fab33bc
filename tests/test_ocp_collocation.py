"""Direct-collocation transcription: the Radau IIA matrices against their defining properties,
the collocation defects of a simulated response (CVODES, independent of the collocation code)
shrink at the scheme's order as the elements get shorter, and bad input is rejected."""

import numpy as np
import pytest

from pressocp import PressParams
from pressocp.design import design_speed
from pressocp.model import build_model
from pressocp.ocp import SpeedProblem
from pressocp.ocp.collocation import (CollocationGrid, collocation_defect, collocation_states, radau_matrices,
                                      solve_collocation)


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_radau_matrices_differentiate_and_extrapolate_polynomials_exactly(d):
    tau, C, D = radau_matrices(d)
    assert tau[0] == 0.0 and tau[-1] == pytest.approx(1.0)
    # Radau IIA points: roots of P_d(2x-1) - P_{d-1}(2x-1) (Legendre), from numpy, not CasADi
    leg = np.polynomial.legendre.Legendre
    roots = np.sort((leg.basis(d) - leg.basis(d - 1)).roots().real)
    np.testing.assert_allclose(tau[1:], (roots + 1) / 2, atol=1e-12)
    for k in range(d + 1):  # x = tau^k: a polynomial of degree <= d is represented exactly
        x = tau**k
        np.testing.assert_allclose(x @ C, k * tau ** max(k - 1, 0) * (k > 0), atol=1e-10)
        assert x @ D == pytest.approx(1.0)


def test_collocation_defects_of_a_simulated_response_converge():
    """A smooth case (soft contact, no impact): the defects of the CVODES solution sampled at the
    collocation points fall with the element length h like h^(d+1) or faster while the elements
    do not resolve the contact dynamics yet, and go to the integrator's noise once they do."""
    from pressocp.ocp.optimize import soft_params
    from pressocp.simulate import periodic_state

    params = PressParams()
    model = build_model(soft_params(params, 1e4), n_harmonics=4)
    speed = design_speed(params, period=1.0, ram_speed=-0.15, n_harmonics=4).speed
    x0, _ = periodic_state(model, speed, method="cvodes", rtol=1e-9)
    defects = []
    for K in (200, 400):
        g = CollocationGrid(1.0, K, 3)
        defects.append(collocation_defect(model, speed, collocation_states(model, speed, x0, g, 1e-10), g))
    assert defects[1] < defects[0] / 8.0, defects  # order >= 3 in h


def test_bad_input_rejected():
    params = PressParams()
    prob = SpeedProblem(params, period=1.0, ram_speed=-0.15, n_harmonics=4)
    model = build_model(params, n_harmonics=4)
    speed = design_speed(params, period=1.0, ram_speed=-0.15, n_harmonics=4).speed
    g = CollocationGrid(1.0, 10, 3)
    with pytest.raises(ValueError, match="states must have shape"):
        solve_collocation(prob, model, speed, np.zeros((model.nx, 5)), 0.3, g)
    with pytest.raises(ValueError, match="grid.period"):
        solve_collocation(prob, model, speed, np.zeros((model.nx, 40)), 0.3, CollocationGrid(0.8, 10, 3))
    with pytest.raises(ValueError, match="elements"):
        CollocationGrid(1.0, 0)
    with pytest.raises(ValueError, match="degree"):
        radau_matrices(0)


def test_collocation_converges_on_the_clearance_model_and_the_optimum_resimulates():
    """Smooth case (T = 1 s, -0.15 m/s, 4 harmonics, both clearances, target contact stiffness):
    from the rigid optimum and its simulated periodic states, IPOPT converges, and the optimum,
    re-simulated by CVODES (periodic, 20 000 samples), has the reported peak and the ram speed in
    tolerance on the whole window."""
    from pressocp.ocp import solve_rigid
    from pressocp.ocp.optimize import _verify, ram_speed_violation
    from pressocp.simulate import periodic_state

    params = PressParams()
    model = build_model(params, n_harmonics=4)
    prob = SpeedProblem(params, period=1.0, ram_speed=-0.15, n_harmonics=4)
    rig = solve_rigid(prob, samples=200)
    x0, _ = periodic_state(model, rig.speed, method="cvodes", rtol=1e-9)
    g = CollocationGrid(1.0, 200, 3)
    start = collocation_states(model, rig.speed, x0, g, 1e-10)
    sol = solve_collocation(prob, model, rig.speed, start, rig.t1, g,
                            ipopt_options={"ipopt.hessian_approximation": "exact"})
    assert sol.success, sol.status
    assert max(sol.violations.values()) < 1e-6, sol.violations
    sim = _verify(model, sol.speed, 1e-8)
    assert sim.stats["periodic"].get("found", True) is True
    assert sim.peak("torque") == pytest.approx(sol.value, rel=5e-3)
    assert ram_speed_violation(sim, prob, rig.t1) <= 0.0
    start_peak = _verify(model, rig.speed, 1e-8).peak("torque")
    assert sim.peak("torque") <= start_peak * (1 + 1e-3)


def test_optimize_speed_by_collocation_keeps_contact_and_resimulates():
    """`optimize_speed(method="collocation")`, smooth case, every stage run: the clearance stage is
    collocation with the journals held on their bearing walls; the CVODES re-simulation of the
    optimum keeps contact in both pins everywhere (not only at the Radau points), has the value the
    optimiser reported and the ram speed in tolerance, and is no worse than the rigid optimum's."""
    from pressocp.ocp import optimize_speed

    model = build_model(PressParams(), n_harmonics=4)
    r = optimize_speed(model, period=1.0, ram_speed=-0.15, n_harmonics=4, method="collocation", elements=200,
                       stages="all", rigid_samples=200, verify_rtol=1e-8, progress=False)
    assert r.success, r.status
    st = r.stages[-1]
    assert (st["name"], st["method"], st["elements"], st["min_eccentricity"]) == ("target", "collocation", 200, 1.0)
    assert st["violations"]["eccentricity"] <= 1e-6
    sim = r.simulation
    for j in ("crank_pin", "wrist_pin"):
        assert np.min(getattr(sim, f"{j}_eccentricity")) > 0.999, j
    assert r.peak_torque == pytest.approx(r.objective_value, rel=5e-3)
    assert r.max_ram_speed_violation == 0.0
    assert r.peak_torque <= r.stages[0]["clearance_peak_torque"] * (1 + 1e-3)


def test_optimize_speed_collocation_arguments_checked():
    from pressocp.ocp import optimize_speed

    with pytest.raises(ValueError, match=r"min_eccentricity must be in \[0, 1\]"):
        optimize_speed(method="collocation", min_eccentricity=1.5, progress=False)
    with pytest.raises(ValueError, match="elements"):
        optimize_speed(method="collocation", elements=5, progress=False)
    with pytest.raises(ValueError, match="method"):
        optimize_speed(method="radau", progress=False)


def test_compiled_point_function_agrees_with_the_virtual_machine():
    """`jit=True` (CasADi JIT through the system C compiler) evaluates the same residuals."""
    from pressocp.ocp.collocation import collocation_residuals, crank_motion

    model = build_model(PressParams(), n_harmonics=4)
    speed = design_speed(model.params, period=1.0, ram_speed=-0.15, n_harmonics=4).speed
    g = CollocationGrid(1.0, 20, 3)
    rng = np.random.default_rng(1)
    X = rng.normal(0.0, 0.5, (model.nx, g.points.size)) + np.array([1.0] + [0.0] * (model.nx - 1))[:, None]
    crank = crank_motion(speed, g.times)
    vm = collocation_residuals(model, g, ("torque", "ram_velocity"), X, crank)
    jit = collocation_residuals(model, g, ("torque", "ram_velocity"), X, crank, jit=True)
    for a, b in zip(vm, jit):
        np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=1e-10, atol=1e-9)


def test_compiled_hessian_with_few_directions_agrees_with_the_virtual_machine():
    """The exact Hessian of a collocation NLP compiled with the options `solve_collocation(..., jit=True)`
    uses (`nlp_options`: `JIT_DIRECTIONS` directions per sweep) equals the virtual machine's with
    CasADi's default directions."""
    import casadi as ca

    from pressocp.ocp.collocation import collocation_residuals, nlp_options

    model = build_model(PressParams(), n_harmonics=4)
    g = CollocationGrid(1.0, 4, 3)
    rng = np.random.default_rng(2)
    X = ca.MX.sym("X", model.nx, g.points.size)
    crank = ca.MX.sym("crank", 3, g.times.size)
    w = ca.veccat(X, crank)
    x0 = rng.normal(0.0, 0.5, w.numel()) + 1.0
    lam = rng.normal(0.0, 1.0, model.nx * g.times.size)
    hessians = []
    for jit in (False, True):
        defect, _, Y = collocation_residuals(model, g, ("torque", "ram_velocity"), X, crank, jit=jit)
        solver = ca.nlpsol("h", "ipopt", {"x": w, "f": ca.sumsqr(Y), "g": ca.vec(defect)}, nlp_options(jit))
        H = solver.get_function("nlp_hess_l")(x0, [], 1.0, lam)
        hessians.append(np.asarray(ca.densify(H)))
    assert np.abs(hessians[0]).max() > 0.0
    np.testing.assert_allclose(hessians[1], hessians[0], rtol=1e-9, atol=1e-9 * np.abs(hessians[0]).max())
