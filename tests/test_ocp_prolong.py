"""Multipliers carried to a finer collocation grid (`pressocp.ocp.prolong`): each kind of group
against the function of time it stands for (written here from the rules, not from the code), a
layout the map does not know refused with its reason, and a refined solve of the smooth clearance
case started from the carried solution reaching the optimum of the same grid solved from the
re-simulated response."""

import numpy as np
import pytest

from pressocp import Collocation, PressParams, Rigid, SpeedProblem, WarmStart, build_model
from pressocp.ocp.collocation import CollocationGrid
from pressocp.ocp.prolong import carried_multipliers
from pressocp.verify import verify_speed

T = 0.8
COARSE, FINE = CollocationGrid(T, 20, 3), CollocationGrid(T, 40, 3)
B = np.array([(16 - 6**0.5) / 36, (16 + 6**0.5) / 36, 1 / 9])  # Radau IIA weights, d = 3


def density(t):
    return 2.0 + np.sin(2 * np.pi * t / T)


def layout(grid: CollocationGrid, band: np.ndarray, nx: int = 2) -> list:
    """A collocation NLP's groups in the order `Collocation.solve` and `solve_states` add them."""
    N, K = grid.times.size, grid.elements
    sizes = [("collocation", nx * N), ("eccentricity", N), ("crank_motion", 3 * N), ("continuity", nx * K),
             ("epigraph", N), ("epigraph", N), ("ram_speed_samples", band.size), ("window_phase", 1),
             ("window_phase", 1), ("omega", 1000)]
    out, i = [], 0
    for name, k in sizes:
        out.append((name, i, k))
        i += k
    return out


def coarse_multipliers(groups: list, band: np.ndarray) -> np.ndarray:
    """Multipliers of the coarse grid as the module's rules say they follow a costate p and a density
    nu: b_r p for collocation, h b_r nu for measures, p at the element ends for continuity."""
    t, h = COARSE.times, COARSE.h
    b = np.tile(B, COARSE.elements)
    rows = {"collocation": np.vstack([b * density(t), -b * density(t)]).ravel(order="F"),
            "eccentricity": h * b * density(t), "crank_motion": np.vstack([h * b * density(t)] * 3).ravel(order="F"),
            "continuity": np.vstack([density(h * np.arange(1, 21))] * 2).ravel(order="F"),
            "epigraph": h * b * density(t), "ram_speed_samples": (h * b * density(t))[band],
            "window_phase": np.array([0.25]), "omega": np.linspace(-1, 1, 1000)}
    return np.concatenate([rows[name] for name, _, _ in groups])


def test_each_group_is_carried_as_the_function_of_time_it_stands_for():
    band_c, band_f = np.arange(10, 16), np.arange(19, 33)
    gc, gf = layout(COARSE, band_c), layout(FINE, band_f)
    lam, why = carried_multipliers(gc, coarse_multipliers(gc, band_c), COARSE.samples(band_c), gf,
                                   FINE.samples(band_f))
    assert why == "" and lam.size == gf[-1][1] + gf[-1][2]
    t, h, b = FINE.times, FINE.h, np.tile(B, FINE.elements)
    got = {name: lam[i : i + k] for name, i, k in gf}
    tol = 2e-2  # linear interpolation of a sine on elements of 1/20 of its period
    np.testing.assert_allclose(got["collocation"], np.vstack([b * density(t), -b * density(t)]).ravel(order="F"),
                               rtol=tol)
    np.testing.assert_allclose(got["eccentricity"], h * b * density(t), rtol=tol)
    np.testing.assert_allclose(got["crank_motion"], np.vstack([h * b * density(t)] * 3).ravel(order="F"), rtol=tol)
    np.testing.assert_allclose(got["continuity"], np.vstack([density(h * np.arange(1, 41))] * 2).ravel(order="F"),
                               rtol=tol)
    np.testing.assert_allclose(got["epigraph"], h * b * density(t), rtol=tol)
    np.testing.assert_allclose(got["ram_speed_samples"], (h * b * density(t))[band_f], rtol=tol)
    assert got["window_phase"][0] == 0.25 and np.array_equal(got["omega"], np.linspace(-1, 1, 1000))
    # a measure's total (the integral of its density) is kept: halved elements, twice the rows
    assert got["eccentricity"].sum() == pytest.approx(h * b @ density(t), rel=1e-12)
    assert got["eccentricity"].sum() == pytest.approx(2.0 * T, rel=1e-3)  # the integral of 2 + sin over a period


def test_a_layout_the_map_does_not_know_is_refused_with_its_reason():
    band = np.arange(10, 16)
    gc = layout(COARSE, band)
    lam = coarse_multipliers(gc, band)
    assert carried_multipliers(gc, lam, COARSE.samples(band), gc[:-1], FINE.samples(band))[1] == \
        "the two grids' NLPs have different constraint groups"
    odd = [("mystery", 0, 5)]
    assert carried_multipliers(odd, np.zeros(5), COARSE.samples(band), odd, FINE.samples(band)) == \
        (None, "no rule carries group mystery to a finer grid")
    fixed = [("omega", 0, 5)], [("omega", 0, 6)]
    assert "5 rows on one grid and 6" in carried_multipliers(fixed[0], np.zeros(5), COARSE.samples(band), fixed[1],
                                                              FINE.samples(band))[1]


SMOOTH = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)


def test_a_refined_solve_from_the_carried_solution_reaches_the_finer_grids_optimum():
    """The smooth clearance case on 100 elements, then on 200 from that solution, primal and dual:
    it starts at the carried point (no simulation), converges, and ends at the optimum of the same
    200-element NLP solved from the re-simulated response (a different start), its re-simulation
    confirming the peak."""
    model = build_model(SMOOTH.press, n_harmonics=4)
    rig = Rigid(samples=200).solve(SMOOTH, model)
    coarse = Collocation(elements=100, jit=False).solve(SMOOTH, model, WarmStart(rig.speed))
    assert coarse.success and coarse.nlp is not None, coarse.status
    fine = Collocation(elements=200, jit=False).solve(SMOOTH, model, WarmStart(coarse.speed, point=coarse.nlp))
    assert fine.details["carried_from_elements"] == 100 and fine.details["multipliers_carried"] is True
    assert "periodic_warm_start" not in fine.details
    assert fine.success, fine.status
    cold = Collocation(elements=200, jit=False).solve(SMOOTH, model, WarmStart(coarse.speed))
    assert cold.success and "multipliers_carried" not in cold.details
    assert fine.objective == pytest.approx(cold.objective, rel=1e-4)
    assert verify_speed(model, fine.speed, 1e-9).peak("torque") == pytest.approx(fine.objective, rel=5e-3)
