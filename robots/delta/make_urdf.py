"""Write ``delta.urdf``: the spanning tree of a Delta robot with the ABB IRB 340 dimensions.

Run ``python make_urdf.py`` in this folder after changing a number below; the test suite checks
that the committed URDF is what this script writes. Every number's source is in ``README.md``
and in the ``sources`` section of ``delta.yaml``.

Geometry of R. L. Williams II, "The Delta Parallel Robot: Kinematics Solutions" (Ohio
University, 2016): base frame at the centre of the base triangle, z up (the robot hangs from an
overhead frame, the platform below it); leg i lies in the vertical half-plane at angle gamma_i
about z. Each leg is built in a leg frame turned by gamma_i about z (x radial, outward; y along
the actuator axis; z up): actuated revolute ``arm_i`` about y at the base radius w_B (q = 0: arm
horizontal, pointing out; q > 0 lowers it) -> yoke (revolute about y at the elbow) -> two rods
(revolute about the yoke's z, spaced by the parallelogram width along y) -> far link (revolute
about z at rod 1's lower end) -> revolute ``wrist_i`` about y -> platform (leg 1) or a massless
stub welded to the platform (legs 2 and 3). Rod 2's lower end and the far link's second pivot are
the parallelogram's point closure.
"""

from __future__ import annotations

import math
from pathlib import Path

BASE_SIDE_M = 0.567  # s_B: side of the base triangle whose side midpoints carry the actuator axes
PLATFORM_SIDE_M = 0.076  # s_P: side of the platform triangle whose vertices carry the rods' lower ends
ARM_LENGTH_M = 0.524  # L: actuator axis to elbow
ROD_LENGTH_M = 1.244  # l: parallelogram rods, ball centre to ball centre
PARALLELOGRAM_WIDTH_M = 0.131  # h: spacing of the two rods of a parallelogram
BASE_RADIUS_M = math.sqrt(3) / 6 * BASE_SIDE_M  # w_B: base centre to an actuator axis
PLATFORM_RADIUS_M = PLATFORM_SIDE_M / math.sqrt(3)  # u_P: platform centre to a leg's platform point
LEG_ANGLES_RAD = (-math.pi / 2, math.pi / 6, 5 * math.pi / 6)  # gamma_i: Williams' B_1, B_2, B_3

ARM_RADIUS_M = 0.025
ROD_RADIUS_M = 0.008
PLATFORM_THICKNESS_M = 0.03
ARM_MASS_KG = 1.2
ROD_MASS_KG = 0.15
SPRING_PAIR_MASS_KG = 0.03
SPRING_RADIUS_M = 0.005
PLATFORM_MASS_KG = 1.5

GEAR_RATIO = 25.0
MOTOR_MAX_TORQUE_NM = 12.0
MOTOR_MAX_SPEED_RAD_S = 5000 * 2 * math.pi / 60
ARM_LIMITS_RAD = (-0.9, 1.5)

COLORS = {"base": "0.6 0.6 0.6 1", "arm": "0.2 0.4 0.8 1", "rod": "0.85 0.55 0.1 1",
          "link": "0.3 0.3 0.3 1", "platform": "0.3 0.3 0.4 1"}


def rod_inertia_x(mass_kg: float, length_m: float, radius_m: float) -> tuple[float, float, float]:
    """Principal moments (kg·m²) of a solid cylinder along x about its centre."""
    transverse = mass_kg * (3 * radius_m**2 + length_m**2) / 12
    return (mass_kg * radius_m**2 / 2, transverse, transverse)


def rod_inertia_y(mass_kg: float, length_m: float, radius_m: float) -> tuple[float, float, float]:
    """Principal moments (kg·m²) of a solid cylinder along y about its centre."""
    axial, transverse, _ = rod_inertia_x(mass_kg, length_m, radius_m)
    return (transverse, axial, transverse)


def disc_inertia_z(mass_kg: float, radius_m: float, thickness_m: float) -> tuple[float, float, float]:
    """Principal moments (kg·m²) of a solid cylinder along z about its centre."""
    transverse = mass_kg * (3 * radius_m**2 + thickness_m**2) / 12
    return (transverse, transverse, mass_kg * radius_m**2 / 2)


