"""Local sensitivities of a response's peaks to press parameters, by forward sensitivities of the
periodic response through the integrator.

    s = po.sensitivities(po.build_model(press), speed, ("slider_mass", "wrist_pin.clearance"))
    s.table        # d peak / d parameter, with the normalised p / J dJ/dp

A peak J = |y(t*)| is differentiated as the value at the peak's time: dJ/dp = sign(y(t*)) dy(t*)/dp
(the peak time moves with p, but y' = 0 there). When other local maxima come within `UNIQUE_TOL` of
the peak (a min-max optimum equalises several), J is the maximum of them and its derivative is
one-sided: each is differentiated and the row gives both sides and is flagged.

The periodic state moves with the parameter too. With Phi(x0, p) the state after one period,
x0*(p) = Phi(x0*, p) gives dx0*/dp = (I - dPhi/dx0)^-1 dPhi/dp, and y(t*) = Y(x0*, p) then gives
dy/dp = dY/dx0 dx0*/dp + dY/dp. The Jacobians are forward sensitivities of CVODES (forward mode
is asked for: adjoints through the contact fail), from a periodic state found to 1000 rtol.

Each derivative carries an error estimate (unless ``error_estimate=False``): the same derivative at
ten times the tolerance, its periodic state found anew, compared. A peak's derivative can be a
near-cancellation: at constant speed a journal on its wall moves along the joint force when the
clearance or the contact stiffness changes, so the torque's explicit dependence on the contact force
and its dependence through the journal's position cancel to 1e-5 (clearance) or 1e-7 (stiffness) of
their size, and the integrator's error in the sensitivities decides the result. The estimate is the
error of the looser run, so it is an upper one: a ``resolved`` row (estimate at most 1 %) can be
trusted; one that is not is below what this tolerance verifies, and a smaller rtol may resolve it
(docs/measurements.md measures where)."""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from .compile_cache import use_jit
from .cvodes_fsa import ForwardSensitivities, FsaError, built
from . import checks as chk
from .interrupt import compiling, interruptible
from .model import OUTPUT_NAMES, PressModel, build_model
from .params import check_parameter
from .result import SimResult
from .simulate import (HINT, MAX_RTOL, direct_driver, Integrator, SimulationError, calling, compiled_dae,
                       first_line, for_repeated_use, periodic_state, simulate)
from .sensitivity_cycle import (PERIODIC_TOL, SAMPLES, SensitivityCycle, output_jacobian, parameter_scale,
                                parameter_seeds, refined, sensitivity_cycle, state_motion)
from .speed import FourierSpeed

if TYPE_CHECKING:
    import pandas as pd

#: Quantities (peak magnitudes) and the model output they are the peak of.
QUANTITIES = {"peak_torque": "torque", "peak_slider_normal_force": "slider_normal_force",
              "peak_crank_pin_force": "crank_pin_force", "peak_wrist_pin_force": "wrist_pin_force"}
#: A second sample within this relative distance of the peak, away from it, makes the peak not unique.
UNIQUE_TOL = 1e-3
#: Within this share of the period of a peak the error estimate's run finds the same peak.
NEAR = 0.005
#: The error estimate compares the derivatives with those at this many times rtol.
LOOSER = 10.0
#: A derivative whose error estimate (relative) is at most this is ``resolved``.
RESOLVED = 0.01
#: CVODES options of the forward-sensitivity integration. Without the second-order correction of the
#: augmented system's Newton matrix (each direction solved with the states' own factorisation) the
#: seed optimum's 11 directions over one cycle at rtol 1e-10 took 8.6 s instead of 31.5 s, the
#: derivatives the same to 1e-8; CasADi's ``sensitivity_method`` and ``fsens_err_con`` changed
#: nothing, GMRES was slower (docs/measurements.md, "AD sensitivities on the seed optimum").
SENSITIVITY_OPTIONS = {"second_order_correction": False}
#: `Sensitivities.engine` of the compiled CVODES driver, the directions integrated with the states as one
#: system (`pressocp.cvodes_fsa`).
ENGINE_FSA = "cvodes fused (compiled)"
#: `Sensitivities.unverified` without an error estimate.
NO_ESTIMATE = "no error estimate was asked for (error_estimate=False)"
#: `Sensitivities.engine` of CasADi's forward integrator (the augmented system).
ENGINE_CASADI = "casadi forward"


