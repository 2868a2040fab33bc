"""Independent Newton-Euler reference for a planar slider-crank press.

Frame: y along the slide pointing away from the bed ("up"), x perpendicular,
z = x × y out of plane.  Crank axis O at the origin, slide line x = 0, slider
below the crank.  Crank pin A = (r sinθ, r cosθ): θ = 0 is top dead centre and
increasing θ turns the crank clockwise (about −z).  Rod angle φ is defined by
A − B = l (sinφ, cosφ), so the rod's angular velocity about +z is −dφ/dt.

Free bodies (all forces in N, moments in N·m):
  slider : m_s a_B = −F_B + (N, 0) − m_s g ŷ
  rod    : m_r a_G = F_A + F_B − m_r g ŷ
           J_r (−φ̈) = (A − G) × F_A + (B − G) × F_B
  crank  : m_c a_C = O − F_A − m_c g ŷ
           J_c (−α) = A × (−F_A) + C × (−m_c g ŷ) − T
where F_A / F_B are the forces ON the rod from crank / slider, N is the guide
force on the slider, O the bearing force and T the motor torque (positive
clockwise, i.e. in the direction of increasing θ).  The 8 equations are solved
per sample for (F_Ax, F_Ay, F_Bx, F_By, N, T, O_x, O_y).
"""
import numpy as np


def _cross(p, f):
    """z-component of the 2-D cross product p × f (arrays of shape (..., 2))."""
    return p[..., 0] * f[..., 1] - p[..., 1] * f[..., 0]


def slider_crank_kinematics(r, l, theta, omega, alpha):
    """Analytic position, velocity and acceleration of the slider-crank.

    Parameters
    ----------
    r, l : float
        Crank radius and rod length, m.
    theta, omega, alpha : array_like
        Crank angle (rad), speed (rad/s), acceleration (rad/s²).

    Returns
    -------
    dict
        ``A, vA, aA, B, vB, aB, G, vG, aG`` (shape (n, 2), m, m/s, m/s²);
        ``phi, phid, phidd`` rod angle (rad), rate (rad/s), accel (rad/s²).
    """
    th, w, a = (np.atleast_1d(np.asarray(v, float)) for v in (theta, omega, alpha))
    th, w, a = np.broadcast_arrays(th, w, a)
    s, c = np.sin(th), np.cos(th)
    sphi = r * s / l
    cphi = np.sqrt(1.0 - sphi**2)
    phi = np.arctan2(sphi, cphi)
    phid = r * c * w / (l * cphi)
    phidd = (r * c * a - r * s * w**2 + l * sphi * phid**2) / (l * cphi)

    A = np.stack([r * s, r * c], -1)
    vA = np.stack([r * c * w, -r * s * w], -1)
    aA = np.stack([r * (c * a - s * w**2), -r * (s * a + c * w**2)], -1)

    yB = r * c - l * cphi
    vyB = -r * s * w + l * sphi * phid
    ayB = -r * (c * w**2 + s * a) + l * (cphi * phid**2 + sphi * phidd)
    z = np.zeros_like(yB)
    B, vB, aB = (np.stack([z, q], -1) for q in (yB, vyB, ayB))
    return dict(A=A, vA=vA, aA=aA, B=B, vB=vB, aB=aB,
                G=(A + B) / 2, vG=(vA + vB) / 2, aG=(aA + aB) / 2,
                phi=phi, phid=phid, phidd=phidd)


