"""Command line: ``pressocp`` (or ``python -m pressocp``) runs the default scenario."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from .design import design_speed
from .params import PressParams
from .problem import SpeedProblem
from .plots import plot_responses, save
from .rigid import rigid_response
from .speed import FourierSpeed


def run_design(out: Path, period: float, ram_speed: float, window: tuple[float, float]) -> dict:
    """Rigid speed design of the default press: figure, JSON summary, printed table."""
    params = PressParams()
    t0 = time.perf_counter()
    d = design_speed(SpeedProblem(params, period=period, ram_speed=ram_speed, window=window))
    wall = time.perf_counter() - t0
    t = np.linspace(0, period, 4001)
    const = rigid_response(params, FourierSpeed.constant(period), t)
    designed = rigid_response(params, d.speed, t)
    fig = plot_responses([("constant speed", const), ("designed speed", designed)], window=(d.t1, d.t2),
                         title=f"Rigid speed design: ram speed {ram_speed:g} m/s over h/H {window[0]:g}→{window[1]:g}")
    out.mkdir(parents=True, exist_ok=True)
    save(fig, out / "design_speed.png")
    summary = {
        "scenario": "default press, rigid speed design",
        "period_s": period, "ram_speed_m_s": ram_speed, "window_h_over_H": list(window),
        "converged": d.converged, "status": d.status, "t1_s": d.t1, "t2_s": d.t2,
        "max_rel_ram_speed_error": d.max_error, "rms_rel_ram_speed_error": d.rms_error,
        "min_omega_rad_s": d.min_omega, "wall_time_s": wall,
        "peak_torque_constant_Nm": const.peak("torque"), "peak_torque_designed_Nm": designed.peak("torque"),
        "peak_normal_force_designed_N": designed.peak("slider_normal_force"),
        "min_wrist_pin_force_designed_N": float(designed.wrist_pin_force.min()),
        "a": d.speed.a.tolist(), "b": d.speed.b.tolist(),
    }
    (out / "design_speed.json").write_text(json.dumps(summary, indent=2))
    return summary


def run_impacts(out: Path) -> int:
    """Seed Figs. 6 and 9: constant vs rigid-designed speed on the clearance model."""
    from .plots import plot_impact_study
    from .studies import impact_study

    t0 = time.perf_counter()
    st = impact_study()
    wall = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    save(plot_impact_study(st), out / "impacts.png")
    ratios = st.ratios()
    summary = {"period_s": st.design.speed.period, "ram_speed_m_s": st.design.ram_speed, "wall_time_s": wall,
               "ratios_clearance_over_rigid": ratios,
               "min_wrist_pin_force_rigid_N": {"constant": float(st.constant_rigid.wrist_pin_force.min()),
                                               "designed": float(st.designed_rigid.wrist_pin_force.min())},
               "periodic": {"constant": st.constant.stats.get("periodic"), "designed": st.designed.stats.get("periodic")}}
    (out / "impacts.json").write_text(json.dumps(summary, indent=2, default=float))
    print(f"Impact study, default press with 0.1 mm clearances, T = {summary['period_s']:g} s ({wall:.1f} s)")
    for k, r in ratios.items():
        print(f"  {k:9s} speed: clearance/ideal peak torque x{r['torque']:.2f}, slider normal force "
              f"x{r['slider_normal_force']:.2f}, wrist-pin force x{r['wrist_pin_force']:.2f}")
    print(f"  wrote {out / 'impacts.png'} and {out / 'impacts.json'}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """Entry point."""
    ap = argparse.ArgumentParser(prog="pressocp", description=__doc__)
    ap.add_argument("study", nargs="?", default="design", choices=("design", "impacts"),
                    help="design: rigid speed design of the default scenario (default); impacts: seed Figs. 6 and 9")
    ap.add_argument("--out", type=Path, default=Path("out"), help="output folder (default: out)")
    ap.add_argument("--period", type=float, default=1.0, help="cycle time T, s")
    ap.add_argument("--ram-speed", type=float, default=-0.1, help="ram velocity in the window, m/s (negative)")
    ap.add_argument("--window", type=float, nargs=2, default=(0.7, 0.3), metavar=("H1", "H2"),
                    help="working window h/H at entry and exit on the downstroke")
    args = ap.parse_args(argv)
    if args.study == "impacts":
        return run_impacts(args.out)
    s = run_design(args.out, args.period, args.ram_speed, tuple(args.window))
    print(f"Rigid speed design, default press, T = {s['period_s']:g} s, ram speed {s['ram_speed_m_s']:g} m/s "
          f"over h/H {s['window_h_over_H'][0]:g}→{s['window_h_over_H'][1]:g}")
    print(f"  IPOPT: {s['status']}  ({s['wall_time_s']:.2f} s)")
    print(f"  window t1 = {s['t1_s']:.4f} s, t2 = {s['t2_s']:.4f} s")
    print(f"  ram speed error: max {100 * s['max_rel_ram_speed_error']:.3f} %, RMS {100 * s['rms_rel_ram_speed_error']:.3f} %")
    print(f"  min crank speed {s['min_omega_rad_s']:.3f} rad/s (mean {2 * np.pi / s['period_s']:.3f})")
    print(f"  peak motor torque: constant speed {s['peak_torque_constant_Nm']:.1f} N·m, "
          f"designed {s['peak_torque_designed_Nm']:.1f} N·m")
    print(f"  min wrist-pin force with the design: {s['min_wrist_pin_force_designed_N']:.1f} N")
    print(f"  wrote {args.out / 'design_speed.png'} and {args.out / 'design_speed.json'}")
    return 0 if s["converged"] else 1


if __name__ == "__main__":
    raise SystemExit(main())
