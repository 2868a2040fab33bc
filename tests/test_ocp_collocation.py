"""`Collocation`: the Radau IIA matrices against their defining properties (numpy's Legendre roots),
the collocation defects of a simulated response (CVODES, independent of the collocation code) shrink
at the scheme's order, the compiled functions equal the virtual machine's, and the transcription
converges on the clearance model to an optimum its re-simulation confirms."""

from dataclasses import replace

import casadi as ca
import numpy as np
import pytest

from pressocp import Collocation, PressParams, Rigid, SpeedProblem, WarmStart, build_model, design_speed
from pressocp.ocp.collocation import (RELAX_ITERATIONS, CollocationGrid, collocation_defect, collocation_residuals,
                                      nlp_options, point_function, radau_matrices)
from pressocp.ocp import transcription_from
from pressocp.ocp.nlp import crank_motion
from pressocp.ocp.states import states_at
from pressocp.ocp.strategy import soft_params
from pressocp.verify import ram_speed_violation, verify_speed
from pressocp.simulate import Integrator, periodic_state

SMOOTH = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_radau_matrices_differentiate_and_extrapolate_polynomials_exactly(d):
    tau, C, D, _ = radau_matrices(d)
    assert tau[0] == 0.0 and tau[-1] == pytest.approx(1.0)
    # Radau IIA points: roots of P_d(2x-1) - P_{d-1}(2x-1) (Legendre), from numpy, not CasADi
    leg = np.polynomial.legendre.Legendre
    roots = np.sort((leg.basis(d) - leg.basis(d - 1)).roots().real)
    np.testing.assert_allclose(tau[1:], (roots + 1) / 2, atol=1e-12)
    for k in range(d + 1):  # x = tau^k: a polynomial of degree <= d is represented exactly
        x = tau**k
        np.testing.assert_allclose(x @ C, k * tau[1:] ** max(k - 1, 0) * (k > 0), atol=1e-10)
        assert x @ D == pytest.approx(1.0)


def test_collocation_defects_of_a_simulated_response_converge():
    """A smooth case (soft contact, no impact): the defects of the CVODES solution sampled at the
    collocation points fall with the element length h like h^(d+1) or faster while the elements
    do not resolve the contact dynamics yet."""
    model = build_model(soft_params(SMOOTH.press, 1e4), n_harmonics=4)
    speed = design_speed(SMOOTH).speed
    x0, _ = periodic_state(model, speed, integrator=Integrator(method="cvodes", rtol=1e-9))
    defects = []
    for K in (200, 400):
        g = CollocationGrid(1.0, K, 3)
        defects.append(collocation_defect(model, speed, states_at(model, speed, x0, g.points, 1e-10), g))
    assert defects[1] < defects[0] / 8.0, defects  # order >= 3 in h


def test_bad_input_rejected():
    with pytest.raises(ValueError, match="elements"):
        CollocationGrid(1.0, 0)
    with pytest.raises(ValueError, match="degree"):
        radau_matrices(0)
    with pytest.raises(ValueError, match=r"min_eccentricity must be in \[0, 1\]"):
        Collocation(min_eccentricity=1.5)
    with pytest.raises(ValueError, match="elements"):
        Collocation(elements=5)
    with pytest.raises(ValueError, match="jit"):
        Collocation(jit="yes")
    with pytest.raises(ValueError, match="needs a model with states"):
        Collocation(elements=20).solve(SMOOTH, build_model(SMOOTH.press, clearance=(), n_harmonics=4),
                                       WarmStart(design_speed(SMOOTH).speed))


def test_collocation_converges_on_the_clearance_model_and_the_optimum_resimulates():
    """Smooth case (T = 1 s, -0.15 m/s, 4 harmonics, both clearances, target contact stiffness):
    from the rigid optimum, IPOPT converges with the journals on their walls, and the optimum,
    re-simulated by CVODES (periodic, 20 000 samples), keeps contact everywhere (not only at the
    Radau points), has the reported peak and the ram speed in tolerance over the model's window."""
    model = build_model(SMOOTH.press, n_harmonics=4)
    rig = Rigid(samples=200).solve(SMOOTH, model)
    sol = Collocation(elements=100, jit=False).solve(SMOOTH, model, WarmStart(rig.speed))
    assert sol.success, sol.status
    assert "solver" not in model.functions  # only a compiled solve keeps its solver (for its derivatives)
    assert max(sol.violations.values()) < 1e-6, sol.violations
    sim = verify_speed(model, sol.speed, 1e-9)
    assert sim.stats["periodic"].get("found", True) is True
    assert sim.peak("torque") == pytest.approx(sol.objective, rel=5e-3)
    assert ram_speed_violation(sim, SMOOTH) <= 0.0
    for j in ("crank_pin", "wrist_pin"):
        assert np.min(getattr(sim, f"{j}_eccentricity")) > 0.999, j
    assert sim.peak("torque") <= verify_speed(model, rig.speed, 1e-9).peak("torque") * (1 + 1e-3)


