"""The generic kinematics' compiled kernels made ready before a command needs them: loaded from numba's cache, or,
on a machine's first run, compiled by two processes at once.

A first compile costs about 15 s of CPU. It is shared with a helper process in the stages of
:mod:`placement.kinematics.compile_stages`; both processes write numba's on-disk cache, which each reads
before compiling a function. This process waits for the helper's stage announcements (on the helper's
standard output) before the stages that call what the helper compiles, so that no function is compiled
twice; if the helper cannot start or stops early, this process compiles what is missing. When the cache holds
the kernels already, the helper is stopped at once. The helper imports
the kernels without the package's ``__init__`` (which loads the whole library, about 1 s of CPU): empty
package modules stand in for ``placement`` and ``placement.kinematics``.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from placement.kinematics import compile_stages, kernels
from placement.kinematics.batched import DAMPING, SETTINGS
from placement.kinematics.compile_stages import LOW_LEVEL, NEWTON, Sample

ENTRY_POINTS = (kernels.solve_paths, kernels.rates, kernels.rotation_vectors)
PACKAGE_FOLDER = Path(__file__).resolve().parent.parent  # placement/
HELPER_PROGRAM = """import sys, types
for name, folder in {packages!r}:
    package = types.ModuleType(name)
    package.__path__ = [folder]
    sys.modules[name] = package
from placement.kinematics.compile_stages import helper_stages
helper_stages()
"""


def touch_kernels() -> None:
    """Load or compile every kernel a robot uses (on a machine's first run some 8 s, shared with a helper
    process)."""
    if all(function.signatures for function in ENTRY_POINTS):  # this process has them already
        return
    helper = _start_helper()  # at once: it takes half a second to start
    sample = Sample.build()
    if not _in_cache(sample):
        _compile_in_stages(sample, helper)
    elif helper is not None:
        helper.terminate()
        helper.wait()
    _run_entry_points(sample)


def _compile_in_stages(sample: Sample, helper: subprocess.Popen | None) -> None:
    """This process's stages of a first compile, each after the helper's stages it calls (module docstring)."""
    compile_stages.compile_leaves(sample)
    _await(helper, LOW_LEVEL)
    compile_stages.compile_tangent(sample)
    _await(helper, NEWTON)
    compile_stages.compile_paths(sample)
    if helper is not None:
        helper.communicate()  # its last stage: the rates


def _in_cache(sample: Sample) -> bool:
    """Whether numba's cache holds the kernels (judged by a small one: a first run saves them all, and a change to
    kernels.py makes them all stale)."""
    compile_stages.compile_probe(sample)
    return bool(kernels._copy.stats.cache_hits)


def _start_helper() -> subprocess.Popen | None:
    """A Python process running :func:`placement.kinematics.compile_stages.helper_stages` on this process's
    import path, its standard output piped (None if none can start). Its errors are discarded: if it fails, this
    process compiles its stages."""
    path = [entry or os.getcwd() for entry in sys.path]
    packages = [("placement", str(PACKAGE_FOLDER)), ("placement.kinematics", str(PACKAGE_FOLDER / "kinematics"))]
    try:
        return subprocess.Popen([sys.executable, "-c", HELPER_PROGRAM.format(packages=packages)],
                                env={**os.environ, "PYTHONPATH": os.pathsep.join(path)}, stdin=subprocess.DEVNULL,
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    except OSError:
        return None


def _await(helper: subprocess.Popen | None, stage: str) -> None:
    """Wait until the helper says it has done ``stage`` (or has stopped; at once without a helper)."""
    if helper is None or helper.stdout is None:
        return
    for line in helper.stdout:
        if line.strip() == stage:
            return


def _run_entry_points(sample: Sample) -> None:
    """Run the path solve, the rates and the rotation vectors on the sample, as the solver calls them (compiled by
    now, or loaded from the cache)."""
    q, _, _ = kernels.solve_paths(sample.tree, sample.q, sample.positions, sample.rotations, np.zeros((2, 0)), False, 2,
                                  np.array([0, 1], dtype=np.int64), np.zeros((0, 5), dtype=np.int64),
                                  np.array([0.0, np.sqrt(2.0)]), SETTINGS)
    kernels.rates(sample.tree, q, np.zeros((2, 3)), np.zeros((2, 3)), DAMPING)
    kernels.rotation_vectors(sample.rotations)
