"""Sensitivity studies of the 75 spm scenario (`press75`), with figures.

Cases (each resumes from its CSV in results/, so an interrupted run continues):

* ``stroke_rate``  optimal peaks against the stroke rate, 40-75 spm (cold starts, the default call; from
                   80 spm on it finds no answer, see docs/measurements.md)
* ``clearance``    optimal peaks against the clearance of both joints, 0.02-0.3 mm
* ``ram_speed``    optimal peaks against the working ram speed, -0.1 .. -0.2 m/s (-0.05 m/s cannot
                   be held over the window at 75 spm: refused before solving; -0.075 m/s, near the
                   crank's limit, ran 24 min without an answer, see docs/measurements.md)
* ``slider_mass``  optimal peaks against the slider mass, 100-250 kg
* ``wear``         the 75 spm optimum (designed at 0.1 mm) evaluated at 0.05-0.4 mm
* ``tornado``      normalised sensitivities of the peak torque at the kinematic design and at the optimum

Writes results/study_<case>.csv and .png (and, for tornado, study_tornado.json).

    python benchmarks/bench_studies.py CASE [CASE ...] [--workers N] [--replot]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.plots import key_values, plot_sweep, plot_tornado, plot_wear, save  # noqa: E402
from pressocp.studies import wear_study  # noqa: E402
from pressocp.workers import process_pool  # noqa: E402
from goals import GOAL_FLOOR_RATIO  # noqa: E402

OUT = Path(__file__).parent / "results"
REFERENCE = Path(__file__).parent.parent / "tests" / "references" / "press75_optimum_speed.json"
GRIDS = {
    "stroke_rate": {"problem.stroke_rate_spm": [40, 50, 60, 65, 70, 75]},
    "ram_speed": {"problem.ram_speed": [-0.1, -0.125, -0.15, -0.2]},
    "slider_mass": {"slider_mass": [100.0, 150.0, 200.0, 250.0]},
}
CLEARANCES = [2e-5, 5e-5, 1e-4, 2e-4, 3e-4]
TORNADO_RTOL = 1e-10  # the tornado's integration tolerance (recorded with its tables)
PARAMETERS = ("slider_mass", "rod_mass", "crank_inertia", "wrist_pin.clearance", "crank_pin.clearance",
              "wrist_pin.stiffness", "crank_pin.stiffness")


def optima(case: str, workers: int) -> None:
    scenario = po.Scenario.load("press75")
    if case == "clearance":
        vary = [{"crank_pin.clearance": c, "wrist_pin.clearance": c} for c in CLEARANCES]
        key = "wrist_pin.clearance"
    else:
        vary = GRIDS[case]
        key = next(iter(vary))
    with process_pool(workers) as ex:  # the pool po.sweep starts by default
        table = po.sweep(scenario, vary, "optimize", executor=ex, progress=True, csv=OUT / f"study_{case}.csv",
                         continuation=False)
    optima_figure(table, case)
    cols = [c for c in (key, "ok", "peak_torque_N_m", "rigid_peak_torque_N_m", "initial_peak_torque_N_m",
                        "peak_crank_pin_force_N", "peak_wrist_pin_force_N", "wall_time_s", "error") if c in table]
    print(table[cols].to_string(index=False))


def case_key(case: str) -> str:
    return "wrist_pin.clearance" if case == "clearance" else next(iter(GRIDS[case]))


def optima_figure(table, case: str) -> None:
    """`plot_sweep` of an optima study, with the project's goal on the torque panel: 1.10 x the rigid
    floor (issue #4, "impacts designed out"). The seed point's 147.5 N·m (issue #14) is not drawn: on
    the log axis it cannot be told from the optimum's 147.8."""
    key = case_key(case)
    fig = plot_sweep(table, [key], title=f"75 spm scenario: optima against {key} (both joints)" if case == "clearance"
                     else f"75 spm scenario: optima against {key}")
    ax = fig.axes[0]
    ok = table[table["ok"].astype(bool)].sort_values(key)
    x = key_values(key, ok[key], table[key])  # in the axis's unit, as plot_sweep draws the points
    ax.plot(x, GOAL_FLOOR_RATIO * ok["rigid_peak_torque_N_m"], "--", color="tab:red", lw=0.8,
            label=f"goal: {GOAL_FLOOR_RATIO:.2f} × floor")
    ax.legend(fontsize=7)
    save(fig, OUT / f"study_{case}.png")


def wear(workers: int) -> None:
    scenario = po.Scenario.load("press75")
    speed = po.FourierSpeed.from_dict(json.loads(REFERENCE.read_text()))
    with process_pool(workers) as ex:  # the pool po.sweep starts by default
        table = wear_study(scenario, speed, executor=ex, progress=True, csv=OUT / "study_wear_points.csv")
    table.to_csv(OUT / "study_wear.csv", index=False)
    save(plot_wear(table, scenario.problem.press.wrist_pin.clearance,
                   title="the 75 spm optimum (designed at 0.1 mm) as the joints wear"), OUT / "study_wear.png")
    print(table[["clearance", "ok", "peak_torque_N_m", "ideal_joints_peak_torque_N_m", "torque_ratio",
                 "min_crank_pin_eccentricity", "min_wrist_pin_eccentricity", "free_flight"]].to_string(index=False))


def tornado_figure(out: dict) -> None:
    """Both tornado panels from the saved tables (`study_tornado.json`)."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for ax, (label, run) in zip(axes, out.items()):
        s = po.Sensitivities(pd.DataFrame(run["table"]), pd.DataFrame(), True, run["wall_time_s"], run["unverified"])
        plot_tornado(s, title=f"peak motor torque, 75 spm, {label}", ax=ax)
    fig.tight_layout()
    save(fig, OUT / "study_tornado.png")


def tornado() -> None:
    scenario = po.Scenario.load("press75")
    model = scenario.build_model()
    speeds = {"kinematic design (impacting)": po.design_speed(scenario.problem).speed,
              "optimum": po.FourierSpeed.from_dict(json.loads(REFERENCE.read_text()))}
    out = {}
    for label, speed in speeds.items():
        t0 = time.perf_counter()
        s = po.sensitivities(model, speed, PARAMETERS, rtol=TORNADO_RTOL)
        out[label] = {"wall_time_s": time.perf_counter() - t0, "rtol": TORNADO_RTOL, "unverified": s.unverified,
                      "table": s.table.to_dict("records")}
        print(label, s.table[["parameter", "value", "derivative", "normalised", "error_estimate", "resolved", "unique"]]
              .to_string(index=False))
    (OUT / "study_tornado.json").write_text(json.dumps(out, indent=2, default=str) + "\n")
    tornado_figure(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cases", nargs="+", choices=("stroke_rate", "clearance", "ram_speed", "slider_mass", "wear",
                                                 "tornado"))
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the figures from the saved results (wear: not redrawn)")
    args = ap.parse_args()
    if args.replot:
        for case in args.cases:
            if case == "wear":
                print(f"{case}: no --replot (its figure is drawn from the computed result)")
            elif case == "tornado":
                tornado_figure(json.loads((OUT / "study_tornado.json").read_text()))
            else:
                optima_figure(pd.read_csv(OUT / f"study_{case}.csv"), case)
        return
    OUT.mkdir(exist_ok=True)
    for case in args.cases:
        if case == "wear":
            wear(args.workers)
        elif case == "tornado":
            tornado()
        else:
            optima(case, args.workers)


if __name__ == "__main__":
    main()
