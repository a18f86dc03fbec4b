"""The exact chain for many placements at once, and where it runs.

- :mod:`placement.evaluation.evaluator`: path -> base frame -> kinematics -> dynamics -> drives ->
  objectives and limits, batched over placements;
- :mod:`placement.contract.batch`: what the chain computes for a batch, handed to objectives and limits;
- :mod:`placement.evaluation.results`: evaluations and placement details;
- :mod:`placement.evaluation.parallel`: this machine's process pool or a Dask cluster.
"""
