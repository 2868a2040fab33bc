"""`optimize_speed`: the model hierarchy applied to optimisation.

Stages, each warm-starting the next:

1. ``rigid``: the ideal press, exact Hessian, closed form (`solve_rigid`). Its optimum is the floor.
   It is re-simulated on the clearance model; when it impacts there (the joint forces reverse):
1b. ``no_reversal``: the ideal press again, with the rod tension at both pins kept above
   ``tension_margin`` x the hanging weight (`SpeedProblem.min_tension`), warm-started from the
   rigid optimum. Without a force reversal the journals stay on their bearings, so its optimum
   is impact-free by construction; it is re-simulated on the clearance model too.
2. ``soft``: the clearance model with a softer, more damped contact (``soft_factor``), multiple
   shooting (`solve_shooting`), node states from a simulation of the previous stage's speed.
3. ``target``: the clearance model as given.
4. ``flexible``: when the model's rod is flexible, the same problem on it.
5. ``refine_k`` (opt-in, ``refine_rounds``): trust-region rounds of shooting on the clearance model
   from the answer so far (`solve_shooting` with ``coefficient_step``, a few IPOPT iterations each);
   a round's final iterate is kept only when its periodic re-simulation lowers the objective with
   the ram speed in tolerance. Slow (minutes per round) but every accepted step is verified.

With ``method="collocation"``, stages 3 and 4 are Radau collocation (`solve_collocation`) with the
journals kept on their bearing walls (``min_eccentricity``): a contact-keeping start (the
no-reversal optimum) needs no soft stage, and every iterate is a smooth response the elements
resolve, so the solve converges on the clearance model (measured on the seed case; see the README).

The optimum is then re-simulated with `simulate(..., periodic=True)` at ``verify_rtol`` on a fine
grid; ``peak_torque``, the ram-speed violation and ``simulation`` come from that run, not from the
optimiser's samples.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from .. import _checks as chk
from ..design import design_speed
from ..model import PressModel, build_model
from ..params import PressParams
from ..rigid import rigid_inverse_dynamics, rigid_response
from ..simulate import SimulationError, periodic_state, simulate
from ..speed import DEFAULT_HARMONICS, FourierSpeed
from .problem import SpeedProblem
from .result import OcpResult
from .collocation import CollocationGrid, collocation_defect, collocation_states, solve_collocation
from .rigid import solve_rigid
from .shooting import SHOOTING_METHODS, ShootingGrid, node_states, solve_shooting

#: Transcriptions of the clearance stages: multiple shooting through an integrator, or collocation.
METHODS = SHOOTING_METHODS + ("collocation",)
#: Default collocation elements per second of period (0.5 ms elements). Measured on the seed case
#: (T = 0.8 s, benchmarks/bench_collocation.py): the solve time is about the same from 600 to 1600
#: elements (finer grids need fewer iterations), and at 1600 the optimum re-simulates within 0.02 %
#: (0.26 % at 800; 400 did not converge).
ELEMENTS_PER_SECOND = 2000

#: The soft stage runs only when the rigid optimum's peak torque on the clearance model exceeds the
#: rigid peak by this factor (it impacts); otherwise the target stage starts at once.
IMPACT_RATIO = 1.10
#: The rigid optimum is accepted on a clearance model ("auto" stages) when its re-simulated peak is
#: within this factor of the rigid floor and the ram speed stays within tolerance.
VERIFIED_RATIO = 1.02
#: Default lower bound on the rod tension of the ``no_reversal`` stage, as a fraction of the weight of
#: rod and slider (measured on the default press at T = 0.8 s: see the README).
DEFAULT_TENSION_MARGIN = 0.05
#: IPOPT iterations per trust-region refinement round, and the trust region's growth and shrink factors.
REFINE_ITERATIONS = 6
REFINE_GROW, REFINE_SHRINK = 1.5, 0.4
#: Default shooting intervals per period and output samples per interval.
DEFAULT_INTERVALS = 16
DEFAULT_SAMPLES = 25


def soft_params(params: PressParams, factor: float) -> PressParams:
    """The press with every bearing's contact stiffness divided by ``factor`` (continuation stage)."""
    chk.positive("soft_factor", factor)
    bearings = {k: replace(getattr(params, k), stiffness=getattr(params, k).contact_stiffness / factor)
                for k in ("crank_pin", "wrist_pin")}
    return params.replace(**bearings)


