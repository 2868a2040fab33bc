"""Reproducible studies built on the model: Simeon's flexible slider crank and the clearance (wear)
study over a sweep. The impact phenomenon of the source paper is `pressocp.impacts`."""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Executor
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import beam
from .model import build_model
from .params import PressParams
from .result import SimResult
from .simulate import Integrator, simulate
from .speed import FourierSpeed
from .sweeps import sweep

if TYPE_CHECKING:
    import pandas as pd

    from .scenario import Scenario

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
    return simulate(m, speed, t_end=t_end, x0=x0, integrator=Integrator(method="cvodes", rtol=rtol), n_out=n_out)


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
