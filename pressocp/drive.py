"""The servo drive: a motor behind a gear, its torque-speed envelope, and a crank-side response in the
motor's terms (what a drive is sized by: peak and RMS torque against the ratings, speed, inertia
ratio, power, energy per stroke and the DC-bus energy swing).

Conventions: the gear turns the crank `gear_ratio` times slower than the motor (omega_motor = i
omega); motor torque is positive when it drives. Power through the gear loses (1 - efficiency) of
itself in either direction: driving, the motor gives tau_crank omega / eta; regenerating, it takes
back eta |tau_crank omega|. The motor and gear inertias act at the motor shaft, on top of the press
(`PressParams.crank_inertia` is then the crank's own). Motor losses are not modelled: the electrical
power is the motor's mechanical power.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from . import checks as chk

#: A motor above this speed, rad/s (about 30 000 rpm), is refused as a speed given in rpm.
MAX_MOTOR_SPEED = 3200.0
#: Above this speed, rad/s (about 10 500 rpm; press servo motors run up to about 6 000 rpm), a motor is
#: suspected of a speed given in rpm (`pressocp.checks.PlausibilityWarning`; ``--strict`` refuses it):
#: the usual rated speeds typed as rad/s, 1 500 to 3 000 rpm, land between the two limits (above
#: 3 200, the error of `MAX_MOTOR_SPEED`).
SUSPECT_MOTOR_SPEED = 1100.0


@dataclass(frozen=True)
class Drive:
    """A servo motor and its gear.

    Attributes
    ----------
    gear_ratio : float
        Motor speed over crank speed i, - (> 0).
    peak_torque : float
        The motor's peak torque up to its corner speed, N m.
    continuous_torque : float
        Its rated continuous (RMS) torque, N m, at most the peak torque.
    max_speed : float
        Its highest speed, rad/s (1000 rpm is 104.7 rad/s).
    power_limit : float or None
        Above the corner speed (power_limit / peak_torque, rad/s) the peak torque falls as
        power_limit / speed, W; None: flat up to max_speed.
    gear_efficiency : float
        eta in (0, 1].
    motor_inertia : float
        The rotor's inertia, kg m^2.
    gear_inertia : float
        The gear's inertia at the motor shaft, kg m^2 (>= 0).
    curve_speeds, curve_torques : tuple of float
        The peak-torque curve as points from the motor's data sheet instead of a power limit: motor
        speeds (rad/s, increasing from 0 to max_speed) and the peak torque at each (N m, never
        rising with speed, the first equal to peak_torque); linear between them. Empty: the
        corner-speed form above.
    regeneration_efficiency : float
        Share of the energy the motor regenerates that the supply gets back, in [0, 1] (0: a brake
        resistor burns it; near 1: a regenerative supply or a capacitor bank), for the energy drawn
        per stroke.
    """

    gear_ratio: float = 20.0
    peak_torque: float = 20.0
    continuous_torque: float = 10.0
    max_speed: float = 314.0
    power_limit: float | None = None
    gear_efficiency: float = 0.95
    motor_inertia: float = 2e-3
    gear_inertia: float = 0.0
    curve_speeds: tuple[float, ...] = ()
    curve_torques: tuple[float, ...] = ()
    regeneration_efficiency: float = 0.0

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        chk.positive("gear_ratio", self.gear_ratio, "-")
        peak = chk.positive("peak_torque", self.peak_torque, "N m")
        cont = chk.positive("continuous_torque", self.continuous_torque, "N m")
        if cont > peak:
            raise ValueError(f"continuous_torque must be in (0, peak_torque = {peak:g}] N m, got {cont!r}")
        speed = chk.positive("max_speed", self.max_speed, "rad/s")
        if speed > MAX_MOTOR_SPEED:
            slip = f": a value in rpm? {speed:g} rpm is {speed * 2 * np.pi / 60:.4g} rad/s"
            raise ValueError(f"max_speed must be in (0, {MAX_MOTOR_SPEED:g}] rad/s, got {speed!r}{slip}")
        if speed > SUSPECT_MOTOR_SPEED:
            chk.suspect(f"max_speed = {speed:g} rad/s is {speed * 60 / (2 * np.pi):.0f} rpm, faster than press servo "
                        f"motors run (up to about 6000 rpm): a value in rpm? {speed:g} rpm is "
                        f"{speed * 2 * np.pi / 60:.4g} rad/s")
        if self.power_limit is not None:
            chk.positive("power_limit", self.power_limit, "W")
        eta = chk.positive("gear_efficiency", self.gear_efficiency, "-")
        if eta > 1.0:
            raise ValueError(f"gear_efficiency must be in (0, 1], got {eta!r}" + (
                f": a value in %? {eta:g} % is {eta / 100:g}" if eta <= 100 else ""))
        chk.positive("motor_inertia", self.motor_inertia, "kg m^2")
        chk.nonnegative("gear_inertia", self.gear_inertia, "kg m^2")
        regen = chk.nonnegative("regeneration_efficiency", self.regeneration_efficiency, "-")
        if regen > 1.0:
            raise ValueError(f"regeneration_efficiency must be in [0, 1], got {regen!r}" + (
                f": a value in %? {regen:g} % is {regen / 100:g}" if regen <= 100 else ""))
        self._check_curve(peak, speed)

    def _check_curve(self, peak: float, top: float) -> None:
        w, t = chk.point_table(self, "curve_speeds", "curve_torques")
        if not w:
            return
        if self.power_limit is not None:
            raise ValueError("power_limit must be None with a peak-torque curve (curve_speeds, curve_torques): the "
                             "curve gives the torque at every speed")
        if len(w) < 2 or w[0] != 0.0 or abs(w[-1] - top) > 1e-9 * top:
            slip = (f": speeds in rpm? {w[-1]:g} rpm is {w[-1] * 2 * np.pi / 60:.4g} rad/s"
                    if len(w) >= 2 and abs(w[-1] * 2 * np.pi / 60 - top) <= 1e-3 * top else "")
            raise ValueError(f"curve_speeds must run from 0 to max_speed = {top:g} rad/s, increasing, got {list(w)}"
                             + slip)
        for k in range(len(w) - 1):
            if w[k + 1] <= w[k]:
                raise ValueError(f"curve_speeds must increase, got {w[k]:g} then {w[k + 1]:g} rad/s")
            if t[k + 1] > t[k]:
                raise ValueError(f"curve_torques must not rise with speed (a peak-torque envelope), got {t[k]:g} N m "
                                 f"at {w[k]:g} rad/s, then {t[k + 1]:g} N m at {w[k + 1]:g} rad/s")
        if t[0] != peak or t[-1] <= 0.0:
            raise ValueError(f"curve_torques must start at peak_torque = {peak:g} N m and stay > 0, got {list(t)}")

    def peak_torque_at(self, speed) -> np.ndarray:
        """The envelope: the motor's peak torque (N m) at motor speeds `speed` (rad/s, either sign);
        0 above max_speed."""
        s = np.abs(np.asarray(speed, dtype=float))
        peak = np.full(s.shape, self.peak_torque)
        if self.curve_speeds:
            peak = np.interp(s, self.curve_speeds, self.curve_torques)
        if self.power_limit is not None:
            peak = np.minimum(peak, self.power_limit / np.maximum(s, 1e-300))
        return np.where(s <= self.max_speed, peak, 0.0)

    def motor_torques(self, crank_torque, crank_alpha):
        """The motor torque (N m) while the gear drives the crank and while the crank drives back
        (regenerating), at crank torque `crank_torque` (N m) and crank acceleration `crank_alpha`
        (rad/s^2): crank torque / (i eta) or crank torque x eta / i, plus the rotor's and the
        gear's inertia torque. Numbers, arrays or CasADi expressions; which of the two acts follows
        the sign of the crank's power."""
        i, eta = self.gear_ratio, self.gear_efficiency
        rotor = (self.motor_inertia + self.gear_inertia) * i * crank_alpha
        return crank_torque / (i * eta) + rotor, crank_torque * (eta / i) + rotor

    def acting_torque(self, crank_torque, crank_alpha) -> np.ndarray:
        """The motor torque that acts (N m): `motor_torques`' driving one where the crank torque is
        >= 0 (a crank turning forward takes power), the regenerating one elsewhere (numpy arrays)."""
        tau = np.asarray(crank_torque, dtype=float)
        driving, regenerating = self.motor_torques(tau, np.asarray(crank_alpha, dtype=float))
        return np.where(tau >= 0.0, driving, regenerating)

    def supply_power(self, motor_power) -> np.ndarray:
        """The power drawn from the supply (W) at the motor's power `motor_power` (W): all of it while
        the motor drives, less `regeneration_efficiency` of it back while it regenerates."""
        p = np.asarray(motor_power, dtype=float)
        return np.maximum(p, 0.0) - self.regeneration_efficiency * np.maximum(-p, 0.0)

    def to_dict(self) -> dict:
        """Plain data (None values and an empty curve left out)."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()
                if v is not None and v != ()}


@dataclass(frozen=True)
class MotorCycle:
    """One cycle of a response in the motor's terms.

    Attributes
    ----------
    t : ndarray
        Time, s.
    speed, torque, power : ndarray
        Motor speed (rad/s), torque (N m, positive driving) and mechanical power (W).
    peak_torque, rms_torque, max_speed, peak_power : float
        max |torque| (N m), its RMS over the cycle (N m), max |speed| (rad/s), max power (W).
    inertia_ratio : float
        The largest over the cycle of (load inertia / i^2 + gear inertia) / motor inertia, -.
    peak_torque_margin : float
        min over the cycle of (envelope(speed) - |torque|) / Drive.peak_torque, - (< 0: over the peak
        curve somewhere, or turning faster than the top speed, where the envelope is 0).
    rms_margin, speed_margin : float
        1 - rms_torque / continuous_torque and 1 - max_speed / Drive.max_speed, - (< 0: over).
    energy_driving, energy_regenerated : float
        The motor's energy out (J) and back (J, >= 0) per cycle.
    energy_drawn : float
        The supply's energy per cycle, J: energy_driving - Drive.regeneration_efficiency x
        energy_regenerated.
    bus_energy_swing : float
        Range of the integral of (power - its mean) over the cycle, J: what a DC-bus capacitor must
        buffer for the supply to deliver the mean power only.
    gear_losses : float
        Energy lost in the gear per cycle, J.
    """

    t: np.ndarray
    speed: np.ndarray
    torque: np.ndarray
    power: np.ndarray
    peak_torque: float
    rms_torque: float
    max_speed: float
    peak_power: float
    inertia_ratio: float
    peak_torque_margin: float
    rms_margin: float
    speed_margin: float
    energy_driving: float
    energy_regenerated: float
    energy_drawn: float
    bus_energy_swing: float
    gear_losses: float

    def summary(self) -> dict[str, float]:
        """The cycle's figures as plain data (SI)."""
        return {k: float(getattr(self, k)) for k in (
            "peak_torque", "rms_torque", "max_speed", "peak_power", "inertia_ratio", "peak_torque_margin", "rms_margin",
            "speed_margin", "energy_driving", "energy_regenerated", "energy_drawn", "bus_energy_swing", "gear_losses")}