def _warm_state(model: PressModel, speed: FourierSpeed, rtol: float) -> tuple:
    """The periodic state of `speed` on `model` (scaled), or (when none is found) the state after
    three cycles from rest. Returns (x0, info)."""
    try:
        x0, info = periodic_state(model, speed, method="cvodes", rtol=rtol)
        return x0, {"periodic_warm_start": True, **info}
    except SimulationError as err:
        x0 = settled_state(model, speed, 3, rtol)
        return x0, {"periodic_warm_start": False, "reason": str(err).splitlines()[0]}


def _warm_nodes(model: PressModel, speed: FourierSpeed, grid: ShootingGrid, rtol: float) -> tuple:
    """Node states integrated from `_warm_state`. Returns (nodes, info)."""
    x0, info = _warm_state(model, speed, min(rtol, 1e-7))
    return node_states(model, speed, x0, grid, "cvodes", min(rtol, 1e-7)), info


def _collocation_stage(problem: SpeedProblem, model: PressModel, speed: FourierSpeed, t1: float,
                       grid: CollocationGrid, name: str, periodic: bool, min_eccentricity: float | None,
                       ipopt_options: dict | None, progress: bool, jit: bool = False) -> tuple:
    """A collocation stage warm-started from the periodic response of `speed` (exact Hessian).
    Returns (solution, record entries: the grid and the warm start's collocation defect)."""
    x0, warm = _warm_state(model, speed, 1e-8)
    states = collocation_states(model, speed, x0, grid, 1e-9)
    warm.update(elements=grid.elements, degree=grid.degree, min_eccentricity=min_eccentricity, jit=jit,
                defect_start=collocation_defect(model, speed, states, grid))
    opts = {"ipopt.hessian_approximation": "exact", **(ipopt_options or {})}
    sol = solve_collocation(problem, model, speed, states, t1, grid, stage=name, periodic=periodic,
                            ipopt_options=opts, progress=progress, min_eccentricity=min_eccentricity, jit=jit)
    return sol, warm


