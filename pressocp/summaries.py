"""What a run reports: the flat keys of an optimum's or a simulation's ``summary.json`` (also a sweep
row's columns), the response of a speed as a job or a sweep point computes it, and the time table as
text. Used by the command line's jobs and by the sweeps alike."""

from __future__ import annotations

import numpy as np

from .drive import MotorCycle
from .journals import contact_losses
from .objectives import get as get_objective
from .ocp.ocp_result import OcpResult
from .verify import describe_excess, is_periodic, ram_speed_error, rigid_reference, settled_response
from .params import PressParams
from .problem import SpeedProblem
from .report import format_table, peak_summary
from .result import SimResult
from .simulate import for_repeated_use
from .scenario import Scenario
from .speed import FourierSpeed


def problem_summary(problem: SpeedProblem) -> dict:
    """The problem's keys of a summary: period, stroke rate, ram speed and tolerance, window, objective;
    the counterbalance and the process force's largest value when the press has them."""
    press = problem.press
    forces = {}
    if press.counterbalance.force > 0.0:
        cb = press.counterbalance
        forces["counterbalance"] = {"force_N": cb.force, "gas_length_m": cb.gas_length, "exponent": cb.exponent}
    if press.process_force.active:
        forces["process_force_max_N"] = press.process_force.peak
    return {"period_s": problem.period, "stroke_rate_spm": problem.stroke_rate_spm,
            "ram_speed_m_s": problem.ram_speed, "ram_speed_tol_m_s": problem.tol,
            "window_h_over_H": list(problem.window), "objective": problem.objective, **forces}


def optimum_summary(scenario: Scenario, result: OcpResult, ideal: SimResult | None = None) -> dict:
    """The keys of an optimum's ``summary.json``: the problem, convergence and verification, the peaks
    of the answer and of the initial speed on the model (``initial_...``) and of the initial speed on
    the ideal press (``initial_ideal_joints_...``, when `ideal` is given), the floor, stages. The
    problem is the result's: with a counterbalance chosen with the speed, its force is the chosen one."""
    problem = result.problem
    ideal_peaks = {} if ideal is None else peak_summary(ideal, "initial_ideal_joints_")
    return {
        "job": "optimize", "scenario": scenario.name, "model": scenario.model.describe(),
        "transcription": result.transcription, **problem_summary(problem),
        "converged": result.success, "verified": result.verified, "periodic": result.periodic,
        "status": result.status, "objective_value": result.verified_objective,
        "objective_unit": get_objective(problem.objective).unit,
        **peak_summary(result.simulation), **peak_summary(result.initial_simulation, "initial_"), **ideal_peaks,
        "rigid_peak_torque_N_m": result.rigid_peak_torque,
        "max_ram_speed_error": ram_speed_error(result.simulation, problem),
        "max_ram_speed_violation_m_s": result.max_ram_speed_violation, "limits_exceeded": result.limits,
        "window_t_s": [result.t1, result.t2],
        **contact_summary(result.simulation, problem.press, scenario.model.clearance),
        "min_omega_rad_s": result.min_omega, "iterations": result.iterations, "wall_time_s": result.wall_time,
        "stages": [{"name": s.name, "model": s.model, "status": s.status, "success": s.success,
                    "superseded": s.superseded, "iterations": s.iterations, "wall_time_s": s.wall_time,
                    "objective": s.objective, "timing_s": s.timing} for s in result.stages],
        "time_table_s": result.time_table(),
    }


def flag_reason(summary: dict) -> str:
    """Why a job's results are flagged, from its summary: not converged (IPOPT's status), or not
    verified (the re-simulation not periodic, the ram speed out of tolerance, a limit exceeded), else
    its status; for a stroke-rate search, its verdict."""
    if summary.get("job") == "rate":
        return str(summary.get("status", "no rate tried held every limit"))
    if summary.get("converged") is False:
        return f"not converged ({summary.get('status')})"
    periodic = summary.get("periodic")
    if summary.get("verified") is False or periodic not in (True, None):
        why = []
        if periodic not in (True, None):
            why.append(f"the re-simulation is not periodic ({periodic})")
        if summary.get("max_ram_speed_violation_m_s", 0.0) > 0.0:
            why.append(f"the ram speed leaves its tolerance by {summary['max_ram_speed_violation_m_s']:.3g} m/s")
        if summary.get("limits_exceeded"):
            why.append(describe_excess(summary["limits_exceeded"]))
        return "not verified" + (f": {'; '.join(why)}" if why else "")
    return str(summary.get("status", periodic))


#: Columns of the time table in the report: `OcpResult.time_table` key -> heading.
TIME_COLUMNS = {"wall": "wall", "build": "build", "compile": "compile", "functions": "functions",
                "linear_solver": "linear solver", "start": "warm start", "checks": "checks"}


def time_table_text(result: OcpResult) -> str:
    """`OcpResult.time_table` as a plain-text table (s), with a row of the column sums (more than the
    call's wall time when candidate chains ran side by side)."""
    rows = result.time_table()
    total = {k: sum(r[k] for r in rows) for k in TIME_COLUMNS}
    return format_table([["stage", "iterations", *TIME_COLUMNS.values()],
                         *([r["stage"], str(r["iterations"]), *(f"{r[k]:.1f}" for k in TIME_COLUMNS)] for r in rows),
                         ["sum", str(sum(r["iterations"] for r in rows)), *(f"{total[k]:.1f}" for k in TIME_COLUMNS)]])


