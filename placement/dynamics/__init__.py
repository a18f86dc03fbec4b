"""Dynamics of serial and closed-loop robots, batched over samples.

- :mod:`placement.dynamics.inverse`: actuator efforts by RNEA projected on the closure null space;
- :mod:`placement.dynamics.path_dynamics`: the same efforts along a path as A·s̈ + B·ṡ² + C, and the forms
  affine in the path motion that limits bound the optimal timing law with.
"""