def optimize_speed(
    model: PressModel | None = None,
    initial: FourierSpeed | None = None,
    period: float = 1.0,
    ram_speed: float = -0.1,
    window: tuple[float, float] = (0.7, 0.3),
    objective: str = "peak_torque",
    n_harmonics: int = DEFAULT_HARMONICS,
    intervals: int | None = None,
    samples_per_interval: int | None = None,
    periodic: bool = True,
    ram_speed_tol: float | None = None,
    omega_min: float | None = None,
    method: str = "idas",
    ipopt_options: dict | None = None,
    progress: bool = True,
    *,
    omega_max: float | None = None,
    alpha_max: float | None = None,
    rtol: float = 1e-6,
    soft_factor: float | None = 100.0,
    verify_rtol: float = 1e-9,
    rigid_samples: int = 1000,
    max_steps: int = 10**6,
    stages: str = "auto",
    tension_margin: float | None = DEFAULT_TENSION_MARGIN,
    refine_rounds: int = 0,
    refine_step: float = 0.2,
    elements: int | None = None,
    min_eccentricity: float | None = 1.0,
    jit: bool = False,
) -> OcpResult:
    """Design the crank speed that minimises a peak load with a constant ram speed in the window.

    Parameters
    ----------
    model : PressModel, optional
        Target model; default the default press with clearance in both pins and a rigid rod. A model
        without states (ideal joints) stops after the rigid stage.
    initial : FourierSpeed, optional
        Initial speed; default the kinematic design (`pressocp.design.design_speed`) of the window.
        ``initial_peak_torque`` is its periodic peak on the target model (its 4th cycle from rest
        when it impacts).
    period : float
        Cycle time T, s.
    ram_speed : float
        Ram velocity in the window, m/s (negative: downstroke).
    window : (float, float)
        (h1/H, h2/H), the working window on the downstroke.
    objective : {"peak_torque", "peak_slider_normal_force", "peak_pin_force", "rms_torque"}
    n_harmonics : int
        Harmonics of the speed, 1..50.
    intervals : int, optional
        Shooting intervals per period (default 16), 1..400.
    samples_per_interval : int, optional
        Output samples per interval for the load and ram-speed constraints (default 25), 1..1000.
    periodic : bool
        Periodic steady state x(T) = x(0); otherwise the first node is the warm start's.
    ram_speed_tol : float, optional
        |v - ram_speed| allowed in the window, m/s; default 1 % of |ram_speed|.
    omega_min : float, optional
        Lower crank-speed bound, rad/s; default 5 % of the mean speed.
    method : {"idas", "cvodes", "collocation"}
        Transcription of the clearance stages: multiple shooting with that interval integrator, or
        direct collocation (`elements`, `min_eccentricity`; `intervals`, `samples_per_interval`,
        `soft_factor` and `rtol` are then unused).
    ipopt_options : dict, optional
        Extra options for the shooting stages' nlpsol (e.g. ``{"ipopt.max_iter": 30}``); the rigid
        stage keeps its defaults.
    progress : bool
        tqdm bars over the IPOPT iterations of the shooting stages.
    omega_max, alpha_max : float, optional
        Motor limits, rad/s and rad/s^2.
    rtol : float
        Tolerance of the shooting integrators.
    soft_factor : float or None
        Contact-stiffness divisor of the continuation stage, which runs when the rigid optimum
        impacts on the clearance model (peak torque > `IMPACT_RATIO` x rigid); None skips it.
    verify_rtol : float
        Tolerance of the final periodic re-simulation.
    rigid_samples : int
        Samples of the rigid stage.
    max_steps : int
        Step limit of each shooting-interval integration.
    stages : {"auto", "all"}
        "auto" (use no more model than the scene needs): when the rigid optimum (or, if that
        impacts, the no-reversal optimum), re-simulated on the clearance model, keeps the ram speed
        within tolerance and its peak within `VERIFIED_RATIO` of its rigid-model peak, it is the
        answer and the shooting stages are skipped (recorded in ``stages``). "all" always runs them,
        warm-started from that speed.
    tension_margin : float or None
        Rod tension kept at both pins by the ``no_reversal`` stage, as a fraction of the weight of
        rod and slider, in [0, 1); None skips that stage. It runs only when the rigid optimum is not
        verified on the clearance model and the press has no process force.
    refine_rounds : int
        Trust-region refinement rounds on the clearance model (rigid rod) after the other stages,
        0..100 (default 0: none). Each runs `REFINE_ITERATIONS` IPOPT iterations of the shooting
        NLP (``ipopt_options`` can override) and re-simulates the final iterate; measured on the
        seed case: ≈ 3.5 min per round, −3.1 % in 5 rounds (see the README).
    refine_step : float
        Initial trust region of the refinement, rad/s on every Fourier coefficient (> 0).
    elements : int, optional
        Collocation elements per period (degree 3), 10..100 000; default `ELEMENTS_PER_SECOND` x T.
    min_eccentricity : float or None
        Collocation only: the journals' eccentricity ratio stays at or above this, in [0, 1]
        (default 1: contact is never lost, so no impact is possible). None: no such constraint; the
        elements must then resolve the impacts (measured: 1 ms elements do not, and the solve fails).
    jit : bool
        Collocation only: compile the model's point function and its derivatives with the system C
        compiler (``cc``; CasADi JIT, -O1). Measured on the seed case at 1600 elements: ≈ 8 s to
        compile, then ≈ 3× faster iterations (the whole call: 93 s median, against 250 s without).

    Returns
    -------
    OcpResult
        ``success`` False when a stage did not converge (its best iterate is returned, its status
        says why, and an integrator failure names the stage and interval).

    Raises
    ------
    ValueError
        Invalid or infeasible request (checked before any solve).
    ShootingError
        (`pressocp.ocp.ShootingError`) a stage's warm start cannot be integrated.
    """
    t_start = time.perf_counter()
    if model is None:
        model = build_model(PressParams(), n_harmonics=n_harmonics)
    if not isinstance(model, PressModel):
        raise ValueError(f"model must be a PressModel (from build_model), got {type(model).__name__}")
    problem = SpeedProblem(model.params, period=period, ram_speed=ram_speed, window=window, objective=objective,
                           n_harmonics=n_harmonics, ram_speed_tol=ram_speed_tol, omega_min=omega_min,
                           omega_max=omega_max, alpha_max=alpha_max)
    chk.choice("method", method, METHODS)
    K = chk.integer("elements", round(ELEMENTS_PER_SECOND * period) if elements is None else elements, 10, 100_000)
    if min_eccentricity is not None:
        chk.in_closed_interval("min_eccentricity", min_eccentricity, 0.0, 1.0)
    N = chk.integer("intervals", DEFAULT_INTERVALS if intervals is None else intervals, 1, 400)
    S = chk.integer("samples_per_interval", DEFAULT_SAMPLES if samples_per_interval is None else samples_per_interval,
                    1, 1000)
    chk.positive("rtol", rtol)
    chk.positive("verify_rtol", verify_rtol)
    stages_mode = chk.choice("stages", stages, ("auto", "all"))
    if soft_factor is not None:
        chk.in_open_interval("soft_factor", soft_factor, 1.0, 1e8)
    if tension_margin is not None:
        chk.in_half_open_interval("tension_margin", tension_margin, 0.0, 1.0)
    refine_rounds = chk.integer("refine_rounds", refine_rounds, 0, 100)
    chk.positive("refine_step", refine_step, "rad/s")
    if model.n_harmonics != n_harmonics:
        model = build_model(model.params, model.rod, model.clearance, model.n_elements, n_harmonics)
    if initial is None:
        initial = design_speed(model.params, period=period, ram_speed=ram_speed, window=window,
                               n_harmonics=min(n_harmonics, DEFAULT_HARMONICS)).speed
    elif not np.isclose(initial.period, period):
        raise ValueError(f"initial.period must equal period ({period:g} s), got {initial.period:g} s")

    rigid = solve_rigid(problem, initial, samples=rigid_samples)
    records = list(rigid.stages)
    history = list(rigid.objective_history)
    if model.is_rigid:
        rigid.wall_time = time.perf_counter() - t_start
        return rigid

    base = model if model.rod == "rigid" else build_model(model.params, "rigid", model.clearance, 4, n_harmonics)
    ratio, verified = _check_on(base, rigid, problem, records[0])
    start = rigid  # the speed the clearance stages start from, or the answer
    if not verified and tension_margin is not None and model.params.process_force.force == 0.0:
        bound = tension_margin * problem.hanging_weight
        nr = solve_rigid(replace(problem, min_tension=bound), rigid.speed, samples=rigid_samples)
        rec = {**nr.stages[0], "name": "no_reversal", "min_tension": bound}
        records.append(rec)
        history.extend(nr.objective_history)
        if nr.success:
            ratio_nr, verified = _check_on(base, nr, problem, rec)
            if verified or ratio_nr < ratio:
                start, ratio = nr, ratio_nr
    chain: list[tuple[str, PressModel]] = []
    if stages_mode == "auto" and verified:
        skipped = ["target"]
        if model.rod == "flexible":
            if _check_on(model, start, problem, records[-1], prefix="flexible_")[1]:
                skipped.append("flexible")
            else:
                chain.append(("flexible", model))
        answer = records[-1]["name"]
        for name in skipped:
            records.append({"name": name, "status": f"skipped: the {answer} optimum meets the constraints "
                           f"on this model and its peak is within {VERIFIED_RATIO:g} x its rigid-model peak",
                           "iterations": 0, "wall_time": 0.0, "objective": start.objective_value})
    else:
        if soft_factor is not None and ratio > IMPACT_RATIO and method != "collocation":
            chain.append(("soft", build_model(soft_params(model.params, soft_factor), "rigid", base.clearance, 4,
                                              n_harmonics)))
        chain.append(("target", base))
        if model.rod == "flexible":
            chain.append(("flexible", model))

    grid = ShootingGrid(period, N, S)
    speed, t1, success, status, value = start.speed, start.t1, start.success, start.status, start.objective_value
    for name, m in chain:
        if method == "collocation":
            sol, warm = _collocation_stage(problem, m, speed, t1, CollocationGrid(period, K), name, periodic,
                                           min_eccentricity, ipopt_options, progress, jit)
        else:
            nodes, warm = _warm_nodes(m, speed, grid, rtol)
            sol = solve_shooting(problem, m, speed, nodes, t1, grid, stage=name, periodic=periodic, method=method,
                                 rtol=rtol, ipopt_options=ipopt_options, progress=progress,
                                 max_steps=max_steps)
            warm.update(intervals=N, samples=S)
        records.append({"name": name, "status": sol.status, "iterations": sol.iterations, "wall_time": sol.wall_time,
                       "objective": sol.value, "violations_start": sol.violations_start, "violations": sol.violations,
                       "method": method, "barrier": sol.barrier, **warm})
        history.extend(sol.history)
        speed, success, status, value = sol.speed, sol.success, sol.status, sol.value
        if not success:
            status = f"stage {name!r}: {status}"
            break

    if refine_rounds and success:
        speed, value = _refine(problem, base, speed, value, t1, grid, refine_rounds, refine_step, records, history,
                               method=method if method in SHOOTING_METHODS else "cvodes", rtol=rtol,
                               ipopt_options=ipopt_options, progress=progress, max_steps=max_steps)
    t2 = t1 + problem.window_duration
    sim = _verify(model, speed, verify_rtol)
    init_rigid = rigid_response(model.params, initial, np.linspace(0.0, period, 20001))
    init_sim = _screened(model, initial, objective_peak(init_rigid, objective), objective,
                         min(1e-7, 10 * verify_rtol))[0]
    viol = ram_speed_violation(sim, problem, t1)
    return OcpResult(
        speed=speed, objective=objective, peak_torque=sim.peak("torque"),
        initial_peak_torque=init_sim.peak("torque"), rigid_peak_torque=rigid.peak_torque, objective_value=value,
        t1=t1, t2=t2, success=success, status=status, iterations=sum(s["iterations"] for s in records),
        wall_time=time.perf_counter() - t_start, max_ram_speed_violation=max(viol, 0.0),
        min_omega=speed.min_speed(), objective_history=history, stages=records, simulation=sim,
        initial_simulation=init_sim, rigid=rigid,
    )