def test_compiled_point_function_agrees_with_the_virtual_machine():
    """`jit=True` (CasADi JIT through the system C compiler) evaluates the same residuals."""
    model = build_model(PressParams(), n_harmonics=4)
    speed = design_speed(SMOOTH).speed
    g = CollocationGrid(1.0, 20, 3)
    rng = np.random.default_rng(1)
    X = rng.normal(0.0, 0.5, (model.nx, g.points.size)) + np.array([1.0] + [0.0] * (model.nx - 1))[:, None]
    crank = crank_motion(speed, g.times)
    vm = collocation_residuals(model, g, ("torque", "ram_velocity"), X, crank)
    jit = collocation_residuals(model, g, ("torque", "ram_velocity"), X, crank, jit=True)
    for a, b in zip(vm, jit):
        np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=1e-10, atol=1e-9)


def test_point_function_is_built_once_per_model_and_outputs():
    """A later solve on the same model (a polish round) reuses the point function, so CasADi's
    derivatives of it (compiled, with jit) are reused too; another model or other outputs get their own."""
    model = build_model(PressParams(), n_harmonics=4)
    f = point_function(model, ("torque",))
    assert point_function(model, ("torque",)) is f
    assert point_function(model, ("torque", "ram_velocity")) is not f
    assert point_function(build_model(PressParams(), n_harmonics=4), ("torque",)) is not f


@pytest.mark.slow  # 15 s; the default path's JIT is also exercised end to end by the slow 75 spm tests
def test_compiled_hessian_with_few_directions_agrees_with_the_virtual_machine():
    """The exact Hessian of a collocation NLP compiled with the options a jit solve uses
    (`nlp_options`: few directions per sweep) equals the virtual machine's with CasADi's defaults."""
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


@pytest.mark.slow  # 19 s; a warm start by default: tests/test_ocp_rigid.py
def test_primal_dual_warm_start_stays_at_the_optimum_and_follows_tightened_bounds():
    """The same NLP started from its solution with its multipliers (`StageResult.nlp`) stays there in a
    few iterations; with the ram-speed share lowered (`tightened`) it moves to meet the new bounds.
    The stage's time record adds up."""
    model = build_model(SMOOTH.press, n_harmonics=4)
    rig = Rigid(samples=200).solve(SMOOTH, model)
    tr = Collocation(elements=60, jit=False)
    sol = tr.solve(SMOOTH, model, WarmStart(rig.speed))
    assert sol.success and sol.nlp is not None and sol.nlp.grid == (60, 3)
    assert transcription_from(sol.settings) == tr  # the stage records the transcription that solved it
    parts = sum(sol.timing[k] for k in ("build", "objective", "constraints", "jacobian", "hessian", "callback",
                                        "solver", "start"))
    assert sol.timing["total"] == pytest.approx(sol.wall_time) and parts <= sol.wall_time * 1.001
    again = tr.solve(SMOOTH, model, WarmStart(sol.speed, point=sol.nlp))
    assert again.success and again.iterations <= 5, again.iterations
    assert again.details.get("primal_dual_warm_start") is True
    np.testing.assert_allclose(again.speed.coefficients, sol.speed.coefficients, rtol=0, atol=1e-6)
    tight = tr.tightened(0.3)
    assert tight.backoff == pytest.approx(tr.backoff - 0.3)
    moved = tight.solve(SMOOTH, model, WarmStart(sol.speed, point=sol.nlp))
    assert moved.success and max(moved.violations.values()) < 1e-6
    band = sol.nlp.band
    v = np.asarray(collocation_residuals(model, tight.grid(SMOOTH.period), ("ram_velocity",),
                                         moved.states, crank_motion(moved.speed, tight.grid(1.0).times))[2]).ravel()
    assert np.max(np.abs(v[band] - SMOOTH.ram_speed)) <= tight.backoff * SMOOTH.tol * (1 + 1e-6)
    # `relaxed`: the answer's NLP (its grid, from any transcription) holding the whole tolerance; IPOPT
    # capped (the cap is lifted here: this start sits further from the relaxed optimum than a default one)
    loose = Collocation(elements=400, jit=False).relaxed(sol)
    assert loose.backoff == 1.0 and loose.elements == 60 and loose.ipopt["ipopt.max_iter"] == RELAX_ITERATIONS
    loose = replace(loose, ipopt={**loose.ipopt, "ipopt.max_iter": 100})
    back = loose.solve(SMOOTH, model, WarmStart(sol.speed, point=sol.nlp))
    assert back.success and back.details.get("primal_dual_warm_start") is True
    assert back.objective < sol.objective and loose.relaxed(back) is None
    v = np.asarray(collocation_residuals(model, loose.grid(SMOOTH.period), ("ram_velocity",),
                                         back.states, crank_motion(back.speed, loose.grid(1.0).times))[2]).ravel()
    assert np.max(np.abs(v[band] - SMOOTH.ram_speed)) <= SMOOTH.tol * (1 + 1e-6)


