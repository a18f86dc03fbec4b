"""Write ``orthoglide.urdf``: the spanning tree of the Orthoglide 3-axis.

Run ``python make_urdf.py`` in this folder after changing a number below; the test suite checks
that the committed URDF is what this script writes. Every number's source is in ``README.md``
and in the ``sources`` section of ``orthoglide.yaml``.

Each leg is P-R-Pa-R, built in a leg frame whose x axis is the slider axis e_i (legs y and z are
leg x turned by the cyclic permutation x->y->z): slider (prismatic along x) -> yoke (revolute
about y) -> two parallelogram bars (revolute about z, spaced by the parallelogram width along y)
-> far link (revolute about z on bar 1) -> revolute about y -> platform (leg x) or a massless
stub welded to the platform (legs y and z). Bar 2's tip and the far link's second pivot are the
parallelogram's point closure.
"""

from __future__ import annotations

import math
from pathlib import Path

CUBE_SIDE_M = 0.2
LEG_LENGTH_M = CUBE_SIDE_M / (1 / math.sqrt(6) + 1 / math.sqrt(18))
PARALLELOGRAM_WIDTH_M = 0.08
BAR_RADIUS_M = 0.008
LINK_BOX_M = 0.02
SLIDER_BOX_M = 0.08
PLATFORM_BOX_M = 0.10

SLIDER_MASS_KG = 2.0
BAR_MASS_KG = 0.4
YOKE_MASS_KG = 0.1
FAR_LINK_MASS_KG = 0.1
PLATFORM_MASS_KG = 6.0

RHO_MIN_M = LEG_LENGTH_M / math.sqrt(6)
RHO_MAX_M = LEG_LENGTH_M * (1 + 1 / math.sqrt(18))
V_MAX_M_S = 1.0
SLIDER_FORCE_MAX_N = 1.274 * 2 * math.pi / 0.020

# Leg frames: columns are the images of the leg's x, y, z axes in the base frame.
LEG_RPY = {"x": (0.0, 0.0, 0.0), "y": (math.pi / 2, 0.0, math.pi / 2), "z": (-math.pi / 2, -math.pi / 2, 0.0)}

COLORS = {"rail": "0.6 0.6 0.6 1", "slider": "0.2 0.4 0.8 1", "bar": "0.85 0.55 0.1 1",
          "link": "0.3 0.3 0.3 1", "platform": "0.3 0.3 0.4 1", "tool": "0.75 0.75 0.75 1"}
TOOL_LENGTH_M = 0.05  # drawn only: the spindle's tool, whose tip is the platform point


def box_inertia(mass_kg: float, sx: float, sy: float, sz: float) -> tuple[float, float, float]:
    """Principal moments (kg·m²) of a solid box of side lengths sx, sy, sz (m)."""
    return (mass_kg * (sy**2 + sz**2) / 12, mass_kg * (sx**2 + sz**2) / 12, mass_kg * (sx**2 + sy**2) / 12)


def rod_inertia_x(mass_kg: float, length_m: float, radius_m: float) -> tuple[float, float, float]:
    """Principal moments (kg·m²) of a solid cylinder along x about its centre."""
    transverse = mass_kg * (3 * radius_m**2 + length_m**2) / 12
    return (mass_kg * radius_m**2 / 2, transverse, transverse)


def fmt(*values: float) -> str:
    return " ".join(repr(float(v)) for v in values)


def link(name: str, mass: float = 0.0, com=(0.0, 0.0, 0.0), moments=(0.0, 0.0, 0.0), visual: str = "") -> str:
    inertial = ""
    if mass > 0:
        ixx, iyy, izz = moments
        inertial = (f'    <inertial><origin xyz="{fmt(*com)}"/><mass value="{fmt(mass)}"/>'
                    f'<inertia ixx="{fmt(ixx)}" iyy="{fmt(iyy)}" izz="{fmt(izz)}" ixy="0" ixz="0" iyz="0"/></inertial>\n')
    return f'  <link name="{name}">\n{inertial}{visual}  </link>\n'


def visual_box(size, xyz=(0.0, 0.0, 0.0), color: str = "link") -> str:
    return (f'    <visual><origin xyz="{fmt(*xyz)}"/><geometry><box size="{fmt(*size)}"/></geometry>'
            f'<material name="{color}"><color rgba="{COLORS[color]}"/></material></visual>\n')


def visual_rod_z(length: float, radius: float, color: str, z: float) -> str:
    return (f'    <visual><origin xyz="{fmt(0, 0, z)}"/><geometry><cylinder length="{fmt(length)}" radius="{fmt(radius)}"/>'
            f'</geometry><material name="{color}"><color rgba="{COLORS[color]}"/></material></visual>\n')


def visual_rod_x(length: float, radius: float, color: str) -> str:
    return (f'    <visual><origin xyz="{fmt(-length / 2, 0, 0)}" rpy="0 {fmt(math.pi / 2)} 0"/>'
            f'<geometry><cylinder length="{fmt(length)}" radius="{fmt(radius)}"/></geometry>'
            f'<material name="{color}"><color rgba="{COLORS[color]}"/></material></visual>\n')


