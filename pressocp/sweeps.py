"""Sweeps: one task (optimise, simulate, impacts) over a grid or a path of scenario values, in
parallel over any `concurrent.futures.Executor`, as a pandas table.

    table = po.sweep(po.Scenario.load("press75"),
                     {"wrist_pin.clearance": [5e-5, 1e-4, 2e-4], "problem.stroke_rate_spm": [60, 75]},
                     task="simulate")

Values are named by the scenario's dotted keys (press fields with or without ``press.``; problem,
model and solver keys with their table). A dict of lists is a grid (every combination); a list of
dicts is a path, whose optima are warm-started from their neighbour's (continuation, one after the
other). A grid of optima can be continued along one of its keys (`Continuation`): its lines along
that key are cut into short segments, each solved cold at its first point and warm from there on,
the segments side by side. Points run in worker processes (IPOPT's MUMPS is not thread-safe); a
``dask.distributed`` ``Client.get_executor()`` runs them on a cluster. A point that fails is a row
with its error, not a failed sweep. With ``csv=`` the table is written after every point and a
rerun skips the points already done.
"""

from __future__ import annotations

import itertools
import json
import os
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, Future, wait
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tqdm.auto import tqdm

from . import checks as chk
from . import impacts
from .io import atomic_write
from .model import ModelSpec
from .problem import SpeedProblem
from .scenario import Scenario
from .speed import FourierSpeed
from .summaries import flag_reason, optimum_summary, simulate_speed, simulation_summary
from .workers import process_pool

if TYPE_CHECKING:
    import pandas as pd

#: What a sweep can run at each point.
TASKS = ("optimize", "simulate", "impacts")
#: Columns every row has after the varied values.
BASE_COLUMNS = ("task", "ok", "error", "wall_time_s")


@dataclass(frozen=True)
class Continuation:
    """A grid of optima warm-started along one of its keys.

    The points that differ only in `along` form a line, in the order of its values. Each line is cut
    into segments of `segment` points: the first point of a segment is solved cold, each next one from
    its neighbour's optimum (`Strategy(mode="continue")`, rescaled to its period; cold again when
    that chain fails or the neighbour failed). The segments run side by side. Which optimum each
    point starts from is fixed by the grid, so the table does not depend on the workers.

    On the 75 spm seed, an optimum started from its neighbour at the next wrist-pin clearance (0.05,
    0.1, 0.2, 0.3 mm) took 63-67 s instead of 145 s cold, to the cold optimum within 0.03 %
    (docs/decisions/2026-11-28-sweep-continuation.md). Along the stroke rate continuation did not
    pay: a neighbour's peaks and window fall at other times at another period (docs/measurements.md).

    Attributes
    ----------
    along : str
        A key of the grid (as given in ``vary``).
    segment : int
        Points per segment, 1..10000: 1 solves every point cold; a line's length runs it as one path
        (one after the other).
    """

    along: str
    segment: int = 2

    def __post_init__(self) -> None:
        if not isinstance(self.along, str) or not self.along:
            raise ValueError(f"Continuation.along must name a key of the grid, got {self.along!r}")
        chk.integer("Continuation.segment", self.segment, 1, 10_000)

    def segments(self, points: list[dict]) -> list[list[int]]:
        """Indices of `points` (a grid's, `points_of`) segment by segment, in the order of the grid."""
        if self.along not in points[0]:
            raise ValueError(f"Continuation.along is {self.along!r}, not a key of the grid "
                             f"({', '.join(points[0])})")
        lines: dict[str, list[int]] = {}
        for i, p in enumerate(points):
            lines.setdefault(_key_of({k: v for k, v in p.items() if k != self.along}), []).append(i)
        return [line[j:j + self.segment] for line in lines.values() for j in range(0, len(line), self.segment)]


def points_of(vary: Mapping[str, Sequence] | Sequence[Mapping[str, Any]]) -> tuple[list[dict], bool]:
    """The points of a grid (dict of lists: every combination, the last key varying fastest) or of a
    path (list of dicts, in order), and whether it is a path."""
    if isinstance(vary, Mapping):
        if not vary:
            raise ValueError("vary must name at least one key")
        keys = list(vary)
        for k in keys:
            if isinstance(vary[k], (str, bytes)) or not isinstance(vary[k], Sequence) or len(vary[k]) == 0:
                raise ValueError(f"vary[{k!r}] must be a non-empty list of values, got {vary[k]!r}")
        return [dict(zip(keys, combo)) for combo in itertools.product(*(vary[k] for k in keys))], False
    points = [dict(p) for p in vary]
    if not points or not all(points):
        raise ValueError("a path must be a non-empty list of non-empty dicts of scenario values")
    keys = set(points[0])
    for i, p in enumerate(points):
        if set(p) != keys:
            raise ValueError(f"path point {i} sets {sorted(p)}, point 0 sets {sorted(keys)}: every point must "
                             "set the same keys")
    return points, True


