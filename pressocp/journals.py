"""The journals' contact with their bearing walls over a response: how often each clearance joint's
journal leaves its wall, how long and how far, and how fast it comes back to it (the impact).

A journal is on its wall while its eccentricity ratio |e|/c is at least 1 (the contact law's
penetration is positive), in flight below. The return speed is the radial speed at which the
journal reaches the wall again, estimated from the two output samples either side of the return:
it sets the impact's force spike (the contact's damping acts on the penetration rate), so a graze
of a micrometre that lands at 0.1 mm/s and a flight across the gap that lands at 40 mm/s are both
one contact loss but not the same event.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Mapping, Sequence

import numpy as np

from .params import PressParams
from .result import SimResult


@dataclass(frozen=True)
class ContactLosses:
    """One clearance joint's separations from its bearing wall over a response.

    Attributes
    ----------
    losses : int
        Times the journal leaves its wall (a periodic response's samples are read as one cycle, so
        a flight across its end counts once).
    flight_time : float
        The longest separation, s (0 without one; the whole span when the journal never touches).
    depth : float
        The largest distance off the wall, c (1 - min |e|/c), m (0 without a separation).
    depth_ratio : float
        `depth` as a fraction of the radial clearance c.
    return_speed : float
        The largest radial speed at which the journal reaches its wall again, m/s (0 without a
        return), from the samples either side of each return.
    """

    losses: int
    flight_time: float
    depth: float
    depth_ratio: float
    return_speed: float

    def to_dict(self) -> dict[str, float | int]:
        """The fields by name (SI units), for JSON."""
        return asdict(self)


def wall_contact(t: np.ndarray, ratio: np.ndarray, clearance: float) -> ContactLosses:
    """`ContactLosses` of one journal from its eccentricity ratio |e|/c sampled at times `t` (s,
    increasing) over one cycle, the last sample being the first one again (a periodic response as
    `pressocp.verify.verify_speed` gives it), with radial clearance `clearance` (m). The times of
    leaving and reaching the wall are interpolated linearly between samples."""
    t, ratio = np.asarray(t, dtype=float), np.asarray(ratio, dtype=float)
    if t.shape != ratio.shape or t.ndim != 1 or t.size < 3:
        raise ValueError(f"t and ratio must be 1-D arrays of the same length >= 3, got {t.shape} and {ratio.shape}")
    r, step = ratio[:-1], np.diff(t)  # step[i]: from sample i to the next, the last one back to sample 0
    free = r < 1.0
    depth_ratio = float(max(1.0 - r.min(), 0.0))
    if not free.any():
        return ContactLosses(0, 0.0, 0.0, 0.0, 0.0)
    if free.all():
        return ContactLosses(1, float(t[-1] - t[0]), depth_ratio * clearance, depth_ratio, 0.0)
    # the cycle rotated to start on the wall, and closed by its first sample: every flight then
    # starts and ends inside it
    order = np.roll(np.arange(r.size), -int(np.flatnonzero(~free)[0]))
    rr, st = np.append(r[order], r[order[0]]), step[order]
    tau = np.concatenate([[0.0], np.cumsum(st)])
    f = rr < 1.0
    leaves = np.flatnonzero(f[1:] & ~f[:-1]) + 1  # first sample in flight
    returns = np.flatnonzero(~f[1:] & f[:-1]) + 1  # first sample back on the wall

    def crossing(i: int) -> float:  # when |e|/c passes 1 between samples i - 1 and i
        return float(tau[i - 1] + (1.0 - rr[i - 1]) / (rr[i] - rr[i - 1]) * st[i - 1])

    longest = max(crossing(b) - crossing(a) for a, b in zip(leaves, returns))
    fastest = max(float((rr[b] - rr[b - 1]) * clearance / st[b - 1]) for b in returns)
    return ContactLosses(int(leaves.size), longest, depth_ratio * clearance, depth_ratio, fastest)


def contact_losses(sim: SimResult, press: PressParams, joints: Sequence[str]) -> dict[str, ContactLosses]:
    """`wall_contact` of each clearance joint of `joints` ("crank_pin", "wrist_pin") of `press` over
    the response `sim` (a periodic response read as one cycle)."""
    return {j: wall_contact(sim.t, getattr(sim, f"{j}_eccentricity"), getattr(press, j).clearance) for j in joints}


def describe_contacts(found: Mapping[str, ContactLosses]) -> str:
    """One line for a report: each joint on its wall throughout, or its separations (count, the
    longest, the deepest in µm and as a share of the clearance, the fastest return)."""
    parts = []
    for joint, c in found.items():
        name = joint.replace("_", " ")
        if not c.losses:
            parts.append(f"{name} on its wall throughout")
            continue
        times = "once" if c.losses == 1 else f"{c.losses} times"
        parts.append(f"{name} leaves its wall {times} a cycle (longest {1e3 * c.flight_time:.2g} ms, "
                     f"{1e6 * c.depth:.2g} µm = {100 * c.depth_ratio:.2g} % of its clearance, back at up to "
                     f"{1e3 * c.return_speed:.2g} mm/s)")
    return "journals: " + "; ".join(parts) if parts else "no clearance joints"


__all__ = ["ContactLosses", "contact_losses", "describe_contacts", "wall_contact"]
