"""The workbench: the placement of one path on one robot, live in the browser (``python -m placement app``).

Its optional dependencies (viser, trimesh and pycollada for the meshes, matplotlib for the pictures, pymoo for
fronts) are the [app] extra's: importing this package checks them first, so that a missing one is named with
the extra that brings it (:func:`placement.distribution.require`).
"""

from placement.distribution import WORKBENCH, require

require(WORKBENCH)