@dataclass
class Sensitivities:
    """Derivatives of peak quantities with respect to press parameters.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per (quantity, parameter): ``value`` (the peak, N m or N), ``parameter_value`` (SI),
        ``derivative`` (dJ/dp at the largest peak, unit of J per unit of p), ``normalised``
        (p / J dJ/dp, dimensionless: the % change of J per % change of p), ``time`` (s, the peak's
        time within the cycle, located between samples by a parabola), ``peaks`` (local maxima
        within `UNIQUE_TOL` of the largest), ``unique`` (one such peak). When there are several (a
        min-max optimum equalises them), J is their maximum and its derivative is one-sided:
        ``derivative_up`` (p increasing: the largest of their derivatives) and ``derivative_down``
        (p decreasing: the smallest) hold for an exact tie; `change` predicts a finite step.
        ``error_estimate`` (relative: the largest change of a rival peak's derivative when rtol is
        loosened tenfold, an upper estimate of the error at rtol) and ``resolved`` (it is at most
        `RESOLVED`).
    per_peak : pandas.DataFrame
        One row per (quantity, rival peak, parameter): ``time`` (s), ``value``, ``derivative``,
        ``error_estimate``.
    periodic : bool
        Whether the derivatives include the motion of the periodic state.
    wall_time : float
        s.
    unverified : str
        Empty, or why there is no error estimate (none was asked for, or the run at ten times rtol
        failed: through impacts its periodic search can stall above its tolerance); every
        ``error_estimate`` is then inf.
    engine : str
        What integrated the sensitivities: ``ENGINE_FSA`` (CVODES compiled with the model, the
        directions integrated with the states as one system: `pressocp.cvodes_fsa`) or
        ``ENGINE_CASADI`` (CasADi's forward integrator: where the former cannot be built, which a
        warning says: `kept_fsa`).
    """

    table: pd.DataFrame
    per_peak: pd.DataFrame
    periodic: bool
    wall_time: float
    unverified: str = ""
    engine: str = ""

    def change(self, quantity: str, parameter: str, dp: float) -> float:
        """First-order change of J for a step `dp` of the parameter (its unit): the new maximum of
        the rival peaks, each moved by its own derivative, minus J."""
        rows = self.per_peak[(self.per_peak["quantity"] == quantity) & (self.per_peak["parameter"] == parameter)]
        if rows.empty:
            raise KeyError(f"no row for {quantity!r} and {parameter!r}")
        return float(np.max(rows["value"] + dp * rows["derivative"]) - rows["value"].max())

    def derivative(self, quantity: str, parameter: str) -> float:
        """dJ/dp of one pair."""
        row = self.table[(self.table["quantity"] == quantity) & (self.table["parameter"] == parameter)]
        if row.empty:
            raise KeyError(f"no row for {quantity!r} and {parameter!r}")
        return float(row["derivative"].iloc[0])


def peak_times(t: np.ndarray, y: np.ndarray, period: float) -> list[float]:
    """Times of max |y| and of every other local maximum within `UNIQUE_TOL` of it and more than 1 %
    of the period away from it (the maximum first; one entry: the maximum is unique), each located
    between samples by a parabola."""
    mag = np.abs(y)
    k = int(np.argmax(mag))
    inner = np.flatnonzero((mag[1:-1] >= mag[:-2]) & (mag[1:-1] >= mag[2:])) + 1
    rivals = inner[mag[inner] >= (1.0 - UNIQUE_TOL) * mag[k]]
    times = [refined(t, mag, k)]
    for i in sorted(rivals, key=lambda i: -mag[i]):
        gaps = [min(abs(t[i] - s), period - abs(t[i] - s)) for s in times]
        if min(gaps) > 0.01 * period:
            times.append(refined(t, mag, int(i)))
    return times


def sensitivity_dae(dae: dict) -> dict | ca.Function:
    """The explicit ODE for the sensitivity integrator: a Function compiled with its derivatives and
    called through MX (`pressocp.simulate.calling`, so that the states' own right-hand side runs
    compiled too) when a C compiler is found, else the DAE dict as it is. CasADi's virtual machine
    evaluates the forward derivatives of the contact model slowly: on the seed optimum 11 directions
    over one cycle took 8.9 s interpreted and 1.5 s compiled, the same derivatives; the MX call took
    the whole `sensitivities` of 3 parameters from 8.6 to 7.2 s (2026-11-26)."""
    return calling(compiled_dae(dae)) if use_jit("auto", "the sensitivities' right-hand side") else dae


