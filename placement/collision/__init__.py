"""Collision distances between a robot, its tool and its cell, batched over configurations.

- :mod:`placement.collision.geometry`: the collision geometry of a robot, its tool and a cell (coal, via Pinocchio);
- :mod:`placement.collision.pairs`: which bodies are checked against which;
- :mod:`placement.collision.distances`: :class:`placement.collision.distances.CollisionScene`, batched distances with a
  prefilter of compiled lower bounds (:mod:`placement.collision.bounds`).
"""
