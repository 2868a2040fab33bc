"""Reproducible studies built on the model: the impact phenomenon of the source paper and Simeon's
flexible slider crank."""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import beam
from .design import SpeedDesign, design_speed
from .model import ModelSpec, build_model
from .ocp.result import PEAK_SERIES
from .ocp.verify import is_periodic, verify_speed
from .params import PressParams
from .problem import SpeedProblem
from .result import SimResult
from .rigid import rigid_response
from .simulate import simulate
from .speed import FourierSpeed

if TYPE_CHECKING:
    import pandas as pd

    from .scenario import Scenario

#: The impact scenario of the source paper's Figs. 6 and 9: at 60 strokes/min the rigid design of
#: -0.1 m/s keeps the wrist-pin force above ~490 N (no reversal, no impact); 75 strokes/min (T = 0.8 s)
#: is the smallest step of the scan 1.0/0.8/0.7/0.6/0.5 s at which it reverses.
IMPACT_PERIOD = 0.8
IMPACT_RAM_SPEED = -0.1


@dataclass
class ImpactStudy:
    """Constant versus rigid-designed speed, a model with clearance against rigid inverse dynamics."""

    design: SpeedDesign
    constant: SimResult
    constant_rigid: SimResult
    designed: SimResult
    designed_rigid: SimResult

    def not_periodic(self) -> dict[str, str]:
        """The responses (``constant``, ``designed``) that are not periodic steady states, each with
        the reason (`pressocp.ocp.verify.is_periodic`); empty when both are."""
        found = {"constant": is_periodic(self.constant), "designed": is_periodic(self.designed)}
        return {k: v for k, v in found.items() if v is not True}

    def ratios(self) -> dict[str, dict[str, float]]:
        """Peak model value / peak rigid value for each load, for both speeds."""
        return {
            label: {n: clr.peak(n) / rig.peak(n) for n in PEAK_SERIES}
            for label, clr, rig in (("constant", self.constant, self.constant_rigid),
                                    ("designed", self.designed, self.designed_rigid))
        }


def impact_study(problem: SpeedProblem | None = None, model: ModelSpec | None = None,
                 rtol: float = 1e-8) -> ImpactStudy:
    """Responses of `model` (default: rigid rod, both clearances) at constant speed and at the rigid
    design of `problem` (default: the default press at 75 strokes/min, -0.1 m/s over h/H 0.7 -> 0.3),
    with the rigid inverse dynamics on the same time grid.

    The responses are periodic steady states (CVODES at `rtol`) when one is found, else the 6th cycle
    from rest (``stats["periodic"]`` says why)."""
    problem = SpeedProblem(PressParams(), period=IMPACT_PERIOD, ram_speed=IMPACT_RAM_SPEED) \
        if problem is None else problem
    m = (ModelSpec() if model is None else model).build(problem.press, problem.n_harmonics)
    d = design_speed(problem)
    const = FourierSpeed.constant(problem.period)
    rc = verify_speed(m, const, rtol)
    rd = verify_speed(m, d.speed, rtol)
    return ImpactStudy(d, rc, rigid_response(problem.press, const, rc.t), rd,
                       rigid_response(problem.press, d.speed, rd.t))


#: Simeon test set: elastic rates of the first two transverse modes at t = 0 (m/s) and the reference.
SIMEON_MODE_RATES = (0.44490, 4.6343e-3)
SIMEON_REFERENCE = {"t": 0.1, "slider_position": 0.169737333, "slider_velocity": -8.7531,
                    "midspan_deflection": 1.8932e-4, "midspan_extremes": 1.65e-3}


def simeon_crank(n_elements: int = 4, rtol: float = 1e-10, t_end: float = 0.1, n_out: int = 2001,
                 n_modes: int | None = None) -> SimResult:
    """Simeon's flexible slider crank from the test-set initial values.

    The crank turns at 150 rad/s from theta = pi (pointing along the slide toward the slider, as
    in the test set). The rod starts undeformed with the test set's modal rates
    w_dot = q1d sin(pi xi/L) + q2d sin(2 pi xi/L); the test set's axial deformations have no
    counterpart in the axially rigid rod. The frames are mirror images of ours, but the rod's
    transverse axis (+90 deg from crank pin -> wrist pin in the test set) maps onto ours, so w
    compares directly. With `n_modes` the rod is reduced to that many modes (`ModelSpec.n_modes`)
    and the initial rates are their mass-weighted fit.
    """
    p = PressParams.simeon()
    L = p.rod_length
    m = build_model(p, rod="flexible", clearance=(), n_elements=n_elements, n_modes=n_modes)
    q1d, q2d = SIMEON_MODE_RATES
    qd = beam.interpolate(L, n_elements,
                          lambda x: q1d * np.sin(np.pi * x / L) + q2d * np.sin(2 * np.pi * x / L),
                          lambda x: np.pi / L * (q1d * np.cos(np.pi * x / L) + 2 * q2d * np.cos(2 * np.pi * x / L)))
    if m.rod_modes is not None:
        mass, _ = beam.pinned_pinned_matrices(L, n_elements, p.rod_mass / L, p.rod_youngs_modulus * p.rod_area_moment)
        qd = beam.modal_coordinates(m.rod_modes, mass, qd)
    x0 = np.concatenate([np.zeros(qd.size), qd]) / m.x_scale
    speed = FourierSpeed.constant(2 * np.pi / 150.0, theta0=np.pi)
    return simulate(m, speed, t_end=t_end, x0=x0, method="cvodes", rtol=rtol, n_out=n_out)


#: Clearances of the wear study (every clearance joint at once), m.
WEAR_CLEARANCES = (5e-5, 1e-4, 1.5e-4, 2e-4, 3e-4, 4e-4)
#: A journal whose eccentricity ratio |e|/c falls below this has left its bearing wall: a free flight,
#: which ends in an impact.
FREE_FLIGHT_ECCENTRICITY = 0.95


def wear_study(scenario: Scenario, speed: FourierSpeed, clearances: Sequence[float] = WEAR_CLEARANCES,
               executor: Executor | None = None, progress: bool = False,
               csv: str | Path | None = None) -> pd.DataFrame:
    """One crank speed as the joints wear: its periodic response with every clearance joint of the
    scenario's model at each of `clearances` (m), the other values as in `scenario`.

    Parameters
    ----------
    scenario : Scenario
    speed : FourierSpeed
    clearances : sequence of float
        m.
    executor, progress, csv
        As in `pressocp.sweep`.

    Returns
    -------
    pandas.DataFrame
        The `pressocp.sweep` table (task "simulate"), with ``clearance`` (m), ``torque_ratio`` (peak torque
        over the ideal press's) and ``free_flight`` (a journal's eccentricity ratio below
        `FREE_FLIGHT_ECCENTRICITY` somewhere in the cycle, or no periodic response).
    """
    from .sweeps import sweep

    joints = scenario.model.clearance
    if not joints:
        raise ValueError("the scenario's model has no clearance joint to wear")
    path = [{f"{j}.clearance": float(c) for j in joints} for c in clearances]
    table = sweep(scenario, path, "simulate", speed=speed, executor=executor, progress=progress, csv=csv)
    table.insert(0, "clearance", [float(c) for c in clearances])
    table["torque_ratio"] = table["peak_torque_N_m"] / table["ideal_joints_peak_torque_N_m"]
    ecc = table[[f"min_{j}_eccentricity" for j in joints]].min(axis=1)
    table["free_flight"] = (ecc < FREE_FLIGHT_ECCENTRICITY) | ~table["ok"].astype(bool)
    return table