def kept_sensitivity_dae(msym: PressModel) -> dict | ca.Function:
    """`sensitivity_dae` of `msym`, built once and kept with it (for the run at rtol, the short runs to
    the peaks and the estimate's run)."""
    if "sensitivity_dae" not in msym.functions:
        msym.functions["sensitivity_dae"] = sensitivity_dae(msym.dae(explicit=True, work=False))
    return msym.functions["sensitivity_dae"]


def kept_fsa(msym: PressModel, n_parameters: int) -> ForwardSensitivities | None:
    """The compiled forward-sensitivity integrator of `msym` (`pressocp.cvodes_fsa`), built once and
    kept with it; None where it cannot be built (no C compiler, no CasADi 3.8 CVODES library, or a
    failed compile or load), which a warning says once per model: the sensitivities then run through
    CasADi's forward integrator."""
    if "cvodes_fsa" not in msym.functions:
        # the states and their nx + n_parameters directions as one system: on the seed optimum 2.2 x
        # faster than CVODES's staggered sensitivities (docs/decisions/2026-12-01-fused-sensitivities.md)
        fsa, why = built(msym.dae(explicit=True, work=False), n_parameters, msym.nx + n_parameters)
        if fsa is None:
            warnings.warn(f"compiled forward sensitivities unavailable ({why}): CasADi's forward integrator "
                          "runs them (on the seed optimum its period took 4-5 x as long, the whole call "
                          "about 4 x)", RuntimeWarning, stacklevel=3)
        msym.functions["cvodes_fsa"] = fsa
    return msym.functions["cvodes_fsa"]


