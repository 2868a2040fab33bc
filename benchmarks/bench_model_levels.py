"""Model levels across scenes (issue #17, item 4): how far the peak loads of each level are from the
richest one, what each costs, and what `recommend_model` says about the scene.

Levels: ``rigid`` (the ideal press, closed form), ``clearance`` (rigid rod, clearance in both pins)
and ``flexible`` (the flexible rod, 4 elements, with the scene's joints): the richest. A slender-rod
scene has ideal joints (its rod's bending is the scene), so it has no clearance level.

Scenes: the default press at 50 / 60 / 75 strokes/min; at 75 spm with 0.02 and 0.3 mm clearances;
Simeon's slender rod (the bundled ``slender_rod`` press) at 50 / 100 / 150 rad/s. Each with two crank
speeds: constant, and the kinematic design of the scene's problem (`design_speed`, the ram at
constant speed in the window, on the ideal press).

Each response on a model with states is the 6th cycle from rest (CVODES rtol 1e-7): an impacting
response has no periodic state, and the search for one on the flexible rod costs minutes (forward
sensitivities of 24 states per Newton step); ``settling`` records the relative change of each peak
from the 5th cycle to the 6th. The error of a level is |peak - peak_richest| / peak_richest for the peak
motor torque, the peak crank-pin force and the peak slider normal force; the cost is the wall time of
that level's six cycles (one run each).

    python benchmarks/bench_model_levels.py [--replot]

Writes results/model_levels.json and model_levels.png.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from pressocp import (FourierSpeed, PressParams, Scenario, SpeedProblem, build_model, design_speed,
                      recommend_model)
from pressocp.verify import cycle_from, rigid_reference, settled_state
from pressocp.plots import save
from pressocp.io import versions
from pressocp.report import stamp

OUT = Path(__file__).parent / "results"
LOADS = ("torque", "crank_pin_force", "slider_normal_force")
RTOL = 1e-7
#: The cycle from rest that stands for the steady state.
CYCLE = 6


def scenes() -> list[dict]:
    """(name, problem, joints with clearance) of every scene."""
    out = []
    for spm in (50, 60, 75):
        out.append({"scene": f"default press, {spm} spm, 0.1 mm", "axis": "stroke rate",
                    "problem": SpeedProblem(PressParams(), period=60.0 / spm), "clearance": ("crank_pin", "wrist_pin")})
    for c in (2e-5, 3e-4):
        p = PressParams()
        p = p.replace(crank_pin=replace(p.crank_pin, clearance=c), wrist_pin=replace(p.wrist_pin, clearance=c))
        out.append({"scene": f"default press, 75 spm, {c * 1e3:g} mm", "axis": "clearance",
                    "problem": SpeedProblem(p, period=0.8), "clearance": ("crank_pin", "wrist_pin")})
    slender = Scenario.load("slender_rod").problem
    for w in (50.0, 100.0, 150.0):
        period = 2 * np.pi / w
        out.append({"scene": f"slender rod, {w:g} rad/s", "axis": "rod slenderness",
                    "problem": slender.replace(period=period, ram_speed=slender.ram_speed * w / 100.0),
                    "clearance": ()})
    return out


def response(model, speed: FourierSpeed, problem: SpeedProblem) -> tuple[dict, float, object]:
    """Peak loads of the `CYCLE`-th cycle of `speed` on `model` (None: the ideal press), the wall time of
    all the cycles, and each peak's relative change from the cycle before."""
    t0 = time.perf_counter()
    if model is None:
        sim = rigid_reference(problem, speed)
        return {k: sim.peak(k) for k in LOADS}, time.perf_counter() - t0, {k: 0.0 for k in LOADS}
    x = settled_state(model, speed, CYCLE - 2, RTOL)
    before = cycle_from(model, speed, RTOL, x, CYCLE - 1, "")
    sim = cycle_from(model, speed, RTOL, before.states[:, -1] / model.x_scale, CYCLE, "")
    peaks = {k: sim.peak(k) for k in LOADS}
    return peaks, time.perf_counter() - t0, {k: abs(before.peak(k) / peaks[k] - 1) for k in LOADS}


