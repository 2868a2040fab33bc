"""Contact losses read from an eccentricity-ratio series, against closed-form flights."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from pressocp.journals import ContactLosses, describe_contacts, wall_contact

C = 2.5e-4  # m, radial clearance
T = np.linspace(0.0, 1.0, 20001)  # one 1 s cycle, the last sample the first one again


def bump(t, start, width, amplitude):
    """A dip of the ratio below 1.002: 1.002 - amplitude sin(pi s / width) for s = (t - start) mod 1 in
    [0, width], read round the cycle."""
    s = np.mod(t - start, 1.0)
    return np.where(s < width, amplitude * np.sin(np.pi * s / width), 0.0)


def flight(width, amplitude):
    """The closed form of one dip: time below 1, depth (share of c), radial speed at the return (m/s)."""
    x = np.arcsin(0.002 / amplitude)
    return (width / np.pi * (np.pi - 2 * x), amplitude - 0.002,
            amplitude * np.pi / width * np.cos(x) * C)


def two_flights():
    return 1.002 - bump(T, 0.3, 0.1, 0.01) - bump(T, 0.95, 0.1, 0.02)  # the second across the cycle's end


def test_two_flights_match_their_closed_form():
    c = wall_contact(T, two_flights(), C)
    long_time, depth, fast = flight(0.1, 0.02)
    assert c.losses == 2
    assert c.flight_time == pytest.approx(long_time, rel=1e-4)
    assert c.depth_ratio == pytest.approx(depth, rel=1e-6)
    assert c.depth == pytest.approx(depth * C, rel=1e-6)
    assert c.return_speed == pytest.approx(fast, rel=1e-3)


def test_one_flight_inside_the_cycle():
    c = wall_contact(T, 1.002 - bump(T, 0.3, 0.1, 0.01), C)
    time_, depth, speed = flight(0.1, 0.01)
    assert (c.losses, c.flight_time, c.depth_ratio, c.return_speed) == pytest.approx((1, time_, depth, speed),
                                                                                      rel=1e-3)


@settings(max_examples=25, deadline=None)
@given(shift=st.integers(0, T.size - 2))
def test_the_cycles_start_does_not_change_the_answer(shift):
    """Rotating the samples of a closed cycle (its start anywhere, flights across the end included)."""
    r = two_flights()[:-1]
    rotated = np.roll(r, -shift)
    c = wall_contact(T, np.append(rotated, rotated[0]), C)
    ref = wall_contact(T, two_flights(), C)
    assert c.losses == ref.losses
    assert (c.flight_time, c.depth, c.return_speed) == pytest.approx((ref.flight_time, ref.depth, ref.return_speed),
                                                                     rel=1e-9, abs=1e-12)


def test_on_the_wall_and_never_on_it():
    assert wall_contact(T, np.full(T.size, 1.01), C) == ContactLosses(0, 0.0, 0.0, 0.0, 0.0)
    free = wall_contact(T, np.full(T.size, 0.5), C)
    assert (free.losses, free.flight_time, free.depth, free.return_speed) == (1, 1.0, pytest.approx(0.5 * C), 0.0)


def test_bad_series_are_refused():
    with pytest.raises(ValueError, match="same length"):
        wall_contact(T, np.ones(5), C)


def test_the_report_line_names_each_joint():
    line = describe_contacts({"crank_pin": wall_contact(T, two_flights(), C),
                              "wrist_pin": ContactLosses(0, 0.0, 0.0, 0.0, 0.0)})
    assert line.startswith("journals: crank pin leaves its wall 2 times a cycle (longest")
    assert "4.5 µm = 1.8 % of its clearance" in line and line.endswith("wrist pin on its wall throughout")
