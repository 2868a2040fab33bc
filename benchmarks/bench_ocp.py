"""Optimiser benchmark: wall time to convergence of `optimize_speed` on the clearance model, the
SLSQP single-shooting baseline (finite differences, the seed's approach) to the same objective
within 1 %, and the seed story figure.

Cases (run one per call; each appends one JSON line to benchmarks/results/ocp.jsonl and writes
ocp_<case>.png):

* ``default``      T = 1 s, -0.1 m/s: the default call ``optimize_speed(SpeedProblem(PressParams()))``
                   (strategy "auto", collocation for the clearance stage when it runs).
* ``default_all``  the same with every stage run (strategy "all").
* ``default_idas`` the same with the clearance stages by multiple shooting (``MultipleShooting("idas")``,
                   strategy "all"; the old default transcription).
* ``seed``         T = 0.8 s (75 spm), the default call ``optimize_speed(SpeedProblem(PressParams(),
                   period=0.8))``: the rigid-designed speed impacts (model issue), the rigid optimum
                   too, so the chain runs rigid, no-reversal and collocation (0.5 ms elements, journals
                   kept on their bearing walls, compiled when a C compiler is found).
* ``seed_idas``    the seed case with the clearance stages by multiple shooting (``MultipleShooting("idas")``,
                   soft-contact stage first when the start impacts), strategy "all".
* ``seed_collocation``  the seed case, ``Collocation(jit=False)`` (CasADi's virtual machine), strategy "all".
* ``seed_collocation_jit``  the same with ``Collocation(jit=True)`` (compiled model functions).
* ``pin_cap``      the seed default call with the crank-pin and wrist-pin forces capped at ``--cap-N``
                   newtons (``SpeedProblem.max_pin_force``); the row records the answer's peaks
                   (torque, crank-pin and wrist-pin force) for the cap trade-off; writes
                   ocp_pin_cap_<N>N.png.
* ``slsqp``        the baseline on the case named by ``--ref`` (default ``seed``), from the same
                   rigid-designed speed, to the objective that case reached, capped at ``--cap`` s.
* ``flexible``     the seed default call on the flexible rod (4 elements): the same chain, then the
                   clearance stage on the flexible rod unless the rigid-rod answer is verified on it.
* ``slender``      the bundled ``slender_rod`` scenario (Simeon's slider crank, 100 rad/s, ideal
                   joints, flexible rod of 4 elements) through its default call; the rigid-press optimum
                   and the answer are then both re-simulated (periodic, rtol 1e-9) on the flexible rod
                   with 2, 4 and 8 elements (``element_check``).

    python benchmarks/bench_ocp.py CASE [--max-iter K] [--cap SECONDS] [--cap-N NEWTONS] [--ref CASE] [--repeat R]

``--max-iter K`` caps the IPOPT iterations of each clearance stage (the transcription's ``ipopt``
options); by default the transcription's own cap (IPOPT_WARM: 200) applies, so ``seed`` is exactly the default
call. With ``--repeat R`` an optimisation case runs R times in one process: ``wall_time_s`` is the
median, ``wall_times_s`` lists every run, and the rest of the row describes the last run (the runs
must agree: ``answers_agree`` compares their re-simulated peaks to 1e-6: MUMPS on threaded BLAS is
not bitwise repeatable).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path
from typing import TYPE_CHECKING

from pressocp import (Integrator, Collocation, FourierSpeed, MultipleShooting, PressParams, Scenario, SpeedProblem, build_model,
                      design_speed, optimize_speed, simulate)
from pressocp.ocp.strategy import max_relative_change
from pressocp.plots import draw_levels, plot_speed_design, rigid_torque_level, save
from pressocp.report import stamp

from goals import GOAL_CASE_WALL_S, GOAL_FLOOR_RATIO, GOAL_PEAK_NM, GOAL_WALL_S
from status import figure_note  # a sibling script: this folder is the script's path

if TYPE_CHECKING:
    import matplotlib.figure

OUT = Path(__file__).parent / "results"
OPTIMISATION_CASES = ["default", "default_all", "default_idas", "seed", "seed_idas", "seed_collocation",
                      "seed_collocation_jit", "pin_cap", "flexible", "slender"]
#: Cases the SLSQP baseline can be pointed at (peak torque, no pin cap).
REF_CASES = ["default", "default_all", "default_idas", "seed", "seed_idas", "seed_collocation", "seed_collocation_jit"]


def summary(r, case: str, call: dict) -> dict:
    so, si = r.simulation, r.initial_simulation
    return {
        "case": case, "kwargs": call, "problem": r.problem.to_dict(), "model": r.model.describe(),
        "transcription": r.transcription, "strategy": r.strategy,
        "success": r.success, "status": r.status, "wall_time_s": r.wall_time,
        "iterations": r.iterations, "peak_torque": r.peak_torque, "initial_peak_torque": r.initial_peak_torque,
        "rigid_peak_torque": r.rigid_peak_torque, "floor_ratio": r.peak_torque / r.rigid_peak_torque,
        "reported_objective": r.objective_value, "verified_objective": r.verified_objective,
        "resimulated_vs_reported": r.verified_objective / r.objective_value - 1.0,
        "peaks": r.peaks, "initial_peaks": r.initial_peaks,
        "peak_slider_normal_force": so.peak("slider_normal_force"),
        "initial_peak_slider_normal_force": si.peak("slider_normal_force"),
        "torque_reduction_pct": 100 * (1 - r.peak_torque / r.initial_peak_torque),
        "normal_force_reduction_pct": 100 * (1 - so.peak("slider_normal_force") / si.peak("slider_normal_force")),
        "max_speed_change_rel": max_relative_change(r.speed, r.initial_speed),
        "max_ram_speed_violation": r.max_ram_speed_violation, "verified": r.verified, "periodic": r.periodic,
        "limits_exceeded": r.limits,
        "min_omega": r.min_omega, "t1": r.t1, "t2": r.t2, "rigid_t1": r.rigid.t1,
        "periodic_verified": so.stats.get("periodic", {}),
        "stages": [s.to_dict() for s in r.stages], "objective_history": r.history,
        "coefficients": r.speed.coefficients.tolist(),
    }


def element_check(r, elements=(2, 4, 8)) -> list[dict]:
    """The rigid-press optimum and the answer re-simulated (periodic, CVODES rtol 1e-9) on the flexible
    rod of `r`'s press with each element count: the model's own discretisation error."""
    rows = []
    for n in elements:
        model = build_model(r.problem.press, rod="flexible", clearance=r.model.clearance, n_elements=n,
                            n_harmonics=r.problem.n_harmonics)
        for label, speed in (("rigid_optimum", r.stages[0].speed), ("answer", r.speed)):
            t0 = time.perf_counter()
            sim = simulate(model, speed, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=20001)
            rows.append({"n_elements": n, "speed": label, "peak_torque": sim.peak("torque"),
                         "periodic": sim.stats.get("periodic", {}).get("found", True),
                         "max_midspan_deflection": float(abs(sim.rod_midspan_deflection).max()),
                         "wall_time_s": time.perf_counter() - t0})
            print(f"  {n} elements, {label}: {rows[-1]['peak_torque']:.4f} N m", flush=True)
    return rows


def slender_figure(row: dict) -> "matplotlib.figure.Figure":
    """The slender-rod row's two speeds re-simulated on the flexible rod with 8 elements: motor torque and
    midspan deflection over a cycle (the rigid-press optimum against the answer)."""
    import matplotlib.pyplot as plt

    problem = SpeedProblem.from_dict(row["problem"])
    model = build_model(problem.press, rod="flexible", clearance=(), n_elements=8, n_harmonics=problem.n_harmonics)
    speeds = {"rigid-press optimum": FourierSpeed.from_dict(row["stages"][0]["speed"]),
              "flexible-rod optimum (the answer)": FourierSpeed.from_dict(row["stages"][-1]["speed"])}
    fig, ax = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for (label, speed), color in zip(speeds.items(), ("C3", "C0")):
        sim = simulate(model, speed, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=8001)
        ax[0].plot(sim.t * 1e3, sim.torque, color=color, label=f"{label}: peak {sim.peak('torque'):.1f} N·m")
        ax[1].plot(sim.t * 1e3, sim.rod_midspan_deflection * 1e3, color=color, label=label)
    draw_levels(ax[0], [rigid_torque_level(problem.objective, row["rigid_peak_torque"])], legend=False)
    ax[0].set_ylabel("motor torque, N·m")
    ax[1].set_ylabel("rod midspan deflection, mm")
    ax[1].set_xlabel("time, ms")
    ax[0].legend(fontsize=8)
    ax[0].set_title("slender rod at 100 rad/s, both speeds on the flexible rod (8 elements, periodic, rtol 1e-9)",
                    fontsize=10)
    fig.tight_layout()
    figure_note(fig, row.get("run"))  # rows of before rows carried their run: "not recorded"
    return fig


def goal_levels(case: str, floor: float) -> dict[str, list[tuple[float, str]]]:
    """The project's goals on a case's torque axis: the peak within `GOAL_FLOOR_RATIO` x the rigid
    floor (N m), and for the 75 spm default call (``seed``) `GOAL_PEAK_NM`."""
    goals = [(GOAL_FLOOR_RATIO * floor, f"goal: {GOAL_FLOOR_RATIO:.2f} × floor = {GOAL_FLOOR_RATIO * floor:.1f} N·m")]
    if case == "seed":
        goals.append((GOAL_PEAK_NM, f"goal: ≤ {GOAL_PEAK_NM:g} N·m"))
    return {"torque": goals}


def optimisation_call(case: str, max_iter: int | None, cap_N: float | None) -> tuple[dict, dict]:
    """The `optimize_speed` arguments of an optimisation case, and their description for the row."""
    ipopt = {} if max_iter is None else {"ipopt.max_iter": max_iter}
    if case == "slender":
        sc = Scenario.load("slender_rod")
        kwargs = {"problem": sc.problem, "model": sc.build_model(), "transcription": sc.solver.make_transcription(),
                  "strategy": sc.solver.make_strategy()}
        return kwargs, {"scenario": "slender_rod", "model": sc.model.describe(), "max_iter": max_iter}
    period = 1.0 if case.startswith("default") else 0.8
    press = PressParams()
    problem = SpeedProblem(press, period=period, max_pin_force=cap_N if case == "pin_cap" else None)
    kwargs: dict = {"problem": problem}
    if case.endswith("_idas"):
        kwargs.update(transcription=MultipleShooting("idas", ipopt=ipopt), strategy="all")
    elif case.startswith("seed_collocation"):
        kwargs.update(transcription=Collocation(jit=case.endswith("_jit"), ipopt=ipopt), strategy="all")
    else:
        if ipopt:
            kwargs["transcription"] = Collocation(ipopt=ipopt)
        if case == "default_all":
            kwargs["strategy"] = "all"
    if case == "flexible":
        kwargs["model"] = build_model(press, rod="flexible", n_elements=4)
    call = {"period": period, "transcription": repr(kwargs.get("transcription", Collocation())),
            "strategy": kwargs.get("strategy", "auto"), "max_iter": max_iter}
    if case == "pin_cap":
        call["max_pin_force"] = cap_N
    if case == "flexible":
        call["model"] = kwargs["model"].spec.describe()
    return kwargs, call


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=OPTIMISATION_CASES + ["slsqp"])
    ap.add_argument("--max-iter", type=int, default=None,
                    help="IPOPT iteration cap of the clearance stages (default: the transcription's, 300)")
    ap.add_argument("--cap", type=float, default=1800.0, help="SLSQP time cap, s")
    ap.add_argument("--cap-N", type=float, default=None, dest="cap_N",
                    help="pin_cap: cap on the crank-pin and wrist-pin forces, N")
    ap.add_argument("--ref", default="seed", choices=REF_CASES,
                    help="case whose optimum the SLSQP baseline must reach within 1 %%")
    ap.add_argument("--repeat", type=int, default=1, help="runs of an optimisation case (median time)")
    ap.add_argument("--figure-only", action="store_true",
                    help="slender: redraw ocp_slender_flexible.png from the last slender row of ocp.jsonl")
    a = ap.parse_args()
    if a.repeat < 1:
        ap.error(f"--repeat must be >= 1, got {a.repeat}")
    if a.max_iter is not None and a.max_iter < 1:
        ap.error(f"--max-iter must be >= 1, got {a.max_iter}")
    if a.case == "pin_cap" and a.cap_N is None:
        ap.error("pin_cap needs --cap-N NEWTONS")
    if a.case != "pin_cap" and a.cap_N is not None:
        ap.error("--cap-N is for the pin_cap case only")
    OUT.mkdir(exist_ok=True)
    if a.figure_only:
        if a.case != "slender":
            ap.error("--figure-only is for the slender case")
        rows = [json.loads(x) for x in (OUT / "ocp.jsonl").read_text().splitlines()]
        save(slender_figure([x for x in rows if x.get("case") == "slender"][-1]), OUT / "ocp_slender_flexible.png")
        return
    run = stamp()  # when and where the row is measured
    if a.case == "slsqp":
        from slsqp_baseline import slsqp_baseline  # a sibling script: this folder is the script's path

        rows = [json.loads(s) for s in (OUT / "ocp.jsonl").read_text().splitlines()]
        ref = [r for r in rows if r.get("case") == a.ref][-1]
        params = PressParams()
        model = build_model(params)
        if "problem" in ref:  # t1: when the re-simulated clearance ram enters the window
            prob = SpeedProblem.from_dict(ref["problem"])
            h_start = prob.window_heights[0] + model.ram_drop
        else:  # rows of the old interface: t1 was the rigid press's window start
            prob = SpeedProblem(params, period=ref["kwargs"].get("period", 1.0), ram_speed=-0.1)
            h_start = None
        init = design_speed(prob).speed
        # the target is the optimum's verified peak (re-simulated at rtol 1e-9), not a sampled value
        res = slsqp_baseline(model, prob, init, ref["t1"], ref["peak_torque"], time_cap=a.cap, h_start=h_start)
        row = {"case": "slsqp", "ref": a.ref, **res, "optimizer_wall_time_s": ref["wall_time_s"], "run": run,
               "speedup": (">" if not res["reached"] else "") + f"{res['wall_time'] / ref['wall_time_s']:.1f}"}
    else:
        kwargs, call = optimisation_call(a.case, a.max_iter, a.cap_N)
        times, peaks = [], []
        for i in range(a.repeat):
            r = optimize_speed(**kwargs)
            times.append(r.wall_time)
            peaks.append(r.peak_torque)
            print(f"{a.case} run {i + 1}: {r.wall_time:.1f} s, {r.status}, {r.peak_torque:.4f} N m", flush=True)
        row = summary(r, a.case, call)
        row.update(wall_time_s=statistics.median(times), wall_times_s=times,
                   answers_agree=max(peaks) - min(peaks) <= 1e-6 * max(peaks), run=run)
        if a.case == "slender":
            row["element_check"] = element_check(r)
            save(slender_figure(row), OUT / "ocp_slender_flexible.png")
        name = f"pin_cap_{a.cap_N:.0f}N" if a.case == "pin_cap" else a.case
        cap = f", pin forces ≤ {a.cap_N:.0f} N" if a.case == "pin_cap" else ""
        title = (f"{a.case}{cap}: peak torque {r.initial_peak_torque:.0f} → {r.peak_torque:.0f} N·m "
                 f"(rigid floor {r.rigid_peak_torque:.1f}), {row['wall_time_s']:.0f} s "
                 f"(goal {GOAL_CASE_WALL_S.get(a.case, GOAL_WALL_S):.0f} s"
                 f"{'' if a.repeat == 1 else f', median of {a.repeat}'})")
        fig = plot_speed_design(r, title, levels=goal_levels(a.case, r.rigid_peak_torque))
        figure_note(fig, run)
        save(fig, OUT / f"ocp_{name}.png")
    with open(OUT / "ocp.jsonl", "a") as fh:
        fh.write(json.dumps(row, default=float) + "\n")
    short = {k: v for k, v in row.items() if k not in ("objective_history", "history", "coefficients", "stages")}
    if "stages" in row:
        short["stages"] = [f"{s['name']}: {s['status']}, {s['iterations']} it, {s['wall_time']:.1f} s"
                           for s in row["stages"]]
    print(json.dumps(short, default=float, indent=1))


if __name__ == "__main__":
    main()