def peak_derivatives(msym: PressModel, speed: FourierSpeed, targets: Sequence[tuple[float, int]], x0: np.ndarray,
                     n_parameters: int, rtol: float, periodic: bool,
                     nominal: dict[float, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray, str]:
    """Outputs y at given times and sign(y) dy/dp, by forward sensitivities of one period from `x0`.

    The sensitivities come from CVODES compiled with the model (`kept_fsa`), which integrates the
    states and the directions as one system; else from CasADi's forward integrator called directly,
    which integrates the states too but returns only the directions, so the states at the targets'
    times come from `nominal` (else one plain run of the period). On the seed optimum at rtol 3e-9
    the 11 directions took 0.18 s compiled against 0.74 s through CasADi's forward integrator in the
    same run (`benchmarks/results/sensitivity_seed.json`, ``engine_periods``).

    Parameters
    ----------
    msym : PressModel
        The model with its last `n_parameters` parameters as symbols.
    speed : FourierSpeed
    targets : sequence of (float, int)
        (time within the period in s, index in `OUTPUT_NAMES`) of each output.
    x0 : ndarray
        Scaled start state (the periodic state when `periodic`).
    n_parameters : int
    rtol : float
        CVODES tolerance (relative, and absolute on the scaled states; the directions' from the
        states' in their units, `parameter_scale`).
    periodic : bool
        Include the motion of the periodic state, dx0/dp = (I - dPhi/dx0)^-1 dPhi/dp.
    nominal : dict, optional
        Scaled states at each target time other than 0 (`states_from_samples`), from a run at `rtol`
        from `x0`: read by CasADi's forward integrator only.

    Returns
    -------
    y : ndarray, shape (len(targets),)
    d : ndarray, shape (len(targets), n_parameters)
    engine : str
        `ENGINE_FSA` or `ENGINE_CASADI`.
    """
    T, nx = speed.period, msym.nx
    times = sorted({t for t, _ in targets if t > 0.0})
    grid = [*times, T] if not times or times[-1] < T else times
    pv = msym.parameters(speed)
    n_speed = pv.size - n_parameters
    # differentiated with respect to q = p / scale: the directions' states are then of the states'
    # own size, and the error control weighs them alike
    scale = parameter_scale(pv[n_speed:])
    nd = nx + n_parameters
    fsa = kept_fsa(msym, n_parameters)
    if fsa is not None:
        Q = parameter_seeds(nx, scale)
        try:  # Ctrl-C stops it (KeyboardInterrupt)
            X, S, _ = fsa.run(x0, pv, np.eye(nx, nd), Q, np.array(grid), rtol)
        except FsaError as err:
            raise SimulationError(str(err), time=err.time, method="cvodes (sensitivities)", hint=HINT) from None
        nominal, engine = {t: X[:, grid.index(t)] for t in times}, ENGINE_FSA
    else:
        S, engine = casadi_forward(msym, grid, x0, pv, scale, rtol), ENGINE_CASADI
        if nominal is None:
            X = integrated(msym.functions["sensitivity_period"], x0=x0, p=pv)["xf"]
            nominal = {t: X[:, grid.index(t)] for t in times}
    S[:, nx:, :] /= scale[:, None]
    dx0 = state_motion(S[:, :, -1], periodic)
    Y = output_jacobian(msym)
    y, d = np.empty(len(targets)), np.empty((len(targets), n_parameters))
    for k, (t, i) in enumerate(targets):
        x, St = (x0, np.eye(nx, nd)) if t == 0.0 else (nominal[t], S[:, :, grid.index(t)])
        values, y_x, y_q = (np.asarray(v) for v in Y(t, x, pv[:n_speed], pv[n_speed:]))
        y[k] = values[i, 0]
        d[k] = np.sign(y[k]) * (y_x[i] @ (St[:, :nx] @ dx0 + St[:, nx:]) + y_q[i])
    return y, d, engine


def casadi_forward(msym: PressModel, grid: list[float], x0: np.ndarray, pv: np.ndarray, scale: np.ndarray,
                   rtol: float) -> np.ndarray:
    """The directions (nx, nx + n_parameters, len(grid)) of one period from `x0` by CasADi's forward
    integrator (the augmented system), the parameter directions in units of `scale`; the period's
    plain integrator is kept in ``msym.functions["sensitivity_period"]``."""
    nx, n_parameters = msym.nx, scale.size
    nd = nx + n_parameters
    with compiling():  # the compiled DAE's derivatives are compiled as these are built
        F = ca.integrator("period", "cvodes", kept_sensitivity_dae(msym), 0.0, grid,
                          {"reltol": rtol, "abstol": rtol, "max_num_steps": 10**7, **SENSITIVITY_OPTIONS})
        forward = F.forward(nd)
    # holding the forward integrator holds the derivative functions CasADi built of the compiled DAE,
    # which it would otherwise free and build again (about 0.8 s) for the next integrator of this model
    msym.functions["sensitivity_forward"], msym.functions["sensitivity_period"] = forward, F
    seeds_p = np.zeros((pv.size, nd))
    seeds_p[pv.size - n_parameters:, nx:] = np.diag(scale)
    # the nominal outputs, an input of the forward integrator that it does not read, are left zero
    S = integrated(forward, x0=x0, p=pv, fwd_x0=np.eye(nx, nd), fwd_p=seeds_p)["fwd_xf"]
    return S.reshape(nx, nd, len(grid))  # the directions' states at each grid time, direction by direction


def states_from_samples(msym: PressModel, speed: FourierSpeed, t: np.ndarray, X: np.ndarray, times: Sequence[float],
              rtol: float) -> dict[float, np.ndarray]:
    """Scaled states at `times` (s, in [t[0], t[-1]]) of the run sampled as `X` (scaled, one column per
    entry of `t`): each integrated at `rtol` from the last sample before it (a few steps over less
    than a sample's spacing), or that sample when it falls on one."""
    pv = msym.parameters(speed)
    out = {}
    for ts in times:
        k = int(np.searchsorted(t, ts, side="right")) - 1
        if t[k] == ts or ts <= 0.0:
            out[ts] = X[:, k]
            continue
        short = ca.integrator("to_peak", "cvodes", kept_sensitivity_dae(msym), float(t[k]), [float(ts)],
                              {"reltol": rtol, "abstol": rtol, "max_num_steps": 10**6})
        out[ts] = integrated(short, x0=X[:, k], p=pv)["xf"].ravel()
    return out


def integrated(F: ca.Function, **args: np.ndarray) -> dict[str, np.ndarray]:
    """The outputs of the integrator `F` at `args` (a plain call: a forward integrator's inputs that it
    does not read are sparse, which `pressocp.buffers.call` does not take); Ctrl-C stops it, and its
    failure raises `SimulationError`."""
    try:
        with interruptible():
            return {k: np.asarray(v) for k, v in F(**args).items()}
    except RuntimeError as err:
        raise SimulationError(first_line(err), method="cvodes (sensitivities)", hint=HINT) from None


def sensitivities(model: PressModel, speed: FourierSpeed, parameters: Sequence[str],
                  quantities: Sequence[str] = ("peak_torque",), periodic: bool = True,
                  rtol: float = 1e-10, error_estimate: bool = True) -> Sensitivities:
    """dJ/dp of peak quantities J of the response of `model` to `speed`, for press parameters p.

    Parameters
    ----------
    model : PressModel
        A model with states (`build_model`); it is rebuilt with `parameters` as symbols.
    speed : FourierSpeed
    parameters : sequence of str
        Dotted names in `pressocp.params.NUMERIC_PARAMETERS` (``"slider_mass"``, ``"wrist_pin.clearance"``,
        ``"crank_pin.stiffness"``, ...).
    quantities : sequence of str
        Keys of `QUANTITIES`.
    periodic : bool
        Differentiate the periodic steady state (True) or the first cycle from the model's rest state.
    rtol : float
        Integrator tolerance (CVODES), also of the periodic search, in (0, `MAX_RTOL` / `LOOSER`) = (0, 1e-3):
        the error estimate runs at `LOOSER` times it.
    error_estimate : bool
        Compute the periodic state and the derivatives once more at ten times `rtol` and compare
        (``error_estimate`` and ``resolved`` in the table). That run costs about as much as the
        first (on the seed optimum at rtol 1e-8: 0.49 s with it, 0.2-0.3 s without). Without it every ``error_estimate``
        is inf, no row is ``resolved`` and `Sensitivities.unverified` says why: for a study that
        has checked the tolerance once (`benchmarks/bench_sensitivity_seed.py` measures the error
        at each rtol against central differences) and repeats the call many times.

    Returns
    -------
    Sensitivities

    Raises
    ------
    ValueError
        An unknown parameter or quantity, a tolerance out of its range, a model without states (checked
        before integrating).
    SimulationError
        The periodic search or the integration failed.
    """
    t_start = time.perf_counter()
    chk.in_open_interval("rtol", rtol, 0.0, MAX_RTOL / LOOSER)
    names = tuple(check_parameter(n) for n in parameters)
    if not names:
        raise ValueError("parameters must name at least one press parameter")
    for q in quantities:
        if q not in QUANTITIES:
            raise ValueError(f"quantity {q!r} is not one of {', '.join(QUANTITIES)}")
    if model.is_rigid:
        raise ValueError("the model has no states: differentiate the closed-form rigid response instead")
    msym = sensitivity_model(model, names)
    pv = msym.parameters(speed)
    fsa = kept_fsa(msym, len(names))
    if fsa is not None and direct_search(model):
        peaks, y, d, errors, unverified = compiled(model, msym, fsa, speed, quantities, rtol, periodic,
                                                   error_estimate)
        engine = ENGINE_FSA
    else:
        peaks, y, d, errors, unverified, engine = searched(model, msym, speed, quantities, rtol, periodic,
                                                           error_estimate)
    rows, per_peak = sensitivity_rows(peaks, names, pv[pv.size - len(names):], y, d, errors)
    import pandas as pd  # 0.5 s to import: only where a table is made

    return Sensitivities(pd.DataFrame(rows), pd.DataFrame(per_peak), periodic, time.perf_counter() - t_start,
                         unverified, engine)


def compiled(model: PressModel, msym: PressModel, fsa: ForwardSensitivities, speed: FourierSpeed,
             quantities: Sequence[str], rtol: float, periodic: bool,
             error_estimate: bool) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, str]:
    """The peaks of each quantity, their values y, derivatives d and error estimates (and why there are
    none, or "") through the compiled driver: the peaks located on the cycle that carries the
    directions (`pressocp.sensitivity_cycle`), the estimate the same at `LOOSER` times rtol, each
    peak's derivative there read at that run's own peak nearest it."""
    T = speed.period
    cycle = sensitivity_cycle(model, msym, fsa, speed, rtol, periodic)
    peaks, targets = located(cycle.response, cycle.response.t, quantities, T)
    y, d = at_peaks(cycle, msym, speed, targets)
    if not error_estimate:
        return peaks, y, d, np.full(d.shape, np.inf), NO_ESTIMATE
    try:
        # one plain cycle more before its Newton steps: its periodic state's error is then not the
        # main run's (the same steps from the same start would repeat it, and the derivatives at
        # constant speed moved by 0.3 % with a residual of 1e-10)
        loose = sensitivity_cycle(model, msym, fsa, speed, LOOSER * rtol, periodic, extra_cycles=1)
    except SimulationError as err:  # no estimate: every derivative is unverified, and says why
        return peaks, y, d, np.full(d.shape, np.inf), failed_estimate(err)
    # each peak read where the looser run has it: its time moves with the tolerance by microseconds,
    # and the derivative with it (`pressocp.sensitivity_cycle`)
    d_loose = at_peaks(loose, msym, speed, [(loose.peak_near(i, t, NEAR * T), i) for t, i in targets])[1]
    return peaks, y, d, relative(d, d_loose), ""


