"""The built-in robots, shipped as data inside the wheel as ``placement.robots``.

Each folder holds one robot: a sidecar YAML named after the folder, its URDF (for a closed-loop
machine), a README of sources, and optionally a closed-form kinematics plug-in.
"""
