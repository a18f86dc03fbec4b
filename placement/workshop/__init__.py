"""The robot workshop: robots loaded by name or file, checked, assembled, estimated and calibrated.

- :mod:`placement.workshop.load`: :func:`placement.workshop.load.load_robot`, by name, sidecar or Gepetto folder;
- :mod:`placement.workshop.catalog`: the built-in robots and example-robot-data's arms, by name;
- :mod:`placement.workshop.estimates`: an example-robot-data arm with its drives and workspace estimated;
- :mod:`placement.workshop.gepetto`: Gepetto's example-parallel-robots folders, with their estimates;
- :mod:`placement.workshop.assemble`: the loops of a robot exported open, closed;
- :mod:`placement.workshop.checks`: a robot's model proven exact (round trips, power balance, plausibility);
- :mod:`placement.workshop.calibration`: drive constants fitted to measured logs.
"""
