"""Reference: the six-bar drag-link press's kinematics in numpy, written separately from
`pressocp.mechanism.six_bar` (the package's first implementation, kept as the test reference).

Kinematics of input crank → ram.

Mechanism
---------
An input crank (driven at constant speed) drives a *drag-link* four-bar
(ground link shortest, Grashof, so input and output cranks both turn fully
round).  The four-bar's output link is rigidly keyed to the crank (arm) of an
ordinary in-line slider-crank press on the same output axis; the arm may sit at
a phase angle relative to the output link.  The slider-crank's connecting rod
drives the ram.

Frame and sign conventions (the same as the rest of ``pressocp``)
-----------------------------------------------------------------
* ``y`` runs along the slide pointing away from the bed ("up"), ``x`` is
  perpendicular; the output (press-crank) axis is the origin, the slide line is
  ``x = 0`` and the ram lies below the crank axis.
* Every link angle in this module is a *clock angle*: measured from ``+y``,
  positive clockwise, so a point at radius ``r`` and angle ``q`` about an axis
  sits at ``axis + r (sin q, cos q)``.  Input crank, output link and press
  crank all turn the same way (increasing angle, clockwise).
* ``psi`` is the press-crank (arm) angle, ``psi = 0`` at top dead centre, and
  the ram height above bottom dead centre is
  ``h = r cos(psi) - sqrt(l**2 - r**2 sin(psi)**2) + r + l``, so ``h = H = 2 r``
  at ``psi = 0`` and ``h = 0`` at ``psi = pi``.
* The *input angle* ``theta`` passed to the public functions is the input-crank
  angle measured from the input-crank position at which the ram is at top
  dead centre (the phase offset is computed internally), so ``theta = 0`` gives
  ``h = H``.  ``psi(theta)`` is returned unwrapped: ``psi(0) = 0`` and
  ``psi(theta + 2 pi) = psi(theta) + 2 pi``.
* Ram velocity is ``dh/dt`` (negative on the downstroke).

The default dimensions were found by ``benchmarks/design_sixbar.py`` (rounded
to 0.1 mm / 0.01 deg and re-verified): at constant input speed the ram speed
stays within ±2.0 % of its mean (0.123 m/s at a 1 s cycle) while the ram moves
from 0.35 H down to 0.1 H on the downstroke; that zone takes 20.3 % of the
cycle, 2.2 times as long as in a plain crank press of the same stroke and cycle
time (zone speed ratio 0.458).  The four-bar transmission angle stays within
31.0..102.1 deg, and the output/input speed ratio varies over 0.40..1.86
(fast approach and return, bottom dead centre at 64 % of the cycle).
"""

from __future__ import annotations

import math

import numpy as np

from pressocp import checks as chk
from pressocp.mechanism.six_bar import SixBarPress

__all__ = [
    "sixbar_positions",
    "sixbar_kinematics",
    "sixbar_stroke",
    "working_zone_interval",
    "working_zone_speed",
]

_TWO_PI = 2.0 * math.pi


def _wrap(x: np.ndarray | float) -> np.ndarray:
    """Wrap angles (rad) to [-pi, pi)."""
    return np.mod(np.asarray(x, dtype=float) + math.pi, _TWO_PI) - math.pi


def theta_offset(press: SixBarPress) -> float:
    """Input-crank clock angle (rad) at which the ram is at top dead centre."""
    # psi = phi + arm_phase = 0  ->  output-link clock angle phi = -arm_phase.
    return float(_input_from_output(press, np.array([-float(press.arm_phase)]))[0])


def lag_mid(press: SixBarPress) -> float:
    """Midpoint (rad) of the range of psi(theta) - theta, used for unwrapping."""
    th = np.linspace(0.0, _TWO_PI, 2049)
    raw = _fourbar(press, th + theta_offset(press))["phi"] + float(press.arm_phase) - th
    lag = np.unwrap(_wrap(raw))
    lag -= _TWO_PI * np.round(lag[0] / _TWO_PI)  # psi(0) = 0 exactly (up to round-off)
    lo, hi = float(lag.min()), float(lag.max())
    if hi - lo > 1.8 * math.pi:
        raise RuntimeError("output/input phase lag varies by almost 2*pi; cannot unwrap psi uniquely")
    return 0.5 * (lo + hi)


