"""Multipliers carried to a finer collocation grid (`pressocp.ocp.prolong`): each kind of group
against the function of time it stands for (written here from the rules, not from the code), a
layout the map does not know refused with its reason, and a refined solve of the smooth clearance
case started from the carried solution reaching the optimum of the same grid solved from the
re-simulated response."""

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

import pressocp.ocp.strategy as strategy_module
from pressocp import Collocation, PressParams, Rigid, SpeedProblem, WarmStart, build_model
from pressocp.ocp import Transcription
from pressocp.ocp.collocation import CollocationGrid
from pressocp.ocp.prolong import carried_multipliers
from pressocp.ocp.stage import NlpPoint, StageResult
from pressocp.ocp.strategy import Strategy
from pressocp.speed import FourierSpeed
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


def test_a_refined_stage_that_fails_from_the_carried_start_is_solved_again_from_the_periodic_response(monkeypatch):
    """`Strategy.followed` with a stand-in transcription whose 20-element grid does not converge from
    a carried start: that stage stays in the record, superseded, and the same grid is solved again
    from the answer's periodic state; the next refinement starts from the new answer, carried."""
    speed = FourierSpeed(1.0, np.array([2 * np.pi]), np.zeros(1))
    calls = []

    @dataclass(frozen=True)
    class Halving(Transcription):
        elements: int = 10

        def refined(self, period, rod="rigid", where=None):
            return Halving(2 * self.elements) if self.elements < 40 else None

        def solve(self, problem, model, start, name="target", progress=False):
            carried = start.point is not None
            calls.append((name, self.elements, carried, None if start.x0 is None else list(start.x0)))
            ok = not (carried and self.elements == 20)
            return StageResult(
                name=name, transcription="Halving", model="m", success=ok,
                status="Solve_Succeeded" if ok else "Maximum_Iterations_Exceeded", iterations=1, wall_time=0.0,
                objective=1.0, speed=speed, last_speed=speed, t1=0.0,
                details={"carried_from_elements": start.point.grid[0]} if carried else {},
                nlp=NlpPoint(np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1, int), 1.0, (self.elements, 3)))

    monkeypatch.setattr(Strategy, "verify_stage", lambda self, model, stage: SimpleNamespace(states=np.ones((2, 3))))
    monkeypatch.setattr(Strategy, "grid_error", lambda self, stage, problem: ("re-simulated 2 against 1", 0.0))
    monkeypatch.setattr(strategy_module, "is_periodic", lambda sim: True)
    monkeypatch.setattr(strategy_module, "near_peak", lambda problem, sim, share: np.zeros(0))
    model, problem = SimpleNamespace(rod="rigid", x_scale=np.array([1.0, 2.0])), SimpleNamespace(period=1.0, tol=0.01)
    first = Halving(10).solve(problem, model, WarmStart(speed), "target")
    stages, last = Strategy().followed(problem, model, Halving(10), first, False)
    assert [(s.name, s.success, bool(s.superseded)) for s in stages] == [
        ("target", True, False), ("target_refined_1", False, True), ("target_refined_1_resimulated", True, False),
        ("target_refined_2", True, False)]
    assert calls[1:] == [("target_refined_1", 20, True, [1.0, 0.5]), ("target_refined_1_resimulated", 20, False, [1.0, 0.5]),
                         ("target_refined_2", 40, True, [1.0, 0.5])]
    assert "carried to the finer grid" in stages[1].superseded and last == Halving(40)
