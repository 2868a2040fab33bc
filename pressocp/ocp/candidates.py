"""Candidate chains: a chain from several starts, side by side, the best verified kept.

Where a model with states' local optimum lands depends on its start, and no one start is best
everywhere (75 spm seed, `docs/decisions/2026-11-25-candidate-starts.md`; the slender rod,
`docs/decisions/2026-11-27-flexible-starts.md`). So the clearance chain is run from each
no-reversal start (`Strategy.tension_margin`, one margin per candidate), and the flexible chain of a
rod between ideal joints from the rigid optimum at each ram-speed backoff
(`Strategy.flexible_backoffs`); each candidate's answer is re-simulated at the strategy's tolerance,
and the lowest verified objective (periodic, ram speed in tolerance, no limit exceeded) wins.
Candidates run in spawned worker processes (`pressocp.workers`), two at a time on two cores; IPOPT
is not safe in threads.
"""

from __future__ import annotations

import warnings
from concurrent.futures import Executor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import replace
from typing import TYPE_CHECKING, Callable

import numpy as np

from ..model import ModelSpec
from ..problem import SpeedProblem
from ..workers import parallel_workers, process_pool
from .stage import PAUSED, StageResult, Transcription
from ..verify import unverified_reason

if TYPE_CHECKING:
    from .strategy import Strategy


def candidate_chain(strategy: "Strategy", problem: SpeedProblem, base: ModelSpec, rigid: StageResult,
                    transcription: Transcription, margin: float, suffix: str,
                    progress: bool = False) -> list[StageResult]:
    """One candidate: `Strategy.clearance_chain` on the rigid-rod model `base` from the no-reversal start
    at `margin`, its answer verified (`Strategy.verify_stage`), its stages named with `suffix`. Runs
    in a worker process too (the model is built from its spec there), so its stages carry no solver
    objects."""
    model = base.build(problem.press, problem.n_harmonics)
    stages = strategy.clearance_chain(problem, model, rigid, transcription, None, progress, margin, candidate=True)
    return verified_and_named(strategy, model, stages, suffix)


def flexible_candidate(strategy: "Strategy", problem: SpeedProblem, spec: ModelSpec, start: StageResult,
                       transcription: Transcription, suffix: str, progress: bool = False) -> list[StageResult]:
    """One candidate on a flexible rod between ideal joints: `Strategy.flexible_chain` on the model
    `spec` from the rigid optimum `start`, its answer verified, its stages named with `suffix`. Runs in
    a worker process too (the model is built there)."""
    model = spec.build(problem.press, problem.n_harmonics)
    stages = strategy.flexible_chain(problem, model, start, transcription, progress, candidate=True)
    return verified_and_named(strategy, model, stages, suffix)


def run_flexible_candidates(strategy: "Strategy", problem: SpeedProblem, spec: ModelSpec, starts: list[StageResult],
                            transcription: Transcription, progress: bool,
                            pool: Executor | None = None) -> list[StageResult]:
    """`flexible_candidate` from each rigid optimum of `starts` (the rigid stage first, then its
    re-solves ``rigid@b``), in `pool` or new worker processes as `run_candidates`; their stages, the
    best candidate's last, each suffixed with its start's backoff."""
    backoffs = [st.details["backoff"] for st in starts]
    suffixes = [f"@{b:g}" for b in backoffs]
    args = [(strategy, problem, spec, replace(st, point=None, nlp=None), transcription, sfx)
            for st, sfx in zip(starts, suffixes)]
    labels = [f"{b:g}" for b in backoffs]
    early = EarlyResume(strategy, problem, spec, progress)
    chains = _in_workers(flexible_candidate, args, strategy.workers, progress,
                         f"candidates (flexible stage from the rigid optima at backoffs {', '.join(labels)})",
                         pool, early)
    return keep_best(polished_best(strategy, problem, spec, chains, labels, progress, early.resumed), labels, problem)


def verified_and_named(strategy: "Strategy", model, stages: list[StageResult], suffix: str) -> list[StageResult]:
    """A candidate's `stages` with the last one's answer verified on `model` (`Strategy.verify_stage`)
    when it converged, each named with `suffix` and without solver objects (for the worker's reply)."""
    last = stages[-1]
    if last.success and not last.was_skipped:
        strategy.verify_stage(model, last)
    return [replace(s, name=s.name + suffix, point=None) for s in stages]


