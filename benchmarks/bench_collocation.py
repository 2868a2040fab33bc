"""Speed against accuracy of the collocation stage on the clearance model: the seed case (T = 0.8 s,
-0.1 m/s over h/H 0.7 -> 0.3, 15 harmonics, both clearances, rigid rod, target contact), solved by
Radau collocation with the journals kept on their bearing walls (``min_eccentricity=1``) for a
range of element counts, each from the same start: the no-reversal optimum (the start the default
`optimize_speed` chain gives its collocation stage: the rigid problem with the rod tension at both
pins kept above 5 % of the hanging weight, warm-started from the rigid optimum, both `Rigid()`
solves with the clearance model's ram drop) and its periodic response.

Per element count: wall time and iterations of the collocation solve, the warm start's
collocation defect, the value IPOPT reported and the peak of an independent periodic CVODES
re-simulation of the optimum (rtol 1e-9, 20 000 samples), their difference, the ram-speed
violation and the least eccentricity ratio of the re-simulation (>= 1: contact kept).

Writes benchmarks/results/collocation.json and collocation.png.

    python benchmarks/bench_collocation.py [--elements 300 400 600 800 1200 1600] [--jit] [--replot]

``--jit`` compiles each grid's point function (``Collocation(jit=True)``; without it ``jit=False``,
CasADi's virtual machine); its compilation is inside the measured solve time. ``wall_time_s`` is the
whole `Collocation.solve` call: the integration of the warm start's states at the grid points (from
its periodic state, given), the NLP's construction (and compilation) and IPOPT; ``nlp_wall_time_s``
is the stage's own record.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from pressocp import Collocation, PressParams, SpeedProblem, Strategy, WarmStart, design_speed
from pressocp.model import build_model
from pressocp.verify import ram_speed_violation, verify_speed
from pressocp.plots import save
from pressocp.report import stamp
from pressocp.rigid import rigid_response
from pressocp.simulate import Integrator, periodic_state
from goals import GOAL_WALL_S, GOAL_VERIFY_PCT, GOAL_PEAK_NM, GOAL_FLOOR_RATIO
from status import figure_note, job_run  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"
PERIOD = 0.8


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--elements", type=int, nargs="+", default=[300, 400, 600, 800, 1200, 1600])
    ap.add_argument("--max-iter", type=int, default=300)
    ap.add_argument("--jit", action="store_true", help="compile the point function (CasADi JIT)")
    ap.add_argument("--replot", action="store_true", help="only redraw the PNG from the JSON")
    a = ap.parse_args()
    if a.replot:
        save(figure(json.loads((OUT / "collocation.json").read_text())), OUT / "collocation.png")
        return
    params = PressParams()
    model = build_model(params)
    problem = SpeedProblem(params, period=PERIOD, ram_speed=-0.1)
    t0 = time.perf_counter()
    strategy = Strategy()
    rigid = strategy.rigid.solve(problem, model, WarmStart(design_speed(problem).speed), "rigid")
    start = strategy.rigid.solve(problem.replace(min_tension=strategy.margins[0] * problem.hanging_weight),
                                 model, WarmStart(rigid.speed), "no_reversal")
    start_time = time.perf_counter() - t0
    x0, _ = periodic_state(model, start.speed, integrator=Integrator(method="cvodes", rtol=1e-9))
    start_peak = verify_speed(model, start.speed, 1e-9, x0=x0).peak("torque")
    floor = rigid_response(params, rigid.speed, np.linspace(0.0, PERIOD, 20001)).peak("torque")
    rows = []
    for K in a.elements:
        settings = Collocation(elements=K, min_eccentricity=1.0, jit=a.jit, ipopt={"ipopt.max_iter": a.max_iter})
        t0 = time.perf_counter()
        sol = settings.solve(problem, model, WarmStart(start.speed, x0), name=f"collocation_{K}")
        wall = time.perf_counter() - t0
        sim = verify_speed(model, sol.speed, 1e-9)
        peak = sim.peak("torque")
        rows.append({
            "elements": K, "success": sol.success, "status": sol.status, "iterations": sol.iterations,
            "wall_time_s": wall, "nlp_wall_time_s": sol.wall_time, "defect_start": sol.details["defect_start"],
            "reported_peak_torque": sol.objective, "resimulated_peak_torque": peak,
            "reported_vs_resimulated": sol.objective / peak - 1.0,
            "ram_speed_violation": max(ram_speed_violation(sim, problem), 0.0),
            "min_eccentricity_ratio": float(min(sim.crank_pin_eccentricity.min(), sim.wrist_pin_eccentricity.min())),
            "periodic": sim.stats.get("periodic", {}),
        })
        print(json.dumps(rows[-1], default=float), flush=True)
    out = {"case": "seed, T = 0.8 s, -0.1 m/s, both clearances",
           "start": "no-reversal optimum (Rigid stages of the default Strategy)",
           "start_peak_torque": start_peak, "start_wall_time_s": start_time,
           "start_status": start.status, "rigid_floor": floor, "jit": a.jit, "rows": rows, "run": stamp()}
    (OUT / "collocation.json").write_text(json.dumps(out, indent=1, default=float))
    save(figure(out), OUT / "collocation.png")


def figure(out: dict):
    rows = out["rows"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    K = np.array([r["elements"] for r in rows])
    wall = np.array([r["wall_time_s"] for r in rows])
    err = np.abs([r["reported_vs_resimulated"] for r in rows])
    ok = np.array([r["success"] for r in rows])
    ax.semilogy(wall[ok], 100 * err[ok], "o", label="converged")
    if (~ok).any():
        ax.semilogy(wall[~ok], 100 * err[~ok], "x", color="C3", label="not converged")
    for k, w, e in zip(K, wall, err):
        ax.annotate(f"{k}", (w, 100 * e), textcoords="offset points", xytext=(4, 4), fontsize=8)
    jit = " (compiled, compilation included)" if out.get("jit") else ""
    # the project's goals (issue #4): the whole optimisation within 120 s on 2 cores (the solve
    # alone here; the start took start_wall_time_s more), the reported peak within 2 % of the re-simulated
    ax.axvline(GOAL_WALL_S, color="tab:red", ls="--", lw=0.8)
    ax.text(GOAL_WALL_S, 1.0, f" goal: {GOAL_WALL_S:.0f} s", transform=ax.get_xaxis_transform(),
            color="tab:red", fontsize=7, ha="right", va="bottom")
    if out.get("start_wall_time_s"):
        budget = GOAL_WALL_S - out["start_wall_time_s"]
        ax.axvline(budget, color="0.5", ls="--", lw=0.8)
        ax.text(budget, 0.99, f"120 s − start ({out['start_wall_time_s']:.0f} s) ", transform=ax.get_xaxis_transform(),
                color="0.4", fontsize=7, ha="right", va="top")  # inside, below the goal's label
    ax.axhline(GOAL_VERIFY_PCT, color="tab:red", ls="--", lw=0.8)
    ax.text(ax.get_xlim()[0], GOAL_VERIFY_PCT, f"  goal: within {GOAL_VERIFY_PCT:g} %", color="tab:red", fontsize=7,
            va="bottom")
    ax.set(xlabel=f"collocation solve wall time{jit}, s", ylabel="|reported − re-simulated| peak, %",
           title="speed against accuracy (labels: elements)\n")
    ax.legend(loc="center left")
    peak = np.array([r["resimulated_peak_torque"] for r in rows])
    bx.plot(K[ok], peak[ok], "o-", label="collocation optimum (re-simulated)")
    if (~ok).any():
        bx.plot(K[~ok], peak[~ok], "x", color="C3", label="not converged (its last iterate)")
    bx.axhline(out["start_peak_torque"], color="C1", ls="--", label="start: no-reversal optimum")
    bx.axhline(out["rigid_floor"], color="k", ls=":", label="rigid floor")
    # goals: the seed case's default call at most 147.5 N·m (issue #14); near the floor, 1.10 × (issue #4)
    near = GOAL_FLOOR_RATIO * out["rigid_floor"]
    for v, text in ((GOAL_PEAK_NM, f"goal: ≤ {GOAL_PEAK_NM:g} N·m"),
                    (near, f"goal: {GOAL_FLOOR_RATIO:.2f} × floor = {near:.1f} N·m")):
        bx.axhline(v, color="tab:red", ls="--", lw=0.8)
        bx.text(bx.get_xlim()[0], v, "  " + text, color="tab:red", fontsize=7, ha="left", va="top")  # under the line
    bx.set(xlabel="elements per period", ylabel="peak motor torque, N·m", title="optimum on the clearance model\n")
    bx.legend(loc="center right", fontsize=8)
    fig.tight_layout()
    # a file of before the rows carried their run: the runner's record of the job that wrote it
    figure_note(fig, out.get("run") or job_run("collocation.json"))
    return fig


if __name__ == "__main__":
    main()
