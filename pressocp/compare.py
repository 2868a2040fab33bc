"""``pressocp compare A B``: two designs side by side, to compare two speeds, two presses or two
motors. Each side is a results folder (written by ``optimize``, ``simulate`` or ``design``: its
``summary.json`` and ``results.csv``), a scenario (a bundled name or a TOML file: its rigid speed
design simulated on its model, the ``simulate`` job, into a temporary folder) or a speed file
(``speed.json`` or ``result.json``, simulated on the ``--scenario``).

The table holds every sizing figure both summaries have (the peaks, the crank's RMS torque from
``results.csv``, the ram speed error, and with a drive on both sides the motor's figures), with the
ratio B/A; the figures overlay the cycles against the crank angle and, with a drive on both sides,
the motor's operating points."""

from __future__ import annotations

import json
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .drive import Drive
from .io import SUMMARY_NAME, RunMismatch, atomic_write, check_run_file
from .jobs import read_speed, simulate_job
from .plots import plot_compared_cycles, plot_operating_points, save
from .report import format_table
from .scenario import Scenario, ScenarioError
from .speed import FourierSpeed
from .units import force_unit

if TYPE_CHECKING:
    import pandas as pd

#: The label of the compared response in ``results.csv`` and in the ``drive`` block, by job.
JOB_LABELS = {"optimize": "optimum", "simulate": "speed", "design": "design"}
#: The crank-side sizing figures: summary key -> (label, SI unit). ``rms_torque_N_m`` is computed
#: from ``results.csv`` (the summaries do not hold it).
FIGURES = {
    "peak_torque_N_m": ("peak crank torque", "N m"),
    "rms_torque_N_m": ("RMS crank torque", "N m"),
    "rigid_peak_torque_N_m": ("rigid-press floor of the peak torque", "N m"),
    "peak_slider_normal_force_N": ("peak slider normal force", "N"),
    "peak_crank_pin_force_N": ("peak crank-pin force", "N"),
    "peak_wrist_pin_force_N": ("peak wrist-pin force", "N"),
    "min_crank_pin_eccentricity": ("smallest crank-pin |e|/c", "-"),
    "min_wrist_pin_eccentricity": ("smallest wrist-pin |e|/c", "-"),
    "max_ram_speed_error": ("max ram speed error in the window", "-"),
    "stroke_rate_spm": ("stroke rate", "strokes/min"),
}
#: The motor's figures (`MotorCycle.summary`), prefixed ``motor_`` in the table: key -> (label, unit).
DRIVE_FIGURES = {
    "peak_torque": ("peak motor torque", "N m"),
    "rms_torque": ("RMS motor torque", "N m"),
    "peak_torque_margin": ("margin to the peak curve", "-"),
    "rms_margin": ("margin to the continuous rating", "-"),
    "max_speed": ("motor top speed", "rad/s"),
    "speed_margin": ("margin to the top speed", "-"),
    "inertia_ratio": ("load / motor inertia", "-"),
    "peak_power": ("peak power", "W"),
    "energy_driving": ("energy per stroke out", "J"),
    "energy_regenerated": ("energy per stroke back", "J"),
    "energy_drawn": ("energy drawn per stroke", "J"),
    "bus_energy_swing": ("DC-bus energy swing", "J"),
    "gear_losses": ("gear losses per stroke", "J"),
}
#: The files `compare` writes into its folder.
COMPARE_FILES = ("compare.csv", "compare.png", "motor.png", "report.txt")


class CompareError(ValueError):
    """A bad argument of ``pressocp compare``: the message names it (exit code 2)."""


