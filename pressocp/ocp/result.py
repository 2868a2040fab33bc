"""Result of a speed optimisation."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..result import SimResult
from ..speed import FourierSpeed


@dataclass
class OcpResult:
    """Optimal crank speed and how it was found.

    Attributes
    ----------
    speed : FourierSpeed
        Optimal (or best-iterate) speed; ``speed.amplitude`` and ``speed.phase`` give r_k, phi_k.
    objective : str
        What was minimised.
    peak_torque, initial_peak_torque, rigid_peak_torque : float
        Peak |torque| of the optimum, of the initial speed and of the rigid optimum (the floor), N m,
        each evaluated on the model the stage solved (see `stages`).
    objective_value : float
        The epigraph variable s (or the RMS torque), in the objective's unit.
    t1, t2 : float
        Working window, s.
    success : bool
        IPOPT's success flag of the last stage; when False the speed is the best iterate.
    status : str
        IPOPT return status of the last stage.
    iterations : int
        IPOPT iterations, summed over stages.
    wall_time : float
        Total wall time, s.
    max_ram_speed_violation : float
        max(|v - ram_speed| - tol, 0) on a dense grid over the window, m/s.
    min_omega : float
        Smallest crank speed over the period, rad/s.
    objective_history : list of float
        Objective per IPOPT iteration (all stages, in order).
    stages : list of dict
        Per stage: name, status, iterations, wall time, objective; a shooting stage adds its
        constraint violations by group at the start and end, its grid, and ``barrier`` (IPOPT's
        barrier parameter per iteration). A rigid-model stage checked on the clearance model
        (``rigid``, ``no_reversal``) adds ``clearance_peak_torque`` (N m), ``clearance_ratio``
        (to its rigid-model peak), ``periodic``, ``ram_speed_violation`` (m/s) and
        ``min_rod_tension`` (N, the smaller axial tension of the two pins over the cycle on the
        rigid model: negative means the joint forces reverse).
        A collocation stage adds ``elements``, ``degree``, ``min_eccentricity``, ``jit`` and
        ``defect_start`` (the largest collocation defect of its warm start: near 0 when the grid
        resolves the response).
    simulation : SimResult or None
        Re-simulated (or re-evaluated) response of the optimum.
    initial_simulation : SimResult or None
        The same for the initial speed.
    rigid : OcpResult or None
        The rigid stage's own result (shooting stages only).
    """

    speed: FourierSpeed
    objective: str
    peak_torque: float
    initial_peak_torque: float
    rigid_peak_torque: float
    objective_value: float
    t1: float
    t2: float
    success: bool
    status: str
    iterations: int
    wall_time: float
    max_ram_speed_violation: float
    min_omega: float
    objective_history: list = field(default_factory=list)
    stages: list = field(default_factory=list)
    simulation: SimResult | None = None
    initial_simulation: SimResult | None = None
    rigid: "OcpResult | None" = None

    @property
    def max_speed_change(self) -> float:
        """max |omega_opt - omega_initial| / mean speed over the period (needs `initial_simulation`)."""
        if self.initial_simulation is None or self.simulation is None:
            raise ValueError("max_speed_change needs both simulations")
        t = self.simulation.t
        wbar = 2 * np.pi / self.speed.period
        return float(np.max(np.abs(self.speed.omega(t) - np.interp(t, self.initial_simulation.t,
                                                                    self.initial_simulation.omega))) / wbar)

    @property
    def amplitude(self) -> np.ndarray:
        """r_k, rad/s."""
        return self.speed.amplitude

    @property
    def phase(self) -> np.ndarray:
        """phi_k, rad."""
        return self.speed.phase