def verified_value(stage: StageResult, problem: SpeedProblem) -> float:
    """The objective of a candidate's answer on its re-simulation when the stage converged and that
    re-simulation verifies it (periodic, the ram speed in tolerance, no limit exceeded:
    `unverified_reason`); +inf otherwise."""
    sim = stage.simulation
    if not stage.success or sim is None or unverified_reason(problem, stage.speed, sim):
        return float("inf")
    return problem.objective_value(sim)


def run_candidates(strategy: "Strategy", problem: SpeedProblem, base: ModelSpec, rigid: StageResult,
                   transcription: Transcription, margins: tuple[float, ...], progress: bool,
                   pool: Executor | None = None) -> list[StageResult]:
    """Every candidate chain (`candidate_chain`), in `pool` (default: ``strategy.workers`` new processes;
    here, one after the other, with one worker or when the pool breaks), then their stages: the
    candidates not kept first (marked ``superseded`` with their verified value), the best last. Each
    candidate's last stage records ``details["candidate_value"]``; the best one's also
    ``details["candidates"]``, every margin's verified value.

    A candidate whose no-reversal stage does not converge ends there: the target stage it would run
    from the rigid optimum can take minutes without converging while the others' answers wait
    (measured: `docs/decisions/2026-11-26-blas-threads.md`). When every candidate ends so, that chain
    from the rigid optimum runs once, here (its stages unsuffixed)."""
    suffixes = [f"@{m:g}" for m in margins]
    rigid = replace(rigid, point=None)  # no solver objects into the workers
    args = [(strategy, problem, base, rigid, transcription, m, sfx) for m, sfx in zip(margins, suffixes)]
    labels = [f"{m:g}" for m in margins]
    early = EarlyResume(strategy, problem, base, progress)
    chains = _in_workers(candidate_chain, args, strategy.workers, progress,
                         f"candidates (tension margins {', '.join(labels)})", pool, early)
    if all(len(c) == 1 and not c[0].success for c in chains):  # no candidate got past its no-reversal stage
        model = base.build(problem.press, problem.n_harmonics)
        note = "candidate ended: its no-reversal stage did not converge, as every candidate's did"
        return [*(replace(c[0], superseded=note) for c in chains),
                *strategy.clearance_chain(problem, model, rigid, transcription, None, progress, None)]
    return keep_best(polished_best(strategy, problem, base, chains, labels, progress, early.resumed), labels, problem)


class EarlyResume:
    """`_run`'s ``returned`` for candidate chains in worker processes: a chain that returns paused
    (`PAUSED`) with an answer no higher than every chain returned so far resumes its polish here at
    once (`Strategy.resume_polish`), while the others still run: by the time they have all returned,
    it is most often the best, and its rounds have overlapped theirs. At most one chain resumes
    early; `polished_best` keeps its rounds only if it is the best once every chain has returned, so
    the answer is that of waiting for all of them. ``resumed``: (index, the resumed stages) or None."""

    def __init__(self, strategy: "Strategy", problem: SpeedProblem, spec: ModelSpec, progress: bool):
        self.strategy, self.problem, self.spec, self.progress = strategy, problem, spec, progress
        self.values: dict[int, float] = {}
        self.resumed: tuple[int, list[StageResult]] | None = None

    def __call__(self, k: int, chain: list[StageResult]) -> None:
        self.values[k] = verified_value(chain[-1], self.problem)
        if self.resumed is None and PAUSED in chain[-1].details and self.values[k] <= min(self.values.values()):
            self.resumed = (k, resumed_rounds(self.strategy, self.problem, self.spec, chain, self.progress))


def resumed_rounds(strategy: "Strategy", problem: SpeedProblem, spec: ModelSpec, chain: list[StageResult],
                   progress: bool) -> list[StageResult]:
    """The rest of the paused `chain`'s rounds (`Strategy.resume_polish` on its model rebuilt from
    `spec`), verified and named with the chain's suffix (`verified_and_named`)."""
    model = spec.build(problem.press, problem.n_harmonics)
    suffix = chain[-1].name[chain[-1].name.rindex("@"):]
    more = strategy.resume_polish(problem, model, chain, progress)
    return verified_and_named(strategy, model, more, suffix) if more else []


