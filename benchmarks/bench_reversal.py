"""How much joint-force reversal does the clearance model forgive? The seed case (T = 0.8 s,
-0.1 m/s over h/H 0.7 -> 0.3, 15 harmonics): the rigid optimum (the floor) compresses the rod by
about 1.7 kN and impacts on the clearance model. This sweep solves the rigid problem again with the
rod tension at both pins bounded below by ``min_tension`` (negative: a shallow reversal of at most
that much compression is allowed), warm-started from the rigid optimum, and re-simulates each
optimum on the clearance model (both pins, rigid rod): the 4th cycle from rest, then the periodic
response unless that cycle impacts (`pressocp.verify.screen`, as `optimize_speed` does). The
rigid solves are `Rigid(samples=...)` for the clearance model, as the chain's: the window is
widened by the model's ram drop so that the ram speed holds on that model's own window, where the
re-simulation checks it.

Writes benchmarks/results/reversal.json and reversal.png.

    python benchmarks/bench_reversal.py [--bounds -300 -30 0 75 ...] [--samples 1000]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from pressocp import PressParams, Rigid, SpeedProblem, WarmStart, rigid_inverse_dynamics, rigid_response
from pressocp.design import design_speed
from pressocp.model import build_model
from pressocp.verify import IMPACT_RATIO, is_periodic, ram_speed_violation, screen
from pressocp.plots import save

OUT = Path(__file__).parent / "results"
BOUNDS = [-1000.0, -300.0, -100.0, -30.0, -20.0, -10.0, -3.0, 0.0, 25.0, 50.0, 75.0, 100.0]


def row(problem: SpeedProblem, model, r, bound: float | None, wall: float) -> dict:
    """Rigid-model and clearance-model loads of one rigid-stage optimum `r` (a `StageResult`)."""
    period = problem.period
    t = np.linspace(0.0, period, 8001)
    dense = rigid_response(problem.press, r.speed, t)
    ne = rigid_inverse_dynamics(problem.press, *r.speed.evaluate(t))
    tension = np.minimum(ne["crank_pin_tension"], ne["wrist_pin_tension"])
    sim, ratio = screen(model, r.speed, dense.peak("torque"), "peak_torque", 1e-7)
    periodic = is_periodic(sim)
    return {
        "min_tension": bound, "status": r.status, "success": r.success, "solve_time_s": wall,
        "rigid_peak_torque": dense.peak("torque"), "rigid_min_tension": float(tension.min()),
        "reversed_fraction": float(np.mean(tension < 0.0)),
        "clearance_peak_torque": sim.peak("torque"), "clearance_ratio": ratio, "periodic": periodic,
        "clearance_peak_slider_normal_force": sim.peak("slider_normal_force"),
        "clearance_peak_pin_force": max(sim.peak("crank_pin_force"), sim.peak("wrist_pin_force")),
        "rigid_peak_pin_force": max(dense.peak("crank_pin_force"), dense.peak("wrist_pin_force")),
        "ram_speed_violation": max(ram_speed_violation(sim, problem), 0.0),
    }


def figure(rows: list[dict], floor: float):
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    b = np.array([r["min_tension"] for r in rows[1:]])
    for a, key, label in ((ax, "peak_torque", "peak motor torque, N·m"), (bx, "peak_pin_force", "peak pin force, N")):
        a.plot(b, [r["rigid_" + key] for r in rows[1:]], "o-", label="rigid model (optimised)")
        a.plot(b, [r["clearance_" + key] for r in rows[1:]], "s-", label="clearance model (re-simulated)")
        a.axhline(rows[0]["clearance_" + key], color="C1", ls=":", label="rigid optimum on the clearance model")
        a.axhline(rows[0]["rigid_" + key], color="C0", ls=":", label="rigid optimum (the floor)")
        a.axvline(0.0, color="0.6", lw=0.8)
        a.set_xscale("symlog", linthresh=10.0)
        a.set_yscale("log")
        a.set_xlabel("least rod tension the rigid stage keeps, N (< 0: reversal allowed)\n"
                     "symmetric log axis: linear within ±10 N")
        a.set_ylabel(label)
    ax.axhline(1.10 * floor, color="k", ls="--", lw=0.8, label="1.10 × floor")
    ax.legend(fontsize=7)
    fig.suptitle("Seed case, 75 spm: rigid-stage optima with a rod-tension bound, re-simulated with clearance")
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bounds", type=float, nargs="+", default=BOUNDS)
    ap.add_argument("--samples", type=int, default=1000)
    a = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    params = PressParams()
    model = build_model(params)
    problem = SpeedProblem(params, period=0.8, ram_speed=-0.1)
    initial = design_speed(problem).speed
    rigid = Rigid(samples=a.samples)
    t0 = time.perf_counter()
    free = rigid.solve(problem, model, WarmStart(initial))
    rows = [row(problem, model, free, None, time.perf_counter() - t0)]
    for bound in a.bounds:
        t0 = time.perf_counter()
        r = rigid.solve(problem.replace(min_tension=bound), model, WarmStart(free.speed), "min_tension")
        rows.append(row(problem, model, r, bound, time.perf_counter() - t0))
        print({k: (round(v, 3) if isinstance(v, float) else v) for k, v in rows[-1].items()}, flush=True)
    out = {"case": "seed T=0.8 s, -0.1 m/s, 15 harmonics", "samples": a.samples, "impact_ratio": IMPACT_RATIO,
           "rows": rows}
    (OUT / "reversal.json").write_text(json.dumps(out, indent=1, default=float))
    save(figure(rows, rows[0]["rigid_peak_torque"]), OUT / "reversal.png")


if __name__ == "__main__":
    main()