# ---------------------------------------------------------------------- four-bar
def _fourbar(press: SixBarPress, theta_abs: np.ndarray) -> dict[str, np.ndarray]:
    """Four-bar position, velocity and acceleration analysis.

    Works in the "clock" frame (u, v) = (y, x), in which clock angles are
    ordinary counter-clockwise angles, with the output axis at the origin.

    Parameters
    ----------
    press : SixBarPress
    theta_abs : ndarray
        Input-crank clock angle, rad.

    Returns
    -------
    dict
        ``phi`` output-link clock angle (rad, wrapped), ``beta`` coupler clock
        angle (rad), ``dphi`` = dphi/dtheta, ``ddphi`` = d2phi/dtheta2,
        ``mu`` transmission angle (rad, in [0, pi]), ``A``/``B`` joint
        positions in (u, v), m.
    """
    g, a, b, c = (float(press.ground_length), float(press.input_crank), float(press.coupler),
                  float(press.output_link))
    gam = float(press.ground_angle)
    th = np.asarray(theta_abs, dtype=float)
    # Input axis O2 = -g e(gam); crank pin A = O2 + a e(theta).
    au = -g * math.cos(gam) + a * np.cos(th)
    av = -g * math.sin(gam) + a * np.sin(th)
    d2 = au * au + av * av
    d = np.sqrt(d2)
    delta = np.arctan2(av, au)
    cos_eps = np.clip((c * c + d2 - b * b) / (2.0 * c * d), -1.0, 1.0)
    phi = delta + press.assembly * np.arccos(cos_eps)
    bu = c * np.cos(phi)
    bv = c * np.sin(phi)
    beta = np.arctan2(bv - av, bu - au)
    # Velocity: a e'(th) + b beta' e'(beta) = c phi' e'(phi); dot with e(beta), e(phi).
    s_bp = np.sin(beta - phi)
    dphi = a * np.sin(beta - th) / (c * s_bp)
    dbeta = -a * np.sin(phi - th) / (b * np.sin(phi - beta))
    # Acceleration (theta'' = 0), dotted with e(beta):
    #   -a cos(th-beta) - b beta'^2 = c phi'' sin(beta-phi) - c phi'^2 cos(phi-beta)
    ddphi = (c * dphi**2 * np.cos(phi - beta) - a * np.cos(th - beta) - b * dbeta**2) / (c * s_bp)
    mu = np.arccos(np.clip((b * b + c * c - d2) / (2.0 * b * c), -1.0, 1.0))
    return {"phi": phi, "beta": beta, "dphi": dphi, "ddphi": ddphi, "mu": mu,
            "A": np.stack([au, av], -1), "B": np.stack([bu, bv], -1)}


def _input_from_output(press: SixBarPress, phi: np.ndarray) -> np.ndarray:
    """Inverse four-bar: input-crank clock angle (rad, wrapped) for output clock angle ``phi``.

    Of the two circle intersections the one lying on the press's assembly
    branch is returned (checked by re-running the forward analysis).
    """
    g, a, b, c = (float(press.ground_length), float(press.input_crank), float(press.coupler),
                  float(press.output_link))
    gam = float(press.ground_angle)
    phi = np.asarray(phi, dtype=float)
    o2 = np.array([-g * math.cos(gam), -g * math.sin(gam)])
    bu = c * np.cos(phi) - o2[0]
    bv = c * np.sin(phi) - o2[1]  # B relative to O2
    e2 = bu * bu + bv * bv
    e = np.sqrt(e2)
    base = np.arctan2(bv, bu)
    half = np.arccos(np.clip((a * a + e2 - b * b) / (2.0 * a * e), -1.0, 1.0))
    cands = np.stack([base + half, base - half])
    err = np.abs(_wrap(_fourbar(press, cands)["phi"] - phi[None, ...]))
    pick = np.argmin(err, axis=0)
    return _wrap(np.take_along_axis(cands, pick[None, ...], axis=0)[0])


