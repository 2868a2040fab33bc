"""Collocation grids of unequal elements and their local refinement: quadrature, points and carried
states checked against formulas written here (antiderivatives, numpy's polynomials), the residuals
of a grid whose edges happen to be equal against the equal grid's own; on a response whose journals
cross their gaps, the cut elements are those with the largest defects and cutting shrinks them; and
on the smooth clearance case a solve on the cut grid from the carried coarse solution reaches the
optimum of the uniformly refined grid."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from pressocp import Collocation, PressParams, Rigid, SpeedProblem, WarmStart, build_model
from pressocp.ocp.collocation import CollocationGrid, collocation_residuals, element_defects
from pressocp.ocp.nlp import crank_motion
from pressocp.ocp.prolong import carried_multipliers
from pressocp.ocp.stage import Resimulated
from pressocp.checks import PlausibilityWarning
from pressocp.ocp.strategy import near_peak, soft_params
from pressocp.simulate import Integrator, periodic_state
from pressocp.speed import FourierSpeed
from pressocp.verify import verify_speed

T = 0.8
EDGES = (0.0, 0.05, 0.125, 0.3, 0.31, 0.5, 0.72, 0.9)
UNEVEN = CollocationGrid(T, len(EDGES), 3, EDGES)


def radau_nodes(d: int) -> np.ndarray:
    """0 and the Radau IIA points of degree d: the roots of P_d - P_(d-1) mapped to (0, 1]."""
    leg = np.polynomial.legendre.Legendre
    return np.concatenate([[0.0], (np.sort((leg.basis(d) - leg.basis(d - 1)).roots().real) + 1) / 2])


def test_an_uneven_grids_points_lie_at_the_radau_nodes_of_its_elements():
    starts = T * np.array(EDGES)
    lengths = np.diff(np.append(starts, T))
    expected = (starts[:, None] + lengths[:, None] * radau_nodes(3)[None, :]).ravel()
    np.testing.assert_allclose(UNEVEN.points, expected, atol=1e-14)
    assert UNEVEN.lengths.sum() == pytest.approx(T, rel=1e-14)
    assert UNEVEN.key == (8, 3, EDGES) and CollocationGrid(T, 8, 3).key == (8, 3)


def test_an_uneven_grids_weights_integrate_polynomials_of_degree_2d_minus_2_exactly():
    """h_k b_r over the grid integrate t^k exactly for k <= 2d - 2, against the antiderivative."""
    for k in range(5):
        assert UNEVEN.weights @ UNEVEN.times**k == pytest.approx(T ** (k + 1) / (k + 1), rel=1e-12)


def test_bad_edges_fail_naming_the_field():
    with pytest.raises(ValueError, match="edges: element starts"):
        CollocationGrid(1.0, 3, 3, (0.0, 0.5, 0.4))
    with pytest.raises(ValueError, match="edges: 2 element starts given for 3"):
        CollocationGrid(1.0, 3, 3, (0.0, 0.5))
    with pytest.raises(ValueError, match="edges: element starts"):
        Collocation(edges=(0.1, 0.5))
    with pytest.raises(ValueError, match="elements must be an integer in \\[10, 100000\\], got 2"):
        Collocation(edges=(0.0, 0.5))
    with pytest.raises(ValueError, match="refinement"):
        Collocation(refinement="everywhere")
    tr = Collocation(edges=list(np.arange(12) / 12))
    assert tr.elements == 12 and isinstance(tr.edges, tuple) and tr.grid(2.0).key == (12, 3, tr.edges)


@pytest.mark.parametrize("d", [2, 3])
def test_states_are_carried_exactly_to_a_grid_with_some_elements_cut(d):
    """Each coarse element holds its own polynomial of degree d: carried to the grid with elements 1,
    3 and 6 cut (and then element 0 of that), the values equal the polynomials at the fine points."""
    rng = np.random.default_rng(d)
    coarse = CollocationGrid(T, len(EDGES), d, EDGES)
    coefficients = rng.normal(size=(2, coarse.elements, d + 1))
    starts = T * np.array(EDGES)
    lengths = np.diff(np.append(starts, T))

    def values(fine: CollocationGrid) -> np.ndarray:
        """The polynomials at `fine`'s points, each point read in the coarse element that holds the
        middle of its own fine element (an element's end belongs to its element)."""
        m = np.arange(fine.points.size) // (d + 1)
        k = np.searchsorted(starts, fine.starts[m] + fine.lengths[m] / 2, side="right") - 1
        s = (fine.points - starts[k]) / lengths[k]
        return np.array([[np.polyval(coefficients[r, kk], ss) for kk, ss in zip(k, s)] for r in range(2)])

    at_points = np.array([[np.polyval(coefficients[r, m], t) for m in range(coarse.elements) for t in radau_nodes(d)]
                          for r in range(2)])
    np.testing.assert_allclose(values(coarse), at_points, atol=1e-12)
    cut = coarse.cut(np.isin(np.arange(coarse.elements), [1, 3, 6]))
    assert cut.elements == 11 and coarse.splits(cut) and not cut.splits(coarse)
    twice = cut.cut(np.arange(cut.elements) == 0)
    for fine in (cut, twice):
        np.testing.assert_allclose(coarse.interpolate(at_points, fine), values(fine), atol=1e-11)
    moved = CollocationGrid(T, 9, d, tuple(sorted((*EDGES[:-1], 0.91, 0.95))))
    assert not coarse.splits(moved)  # 0.9 is no element start of it
    with pytest.raises(ValueError, match="does not cut"):
        coarse.interpolate(at_points, moved)


def test_a_measure_carried_to_an_uneven_grid_keeps_its_integral():
    """An inequality's multipliers h_k b_r nu(t) on the uneven grid, carried to the grid with three
    elements cut: each row is h b_r nu(t) of its fine point (to the linear interpolation's error),
    and their sum the integral of nu over the period."""
    nu = lambda t: 2.0 + np.sin(2 * np.pi * t / T)  # noqa: E731
    fine = UNEVEN.cut(np.isin(np.arange(UNEVEN.elements), [0, 2, 5]))
    b = np.tile(np.array([(16 - 6**0.5) / 36, (16 + 6**0.5) / 36, 1 / 9]), UNEVEN.elements)
    h = np.repeat(UNEVEN.lengths, 3)
    band = np.arange(4, 9)
    lam, why = carried_multipliers([("eccentricity", 0, UNEVEN.times.size)], h * b * nu(UNEVEN.times),
                                   UNEVEN.samples(band), [("eccentricity", 0, fine.times.size)], fine.samples(band))
    assert why == ""
    hf, bf = np.repeat(fine.lengths, 3), np.tile(b[:3], fine.elements)
    np.testing.assert_allclose(lam, hf * bf * nu(fine.times), rtol=0.1)  # elements up to 0.18 s, a sine of 0.8 s
    assert lam.sum() == pytest.approx(2.0 * T, rel=2e-2)


def test_equal_edges_give_the_equal_grids_residuals():
    model = build_model(PressParams())
    even, spelled = CollocationGrid(T, 12, 3), CollocationGrid(T, 12, 3, tuple(np.arange(12) / 12))
    np.testing.assert_allclose(spelled.points, even.points, atol=1e-15)
    rng = np.random.default_rng(0)
    X = np.asarray(model.x0, float)[:, None] + 0.1 * rng.normal(size=(model.nx, even.points.size))
    crank = crank_motion(FourierSpeed(T, np.array([0.3, 0.1]), np.array([-0.2, 0.05])), even.times)
    for a, b in zip(collocation_residuals(model, even, ("torque",), X, crank),
                    collocation_residuals(model, spelled, ("torque",), X, crank)):
        np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=1e-12, atol=1e-12)