@dataclass
class Design:
    """One side of a comparison.

    Attributes
    ----------
    name : str
        The argument it came from.
    summary : dict
        Its ``summary.json``.
    results : pandas.DataFrame
        Its ``results.csv`` (one cycle, SI, headers with units).
    label : str
        The compared response's label in both (`JOB_LABELS`).
    """

    name: str
    summary: dict
    results: pd.DataFrame
    label: str

    def series(self, name: str) -> np.ndarray | None:
        """A series of the compared response from ``results.csv`` (SI), None when the file lacks it."""
        column = next((c for c in self.results.columns if c.startswith(f"{self.label} {name} [")), None)
        return None if column is None else self.results[column].to_numpy(float)

    def drive(self) -> Drive | None:
        """The drive of its summary's ``drive`` block, None without one."""
        block = self.summary.get("drive")
        if not isinstance(block, dict):
            return None
        return Drive(**{f.name: block[f.name] for f in fields(Drive) if f.name in block})

    def figures(self) -> dict[str, float]:
        """Its sizing figures by table key (`FIGURES`, and ``motor_...`` from `DRIVE_FIGURES`), SI."""
        out = {k: float(self.summary[k]) for k in FIGURES
               if isinstance(self.summary.get(k), (int, float)) and not isinstance(self.summary.get(k), bool)}
        t, torque = self.series_time(), self.series("torque")
        if t is not None and torque is not None and t[-1] > t[0]:
            from scipy.integrate import trapezoid  # 1 s to import: only where runs are compared

            out["rms_torque_N_m"] = float(np.sqrt(trapezoid(torque**2, t) / (t[-1] - t[0])))
        cycle = (self.summary.get("drive") or {}).get(self.label)
        if isinstance(cycle, dict):
            out.update({f"motor_{k}": float(cycle[k]) for k in DRIVE_FIGURES if k in cycle})
        return out

    def series_time(self) -> np.ndarray | None:
        """The time column of ``results.csv``, s."""
        return self.results["t [s]"].to_numpy(float) if "t [s]" in self.results else None


def load_results(folder: Path, which: str, name: str | None = None) -> Design:
    """The `Design` of a results folder; `CompareError` naming the argument `which` ("A" or "B")
    when it is not one (no summary.json or results.csv, a job not compared, files changed after
    the run)."""
    name = str(folder) if name is None else name
    for needed in (SUMMARY_NAME, "results.csv"):
        if not (folder / needed).is_file():
            raise CompareError(f"{which} {name}: not a results folder of pressocp optimize or simulate (no {needed})")
    try:
        check_run_file(folder / SUMMARY_NAME)
        check_run_file(folder / "results.csv")
        summary = json.loads((folder / SUMMARY_NAME).read_text(encoding="utf-8"))
        import pandas as pd  # 0.5 s to import: only where a table is made

        results = pd.read_csv(folder / "results.csv")
    except RunMismatch as err:
        raise CompareError(f"{which} {name}: {err}") from None
    except (ValueError, UnicodeDecodeError) as err:
        raise CompareError(f"{which} {name}: unreadable results ({err})") from None
    job = summary.get("job") if isinstance(summary, dict) else None
    if job not in JOB_LABELS:
        raise CompareError(f"{which} {name}: a {job!r} job's folder; compare reads the folders of "
                           f"{', '.join(JOB_LABELS)}")
    return Design(name, summary, results, JOB_LABELS[job])


def simulated(scenario: Scenario, folder: Path, which: str, name: str, speed: FourierSpeed | None = None,
              source: str = "rigid design") -> Design:
    """`speed` (default the scenario's rigid design) simulated on the scenario's model into `folder`
    (the ``simulate`` job), as a `Design` named `name`."""
    folder.mkdir(parents=True, exist_ok=True)
    simulate_job(scenario, folder, speed, source)
    return load_results(folder, which, name)


def prepare(arg: str, which: str, scenario: Scenario, overrides: dict | None = None) -> Callable[[Path], Design]:
    """Check one argument before anything is simulated and return what makes its `Design` from a
    work folder: a results folder as it is; a speed file (``.json``) simulated on `scenario`; a
    scenario (a bundled name or a TOML file, with `overrides`), its rigid design simulated, into
    ``workdir/which``. `CompareError` names `which` ("A" or "B") and the argument."""
    path = Path(arg)
    if path.is_dir():
        design = load_results(path, which, arg)
        return lambda workdir: design
    if path.suffix == ".json":
        try:
            speed = read_speed(path)
            scenario.check_speed(speed, arg)
        except (ValueError, ScenarioError) as err:
            raise CompareError(f"{which} {arg}: {str(err).removeprefix('--speed: ')}") from None
        return lambda workdir: simulated(scenario, workdir / which, which, arg, speed, arg)
    if not path.exists() and path.suffix not in ("", ".toml"):
        raise CompareError(f"{which} {arg}: no such results folder, speed file or scenario")
    try:
        own = Scenario.load(arg)
        own = own.with_overrides(overrides) if overrides else own
    except ScenarioError as err:
        raise CompareError(f"{which} {arg}: not a results folder, a speed file (.json) or a scenario: {err}") from None
    return lambda workdir: simulated(own, workdir / which, which, arg)