def _refine(problem: SpeedProblem, model: PressModel, speed: FourierSpeed, value: float, t1: float,
            grid: ShootingGrid, rounds: int, step: float, records: list, history: list, **shooting) -> tuple:
    """Trust-region rounds of `solve_shooting` on `model` from `speed`; (speed, optimiser value) of the
    last accepted round, or the inputs. Appends a record per round to `records`.

    Each round's node states are integrated from the periodic state of the current speed, taken
    from its verifying re-simulation (the start's, then each accepted candidate's)."""
    sim = _verify(model, speed, 1e-7)
    best = objective_peak(sim, problem.objective)
    opts = {"ipopt.max_iter": REFINE_ITERATIONS, **(shooting.pop("ipopt_options") or {})}
    for k in range(rounds):
        t0 = time.perf_counter()
        rec = {"name": f"refine_{k + 1}", "coefficient_step": step, "iterations": 0, "objective": value}
        records.append(rec)
        try:
            nodes = node_states(model, speed, sim.states[:, 0] / model.x_scale, grid, "cvodes", 1e-7)
            sol = solve_shooting(problem, model, speed, nodes, t1, grid, stage=rec["name"], ipopt_options=opts,
                                 coefficient_step=step, **shooting)
        except SimulationError as err:  # the verified answer so far stands
            rec.update(status=f"stopped: {str(err).splitlines()[0]}", accepted=False,
                       wall_time=time.perf_counter() - t0)
            break
        history.extend(sol.history)
        cand, ratio, periodic = _screened(model, sol.last_speed, best, problem.objective, 1e-7)
        viol = ram_speed_violation(cand, problem, t1)
        accepted = bool(periodic is True and ratio < 1.0 and viol <= 0.0)
        rec.update(status=sol.status, iterations=sol.iterations, accepted=accepted, clearance_value=ratio * best,
                   periodic=periodic, ram_speed_violation=max(viol, 0.0), wall_time=time.perf_counter() - t0)
        if accepted:
            speed, sim, best, step = sol.last_speed, cand, ratio * best, step * REFINE_GROW
            value = rec["objective"] = float(sol.history[-1]) if sol.history else value
        else:
            step *= REFINE_SHRINK
    return speed, value


