"""Tool paths in their own frame F_p: the file schema, shapes, segments, G-code, pose lists and sampling.

A path file (:mod:`placement.path.path_file`) is read by :func:`placement.path.load.load_path` into a
:class:`placement.path.toolpath.ToolPath`: segments (:mod:`placement.path.segments`) written in
the file, read from a G-code program (:mod:`placement.path.gcode`) or a pose list
(:mod:`placement.path.poses`), with their feeds, process forces and timing law. The path is
sampled in time by its law (:mod:`placement.timing`) or along its arc length for the optimal law
(:mod:`placement.path.samples`).
"""

from placement.path.load import load_path
from placement.path.samples import PathGeometry, PathSamples
from placement.path.toolpath import ToolPath

__all__ = ["PathGeometry", "PathSamples", "ToolPath", "load_path"]