def slider_crank_newton_euler(r, l, m_crank, crank_com, J_crank, m_rod, J_rod,
                              m_slider, g, theta, omega, alpha):
    """Newton-Euler inverse dynamics of a planar slider-crank.

    Parameters
    ----------
    r, l : float
        Crank radius and connecting-rod length, m.
    m_crank : float
        Crank mass, kg.
    crank_com : float
        Distance of the crank centre of mass from O along OA, m.
    J_crank : float
        Crank moment of inertia about the crank axis O, kg·m².
    m_rod, J_rod : float
        Rod mass (kg) and moment of inertia about its midpoint (kg·m²).
    m_slider : float
        Slider mass, kg (lumped at the wrist pin B).
    g : float
        Gravitational acceleration (≥ 0, acting in −y), m/s².
    theta, omega, alpha : array_like
        Crank angle (rad, 0 = TDC), speed (rad/s), acceleration (rad/s²).

    Returns
    -------
    dict of ndarray
        ``torque`` motor torque, N·m, positive driving increasing θ;
        ``crank_pin_force``, ``wrist_pin_force`` pin force magnitudes, N;
        ``slider_normal_force`` x-force of the guide on the slider, N;
        ``crank_pin_tension``, ``wrist_pin_tension`` axial pin forces on the rod, N,
        positive in tension (the hanging slider's weight);
        ``ram_height`` (m, above BDC), ``ram_velocity`` (m/s),
        ``ram_acceleration`` (m/s²); ``rod_angle`` (rad),
        ``rod_angular_velocity`` (rad/s), ``rod_angular_acceleration`` (rad/s²).
    """
    k = slider_crank_kinematics(r, l, theta, omega, alpha)
    n = k["phi"].shape[0]
    th = np.broadcast_to(np.atleast_1d(np.asarray(theta, float)), (n,))
    al = np.broadcast_to(np.atleast_1d(np.asarray(alpha, float)), (n,))
    A, B, G = k["A"], k["B"], k["G"]
    C = crank_com * np.stack([np.sin(th), np.cos(th)], -1)
    aC = (crank_com / r) * k["aA"]
    pA, pB = A - G, B - G

    # unknowns x = [FAx, FAy, FBx, FBy, N, T, Ox, Oy]
    M = np.zeros((n, 8, 8))
    b = np.zeros((n, 8))
    # slider x, y
    M[:, 0, 2], M[:, 0, 4] = -1.0, 1.0
    b[:, 0] = m_slider * k["aB"][:, 0]
    M[:, 1, 3] = -1.0
    b[:, 1] = m_slider * (k["aB"][:, 1] + g)
    # rod x, y, moment about G
    M[:, 2, 0], M[:, 2, 2] = 1.0, 1.0
    b[:, 2] = m_rod * k["aG"][:, 0]
    M[:, 3, 1], M[:, 3, 3] = 1.0, 1.0
    b[:, 3] = m_rod * (k["aG"][:, 1] + g)
    M[:, 4, 0], M[:, 4, 1] = -pA[:, 1], pA[:, 0]
    M[:, 4, 2], M[:, 4, 3] = -pB[:, 1], pB[:, 0]
    b[:, 4] = -J_rod * k["phidd"]
    # crank x, y, moment about O
    M[:, 5, 0], M[:, 5, 6] = -1.0, 1.0
    b[:, 5] = m_crank * aC[:, 0]
    M[:, 6, 1], M[:, 6, 7] = -1.0, 1.0
    b[:, 6] = m_crank * (aC[:, 1] + g)
    M[:, 7, 0], M[:, 7, 1], M[:, 7, 5] = A[:, 1], -A[:, 0], -1.0
    b[:, 7] = -J_crank * al - _cross(C, np.stack([0 * th, -m_crank * g * np.ones(n)], -1))

    x = np.linalg.solve(M, b[..., None])[..., 0]
    e = (A - B) / l  # rod axis, from the wrist pin to the crank pin
    return {
        "torque": x[:, 5],
        "crank_pin_force": np.hypot(x[:, 0], x[:, 1]),
        "wrist_pin_force": np.hypot(x[:, 2], x[:, 3]),
        "slider_normal_force": x[:, 4],
        # axial components of the forces on the rod, positive when they pull its ends apart
        "crank_pin_tension": x[:, 0] * e[:, 0] + x[:, 1] * e[:, 1],
        "wrist_pin_tension": -(x[:, 2] * e[:, 0] + x[:, 3] * e[:, 1]),
        "ram_height": B[:, 1] + r + l,
        "ram_velocity": k["vB"][:, 1],
        "ram_acceleration": k["aB"][:, 1],
        "rod_angle": k["phi"],
        "rod_angular_velocity": k["phid"],
        "rod_angular_acceleration": k["phidd"],
    }