def objective_peak(sim, objective: str) -> float:
    """The objective's value on a simulated response (peak load or RMS torque)."""
    if objective == "rms_torque":
        return float(np.sqrt(np.mean(sim.torque**2)))
    if objective == "peak_pin_force":
        return max(sim.peak("crank_pin_force"), sim.peak("wrist_pin_force"))
    return sim.peak({"peak_torque": "torque", "peak_slider_normal_force": "slider_normal_force"}[objective])


def ram_speed_violation(sim, problem: SpeedProblem, t1: float) -> float:
    """max(|v - ram_speed|) - tol over the window samples of a response, m/s (<= 0: within tolerance)."""
    mask = (sim.t >= t1) & (sim.t <= t1 + problem.window_duration)
    return float(np.max(np.abs(sim.ram_velocity[mask] - problem.ram_speed))) - problem.tol


def _screened(model: PressModel, speed: FourierSpeed, rigid_value: float, objective: str, rtol: float) -> tuple:
    """Response of `speed` on `model` and its objective ratio to `rigid_value` (the rigid model's).

    A screen first: the 4th cycle from rest. If it impacts (ratio > `IMPACT_RATIO`), that cycle is the
    answer and no periodic state is searched for (there is often none: the journals' free flight is
    chaotic, and the failing search took ~25 s at T = 0.8 s on the rigid rod, many minutes on the
    flexible one). Otherwise the periodic response (`_verify`) from the screen's state.
    Returns (sim, ratio, periodic: True, False (searched, not found) or a reason string)."""
    x3 = settled_state(model, speed, 3, rtol)
    reason = "not searched: impacting (4th cycle from rest)"
    sim = _cycle_from(model, speed, rtol, x3, cycle=4, reason=reason)
    ratio = objective_peak(sim, objective) / rigid_value
    if ratio > IMPACT_RATIO:
        return sim, ratio, reason
    sim = _verify(model, speed, rtol, x0=x3)
    return sim, objective_peak(sim, objective) / rigid_value, sim.stats["periodic"].get("found", True)


