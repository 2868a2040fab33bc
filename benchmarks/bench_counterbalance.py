"""press75 with a slide counterbalance, and press75 drawing a cup: verified optima and joint-force
reversals.

    python -m benchmarks.bench_counterbalance [--skip-constant] [--workers N]

Runs the default call (both clearances, rigid rod, the default chain) of:

* ``none``: press75 as bundled (no counterbalance);
* ``constant``: press75 with ``counterbalance_range = [0, 12 kN]``, a constant force (a large surge
  tank): the counterbalance stage chooses the force with the speed on the ideal press, the rod
  held in compression;
* ``gas``: the same with a gas spring (0.3 m of gas at bottom dead centre, exponent 1.4);
* ``drawing``: the bundled drawing75 (a deep-drawing force curve over the window, no counterbalance);
* ``drawing_constant`` and ``drawing_curve`` (unless ``--skip-constant``): a 1 kN force over h 30 to
  70 mm, once as the constant force and once as the curve of its two points: the same optimum.

For each: the verified peak torque, the chosen force, the wall time, the rod-load reversals of the
answer on the ideal press (sign changes of the axial load at the wrist pin over a period) and the
journals' contact losses on the verifying simulation (entries of the eccentricity below the
clearance, per joint). Single runs, not medians: the results are answers, not times; the machine's
load is recorded with the date. Writes ``results/counterbalance.json`` and
``results/counterbalance.png``.

The cases run `--workers` at a time (default 2) in the package's worker pool, the longest first. In a
worker a case runs its two candidate chains one after the other (a sweep point's path), where a
default call in the main process runs them side by side: the same answer since CasADi's BLAS runs
one thread in every process (`pressocp.blas`), but a case's ``wall_time_s`` is the sum of its chains.
"""

from __future__ import annotations

import argparse
import importlib
import json
import time
from concurrent.futures import as_completed
from pathlib import Path

import numpy as np

import pressocp as po
from pressocp.io import versions
from pressocp.journals import contact_losses
from pressocp.plots import save
from pressocp.report import stamp
from pressocp.workers import process_pool

OUT = Path(__file__).parent / "results"
#: Range of the counterbalance's force, N (8 x the hanging weight of ram and rod).
RANGE = (0.0, 12000.0)


def reversals(problem: po.SpeedProblem, speed: po.FourierSpeed) -> int:
    """Sign changes over one period of the rod's axial load at the wrist pin on the ideal press."""
    t = np.linspace(0.0, speed.period, 4001)[:-1]
    theta, omega, alpha = speed.evaluate(t)
    load = np.asarray(po.rigid_inverse_dynamics(problem.press, theta, omega, alpha)["wrist_pin_tension"]).ravel()
    sign = np.sign(load)
    return int(np.sum(sign != np.roll(sign, 1)))


def contacts(sim, press: po.PressParams) -> dict[str, dict]:
    """Per joint, the journal's separations from its bearing wall over the simulated period
    (`pressocp.journals.contact_losses`: count, longest, deepest, fastest return)."""
    return {j: c.to_dict() for j, c in contact_losses(sim, press, ("crank_pin", "wrist_pin")).items()}


def case(name: str, scenario: po.Scenario, **changes) -> dict:
    problem = scenario.problem.replace(**changes)
    t0 = time.perf_counter()
    result = po.optimize_speed(problem, scenario.build_model().spec.build(problem.press, problem.n_harmonics),
                               progress=False)
    wall = time.perf_counter() - t0
    final = result.problem
    found = contacts(result.simulation, final.press)
    record = {
        "case": name, "success": result.success, "verified": result.verified, "status": result.status,
        "peak_torque_N_m": result.peak_torque, "rigid_peak_torque_N_m": result.rigid_peak_torque,
        "counterbalance": final.press.counterbalance.__dict__, "process_force_max_N": final.press.process_force.peak,
        "reversal_side": final.reversal_side(), "rod_load_reversals": reversals(final, result.speed),
        "contact_losses": {j: c["losses"] for j, c in found.items()}, "contacts": found,
        "max_ram_speed_violation_m_s": result.max_ram_speed_violation, "wall_time_s": wall,
        "speed": result.speed.to_dict(),
        "stages": [{"name": s.name, "status": s.status, "iterations": s.iterations, "objective": s.objective,
                    "wall_time_s": s.wall_time} for s in result.stages]}
    print(json.dumps({k: record[k] for k in ("case", "verified", "peak_torque_N_m", "counterbalance",
                                              "rod_load_reversals", "contact_losses", "wall_time_s")}), flush=True)
    sim = result.simulation
    return record | {"_curve": {"theta": np.asarray(sim.theta), "torque": np.asarray(sim.torque),
                                "wrist_pin_force": np.asarray(sim.wrist_pin_force)}}


