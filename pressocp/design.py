"""Kinematic speed design for the rigid press.

* `design_speed`: a Fourier crank speed whose rigid ram velocity is constant over a working window
  on the downstroke (a small NLP in CasADi/IPOPT: smoothest speed that keeps the ram speed within
  a tolerance band; the least-squares error is the primary objective).
* `speed_for_ram_motion`: the crank speed that makes the four-bar follow a given ram motion
  (inverse kinematics, then a linear least-squares fit of the crank angle).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from . import checks as chk
from .params import PressParams
from .interrupt import interruptible
from .ipopt_options import IPOPT_DESIGN
from .mechanism import SLIDER_CRANK, Mechanism, SixBar, SixBarPress
from .mechanism.ideal import ideal_kinematics
from .model import build_model
from .problem import SpeedProblem
from .rigid import crank_angle_at_height
from .speed import DEFAULT_HARMONICS, FourierSpeed, series

@dataclass(frozen=True)
class SpeedDesign:
    """Result of `design_speed`.

    Attributes
    ----------
    speed : FourierSpeed
        The designed crank speed (theta0 = 0: top dead centre at t = 0).
    t1, t2 : float
        Times at which the ram enters and leaves the working window, s.
    ram_speed : float
        Target ram velocity in the window, m/s (negative).
    window : tuple of float
        (h1/H, h2/H) at entry and exit.
    max_error, rms_error : float
        Max and RMS of |v - ram_speed| / |ram_speed| on a dense grid over [t1, t2].
    min_omega : float
        Smallest crank speed over the period, rad/s.
    converged : bool
        Whether IPOPT reported success; when False, ``speed`` is the last iterate.
    status : str
        IPOPT return status.
    """

    speed: FourierSpeed
    t1: float
    t2: float
    ram_speed: float
    window: tuple[float, float]
    max_error: float
    rms_error: float
    min_omega: float
    converged: bool
    status: str


@dataclass(frozen=True)
class DesignSettings:
    """Settings of `design_speed`.

    Attributes
    ----------
    band : float
        Share of the problem's ram-speed tolerance held at the design's samples, in (0, 1]
        (0.5: the default problem's 1 % becomes a +-0.5 % band).
    samples : int
        Samples in the window (the period has 4x as many for the crank-speed bound), 10..5000.
    smoothing_weight : float
        Weight of the smoothness term (integral of the squared crank acceleration), >= 0.
    """

    band: float = 0.5
    samples: int = 200
    smoothing_weight: float = 1e-6

    def __post_init__(self) -> None:
        chk.in_closed_interval("band", self.band, 1e-6, 1.0)
        chk.integer("samples", self.samples, 10, 5000)
        chk.nonnegative("smoothing_weight", self.smoothing_weight)


def _window_trajectory(params: PressParams, period: float, ram_speed: float, window, n: int = 2000,
                       mechanism: Mechanism = SLIDER_CRANK):
    """A smooth crank-angle trajectory with the exact window motion: the design's initial guess.

    Inside the window theta follows the inverse kinematics of h = h1 + v (t - t1); outside, a
    cubic Hermite segment joins the window's exit to its entry one revolution later.
    Returns (t1, t, theta) with theta(0) = 0.
    """
    H = mechanism.stroke(params)
    w0, w1 = window
    tau = (w0 - w1) * H / abs(ram_speed)
    s = np.linspace(0.0, tau, n)
    th_w = mechanism.input_angle_at_height(params, w0 * H + ram_speed * s, "down")
    dth = lambda h: ram_speed / ideal_kinematics(  # noqa: E731
        params, mechanism, mechanism.input_angle_at_height(params, h, "down"), 1.0)["ram_velocity"]
    om0, om1 = dth(w0 * H), dth(w1 * H)
    # Hermite from (tau, th_w[-1], om1) to (period, th_w[0] + 2 pi, om0)
    d = period - tau
    u = np.linspace(0.0, 1.0, n)[1:-1]
    p0, p1 = th_w[-1], th_w[0] + 2 * np.pi
    h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
    th_o = h00 * p0 + h10 * d * om1 + h01 * p1 + h11 * d * om0
    t_local = np.concatenate([s, tau + u * d])
    th_local = np.concatenate([th_w, th_o])
    # shift time so that theta passes 2 pi (top dead centre) at t = 0
    t_tdc = np.interp(2 * np.pi, th_local, t_local)
    t = np.mod(t_local - t_tdc, period)
    theta = np.mod(th_local, 2 * np.pi)
    order = np.argsort(t)
    return float(np.mod(-t_tdc, period)), t[order], np.unwrap(theta[order])


def design_speed(problem: SpeedProblem, settings: DesignSettings | None = None) -> SpeedDesign:
    """Fourier crank speed that holds a constant rigid ram speed over the problem's working window.

    The window starts when the ram passes ``window[0]*H`` on the downstroke (time t1) and ends at
    ``window[1]*H`` (time t2 = t1 + (h1 - h2)/|v|). IPOPT minimises the mean squared relative ram
    speed error on the window plus ``settings.smoothing_weight`` times the normalised integral of
    the squared crank acceleration, subject to |v - ram_speed| <= band x tol at the samples and
    omega >= omega_min over the period; the mean speed is 2 pi/T by construction. The problem's
    objective, limits other than omega_min, and caps are not used: this is the kinematic design
    an optimisation starts from.

    Parameters
    ----------
    problem : SpeedProblem
        Press, period, ram speed, window, harmonics, tolerance and omega_min.
    settings : DesignSettings, optional

    Returns
    -------
    SpeedDesign
    """
    chk.instance("problem", problem, SpeedProblem)
    S = DesignSettings() if settings is None else chk.instance("settings", settings, DesignSettings)
    params, T, v, (w0, w1), n = problem.press, problem.period, problem.ram_speed, problem.window, problem.n_harmonics
    tol = S.band * problem.tol / abs(v)
    m = S.samples
    wmin = problem.omega_lower
    tau = problem.window_duration

    # initial guess: fit of an exact-window trajectory
    mechanism = problem.mechanism
    t1_0, t_g, th_g = _window_trajectory(params, T, v, (w0, w1), mechanism=mechanism)
    guess = _fit_theta(t_g, th_g, T, n)

    nlp = design_nlp(problem, S)
    solver = ca.nlpsol("design", "ipopt", nlp.problem, {**IPOPT_DESIGN, "jac_g": nlp.jac_g, "hess_lag": nlp.hess_lag})
    lbg = np.concatenate([-tol * np.ones(m), wmin * np.ones(4 * m), [0.0, 0.0]])
    ubg = np.concatenate([tol * np.ones(m), np.inf * np.ones(4 * m), [0.0, mechanism.bottom_dead_centre(params)]])
    with interruptible():
        sol = solver(x0=np.concatenate([guess.coefficients, [t1_0]]), lbg=lbg, ubg=ubg,
                     lbx=np.concatenate([-np.inf * np.ones(2 * n), [0.0]]),
                     ubx=np.concatenate([np.inf * np.ones(2 * n), [T - tau]]))
    stats = solver.stats()
    x = np.asarray(sol["x"]).ravel()
    speed = FourierSpeed.from_coefficients(T, x[: 2 * n])
    t1v = float(x[-1])
    max_err, rms_err = window_error(params, speed, t1v, t1v + tau, v, mechanism=mechanism)
    return SpeedDesign(
        speed=speed, t1=t1v, t2=t1v + tau, ram_speed=v, window=(w0, w1), max_error=max_err,
        rms_error=rms_err, min_omega=speed.min_speed(), converged=bool(stats["success"]),
        status=str(stats["return_status"]),
    )


@dataclass(frozen=True)
class DesignNlp:
    """The design NLP (`design_nlp`) with its constraint Jacobian and its Lagrangian Hessian, as the
    functions ``jac_g`` and ``hess_lag`` that `casadi.nlpsol` takes in place of its own."""

    problem: dict
    jac_g: ca.Function
    hess_lag: ca.Function


def design_nlp(problem: SpeedProblem, settings: DesignSettings) -> DesignNlp:
    """The design NLP in z = (Fourier coefficients, t1), with constraints (relative ram-speed errors at
    the window's samples, crank speeds over the period, h(t1)/H - w0, theta(t1)).

    Every sample is the same small SX function of z mapped over the samples, and so are its gradient
    and Hessian: the Jacobian and the exact Lagrangian Hessian are stacks and sums of per-sample
    kernels. CasADi's own Hessian of one SX expression over all 1000 samples is the same matrix, but
    took 7 s to build (1.1 M nodes): with it the seed design took 11.7 s, with the kernels 1.3 s, to
    the same optimum (1e-13; docs/optimisation.md).
    """
    params, T, v, n = problem.press, problem.period, problem.ram_speed, problem.n_harmonics
    m, H, w0, tau = settings.samples, problem.stroke, problem.window[0], problem.window_duration
    wbar = 2 * np.pi / T
    z = ca.SX.sym("z", 2 * n + 1)
    c, t1 = z[: 2 * n], z[2 * n]
    kinematics = problem.mechanism.kinematics_function(params)

    def at(t):
        th, om, al = series(t, c[:n], c[n:], T)
        return kinematics(theta=th, omega=om, alpha=al), th, om

    s, ts = ca.SX.sym("s"), ca.SX.sym("t")  # window fraction, time (s)
    err = at(t1 + tau * s)[0]["ram_velocity"] / v - 1
    omega = at(ts)[2]
    k = 2 * np.pi * np.arange(1, n + 1) / T
    smooth = settings.smoothing_weight * (T / 2) * ca.sumsqr(ca.vertcat(k, k) * c) * T / wbar**2  # int alpha^2 dt
    kin1, th1, _ = at(t1)
    ends = ca.vertcat(kin1["ram_height"] / H - w0, th1)
    # multipliers: sigma (objective), one per sample, two at the ends
    sig, lam, lam_end = ca.SX.sym("sigma"), ca.SX.sym("lambda"), ca.SX.sym("lambda_end", 2)
    h_err, g_err = ca.hessian(err, z)
    kernels = {
        "err": ca.Function("err", [s, z], [err, ca.jacobian(err, z)]),
        "omega": ca.Function("omega", [ts, z], [omega, ca.jacobian(omega, z)]),
        "ends": ca.Function("ends", [z], [ends, ca.jacobian(ends, z), smooth]),
        "h_err": ca.Function("h_err", [s, z, sig, lam],
                             [ca.triu((sig * 2 * err / m + lam) * h_err + (sig * 2 / m) * ca.mtimes(g_err, g_err.T))]),
        "h_omega": ca.Function("h_omega", [ts, z, lam], [ca.triu(lam * ca.hessian(omega, z)[0])]),
        "h_ends": ca.Function("h_ends", [z, sig, lam_end],
                              [ca.triu(ca.hessian(ca.dot(lam_end, ends) + sig * smooth, z)[0])]),
    }
    X, P = ca.MX.sym("x", z.numel()), ca.MX.sym("p", 0)
    sw = ca.DM(np.linspace(0.0, 1.0, m)).T
    tp = ca.DM(np.linspace(0.0, T, 4 * m, endpoint=False)).T
    e, je = kernels["err"].map(m)(sw, ca.repmat(X, 1, m))
    w, jw = kernels["omega"].map(4 * m)(tp, ca.repmat(X, 1, 4 * m))
    ge, jend, sm = kernels["ends"](X)
    g = ca.vertcat(e.T, w.T, ge)
    jac = ca.vertcat(ca.reshape(je, z.numel(), m).T, ca.reshape(jw, z.numel(), 4 * m).T, jend)
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.numel())

    def block_sum(blocks, count):  # the sum of `count` square blocks side by side
        return ca.mtimes(blocks, ca.repmat(ca.DM.eye(z.numel()), count, 1))

    hess = (block_sum(kernels["h_err"].map(m)(sw, ca.repmat(X, 1, m), lam_f, lam_g[:m].T), m)
            + block_sum(kernels["h_omega"].map(4 * m)(tp, ca.repmat(X, 1, 4 * m), lam_g[m : 5 * m].T), 4 * m)
            + kernels["h_ends"](X, lam_f, lam_g[5 * m :]))
    return DesignNlp(
        problem={"x": X, "f": ca.sumsqr(e) / m + sm, "g": g},
        jac_g=ca.Function("nlp_jac_g", [X, P], [g, jac], ["x", "p"], ["g", "jac_g_x"]),
        hess_lag=ca.Function("nlp_hess_l", [X, P, lam_f, lam_g], [ca.triu(hess)], ["x", "p", "lam_f", "lam_g"],
                             ["triu_hess_gamma_x_x"]),
    )


def window_error(params: PressParams, speed: FourierSpeed, t1: float, t2: float, ram_speed: float,
                 n: int = 4001, mechanism: Mechanism = SLIDER_CRANK) -> tuple[float, float]:
    """Max and RMS relative rigid ram speed error on a dense grid over [t1, t2]."""
    t = np.linspace(t1, t2, n)
    th, om, al = speed.evaluate(t)
    vr = ideal_kinematics(params, mechanism, th, om, al)["ram_velocity"]
    e = np.abs(vr / ram_speed - 1)
    return float(e.max()), float(np.sqrt(np.mean(e**2)))


def _fit_theta(t: np.ndarray, theta: np.ndarray, period: float, n: int) -> FourierSpeed:
    """Least-squares fit of a crank-angle history theta(t) by a Fourier speed (mean 2 pi/T, theta0 free)."""
    k = 2 * np.pi * np.arange(1, n + 1) / period
    S, C = np.sin(np.outer(t, k)), np.cos(np.outer(t, k))
    basis = np.hstack([np.ones((t.size, 1)), S / k, (1 - C) / k])
    coef = np.linalg.lstsq(basis, theta - 2 * np.pi / period * t, rcond=None)[0]
    return FourierSpeed(period, coef[1 : n + 1], coef[n + 1 :], theta0=coef[0])


def speed_for_ram_motion(
    params: PressParams,
    t: Any,
    h: Any,
    period: float | None = None,
    n_harmonics: int = DEFAULT_HARMONICS,
) -> FourierSpeed:
    """Crank speed that makes the four-bar follow a given periodic ram motion.

    The ram heights are inverted to crank angles (downstroke where h falls, upstroke where it
    rises, continuous through the dead centres), and the crank-angle history is fitted in the
    least-squares sense by a Fourier speed with mean 2 pi / T (no differentiation of the data).

    Parameters
    ----------
    params : PressParams
        The four-bar press.
    t : array-like
        Sample times over one period, s, increasing.
    h : array-like
        Ram height above bottom dead centre at those times, m, within [0, H]; one full stroke
        (one top and one bottom dead centre) per period.
    period : float, optional
        Period T, s; default ``t[-1] - t[0]``.
    n_harmonics : int
        Number of harmonics, 1..200.

    Returns
    -------
    FourierSpeed
        With theta0 fitted (the crank angle at t = 0).
    """
    t = chk.finite_array("t", t)
    h = chk.finite_array("h", h)
    if t.shape != h.shape:
        raise ValueError(f"t and h must have the same length, got {t.size} and {h.size}")
    n = chk.integer("n_harmonics", n_harmonics, 1, 200)
    if t.size < 2 * n + 1:
        raise ValueError(f"need at least 2*n_harmonics+1={2 * n + 1} samples, got {t.size}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("t must be strictly increasing")
    T = chk.positive("period", t[-1] - t[0] if period is None else period, "s")
    Hs = params.stroke
    if np.any(h < -1e-9 * Hs) or np.any(h > Hs * (1 + 1e-9)):
        raise ValueError(f"h must be within [0, {Hs:g}] m (the stroke of the four-bar)")
    # Branch from the sign of a centred difference (periodic neighbours when the samples close the
    # period): falling -> downstroke. At a sample next to a dead centre this picks the right side.
    closed = np.isclose(t[-1] - t[0], T, rtol=1e-9, atol=0.0)
    core = h[:-1] if closed else h
    fwd, bwd = np.roll(core, -1), np.roll(core, 1)
    if not closed:
        fwd[-1], bwd[0] = core[-1], core[0]
    falling = fwd - bwd < 0
    down = np.append(falling, falling[0]) if closed else falling
    th_down = crank_angle_at_height(params, np.clip(h, 0, Hs), "down")
    theta = np.where(down, th_down, 2 * np.pi - th_down)
    theta = np.unwrap(theta)
    return _fit_theta(t, theta, T, n)


def emulate_sixbar(params: PressParams, sixbar=None, period: float = 1.0, n_harmonics: int = DEFAULT_HARMONICS,
                   n: int = 2001) -> dict:
    """Crank speed that makes the four-bar `params` reproduce a six-bar press's stroke, and both
    presses' motion and motor torque on ideal joints, each from its model (`build_model`).

    Parameters
    ----------
    params : PressParams
        The four-bar (its stroke must equal the six-bar's). The six-bar's slider-crank part is the
        same press with the six-bar drive's crank radius and rod length.
    sixbar : SixBar or SixBarPress, optional
        Reference link press (`pressocp.mechanism.SixBar`, or its geometry alone: no input-crank or
        coupler inertia); default `SixBar()`.
    period : float
        Cycle time, s (constant input speed of the six-bar).
    n_harmonics : int
        Harmonics of the four-bar's speed.
    n : int
        Samples over the period.

    Returns
    -------
    dict
        ``t``, ``h_sixbar``, ``v_sixbar``, ``torque_sixbar`` (six-bar at constant input speed),
        ``speed`` (FourierSpeed), ``h_fourbar``, ``v_fourbar`` and ``torque_fourbar`` (the four-bar with
        that speed), ``max_position_error`` (m); heights m, velocities m/s, torques N m.
    """
    six = SixBar() if sixbar is None else SixBar(sixbar) if isinstance(sixbar, SixBarPress) else sixbar
    chk.instance("sixbar", six, SixBar)
    if not np.isclose(six.drive.stroke, params.stroke, rtol=1e-9):
        raise ValueError(f"the four-bar's stroke ({params.stroke:g} m) must equal the six-bar's ({six.drive.stroke:g} m)")
    period = chk.positive("period", period, "s")
    t = np.linspace(0.0, period, chk.integer("n", n, 2, 10_000_000))
    press6 = params.replace(crank_radius=six.drive.crank_radius, rod_length=six.drive.rod_length)
    y6 = build_model(press6, clearance=(), mechanism=six).ideal_series(FourierSpeed.constant(period), t)
    speed = speed_for_ram_motion(params, t, y6["ram_height"], period=period, n_harmonics=n_harmonics)
    y4 = build_model(params, clearance=(), n_harmonics=speed.n_harmonics).ideal_series(speed, t)
    return {"t": t, "h_sixbar": y6["ram_height"], "v_sixbar": y6["ram_velocity"], "torque_sixbar": y6["torque"],
            "speed": speed, "h_fourbar": y4["ram_height"], "v_fourbar": y4["ram_velocity"],
            "torque_fourbar": y4["torque"],
            "max_position_error": float(np.max(np.abs(y4["ram_height"] - y6["ram_height"])))}