def as_scenario(base: Scenario | SpeedProblem) -> Scenario:
    """A scenario from a scenario or a problem (default model: rigid rod, both clearances)."""
    if isinstance(base, Scenario):
        return base
    if isinstance(base, SpeedProblem):
        return Scenario("sweep", base, ModelSpec())
    raise ValueError(f"base must be a Scenario or a SpeedProblem, got {type(base).__name__}")


def run_point(task: str, scenario: Scenario, speed: FourierSpeed | None = None,
              initial: FourierSpeed | None = None) -> dict:
    """One row: `task` on `scenario` (flat values: peaks, convergence, verification, the speed as JSON).
    Errors are caught into the row (``ok`` False, ``error`` the message); Ctrl-C is not."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {"task": task, "ok": False, "error": ""}
    try:
        if task == "optimize":
            result = scenario.optimize(False, initial=initial, strategy=None if initial is None else
                                       replace(scenario.solver.make_strategy(), mode="continue"))
            summary = optimum_summary(scenario, result)
            row.update(ok=bool(result.success and result.verified), speed=json.dumps(result.speed.to_dict()))
            if not row["ok"]:
                row["error"] = flag_reason(summary)
            if initial is not None:  # a path: did the chain from the neighbour give the answer?
                row["start"] = "cold after the neighbour's chain failed" if any(s.superseded for s in result.stages) \
                    else "neighbour"
        elif task == "simulate":
            from .design import design_speed

            speed = design_speed(scenario.problem).speed if speed is None else speed
            sim, ideal = simulate_speed(scenario, speed)
            summary = simulation_summary(scenario, sim, ideal, "sweep")
            row.update(ok=summary["periodic"] is True, speed=json.dumps(speed.to_dict()))
            if not row["ok"]:
                row["error"] = f"not periodic: {summary['periodic']}"
        else:
            st = impacts.impact_study(scenario.problem, scenario.model, rtol=scenario.solver.verify_rtol)
            summary = {f"{label}_{load}_ratio": r for label, ratios in st.ratios().items()
                       for load, r in ratios.items()}
            missing = st.not_periodic()
            row.update(ok=not missing, speed=json.dumps(st.design.speed.to_dict()),
                       **({"error": "not periodic: " + "; ".join(f"{k}: {v}" for k, v in missing.items())}
                          if missing else {}))
        row.update({k: v for k, v in summary.items() if isinstance(v, (bool, int, float, str))
                    and k not in ("job", "scenario", "speed")})
    except (ValueError, ArithmeticError, RuntimeError) as err:  # solver and model failures: a row
        row["error"] = f"{type(err).__name__}: {str(err).splitlines()[0] if str(err) else ''}"
    row["wall_time_s"] = time.perf_counter() - t0
    return row


def rescale(speed: FourierSpeed, period: float) -> FourierSpeed:
    """The same crank motion per cycle at another period: theta(t) = theta_0(t T0 / T), so omega and
    every coefficient scale by T0 / T (a neighbour's optimum as the start of the next point)."""
    f = speed.period / period
    return FourierSpeed(period, speed.a * f, speed.b * f, speed.theta0)


def _default_executor(n: int) -> Executor:
    """`process_pool` of min(n, CPUs) workers: one native thread each, so n workers use n cores."""
    return process_pool(max(1, min(n, os.cpu_count() or 1)))


def _norm(v: Any) -> Any:
    """A value as compared across a CSV round trip: numbers as floats, lists element-wise."""
    if isinstance(v, (list, tuple)):
        return [_norm(x) for x in v]
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(v)
    return v


def _key_of(values: Mapping[str, Any]) -> str:
    return json.dumps({k: _norm(values[k]) for k in sorted(values)}, sort_keys=True, default=str)


def _done_rows(csv: Path | None, keys: list[str]) -> dict[str, dict]:
    """Rows of an earlier run of the same sweep that succeeded, by their varied values."""
    if csv is None or not csv.exists():
        return {}
    import pandas as pd  # 0.5 s to import: only where a table is made

    old = pd.read_csv(csv)
    if not set(keys) <= set(old.columns):
        raise ValueError(f"{csv} holds another sweep (its columns lack {sorted(set(keys) - set(old.columns))})")
    old = old.astype(object).where(old.notna(), None)
    done = {}
    for row in old.to_dict("records"):
        if str(row.get("ok")) == "True":
            done[_key_of({k: _plain(row[k]) for k in keys})] = row
    return done


def _plain(v: Any) -> Any:
    """CSV cells read back as the values written (lists were written as JSON)."""
    if isinstance(v, str) and v.startswith("["):
        return json.loads(v)
    return v


def sweep(base: Scenario | SpeedProblem, vary: Mapping[str, Sequence] | Sequence[Mapping[str, Any]],
          task: str = "optimize", speed: FourierSpeed | None = None, executor: Executor | None = None,
          progress: bool = True, *, csv: str | Path | None = None,
          continuation: bool | Continuation = True) -> pd.DataFrame:
    """Run `task` at every point of `vary` and tabulate.

    Parameters
    ----------
    base : Scenario or SpeedProblem
        The values not varied.
    vary : dict of lists, or list of dicts
        A grid (every combination) or a path (in order; with `continuation`, optima warm-started from
        their neighbour's, one after the other). Keys are dotted scenario keys: ``"wrist_pin.clearance"`` (m),
        ``"slider_mass"`` (kg), ``"problem.stroke_rate_spm"``, ``"problem.ram_speed"`` (m/s), ...
    task : {"optimize", "simulate", "impacts"}
        What each point runs: `optimize_speed` (verified optimum), the periodic response of `speed`
        (default: each point's kinematic design), or the impact study (constant and designed speed).
    speed : FourierSpeed, optional
        The speed a "simulate" sweep evaluates at every point (its period must be each point's).
    executor : concurrent.futures.Executor, optional
        Where the points run; default a process pool with one worker per core (at most one per
        point). ``Client.get_executor()`` of ``dask.distributed`` runs them on a cluster. The
        executor is not shut down.
    progress : bool
        A tqdm bar over the points.
    csv : path, optional
        Write the table there after every point (atomically) and skip the points that an earlier
        run wrote with ``ok`` True.
    continuation : bool or Continuation
        Along a path of optima, start each from its neighbour's (True) or run the points as
        independent cold starts in parallel, like a grid (False: a path is then just a list of points,
        e.g. both clearances varied together). A `Continuation` warm-starts a grid of optima along
        one of its keys; True or False leave a grid's points cold.

    Returns
    -------
    pandas.DataFrame
        One row per point, in the order of the points: the varied values, ``task``, ``ok``
        (converged and verified / periodic), ``error`` (empty unless the point failed), the peaks and
        the other summary values of the task, ``speed`` (JSON of `FourierSpeed.to_dict`) and
        ``wall_time_s``.

    Raises
    ------
    ValueError, ScenarioError
        A bad point, task or speed, before anything runs.
    KeyboardInterrupt
        Ctrl-C: the points done are in `csv` (when given); pending ones are cancelled.
    """
    points, is_path, segments, scenarios = _checked(base, vary, task, speed, continuation)
    keys = list(points[0])
    csv = None if csv is None else Path(csv)
    done = _done_rows(csv, keys)
    rows: dict[int, dict] = {i: {**done[_key_of(p)], **p} for i, p in enumerate(points) if _key_of(p) in done}
    todo = [i for i in range(len(points)) if i not in rows]
    bar = tqdm(total=len(points), initial=len(rows), desc=f"sweep ({task})", disable=not progress)

    def record(i: int, row: dict) -> None:
        rows[i] = {**points[i], **row}
        bar.update(1)
        if csv is not None:
            atomic_write(csv, _table(rows, keys).to_csv(index=False))

    try:
        if segments is None and is_path and task == "optimize" and continuation:  # each from its neighbour
            run_path(scenarios, rows, executor, record)
        elif todo:  # a grid: segments of a continuation, or every point on its own
            run_segments(task, scenarios, [[i] for i in todo] if segments is None else segments, rows, speed,
                         executor, record)
    finally:
        bar.close()
    return _table(rows, keys)


def _checked(base: Scenario | SpeedProblem, vary: Mapping[str, Sequence] | Sequence[Mapping[str, Any]], task: str,
             speed: FourierSpeed | None, continuation: bool | Continuation
             ) -> tuple[list[dict], bool, list[list[int]] | None, list[Scenario]]:
    """`sweep`'s input checked before anything runs: its points, whether they are a path, the
    segments of a `Continuation` (None without one) and every point's scenario."""
    if task not in TASKS:
        raise ValueError(f"task must be one of {', '.join(TASKS)}; got {task!r}")
    scenario = as_scenario(base)
    points, is_path = points_of(vary)
    segments = None
    if isinstance(continuation, Continuation):
        if is_path or task != "optimize":
            raise ValueError(f"a Continuation warm-starts a grid of optima; this sweep is a "
                             f"{'path' if is_path else 'grid'} of task {task!r} (a path of optima is "
                             "continued with continuation=True)")
        segments = continuation.segments(points)
    scenarios = [scenario.with_overrides(p) for p in points]  # every point checked before any solve
    if speed is not None:
        if task != "simulate":
            raise ValueError(f"speed is the speed a simulate sweep evaluates; task is {task!r}")
        for p, s in zip(points, scenarios):
            s.check_speed(speed, f"speed (point {p})")
    return points, is_path, segments, scenarios


def speed_of(row: dict) -> FourierSpeed | None:
    """The optimum of a row that succeeded (the next point's start), else None."""
    return FourierSpeed.from_dict(json.loads(row["speed"])) if row.get("ok") and row.get("speed") else None


def start_for(previous: FourierSpeed | None, scenario: Scenario) -> FourierSpeed | None:
    """A neighbour's optimum as `scenario`'s start: rescaled to its period; None when there is none
    or it has more harmonics than the scenario's problem."""
    start = None if previous is None else rescale(previous, scenario.problem.period)
    return None if start is not None and start.n_harmonics > scenario.problem.n_harmonics else start


def run_path(scenarios: list[Scenario], rows: dict[int, dict], executor: Executor | None,
             record: Callable[[int, dict], None]) -> None:
    """The optima of a path of `scenarios`, one after the other, each started from its neighbour's
    answer (rescaled to its period), in `executor` or here; the points already in `rows` are skipped
    (their speed is the next one's start); each new row goes to `record`."""
    previous = None
    for i, scenario in enumerate(scenarios):
        if i in rows:
            previous = speed_of(rows[i])
            continue
        start = start_for(previous, scenario)
        row = (executor.submit(run_point, "optimize", scenario, None, start).result() if executor is not None
               else run_point("optimize", scenario, None, start))
        record(i, row)
        previous = speed_of(row) or previous


def run_segments(task: str, scenarios: list[Scenario], segments: list[list[int]], rows: dict[int, dict],
                 speed: FourierSpeed | None, executor: Executor | None,
                 record: Callable[[int, dict], None]) -> None:
    """`task` at `scenarios` segment by segment, the segments side by side (one point each: a plain
    grid; `Continuation.segments`: optima continued). Every segment's first open point is submitted
    at once, and each next point when its neighbour's row arrives, started from that neighbour's
    optimum (cold when the neighbour failed). Points already in `rows` are skipped (their speed
    starts the next one). In `executor` or in a process pool of its own (shut down at the end); each
    row goes to `record` as it arrives; an exception (Ctrl-C included) cancels the points not
    started."""
    own = executor is None
    pool = _default_executor(sum(any(i not in rows for i in seg) for seg in segments)) if own else executor
    pending: dict[Future, tuple[list[int], int]] = {}

    def submit(segment: list[int], k: int, previous: FourierSpeed | None) -> None:
        while k < len(segment) and segment[k] in rows:  # done in an earlier run
            previous = speed_of(rows[segment[k]])
            k += 1
        if k < len(segment):
            scenario = scenarios[segment[k]]
            pending[pool.submit(run_point, task, scenario, speed, start_for(previous, scenario))] = (segment, k)

    try:
        for segment in segments:
            submit(segment, 0, None)
        while pending:
            done, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            for fut in done:
                segment, k = pending.pop(fut)
                row = fut.result()
                record(segment[k], row)
                submit(segment, k + 1, speed_of(row))
    except BaseException:
        for f in pending:
            f.cancel()
        raise
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)


def _table(rows: dict[int, dict], keys: list[str]) -> pd.DataFrame:
    import pandas as pd  # 0.5 s to import: only where a table is made

    frame = pd.DataFrame([rows[i] for i in sorted(rows)])
    first = [*keys, *BASE_COLUMNS]
    return frame[[c for c in first if c in frame] + [c for c in frame if c not in first]]


__all__ = ["TASKS", "Continuation", "as_scenario", "points_of", "rescale", "run_point", "sweep"]
