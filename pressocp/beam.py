"""Euler-Bernoulli beam with Hermite cubic elements, in a chord frame (pinned-pinned ends).

The rod axis runs along the chord through the two bearing centres; transverse displacements w
vanish at both ends. Nodal unknowns are (w_i, w'_i) at nodes 0..N; with w_0 = w_N = 0 the free
degrees of freedom are ordered ``[w'_0, w_1, w'_1, ..., w_{N-1}, w'_{N-1}, w'_N]`` (2 N of them).
Energies are integrated with 4-point Gauss quadrature, exact for the consistent mass (degree 6).
"""

from __future__ import annotations

from collections.abc import Iterator

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


def quadrature_points(length: float, n_elements: int, q, qd=None) -> Iterator[tuple[float, float, object, object, object]]:
    """Yield (xi, weight, w, w_dot, w'') at every Gauss point of every element.

    Parameters
    ----------
    length : float
        Rod length l, m.
    n_elements : int
        Number of elements N.
    q, qd : ca.SX or ndarray
        Free elastic DOFs and their rates (qd may be None).
    """
    Le = length / n_elements
    for e, dofs in enumerate(element_dofs(n_elements)):
        qe = _gather(q, dofs)
        qde = _gather(qd, dofs) if qd is not None else None
        for s, wgt in zip(GAUSS_S, GAUSS_WS):
            N, N2 = hermite(s, Le)
            w = ca.dot(ca.DM(N), qe) if isinstance(qe, (ca.SX, ca.MX)) else N @ qe
            w2 = ca.dot(ca.DM(N2), qe) if isinstance(qe, (ca.SX, ca.MX)) else N2 @ qe
            wd = None if qde is None else (ca.dot(ca.DM(N), qde) if isinstance(qde, (ca.SX, ca.MX)) else N @ qde)
            yield (e + s) * Le, wgt * Le, w, wd, w2


def deflection_at(length: float, n_elements: int, q, xi: float):
    """Transverse deflection w at axial position xi in [0, l], m."""
    Le = length / n_elements
    e = min(int(xi // Le), n_elements - 1)
    N, _ = hermite(xi / Le - e, Le)
    qe = _gather(q, element_dofs(n_elements)[e])
    return ca.dot(ca.DM(N), qe) if isinstance(qe, (ca.SX, ca.MX)) else float(N @ qe)


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
    q = ca.SX.sym("q", 2 * n_elements)
    qd = ca.SX.sym("qd", 2 * n_elements)
    T = 0
    V = 0
    for _, wgt, w, wd, w2 in quadrature_points(length, n_elements, q, qd):
        T += 0.5 * mass_per_length * wgt * wd**2
        V += 0.5 * bending_stiffness * wgt * w2**2
    M = ca.evalf(ca.hessian(T, qd)[0])
    K = ca.evalf(ca.hessian(V, q)[0])
    return np.array(M), np.array(K)


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
        shapes[:, k] = v / w[np.argmax(np.abs(w))]
    return shapes, np.sqrt(values)


def modal_coordinates(shapes: np.ndarray, mass: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Modal coordinates of the free DOFs `q` (the mass-weighted least-squares fit by `shapes`)."""
    ms = mass @ shapes
    return np.linalg.solve(shapes.T @ ms, ms.T @ q)