def slider_crank_energy(r, l, m_crank, crank_com, J_crank, m_rod, J_rod,
                        m_slider, g, theta, omega):
    """Kinetic + potential energy (J) of the mechanism, PE zero at y = 0."""
    k = slider_crank_kinematics(r, l, theta, omega, 0.0)
    th = k["A"][:, 1] / r  # cos θ
    ke = (0.5 * J_crank * np.asarray(omega, float)**2
          + 0.5 * m_rod * np.sum(k["vG"]**2, -1) + 0.5 * J_rod * k["phid"]**2
          + 0.5 * m_slider * k["vB"][:, 1]**2)
    pe = g * (m_crank * crank_com * th + m_rod * k["G"][:, 1] + m_slider * k["B"][:, 1])
    return ke + pe


if __name__ == "__main__":
    r, l = 0.05, 0.12
    p = dict(r=r, l=l, m_crank=0.30, crank_com=0.025, J_crank=1e-4 + 0.30 * 0.025**2,
             m_rod=0.21, J_rod=2.5e-4, m_slider=0.14)
    w0 = 5000 * 2 * np.pi / 60
    th = np.linspace(0, 2 * np.pi, 200001)
    out = slider_crank_newton_euler(**p, g=0.0, theta=th, omega=w0, alpha=0.0)

    print("1. Flores & Ambrosio, 5000 rpm, g = 0")
    rows = [("torque max", out["torque"].max(), 138.5),
            ("torque min", out["torque"].min(), -138.5),
            ("crank-pin force max", out["crank_pin_force"].max(), 6200.0),
            ("wrist-pin force max", out["wrist_pin_force"].max(), 2720.0),
            ("|slider normal| max", np.abs(out["slider_normal_force"]).max(), 1100.0),
            ("|ram accel| max", np.abs(out["ram_acceleration"]).max(), r * w0**2 * (1 + r / l))]
    for name, v, ref in rows:
        print(f"   {name:22s} {v:12.4f}  ref {ref:12.4f}  rel diff {(v - ref) / abs(ref):+.3e}")

    print("2. power checks")
    dt = (2 * np.pi / w0) / (th.size - 1)
    tq = out["torque"] * w0
    work = np.sum(0.5 * (tq[1:] + tq[:-1])) * dt
    print(f"   constant speed: ∫T·ω dt = {work:.3e} J, ∫|T·ω| dt = {np.sum(np.abs(tq)) * dt:.3e} J  (peak |T·ω| = {np.abs(tq).max():.3e} W)")
    for W, g in ((w0, 0.0), (w0, 9.81), (2 * np.pi, 9.81)):  # last: gravity-dominated
        t = np.linspace(0, 2 * 2 * np.pi / W, 20001)
        h = t[1] - t[0]
        thv = W * t + 0.3 * np.sin(W * t)
        wv = W * (1 + 0.3 * np.cos(W * t))
        av = -0.3 * W**2 * np.sin(W * t)
        o = slider_crank_newton_euler(**p, g=g, theta=thv, omega=wv, alpha=av)
        E = slider_crank_energy(**p, g=g, theta=thv, omega=wv)
        dE = (E[2:] - E[:-2]) / (2 * h)
        P = o["torque"][1:-1] * wv[1:-1]
        print(f"   varying speed, ω0={W:7.2f} rad/s, g={g}: max|Tω − dE/dt| / max|Tω| = "
              f"{np.abs(P - dE).max() / np.abs(P).max():.3e}")
        if g == 0.0:
            o3, h3 = o, h

    print("3. ram velocity / acceleration vs finite differences (varying speed)")
    o, h = o3, h3
    hh = o["ram_height"]
    v_fd = (hh[2:] - hh[:-2]) / (2 * h)
    a_fd = (hh[2:] - 2 * hh[1:-1] + hh[:-2]) / h**2
    v, a = o["ram_velocity"][1:-1], o["ram_acceleration"][1:-1]
    print(f"   velocity:     max abs err {np.abs(v - v_fd).max():.3e} m/s  "
          f"(rel {np.abs(v - v_fd).max() / np.abs(v).max():.3e})")
    print(f"   acceleration: max abs err {np.abs(a - a_fd).max():.3e} m/s²  "
          f"(rel {np.abs(a - a_fd).max() / np.abs(a).max():.3e})")