# ------------------------------------------------------------------ slider-crank
def _slider(r: float, l: float, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ram height h (m) above BDC and its first/second derivatives w.r.t. psi (m/rad, m/rad²)."""
    sp, cp = np.sin(psi), np.cos(psi)
    s = np.sqrt(l * l - (r * sp) ** 2)
    ds = -r * r * sp * cp / s
    dds = -r * r * np.cos(2.0 * psi) / s - (r * r * sp * cp) ** 2 / s**3
    h = r * cp - s + r + l
    dh = -r * sp - ds
    ddh = -r * cp - dds
    return h, dh, ddh


# ------------------------------------------------------------------- public API
def sixbar_positions(press: SixBarPress, theta_in: np.ndarray | float) -> dict[str, np.ndarray]:
    """Joint positions of the six-bar press in the press frame.

    Parameters
    ----------
    press : SixBarPress
    theta_in : array_like
        Input angle, rad (0 = ram at top dead centre).

    Returns
    -------
    dict
        Arrays of shape ``theta_in.shape + (2,)`` holding (x, y) in m:
        ``"O2"`` input axis, ``"O4"`` output axis (origin), ``"A"`` input
        crank / coupler joint, ``"B"`` coupler / output-link joint, ``"C"``
        press-crank pin, ``"D"`` ram (rod / slider joint).
    """
    th = np.asarray(theta_in, dtype=float)
    fb = _fourbar(press, th + theta_offset(press))
    r, l = float(press.crank_radius), float(press.rod_length)
    psi = fb["phi"] + float(press.arm_phase)
    cx, cy = r * np.sin(psi), r * np.cos(psi)
    dy = cy - np.sqrt(l * l - cx * cx)

    def swap(p: np.ndarray) -> np.ndarray:
        """(u, v) = (y, x) -> (x, y)."""
        return p[..., ::-1]

    o2 = np.broadcast_to(press.input_axis, th.shape + (2,)).copy()
    return {
        "O2": o2,
        "O4": np.zeros(th.shape + (2,)),
        "A": swap(fb["A"]),
        "B": swap(fb["B"]),
        "C": np.stack([cx, cy], -1),
        "D": np.stack([np.zeros_like(dy), dy], -1),
    }


def sixbar_kinematics(press: SixBarPress, theta_in: np.ndarray | float) -> dict[str, np.ndarray]:
    """Ram and output-crank kinematics versus input angle (analytic derivatives).

    Parameters
    ----------
    press : SixBarPress
        Mechanism dimensions.
    theta_in : array_like
        Input-crank angle, rad, measured from the ram's top-dead-centre
        position (any shape; any real values, not necessarily sorted).

    Returns
    -------
    dict
        Arrays shaped like ``theta_in``:

        ``"psi"``            output/press-crank angle, rad, unwrapped, ``psi(0) = 0``
        ``"dpsi_dtheta"``    velocity ratio dpsi/dtheta, -
        ``"d2psi_dtheta2"``  d2psi/dtheta2, 1/rad
        ``"ram_height"``     h above bottom dead centre, m (``h(0) = H``)
        ``"dh_dtheta"``      dh/dtheta, m/rad
        ``"d2h_dtheta2"``    d2h/dtheta2, m/rad²
        ``"transmission_angle"``  four-bar transmission angle (coupler vs. output link), rad in [0, pi]
    """
    th = np.asarray(theta_in, dtype=float)
    fb = _fourbar(press, th + theta_offset(press))
    mid = lag_mid(press)
    psi = th + _wrap(fb["phi"] + float(press.arm_phase) - th - mid) + mid
    h, dh, ddh = _slider(float(press.crank_radius), float(press.rod_length), psi)
    w, dw = fb["dphi"], fb["ddphi"]
    return {
        "psi": psi,
        "dpsi_dtheta": w,
        "d2psi_dtheta2": dw,
        "ram_height": h,
        "dh_dtheta": dh * w,
        "d2h_dtheta2": ddh * w * w + dh * dw,
        "transmission_angle": fb["mu"],
    }


def sixbar_stroke(press: SixBarPress, period: float, n: int = 721) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ram motion over one cycle at constant input speed ``2 pi / period``.

    Parameters
    ----------
    press : SixBarPress
    period : float
        Cycle time (one input revolution), s.
    n : int, optional
        Number of samples, ``t`` from 0 to ``period`` inclusive (>= 2).

    Returns
    -------
    t : ndarray
        Time, s.
    h : ndarray
        Ram height above bottom dead centre, m (``h[0] = h[-1] = H``).
    v : ndarray
        Ram velocity dh/dt, m/s (negative on the downstroke).
    """
    period = chk.positive("period", period, "s")
    n = chk.integer("n", n, 2, 10_000_000)
    omega = _TWO_PI / period
    t = np.linspace(0.0, period, n)
    k = sixbar_kinematics(press, omega * t)
    return t, k["ram_height"], k["dh_dtheta"] * omega


def _zone_bounds(zone: tuple[float, float]) -> tuple[float, float]:
    if len(zone) != 2:
        raise ValueError(f"zone must be a pair (h/H start, h/H end) in (0, 1), got {zone!r}")
    z0 = chk.in_open_interval("zone[0]", zone[0], 0.0, 1.0)
    z1 = chk.in_open_interval("zone[1]", zone[1], 0.0, 1.0)
    if z0 == z1:
        raise ValueError(f"zone bounds must differ (h/H in (0, 1)), got {zone!r}")
    return max(z0, z1), min(z0, z1)


def _zone_angles(press: SixBarPress, zone: tuple[float, float]) -> tuple[float, float, float, float]:
    """Press-crank and input angles (rad) where the downstroke enters/leaves the zone."""
    hi, lo = _zone_bounds(zone)
    r, l, big_h = float(press.crank_radius), float(press.rod_length), press.stroke
    # Inverse slider-crank: y = h - r - l (ram below axis), cos psi = (y^2 + r^2 - l^2) / (2 y r).
    y = np.array([hi, lo]) * big_h - r - l
    psi = np.arccos(np.clip((y * y + r * r - l * l) / (2.0 * y * r), -1.0, 1.0))  # in (0, pi): downstroke
    th_abs = _input_from_output(press, psi - float(press.arm_phase))
    raw = _wrap(th_abs - theta_offset(press))
    # theta = psi - lag, lag unwrapped about its mid value.
    lag = _wrap(psi - raw - lag_mid(press)) + lag_mid(press)
    theta = psi - lag
    return float(psi[0]), float(psi[1]), float(theta[0]), float(theta[1])


def working_zone_interval(press: SixBarPress, period: float,
                          zone: tuple[float, float] = (0.35, 0.1)) -> tuple[float, float]:
    """Times at which the ram enters and leaves the working zone on the downstroke.

    Parameters
    ----------
    press : SixBarPress
    period : float
        Cycle time at constant input speed, s.
    zone : tuple of float, optional
        Ram heights as fractions of the stroke, ``h/H``, between which the zone
        lies (order irrelevant), each in (0, 1).  Default (0.35, 0.1).

    Returns
    -------
    t_start, t_end : float
        Times (s, within ``[0, period]``, measured from top dead centre) at
        which ``h`` passes the upper and the lower zone bound.
    """
    period = chk.positive("period", period, "s")
    _, _, th0, th1 = _zone_angles(press, zone)
    return th0 * period / _TWO_PI, th1 * period / _TWO_PI


def working_zone_speed(press: SixBarPress, period: float, zone: tuple[float, float] = (0.35, 0.1),
                       n: int = 2001) -> tuple[float, float]:
    """Mean ram speed in the downstroke working zone and its worst relative deviation.

    Parameters
    ----------
    press : SixBarPress
    period : float
        Cycle time at constant input speed ``2 pi / period``, s.
    zone : tuple of float, optional
        Zone bounds as fractions ``h/H`` (order irrelevant), each in (0, 1).
        Default (0.35, 0.1): from 0.35 H down to 0.1 H.
    n : int, optional
        Number of uniformly spaced samples in time across the zone used for
        the deviation (>= 2).

    Returns
    -------
    mean_speed : float
        Mean ram speed ``|dh/dt|`` over the zone, m/s (positive): the zone
        height divided by the time taken to cross it.
    max_rel_deviation : float
        ``max | |v(t)| - mean_speed | / mean_speed`` over the zone, -
        (0.05 means within ±5 %).
    """
    period = chk.positive("period", period, "s")
    n = chk.integer("n", n, 2, 10_000_000)
    hi, lo = _zone_bounds(zone)
    _, _, th0, th1 = _zone_angles(press, zone)
    omega = _TWO_PI / period
    mean_speed = (hi - lo) * press.stroke * omega / (th1 - th0)
    k = sixbar_kinematics(press, np.linspace(th0, th1, n))
    speed = -k["dh_dtheta"] * omega
    return float(mean_speed), float(np.max(np.abs(speed - mean_speed)) / mean_speed)
