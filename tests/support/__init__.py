"""Helpers shared by the tests: robot copies, trajectories, analytic models, the MuJoCo model, paths."""
