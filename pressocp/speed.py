"""Periodic crank speed as a truncated Fourier series with a fixed period.

    omega(t) = 2 pi / T + sum_k a_k cos(2 pi k t / T) + b_k sin(2 pi k t / T),   k = 1..n

so the mean speed is exactly one revolution per period and theta(t + T) - theta(t) = 2 pi.
One definition (`series`) serves numpy arrays and CasADi symbols, so the model, the speed design
and the optimiser all share it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from . import checks as chk

DEFAULT_HARMONICS = 15


def series(t: Any, a: Any, b: Any, period: float, theta0: Any = 0.0) -> tuple[Any, Any, Any]:
    """Crank angle, speed and acceleration of a Fourier speed.

    Parameters
    ----------
    t : float, numpy array or CasADi SX/MX scalar
        Time, s. A numpy array of any shape is evaluated elementwise.
    a, b : array-like or CasADi column of length n
        Cosine and sine coefficients, rad/s.
    period : float
        Period T, s.
    theta0 : float or CasADi scalar
        Crank angle at t = 0, rad.

    Returns
    -------
    theta, omega, alpha
        rad, rad/s, rad/s^2; numpy arrays shaped like ``t`` or CasADi expressions.
    """
    symbolic = any(isinstance(x, (ca.SX, ca.MX)) for x in (t, a, b, theta0))
    if symbolic:
        n = a.shape[0] if isinstance(a, (ca.SX, ca.MX)) else len(a)
        w = 2 * np.pi * np.arange(1, n + 1) / period  # harmonic angular frequencies
        c, s = ca.cos(w * t), ca.sin(w * t)
        a_, b_ = (x if isinstance(x, (ca.SX, ca.MX)) else ca.DM(np.asarray(x, float)) for x in (a, b))
        theta = theta0 + 2 * np.pi / period * t + ca.dot(a_ / w, s) + ca.dot(b_ / w, 1 - c)
        omega = 2 * np.pi / period + ca.dot(a_, c) + ca.dot(b_, s)
        alpha = ca.dot(w * b_, c) - ca.dot(w * a_, s)
        return theta, omega, alpha
    t = np.asarray(t, dtype=float)
    a, b = np.asarray(a, float), np.asarray(b, float)
    w = 2 * np.pi * np.arange(1, a.size + 1) / period
    arg = t[..., None] * w
    c, s = np.cos(arg), np.sin(arg)
    theta = theta0 + 2 * np.pi / period * t + s @ (a / w) + (1 - c) @ (b / w)
    omega = 2 * np.pi / period + c @ a + s @ b
    alpha = c @ (w * b) - s @ (w * a)
    return theta, omega, alpha


@dataclass(frozen=True, eq=False)
class FourierSpeed:
    """Crank speed omega(t) = 2 pi/T + sum_k a_k cos(2 pi k t/T) + b_k sin(2 pi k t/T).

    Parameters
    ----------
    period : float
        Period T, s (> 0).
    a, b : array-like
        Cosine and sine coefficients a_1..a_n, b_1..b_n, rad/s; equal lengths, n >= 0.
    theta0 : float
        Crank angle at t = 0, rad (0 = top dead centre).
    """

    period: float
    a: np.ndarray
    b: np.ndarray
    theta0: float = 0.0

    def __post_init__(self) -> None:
        chk.positive("period", self.period, "s")
        a = chk.finite_array("a", self.a)
        b = chk.finite_array("b", self.b)
        if a.shape != b.shape:
            raise ValueError(
                f"a and b must have the same length (one coefficient per harmonic), got {a.size} and {b.size}"
            )
        chk.finite("theta0", self.theta0)
        object.__setattr__(self, "a", a.copy())
        object.__setattr__(self, "b", b.copy())
        object.__setattr__(self, "period", float(self.period))
        object.__setattr__(self, "theta0", float(self.theta0))
        self.a.flags.writeable = False
        self.b.flags.writeable = False

    # Construction ---------------------------------------------------------------------------
    @classmethod
    def constant(cls, period: float, n_harmonics: int = DEFAULT_HARMONICS, theta0: float = 0.0) -> "FourierSpeed":
        """Constant speed 2 pi / T with all n harmonics zero."""
        n = chk.integer("n_harmonics", n_harmonics, 0, 10_000)
        return cls(period, np.zeros(n), np.zeros(n), theta0)

    @classmethod
    def from_coefficients(cls, period: float, coefficients: Any, theta0: float = 0.0) -> "FourierSpeed":
        """From the 2n decision variables [a_1..a_n, b_1..b_n] (rad/s), e.g. the head of an NLP's x."""
        c = chk.finite_array("coefficients", coefficients)
        if c.size % 2:
            raise ValueError(f"coefficients must have an even length (a then b), got {c.size}")
        n = c.size // 2
        return cls(period, c[:n], c[n:], theta0)

    @classmethod
    def from_amplitude_phase(
        cls, period: float, r: Any, phi: Any, theta0: float = 0.0
    ) -> "FourierSpeed":
        """From omega = 2 pi/T + sum_k r_k sin(2 pi k t/T + phi_k) (r in rad/s, phi in rad)."""
        r = chk.finite_array("r", r)
        phi = chk.finite_array("phi", phi)
        if r.shape != phi.shape:
            raise ValueError(f"r and phi must have the same length, got {r.size} and {phi.size}")
        return cls(period, r * np.sin(phi), r * np.cos(phi), theta0)

    @classmethod
    def fit(
        cls,
        t: Any,
        omega: Any,
        period: float,
        n_harmonics: int = DEFAULT_HARMONICS,
        theta0: float = 0.0,
        weights: Any = None,
    ) -> "FourierSpeed":
        """Least-squares fit to sampled speeds with the mean held at 2 pi / T.

        Parameters
        ----------
        t, omega : array-like
            Sample times (s) and crank speeds (rad/s).
        period : float
            Period T, s.
        n_harmonics : int
            Number of harmonics n.
        theta0 : float
            Crank angle at t = 0, rad.
        weights : array-like, optional
            Non-negative weight of each sample.
        """
        T = chk.positive("period", period, "s")
        n = chk.integer("n_harmonics", n_harmonics, 0, 10_000)
        t = chk.finite_array("t", t)
        w_ = chk.finite_array("omega", omega)
        if t.shape != w_.shape:
            raise ValueError(f"t and omega must have the same length, got {t.size} and {w_.size}")
        if t.size < 2 * n:
            raise ValueError(f"need at least 2*n_harmonics={2 * n} samples, got {t.size}")
        k = 2 * np.pi * np.arange(1, n + 1) / T
        basis = np.hstack([np.cos(np.outer(t, k)), np.sin(np.outer(t, k))])
        rhs = w_ - 2 * np.pi / T
        if weights is not None:
            sw = np.sqrt(chk.finite_array("weights", weights))
            basis, rhs = basis * sw[:, None], rhs * sw
        coef = np.linalg.lstsq(basis, rhs, rcond=None)[0]
        return cls(T, coef[:n], coef[n:], theta0)

    # Evaluation -----------------------------------------------------------------------------
    @property
    def n_harmonics(self) -> int:
        """Number of harmonics n."""
        return int(self.a.size)

    @property
    def mean_speed(self) -> float:
        """Mean crank speed 2 pi / T, rad/s."""
        return 2 * np.pi / self.period

    def evaluate(self, t: Any) -> tuple[Any, Any, Any]:
        """theta (rad), omega (rad/s), alpha (rad/s^2) at times t (numpy or CasADi)."""
        return series(t, self.a, self.b, self.period, self.theta0)

    def theta(self, t: Any) -> Any:
        """Crank angle, rad."""
        return self.evaluate(t)[0]

    def omega(self, t: Any) -> Any:
        """Crank speed, rad/s."""
        return self.evaluate(t)[1]

    def alpha(self, t: Any) -> Any:
        """Crank angular acceleration, rad/s^2."""
        return self.evaluate(t)[2]

    @property
    def coefficients(self) -> np.ndarray:
        """The 2 n decision variables [a_1..a_n, b_1..b_n], rad/s."""
        return np.concatenate([self.a, self.b])

    def with_coefficients(self, coefficients: Any) -> "FourierSpeed":
        """A copy with new coefficients [a, b] (same period, theta0, n)."""
        c = chk.finite_array("coefficients", coefficients)
        if c.size != 2 * self.n_harmonics:
            raise ValueError(f"coefficients must have length 2*n_harmonics={2 * self.n_harmonics}, got {c.size}")
        return FourierSpeed(self.period, c[: self.n_harmonics], c[self.n_harmonics :], self.theta0)

    def padded(self, n_harmonics: int) -> "FourierSpeed":
        """The same speed with n_harmonics >= self.n_harmonics harmonics (the extra ones zero)."""
        n = chk.integer("n_harmonics", n_harmonics, 0, 10_000)
        if n < self.n_harmonics:
            raise ValueError(f"n_harmonics must be in [{self.n_harmonics}, 10000] (the speed has "
                             f"{self.n_harmonics} harmonics), got {n}")
        pad = np.zeros(n - self.n_harmonics)
        return FourierSpeed(self.period, np.concatenate([self.a, pad]), np.concatenate([self.b, pad]), self.theta0)

    @property
    def amplitude(self) -> np.ndarray:
        """r_k of omega = mean + sum r_k sin(2 pi k t/T + phi_k), rad/s."""
        return np.hypot(self.a, self.b)

    @property
    def phase(self) -> np.ndarray:
        """phi_k of omega = mean + sum r_k sin(2 pi k t/T + phi_k), rad."""
        return np.arctan2(self.a, self.b)

    def min_speed(self, samples: int = 4096) -> float:
        """Minimum crank speed over a period on a uniform grid, rad/s."""
        return float(np.min(self.omega(np.linspace(0.0, self.period, samples, endpoint=False))))

    # Saving ---------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain-data form (JSON-safe): period (s), theta0 (rad), a and b (rad/s) as lists."""
        return {"period": self.period, "theta0": self.theta0, "a": self.a.tolist(), "b": self.b.tolist()}

    @classmethod
    def from_dict(cls, data: dict) -> "FourierSpeed":
        """Inverse of `to_dict` (validated as in the constructor)."""
        try:
            return cls(data["period"], data["a"], data["b"], data.get("theta0", 0.0))
        except KeyError as err:
            raise ValueError(f"a speed needs the key {err.args[0]!r} (period, a, b; theta0 optional)") from None

    def __repr__(self) -> str:
        return (
            f"FourierSpeed(period={self.period:g}, n_harmonics={self.n_harmonics}, theta0={self.theta0:g}, "
            f"max amplitude={self.amplitude.max(initial=0.0):.4g} rad/s)"
        )
