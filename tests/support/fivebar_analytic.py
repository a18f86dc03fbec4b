"""Independent analytic model of the planar five-bar test robot (``tests/robots/fivebar``).

The mechanism moves in the base x-y plane, every joint axis along +z. Arm i is a proximal link
(actuated joint ``a_i`` at A_i, length L1) and a distal link (passive joint ``b_i`` at B_i, length
L2); the two distal tips meet at the end-effector point P. Arm 1 has its elbow out to the left
(q_a1 = phi1 + beta1), arm 2 to the right (q_a2 = phi2 - beta2), where phi_i is the direction of
P - A_i and beta_i the angle at A_i of the triangle A_i B_i P (law of cosines).

Everything is written with :mod:`placement.kinematics.taylor`, so positions seeded with velocities and
accelerations give exact joint rates and accelerations, and positions seeded with unit directions
give the Jacobian dq/dP. Nothing here uses pinocchio or the placement kinematics, so it can check
them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from placement.kinematics import taylor
from placement.kinematics.taylor import Taylor2

A1 = (-0.1, 0.0)  # m, base frame: axis of actuated joint a1
A2 = (0.1, 0.0)  # m, base frame: axis of actuated joint a2
L1 = 0.2  # m, proximal link length (a_i to b_i)
L2 = 0.25  # m, distal link length (b_i to the tip)
ROD_RADIUS = 0.01  # m, radius of every link, modelled as a solid cylinder
PROX_MASS = 0.5  # kg, each proximal link
DIST_MASS = 0.4  # kg, each distal link
PAYLOAD_MASS = 1.0  # kg, point-like payload at the tip of arm 1
PAYLOAD_CUBE = 0.02  # m, side of the payload cube (its own inertia is tiny)
GRAVITY = (0.0, -9.81)  # m/s², base frame
REFERENCE_TIP = (0.0, 0.30)  # m, tip position of the sidecar's reference configuration

# Proximal rod about its joint axis A_i (kg·m²): centroidal m(3r² + l²)/12 plus m(l/2)².
PROX_INERTIA_A = PROX_MASS * (3 * ROD_RADIUS**2 + L1**2) / 12 + PROX_MASS * (L1 / 2) ** 2


def _arm(px: Taylor2, py: Taylor2, base: tuple[float, float], elbow: float) -> tuple[Taylor2, Taylor2]:
    """Joint angles (q_a, q_b) of one arm; elbow = +1 for out to the left, -1 to the right."""
    dx, dy = px - base[0], py - base[1]
    d2 = dx * dx + dy * dy
    phi = taylor.arctan2(dy, dx)
    cos_beta = (L1**2 + d2 - L2**2) / (2.0 * L1 * taylor.sqrt(d2))
    beta = taylor.arctan2(taylor.sqrt(1.0 - cos_beta * cos_beta), cos_beta)
    # Relative elbow angle: |P - A|² = L1² + L2² + 2 L1 L2 cos(q_b); an elbow out to the left turns
    # clockwise from the proximal to the distal link (q_b < 0), an elbow to the right anticlockwise.
    cos_b = (d2 - L1**2 - L2**2) / (2.0 * L1 * L2)
    q_b = taylor.arctan2(-elbow * taylor.sqrt(1.0 - cos_b * cos_b), cos_b)
    return phi + elbow * beta, q_b


def joint_angles(px: Taylor2 | ArrayLike, py: Taylor2 | ArrayLike) -> dict[str, Taylor2]:
    """Every joint angle of the five-bar for a tip position.

    Args:
        px, py: Tip coordinates in the base frame (m), Taylor2 (value, first and second time
            derivative, or unit-direction seeds) or plain floats/arrays.

    Returns:
        ``{"a1", "b1", "a2", "b2"}``: joint angles in rad (Taylor2; derivatives in rad/s, rad/s²
        when seeded with m/s, m/s²). Arm 1 elbow out to the left, arm 2 to the right. Values are
        NaN outside the reach of an arm.
    """
    px, py = _lift(px), _lift(py)
    a1, b1 = _arm(px, py, A1, +1.0)
    a2, b2 = _arm(px, py, A2, -1.0)
    return {"a1": a1, "b1": b1, "a2": a2, "b2": b2}


def _lift(x: Taylor2 | ArrayLike) -> Taylor2:
    return x if isinstance(x, Taylor2) else Taylor2.constant(x)


def lumped_torques(position_m: ArrayLike, velocity_m_s: ArrayLike, acceleration_m_s2: ArrayLike,
                   external_force_N: ArrayLike | None = None, tip_mass_kg: float = PAYLOAD_MASS,
                   prox_mass_kg: float = PROX_MASS, prox_inertia_A_kg_m2: float = PROX_INERTIA_A,
                   gravity_m_s2: ArrayLike = GRAVITY) -> np.ndarray:
    """Actuator torques of the idealised (lumped) five-bar, in N·m.

    The idealised five-bar has massless distal links, a point mass ``tip_mass_kg`` at the tip P
    and proximal links that are uniform rods of mass ``prox_mass_kg`` and inertia
    ``prox_inertia_A_kg_m2`` about their joint axes A_i (centre of mass at L1/2 along the link)::

        tau_i = I_A·qdd_ai - M_g,i + [J_Pᵀ (m_tip (a_P - g) - F_ext)]_i

    where M_g,i = z·(r_ci × m_prox g) is the gravity moment of proximal link i about A_i, and
    J_P = dP/dq_a (2x2) is the inverse of dq_a/dP, obtained exactly from :func:`joint_angles`
    with Taylor2 seeded by unit directions. It matches the full model of ``fivebar.urdf`` only when
    the distal links' mass and the payload's own rotational inertia are neglected.

    Sign convention: tau_i is the torque the actuator applies to proximal link i about +z (the
    joint axis), positive anticlockwise seen from +z; F_ext is the force the environment applies
    on the tip (N, base frame), so a positive F_ext·dP/dq_i lowers the torque needed.

    Args:
        position_m: (N, 2) or (N, 3) tip positions in the base frame (only x, y are used).
        velocity_m_s: Same shape, tip velocities.
        acceleration_m_s2: Same shape, tip (classical) accelerations.
        external_force_N: Same shape or None: force on the tip from the environment.
        tip_mass_kg: Point mass at the tip.
        prox_mass_kg: Mass of each proximal link.
        prox_inertia_A_kg_m2: Inertia of each proximal link about its joint axis.
        gravity_m_s2: Gravity (gx, gy[, gz]) in the base frame.

    Returns:
        (N, 2) torques [tau_a1, tau_a2] in N·m.
    """
    p, v, a = (np.atleast_2d(np.asarray(x, dtype=float))[:, :2] for x in (position_m, velocity_m_s, acceleration_m_s2))
    g = np.asarray(gravity_m_s2, dtype=float)[:2]
    n = len(p)
    # Row 0 carries the trajectory's derivatives; rows 1-2 the unit directions e_x, e_y.
    coordinates = [Taylor2(np.tile(p[:, c], (3, 1)), np.vstack([v[:, c], np.outer(np.eye(2)[c], np.ones(n))]),
                           np.vstack([a[:, c], np.zeros((2, n))])) for c in range(2)]
    joints = joint_angles(*coordinates)
    q = np.stack([joints["a1"].v[0], joints["a2"].v[0]], axis=1)  # (N, 2) rad
    qdd = np.stack([joints["a1"].d2[0], joints["a2"].d2[0]], axis=1)  # (N, 2) rad/s²
    dq_dp = np.stack([joints["a1"].d1[1:].T, joints["a2"].d1[1:].T], axis=1)  # (N, 2, 2): [i, j] = dq_ai/dp_j
    force = tip_mass_kg * (a - g)
    if external_force_N is not None:
        force = force - np.atleast_2d(np.asarray(external_force_N, dtype=float))[:, :2]
    # J_Pᵀ f with J_P = (dq/dp)⁻¹: solve (dq/dp)ᵀ x = f.
    transmitted = np.linalg.solve(np.transpose(dq_dp, (0, 2, 1)), force[..., None])[..., 0]
    com_x, com_y = 0.5 * L1 * np.cos(q), 0.5 * L1 * np.sin(q)
    gravity_moment = prox_mass_kg * (com_x * g[1] - com_y * g[0])
    return prox_inertia_A_kg_m2 * qdd - gravity_moment + transmitted


def reached_on_branch(px: ArrayLike, py: ArrayLike, actuator_range_rad: float,
                      reference: tuple[float, float] = REFERENCE_TIP) -> np.ndarray:
    """Whether the tip reaches (px, py) from the reference tip without leaving its branch or meeting a singularity.

    On the branch of :func:`joint_angles` (arm 1's elbow out to the left, arm 2's to the right), a tip
    position is reached when both arms reach it short of a serial singularity (L2 - L1 < |P - A_i| <
    L1 + L2: an arm neither folded nor stretched), when the triangle B1 B2 P turns the same way as at
    the reference tip (the same assembly mode, the distal links not aligned: no parallel singularity),
    and when each actuated angle lies within ``actuator_range_rad`` of its value at the reference.

    Args:
        px, py: Tip coordinates in the base frame (m), arrays of one shape.
        actuator_range_rad: Each actuator's range either side of its reference angle (below pi, so that the
            angles' differences are unambiguous).
        reference: The reference tip position (m).

    Returns:
        A boolean array of the shape of ``px``.
    """
    px, py = np.asarray(px, dtype=float), np.asarray(py, dtype=float)

    def arm(x: np.ndarray, y: np.ndarray, base: tuple[float, float], elbow: float) -> tuple[np.ndarray, ...]:
        distance = np.hypot(x - base[0], y - base[1])
        with np.errstate(invalid="ignore"):
            beta = np.arccos((L1**2 + distance**2 - L2**2) / (2 * L1 * distance))
        angle = np.arctan2(y - base[1], x - base[0]) + elbow * beta
        return angle, base[0] + L1 * np.cos(angle), base[1] + L1 * np.sin(angle), distance

    def turn(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        a1, bx1, by1, d1 = arm(x, y, A1, +1.0)
        a2, bx2, by2, d2 = arm(x, y, A2, -1.0)
        return a1, a2, (bx2 - bx1) * (y - by1) - (by2 - by1) * (x - bx1), d1, d2

    ref_a1, ref_a2, ref_turn, _, _ = turn(np.array(reference[0]), np.array(reference[1]))
    a1, a2, side, d1, d2 = turn(px, py)
    within = np.ones(px.shape, bool)
    for distance in (d1, d2):
        within &= (distance > L2 - L1) & (distance < L1 + L2)
    for angle, start in ((a1, ref_a1), (a2, ref_a2)):
        within &= np.abs(np.angle(np.exp(1j * (angle - start)))) <= actuator_range_rad
    return within & (np.sign(side) == np.sign(ref_turn)) & (side != 0)
