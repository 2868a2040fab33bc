"""A collocation NLP's multipliers carried to a finer grid of the same period.

A refined collocation stage starts at the coarse solution: its states along the coarse grid's
collocation polynomials (`pressocp.ocp.collocation.CollocationGrid.interpolate`) and, here, each
constraint group's multipliers as the function of time they approximate. With both, IPOPT's
primal-dual warm start (`pressocp.ipopt_options.IPOPT_WARM_START`) begins next to the finer grid's own
optimum, instead of a barrier restarted without multipliers, which leads to another local optimum
(docs/decisions/2026-11-29-refined-start.md).

How a group's multipliers follow the grid depends on how its rows do (K elements, each of its own
length h, the Radau weights b_r):

* rows at the Radau points that discretise an integral of a density (an inequality's or an
  equality's multiplier measure: the contact, the crank motion's tie, the epigraph, caps and drive
  limits, the ram-speed samples): lambda = h b_r x the density;
* the collocation equations ``sum_j C_jr x_j - h f_r = h (dx/dt - f)``: lambda = b_r x the costate,
  no h;
* the element ends' continuity and a running sum's rows: lambda = the costate itself;
* rows that do not follow the grid (the window's phase, the crank-speed samples, the RMS row):
  copied.

Each density is interpolated linearly in time, periodically over the period (the ram-speed samples
within their band). An inequality's density is only a guess where the active set moves between the
grids; IPOPT corrects it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Groups with one row set per Radau point whose multipliers are h b_r x a density.
MEASURES = frozenset({"crank_motion", "eccentricity", "epigraph", "max_pin_force", "drive_peak_torque",
                      "drive_power", "drive_speed", "swing"})
#: Groups with one row set per Radau point whose multipliers are b_r x a costate.
COLLOCATION = frozenset({"collocation"})
#: Groups with one row set per Radau point whose multipliers are a costate.
RUNNING = frozenset({"running_sum"})
#: Groups with one row set per element end (the costate there).
ENDS = frozenset({"continuity"})
#: The ram-speed rows, one per sample of the window's band (a measure, as `MEASURES`).
BAND = frozenset({"ram_speed_samples"})
#: Groups whose rows do not depend on the grid.
FIXED = frozenset({"window_phase", "omega", "alpha", "drive_rms"})


@dataclass(frozen=True)
class Samples:
    """Where one collocation grid's rows lie.

    Attributes
    ----------
    period : float
        s.
    times : ndarray
        The Radau points, element by element, s.
    weights : ndarray
        Their quadrature weights h b_r, s.
    lengths : ndarray
        The length h of each Radau point's element, s.
    ends : ndarray
        End times of the elements, s.
    band : ndarray of int
        The samples of the ram-speed rows (indices in ``times``).
    """

    period: float
    times: np.ndarray
    weights: np.ndarray
    lengths: np.ndarray
    ends: np.ndarray
    band: np.ndarray


def interpolated(values: np.ndarray, t_from: np.ndarray, t_to: np.ndarray, period: float | None) -> np.ndarray:
    """Rows of `values` (m x len(t_from)) at `t_to`, linear in time; periodic over `period`, or held at
    the end values outside `t_from` when `period` is None."""
    values = np.atleast_2d(values)
    return np.array([np.interp(t_to, t_from, row, period=period) for row in values])


def carried_multipliers(groups_from: list, lam_from: np.ndarray, coarse: Samples, groups_to: list,
                        fine: Samples) -> tuple[np.ndarray | None, str]:
    """The constraint multipliers of a collocation NLP on the `coarse` grid (``lam_from``, in the
    layout `groups_from`: ``Constraints.groups``) carried to the same NLP on the `fine` grid (layout
    `groups_to`), group by group as the module says. Returns (the multipliers, "") or (None, why)
    when a group is not one this map knows or the two layouts do not match."""
    names_from, names_to = [g[0] for g in groups_from], [g[0] for g in groups_to]
    if names_from != names_to:
        return None, "the two grids' NLPs have different constraint groups"
    lam_from = np.asarray(lam_from, float).ravel()
    size = max((i0 + k for _, i0, k in groups_to), default=0)
    out = np.zeros(size)
    n_from, n_to = coarse.times.size, fine.times.size
    for (name, i0, k0), (_, i1, k1) in zip(groups_from, groups_to):
        lam = lam_from[i0 : i0 + k0]
        if name in FIXED:
            if k0 != k1:
                return None, f"group {name} has {k0} rows on one grid and {k1} on the other"
            out[i1 : i1 + k1] = lam
            continue
        if name in MEASURES | COLLOCATION | RUNNING:
            if k0 % n_from or k1 % n_to or k0 // n_from != k1 // n_to:
                return None, f"group {name} is not one row set per Radau point"
            rows = lam.reshape(k0 // n_from, n_from, order="F")
            scale_from, scale_to = ((coarse.weights, fine.weights) if name in MEASURES
                                    else (coarse.weights / coarse.lengths, fine.weights / fine.lengths) if name in COLLOCATION
                                    else (1.0, 1.0))
            carried = interpolated(rows / scale_from, coarse.times, fine.times, coarse.period) * scale_to
        elif name in ENDS:
            e0, e1 = coarse.ends, fine.ends
            if k0 % e0.size or k1 % e1.size or k0 // e0.size != k1 // e1.size:
                # an open response has one end fewer: its last element ends nowhere
                e0, e1 = e0[:-1], e1[:-1]
                if not e0.size or k0 % e0.size or k1 % e1.size or k0 // e0.size != k1 // e1.size:
                    return None, f"group {name} is not one row set per element"
            rows = lam.reshape(k0 // e0.size, e0.size, order="F")
            carried = interpolated(rows, e0, e1, coarse.period)
        elif name in BAND:
            if k0 != coarse.band.size or k1 != fine.band.size:
                return None, f"group {name} does not match the window's samples"
            t0, t1 = coarse.times[coarse.band], fine.times[fine.band]
            carried = interpolated(lam / coarse.weights[coarse.band], t0, t1, None) * fine.weights[fine.band]
        else:
            return None, f"no rule carries group {name} to a finer grid"
        out[i1 : i1 + k1] = np.asarray(carried).ravel(order="F")
    return out, ""
