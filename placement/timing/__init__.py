"""Timing laws: how the tool moves along the path in time.

- :mod:`placement.path.paper_law`: each segment at its own constant feed (the paper's law);
- :mod:`placement.path.realistic_law`: stops at corners, jerk-limited feed profiles with look-ahead between them;
- :mod:`placement.timing.optimal`: as fast as the robot allows at each placement (TOPP-RA), bounded by
  every limit that supplies path bounds (:meth:`placement.contract.limit.Limit.path_bounds`);
- :mod:`placement.path.time_law`: a timing found per placement, and the chain rule of timed rates;
- :mod:`placement.timing.rules`: which law times a path: the one its objectives need, and the overrides
  of the path file's.
"""
