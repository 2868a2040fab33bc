"""Transcriptions compared on the same problems, from the same start.

Each transcription solves the stage on a model with states of one problem (`Transcription.solve`: the
clearance-model stage, or the flexible-rod stage), warm-started from the same speed; its answer is
re-simulated (periodic CVODES, rtol 1e-9). Recorded per run: IPOPT's status, iterations, wall time (IPOPT's,
and the whole call's with the start's periodic response and the model functions' compilation), its
objective and dual infeasibility per iteration (with the time of each iteration), and the verified
objective with the ram-speed violation. The JSON is written after every run, so an interrupted run keeps
the finished ones.

Cases (``--case``; each writes benchmarks/results/transcriptions_<case>.json and .png):

* ``smooth``  T = 1 s, -0.15 m/s, 4 harmonics, default press with both clearances; start: the rigid
              press's optimum, which does not impact. Multiple shooting through IDAS and CVODES (16
              intervals x 25 samples, journals kept on their walls at every sample) and collocation
              at 100, 200 and 400 elements.
* ``seed``    the 75 spm scenario (15 harmonics, -0.1 m/s over h/H 0.7 -> 0.3); start: the
              no-reversal optimum (rod tension >= 5 % of the hanging weight on the rigid press), the
              start the default call gives its clearance stage. IDAS multiple shooting as above,
              capped at ``--shooting-wall`` s of IPOPT wall time, and collocation at 400, 800 and 1600
              elements (1600 is the default call's grid).
* ``flexible`` the bundled ``slender_rod`` scenario (Simeon's slender rod at a mean 100 rad/s, ideal
              joints, the rod in 4 elements), the default call's ``flexible`` stage; start: the rigid
              press's optimum (80.9 N·m there, 112.4 N·m re-simulated on the flexible rod), as in the
              default call. IDAS and CVODES multiple shooting (16 x 25), each capped at
              ``--shooting-wall`` s, and collocation at 63, 126 (the default call's grid: 0.5 ms
              elements) and 252 elements. Every run gets its own model, so that each collocation run
              compiles its model functions as the default call does (about 5.5 min on 2 cores).

* ``map``     which transcription converges over (stroke rate x clearance of both pins): the 75 spm
              scenario at 60 and 75 spm with 0.05 and 0.2 mm clearances, each from its own
              no-reversal optimum; collocation on the default call's grid, IDAS and CVODES multiple
              shooting capped at ``--shooting-wall`` s (``--methods`` runs some of them; the JSON
              keeps the others' rows). Writes transcriptions_map.json and .png.

* ``flexible_shooting`` the same scene: the refinement `recommend_transcription` gives it (IDAS
              multiple shooting, compiled, 16 intervals x 100 samples) started from collocation's answer,
              against that answer re-simulated (issue #29: within 0.5 %).

    python benchmarks/bench_transcriptions.py --case smooth|seed|flexible|flexible_shooting|map [--shooting-wall S]
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from types import SimpleNamespace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.objectives import get as get_objective  # noqa: E402
from pressocp.io import versions  # noqa: E402
from pressocp.ocp.stage import WarmStart  # noqa: E402
from pressocp.verify import is_periodic, ram_speed_violation, verify_speed  # noqa: E402
from pressocp.plots import save  # noqa: E402
from pressocp.report import stamp  # noqa: E402
from goals import GOAL_WALL_S  # noqa: E402
from status import figure_note, job_run  # noqa: E402 (a sibling script: this folder is the script's path)

OUT = Path(__file__).parent / "results"
VERIFY_RTOL = 1e-9
GOAL_REL = 0.005  # issue #17: IDAS multiple shooting's verified optimum within 0.5 % of collocation's
#: Goals below this fraction of the start's objective are not drawn (they would flatten the axis).
GOAL_SHOWN = 0.8
LEGEND_LINE_IN = 0.135  # height of a legend line at 6.5 pt, inch
NOTE_IN = 0.15  # the strip under the legend that the measurement's note (`figure_note`) takes, inch
#: The slender-rod default call's answer re-simulated on the 4-element rod (periodic, rtol 1e-9), N m:
#: its flexible stage then polish_1, both collocation on 126 elements (results/ocp.jsonl, case "slender").
SLENDER_DEFAULT_ANSWER = 71.49


@dataclass
class Case:
    """One problem the transcriptions are compared on.

    Attributes
    ----------
    problem : po.SpeedProblem
    start : StageResult
        The common start (its speed warm-starts every run; its objective is on the rigid press, N m).
    runs : list of (str, Transcription)
        Label and transcription of each run, in order.
    goals : dict
        Horizontal lines of the figure: label -> objective, N m.
    model : callable
        The model of a run (called once per run; the same object for every run unless the case says so).
    stage : str
        Stage name the default chain gives this stage (records, progress).
    extra : dict
        Further fields of the JSON.
    """

    problem: po.SpeedProblem
    start: object
    runs: list
    goals: dict
    model: Callable[[], po.PressModel]
    stage: str = "target"
    extra: dict = field(default_factory=dict)


def smooth_case(wall: float) -> Case:
    problem = po.SpeedProblem(po.PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)
    rigid = po.Rigid(samples=300)
    start = rigid.solve(problem, po.build_model(problem.press, clearance=(), n_harmonics=4),
                        WarmStart(po.design_speed(problem).speed), "rigid")
    cap = {"ipopt.max_wall_time": wall}
    runs = [("IDAS shooting 16x25", po.MultipleShooting("idas", min_eccentricity=1.0, ipopt=cap)),
            ("CVODES shooting 16x25", po.MultipleShooting("cvodes", min_eccentricity=1.0, ipopt=cap))]
    runs += [(f"collocation {n}x3", po.Collocation(elements=n, jit=False)) for n in (100, 200, 400)]
    model = po.build_model(problem.press, n_harmonics=problem.n_harmonics)
    return Case(problem, start, runs, {}, lambda: model)


def seed_case(wall: float) -> Case:
    problem = po.Scenario.load("press75").problem
    # on the target model, as the default chain does: the window is widened by its ram drop
    r, start = no_reversal_start(problem)
    runs = [("IDAS shooting 16x25", po.MultipleShooting("idas", min_eccentricity=1.0,
                                                         ipopt={"ipopt.max_wall_time": wall}))]
    runs += [(f"collocation {n}x3", po.Collocation(elements=n)) for n in (400, 800, 1600)]
    goals = {"issue goal 147.5 N·m": 147.5, f"rigid floor {r.objective:.1f} N·m": r.objective}
    model = po.build_model(problem.press, n_harmonics=problem.n_harmonics)
    return Case(problem, start, runs, goals, lambda: model)


def flexible_case(wall: float) -> Case:
    """The slender-rod scene's flexible stage, from the rigid press's optimum, as the default call runs it
    (`Strategy.flexible_only`): the scenario's model, the rigid stage on it (its window widened by the
    model's ram drop, none here), the default chain's stage name. Each run builds its own model."""
    sc = po.Scenario.load("slender_rod")
    problem = sc.problem
    model = sc.build_model()
    start = po.Rigid().solve(problem, model, WarmStart(po.design_speed(problem).speed), "rigid")
    on_rod = float(get_objective(problem.objective).value(verify_speed(model, start.speed, VERIFY_RTOL)))
    print(f"rigid-press optimum re-simulated on the flexible rod: {on_rod:.5g}", flush=True)
    cap = {"ipopt.max_wall_time": wall}
    default = po.Collocation().grid(problem.period).elements  # 126: 0.5 ms elements
    runs = [(f"collocation {n}x3", po.Collocation(elements=n)) for n in (default // 2, default)]
    runs += [("IDAS shooting 16x25", po.MultipleShooting("idas", ipopt=cap)),
             ("CVODES shooting 16x25", po.MultipleShooting("cvodes", ipopt=cap)),
             (f"collocation {2 * default}x3", po.Collocation(elements=2 * default))]
    goals = {f"rigid-press optimum on the flexible rod {on_rod:.1f} N·m": on_rod,
             f"default call's answer {SLENDER_DEFAULT_ANSWER:.2f} N·m (flexible stage + polish)":
                 SLENDER_DEFAULT_ANSWER}
    return Case(problem, start, runs, goals, sc.build_model, "flexible",
                {"scenario": "slender_rod", "model": model.spec.describe(), "start_on_model_objective": on_rod})


def flexible_shooting_case(wall: float) -> Case:
    """The slender-rod scene (issue #29): IDAS multiple shooting started from collocation's optimum (the
    default call's answer: its flexible stage and polish, collocation on the default grid), its node
    states from that answer's periodic response, against that optimum re-simulated (goal: within
    `GOAL_REL`). The flexible stage alone (from the rigid press's optimum) stops higher, at 75.2 N·m
    (2026-11-26): shooting from there found 70.9, so a comparison with it measured the stage's local
    optimum, not the transcription."""
    sc = po.Scenario.load("slender_rod")
    problem = sc.problem
    model = sc.build_model()
    t0 = time.perf_counter()
    answer = sc.optimize(progress=False)
    start = SimpleNamespace(name="default call", speed=answer.speed, objective=answer.objective_value)
    colloc = float(get_objective(problem.objective).value(verify_speed(model, answer.speed, VERIFY_RTOL)))
    print(f"default call ({answer.status}, {time.perf_counter() - t0:.0f} s): {answer.objective_value:.5g}, "
          f"verified {colloc:.5g}", flush=True)
    cap = {"ipopt.max_wall_time": wall}
    refine = po.recommend_transcription(model).refinement  # IDAS shooting, sampled finely (its docstring)
    refine = replace(refine, ipopt={**refine.ipopt, **cap})
    runs = [(f"IDAS shooting {refine.intervals}x{refine.samples}, compiled", refine)]
    goals = {f"collocation's verified optimum {colloc:.2f} N·m": colloc,
             f"within {GOAL_REL:.1%} of it": colloc * (1 + GOAL_REL)}
    return Case(problem, start, runs, goals, lambda: model, "flexible",
                {"scenario": "slender_rod", "model": model.spec.describe(), "collocation_verified": colloc,
                 "collocation_status": answer.status, "collocation_stages": [st.name for st in answer.stages],
                 "start_label": "the default call's answer (collocation), on the flexible rod"})


MAP_RATES_SPM = (60, 75)
MAP_CLEARANCES_M = (5e-5, 2e-4)


def no_reversal_start(problem):
    """The start the default call gives its clearance stage: the rigid optimum on the target model's
    window, then the no-reversal optimum (rod tension >= 5 % of the hanging weight)."""
    target = po.build_model(problem.press, n_harmonics=problem.n_harmonics)
    r = po.Rigid().solve(problem, target, WarmStart(po.design_speed(problem).speed), "rigid")
    margin = po.Strategy().margins[0] * problem.hanging_weight
    return r, po.Rigid().solve(problem.replace(min_tension=margin), target, WarmStart(r.speed), "no_reversal")


def outcome(row: dict) -> str:
    """converged (IPOPT succeeded, re-simulation periodic with the ram speed in tolerance), converged
    but not verified, not converged, or error."""
    if "error" in row:
        return "error"
    if not row["success"]:
        return "not converged"
    ok = row["periodic"] is True and row["ram_speed_violation_m_s"] <= 0.0
    return "converged" if ok else "converged, not verified"


#: The map's transcriptions, by the name ``--methods`` takes.
MAP_METHODS = {"collocation": "collocation (default grid)", "idas": "IDAS shooting 16x25",
               "cvodes": "CVODES shooting 16x25"}


def map_transcription(method: str, wall: float):
    """The map's transcription `method` (a key of `MAP_METHODS`), shooting capped at `wall` s."""
    if method == "collocation":
        return po.Collocation()
    return po.MultipleShooting(method, min_eccentricity=1.0, ipopt={"ipopt.max_wall_time": wall})


def map_case(wall: float, methods: list[str]) -> None:
    """Run `methods` at every map point; rows of other methods already in the JSON are kept."""
    path = OUT / "transcriptions_map.json"
    labels = [MAP_METHODS[m] for m in methods]
    old = json.loads(path.read_text()) if path.exists() else {"runs": []}
    # a kept row keeps its own date and cap (rows written before rows carried them: the file's)
    kept = [{"date": old.get("date"), "shooting_wall_s": old.get("shooting_wall_s") if "shooting" in r["method"]
             else None, **r} for r in old["runs"] if r["method"] not in labels]
    rows = []
    base = po.Scenario.load("press75")
    for spm in MAP_RATES_SPM:
        for c in MAP_CLEARANCES_M:
            sc = base.with_overrides({"problem.stroke_rate_spm": spm, "crank_pin.clearance": c,
                                      "wrist_pin.clearance": c})
            problem = sc.problem
            rigid, start = no_reversal_start(problem)
            model = po.build_model(problem.press, n_harmonics=problem.n_harmonics)
            for method, label in zip(methods, labels):
                tr = map_transcription(method, wall)
                row = run_one(f"{spm} spm, {c * 1e3:g} mm: {label}", tr, problem, model, start)
                run = stamp()
                row.update(stroke_rate_spm=spm, clearance_m=c, method=label, start_objective=start.objective,
                           rigid_floor=rigid.objective, date=run["date"], run=run,
                           shooting_wall_s=None if method == "collocation" else wall)
                row["outcome"] = outcome(row)
                rows.append(row)
                path.write_text(json.dumps(
                    {**stamp(), "versions": versions(), "case": "map", "shooting_wall_s": wall,
                     "verify_rtol": VERIFY_RTOL, "runs": kept + rows}, indent=1, default=str) + "\n")
    map_figure(json.loads(path.read_text()))


def map_provenance(d: dict, method: str) -> str:
    """When `method`'s cells of the map were run, and its cap ("IDAS 2026-11-24, cap 600 s"): rows
    written before rows carried their own date and cap have the file's."""
    rows = [r for r in d["runs"] if r["method"] == method]
    dates = sorted({str(r.get("date") or d["date"])[:10] for r in rows})
    caps = {r.get("shooting_wall_s", d.get("shooting_wall_s")) for r in rows if "shooting" in method} - {None}
    return f"{method.split(' ')[0]} {', '.join(dates)}" + (f", cap {caps.pop():.0f} s" if len(caps) == 1 else "")


def map_runs(d: dict) -> list[dict]:
    """The stamp of each row of the map: its own (``run``); for a row of before rows carried one, its date
    (or the file's) with the machine of the runner's job run under way then (runs.json), when there was one."""
    out = []
    for r in d["runs"]:
        date = str(r.get("date") or d["date"])
        out.append(r.get("run") or {**job_run("transcriptions_map.json", date), "date": date})
    return out


def map_figure(d: dict) -> None:
    rows = d["runs"]
    methods = [m for m in MAP_METHODS.values() if any(r["method"] == m for r in rows)]
    colours = {"converged": "C2", "converged, not verified": "C1", "not converged": "C3", "error": "k"}
    fig, ax = plt.subplots(figsize=(8, 5))
    for r in rows:
        i = methods.index(r["method"])
        x = MAP_CLEARANCES_M.index(r["clearance_m"]) + (i - (len(methods) - 1) / 2) * 0.3
        y = MAP_RATES_SPM.index(r["stroke_rate_spm"])
        ax.scatter(x, y, s=1700, marker="s", color=colours[r["outcome"]])  # wide enough for "147.3 N·m"
        text = (r["outcome"] if "verified_objective" not in r
                else f"{r['verified_objective']:.1f} N·m\n{r['wall_time_s']:.0f} s")
        name = r["method"].split(" ")[0].replace("collocation", "colloc.")
        text = text.replace("not converged", "not\nconverged")
        ax.annotate(f"{name}\n{text}", (x, y), ha="center", va="center", fontsize=6.5, color="w")
    for name, c in colours.items():
        ax.scatter([], [], marker="s", color=c, label=name)
    ax.set_xticks(range(len(MAP_CLEARANCES_M)), [f"{c * 1e3:g} mm" for c in MAP_CLEARANCES_M])
    ax.set_yticks(range(len(MAP_RATES_SPM)), [f"{s} spm" for s in MAP_RATES_SPM])
    ax.set_xlim(-0.7, len(MAP_CLEARANCES_M) - 0.3)
    ax.set_ylim(-0.6, len(MAP_RATES_SPM) - 0.4)
    ax.set_xlabel("radial clearance of both pins")
    ax.set_ylabel("stroke rate")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=4)
    ax.set_title("Which transcription converges (from the no-reversal optimum)\n"
                 + "; ".join(map_provenance(d, m) for m in methods), fontsize=8)
    fig.tight_layout()
    figure_note(fig, *map_runs(d))
    save(fig, OUT / "transcriptions_map.png")


