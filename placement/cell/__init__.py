"""A robot cell: obstacles, keep-out zones, a tool body on the flange, and collision distances.

- :mod:`placement.cell.schema`: the cell file (and the tool body a sidecar may declare), ``load_cell``.
- :mod:`placement.cell.tool`: ``mount_tool``, a robot carrying the tool's inertia.
- :mod:`placement.cell.geometry`: the collision geometry of a robot, its tool and a cell (coal, via Pinocchio).
- :mod:`placement.cell.pairs`: which bodies are checked against which.
- :mod:`placement.cell.scene`: ``CollisionScene``, batched distances with a prefilter of compiled lower bounds
  (:mod:`placement.cell.bounds`).

This package's ``__init__`` imports nothing: the robot sidecar imports the schema, and the other
modules import the robot.
"""
