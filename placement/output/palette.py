"""The colours of the 3-D scene: what is compared (paths) in Okabe and Ito's colour-blind-safe palette, the rest in
colours that stay apart from it.

Every pair of colours a legend can hold together is at least 20 CIELAB units apart (CIE76), so that no two entries
of a legend read alike: the paths (best, worst, ``--at``, several paths, front members), the workspace and its
named points, the workpiece region, the cell's tool, obstacles and keep-out zones, the nearest pair and the map.
Colours are 0xRRGGBB integers.
"""

from __future__ import annotations

OKABE_ITO = (0x009E73, 0xD55E00, 0x0072B2, 0xE69F00, 0xCC79A7, 0x56B4E9)  # bluish green, vermillion, blue, ...
PATH_COLORS = (*OKABE_ITO, 0x117733, 0x6F4E37)  # one per path when several are drawn (then dark green, brown)
BEST_COLOR, WORST_COLOR, AT_COLOR = OKABE_ITO[0], OKABE_ITO[1], OKABE_ITO[2]
POINT_COLORS = {"O_b": 0x000000, "C": 0x999933, "Q_plus": 0x882255, "Q_minus": 0xF0E442}
CUBE_COLOR, REGION_COLOR, NEAREST_COLOR = 0x8C8C8C, 0x332288, 0xFF00FF
CELL_COLORS = {"tool": (0x505A64, "tool"), "obstacle": (0xB08850, "obstacles"), "keep_out": (0xFF4040, "keep-out zones")}
CELL_OPACITY = {"tool": 1.0, "obstacle": 0.5, "keep_out": 0.12}
MAP_COLOR = 0x440154  # viridis' dark end: the legend's swatch of an energy map
ARM_COLOR = OKABE_ITO[2]  # the workbench's live serial arm: blue, apart from its workpiece (magenta) and ghosts (best, worst)


def path_color(index: int) -> int:
    """The colour of the ``index``-th path of a scene that draws several (0-based; the palette repeats after 8)."""
    return PATH_COLORS[index % len(PATH_COLORS)]


def rgb_255(color: int) -> tuple[int, int, int]:
    """A 0xRRGGBB colour as red, green, blue in 0-255 (viser's)."""
    return (color >> 16) & 255, (color >> 8) & 255, color & 255


def rgb(color: int) -> tuple[float, float, float]:
    """A 0xRRGGBB colour as red, green, blue in [0, 1]."""
    red, green, blue = rgb_255(color)
    return red / 255, green / 255, blue / 255