def compare_table(a: Design, b: Design) -> pd.DataFrame:
    """Every sizing figure both designs have, in SI: columns ``figure`` (the key), ``label``,
    ``unit``, ``A``, ``B`` and ``B/A`` (NaN where A is 0)."""
    fa, fb = a.figures(), b.figures()
    labels = {**FIGURES, **{f"motor_{k}": v for k, v in DRIVE_FIGURES.items()}}
    rows = [{"figure": k, "label": label, "unit": unit, "A": fa[k], "B": fb[k],
             "B/A": fb[k] / fa[k] if fa[k] != 0 else np.nan}
            for k, (label, unit) in labels.items() if k in fa and k in fb]
    import pandas as pd  # 0.5 s to import: only where a table is made

    return pd.DataFrame(rows, columns=["figure", "label", "unit", "A", "B", "B/A"])


def table_text(table: pd.DataFrame, a: Design, b: Design) -> str:
    """The table as text: forces in kN from 10 kN (`force_unit`, one unit per row), margins and the
    ram speed error in %, the rest in SI."""
    rows = [["", f"A: {a.name}", f"B: {b.name}", "B/A"]]
    for r in table.itertuples(index=False):
        unit, factor, fmt = r.unit, 1.0, "{:.4g}"
        if unit == "N":
            unit, factor = force_unit(r.A, r.B)
            fmt = "{:,.2f}" if factor != 1.0 else "{:,.1f}"
        elif unit == "-" and ("margin" in r.figure or "error" in r.figure):
            unit, factor, fmt = "%", 100.0, "{:+.2f}" if "margin" in r.figure else "{:.2f}"
        label = r.label if unit == "-" else f"{r.label}, {unit}"
        ratio = "" if np.isnan(r[5]) else f"{r[5]:.3f}"
        rows.append([label, fmt.format(r.A * factor), fmt.format(r.B * factor), ratio])
    return format_table(rows)


def cycle_of(design: Design) -> dict[str, np.ndarray]:
    """The compared response's series that `plot_compared_cycles` draws (SI)."""
    names = ("theta", "torque", "ram_velocity", "crank_pin_force", "wrist_pin_force")
    return {n: v for n in names if (v := design.series(n)) is not None}


def write_figures(out: Path, a: Design, b: Design) -> list[Path]:
    """compare.png (the cycles against the crank angle) and, when both have a drive and motor
    columns, motor.png (the operating points over the drives' envelopes)."""
    sides = [(f"A: {a.name}", a), (f"B: {b.name}", b)]
    files = [save(plot_compared_cycles([(label, cycle_of(d)) for label, d in sides]), out / "compare.png")]
    points = [(label, d.drive(), d.series("motor_speed"), d.series("motor_torque")) for label, d in sides]
    if all(drive is not None and speed is not None and torque is not None for _, drive, speed, torque in points):
        files.append(save(plot_operating_points(points), out / "motor.png"))
    return files


def compare(a: Design, b: Design, out: Path) -> tuple[pd.DataFrame, str, list[Path]]:
    """Write compare.csv (SI), the figures and report.txt into `out`; return the table, its text and
    the files."""
    table = compare_table(a, b)
    text = "\n".join([f"A: {a.name} ({_what(a)})", f"B: {b.name} ({_what(b)})", "", table_text(table, a, b)])
    files = [atomic_write(out / "compare.csv", table.to_csv(index=False, float_format="%.10g")),
             *write_figures(out, a, b), atomic_write(out / "report.txt", text + "\n")]
    return table, text, files


def _what(design: Design) -> str:
    """A short description of a side: its job, scenario, model and speed."""
    s = design.summary
    parts = [s.get("job"), s.get("scenario"), s.get("model"), s.get("speed")]
    return "; ".join(str(p) for p in parts if p)


def run_compare(make_a: Callable[[Path], Design], make_b: Callable[[Path], Design],
                out: Path) -> tuple[pd.DataFrame, str, list[Path]]:
    """Make both sides (`prepare`; scenarios and speed files simulated in a temporary folder) and
    write the comparison into `out` (a folder that exists)."""
    with tempfile.TemporaryDirectory(prefix="pressocp-compare-") as tmp:
        return compare(make_a(Path(tmp)), make_b(Path(tmp)), out)


__all__ = ["COMPARE_FILES", "CompareError", "DRIVE_FIGURES", "Design", "FIGURES", "compare", "compare_table",
           "load_results", "prepare", "run_compare"]
