"""Placing a path in the robot's base frame: the placement vector [x, y, z, φ, θ, ψ] and its transform
(:mod:`placement.placing.transform`)."""
