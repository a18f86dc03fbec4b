"""A first compile's stages: each process compiles the kernels for the argument types their callers pass, so that
the other process (and the solver's own calls) find them in the cache instead of compiling them again; the helper
starts without the library's import."""

import os
import subprocess
import sys

from placement.kinematics import warmup

INLINED = {"least_squares", "_newton_step", "_model_remainder", "_factor_passive", "_task_inverse", "drifts",
           "_assemble", "_branch_scale"}

STAGES = """
import sys
from placement.kinematics import compile_stages, kernels, warmup
sample = compile_stages.Sample.build()
for stage in sys.argv[1:]:
    if stage == "entry_points":
        warmup._run_entry_points(sample)
        print("signatures", *(len(function.signatures) for function in warmup.ENTRY_POINTS))
    elif stage == "in_cache":
        print("in_cache", warmup._in_cache(sample))
    elif stage == "touch":
        warmup.touch_kernels()
        print("loaded", *sorted(name for name, function in vars(kernels).items()
                                if hasattr(function, "stats") and function.stats.cache_hits))
    else:
        getattr(compile_stages, stage)() if stage == "helper_stages" else getattr(compile_stages, stage)(sample)
print("compiled", *sorted(name for name, function in vars(kernels).items()
                          if hasattr(function, "stats") and function.stats.cache_misses))
"""


def _run(cache: str, *stages: str) -> dict[str, list[str]]:
    """Run some stages in a new process on the cache folder ``cache``: its output lines by their first word."""
    run = subprocess.run([sys.executable, "-c", STAGES, *stages], env={**os.environ, "NUMBA_CACHE_DIR": cache},
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    return {line.split()[0]: line.split()[1:] for line in run.stdout.splitlines()}


def test_no_function_is_compiled_twice(tmp_path):
    """The command's leaves, the helper's stages, then the command's tangent map and path solve, each in a process of
    its own on one cache: no process compiles a function another compiled, and the solver's calls of the entry
    points then add no second signature; a function inlined into its one caller is never compiled on its own; the
    cache then holds the kernels, which an empty one does not, and a later command loads the probe and the entry
    points alone."""
    cache = str(tmp_path / "cache")
    leaves = _run(cache, "compile_probe", "compile_leaves")
    helper = _run(cache, "helper_stages")
    command = _run(cache, "compile_tangent", "compile_paths", "entry_points")
    assert helper["low-level"] == [] and helper["newton"] == []  # announced
    compiled = [set(leaves["compiled"]), set(helper["compiled"]), set(command["compiled"])]
    assert {"_solve_square", "_newton_one", "rates", "solve_paths"} <= set.union(*compiled)
    assert not compiled[0] & compiled[1] and not compiled[0] & compiled[2] and not compiled[1] & compiled[2]
    assert not INLINED & set.union(*compiled)  # typed within their one caller, never compiled on their own
    assert command["signatures"] == ["1", "1", "1"]
    assert _run(cache, "in_cache")["in_cache"] == ["True"]
    assert _run(str(tmp_path / "empty"), "in_cache")["in_cache"] == ["False"]
    later = _run(cache, "touch")
    assert later["compiled"] == [] and later["loaded"] == ["_copy", "rates", "rotation_vectors", "solve_paths"]


def test_the_helper_imports_the_kernels_alone():
    """The helper's program loads the kernels, the tree and its stages, not the rest of the library."""
    packages = [("placement", str(warmup.PACKAGE_FOLDER)),
                ("placement.kinematics", str(warmup.PACKAGE_FOLDER / "kinematics"))]
    program = warmup.HELPER_PROGRAM.format(packages=packages).replace(
        "helper_stages()", "print(*sorted(name for name in sys.modules if name.startswith('placement')))")
    run = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["placement", "placement.kinematics", "placement.kinematics.compile_stages",
                                  "placement.kinematics.kernels", "placement.kinematics.tree"]