@pytest.mark.parametrize("d", [1, 2, 3, 4])
def test_a_coarse_grids_states_are_carried_exactly_where_they_are_polynomials(d):
    """Each element of the coarse grid holds its own polynomial of degree d (random coefficients): its
    values at the coarse points, carried to an even split of the grid, equal the polynomials evaluated
    at the fine points (numpy's polyval, not the Lagrange basis of the code under test)."""
    rng, leg = np.random.default_rng(d), np.polynomial.legendre.Legendre
    coarse = CollocationGrid(0.8, 7, d)
    coefficients = rng.normal(size=(2, coarse.elements, d + 1))  # 2 rows, per element, highest power first

    tau = np.concatenate([[0.0], (np.sort((leg.basis(d) - leg.basis(d - 1)).roots().real) + 1) / 2])  # Radau IIA

    def values(split: int) -> np.ndarray:
        """The polynomials at the points of the grid of `split` x the elements: point j of fine element m
        lies in coarse element m // split, at local time (m % split + tau_j) / split."""
        out = [[np.polyval(coefficients[r, m // split], (m % split + t) / split)
                for m in range(split * coarse.elements) for t in tau] for r in range(2)]
        return np.array(out)

    for split in (2, 3):
        fine = CollocationGrid(0.8, split * coarse.elements, d)
        np.testing.assert_allclose(coarse.interpolate(values(1), fine), values(split), atol=1e-11)
    for other in (CollocationGrid(0.8, 10, d), CollocationGrid(0.8, 14, d % 4 + 1), CollocationGrid(0.9, 14, d)):
        assert not coarse.splits(other)  # 10 does not cut 7 (their starts differ); another degree; another period
        with pytest.raises(ValueError, match="does not cut"):
            coarse.interpolate(values(1), other)


def test_radau_weights_integrate_polynomials_of_degree_2d_minus_2_exactly():
    """h b_r over the grid integrate t^k exactly for k <= 2d - 2 (Radau quadrature, of order 2d - 1),
    against the antiderivative, and not t^(2d - 1) on one element."""
    g = CollocationGrid(0.8, 5, 3)
    for k in range(5):
        assert g.weights @ g.times**k == pytest.approx(0.8 ** (k + 1) / (k + 1), rel=1e-12)
    one = CollocationGrid(1.0, 1, 3)
    assert one.weights @ one.times**5 != pytest.approx(1 / 6, rel=1e-6)


def test_a_grid_is_refined_twice_up_to_the_finest():
    tr = Collocation()
    assert tr.grid(0.8).elements == 400 and tr.refined(0.8).elements == 800
    assert tr.refined(0.8).refined(0.8).elements == 1600 and tr.refined(0.8).refined(0.8).refined(0.8) is None
    assert Collocation().grid(0.05).elements == 100 and Collocation().refined(0.05) is None
    assert Collocation().grid(0.8, "flexible").elements == 1600 and Collocation().refined(0.8, "flexible") is None
