"""Speed versus accuracy of the simulation methods on the same equations.

Scenario: the default press at the rigid-designed speed of the impact study (T = 0.8 s,
ram speed -0.1 m/s over h/H 0.7 -> 0.3), one cycle from its periodic steady state. For each method
and tolerance: wall time per cycle (median of repeats) and the relative error of the peak motor
torque against a CVODES rtol 1e-10 reference. "Equal accuracy" compares the cheapest run of each
method whose peak-torque error is below a target. No method integrates the work quadratures (nothing
here reads them). Every method runs on the compiled model (``model.jit``: the SUNDIALS integrators and
scipy's call compiled code; the compile, once per method and model, is timed apart as
``compile_s``); "idas (interpreted)" and "cvodes (interpreted)" are the same integrators on CasADi's
virtual machine, "idas (CasADi's clock)" compiled IDAS with CasADi's statistics reading the
process CPU clock in every call of its inner functions, as without `pressocp`
(`pressocp.casadi_clock`), and "cvodes-direct" the same CVODES called from code compiled with the
model, without CasADi's integrator object (`pressocp.cvodes_fsa`; its compile timed like the others').

``--case periodic69`` and ``--case seed`` run one scene each, apart from the default two: the same
design at 69 spm, whose impacts repeat cycle after cycle, and the 75 spm seed optimum, whose cycle
is smooth (its journals stay on their walls). On a smooth cycle scipy's Radau (L-stable, order 5)
takes about 1/25 of the steps of IDAS and CVODES, whose BDF orders 4 and 5 (and 3 near top dead
centre) are unstable on the journals' lightly damped contact modes
(docs/decisions/2026-11-28-bdf-order.md).

Writes benchmarks/results/simulation.json and simulation.png (``simulation_<case>`` for one case).

    python benchmarks/bench_simulation.py [--quick] [--replot] [--case all|clearance|flexible|periodic69|seed]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pressocp import FourierSpeed, PressParams, SpeedProblem, set_casadi_clock  # noqa: E402
from pressocp.design import design_speed  # noqa: E402
from pressocp.model import build_model  # noqa: E402
from pressocp.report import stamp  # noqa: E402
from pressocp.simulate import Integrator, SimulationError, periodic_state, simulate  # noqa: E402
from status import figure_note  # noqa: E402 (a sibling script: this folder is the script's path)

OUT = Path(__file__).parent / "results"
#: The 75 spm seed optimum (the tests' reference speed): a smooth periodic cycle.
SEED_OPTIMUM = Path(__file__).parent.parent / "tests" / "references" / "press75_optimum_speed.json"


def flexible_start(model, speed):
    """Flexible-rod start: the rigid-rod clearance model's periodic eccentricities, no elastic
    deformation, then one warm-up cycle (the flexible periodic shooting through impacts took
    > 11 CPU-minutes without converging at rtol 1e-7, so it is not used here)."""
    rigid = build_model(model.params)
    xc, _ = periodic_state(rigid, speed, integrator=Integrator(method="cvodes", rtol=1e-9))
    nw = model.nx // 2 - 4
    x = np.concatenate([xc[:4], np.zeros(nw), xc[4:], np.zeros(nw)])
    return simulate(model, speed, x0=x, integrator=Integrator(method="cvodes", rtol=1e-7), n_out=3).states[:, -1] / model.x_scale


#: Peak-torque errors at which the methods are compared (equal accuracy).
TARGETS = (1e-2, 1e-3)
#: A run this many times slower than a method's quickest row within every target is not repeated.
SLOWER = 1.5
#: Runs of each of IDAS and scipy's Radau, in turn, at their equal-accuracy rows (`in_turn`).
IN_TURN = 5


INTERPRETED = " (interpreted)"
#: A method named with this suffix runs with CasADi's statistics reading the process CPU clock, as
#: CasADi does without `pressocp` (`pressocp.casadi_clock`): a system call in every call of the
#: integrator's inner functions.
CLOCKED = " (CasADi's clock)"


def run_case(name, model, speed, methods, rtols, repeats, budget, rtol_ref=1e-10, floors=None):
    """Every method at every rtol, against a CVODES reference at `rtol_ref` (on `model` as it is).
    ``floors``: method -> the tightest rtol it runs (a tighter one is left out, and recorded as such);
    a method stops at the first rtol whose run takes more than `budget` s. A run that takes more than
    `SLOWER` times the median of the method's quickest row within every accuracy target (`TARGETS`)
    is not repeated: no equal-accuracy comparison can pick that row (its ``repeats`` says 1; scipy's
    Radau at rtol 1e-7 to 1e-9 took 3 x 81 s of the job's 9 min). A method's cost is not monotone in
    rtol through the impacts (IDAS at 1e-7 was quicker than at 1e-6), so every row that could be
    picked is repeated. A method named with `INTERPRETED` runs on an interpreted copy of `model`
    (``jit=False``: "auto" would compile a flexible rod), every other on a compiled copy (``jit``)
    after a timed warm-up run that compiles it."""
    t0 = time.perf_counter()
    if model.rod == "flexible":
        x0, info = flexible_start(model, speed), "rigid-rod periodic state + 1 warm-up cycle"
    else:
        x0, info = periodic_state(model, speed, integrator=Integrator(method="cvodes", rtol=1e-9))
    print(f"{name}: start state {info} in {time.perf_counter() - t0:.1f} s", flush=True)
    ref = simulate(model, speed, x0=x0, integrator=Integrator(method="cvodes", rtol=rtol_ref), n_out=16001, work=False)
    compiled = dataclasses.replace(model, jit=True, functions={})
    interpreted = dataclasses.replace(model, jit=False, functions={})  # "auto" compiles a flexible rod
    rows, compile_s = [], {}
    for label in methods:
        method = label.removesuffix(INTERPRETED).removesuffix(CLOCKED)
        sim_model = interpreted if label.endswith(INTERPRETED) else compiled
        set_casadi_clock(label.endswith(CLOCKED))
        if sim_model is compiled:
            t0 = time.perf_counter()
            simulate(compiled, speed, x0=x0, integrator=Integrator(method=method, rtol=1e-4), t_end=1e-3, n_out=3, work=False)
            compile_s[label] = time.perf_counter() - t0
            print(f"{label}: compiled in {compile_s[label]:.1f} s", flush=True)
        quickest = np.inf  # median time of the method's quickest row within every target so far
        for rtol in rtols:
            if rtol < (floors or {}).get(label, 0.0):
                rows.append({"case": name, "method": label, "rtol": rtol, "ok": False, "time_per_cycle_s": None,
                             "repeats": 0, "peak_torque_rel_error": None, "steps": None,
                             "error": f"not run: below this case's floor for {label} ({floors[label]:g})"})
                continue
            times, err, ok = [], None, True
            for _ in range(repeats):
                t0 = time.perf_counter()
                try:
                    r = simulate(sim_model, speed, x0=x0, integrator=Integrator(method=method, rtol=rtol), n_out=16001, work=False)
                except SimulationError as e:
                    ok, err = False, str(e).splitlines()[0]
                    break
                times.append(time.perf_counter() - t0)
                err = abs(r.peak("torque") / ref.peak("torque") - 1)
                if times[-1] > budget or times[-1] > SLOWER * quickest:
                    break
            row = {"case": name, "method": label, "rtol": rtol, "ok": ok,
                   "time_per_cycle_s": statistics.median(times) if times else None, "repeats": len(times),
                   "peak_torque_rel_error": err if ok else None, "error": None if ok else err,
                   "steps": r.stats.get("steps") if ok else None}
            rows.append(row)
            print(json.dumps(row), flush=True)
            if ok and err <= min(TARGETS):
                quickest = min(quickest, row["time_per_cycle_s"])
            if ok and times and times[-1] > budget:
                break  # tighter tolerances only get slower
    set_casadi_clock(False)
    turns = in_turn(rows, lambda method, rtol: simulate(compiled, speed, x0=x0, n_out=16001, work=False,
                                                        integrator=Integrator(method=method, rtol=rtol)))
    return {"reference_peak_torque": ref.peak("torque"), "rows": rows, "compile_s": compile_s, "in_turn": turns}


def in_turn(rows, run, pair=("idas", "scipy-radau")) -> dict:
    """For each accuracy target, the cheapest row of each method of `pair` within it (`equal_accuracy`)
    run again `IN_TURN` times each, one after the other in turn (`run(method, rtol)`), so that the
    machine's drift over the minutes between the rows' blocks is shared: the medians and their ratio
    (second over first), per target."""
    out = {}
    for target in TARGETS:
        best = equal_accuracy(rows, target)
        if not all(m in best for m in pair):
            continue
        times = {m: [] for m in pair}
        for _ in range(IN_TURN):
            for m in pair:
                t0 = time.perf_counter()
                run(m, best[m]["rtol"])
                times[m].append(time.perf_counter() - t0)
        medians = {m: statistics.median(v) for m, v in times.items()}
        out[f"{target:g}"] = {"rtol": {m: best[m]["rtol"] for m in pair}, "times_s": times, "median_s": medians,
                              "ratio": medians[pair[1]] / medians[pair[0]]}
        print(f"in turn at {target:g}: {medians}", flush=True)
    return out


def equal_accuracy(rows, target):
    best = {}
    for r in rows:
        if r["ok"] and r["peak_torque_rel_error"] <= target:
            m = r["method"]
            if m not in best or r["time_per_cycle_s"] < best[m]["time_per_cycle_s"]:
                best[m] = r
    return best


#: The cycle, s, of the design's periodic impacting orbit: at 0.8 s its per-cycle peaks alternate (rigid
#: rod, 5.9e-4 apart) or wander (flexible rods, 5 %); at 0.87 s they repeat to 1e-7.
PERIODIC_69 = 0.87
GOAL_SPEEDUP = 20.0  # issue #3: IDAS >= 20x faster than scipy-radau at equal peak-torque accuracy
GOAL_FLEXIBLE_S = 1.0  # issue #3: the flexible model (4 elements) under 1 s per cycle


def plot_results(results: dict, methods, path: Path, run: dict | None = None) -> None:
    """Peak-torque error against wall time per cycle, one panel per case (log-log), with the goals:
    scipy-radau's curve at 1/20 of its time (IDAS must lie left of it) and, for the flexible model,
    1 s per cycle; `run` (`stamp`) dates the figure ("not recorded" without it)."""
    fig, axes = plt.subplots(1, len(results), figsize=(5.5 * len(results), 4.2), squeeze=False)
    for ax, (case, res) in zip(axes[0], results.items()):
        for m in methods:
            pts = [(r["time_per_cycle_s"], r["peak_torque_rel_error"], r["rtol"]) for r in res["rows"]
                   if r["method"] == m and r["ok"]]
            if pts:
                x, y, tol = zip(*pts)
                ax.loglog(x, np.maximum(y, 1e-12), "o-", label=m)
                for xi, yi, ti in zip(x, y, tol):
                    ax.annotate(f"{ti:.0e}", (xi, max(yi, 1e-12)), xytext=(3, 2), textcoords="offset points",
                                fontsize=6, alpha=0.7)
                if m == "scipy-radau":
                    ax.loglog(np.asarray(x) / GOAL_SPEEDUP, np.maximum(y, 1e-12), "--", color="tab:red", lw=0.8,
                              label=f"goal for idas: scipy-radau's time / {GOAL_SPEEDUP:g}")
        if case.startswith("flexible"):
            ax.axvline(GOAL_FLEXIBLE_S, color="0.4", ls="--", lw=0.8)
            ax.text(GOAL_FLEXIBLE_S, 0.02, f" goal: {GOAL_FLEXIBLE_S:g} s per cycle", transform=ax.get_xaxis_transform(),
                    color="0.3", fontsize=7, rotation=90, va="bottom", ha="right")
        ax.set_xlabel("wall time per cycle [s] (labels: rtol)")
        ax.set_ylabel("relative error of peak torque")
        model = {"flexible": "flexible model (4 elements)", "periodic69": "clearance model",
                 "seed": "clearance model"}.get(case, f"{case} model")
        scene = "the 75 spm seed optimum (smooth)" if case == "seed" else f"impact scenario (T = {res.get('period', 0.8):g} s)"
        ax.set_title(f"{model}, {scene}", fontsize=9)
        ax.grid(alpha=0.3, which="both")
    one = len(results) == 1  # a narrow figure: the legend in two columns, three rows
    note = 0.035  # the strip under the legend that the measurement's note takes
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="lower center", bbox_to_anchor=(0.5, note),
               ncol=2 if one else 4, fontsize=8)
    fig.tight_layout(rect=(0, (0.17 if one else 0.07) + note, 1, 1))
    figure_note(fig, run)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer tolerances and repeats")
    ap.add_argument("--case", choices=("all", "clearance", "flexible", "periodic69", "seed"), default="all",
                    help="periodic69 (not in all): the clearance model on the same design at 69 spm (T = 0.87 s), "
                         "whose impacts repeat cycle after cycle (docs/decisions/2026-11-27-periodic-yardstick.md); "
                         "seed (not in all): the clearance model on the 75 spm seed optimum's periodic cycle, "
                         "smooth (the journals stay on their walls), scipy's Radau from rtol 1e-3")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the case's PNG from its JSON (simulation.png from simulation.json for all)")
    args = ap.parse_args()
    name = "simulation" if args.case == "all" else f"simulation_{args.case}"
    if args.replot:
        data = json.loads((OUT / f"{name}.json").read_text())
        plot_results(data["results"], ("idas", "cvodes", "cvodes-direct", "scipy-radau", "idas" + INTERPRETED,
                                       "cvodes" + INTERPRETED, "idas" + CLOCKED), OUT / f"{name}.png", data.get("stamp"))
        return
    OUT.mkdir(exist_ok=True)
    p = PressParams()
    speed = design_speed(SpeedProblem(p, period=0.8, ram_speed=-0.1)).speed
    repeats = 1 if args.quick else 3
    rtols = [1e-5, 1e-7] if args.quick else [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
    methods = ["idas", "cvodes", "cvodes-direct", "scipy-radau", "idas" + INTERPRETED, "cvodes" + INTERPRETED]
    results = {}
    if args.case in ("all", "clearance"):
        results["clearance"] = run_case("clearance", build_model(p), speed, [*methods, "idas" + CLOCKED], rtols,
                                        repeats, budget=120)
    if args.case == "periodic69":
        slow = design_speed(SpeedProblem(p, period=PERIODIC_69, ram_speed=-0.1)).speed
        results["periodic69"] = run_case("clearance, 69 spm", build_model(p), slow, methods[:4], rtols, repeats,
                                         budget=120)
        results["periodic69"]["period"] = PERIODIC_69
    if args.case == "seed":
        seed = FourierSpeed.from_dict(json.loads(SEED_OPTIMUM.read_text()))
        results["seed"] = run_case("clearance, seed optimum", build_model(p), seed, methods[:4], [1e-3, *rtols], repeats,
                                   budget=120)
    if args.case in ("all", "flexible"):
        # the flexible model is ~20x dearer: looser reference, tolerances down to 1e-7, one repeat;
        # scipy's Radau down to 1e-6 (at 1e-7 one cycle took 703 s, 2026-11-24)
        results["flexible"] = run_case("flexible (4 elements)", build_model(p, rod="flexible", n_elements=4), speed,
                                       methods, [r for r in rtols if r >= 1e-7], 1, budget=300, rtol_ref=1e-9,
                                       floors={"scipy-radau": 1e-6})
    summary = {}
    for case, res in results.items():
        for target in TARGETS:
            best = equal_accuracy(res["rows"], target)
            entry = {m: {"rtol": r["rtol"], "time_per_cycle_s": r["time_per_cycle_s"]} for m, r in best.items()}
            if "idas" in best and "scipy-radau" in best:
                entry["radau_over_idas"] = best["scipy-radau"]["time_per_cycle_s"] / best["idas"]["time_per_cycle_s"]
            if "idas" + INTERPRETED in best and "scipy-radau" in best:
                entry["radau_over_idas_interpreted"] = (best["scipy-radau"]["time_per_cycle_s"]
                                                        / best["idas" + INTERPRETED]["time_per_cycle_s"])
            if "idas" + CLOCKED in best and "scipy-radau" in best:
                entry["radau_over_idas_casadi_clock"] = (best["scipy-radau"]["time_per_cycle_s"]
                                                         / best["idas" + CLOCKED]["time_per_cycle_s"])
            turn = res.get("in_turn", {}).get(f"{target:g}")
            if turn is not None:
                entry["radau_over_idas_in_turn"] = turn["ratio"]
            summary[f"{case}@{target:g}"] = entry
    run = stamp()
    (OUT / f"{name}.json").write_text(json.dumps({"stamp": run, "results": results, "equal_accuracy": summary}, indent=2))
    plot_results(results, [*methods, "idas" + CLOCKED], OUT / f"{name}.png", run)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