def _check_on(model: PressModel, rigid: OcpResult, problem: SpeedProblem, record: dict, prefix: str = "") -> tuple:
    """Re-simulate a rigid-stage optimum on `model` (`_screened`, rtol 1e-7); (objective ratio to its
    rigid-model value, verified?)."""
    rigid_value = objective_peak(rigid.simulation, problem.objective)
    probe, ratio, periodic = _screened(model, rigid.speed, rigid_value, problem.objective, 1e-7)
    viol = ram_speed_violation(probe, problem, rigid.t1)
    ne = rigid_inverse_dynamics(problem.params, *rigid.speed.evaluate(rigid.simulation.t))
    record["min_rod_tension"] = float(min(ne["crank_pin_tension"].min(), ne["wrist_pin_tension"].min()))
    record.update({prefix + "clearance_peak_torque": probe.peak("torque"), prefix + "clearance_ratio": ratio,
                   prefix + "periodic": periodic, prefix + "ram_speed_violation": max(viol, 0.0)})
    return ratio, bool(periodic is True and ratio <= VERIFIED_RATIO and viol <= 0.0)


def _verify(model: PressModel, speed: FourierSpeed, rtol: float, x0: np.ndarray | None = None):
    """Periodic re-simulation on a fine grid (20 000 samples per cycle), its search started from the
    scaled state `x0` (default the model's). When the response has no periodic steady state (an
    impacting, chaotic one), the 6th cycle from rest is returned and ``stats["periodic"]`` says so."""
    try:
        return simulate(model, speed, periodic=True, method="cvodes", rtol=rtol, n_out=20001, x0=x0)
    except SimulationError as err:
        return _cycle_from(model, speed, rtol, settled_state(model, speed, 5, rtol), cycle=6,
                           reason=str(err).splitlines()[0])


def settled_state(model: PressModel, speed: FourierSpeed, cycles: int, rtol: float) -> np.ndarray:
    """Scaled state after `cycles` cycles from rest (CVODES at `rtol`)."""
    r = simulate(model, speed, cycles=cycles, method="cvodes", rtol=rtol, n_out=cycles + 1)
    return r.states[:, -1] / model.x_scale


def _cycle_from(model: PressModel, speed: FourierSpeed, rtol: float, x0: np.ndarray, cycle: int, reason: str):
    """One cycle from the scaled state `x0` on the fine grid, standing in for a periodic response that
    was not found or not searched for: ``stats["periodic"]`` records which cycle from rest it is and why."""
    sim = simulate(model, speed, method="cvodes", rtol=rtol, n_out=20001, x0=x0)
    sim.stats["periodic"] = {"found": False, "reason": reason, "cycle": cycle}
    return sim