def located(res: SimResult, t: np.ndarray, quantities: Sequence[str],
            period: float) -> tuple[dict[str, list[float]], list[tuple[float, int]]]:
    """The peak times of each quantity on the sampled response `res` (times `t` within the cycle, s),
    and the (time, output index) of every one of them."""
    peaks = {q: [min(max(tq, 0.0), period) for tq in peak_times(t, getattr(res, QUANTITIES[q]), period)]
             for q in quantities}
    return peaks, [(tq, OUTPUT_NAMES.index(QUANTITIES[q])) for q in quantities for tq in peaks[q]]


def at_peaks(cycle: SensitivityCycle, msym: PressModel, speed: FourierSpeed,
             targets: Sequence[tuple[float, int]]) -> tuple[np.ndarray, np.ndarray]:
    """Values and derivatives at each (time, output index) of `targets` on `cycle`."""
    y, d = np.empty(len(targets)), np.empty((len(targets), cycle.dx0.shape[1]))
    for k, (t, i) in enumerate(targets):
        y[k], d[k] = cycle.at_peak(msym, speed, t, i)
    return y, d


def searched(model: PressModel, msym: PressModel, speed: FourierSpeed, quantities: Sequence[str], rtol: float,
             periodic: bool, error_estimate: bool) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, str, str]:
    """As `compiled`, with the engine's name, where the compiled driver of the directions or of the
    periodic search cannot be built: the peaks located on a sampled periodic run by CasADi's CVODES,
    the directions integrated to them (`peak_derivatives`). The peaks of that run are microseconds
    from those of the run with directions, which costs accuracy: read so, the compiled driver's
    derivatives on the seed optimum were 0.9 % off at rtol 1e-8 and 4.8 % at 3e-8, against 0.27 % and
    0.47 % at its own peaks (this engine: 0.24 % at 3e-9, `benchmarks/results/sensitivity_seed.json`)."""
    T = speed.period
    fsa = kept_fsa(msym, len(msym.symbols))  # built (or not) already
    search = (for_repeated_use(model), "cvodes")
    # periodic: the search's last cycle is the sampled response (one cycle fewer than a search and a run)
    res = simulate(search[0], speed, periodic=periodic, n_out=SAMPLES, work=False,
                   integrator=Integrator(search[1], rtol, periodic_tol=PERIODIC_TOL * rtol))
    x0 = res.states[:, 0] / model.x_scale
    t_rel = res.t - res.t[0]
    peaks, targets = located(res, t_rel, quantities, T)
    # the states at the peaks: the compiled driver integrates them; CasADi's forward integrator
    # does not return them, so they come from the sampled response
    nominal = None if fsa is not None else states_from_samples(
        msym, speed, t_rel, res.states / model.x_scale[:, None], [t for t, _ in targets], rtol)
    y, d, engine = peak_derivatives(msym, speed, targets, x0, len(msym.symbols), rtol, periodic, nominal)
    if not error_estimate:
        return peaks, y, d, np.full(d.shape, np.inf), NO_ESTIMATE, engine
    errors, unverified = estimated_errors(search, msym, speed, targets, x0, d, rtol, periodic)
    return peaks, y, d, errors, unverified, engine


