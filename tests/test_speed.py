"""FourierSpeed: definition, derivatives, amplitude/phase view, fit, symbolic twin, validation."""

import casadi as ca
import numpy as np
import pytest

from pressocp import FourierSpeed
from pressocp.speed import series

rng = np.random.default_rng(0)


def random_speed(n=15, T=0.8, scale=1.0):
    return FourierSpeed(T, scale * rng.normal(size=n) / np.arange(1, n + 1), scale * rng.normal(size=n) / np.arange(1, n + 1), theta0=0.3)


def test_one_revolution_per_period():
    s = random_speed()
    t = rng.uniform(0, 5, 50)
    assert np.allclose(s.theta(t + s.period) - s.theta(t), 2 * np.pi, atol=1e-12, rtol=0)
    assert s.theta(0.0) == pytest.approx(0.3, abs=1e-15)


def test_mean_speed_is_one_revolution_per_period():
    s = random_speed()
    t = np.linspace(0, s.period, 1000, endpoint=False)
    assert np.mean(s.omega(t)) == pytest.approx(2 * np.pi / s.period, rel=1e-12)


def test_derivatives_against_finite_differences():
    s = random_speed()
    t = np.linspace(0.01, 0.79, 97)
    d = 2e-6  # truncation ~ d^2 (2 pi 15/T)^3 |c|/6, round-off ~ 1e-16 |theta| / d: both < 1e-8
    assert np.allclose((s.theta(t + d) - s.theta(t - d)) / (2 * d), s.omega(t), rtol=0, atol=1e-7)
    assert np.allclose((s.omega(t + d) - s.omega(t - d)) / (2 * d), s.alpha(t), rtol=0, atol=1e-5)


def test_definition_single_harmonic():
    T = 2.0
    s = FourierSpeed(T, [0.0, 0.5], [0.25, 0.0])
    t = np.linspace(0, 2, 11)
    w = 2 * np.pi / T
    expected = w + 0.5 * np.cos(2 * w * t) + 0.25 * np.sin(w * t)
    assert np.allclose(s.omega(t), expected, atol=1e-14)


def test_amplitude_phase_roundtrip():
    s = random_speed()
    t = np.linspace(0, s.period, 200)
    w = 2 * np.pi / s.period
    k = np.arange(1, 16)
    by_phase = w + np.sin(np.outer(t, k * w) + s.phase) @ s.amplitude
    assert np.allclose(by_phase, s.omega(t), atol=1e-12)
    s2 = FourierSpeed.from_amplitude_phase(s.period, s.amplitude, s.phase, s.theta0)
    assert np.allclose(s2.a, s.a) and np.allclose(s2.b, s.b)


def test_constant():
    s = FourierSpeed.constant(0.5)
    assert s.n_harmonics == 15
    assert np.allclose(s.omega(np.linspace(0, 1, 9)), 4 * np.pi)
    assert np.allclose(s.alpha(np.linspace(0, 1, 9)), 0)


def test_fit_recovers_coefficients_and_mean():
    s = random_speed(n=6, T=1.3)
    t = np.linspace(0, 1.3, 300, endpoint=False)
    f = FourierSpeed.fit(t, s.omega(t), period=1.3, n_harmonics=6)
    assert np.allclose(f.a, s.a, atol=1e-12) and np.allclose(f.b, s.b, atol=1e-12)
    # a mean offset in the data is not absorbed: the mean stays 2 pi/T
    f2 = FourierSpeed.fit(t, s.omega(t) + 1.0, period=1.3, n_harmonics=6)
    assert np.mean(f2.omega(t)) == pytest.approx(2 * np.pi / 1.3)


def test_symbolic_matches_numeric():
    s = random_speed()
    t = ca.SX.sym("t")
    f = ca.Function("f", [t], list(s.evaluate(t)))
    a = ca.SX.sym("a", 15)
    b = ca.SX.sym("b", 15)
    g = ca.Function("g", [t, a, b], list(series(t, a, b, s.period, 0.3)))
    for tv in (0.0, 0.123, 0.77):
        num = s.evaluate(tv)
        sym = [float(x) for x in f(tv)]
        sym2 = [float(x) for x in g(tv, s.a, s.b)]
        assert np.allclose(num, sym, atol=1e-12) and np.allclose(num, sym2, atol=1e-12)


def test_with_coefficients_and_views():
    s = random_speed()
    s2 = s.with_coefficients(s.coefficients)
    assert np.array_equal(s2.a, s.a) and np.array_equal(s2.b, s.b)
    assert "FourierSpeed" in repr(s)


@pytest.mark.parametrize(
    "args, field",
    [
        ((0.0, [1.0], [1.0]), "period"),
        ((-1.0, [1.0], [1.0]), "period"),
        ((float("nan"), [1.0], [1.0]), "period"),
        ((1.0, [1.0, 2.0], [1.0]), "same length"),
        ((1.0, [float("nan")], [1.0]), "a must contain only finite"),
        ((1.0, [1.0], [float("inf")]), "b must contain only finite"),
    ],
)
def test_bad_input(args, field):
    with pytest.raises(ValueError, match=field):
        FourierSpeed(*args)


def test_bad_fit_input():
    with pytest.raises(ValueError, match="n_harmonics"):
        FourierSpeed.fit(np.linspace(0, 1, 10), np.ones(10), 1.0, n_harmonics=-1)
    with pytest.raises(ValueError, match="at least"):
        FourierSpeed.fit(np.linspace(0, 1, 10), np.ones(10), 1.0, n_harmonics=15)
    with pytest.raises(ValueError, match="coefficients"):
        FourierSpeed.constant(1.0).with_coefficients(np.zeros(3))
