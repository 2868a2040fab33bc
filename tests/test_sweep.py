"""Sweeps: grids and paths, identical tables whatever the executor, failed points as rows, resume."""

import json
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

import pressocp as po
from pressocp import sweeps as sweep_module
from pressocp.plots import plot_sweep
from pressocp.scenario import ScenarioError

RIGID = po.Scenario.load("press75").with_overrides({"model.clearance": []})
SPEED = po.FourierSpeed.constant(0.8)


def comparable(table: pd.DataFrame) -> pd.DataFrame:
    return table.drop(columns=["wall_time_s"])


def test_grid_and_path_points():
    grid, is_path = sweep_module.points_of({"slider_mass": [100.0, 200.0], "problem.stroke_rate_spm": [60, 75, 90]})
    assert not is_path and len(grid) == 6 and grid[1] == {"slider_mass": 100.0, "problem.stroke_rate_spm": 75}
    path, is_path = sweep_module.points_of([{"slider_mass": 100.0}, {"slider_mass": 200.0}])
    assert is_path and path[1] == {"slider_mass": 200.0}
    with pytest.raises(ValueError, match="same keys"):
        sweep_module.points_of([{"slider_mass": 100.0}, {"rod_length": 0.3}])
    with pytest.raises(ValueError, match="non-empty list"):
        sweep_module.points_of({"slider_mass": 100.0})


def test_bad_points_fail_before_anything_runs(serial):
    with pytest.raises(ScenarioError, match="wrist_pin.clearance"):
        po.sweep(RIGID, {"wrist_pin.clearance": [1e-4, 0.2]}, task="simulate", speed=SPEED, executor=serial)
    with pytest.raises(ScenarioError, match="slider_mas"):
        po.sweep(RIGID, {"slider_mas": [100.0]}, task="simulate", speed=SPEED, executor=serial)
    with pytest.raises(ScenarioError, match="period"):
        po.sweep(RIGID, {"problem.stroke_rate_spm": [60, 75]}, task="simulate", speed=SPEED, executor=serial)
    with pytest.raises(ValueError, match="task"):
        po.sweep(RIGID, {"slider_mass": [100.0]}, task="optimise")


def test_simulate_sweep_matches_single_runs_and_is_the_same_on_every_executor(serial):
    """Slider mass on the ideal press at constant speed: the peak torque grows with the ram's mass, and
    each row equals the job run alone; one worker, two workers and in-process give the same table."""
    vary = {"slider_mass": [100.0, 150.0, 200.0], "wrist_pin.clearance": [1e-4, 2e-4]}
    in_process = po.sweep(RIGID, vary, task="simulate", speed=SPEED, executor=serial, progress=False)
    assert list(in_process.columns[:3]) == ["slider_mass", "wrist_pin.clearance", "task"]
    assert in_process["ok"].all() and (in_process["error"] == "").all() and len(in_process) == 6
    torque = in_process.groupby("slider_mass")["peak_torque_N_m"].first().to_numpy()
    assert np.all(np.diff(torque) > 0)
    alone = po.rigid_response(RIGID.with_overrides({"slider_mass": 200.0}).press, SPEED,
                              np.linspace(0, 0.8, 20001)).peak("torque")
    assert in_process["peak_torque_N_m"].iloc[-1] == pytest.approx(alone, rel=1e-12)
    for workers in (1, 2):
        with ProcessPoolExecutor(workers) as pool:
            parallel = po.sweep(RIGID, vary, task="simulate", speed=SPEED, executor=pool, progress=False)
        pd.testing.assert_frame_equal(comparable(parallel), comparable(in_process))


def test_a_failed_point_is_a_row(monkeypatch, serial):
    from pressocp import sweeps

    original = sweeps.simulate_speed

    def fails_for_heavy_rams(scenario, speed):
        if scenario.press.slider_mass > 180:
            raise RuntimeError("integrator failed at t = 0.3 s\nhint")
        return original(scenario, speed)

    monkeypatch.setattr(sweeps, "simulate_speed", fails_for_heavy_rams)
    table = po.sweep(RIGID, {"slider_mass": [150.0, 200.0]}, task="simulate", speed=SPEED, executor=serial,
                     progress=False)
    assert table["ok"].tolist() == [True, False]
    assert table["error"].iloc[1] == "RuntimeError: integrator failed at t = 0.3 s"
    assert np.isnan(table["peak_torque_N_m"].iloc[1]) and table["peak_torque_N_m"].iloc[0] > 0