def relative(d: np.ndarray, d_other: np.ndarray) -> np.ndarray:
    """|d - d_other| / |d| (inf-free where d = 0: divided by the smallest positive float)."""
    return np.abs(d - d_other) / np.maximum(np.abs(d), np.finfo(float).tiny)


def failed_estimate(err: SimulationError) -> str:
    """`Sensitivities.unverified` when the run at `LOOSER` times rtol failed."""
    return f"the run at {LOOSER:g} rtol failed: {str(err).splitlines()[0]}"


def direct_search(model: PressModel) -> bool:
    """Whether `model`'s own compiled CVODES driver (`pressocp.simulate.direct_driver`) builds, for the
    periodic searches; a warning says why not when it does not."""
    try:
        direct_driver(model, False)
        return True
    except ValueError as err:
        warnings.warn(f"{err}: the periodic search runs on CasADi's CVODES", RuntimeWarning, stacklevel=3)
        return False


def sensitivity_model(model: PressModel, names: tuple[str, ...]) -> PressModel:
    """`model` with the parameters `names` as symbols, kept with it: a study differentiating one model
    again reuses its built derivatives (about 1 s of building per call)."""
    key = ("sensitivity_model", names, model.params)
    if key not in model.functions:
        model.functions[key] = build_model(model.params, model.rod, model.clearance, model.n_elements,
                                           model.n_harmonics, names, n_modes=model.n_modes,
                                           mechanism=model.mechanism)
    return model.functions[key]