def measure() -> dict:
    rows = []
    for sc in scenes():
        problem = sc["problem"]
        press = problem.press
        levels = {"rigid": None}
        if sc["clearance"]:
            levels["clearance"] = build_model(press, "rigid", sc["clearance"])
        levels["flexible"] = build_model(press, "flexible", sc["clearance"], 4)
        speeds = {"constant": FourierSpeed.constant(problem.period), "kinematic design": design_speed(problem).speed}
        for sname, speed in speeds.items():
            rec = recommend_model(press, speed)
            row = {"scene": sc["scene"], "axis": sc["axis"], "speed": sname, "problem": problem.to_dict(),
                   "recommended": rec.level, "reason": rec.reason, "mode_ratio": rec.mode_ratio,
                   "min_rod_tension_N": rec.min_rod_tension, "levels": {}}
            for lname, model in levels.items():
                peaks, wall, settling = response(model, speed, problem)
                row["levels"][lname] = {"peaks": peaks, "wall_time_s": wall, "settling": settling}
            richest = row["levels"]["flexible"]["peaks"]
            for lv in row["levels"].values():
                lv["error"] = {k: abs(lv["peaks"][k] - richest[k]) / richest[k] for k in LOADS}
            # the plainest level whose three peaks are within 5 % of the richest's
            row["needed_5pct"] = next(n for n, lv in row["levels"].items() if max(lv["error"].values()) <= 0.05)
            rows.append(row)
            errs = {n: f"{lv['error']['torque']:.1e}" for n, lv in row["levels"].items()}
            print(f"{sc['scene']:32s} {sname:16s} torque errors {errs}  needed {row['needed_5pct']:9s} "
                  f"recommended {rec.level}", flush=True)
    return {**stamp(), "versions": versions(), "rtol": RTOL, "rows": rows}


def plot(data: dict) -> plt.Figure:
    rows = data["rows"]
    fig, ax = plt.subplots(1, 2, figsize=(13, 6.5))
    labels = [f"{r['scene']}\n{r['speed']}" for r in rows]
    y = np.arange(len(rows))
    marks = {"rigid": ("o", "C0"), "clearance": ("s", "C1")}
    for lname, (m, c) in marks.items():
        pts = [(i, r["levels"][lname]["error"]) for i, r in enumerate(rows) if lname in r["levels"]]
        ax[0].scatter([e["torque"] for _, e in pts], [i for i, _ in pts], marker=m, color=c,
                      label=f"{lname} level: peak torque")
        ax[0].scatter([max(e.values()) for _, e in pts], [i for i, _ in pts], marker=m, facecolor="none",
                      edgecolor=c, s=80, label=f"{lname} level: worst of the three peaks")
        cost = [(i, r["levels"][lname]["wall_time_s"]) for i, r in enumerate(rows) if lname in r["levels"]]
        ax[1].scatter([w for _, w in cost], [i for i, _ in cost], marker=m, color=c, label=f"{lname} level")
    ax[1].scatter([r["levels"]["flexible"]["wall_time_s"] for r in rows], y, marker="^", color="C2",
                  label="flexible level (4 elements)")
    for i, r in enumerate(rows):
        ax[0].annotate(f"needs {r['needed_5pct']}, recommended {r['recommended']}", (0.01, i), fontsize=7,
                       va="bottom", xycoords=("axes fraction", "data"),
                       color="C3" if r["needed_5pct"] != r["recommended"] else "k")
    ax[0].axvline(0.05, color="k", ls="--", lw=1, label="5 % (the level is enough)")
    ax[0].set_xscale("log")
    ax[0].set_xlim(1e-5, 2.0)
    ax[0].set_xlabel("peak-load error against the flexible level (relative): torque, and the worst of torque,\n"
                     "crank-pin force and slider normal force (red label: the recommendation differs)")
    ax[0].set_yticks(y, labels, fontsize=7)
    ax[0].invert_yaxis()
    ax[0].legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    ax[1].set_xscale("log")
    ax[1].set_xlabel(f"wall time of {CYCLE} cycles from rest, s")
    ax[1].set_yticks(y, [""] * len(y))
    ax[1].invert_yaxis()
    ax[1].legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    fig.suptitle(f"Model levels across scenes: error against the richest, and cost ({data['date'][:10]}, "
                 f"{data['cpus']} CPUs)")
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--replot", action="store_true", help="redraw the figure from the JSON")
    a = ap.parse_args()
    path = OUT / "model_levels.json"
    data = json.loads(path.read_text()) if a.replot else measure()
    if not a.replot:
        OUT.mkdir(exist_ok=True)
        path.write_text(json.dumps(data, indent=1, default=float))
    save(plot(data), OUT / "model_levels.png")


if __name__ == "__main__":
    main()