def test_a_point_that_is_not_periodic_says_why_in_its_error(monkeypatch, serial):
    from pressocp import sweeps

    original = sweeps.simulate_speed

    def not_periodic_for_heavy_rams(scenario, speed):
        sim, ideal = original(scenario, speed)
        if scenario.press.slider_mass > 180:
            sim.stats["periodic"] = {"found": False, "reason": "periodic steady state not found: residual 0.002"}
        return sim, ideal

    monkeypatch.setattr(sweeps, "simulate_speed", not_periodic_for_heavy_rams)
    table = po.sweep(RIGID, {"slider_mass": [150.0, 200.0]}, task="simulate", speed=SPEED, executor=serial,
                     progress=False)
    assert table["ok"].tolist() == [True, False]
    assert table["error"].tolist() == ["", "not periodic: periodic steady state not found: residual 0.002"]


def test_resume_from_csv_skips_points_done(tmp_path, monkeypatch, serial):
    csv = tmp_path / "sweep.csv"
    first = po.sweep(RIGID, {"slider_mass": [100.0, 150.0]}, task="simulate", speed=SPEED, executor=serial,
                     progress=False, csv=csv)
    assert len(pd.read_csv(csv)) == 2
    calls = []
    original = sweep_module.run_point
    monkeypatch.setattr(sweep_module, "run_point", lambda *a, **k: calls.append(a[1].press.slider_mass) or original(*a, **k))
    again = po.sweep(RIGID, {"slider_mass": [100.0, 150.0, 200.0]}, task="simulate", speed=SPEED,
                     executor=serial, progress=False, csv=csv)
    assert calls == [200.0] and len(again) == 3 and len(pd.read_csv(csv)) == 3
    assert again["peak_torque_N_m"].iloc[:2].tolist() == pytest.approx(first["peak_torque_N_m"].tolist(), rel=1e-9)


def test_rescaled_speed_keeps_the_crank_motion_per_cycle():
    speed = po.FourierSpeed(0.8, [1.0, 0.5], [0.2, -0.3])
    other = sweep_module.rescale(speed, 1.0)
    s = np.linspace(0, 1, 101)
    assert np.allclose(other.theta(s * 1.0), speed.theta(s * 0.8), atol=1e-12)


