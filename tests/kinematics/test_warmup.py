"""A first compile's shares: the helper process compiles the kernels for the argument types the path solve
passes them, so that this process finds them in the cache instead of compiling them again."""

import subprocess
import sys

# The entry points are compiled afresh (uncached), so that numba infers the types they pass their callees
# again; the callees come from the cache when they are in it for those types (a second signature otherwise).
SHARES = """
import numba
from placement.kinematics import kernels, warmup
for name in ("solve_paths", "rates", "rotation_vectors"):
    setattr(kernels, name, numba.njit(getattr(kernels, name).py_func))
warmup.helper_share()
warmup._own_share()
print(*(len(function.signatures) for function in (kernels._buffers, kernels._newton_one, kernels.log3)))
"""


def test_the_path_solve_calls_what_the_helper_compiled():
    """The helper's share then this process's: the path solve adds no second signature to what the helper compiled
    (a function compiled for other argument types is compiled twice)."""
    run = subprocess.run([sys.executable, "-c", SHARES], capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1", "1", "1"]