def figure(records: list[dict]):
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2))
    for r in records:
        curve = r["_curve"]
        deg = np.degrees(np.mod(curve["theta"], 2 * np.pi))
        order = np.argsort(deg)
        label = f"{r['case']}: {r['peak_torque_N_m']:.1f} N·m"
        ax.plot(deg[order], curve["torque"][order], lw=1, label=label)
        bx.plot(deg[order], curve["wrist_pin_force"][order] / 1e3, lw=1, label=r["case"])
    ax.set(xlabel="crank angle, deg (0: top dead centre)", ylabel="motor torque at the crank, N·m",
           title="verified optima (re-simulated, both clearances)")
    bx.set(xlabel="crank angle, deg", ylabel="wrist-pin force, kN", title="wrist-pin force")
    ax.legend(fontsize=8)
    bx.legend(fontsize=8)
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skip-constant", action="store_true", help="skip the constant-against-curve pair")
    ap.add_argument("--workers", type=int, default=2, help="cases run at once, each in a worker (default 2)")
    args = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    press75, drawing = po.Scenario.load("press75"), po.Scenario.load("drawing75")
    gas = press75.press.replace(counterbalance=po.Counterbalance(gas_length=0.3, exponent=1.4))
    cases = {"none": (press75, {}), "constant": (press75, {"counterbalance_range": RANGE}),
             "gas": (press75, {"press": gas, "counterbalance_range": RANGE}), "drawing": (drawing, {})}
    if not args.skip_constant:
        constant = po.ProcessForce(force=1000.0, h_top=0.07, h_bottom=0.03)
        curve = po.ProcessForce(heights=(0.03, 0.07), forces=(1000.0, 1000.0))
        cases |= {"drawing_constant": (press75, {"press": press75.press.replace(process_force=constant)}),
                  "drawing_curve": (press75, {"press": press75.press.replace(process_force=curve)})}
    longest_first = [n for n in ("constant", "gas", "drawing", "drawing_constant", "drawing_curve", "none") if n in cases]
    task = importlib.import_module(Path(__file__).stem).case  # by its module's name: the workers import it so
    with process_pool(args.workers) as pool:
        futures = {pool.submit(task, name, cases[name][0], **cases[name][1]): name for name in longest_first}
        done = {futures[f]: f.result() for f in as_completed(futures)}
    records = [done[name] for name in cases]
    fig = figure(records[:4])
    out = {"date_run": stamp(), "versions": versions(), "range_N": list(RANGE), "cases_at_once": args.workers,
           "cases": [{k: v for k, v in r.items() if k != "_curve"} for r in records]}
    by = {r["case"]: r for r in out["cases"]}
    out["counterbalance_lowers_peak"] = bool(
        min(by["constant"]["peak_torque_N_m"], by["gas"]["peak_torque_N_m"]) < by["none"]["peak_torque_N_m"]
        and by["constant"]["verified"] and by["gas"]["verified"])
    if "drawing_curve" in by:
        out["curve_against_constant"] = by["drawing_curve"]["peak_torque_N_m"] / by["drawing_constant"][
            "peak_torque_N_m"] - 1.0
    (OUT / "counterbalance.json").write_text(json.dumps(out, indent=1, default=float))
    save(fig, OUT / "counterbalance.png")


if __name__ == "__main__":
    main()