def motor_cycle(drive: Drive, t, omega, alpha, crank_torque, load_inertia) -> MotorCycle:
    """The motor's side of one cycle of crank motion (`t` s over one period, `omega` rad/s > 0,
    `alpha` rad/s^2) and crank torque (N m, positive driving); `load_inertia` is the press's
    generalised inertia about the crank at those instants (kg m^2: twice its kinetic energy at
    1 rad/s)."""
    from scipy.integrate import cumulative_trapezoid, trapezoid  # 1 s to import: only where a drive is

    t, omega, alpha, tau = (np.asarray(v, dtype=float) for v in (t, omega, alpha, crank_torque))
    if np.any(omega <= 0.0):
        raise ValueError(f"omega must be in (0, inf) rad/s throughout, got a least value {float(np.min(omega)):g}: "
                         "the drive's figures need a crank that keeps turning forward")
    i = drive.gear_ratio
    torque = drive.acting_torque(tau, alpha)  # omega > 0: the crank's power has tau's sign
    speed = i * omega
    power = torque * speed
    rotor = (drive.motor_inertia + drive.gear_inertia) * i * alpha * speed
    period = t[-1] - t[0]
    stored = cumulative_trapezoid(power - trapezoid(power, t) / period, t, initial=0.0)
    rms, top = float(np.sqrt(trapezoid(torque**2, t) / period)), float(np.max(np.abs(speed)))
    driving, regenerated = float(trapezoid(np.maximum(power, 0.0), t)), float(trapezoid(np.maximum(-power, 0.0), t))
    return MotorCycle(
        t=t, speed=speed, torque=torque, power=power, peak_torque=float(np.max(np.abs(torque))), rms_torque=rms,
        max_speed=top, peak_power=float(np.max(power)),
        inertia_ratio=float(np.max((np.asarray(load_inertia) / i**2 + drive.gear_inertia) / drive.motor_inertia)),
        peak_torque_margin=float(np.min(drive.peak_torque_at(speed) - np.abs(torque)) / drive.peak_torque),
        rms_margin=1.0 - rms / drive.continuous_torque, speed_margin=1.0 - top / drive.max_speed,
        energy_driving=driving, energy_regenerated=regenerated,
        energy_drawn=driving - drive.regeneration_efficiency * regenerated,
        bus_energy_swing=float(np.max(stored) - np.min(stored)),
        gear_losses=float(trapezoid(np.abs(power - rotor - tau * omega), t)))


__all__ = ["Drive", "MotorCycle", "motor_cycle"]
