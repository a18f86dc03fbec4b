"""A robot cell as data: the cell file (obstacles, keep-out zones, the workpiece's region, a tool body).

- :mod:`placement.cell.cell_file`: the cell file's schema and :func:`placement.cell.cell_file.load_cell`, and the
  tool body a sidecar may declare.

The robot equipped for a cell is :mod:`placement.robot.equip`; its collision distances, :mod:`placement.collision`.
"""
