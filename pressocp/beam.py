"""Euler-Bernoulli beam with Hermite cubic elements, in a chord frame (pinned-pinned ends).

The rod axis runs along the chord through the two bearing centres; transverse displacements w
vanish at both ends. Nodal unknowns are (w_i, w'_i) at nodes 0..N; with w_0 = w_N = 0 the free
degrees of freedom are ordered ``[w'_0, w_1, w'_1, ..., w_{N-1}, w'_{N-1}, w'_N]`` (2 N of them).
Energies are integrated with 4-point Gauss quadrature, exact for the consistent mass (degree 6).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(4)
GAUSS_S = 0.5 * (GAUSS_X + 1.0)  # points on [0, 1]
GAUSS_WS = 0.5 * GAUSS_W  # weights on [0, 1]


def hermite(s: float, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Hermite cubic shape functions and their second derivatives at local coordinate s in [0, 1].

    Returns
    -------
    N, N2 : ndarray of shape (4,)
        Values (multiplying [w_i, w'_i, w_j, w'_j]) and d^2/dxi^2 (1/m^2 times the same).
    """
    L = length
    N = np.array([1 - 3 * s**2 + 2 * s**3, L * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3, L * (-(s**2) + s**3)])
    N2 = np.array([-6 + 12 * s, L * (-4 + 6 * s), 6 - 12 * s, L * (-2 + 6 * s)]) / L**2
    return N, N2


def element_dofs(n_elements: int) -> list[list[int | None]]:
    """Free-DOF index of each element's [w_i, w'_i, w_j, w'_j] (None where w is zero at an end)."""
    def w_index(i):  # transverse displacement at node i
        return None if i in (0, n_elements) else 2 * i - 1

    def slope_index(i):
        return 0 if i == 0 else (2 * n_elements - 1 if i == n_elements else 2 * i)

    return [[w_index(e), slope_index(e), w_index(e + 1), slope_index(e + 1)] for e in range(n_elements)]


def _gather(q, dofs):
    return ca.vertcat(*[q[d] if d is not None else 0 for d in dofs]) if isinstance(q, (ca.SX, ca.MX)) else \
        np.array([q[d] if d is not None else 0.0 for d in dofs])


@dataclass(frozen=True)
class RodIntegrals:
    """Integrals over the rod of its shape functions N(xi) (free DOFs, xi in [0, l] from the big end),
    the invariants of the floating-frame energies: with w(xi) = N(xi) . u and mass per length rho A,
    the rod's kinetic energy needs rho A times `first`, `moment` and `mass`, its strain energy EI
    times `stiffness` (`pressocp.model`). Numeric, or CasADi expressions when the length is a symbol.

    Attributes
    ----------
    first : (2N,) ndarray or ca.SX
        int N dxi, m (times the DOF's unit).
    moment : (2N,)
        int xi N dxi, m^2.
    mass : (2N, 2N)
        int N N^T dxi, m: the consistent mass matrix per unit rho A.
    stiffness : (2N, 2N)
        int N'' N''^T dxi, 1/m^3: the bending stiffness matrix per unit EI.
    """

    first: object
    moment: object
    mass: object
    stiffness: object


def integrals(length, n_elements: int) -> RodIntegrals:
    """`RodIntegrals` of the pinned-pinned rod of `n_elements` Hermite elements, by the 4-point Gauss
    rule (exact: the integrands are polynomials of degree 6 at most). The integrals are assembled for
    unit elements and scaled by the element length Le: a slope DOF's shape functions carry a factor
    Le, so with D = diag(1 for a deflection, Le for a slope) ``first = Le D f1``, ``moment = Le^2 D
    m1``, ``mass = Le D M1 D`` and ``stiffness = Le^-3 D K1 D``; `length` may be a CasADi symbol."""
    n = 2 * n_elements
    f1, m1, M1, K1 = np.zeros(n), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    for e, dofs in enumerate(element_dofs(n_elements)):
        keep = [k for k, d in enumerate(dofs) if d is not None]
        idx = [dofs[k] for k in keep]
        for s, wgt in zip(GAUSS_S, GAUSS_WS):
            N, N2 = (v[keep] for v in hermite(s, 1.0))
            f1[idx] += wgt * N
            m1[idx] += wgt * (e + s) * N
            M1[np.ix_(idx, idx)] += wgt * np.outer(N, N)
            K1[np.ix_(idx, idx)] += wgt * np.outer(N2, N2)
    slope = np.array([i % 2 == 0 or i == n - 1 for i in range(n)])  # the DOF order of `element_dofs`
    Le = length / n_elements
    if isinstance(Le, (ca.SX, ca.MX)):
        D = ca.diag(ca.vertcat(*[Le if sl else 1.0 for sl in slope]))
        return RodIntegrals(Le * D @ ca.DM(f1), Le**2 * D @ ca.DM(m1), Le * D @ ca.DM(M1) @ D,
                            D @ ca.DM(K1) @ D / Le**3)
    d = np.where(slope, Le, 1.0)
    return RodIntegrals(Le * d * f1, Le**2 * d * m1, Le * np.outer(d, d) * M1, np.outer(d, d) * K1 / Le**3)


