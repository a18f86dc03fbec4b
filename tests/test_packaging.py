"""The wheel ships every module, the top-level robots/ and the type hints' marker (py.typed), and runs outside
the clone."""

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

from placement.kinematics import kernels
from placement.kinematics.warmup import touch_kernels
from tests.support.paths import ROOT


def test_the_wheel_holds_every_module_and_robot_and_runs_from_elsewhere(tmp_path):
    source = tmp_path / "source"  # a clean copy: no build/ left over from an earlier build
    for part in ("placement", "robots"):
        shutil.copytree(ROOT / part, source / part, ignore=shutil.ignore_patterns("__pycache__"))
    for part in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / part, source / part)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w",
                    str(tmp_path), str(source)], check=True, capture_output=True, timeout=300)
    wheel = next(tmp_path.glob("path_placement-*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    modules = {p.relative_to(ROOT).as_posix() for p in (ROOT / "placement").rglob("*.py")}
    robots = {"placement/robots/" + p.relative_to(ROOT / "robots").as_posix() for p in (ROOT / "robots").rglob("*")
              if p.is_file() and p.suffix in (".py", ".urdf", ".yaml", ".md") and "__pycache__" not in p.parts}
    assert {"placement/robots/orthoglide/orthoglide.urdf", "placement/robots/orthoglide/orthoglide.yaml"} <= robots
    assert modules - names == set() and robots - names == set()
    assert "placement/py.typed" in names  # PEP 561: type checkers read the package's own hints
    unpacked = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(unpacked)
    share_compiled_kinematics(unpacked / "placement" / "kinematics")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    result = subprocess.run([sys.executable, "-m", "placement", "check", "orthoglide", "--samples", "20"],
                            cwd=elsewhere, env={"PYTHONPATH": str(unpacked), "PATH": "/usr/bin:/bin"},
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr
    assert f"{unpacked}/placement/robots/orthoglide/orthoglide.yaml" in result.stdout
    assert "exact to round-off" in result.stdout


def share_compiled_kinematics(installed) -> None:
    """Numba's cache of the generic kinematics compiled here (or loaded), copied beside the installed modules.

    Numba keys a cached kernel by its source file's content and its byte code, not by its place: the installed
    wheel's modules, identical to the clone's, load the kernels from this copy instead of compiling them again
    (some 17 s of CPU). Modules that differed from the clone's would be compiled, and run all the same.
    """
    touch_kernels()
    cache = Path(kernels.solve_paths.stats.cache_path)  # __pycache__ beside kernels.py, or under NUMBA_CACHE_DIR
    (installed / "__pycache__").mkdir(exist_ok=True)
    for file in [*cache.glob("kernels.*.nbi"), *cache.glob("kernels.*.nbc")]:
        shutil.copy(file, installed / "__pycache__" / file.name)
