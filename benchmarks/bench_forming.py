"""The forming press of #32 (60 kN over the window): said up front without a counterbalance, solved
with an optimised one.

    python -m benchmarks.bench_forming

The bundled forming40 scenario: r 0.12 m, l 0.55 m, 1.5 t ram, 0.25/0.08 mm clearances, 40 spm,
-0.15 m/s over h/H 0.5 -> 0.15, 60 kN over that window. Without a counterbalance the rod's load must
reverse as the force sets in; the warning `optimize_speed` gives before any solve is recorded (the
request is only checked, not solved). With ``counterbalance_range = [0, 60 kN]`` the default call
(both clearances, rigid rod) chooses the counterbalance with the speed and designs the speed for it:
its verified peak torque against the rigid-press floor without a counterbalance (the ideal press's
optimum, which ignores the impacts), the rod-load reversals on the ideal press and the journals'
contact losses on the verifying simulation. Single run. Writes ``results/forming.json`` and
``results/forming.png``.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import pressocp as po
from pressocp.io import versions
from pressocp.ocp.optimize import checked_request
from pressocp.plots import save
from pressocp.report import stamp

from bench_counterbalance import contacts, reversals  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--max-iter", type=int, default=None,
                        help="IPOPT iteration limit of the collocation stages (default: the package's)")
    args = parser.parse_args()
    transcription = None if args.max_iter is None else po.Collocation(ipopt={"ipopt.max_iter": args.max_iter})
    OUT.mkdir(exist_ok=True)
    scenario = po.Scenario.load("forming40")
    bare = scenario.problem.replace(counterbalance_range=None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        checked_request(bare, None, None, "auto", None)
        said_in = time.perf_counter() - t0
    said = [str(w.message) for w in caught if issubclass(w.category, po.ReversalWarning)]
    t0 = time.perf_counter()
    floor = po.optimize_speed(bare, po.build_model(bare.press, clearance=()), progress=False)
    floor_time = time.perf_counter() - t0
    t0 = time.perf_counter()
    result = po.optimize_speed(scenario.problem, scenario.build_model(), transcription, progress=False)
    wall = time.perf_counter() - t0
    final = result.problem
    found = contacts(result.simulation, final.press)
    record = {
        "date_run": stamp(), "versions": versions(), "warning_without_counterbalance": said,
        "warning_seconds": said_in, "max_iter": args.max_iter,
        "rigid_floor_without_counterbalance_N_m": floor.peak_torque, "rigid_floor_time_s": floor_time,
        "success": result.success, "verified": result.verified, "status": result.status,
        "peak_torque_N_m": result.peak_torque, "rigid_peak_torque_N_m": result.rigid_peak_torque,
        "ratio_to_floor": result.peak_torque / floor.peak_torque,
        "counterbalance_N": final.press.counterbalance.force, "reversal_side": final.reversal_side(),
        "rod_load_reversals": reversals(final, result.speed),
        "contact_losses": {j: c["losses"] for j, c in found.items()}, "contacts": found,
        "max_ram_speed_violation_m_s": result.max_ram_speed_violation, "wall_time_s": wall,
        "speed": result.speed.to_dict(),
        "stages": [{"name": s.name, "status": s.status, "iterations": s.iterations, "objective": s.objective,
                    "wall_time_s": s.wall_time, "superseded": s.superseded,
                    "tension_margin": s.details.get("tension_margin"),
                    "start_min_eccentricity": None if s.check is None else s.check.min_eccentricity}
                   for s in result.stages]}
    print(json.dumps({k: v for k, v in record.items() if k not in ("stages", "versions", "speed")}, default=str), flush=True)
    (OUT / "forming.json").write_text(json.dumps(record, indent=1, default=float))

    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2))
    sim = result.simulation
    deg = np.degrees(np.mod(sim.theta, 2 * np.pi))
    order = np.argsort(deg)
    ax.plot(deg[order], sim.torque[order] / 1e3, lw=1, label=f"optimum, {final.press.counterbalance.force / 1e3:.1f} kN "
            f"counterbalance: {result.peak_torque / 1e3:.2f} kN·m")
    ax.axhline(floor.peak_torque / 1e3, color="k", ls="--", lw=1, label="rigid floor without counterbalance")
    ax.axhline(-floor.peak_torque / 1e3, color="k", ls="--", lw=1)
    title = ("forming40: " + ("verified" if result.verified else "NOT verified") + " "
             + ("optimum" if result.success else "best iterate (IPOPT did not converge)"))
    ax.set(xlabel="crank angle, deg", ylabel="motor torque at the crank, kN·m", title=title)
    ax.legend(fontsize=8)
    for joint in ("crank_pin", "wrist_pin"):  # the response's eccentricity is the ratio |e|/c
        bx.plot(deg[order], np.asarray(getattr(sim, f"{joint}_eccentricity"))[order], lw=1, label=joint)
    bx.axhline(1.0, color="k", lw=0.8)
    bx.set(xlabel="crank angle, deg", ylabel="|e| / clearance", title="journals: > 1 on the wall, < 1 in flight")
    bx.legend(fontsize=8)
    fig.tight_layout()
    save(fig, OUT / "forming.png")


if __name__ == "__main__":
    main()