SMOOTH = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)


@pytest.fixture(scope="module")
def smooth_case():
    model = build_model(SMOOTH.press, n_harmonics=4)
    rig = Rigid(samples=200).solve(SMOOTH, model)
    coarse = Collocation(elements=100, jit=False).solve(SMOOTH, model, WarmStart(rig.speed))
    assert coarse.success and coarse.nlp is not None, coarse.status
    x0 = periodic_state(model, coarse.speed, Integrator("cvodes", 1e-9))[0]
    return model, coarse, Resimulated(model, coarse.speed, x0)


#: The press with its contacts 1000 x softer (hits that last milliseconds, which cut elements resolve)
#: at a constant 150 strokes/min: its journals cross their gaps (eccentricity down to 0.21 of the
#: clearance), so its defects on 200 elements span six decades, highest around the crossings. The
#: smooth case has no such place: its periodic response's defects span 20-50 x, evenly; a response
#: from its periodic search's state (to 1e-4) adds a transient that decays over the period and spans
#: 146-256 x, by CPU, on the threshold of a local cut (1/256).
CROSSING_T = 0.4


@pytest.fixture(scope="module")
def crossing():
    with pytest.warns(PlausibilityWarning, match="stiffness"):
        press = soft_params(PressParams(), 1e3)
    model = build_model(press, n_harmonics=4)
    speed = FourierSpeed(CROSSING_T, np.zeros(4), np.zeros(4))
    x0 = periodic_state(model, speed, Integrator("cvodes", 1e-9), tol=1e-6)[0]
    return Resimulated(model, speed, x0)


