"""What a job writes for a colleague: peak keys for ``summary.json``, the time-series table
(``results.csv``), the before/after table and the plain-text report."""

from __future__ import annotations

import datetime as _dt
import os
import platform
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .drive import MotorCycle
from .io import atomic_write
from .problem import SpeedProblem
from .result import SERIES_UNITS, SimResult
from .units import force_unit, format_force

if TYPE_CHECKING:
    import pandas as pd

#: Loads reported by every job: `SimResult` series -> (summary key stem, label, unit).
LOADS = {
    "torque": ("peak_torque_N_m", "peak motor torque", "N·m"),
    "slider_normal_force": ("peak_slider_normal_force_N", "peak slider normal force", "N"),
    "crank_pin_force": ("peak_crank_pin_force_N", "peak crank-pin force", "N"),
    "wrist_pin_force": ("peak_wrist_pin_force_N", "peak wrist-pin force", "N"),
}


def peak_summary(sim: SimResult, prefix: str = "") -> dict[str, float]:
    """Peak magnitudes of `LOADS`, keyed ``{prefix}peak_torque_N_m`` and so on (N m, N)."""
    return {prefix + key: sim.peak(name) for name, (key, _, _) in LOADS.items()}


#: The suffixes of a journal's eccentricity states (`PressModel.state_names`): the journal centre's
#: x and y from the bearing's centre, m.
ORBIT_SUFFIXES = ("_ex", "_ey")


def journal_orbits(sim: SimResult, state_names: Sequence[str]) -> dict[str, np.ndarray]:
    """The journal centres' x/y eccentricities of a response, by state name (``crank_pin_ex``,
    ``crank_pin_ey``, ...; m), from its states (`SimResult.states`, named by `state_names`, the
    model's `PressModel.state_names`). Empty for a response without states (the ideal press)."""
    if sim.states.shape[0] != len(state_names):
        return {}
    return {name: sim.states[k] for k, name in enumerate(state_names) if name.endswith(ORBIT_SUFFIXES)}


def cycle_table(responses: Mapping[str, SimResult], motors: Mapping[str, MotorCycle] | None = None,
                state_names: Sequence[str] = ()) -> pd.DataFrame:
    """One period of several responses side by side: ``t [s]`` from the first response's start, then
    ``{label} {series} [unit]`` per response (interpolated onto the first one's grid when needed),
    with `state_names` (the model's) each response's journal eccentricities ``{label} crank_pin_ex [m]``
    and so on (`journal_orbits`), and with `motors` (by the same labels) each one's
    ``motor_speed [rad/s]`` and ``motor_torque [N m]``."""
    items = list(responses.items())
    t_ref = items[0][1].t - items[0][1].t[0]
    columns = {"t [s]": t_ref}
    for label, sim in items:
        t = sim.t - sim.t[0]
        same = t.shape == t_ref.shape and np.allclose(t, t_ref, rtol=0.0, atol=1e-12)
        for name, unit in SERIES_UNITS.items():
            if name == "t":
                continue
            values = getattr(sim, name)
            columns[f"{label} {name} [{unit}]"] = values if same else np.interp(t_ref, t, values)
        for name, values in journal_orbits(sim, state_names).items():
            columns[f"{label} {name} [m]"] = values if same else np.interp(t_ref, t, values)
    for label, motor in (motors or {}).items():
        t = motor.t - motor.t[0]
        for name, unit in (("speed", "rad/s"), ("torque", "N m")):
            columns[f"{label} motor_{name} [{unit}]"] = np.interp(t_ref, t, getattr(motor, name))
    import pandas as pd  # 0.5 s to import: only where a table is made

    return pd.DataFrame(columns)


def write_cycle_table(path: str | Path, responses: Mapping[str, SimResult],
                      motors: Mapping[str, MotorCycle] | None = None, state_names: Sequence[str] = ()) -> Path:
    """`cycle_table` as CSV, written atomically."""
    table = cycle_table(responses, motors, state_names)
    return atomic_write(path, table.to_csv(index=False, float_format="%.10g"))


#: The torque row's label when the problem has a drive: its motor has a torque of its own (the motor
#: table's), and the row is the torque at the crank.
CRANK_TORQUE_LABEL = "peak torque at the crank"


def load_table(columns: Sequence[tuple[str, SimResult]], geared: bool = False) -> list[list[str]]:
    """Rows "load | value per column" of the peak `LOADS` of each response; a row of forces in kN when
    its largest is 10 kN or more (`pressocp.units.force_unit`), else in N. `geared`: the problem has a
    drive, and the torque row is labelled `CRANK_TORQUE_LABEL`."""
    rows = [["", *(label for label, _ in columns)]]
    for name, (_, label, unit) in LOADS.items():
        label = CRANK_TORQUE_LABEL if geared and name == "torque" else label
        peaks = [sim.peak(name) for _, sim in columns]
        unit, factor = force_unit(peaks) if unit == "N" else (unit, 1.0)
        digits = 2 if factor != 1.0 else 1
        rows.append([f"{label}, {unit}", *(f"{p * factor:,.{digits}f}" for p in peaks)])
    return rows


def format_table(rows: Sequence[Sequence[str]]) -> str:
    """Plain-text table: first column left-aligned, the others right-aligned."""
    widths = [max(len(str(r[j])) for r in rows) for j in range(len(rows[0]))]
    lines = []
    for r in rows:
        cells = [str(r[0]).ljust(widths[0])] + [str(c).rjust(w) for c, w in zip(r[1:], widths[1:])]
        lines.append("  ".join(cells).rstrip())
    return "\n".join(lines)


def stamp() -> dict[str, str]:
    """When and where a job ran: ISO date-time, machine, its CPU count, platform, Python."""
    return {"date": _dt.datetime.now().isoformat(timespec="seconds"), "machine": platform.node(),
            "cpus": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version()}


def describe_problem(problem: SpeedProblem) -> str:
    """One line: cycle, ram speed and window, objective; the largest process force and the
    counterbalance's force at bottom dead centre when the press has them (`format_force`)."""
    h1, h2 = problem.window
    process, balance = problem.press.process_force, problem.press.counterbalance
    largest = process.peak
    forces = ((f", process force up to {format_force(largest)}" if largest > 0 else "")
              + (f", counterbalance {format_force(balance.force)} at bottom dead centre" if balance.force > 0 else ""))
    return (f"T = {problem.period:g} s ({problem.stroke_rate_spm:g} strokes/min), ram speed "
            f"{problem.ram_speed:g} ± {problem.tol:.3g} m/s over h/H {h1:g} → {h2:g}, "
            f"objective {problem.objective}{forces}")


__all__ = ["LOADS", "ORBIT_SUFFIXES", "cycle_table", "describe_problem", "format_table", "journal_orbits", "load_table", "peak_summary", "stamp", "write_cycle_table"]