def deflection_at(length: float, n_elements: int, q, xi: float):
    """Transverse deflection w at axial position xi in [0, l], m."""
    return deflection_at_share(length, n_elements, q, xi / length)


def deflection_at_share(length, n_elements: int, q, share: float):
    """Transverse deflection w at the axial position ``share * l`` (share in [0, 1]), m. The rod's
    `length` may be a CasADi symbol (a carried parameter): the element and the local coordinate
    follow from `share` alone."""
    e = min(int(share * n_elements), n_elements - 1)
    N, _ = hermite(share * n_elements - e, length / n_elements)
    qe = _gather(q, element_dofs(n_elements)[e])
    return ca.dot(ca.vertcat(*N), qe) if isinstance(qe, (ca.SX, ca.MX)) else float(N @ qe)


def interpolate(length: float, n_elements: int, f, df) -> np.ndarray:
    """Free DOFs that interpolate a field f(xi) with slope df(xi) (pinned ends: f(0) = f(l) = 0)."""
    nodes = np.linspace(0.0, length, n_elements + 1)
    q = np.zeros(2 * n_elements)
    for i, x in enumerate(nodes):
        dofs = element_dofs(n_elements)[min(i, n_elements - 1)]
        w_i, s_i = (dofs[0], dofs[1]) if i < n_elements else (dofs[2], dofs[3])
        if w_i is not None:
            q[w_i] = f(x)
        q[s_i] = df(x)
    return q


def pinned_pinned_matrices(length: float, n_elements: int, mass_per_length: float, bending_stiffness: float):
    """Consistent mass and stiffness matrices of the free DOFs (numeric, for modal checks)."""
    rod = integrals(length, n_elements)
    return mass_per_length * rod.mass, bending_stiffness * rod.stiffness


def modes(length: float, n_elements: int, mass_per_length: float, bending_stiffness: float,
          n_modes: int) -> tuple[np.ndarray, np.ndarray]:
    """The first `n_modes` bending modes of the pinned-pinned rod of `n_elements` elements: the
    fixed-interface normal modes of a Craig-Bampton reduction whose interface is the two pinned
    ends (the chord frame carries the interface's own motion, the rigid rod).

    Returns
    -------
    shapes : ndarray, 2 n_elements x n_modes
        Free DOFs of each mode, scaled to a largest deflection of 1 along the rod (a modal
        coordinate is then that deflection, m), positive there.
    frequencies : ndarray
        Their angular frequencies, rad/s.
    """
    from scipy.linalg import eigh  # only a modal rod needs it

    M, K = pinned_pinned_matrices(length, n_elements, mass_per_length, bending_stiffness)
    values, vectors = eigh(K, M, subset_by_index=(0, n_modes - 1))
    x = np.linspace(0.0, length, 20 * n_elements + 1)
    shapes = np.empty((2 * n_elements, n_modes))
    for k in range(n_modes):
        v = vectors[:, k]
        w = np.array([deflection_at(length, n_elements, v, xi) for xi in x])
        # the first point of largest |w| (an antisymmetric mode has two, equal to round-off)
        shapes[:, k] = v / w[np.flatnonzero(np.abs(w) >= (1.0 - 1e-9) * np.abs(w).max())[0]]
    return shapes, np.sqrt(values)


def modal_coordinates(shapes: np.ndarray, mass: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Modal coordinates of the free DOFs `q` (the mass-weighted least-squares fit by `shapes`)."""
    ms = mass @ shapes
    return np.linalg.solve(shapes.T @ ms, ms.T @ q)
