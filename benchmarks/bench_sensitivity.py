"""Accuracy and cost of `po.sensitivities` on the smooth case: the default press at constant speed,
75 spm (T = 0.8 s), peak motor torque, against slider mass, wrist-pin clearance and crank-pin contact
stiffness (issue #16).

AD (forward sensitivities of the periodic response) at rtol 1e-10 ... 1e-13, each with its error
estimate and wall time, against central differences of periodic simulations at rtol 1e-13 (+-5 %
steps): |torque| at each rival peak's time (the 1e-13 AD's), the state settled cycle by cycle until
it repeats to 1e-10. At a peak's time the difference of |torque| is the peak's derivative (the peak's
time moves with p, but d|torque|/dt = 0 there), without the sampling that locating a peak needs.

    python benchmarks/bench_sensitivity.py [--replot]

Writes results/sensitivity_smooth.json and .png.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.model import OUTPUT_NAMES  # noqa: E402
from pressocp.io import versions  # noqa: E402
from pressocp.plots import save  # noqa: E402
from pressocp.report import stamp  # noqa: E402
from pressocp.sensitivity import RESOLVED  # noqa: E402

OUT = Path(__file__).parent / "results"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")
RTOLS = (1e-10, 1e-11, 1e-12, 1e-13)
FD_RTOL = 1e-13
STEP = 0.05
GOAL = 0.02


def torque_at(press: po.PressParams, speed: po.FourierSpeed, times, rtol: float) -> np.ndarray:
    """|torque| (N m) of the periodic response at `times` (s, in any order)."""
    model = po.build_model(press)
    dae = model.dae(explicit=True)
    dae.pop("quad")
    opts = {"reltol": rtol, "abstol": rtol, "max_num_steps": 10**8}
    cycle = ca.integrator("cycle", "cvodes", dae, 0.0, speed.period, opts)
    p = model.parameters(speed)
    x = model.x0
    for _ in range(60):
        x_next = np.asarray(cycle(x0=x, p=p)["xf"]).ravel()
        change = float(np.max(np.abs(x_next - x)))
        x = x_next
        if change < 1e-10:
            break
    else:
        raise RuntimeError(f"no periodic state: change per cycle {change:.2g}")
    order = np.argsort(times)  # an integrator's output times increase
    grid = [float(times[i]) for i in order]
    X = np.asarray(ca.integrator("to_times", "cvodes", dae, 0.0, grid, opts)(x0=x, p=p)["xf"])
    k = OUTPUT_NAMES.index("torque")
    out = np.empty(len(grid))
    out[order] = [abs(float(model.outputs(t, X[:, i], p)[k])) for i, t in enumerate(grid)]
    return out


def measure() -> dict:
    press = po.PressParams()
    speed = po.FourierSpeed.constant(0.8)
    model = po.build_model(press)
    ad = []
    for rtol in RTOLS:
        s = po.sensitivities(model, speed, PARAMETERS, rtol=rtol)
        ad.append({"rtol": rtol, "wall_time_s": s.wall_time, "per_peak": s.per_peak.to_dict("records"),
                   "table": s.table.to_dict("records")})
        print(f"AD rtol {rtol:g}: {s.wall_time:.1f} s", flush=True)
    finest = ad[-1]["per_peak"]
    fd = []
    for name in PARAMETERS:
        rows = [r for r in finest if r["parameter"] == name]
        times = [r["time"] for r in rows]
        h = STEP * press.value(name)
        t0 = time.perf_counter()
        up = torque_at(press.with_value(name, press.value(name) + h), speed, times, FD_RTOL)
        down = torque_at(press.with_value(name, press.value(name) - h), speed, times, FD_RTOL)
        for r, d in zip(rows, (up - down) / (2 * h)):
            fd.append({"parameter": name, "time": r["time"], "derivative": float(d), "step": STEP})
        print(f"FD {name}: {(up - down) / (2 * h)} ({time.perf_counter() - t0:.1f} s)", flush=True)
    return {**stamp(), "versions": versions(), "case": "default press, constant speed, T = 0.8 s",
            "fd_rtol": FD_RTOL, "goal": GOAL, "resolved_tol": RESOLVED, "ad": ad, "fd": fd}


def plot(data: dict) -> plt.Figure:
    """Per parameter: |AD / FD - 1| of each rival peak against rtol, with the error estimate."""
    fig, axes = plt.subplots(1, len(PARAMETERS), figsize=(11, 3.6), sharey=True)
    for ax, name in zip(axes, PARAMETERS):
        fd = {round(r["time"], 4): r["derivative"] for r in data["fd"] if r["parameter"] == name}
        for k, t in enumerate(sorted(fd)):
            err, est = [], []
            for run in data["ad"]:
                row = min((r for r in run["per_peak"] if r["parameter"] == name), key=lambda r: abs(r["time"] - t))
                err.append(abs(row["derivative"] / fd[t] - 1))
                est.append(row["error_estimate"])
            rt = [run["rtol"] for run in data["ad"]]
            ax.loglog(rt, err, "o-", color=f"C{k}", label=f"peak at t = {t:.3f} s: AD against FD")
            ax.loglog(rt, est, "x:", color=f"C{k}", label="its error estimate (run at 10 rtol)")
        ax.axhline(data["goal"], ls="--", color="tab:red", lw=0.8)
        ax.text(1.1e-13, data["goal"] * 1.3, "goal 2 %", color="tab:red", fontsize=7)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("rtol of AD")
        ax.invert_xaxis()
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("relative error of dJ/dp")
    axes[0].legend(fontsize=6, loc="lower left")
    fig.suptitle("po.sensitivities, peak torque at constant speed (75 spm): AD against central differences "
                 f"at rtol {data['fd_rtol']:g}, ±{100 * STEP:g} %", fontsize=9)
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replot", action="store_true", help="redraw the figure from the JSON")
    args = ap.parse_args()
    path = OUT / "sensitivity_smooth.json"
    data = json.loads(path.read_text()) if args.replot else measure()
    if not args.replot:
        path.write_text(json.dumps(data, indent=1, default=float))
    save(plot(data), OUT / "sensitivity_smooth.png")


if __name__ == "__main__":
    main()
