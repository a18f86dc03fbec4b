"""
Energy over the workspace
=========================

The electric energy of the paper's 30 × 60 mm groove on the Orthoglide, evaluated on a grid of placements
of its centre in the base frame's x–y plane (z = 0, phi = 0), with :func:`placement.sweep`: the whole
exact chain (kinematics, projected inverse dynamics, drives) at each of the grid's placements. Hatched
cells break a limit. The least energy lies near the isotropic point O_b at the origin, as the paper found.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import placement
from placement.output.plots import map_figure

try:
    EXAMPLES = Path(__file__).resolve().parents[1]  # examples/, whatever the working folder
except NameError:  # run by the documentation's build, in examples/gallery/ without __file__
    EXAMPLES = Path.cwd().parent

robot = placement.load_robot("orthoglide")
path = placement.load_path(EXAMPLES / "rect.yaml")
grid_m = np.linspace(-0.12, 0.07, 21)
energy_map = placement.sweep(robot, path, {"x": grid_m, "y": grid_m}, {"z": 0.0, "phi": 0.0})

best = np.unravel_index(np.argmin(np.where(energy_map.feasible, energy_map.value, np.inf)), energy_map.value.shape)
print(f"least energy on the grid: {energy_map.value[best]:.4f} J at x = {grid_m[best[0]] * 1e3:.1f} mm, "
      f"y = {grid_m[best[1]] * 1e3:.1f} mm; {energy_map.feasible.mean() * 100:.0f} % of the grid is feasible")
map_figure(energy_map, "rectangle 30 x 60 mm on the Orthoglide, z = 0, phi = 0")
plt.show()