def estimated_errors(search: tuple[PressModel, str], msym: PressModel, speed: FourierSpeed,
                     targets: Sequence[tuple[float, int]], x0: np.ndarray, d: np.ndarray, rtol: float,
                     periodic: bool) -> tuple[np.ndarray, str]:
    """Relative error estimates of the derivatives `d` (computed from `x0` at `rtol`, `peak_derivatives`):
    |d - d'| / |d| with d' the same derivatives at `LOOSER` times rtol from a periodic state found
    anew at that tolerance (by the model and integrator method of `search`); and "" or, when that run
    fails, inf for every entry and why."""
    # the estimate repeats everything at the looser tolerance, the periodic state included (found anew
    # from the model's start): on the wall of a stiff contact its error moves a small derivative most
    try:
        loose = Integrator(search[1], LOOSER * rtol)
        x_loose = periodic_state(search[0], speed, loose, tol=PERIODIC_TOL * loose.rtol)[0] if periodic else x0
        d_loose = peak_derivatives(msym, speed, targets, x_loose, d.shape[1], LOOSER * rtol, periodic)[1]
    except SimulationError as err:  # no estimate: every derivative is unverified, and says why
        return np.full(d.shape, np.inf), failed_estimate(err)
    return relative(d, d_loose), ""


def sensitivity_rows(peaks: dict, names: tuple[str, ...], values: np.ndarray, y: np.ndarray, d: np.ndarray,
                     errors: np.ndarray) -> tuple[list[dict], list[dict]]:
    """The rows of `Sensitivities.table` (one per quantity and parameter, at its first peak) and of
    ``per_peak``, from the peak times of each quantity (`peaks`), the parameters' `names` and
    `values`, and the values `y`, derivatives `d` and error estimates `errors` at every peak (rows in
    the order of `peaks`, columns per parameter)."""
    rows, per_peak = [], []
    i = 0
    for q, times in peaks.items():
        k = slice(i, i + len(times))
        i += len(times)
        yq, dq, eq = y[k], d[k], errors[k]
        value = float(abs(yq[0]))
        for j, n in enumerate(names):
            pval = float(values[j])
            per_peak += [{"quantity": q, "parameter": n, "time": tk, "value": float(abs(yk)), "derivative": float(dk),
                          "error_estimate": float(ek)} for tk, yk, dk, ek in zip(times, yq, dq[:, j], eq[:, j])]
            rows.append({"quantity": q, "parameter": n, "value": value, "parameter_value": pval,
                         "derivative": float(dq[0, j]), "derivative_up": float(dq[:, j].max()),
                         "derivative_down": float(dq[:, j].min()),
                         "normalised": float(dq[0, j]) * pval / value if value else float("nan"),
                         "error_estimate": float(eq[:, j].max()), "resolved": bool(eq[:, j].max() <= RESOLVED),
                         "time": times[0], "peaks": len(times), "unique": len(times) == 1})
    return rows, per_peak


__all__ = ["QUANTITIES", "Sensitivities", "peak_times", "sensitivities"]
