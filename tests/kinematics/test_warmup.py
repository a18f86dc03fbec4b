"""A first compile's shares: the helper process compiles the kernels for the argument types the path solve
passes them, so that this process finds them in the cache instead of compiling them again."""

import os
import subprocess
import sys

SHARES = """
from placement.kinematics import kernels, warmup
warmup.helper_share()
warmup._own_share()
print(*(len(function.signatures) for function in (kernels._buffers, kernels._newton_one, kernels.log3)))
"""


def test_the_path_solve_calls_what_the_helper_compiled(tmp_path):
    """In a process with an empty cache, the helper's share then this process's: the path solve adds no second
    signature to what the helper compiled (a function compiled for other argument types is compiled twice)."""
    run = subprocess.run([sys.executable, "-c", SHARES], env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)},
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["1", "1", "1"]