def joint(name: str, kind: str, parent: str, child: str, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0),
          axis=(1, 0, 0), limit: tuple[float, float, float, float] | None = None) -> str:
    text = (f'  <joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{fmt(*xyz)}" rpy="{fmt(*rpy)}"/>')
    if kind != "fixed":
        text += f'<axis xyz="{fmt(*axis)}"/>'
    if limit is not None:
        lower, upper, effort, velocity = limit
        text += f'<limit lower="{fmt(lower)}" upper="{fmt(upper)}" effort="{fmt(effort)}" velocity="{fmt(velocity)}"/>'
    return text + "</joint>\n"


def leg(axis: str) -> str:
    """Links and joints of the leg whose slider moves along base axis ``axis``."""
    L, w = LEG_LENGTH_M, PARALLELOGRAM_WIDTH_M
    passive = (-math.pi, math.pi, 0.0, 100.0)
    end = "platform" if axis == "x" else f"leg_{axis}_end"
    s = SLIDER_BOX_M
    text = link(f"slider_{axis}", SLIDER_MASS_KG, moments=box_inertia(SLIDER_MASS_KG, s, s, s),
                visual=visual_box((s, s, s), color="slider"))
    text += joint(f"slider_{axis}", "prismatic", "base", f"slider_{axis}", rpy=LEG_RPY[axis],
                  limit=(RHO_MIN_M, RHO_MAX_M, SLIDER_FORCE_MAX_N, V_MAX_M_S))
    yoke = (LINK_BOX_M, w + LINK_BOX_M, LINK_BOX_M)
    text += link(f"yoke_{axis}", YOKE_MASS_KG, moments=box_inertia(YOKE_MASS_KG, *yoke), visual=visual_box(yoke))
    text += joint(f"yoke_{axis}", "revolute", f"slider_{axis}", f"yoke_{axis}", axis=(0, 1, 0), limit=passive)
    bar_moments = rod_inertia_x(BAR_MASS_KG, L, BAR_RADIUS_M)
    for k, y in ((1, w / 2), (2, -w / 2)):
        text += link(f"bar{k}_{axis}", BAR_MASS_KG, com=(-L / 2, 0, 0), moments=bar_moments,
                     visual=visual_rod_x(L, BAR_RADIUS_M, "bar"))
        text += joint(f"bar{k}_{axis}", "revolute", f"yoke_{axis}", f"bar{k}_{axis}", xyz=(0, y, 0),
                      axis=(0, 0, 1), limit=passive)
    text += link(f"bar2_{axis}_tip")
    text += joint(f"bar2_{axis}_tip", "fixed", f"bar2_{axis}", f"bar2_{axis}_tip", xyz=(-L, 0, 0))
    text += link(f"far_{axis}", FAR_LINK_MASS_KG, com=(0, -w / 2, 0), moments=box_inertia(FAR_LINK_MASS_KG, *yoke),
                 visual=visual_box(yoke, xyz=(0, -w / 2, 0)))
    text += joint(f"far_{axis}", "revolute", f"bar1_{axis}", f"far_{axis}", xyz=(-L, 0, 0), axis=(0, 0, 1),
                  limit=passive)
    text += link(f"far_{axis}_pivot2")
    text += joint(f"far_{axis}_pivot2", "fixed", f"far_{axis}", f"far_{axis}_pivot2", xyz=(0, -w, 0))
    if axis == "x":
        p = PLATFORM_BOX_M
        # Drawn above the tool tip so that the path under the tool stays visible.
        drawing = (visual_box((p, p, p / 2), xyz=(0, 0, TOOL_LENGTH_M + p / 4), color="platform")
                   + visual_rod_z(TOOL_LENGTH_M, 0.005, "tool", TOOL_LENGTH_M / 2))
        text += link("platform", PLATFORM_MASS_KG, moments=box_inertia(PLATFORM_MASS_KG, p, p, p), visual=drawing)
    else:
        text += link(end)
    text += joint(f"wrist_{axis}", "revolute", f"far_{axis}", end, xyz=(0, -w / 2, 0), axis=(0, 1, 0),
                  limit=passive)
    return text


def urdf_text() -> str:
    """The whole URDF document."""
    rails = "".join(
        visual_box(size, xyz=xyz, color="rail")
        for size, xyz in (((0.45, 0.03, 0.03), (0.3, 0, 0)), ((0.03, 0.45, 0.03), (0, 0.3, 0)),
                          ((0.03, 0.03, 0.45), (0, 0, 0.3)))
    )
    text = '<?xml version="1.0"?>\n<!-- Written by make_urdf.py: edit that script, not this file. -->\n'
    text += '<robot name="orthoglide">\n' + link("base", visual=rails)
    for axis in "xyz":
        text += leg(axis)
    text += link("tool")
    text += joint("tool", "fixed", "platform", "tool")
    for axis, rpy in (("y", LEG_RPY["y"]), ("z", LEG_RPY["z"])):
        text += link(f"platform_anchor_{axis}")
        text += joint(f"platform_anchor_{axis}", "fixed", "platform", f"platform_anchor_{axis}", rpy=rpy)
    return text + "</robot>\n"


if __name__ == "__main__":
    Path(__file__).with_name("orthoglide.urdf").write_text(urdf_text())