def run_one(label: str, tr, problem, model, start, stage: str = "target") -> dict:
    """One transcription's `stage` on `model` from `start`'s speed, its answer re-simulated.

    ``wall_time_s`` is IPOPT's (from building the solver, compiled derivatives included, to its answer), s;
    ``call_time_s`` the whole `Transcription.solve` call's (the start's periodic response and the compiled
    model function too), s. A run that did not converge answers with its least-infeasible iterate;
    its last iterate is re-simulated too (``last_iterate``). ``speed``: the answer (`FourierSpeed.to_dict`)."""
    print(f"{label} ...", flush=True)
    t0 = time.perf_counter()
    try:
        st = tr.solve(problem, model, WarmStart(start.speed), stage, progress=False)
    except Exception as err:  # a transcription that cannot even start is a measured failure
        return {"label": label, "transcription": repr(tr), "error": f"{type(err).__name__}: {err}",
                "wall_time_s": time.perf_counter() - t0}
    call = time.perf_counter() - t0
    sim = verify_speed(model, st.speed, VERIFY_RTOL)
    objective = get_objective(problem.objective).value(sim)
    row = {"label": label, "transcription": repr(tr), "success": st.success, "status": st.status,
           "iterations": st.iterations, "wall_time_s": st.wall_time, "call_time_s": call, "objective": st.objective,
           "verified_objective": float(objective), "periodic": is_periodic(sim),
           "ram_speed_violation_m_s": float(max(ram_speed_violation(sim, problem), 0.0)),
           "history": st.history, "iteration_log": st.iteration_log, "speed": st.speed.to_dict()}
    print(f"  {st.status}, {st.iterations} it, {st.wall_time:.0f} s ({call:.0f} s in all), J {st.objective:.5g}, "
          f"verified {objective:.5g}, ram-speed violation {row['ram_speed_violation_m_s']:.2g}", flush=True)
    if not st.success:
        last = verify_speed(model, st.last_speed, VERIFY_RTOL)
        row["last_iterate"] = {
            "objective": st.history[-1] if st.history else None,
            "inf_pr": (st.iteration_log.get("inf_pr") or [None])[-1],
            "verified_objective": float(get_objective(problem.objective).value(last)), "periodic": is_periodic(last),
            "ram_speed_violation_m_s": float(max(ram_speed_violation(last, problem), 0.0)),
            "speed": st.last_speed.to_dict()}
        print(f"  last iterate: J {row['last_iterate']['objective']}, verified "
              f"{row['last_iterate']['verified_objective']:.5g}, ram-speed violation "
              f"{row['last_iterate']['ram_speed_violation_m_s']:.2g}", flush=True)
    return row


