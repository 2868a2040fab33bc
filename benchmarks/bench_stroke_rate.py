"""How fast can press75 run its job with a given servo motor? `max_stroke_rate` on the clearance model.

    python -m benchmarks.bench_stroke_rate [--peak-torque 15] [--tolerance-spm 2]

press75 as bundled (both clearances, rigid rod, the default chain at every rate) with a drive of gear
ratio 10, efficiency 0.95, 8e-4 kg m^2 rotor, 3000 rpm top speed, continuous torque 10 N m and the
given peak torque (N m at the motor). The search starts at the scenario's 75 strokes/min. Every rate
tried is optimised, re-simulated (periodic, rtol 1e-9) and checked against the drive's peak curve,
RMS rating and top speed and the ram speed; the found rate is tried again 2 % higher. Records each
trial (rate, verdict, margins, verified peak torque, wall time) and the search's time. Single run;
the machine's load is noted by hand when it was not idle. Writes ``results/stroke_rate.json`` and
``results/stroke_rate.png`` (peak motor torque against the rate, with the motor's peak torque; and
the found rate's cycle over the motor's envelope).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import pressocp as po
from pressocp.io import versions
from pressocp.plots import save
from pressocp.report import stamp
from pressocp.stroke_rate import RateResult

OUT = Path(__file__).parent / "results"


def drive(peak: float) -> po.Drive:
    return po.Drive(gear_ratio=10.0, peak_torque=peak, continuous_torque=10.0, max_speed=314.0, gear_efficiency=0.95,
                    motor_inertia=8e-4)


def figure(found: RateResult, motor: po.Drive):
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2))
    for t in sorted(found.trials, key=lambda t: t.rate_spm):
        if t.motor is None:
            continue
        ax.plot(t.rate_spm, t.motor.peak_torque, "o", color="tab:green" if t.feasible else "tab:red")
        ax.annotate(f"{t.rate_spm:.1f}", (t.rate_spm, t.motor.peak_torque), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.axhline(motor.peak_torque, color="k", lw=1, ls="--", label=f"motor peak torque {motor.peak_torque:g} N·m")
    ax.set(xlabel="stroke rate, strokes/min", ylabel="peak motor torque of the verified optimum, N·m",
           title="rates tried (green: every limit held)")
    ax.legend(fontsize=8)
    for label, t in (("found", found.best), ("+2 %", found.above)):
        if t is not None and t.motor is not None:
            c = t.motor
            bx.plot(np.abs(c.speed) * 60 / (2 * np.pi), np.abs(c.torque), lw=1,
                    label=f"{label}: {t.rate_spm:.1f} spm")
    w = np.linspace(0.0, motor.max_speed, 200)
    bx.plot(w * 60 / (2 * np.pi), motor.peak_torque_at(w), "k--", lw=1, label="peak curve")
    bx.axhline(motor.continuous_torque, color="grey", lw=1, ls=":", label="continuous")
    bx.set(xlabel="motor speed, rpm", ylabel="|motor torque|, N·m", title="the cycle over the envelope")
    bx.legend(fontsize=8)
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--peak-torque", type=float, default=15.0, help="N m at the motor")
    ap.add_argument("--tolerance-spm", type=float, default=2.0)
    args = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    scenario = po.Scenario.load("press75")
    motor = drive(args.peak_torque)
    problem = scenario.problem.replace(drive=motor)
    found = po.max_stroke_rate(problem, scenario.build_model(), po.RateSearch(tolerance_spm=args.tolerance_spm,
                                                                            max_trials=8))
    for t in found.trials:
        print(json.dumps(t.summary(), default=str), flush=True)
    record = {"date_run": stamp(), "versions": versions(), "drive": motor.to_dict(), **found.summary(),
              "above_fails": found.above is not None and not found.above.feasible}
    (OUT / "stroke_rate.json").write_text(json.dumps(record, indent=1, default=str))
    save(figure(found, motor), OUT / "stroke_rate.png")


if __name__ == "__main__":
    main()