def fmt(*values: float) -> str:
    """Numbers as URDF text, exactly (repr of each float)."""
    return " ".join(repr(float(v)) for v in values)


def material(color: str) -> str:
    """A URDF material element of one of ``COLORS``."""
    return f'<material name="{color}"><color rgba="{COLORS[color]}"/></material>'


def link(name: str, mass: float = 0.0, com=(0.0, 0.0, 0.0), moments=(0.0, 0.0, 0.0), visual: str = "") -> str:
    """A link; massless (no inertial element) when ``mass`` is 0."""
    inertial = ""
    if mass > 0:
        ixx, iyy, izz = moments
        inertial = (f'    <inertial><origin xyz="{fmt(*com)}"/><mass value="{fmt(mass)}"/>'
                    f'<inertia ixx="{fmt(ixx)}" iyy="{fmt(iyy)}" izz="{fmt(izz)}" ixy="0" ixz="0" iyz="0"/></inertial>\n')
    return f'  <link name="{name}">\n{inertial}{visual}  </link>\n'


def visual_rod_x(length: float, radius: float, color: str) -> str:
    """A cylinder from the link origin along +x."""
    return (f'    <visual><origin xyz="{fmt(length / 2, 0, 0)}" rpy="0 {fmt(math.pi / 2)} 0"/>'
            f'<geometry><cylinder length="{fmt(length)}" radius="{fmt(radius)}"/></geometry>{material(color)}</visual>\n')


def visual_bar_y(length: float, y: float, color: str) -> str:
    """A thin cross-bar along y, centred at (0, y, 0)."""
    return (f'    <visual><origin xyz="{fmt(0, y, 0)}" rpy="{fmt(math.pi / 2)} 0 0"/>'
            f'<geometry><cylinder length="{fmt(length)}" radius="0.01"/></geometry>{material(color)}</visual>\n')


def visual_disc(radius: float, thickness: float, xyz, color: str) -> str:
    """A disc (cylinder along z) centred at ``xyz``."""
    return (f'    <visual><origin xyz="{fmt(*xyz)}"/><geometry><cylinder length="{fmt(thickness)}" '
            f'radius="{fmt(radius)}"/></geometry>{material(color)}</visual>\n')


def joint(name: str, kind: str, parent: str, child: str, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0),
          axis=(1, 0, 0), limit: tuple[float, float, float, float] | None = None) -> str:
    """A joint; ``limit`` is (lower, upper, effort, velocity) in the joint's SI units."""
    text = (f'  <joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{fmt(*xyz)}" rpy="{fmt(*rpy)}"/>')
    if kind != "fixed":
        text += f'<axis xyz="{fmt(*axis)}"/>'
    if limit is not None:
        lower, upper, effort, velocity = limit
        text += f'<limit lower="{fmt(lower)}" upper="{fmt(upper)}" effort="{fmt(effort)}" velocity="{fmt(velocity)}"/>'
    return text + "</joint>\n"


def fixed_frame(name: str, parent: str, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)) -> str:
    """A massless link ``name`` on a fixed joint ``name_joint``: a frame for a closure or the tool."""
    return link(name) + joint(f"{name}_joint", "fixed", parent, name, xyz=xyz, rpy=rpy)


