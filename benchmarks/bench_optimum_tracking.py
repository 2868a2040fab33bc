"""dJ*/dp of one local optimum against differences of that same optimum followed to p +- h.

`po.optimum_sensitivities` differentiates the optimum its re-solve at the answer lands on. Re-solving
the optimisation at p +- h from scratch, or from the optimum with a fresh barrier, can land on other
local optima (on the 75 spm scene they scatter by 5-10 %: `bench_optimum_sensitivity.py`). Here the
differentiated optimum is followed to p +- h by `resolve_tracking` (IPOPT started at its primal-dual
point with a small barrier), for h = 0.01 %, 0.1 %, 1 % and 2 % of the slider mass, and the central
differences of the tracked optima are compared with the KKT derivative.

    python benchmarks/bench_optimum_tracking.py SCENARIO [--result RESULT.json] [--steps H ...]

``--result`` differentiates a saved `OcpResult` (e.g. the main job's ``out/result.json``) instead of
running the default call first. Appends to results/optimum_tracking.json.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import pressocp as po
from pressocp.ocp.kkt import resolve_tracking
from pressocp.io import versions
from pressocp.report import stamp

OUT = Path(__file__).parent / "results"
PARAMETER = "slider_mass"
STEPS = (1e-4, 1e-3, 1e-2, 2e-2)
#: On top of `IPOPT_TRACKING`: collocation's exact Hessian and MUMPS setting (the rigid transcription's too).
OPTIONS = {"ipopt.hessian_approximation": "exact", "ipopt.mumps_scaling": 0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenario")
    ap.add_argument("--result", type=Path, default=None, help="a saved OcpResult of the scenario's problem")
    ap.add_argument("--steps", type=float, nargs="+", default=list(STEPS), help="relative steps h")
    a = ap.parse_args()
    problem = po.Scenario.load(a.scenario).problem
    t0 = time.perf_counter()
    result = po.OcpResult.from_json(a.result) if a.result else po.optimize_speed(problem, progress=False)
    if result.problem != problem:
        raise SystemExit(f"{a.result} is not a result of scenario {a.scenario!r}'s problem")
    t_opt = time.perf_counter() - t0
    sens = po.optimum_sensitivities(result, (PARAMETER,))
    d = sens.derivative(PARAMETER)
    p = problem.press.value(PARAMETER)
    print(f"{a.scenario}: J* {sens.objective:.6g} (stage {sens.stage}), dJ*/dp {d:.6g} N m/kg; re-solve "
          f"{sens.resolve_time:.0f} s, KKT {sens.kkt_time:.0f} s", flush=True)
    steps = []
    for h in a.steps:
        ends = {}
        for sign in (+1, -1):
            pv = sens.point.p.copy()
            pv[0] *= 1 + sign * h
            t = resolve_tracking(sens.point, pv, OPTIONS)
            ends["up" if sign > 0 else "down"] = {"objective": sens.to_objective * t.f, "success": t.success,
                                                  "status": t.status, "iterations": t.iterations,
                                                  "wall_time_s": t.wall_time}
        ok = ends["up"]["success"] and ends["down"]["success"]  # a failed end gives no difference
        fd = (ends["up"]["objective"] - ends["down"]["objective"]) / (2 * h * p) if ok else float("nan")
        steps.append({"step_relative": h, **ends, "fd_derivative": fd, "relative_difference": d / fd - 1,
                      "one_sided_up": (ends["up"]["objective"] - sens.objective) / (h * p),
                      "one_sided_down": (sens.objective - ends["down"]["objective"]) / (h * p)})
        print(f"  +-{h:g}: {fd:.6g} N m/kg ({d / fd - 1:+.2%}); one-sided {steps[-1]['one_sided_up']:.5g} / "
              f"{steps[-1]['one_sided_down']:.5g}; {ends['up']['iterations']}/{ends['down']['iterations']} it, "
              f"{ends['up']['wall_time_s']:.0f}/{ends['down']['wall_time_s']:.0f} s; {ends['up']['status']}/"
              f"{ends['down']['status']}", flush=True)
    row = {**stamp(), "versions": versions(), "scenario": a.scenario, "result": str(a.result or "default call"),
           "optimize_wall_time_s": t_opt, "result_objective": result.objective_value, "stage": sens.stage,
           "differentiated_objective": sens.objective, "parameter": PARAMETER, "parameter_value": p,
           "derivative": d, "sensitivity_resolve_s": sens.resolve_time, "sensitivity_kkt_s": sens.kkt_time,
           "active": sens.active, "weakly_active": sens.weakly_active,
           "step_up_predicted": float(sens.table.iloc[0]["step_up"]),
           "step_down_predicted": float(sens.table.iloc[0]["step_down"]), "steps": steps}
    path = OUT / "optimum_tracking.json"
    rows = json.loads(path.read_text()) if path.exists() else []
    path.write_text(json.dumps(rows + [row], indent=1, default=str) + "\n")


if __name__ == "__main__":
    main()
