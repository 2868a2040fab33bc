"""How fast can a press run its job with a given servo motor? `max_stroke_rate` on the clearance model.

    python -m benchmarks.bench_stroke_rate [--case press75|press60_big_rotor] [--tolerance-spm 2]
                                           [--also-unconstrained]

Cases (the scenario as bundled: both clearances, rigid rod, the default chain at every rate):

* ``press75``: a drive of gear ratio 10, efficiency 0.95, 8e-4 kg m^2 rotor, 3000 rpm top speed,
  continuous torque 10 N m and peak torque 15 N m (``--peak-torque``). Writes
  ``results/stroke_rate.json`` and ``.png``.
* ``press60_big_rotor``: a new user's drive for press60 (gear 10, 12 N m peak, 6 N m continuous,
  3000 rpm, 2 kW, 4e-3 kg m^2 rotor: J i^2 = 0.4 kg m^2, about the crank's own inertia), where the
  minimum-crank-torque optimum is flat in the rate and says nothing of the motor. Writes
  ``results/stroke_rate_press60_big_rotor.json`` and ``.png``.

The search starts at the scenario's rate. Every rate tried is optimised without the drive's limits
in the NLP, re-simulated (periodic, rtol 1e-9) and checked against the drive's peak curve, RMS
rating and top speed and the ram speed; a rate whose optimum misses only those limits is optimised
again with them as constraints (`RateSearch.hold_limits`) and checked the same way; the found rate
is tried again 2 % higher. With ``--also-unconstrained`` the search is run a second time in the same
process with ``hold_limits=False`` (one optimisation per rate: the search before 2026-12-02), to show
both answers side by side. Records each trial (rate, verdict, whether its limits were constraints,
margins, verified peak torque, wall time) and each search's time. Single run; the machine's load is
noted by hand when it was not idle. The figure: peak motor torque of the deciding optimum against
the rate, with the motor's peak torque (squares: limits held in the NLP); and the found rate's cycle
over the motor's envelope.
"""

from __future__ import annotations

import argparse
import dataclasses
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


BIG_ROTOR = po.Drive(gear_ratio=10.0, peak_torque=12.0, continuous_torque=6.0, max_speed=314.0, power_limit=2000.0,
                     gear_efficiency=0.95, motor_inertia=4e-3)
SHORT = {"peak_torque_margin": "peak", "rms_margin": "RMS", "speed_margin": "speed", "max_pin_force": "pin force",
         "verified": "not verified"}
CASES = {"press75": ("press75", "stroke_rate"), "press60_big_rotor": ("press60", "stroke_rate_press60_big_rotor")}


def figure(found: RateResult, motor: po.Drive, title: str, unconstrained: RateResult | None = None):
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2))
    shown = [t for t in sorted(found.trials, key=lambda t: t.rate_spm) if t.motor is not None]
    for i, t in enumerate(shown):
        ax.plot(t.rate_spm, t.motor.peak_torque, "s" if t.held else "o", color="tab:green" if t.feasible else "tab:red")
        # rates closer than 2 spm to the one before: their labels alternately above and below
        near = i > 0 and t.rate_spm - shown[i - 1].rate_spm < 2.0
        ax.annotate(f"{t.rate_spm:.1f}", (t.rate_spm, t.motor.peak_torque), fontsize=7,
                    xytext=(3, -11 if near and i % 2 else 3), textcoords="offset points")
    # what each failed rate missed (a limit below the peak line: RMS), under the axes: beside the points
    # the labels ran into each other where rates lie close
    missed = [f"{t.rate_spm:.1f} spm: {', '.join(SHORT.get(k, k) for k in t.failed)}" for t in shown if t.failed]
    if missed:
        rows = ["; ".join(missed[i:i + 3]) for i in range(0, len(missed), 3)]
        ax.text(0.0, -0.16, "failed: " + "\n".join(rows), transform=ax.transAxes, va="top", fontsize=7)
    for t in [] if unconstrained is None else unconstrained.trials:
        if t.motor is not None:
            ax.plot(t.rate_spm, t.motor.peak_torque, "x", color="tab:green" if t.feasible else "tab:red", ms=7)
    ax.axhline(motor.peak_torque, color="k", lw=1, ls="--", label=f"motor peak torque {motor.peak_torque:g} N·m")
    if unconstrained is not None and unconstrained.rate_spm is not None:
        ax.axvline(unconstrained.rate_spm, color="grey", lw=1, ls=":",
                   label=f"unconstrained only: {unconstrained.rate_spm:.1f} spm (x: its optima)")
    if found.rate_spm is not None:
        ax.axvline(found.rate_spm, color="tab:green", lw=1, ls=":", label=f"found: {found.rate_spm:.1f} spm")
    ax.set(xlabel="stroke rate, strokes/min", ylabel="peak motor torque of the deciding optimum, N·m",
           title=f"{title}: rates tried (green: every limit held; square: limits in the NLP)")
    ax.title.set_fontsize(9)
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


def searched(problem: po.SpeedProblem, model, search: po.RateSearch) -> RateResult:
    found = po.max_stroke_rate(problem, model, search)
    for t in found.trials:
        print(json.dumps(t.summary(), default=str), flush=True)
    return found


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=sorted(CASES), default="press75")
    ap.add_argument("--peak-torque", type=float, default=15.0, help="N m at the motor (press75's case)")
    ap.add_argument("--tolerance-spm", type=float, default=2.0)
    ap.add_argument("--also-unconstrained", action="store_true",
                    help="run the search a second time with hold_limits=False, in the same process")
    args = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    name, stem = CASES[args.case]
    scenario = po.Scenario.load(name)
    motor = drive(args.peak_torque) if args.case == "press75" else BIG_ROTOR
    problem = scenario.problem.replace(drive=motor)
    model = scenario.build_model()
    search = po.RateSearch(tolerance_spm=args.tolerance_spm, max_trials=8)
    found = searched(problem, model, search)
    record = {"date_run": stamp(), "versions": versions(), "case": args.case, "scenario": name,
              "drive": motor.to_dict(), "hold_limits": True, **found.summary(),
              "optimisations": sum(t.optimisations for t in found.trials),
              "above_fails": found.above is not None and not found.above.feasible}
    unconstrained = None
    if args.also_unconstrained:
        unconstrained = searched(problem, model, dataclasses.replace(search, hold_limits=False))
        record["unconstrained_only"] = unconstrained.summary()
    (OUT / f"{stem}.json").write_text(json.dumps(record, indent=1, default=str))
    save(figure(found, motor, f"{name}, motor {motor.peak_torque:g} N·m", unconstrained), OUT / f"{stem}.png")


if __name__ == "__main__":
    main()
