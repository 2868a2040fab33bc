"""press75 with a servo drive: does the optimum hold the motor's envelope, and what does a too-weak
motor get?

    python -m benchmarks.bench_drive [--peak-torque 15.0] [--weak-peak-torque 8.0] [--no-counterbalance]
                                     [--max-iter N]

The bundled press75 scenario (both clearances, rigid rod, the default chain, the drive's limits
constrained in every stage) with a drive of gear ratio 10, efficiency 0.95, 2e-4 kg m^2 rotor (low inertia),
3000 rpm top speed and a peak torque whose crank equivalent (peak x ratio x efficiency, 142.5 N m)
lies between the rigid press's floor (108.5 N m) and the optimum without a drive (145.1 N m). No
speed alone gets press75's verified peak under that (its no-reversal optimum is about 145 N m), so
the press gets a counterbalance optimised with the speed (``counterbalance_range`` 0 to 12 kN)
unless ``--no-counterbalance``. The answer is re-simulated (the chain's own verification) and
its motor cycle computed on that simulation (`motor_cycle_of`): peak and RMS torque, margins, top
speed. ``--max-iter``: the collocation stages' IPOPT iteration limit (default the package's). A
second run with a motor far too weak records how the result says so. Writes
``results/drive.json`` and ``results/drive.png`` (the optimum's torque-speed figure) with the date
and machine. Single runs, not medians: the result is the envelope held, not a time.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import pressocp as po
from pressocp.drive import Drive
from pressocp.io import versions
from pressocp.plots import plot_torque_speed, save
from pressocp.report import stamp
from pressocp.verify import motor_cycle_of

OUT = Path(__file__).parent / "results"


def drive_for(peak: float) -> Drive:
    """The benchmark's drive with peak torque `peak` (N m at the motor)."""
    return Drive(gear_ratio=10.0, peak_torque=peak, continuous_torque=0.7 * peak, max_speed=314.0,
                 gear_efficiency=0.95, motor_inertia=2e-4)


def one(peak: float, counterbalance: bool, max_iter: int | None = None) -> tuple[dict, object, object]:
    """The default call of press75 with the drive of `peak` (and a counterbalance chosen with the
    speed); its record, result and motor cycle."""
    scenario = po.Scenario.load("press75")
    problem = scenario.problem.replace(drive=drive_for(peak),
                                       counterbalance_range=(0.0, 12000.0) if counterbalance else None)
    t0 = time.perf_counter()
    transcription = None if max_iter is None else po.Collocation(ipopt={"ipopt.max_iter": max_iter})
    result = po.optimize_speed(problem, scenario.build_model(), transcription, progress=False)
    wall = time.perf_counter() - t0
    problem = result.problem
    motor = motor_cycle_of(problem, result.speed, result.simulation)
    record = {"drive": problem.drive.to_dict(), "crank_equivalent_peak_N_m": peak * 10.0 * 0.95, "crank_floor_N_m": 108.5,
              "success": result.success, "verified": result.verified, "status": result.status,
              "peak_torque_N_m": result.peak_torque, "rigid_peak_torque_N_m": result.rigid_peak_torque,
              "max_ram_speed_violation_m_s": result.max_ram_speed_violation, "wall_time_s": wall,
              "counterbalance_N": problem.press.counterbalance.force,
              "motor": motor.summary(), "max_iter": max_iter, "speed": result.speed.to_dict(),
              "stages": [{"name": s.name, "status": s.status, "iterations": s.iterations, "wall_time_s": s.wall_time}
                         for s in result.stages]}
    return record, problem, motor


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--peak-torque", type=float, default=15.0, help="N m at the motor (crank equivalent x 9.5)")
    ap.add_argument("--no-counterbalance", action="store_true", help="press75 as bundled")
    ap.add_argument("--weak-peak-torque", type=float, default=8.0, help="a motor far too weak, N m")
    ap.add_argument("--max-iter", type=int, default=None, help="IPOPT iteration limit of the collocation stages")
    args = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    held, problem, motor = one(args.peak_torque, not args.no_counterbalance, args.max_iter)
    print(json.dumps({k: held[k] for k in ("success", "verified", "status", "peak_torque_N_m", "wall_time_s")}),
          flush=True)
    print("motor:", json.dumps(held["motor"]), flush=True)
    weak, _, _ = one(args.weak_peak_torque, False)
    print(json.dumps({k: weak[k] for k in ("success", "verified", "status", "wall_time_s")}), flush=True)
    record = {"date_run": stamp(), "versions": versions(), "held": held, "weak": weak,
              "envelope_held": bool(held["verified"] and held["motor"]["peak_torque_margin"] >= 0
                                    and held["motor"]["speed_margin"] >= 0 and held["motor"]["rms_margin"] >= 0)}
    (OUT / "drive.json").write_text(json.dumps(record, indent=1))
    save(plot_torque_speed(problem.drive, {"optimum": motor},
                           f"press75, both clearances{'' if args.no_counterbalance else ', optimised counterbalance'}: the optimum over "
                           f"a {args.peak_torque:g} N·m motor (gear 10)"),
         OUT / "drive.png")


if __name__ == "__main__":
    main()
