"""Transcriptions compared on the same problems, from the same start.

Each transcription solves the clearance-model stage of one problem (`Transcription.solve`), warm-started
from the same speed; its answer is re-simulated (periodic CVODES, rtol 1e-9). Recorded per run: IPOPT's
status, iterations, wall time, its objective and dual infeasibility per iteration (with the time of each
iteration), and the verified objective with the ram-speed violation.

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

    python benchmarks/bench_transcriptions.py --case smooth|seed [--shooting-wall S]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.objectives import get as get_objective  # noqa: E402
from pressocp.ocp.result import versions  # noqa: E402
from pressocp.ocp.stage import WarmStart  # noqa: E402
from pressocp.ocp.verify import is_periodic, ram_speed_violation, verify_speed  # noqa: E402
from pressocp.plots import save  # noqa: E402
from pressocp.report import stamp  # noqa: E402

OUT = Path(__file__).parent / "results"
VERIFY_RTOL = 1e-9


def smooth_case(wall: float):
    problem = po.SpeedProblem(po.PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)
    rigid = po.Rigid(samples=300)
    start = rigid.solve(problem, po.build_model(problem.press, clearance=(), n_harmonics=4),
                        WarmStart(po.design_speed(problem).speed), "rigid")
    cap = {"ipopt.max_wall_time": wall}
    runs = [("IDAS shooting 16x25", po.MultipleShooting("idas", min_eccentricity=1.0, ipopt=cap)),
            ("CVODES shooting 16x25", po.MultipleShooting("cvodes", min_eccentricity=1.0, ipopt=cap))]
    runs += [(f"collocation {n}x3", po.Collocation(elements=n, jit=False)) for n in (100, 200, 400)]
    return problem, start, runs, {}


def seed_case(wall: float):
    problem = po.Scenario.load("press75").problem
    rigid = po.Rigid()
    ideal = po.build_model(problem.press, clearance=(), n_harmonics=problem.n_harmonics)
    r = rigid.solve(problem, ideal, WarmStart(po.design_speed(problem).speed), "rigid")
    margin = po.Strategy().tension_margin * problem.hanging_weight
    start = rigid.solve(problem.replace(min_tension=margin), ideal, WarmStart(r.speed), "no_reversal")
    runs = [("IDAS shooting 16x25", po.MultipleShooting("idas", min_eccentricity=1.0,
                                                         ipopt={"ipopt.max_wall_time": wall}))]
    runs += [(f"collocation {n}x3", po.Collocation(elements=n)) for n in (400, 800, 1600)]
    goals = {"issue goal 147.5 N·m": 147.5, f"rigid floor {r.objective:.1f} N·m": r.objective}
    return problem, start, runs, goals


def run_one(label: str, tr, problem, model, start) -> dict:
    print(f"{label} ...", flush=True)
    t0 = time.perf_counter()
    try:
        st = tr.solve(problem, model, WarmStart(start.speed), "target", progress=False)
    except Exception as err:  # a transcription that cannot even start is a measured failure
        return {"label": label, "transcription": repr(tr), "error": f"{type(err).__name__}: {err}",
                "wall_time_s": time.perf_counter() - t0}
    sim = verify_speed(model, st.speed, VERIFY_RTOL)
    objective = get_objective(problem.objective).value(sim)
    row = {"label": label, "transcription": repr(tr), "success": st.success, "status": st.status,
           "iterations": st.iterations, "wall_time_s": st.wall_time, "objective": st.objective,
           "verified_objective": float(objective), "periodic": is_periodic(sim),
           "ram_speed_violation_m_s": float(max(ram_speed_violation(sim, problem), 0.0)),
           "history": st.history, "iteration_log": st.iteration_log}
    print(f"  {st.status}, {st.iterations} it, {st.wall_time:.0f} s, J {st.objective:.5g}, "
          f"verified {objective:.5g}, ram-speed violation {row['ram_speed_violation_m_s']:.2g}", flush=True)
    return row


def figure(case: str, rows: list[dict], goals: dict, start_value: float) -> None:
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for i, r in enumerate(rows):
        if "error" in r:
            continue
        c = f"C{i}"
        t = np.asarray(r["iteration_log"].get("time_s", []))
        h = np.asarray(r["history"][: len(t)])
        a1.plot(t[: len(h)], h, "-", color=c, lw=1, label=f"{r['label']}: {r['status']}")
        a1.plot([r["wall_time_s"]], [r["verified_objective"]], "o" if r["success"] else "x", color=c, ms=7)
        du = np.asarray(r["iteration_log"].get("inf_du", []))
        n = min(len(t), len(du))
        a2.semilogy(t[:n], np.maximum(du[:n], 1e-16), "-", color=c, lw=1)
    for k, (name, v) in enumerate(goals.items()):
        a1.axhline(v, color="0.4", ls=(0, (4, 2 + 2 * k)), lw=0.8, label=name)
    a1.axhline(start_value, color="0.7", lw=0.8, ls=":", label=f"start {start_value:.1f} (rigid press)")
    a1.set_ylabel("objective of the iterate [N·m]\n(o/x: verified answer, converged/not)")
    a2.set_ylabel("IPOPT dual infeasibility (scaled)")
    a2.set_xlabel("wall time [s]")
    a1.set_title(f"Transcriptions from the same start: {case} case", fontsize=10)
    a1.legend(fontsize=7)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, OUT / f"transcriptions_{case}.png")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=("smooth", "seed"), required=True)
    ap.add_argument("--shooting-wall", type=float, default=1800.0,
                    help="IPOPT wall-time cap of each multiple-shooting run, s")
    args = ap.parse_args()
    problem, start, runs, goals = (smooth_case if args.case == "smooth" else seed_case)(args.shooting_wall)
    model = po.build_model(problem.press, n_harmonics=problem.n_harmonics)
    print(f"start: {start.name} optimum, {start.objective:.5g} on the rigid press", flush=True)
    rows = [run_one(label, tr, problem, model, start) for label, tr in runs]
    OUT.mkdir(exist_ok=True)
    out = {**stamp(), "versions": versions(), "case": args.case, "start": start.name,
           "start_objective": start.objective, "verify_rtol": VERIFY_RTOL, "runs": rows}
    (OUT / f"transcriptions_{args.case}.json").write_text(json.dumps(out, indent=1, default=str) + "\n")
    figure(args.case, rows, goals, start.objective)


if __name__ == "__main__":
    main()