def leg(i: int) -> str:
    """Links and joints of leg ``i`` (1, 2 or 3), in its leg frame turned by gamma_i about z."""
    gamma = LEG_ANGLES_RAD[i - 1]
    L, rod, h = ARM_LENGTH_M, ROD_LENGTH_M, PARALLELOGRAM_WIDTH_M
    passive = (-math.pi, math.pi, 0.0, 100.0)
    arm_limit = (*ARM_LIMITS_RAD, GEAR_RATIO * MOTOR_MAX_TORQUE_NM, MOTOR_MAX_SPEED_RAD_S / GEAR_RATIO)
    text = link(f"arm_{i}", ARM_MASS_KG, com=(L / 2, 0, 0), moments=rod_inertia_x(ARM_MASS_KG, L, ARM_RADIUS_M),
                visual=visual_rod_x(L, ARM_RADIUS_M, "arm"))
    text += joint(f"arm_{i}", "revolute", "base", f"arm_{i}", rpy=(0, 0, gamma), axis=(0, 1, 0), limit=arm_limit,
                  xyz=(BASE_RADIUS_M * math.cos(gamma), BASE_RADIUS_M * math.sin(gamma), 0))
    springs = rod_inertia_y(SPRING_PAIR_MASS_KG, h, SPRING_RADIUS_M)
    text += link(f"yoke_{i}", SPRING_PAIR_MASS_KG, moments=springs, visual=visual_bar_y(h, 0.0, "link"))
    text += joint(f"elbow_{i}", "revolute", f"arm_{i}", f"yoke_{i}", xyz=(L, 0, 0), axis=(0, 1, 0), limit=passive)
    for k, y in ((1, h / 2), (2, -h / 2)):
        text += link(f"rod{k}_{i}", ROD_MASS_KG, com=(rod / 2, 0, 0), moments=rod_inertia_x(ROD_MASS_KG, rod, ROD_RADIUS_M),
                     visual=visual_rod_x(rod, ROD_RADIUS_M, "rod"))
        text += joint(f"rod{k}_{i}", "revolute", f"yoke_{i}", f"rod{k}_{i}", xyz=(0, y, 0), axis=(0, 0, 1), limit=passive)
    text += fixed_frame(f"rod2_{i}_tip", f"rod2_{i}", xyz=(rod, 0, 0))
    text += link(f"far_{i}", SPRING_PAIR_MASS_KG, com=(0, -h / 2, 0), moments=springs,
                 visual=visual_bar_y(h, -h / 2, "link"))
    text += joint(f"far_{i}", "revolute", f"rod1_{i}", f"far_{i}", xyz=(rod, 0, 0), axis=(0, 0, 1), limit=passive)
    text += fixed_frame(f"far_{i}_pivot2", f"far_{i}", xyz=(0, -h, 0))
    end = "platform" if i == 1 else f"leg_{i}_end"
    if i == 1:
        r, t = PLATFORM_RADIUS_M, PLATFORM_THICKNESS_M
        text += link("platform", PLATFORM_MASS_KG, com=(-r, 0, 0), moments=disc_inertia_z(PLATFORM_MASS_KG, 2 * r, t),
                     visual=visual_disc(2 * r, t, (-r, 0, 0), "platform"))
    else:
        text += link(end)
    text += joint(f"wrist_{i}", "revolute", f"far_{i}", end, xyz=(0, -h / 2, 0), axis=(0, 1, 0), limit=passive)
    return text


def platform_frames() -> str:
    """The tool frame at the platform centre (axes of the base) and the weld anchors of legs 2 and 3."""
    r, gamma_1 = PLATFORM_RADIUS_M, LEG_ANGLES_RAD[0]
    text = fixed_frame("tool", "platform", xyz=(-r, 0, 0), rpy=(0, 0, -gamma_1))
    for i in (2, 3):
        turn = LEG_ANGLES_RAD[i - 1] - gamma_1
        text += fixed_frame(f"platform_anchor_{i}", "platform", xyz=(-r + r * math.cos(turn), r * math.sin(turn), 0),
                            rpy=(0, 0, turn))
    return text


def urdf_text() -> str:
    """The whole URDF document."""
    base = visual_disc(BASE_SIDE_M / math.sqrt(3), 0.02, (0, 0, 0.05), "base")
    text = '<?xml version="1.0"?>\n<!-- Written by make_urdf.py: edit that script, not this file. -->\n'
    text += '<robot name="delta">\n' + link("base", visual=base)
    for i in (1, 2, 3):
        text += leg(i)
    return text + platform_frames() + "</robot>\n"


if __name__ == "__main__":
    Path(__file__).with_name("delta.urdf").write_text(urdf_text())