@pytest.mark.slow  # 8-15 s (a dask cluster started); executors by default: the test above
def test_dask_local_cluster_gives_the_same_table(serial):
    distributed = pytest.importorskip("distributed")
    vary = {"slider_mass": [100.0, 200.0]}
    in_process = po.sweep(RIGID, vary, task="simulate", speed=SPEED, executor=serial, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        table = po.sweep(RIGID, vary, task="simulate", speed=SPEED, executor=client.get_executor(), progress=False)
    pd.testing.assert_frame_equal(comparable(table), comparable(in_process))
    assert json.loads(table["speed"].iloc[0])["period"] == 0.8


def test_a_grid_continued_along_a_key_runs_segments_cold_then_from_the_neighbour(tmp_path, monkeypatch, serial):
    """Continuation along the clearance: each line (one slider mass) is cut into segments of two; a
    segment's first point starts cold, its second from the first's optimum; a failed first point leaves
    the second cold; a resumed sweep starts a segment's open point from the optimum in the CSV."""
    starts = {}

    def stub(task, scenario, speed=None, initial=None):
        key = (scenario.press.wrist_pin.clearance, scenario.press.slider_mass)
        starts[key] = None if initial is None else initial.a[0]
        ok = key != (3e-4, 200.0)
        mark = 1e4 * key[0] + key[1]  # each optimum told apart by its mean speed
        return {"task": task, "ok": ok, "error": "" if ok else "RuntimeError: x",
                "speed": json.dumps(po.FourierSpeed(0.8, [mark], [0.0]).to_dict())}

    monkeypatch.setattr(sweep_module, "run_point", stub)
    vary = {"wrist_pin.clearance": [1e-4, 2e-4, 3e-4, 4e-4, 5e-4], "slider_mass": [100.0, 200.0]}
    along = sweep_module.Continuation("wrist_pin.clearance")
    assert along.segments(sweep_module.points_of(vary)[0]) == [[0, 2], [4, 6], [8], [1, 3], [5, 7], [9]]
    table = po.sweep(RIGID, vary, executor=serial, progress=False, continuation=along)
    assert len(table) == 10 and table["task"].eq("optimize").all()
    assert starts == {(1e-4, 100.0): None, (2e-4, 100.0): 1 + 100.0, (3e-4, 100.0): None, (4e-4, 100.0): 3 + 100.0,
                      (5e-4, 100.0): None, (1e-4, 200.0): None, (2e-4, 200.0): 1 + 200.0, (3e-4, 200.0): None,
                      (4e-4, 200.0): None, (5e-4, 200.0): None}
    starts.clear()
    csv = tmp_path / "sweep.csv"
    po.sweep(RIGID, {"wrist_pin.clearance": [1e-4]}, executor=serial, progress=False, csv=csv)
    starts.clear()  # the press's own slider mass, 150 kg
    po.sweep(RIGID, {"wrist_pin.clearance": [1e-4, 2e-4, 3e-4]}, executor=serial, progress=False, csv=csv,
             continuation=sweep_module.Continuation("wrist_pin.clearance", segment=3))
    assert starts == {(2e-4, 150.0): 1 + 150.0, (3e-4, 150.0): 2 + 150.0}
    for bad, words in ((dict(vary=[{"slider_mass": 100.0}], continuation=along), "path"),
                       (dict(vary={"slider_mass": [100.0]}, continuation=along), "not a key of the grid"),
                       (dict(vary=vary, continuation=along, task="simulate", speed=SPEED), "task 'simulate'")):
        with pytest.raises(ValueError, match=words):
            po.sweep(RIGID, **{"executor": serial, "progress": False, **bad})
    with pytest.raises(ValueError, match="segment"):
        sweep_module.Continuation("slider_mass", segment=0)


@given(sizes=st.lists(st.integers(1, 4), min_size=1, max_size=3), along=st.integers(0, 2),
       segment=st.integers(1, 5))
def test_segments_cover_each_line_in_order_with_at_most_segment_points(sizes, along, segment):
    """Any grid: every point is in exactly one segment; a segment's points differ only in the key it
    continues along, follow that key's values in order, and number at most `segment`."""
    keys = [f"k{i}" for i in range(len(sizes))]
    along_key = keys[along % len(keys)]
    points, _ = sweep_module.points_of({k: list(range(n)) for k, n in zip(keys, sizes)})
    segments = sweep_module.Continuation(along_key, segment).segments(points)
    assert sorted(i for seg in segments for i in seg) == list(range(len(points)))
    for seg in segments:
        assert 1 <= len(seg) <= segment
        others = {tuple(v for k, v in points[i].items() if k != along_key) for i in seg}
        assert len(others) == 1
        values = [points[i][along_key] for i in seg]
        assert values == list(range(values[0], values[0] + len(seg)))
    # a line of n points makes ceil(n / segment) segments
    n_along = sizes[keys.index(along_key)]
    assert len(segments) == (len(points) // n_along) * -(-n_along // segment)


@pytest.mark.slow  # 40 s
def test_a_continued_grid_of_optima_on_worker_processes_matches_cold_starts():
    """Ideal press, 6 harmonics: the grid continued along the slider mass on 2 worker processes gives
    each point's cold optimum, and its rows say which points started from their neighbour."""
    base = RIGID.with_overrides({"problem.n_harmonics": 6})
    vary = {"slider_mass": [100.0, 130.0], "rod_mass": [2.0, 4.0]}
    with ProcessPoolExecutor(2) as pool:
        warm = po.sweep(base, vary, executor=pool, progress=False, continuation=po.Continuation("slider_mass"))
        cold = po.sweep(base, vary, executor=pool, progress=False)
    assert warm["ok"].all() and cold["ok"].all()
    assert warm["start"].tolist()[2:] == ["neighbour", "neighbour"] and warm["start"].iloc[:2].isna().all()
    np.testing.assert_allclose(warm["peak_torque_N_m"], cold["peak_torque_N_m"], rtol=1e-3)


@pytest.mark.slow  # 14 s
def test_a_path_of_optima_starts_each_from_its_neighbour(monkeypatch, serial):
    """On the ideal press with 6 harmonics (seconds): the second optimum of a path starts from the
    first, rescaled to its period; its answer equals a cold solve of that point."""
    base = RIGID.with_overrides({"problem.n_harmonics": 6})
    starts = []
    original = sweep_module.run_point

    def spy(task, scenario, speed=None, initial=None):
        starts.append(None if initial is None else initial.period)
        return original(task, scenario, speed, initial)

    monkeypatch.setattr(sweep_module, "run_point", spy)
    path = [{"problem.stroke_rate_spm": 60}, {"problem.stroke_rate_spm": 66}]
    warm = po.sweep(base, path, task="optimize", executor=serial, progress=False)
    assert starts == [None, pytest.approx(60 / 66)] and warm["ok"].all()
    assert warm["start"].iloc[1] == "neighbour"  # the path's rows say where their answer came from
    cold = po.sweep(base, {"problem.stroke_rate_spm": [66]}, task="optimize", executor=serial, progress=False)
    assert warm["peak_torque_N_m"].iloc[1] == pytest.approx(cold["peak_torque_N_m"].iloc[0], rel=1e-3)
    # the study figure (notebook 06): on the ideal press each optimum is its own floor (a rescaled
    # neighbour is no feasible start: the window moves with the period, so it may have a lower peak)
    np.testing.assert_allclose(warm["peak_torque_N_m"], warm["rigid_peak_torque_N_m"], rtol=1e-3)
    fig = plot_sweep(warm, ["problem.stroke_rate_spm"], "reduced study")
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert "rigid-press floor" in labels and "initial speed" in labels
    assert fig.axes[-1].get_xlabel() == "problem.stroke_rate_spm [strokes/min]"
    starts.clear()  # without continuation, a path is a list of independent cold starts

    def stub(task, scenario, speed=None, initial=None):
        starts.append(None if initial is None else initial.period)
        return {"task": task, "ok": True, "error": "", "speed": warm["speed"].iloc[0]}

    monkeypatch.setattr(sweep_module, "run_point", stub)
    po.sweep(base, path, task="optimize", executor=serial, progress=False, continuation=False)
    assert starts == [None, None]


def test_wear_study_of_a_design_that_keeps_contact(tmp_path, serial):
    """The 60 spm kinematic design keeps the rod in tension (no impact at 0.1 mm): on a rigid rod with a
    worn wrist pin (0.1 and 0.3 mm) the journal stays on its wall, the peak torque stays within 2 % of
    the ideal press's, and the table and its figure come out."""
    from pressocp.plots import plot_wear
    from pressocp.studies import wear_study

    scenario = po.Scenario.load("press60").with_overrides({"model.clearance": ["wrist_pin"]})
    speed = po.design_speed(scenario.problem).speed
    table = wear_study(scenario, speed, clearances=(1e-4, 3e-4), executor=serial)
    assert table["clearance"].tolist() == [1e-4, 3e-4] and table["ok"].all()
    assert table["wrist_pin.clearance"].tolist() == [1e-4, 3e-4]
    assert (table["min_wrist_pin_eccentricity"] > 0.99).all() and not table["free_flight"].any()
    assert (abs(table["torque_ratio"] - 1) < 0.02).all()
    fig = plot_wear(table, 1e-4)
    fig.savefig(tmp_path / "wear.png")
    assert (tmp_path / "wear.png").stat().st_size > 10_000
    with pytest.raises(ValueError, match="no clearance joint"):
        wear_study(RIGID, speed)


@pytest.mark.slow  # 100 s
def test_a_default_call_and_a_sweep_point_reach_the_same_answer_to_the_bit():
    """press75 (both clearances): the default call runs its rigid stage here and its candidate chains
    side by side in workers; a sweep's point runs all of them one after the other in one worker.
    With CasADi's BLAS on one thread everywhere (`pressocp.blas`) the two take the same path; with two
    threads here, the default call reached 145.14407 N·m against the sweep's 145.14371 (press60's
    paths do not part, so it could not tell)."""
    scenario = po.Scenario.load("press75")
    direct = scenario.optimize(progress=False)
    # a point, not a path (`continuation=False`): it runs in the package's worker pool, not here
    row = po.sweep(scenario, [{"slider_mass": scenario.problem.press.slider_mass}], progress=False,
                   continuation=False).iloc[0]
    assert direct.verified and row["ok"]
    swept = po.FourierSpeed.from_dict(json.loads(row["speed"]))
    assert swept.a.tolist() == direct.speed.a.tolist() and swept.b.tolist() == direct.speed.b.tolist()
    assert row["peak_torque_N_m"] == direct.peak_torque


@pytest.mark.parametrize("converged, verified, error", [
    (True, False, "not verified: the ram speed leaves its tolerance by 2e-05 m/s"),
    (False, False, "not converged (Maximum_Iterations_Exceeded)"),
])
def test_an_optimum_not_converged_or_not_verified_says_why_in_its_error(monkeypatch, converged, verified, error):
    """The optimize task's row names why it is not ok, as the command line's flag does (the solve and its
    summary stand in)."""
    from types import SimpleNamespace

    fake = SimpleNamespace(success=converged, verified=verified, speed=SPEED)
    summary = {"converged": converged, "verified": verified, "periodic": True, "max_ram_speed_violation_m_s": 2e-5,
               "limits_exceeded": {}, "status": "Maximum_Iterations_Exceeded"}
    monkeypatch.setattr(po.Scenario, "optimize", lambda self, *args, **kwargs: fake)
    monkeypatch.setattr(sweep_module, "optimum_summary", lambda scenario, result: summary)
    row = sweep_module.run_point("optimize", RIGID)
    assert row["ok"] is False and row["error"] == error