def figure(case: str, rows: list[dict], goals: dict, start_value: float, start_label: str = "rigid press",
           run: dict | None = None) -> None:
    """Objective, primal and dual infeasibility of each run's iterates against wall time (log);
    the verified answer as a marker (o converged, x not: the least-infeasible iterate; + the last iterate of
    a run that did not converge, when recorded). Goals at or above `GOAL_SHOWN` x the start's objective are
    drawn; the legend goes below the axes; `run`, the measurement's `pressocp.report.stamp`, dates it."""
    fig, axes = plt.subplots(3, 1, figsize=(7, 8.5), sharex=True)
    done = [r for r in rows if "error" not in r]
    for i, r in enumerate(done):
        c, log = f"C{i}", r["iteration_log"]
        t = np.maximum(np.asarray(log.get("time_s", [])), 0.1)
        n = min(len(t), len(r["history"]))
        held = r["ram_speed_violation_m_s"] <= 0.0
        last = r.get("last_iterate")
        axes[0].plot(t[:n], r["history"][:n], "-", color=c, lw=1,
                     label=f"{r['label']}: {r['status']}, {r['iterations']} it, re-simulated "
                           f"{r['verified_objective']:.2f}{'' if held else ', ram speed out of tolerance'}"
                           + ("" if last is None else f"; last iterate {last['verified_objective']:.2f}"
                              + ("" if last["ram_speed_violation_m_s"] <= 0.0 else " (ram speed out)")))
        if last is not None:  # + : the last iterate re-simulated
            axes[0].plot([r["wall_time_s"]], [last["verified_objective"]], "+", color=c, ms=9)
        axes[0].plot([r["wall_time_s"]], [r["verified_objective"]], ("o" if held else "s") if r["success"] else "x",
                     color=c, ms=7, mfc=None if held else "none")
        for ax, key in ((axes[1], "inf_pr"), (axes[2], "inf_du")):
            v = np.asarray(log.get(key, []))
            m = min(len(t), len(v))
            ax.plot(t[:m], np.maximum(v[:m], 1e-16), "-", color=c, lw=1)
    for k, (name, v) in enumerate((n, v) for n, v in goals.items() if v > GOAL_SHOWN * start_value):
        axes[0].axhline(v, color="0.4", ls=(0, (4, 2 + 2 * k)), lw=0.8, label=name)
    axes[0].axhline(start_value, color="0.7", lw=0.8, ls=":", label=f"start {start_value:.2f} ({start_label})")
    # issue #17: multiple shooting's verified optimum within 0.5 % of collocation's (the finest converged grid)
    colloc = [r for r in done if r["label"].startswith("collocation") and r.get("success")]
    if colloc:
        ref = colloc[-1]
        axes[0].axhspan(ref["verified_objective"] * (1 - GOAL_REL), ref["verified_objective"] * (1 + GOAL_REL),
                        color="tab:red", alpha=0.12, lw=0,
                        label=f"goal for shooting: within ±{GOAL_REL:.1%} of {ref['label']}")
    if case in ("smooth", "seed"):  # issue #4: the clearance-model optimisation within 120 s on 2 cores
        for ax in axes:
            ax.axvline(GOAL_WALL_S, color="tab:red", ls="--", lw=0.8)
        axes[-1].text(GOAL_WALL_S, 0.02, f" goal: {GOAL_WALL_S:.0f} s", transform=axes[-1].get_xaxis_transform(),
                      color="tab:red", fontsize=7, va="bottom")
    low = min([r["verified_objective"] for r in done] + [v for v in goals.values() if v > GOAL_SHOWN * start_value]
              + [start_value] + [r["last_iterate"]["verified_objective"] for r in done if "last_iterate" in r])
    axes[0].set_ylim(0.99 * low, 1.12 * max([start_value] + [r["verified_objective"] for r in done]
                                            + [v for v in goals.values() if v > GOAL_SHOWN * start_value]))
    axes[0].set_ylabel("objective of the iterates [N·m]")
    axes[1].set_ylabel("primal infeasibility")
    axes[2].set_ylabel("dual infeasibility (scaled)")
    axes[2].set_xlabel("wall time [s]")
    axes[0].set_title(f"Transcriptions from the same start: {case} case. Markers: the answer re-simulated\n"
                      "(o converged and verified, □ ram speed out of tolerance, x not converged: its least-"
                      "infeasible iterate,\n+ its last iterate); "
                      "iterates off the top are infeasible", fontsize=8)
    handles, labels = axes[0].get_legend_handles_labels()  # below the axes, clear of the curves
    height = 8.5 + LEGEND_LINE_IN * len(labels) + NOTE_IN
    fig.legend(handles, labels, fontsize=6.5, loc="lower left", bbox_to_anchor=(0.01, NOTE_IN / height))
    for ax in axes:
        ax.set_xscale("log")
        ax.grid(alpha=0.3, which="both")
    for ax in axes[1:]:
        ax.set_yscale("log")
    fig.set_figheight(height)
    fig.tight_layout(rect=(0.0, (LEGEND_LINE_IN * len(labels) + 0.1 + NOTE_IN) / height, 1.0, 1.0))
    figure_note(fig, run)
    save(fig, OUT / f"transcriptions_{case}.png")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=("smooth", "seed", "flexible", "flexible_shooting", "map"), required=True)
    ap.add_argument("--replot", action="store_true", help="only redraw the PNG from the JSON")
    ap.add_argument("--methods", nargs="+", choices=tuple(MAP_METHODS), default=list(MAP_METHODS),
                    help="with --case map: the transcriptions to run (the JSON keeps the others' rows)")
    ap.add_argument("--shooting-wall", type=float, default=1800.0,
                    help="IPOPT wall-time cap of each multiple-shooting run, s")
    args = ap.parse_args()
    if args.replot:
        d = json.loads((OUT / f"transcriptions_{args.case}.json").read_text())
        if args.case == "map":
            map_figure(d)
        else:
            figure(args.case, d["runs"], d.get("goals", {}), d["start_objective"], d.get("start_label", "rigid press"), d)
        return
    if args.case == "map":
        OUT.mkdir(exist_ok=True)
        map_case(args.shooting_wall, args.methods)
        return
    case = CASES[args.case](args.shooting_wall)
    start = case.start
    print(f"start: {start.name} optimum, {start.objective:.5g} on the rigid press", flush=True)
    OUT.mkdir(exist_ok=True)
    path = OUT / f"transcriptions_{args.case}.json"
    meta = {**stamp(), "versions": versions(), "case": args.case, "stage": case.stage, "start": start.name,
            "start_objective": start.objective, "goals": case.goals, "shooting_wall_s": args.shooting_wall,
            "verify_rtol": VERIFY_RTOL, **case.extra}
    rows: list[dict] = []
    for label, tr in case.runs:
        rows.append(run_one(label, tr, case.problem, case.model(), start, case.stage))
        path.write_text(json.dumps({**meta, "runs": rows}, indent=1, default=str) + "\n")  # every finished run
    figure(args.case, rows, case.goals, start.objective, case.extra.get("start_label", "rigid press"), meta)


CASES: dict[str, Callable[[float], Case]] = {"smooth": smooth_case, "seed": seed_case, "flexible": flexible_case,
                                             "flexible_shooting": flexible_shooting_case}


if __name__ == "__main__":
    main()