def polished_best(strategy: "Strategy", problem: SpeedProblem, spec: ModelSpec, chains: list[list[StageResult]],
                  labels: list[str], progress: bool,
                  resumed: tuple[int, list[StageResult]] | None = None) -> list[list[StageResult]]:
    """`chains` with the polish resumed on the best one: a chain that paused after its first polish
    round (`Strategy.rounds`, its last stage marked `PAUSED`) polishes further (`resumed_rounds`)
    only when its answer is the lowest verified of all chains' (`verified_value`); every other paused
    chain ends there, saying so in its last stage's ``details["polish_ended"]``. `resumed`: a chain
    already resumed before every chain had returned (`EarlyResume`), its index and stages: kept when
    it is that best one, else recorded as not kept. So the answer does not depend on which worker
    finished first."""
    values = [verified_value(c[-1], problem) for c in chains]
    best = int(np.argmin(values)) if np.isfinite(values).any() else None
    out = []
    for k, chain in enumerate(chains):
        last = chain[-1]
        early = resumed[1] if resumed is not None and resumed[0] == k else None
        if PAUSED not in last.details:
            out.append(chain)
            continue
        if k == best:
            more = early if early is not None else resumed_rounds(strategy, problem, spec, chain, progress)
            last.details.pop(PAUSED)
            out.append(chain + more)
            continue
        last.details.pop(PAUSED)
        last.details["polish_ended"] = (
            f"after its first polish round its answer re-simulates at {values[k]:.6g}, above candidate "
            f"{labels[best]}'s {values[best]:.6g}: only the lowest verified candidate polishes further "
            "(Strategy.polish_candidates)")
        if early is not None:  # resumed while the best one still ran: not kept, its cost recorded
            last.details["polish_ended"] += (
                f"; it had resumed before every candidate returned ({len(early)} stages, "
                f"{sum(st.wall_time for st in early):.1f} s, not kept)")
        out.append(chain)
    return out


def keep_best(chains: list[list[StageResult]], labels: list[str], problem: SpeedProblem) -> list[StageResult]:
    """The candidates' stages: those not kept first (marked ``superseded`` with their verified value),
    the best last. Each candidate's last stage records ``details["candidate_value"]``; the best one's
    also ``details["candidates"]``, every label's verified value."""
    values = [verified_value(c[-1], problem) for c in chains]
    best = int(np.argmin(values)) if np.isfinite(values).any() else _least_failed(chains)
    out: list[StageResult] = []
    for k, chain in enumerate(chains):
        chain[-1].details["candidate_value"] = values[k]
        if k == best:
            continue
        note = (f"candidate not kept: its answer re-simulates at {values[k]:.6g} against {values[best]:.6g}"
                if np.isfinite(values[k]) else "candidate not kept: its answer is not verified")
        out += [replace(s, superseded=s.superseded or note) for s in chain]
    chains[best][-1].details["candidates"] = dict(zip(labels, values))
    return out + chains[best]


def _in_workers(fn, args: list[tuple], workers: int, progress: bool, desc: str,
                pool: Executor | None, returned: Callable[[int, list[StageResult]], None] | None = None
                ) -> list[list[StageResult]]:
    """`_run` of `fn` over `args` on min(`workers`, candidates) processes, with a tqdm bar of `desc`
    (`returned`: as `_run`'s)."""
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(args), desc=desc, unit="chain", leave=True)
    try:
        return _run(fn, args, min(parallel_workers(workers), len(args)), bar, pool, returned)
    finally:
        if bar is not None:
            bar.close()


def _least_failed(chains: list[list[StageResult]]) -> int:
    """With no verified candidate: the one whose chain went furthest (most stages), else the first."""
    return int(np.argmax([len(c) for c in chains]))


def _run(fn, args: list[tuple], workers: int, bar, pool: Executor | None,
         returned: Callable[[int, list[StageResult]], None] | None = None) -> list[list[StageResult]]:
    """`fn` (a candidate chain) over `args`, in order; in `pool`, or a new process pool when
    ``workers > 1`` (shut down afterwards; a given pool is the caller's). In a pool, `returned` is
    called with each chain's index and stages as it returns, while the others still run."""
    def done(chain):
        if bar is not None:
            bar.update(1)
        return chain

    def collected(futures) -> list[list[StageResult]]:
        chains: list = [None] * len(futures)
        index = {f: k for k, f in enumerate(futures)}
        for f in as_completed(futures):
            k = index[f]
            chains[k] = done(f.result())
            if returned is not None:
                returned(k, chains[k])
        return chains

    if pool is not None:
        return collected([pool.submit(fn, *a) for a in args])
    if workers > 1:
        pool = process_pool(workers)
        try:
            return collected([pool.submit(fn, *a) for a in args])
        except BrokenProcessPool as err:  # e.g. a script that starts solving on import, with no main guard
            warnings.warn(f"the candidate chains' worker processes stopped ({err}); running them here one after "
                          "the other. A script that optimises should do so under `if __name__ == '__main__':`",
                          RuntimeWarning, stacklevel=4)
        finally:
            pool.shutdown(wait=False, cancel_futures=True)
    return [done(fn(*a)) for a in args]