def test_local_refinement_cuts_the_elements_with_the_largest_defects_as_far_as_a_uniform_cut(crossing):
    """On 200 elements the cut ones are exactly those with defects within 1/256 of the largest, and the
    cut grid's largest defect is the uniform 400-element grid's, with fewer elements."""
    where, T = crossing, CROSSING_T
    tr = Collocation(elements=200, jit=False, refinement="local")
    grid = tr.grid(T)
    defects = element_defects(where, grid)
    finer = tr.refined(T, "rigid", where)
    chosen = defects >= defects.max() / 256
    assert 0 < chosen.sum() < grid.elements / 2  # some elements, a few
    assert finer.elements == grid.elements + chosen.sum()
    fine = finer.grid(T)
    assert grid.splits(fine)
    # the cut elements are exactly the chosen ones: their starts and midpoints are the fine grid's starts
    expected = np.sort(np.concatenate([grid.starts, (grid.starts + grid.lengths / 2)[chosen]]))
    np.testing.assert_allclose(fine.starts, expected, atol=1e-12)
    uniform = Collocation(elements=400, jit=False).grid(T)
    assert element_defects(where, fine).max() <= 1.01 * element_defects(where, uniform).max() < defects.max() / 4
    assert fine.elements < uniform.elements
    # uniform refinement, the default, ignores where
    assert Collocation(elements=100, jit=False).refined(T, "rigid", where).elements == 200
    # elements at the finest length (0.5 ms: 800 in 0.4 s) are never cut
    assert Collocation(elements=800, jit=False, refinement="local").refined(T, "rigid", where) is None


def test_a_solve_on_the_locally_cut_grid_from_the_carried_solution_reaches_the_finer_optimum(smooth_case):
    model, coarse, where = smooth_case
    local = Collocation(elements=100, jit=False, refinement="local").refined(SMOOTH.period, "rigid", where)
    fine = local.solve(SMOOTH, model, WarmStart(coarse.speed, point=coarse.nlp))
    assert fine.success, fine.status
    assert fine.details["carried_from_elements"] == 100 and fine.details["multipliers_carried"] is True
    assert fine.nlp.grid == local.grid(SMOOTH.period).key and len(fine.details["edges"]) == local.elements
    uniform = Collocation(elements=200, jit=False).solve(SMOOTH, model, WarmStart(coarse.speed, point=coarse.nlp))
    assert fine.objective == pytest.approx(uniform.objective, rel=1e-3)
    assert verify_speed(model, fine.speed, 1e-9).peak("torque") == pytest.approx(fine.objective, rel=5e-3)
    # the stage's settings rebuild its transcription, edges and all
    assert Collocation(**{k: v for k, v in fine.settings.items() if k != "type"}).grid(SMOOTH.period).key == \
        fine.nlp.grid


def test_the_elements_where_the_objective_peaks_are_cut_too(crossing):
    """Times near the re-simulated objective's peak put their elements among the cut ones, whatever
    their defect; `near_peak` finds those times on a response whose torque is known."""
    where, T = crossing, CROSSING_T
    tr = Collocation(elements=200, jit=False, refinement="local")
    grid = tr.grid(T)
    defects = element_defects(where, grid)
    quiet = int(np.argmin(defects))  # far below the cut's threshold
    assert defects[quiet] < defects.max() / 256
    t_quiet = grid.starts[quiet] + 0.3 * grid.lengths[quiet]
    cut = tr.refined(T, "rigid", replace(where, near_peak=np.array([t_quiet + T])))
    plain = tr.refined(T, "rigid", where)
    assert cut.elements == plain.elements + 1
    assert np.any(np.isclose(np.array(cut.edges) * T, grid.starts[quiet] + grid.lengths[quiet] / 2))
    t = np.linspace(0.0, 1.0, 1001)
    sim = SimpleNamespace(t=t + 3.0, torque=100.0 * np.cos(2 * np.pi * t))  # peaks of 100 at 0, 0.5 and 1
    near = near_peak(SMOOTH, sim, 0.02)
    # |cos| >= 0.98 within acos(0.98) / (2 pi) = 0.0319 of each peak
    assert np.all(np.abs(100.0 * np.cos(2 * np.pi * near)) >= 98.0)
    assert near.size == np.sum(np.abs(np.cos(2 * np.pi * t)) >= 0.98)
    rms = replace(SMOOTH, objective="rms_torque")
    assert near_peak(rms, sim, 0.02).size == 0