def simulation_summary(scenario: Scenario, sim: SimResult, ideal: SimResult, source: str) -> dict:
    """The keys of a simulation's ``summary.json``: the problem, periodicity, the peaks on the model and
    on the ideal press (``ideal_joints_...``), the smallest eccentricity ratio |e|/c of each clearance
    joint (``min_<joint>_eccentricity``: below 1 the journal leaves its bearing wall, a free flight
    that ends in an impact), the ram speed error and the objective's value."""
    problem = scenario.problem
    ecc = {f"min_{j}_eccentricity": v for j, v in sim.min_eccentricities(scenario.model.clearance).items()}
    return {"job": "simulate", "scenario": scenario.name, "model": scenario.model.describe(), "speed": source,
            **problem_summary(problem), "periodic": is_periodic(sim), **peak_summary(sim),
            **peak_summary(ideal, "ideal_joints_"), **ecc, **contact_summary(sim, problem.press, scenario.model.clearance),
            "max_ram_speed_error": ram_speed_error(sim, problem),
            "objective_value": problem.objective_value(sim), "rtol": scenario.solver.verify_rtol}


def contact_summary(sim: SimResult, press: PressParams, joints: tuple[str, ...]) -> dict:
    """Flat keys of each clearance joint's separations from its bearing wall over the response
    (`pressocp.journals.contact_losses`): ``<joint>_contact_losses`` (a cycle), ``<joint>_longest_flight_s``,
    ``<joint>_flight_depth_m`` and ``<joint>_return_speed_m_s`` (the fastest landing: the impact)."""
    out = {}
    for j, c in contact_losses(sim, press, joints).items():
        out.update({f"{j}_contact_losses": c.losses, f"{j}_longest_flight_s": c.flight_time,
                    f"{j}_flight_depth_m": c.depth, f"{j}_return_speed_m_s": c.return_speed})
    return out


def simulate_speed(scenario: Scenario, speed: FourierSpeed) -> tuple[SimResult, SimResult]:
    """The periodic response of `speed` on the scenario's model (CVODES at the solver's ``verify_rtol``,
    compiled as the optimiser's verification is, `pressocp.simulate.for_repeated_use`, so that an
    optimum's speed re-simulates to its reported peak), or a cycle from rest when a screen shows the
    response impacts and does not settle (`settled_response`), and the ideal press's on the same grid."""
    problem = scenario.problem
    ideal = rigid_reference(problem, speed)
    sim = settled_response(problem, for_repeated_use(scenario.build_model()), speed, scenario.solver.verify_rtol,
                           problem.objective_value(ideal))
    return sim, ideal


def drive_summary(problem: SpeedProblem, cycles: dict[str, MotorCycle]) -> dict:
    """The ``drive`` key of a summary: the drive's data and each cycle's figures by label (SI: N m,
    rad/s, W, J; margins as fractions, negative when a rating is exceeded)."""
    return {"drive": {**problem.drive.to_dict(), **{label: c.summary() for label, c in cycles.items()}}}


def drive_text(problem: SpeedProblem, cycles: dict[str, MotorCycle]) -> str:
    """The report's table of the drive's figures, one column per cycle."""
    d = problem.drive
    rows = [["motor (gear ratio {:g})".format(d.gear_ratio), *cycles],
            [f"peak torque, N·m (peak curve {d.peak_torque:g})", *(f"{c.peak_torque:.3g}" for c in cycles.values())],
            ["margin to the peak curve", *(f"{100 * c.peak_torque_margin:+.0f} %" for c in cycles.values())],
            [f"RMS torque, N·m (continuous {d.continuous_torque:g})", *(f"{c.rms_torque:.3g}" for c in cycles.values())],
            ["margin to the continuous rating", *(f"{100 * c.rms_margin:+.0f} %" for c in cycles.values())],
            [f"top speed, rpm (max {d.max_speed * 60 / (2 * np.pi):.0f})",
             *(f"{c.max_speed * 60 / (2 * np.pi):.0f}" for c in cycles.values())],
            ["margin to the top speed", *(f"{100 * c.speed_margin:+.0f} %" for c in cycles.values())],
            ["load / motor inertia", *(f"{c.inertia_ratio:.3g}" for c in cycles.values())],
            ["peak power, kW", *(f"{c.peak_power / 1e3:.3g}" for c in cycles.values())],
            ["energy per stroke out / back, J", *(f"{c.energy_driving:.4g} / {c.energy_regenerated:.4g}"
                                                   for c in cycles.values())],
            [f"energy drawn per stroke, J (regeneration {d.regeneration_efficiency:g})",
             *(f"{c.energy_drawn:.4g}" for c in cycles.values())],
            ["DC-bus energy swing, J", *(f"{c.bus_energy_swing:.4g}" for c in cycles.values())]]
    return format_table(rows)
