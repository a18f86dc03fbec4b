"""The wheel ships every module and the top-level robots/, and runs outside the clone."""

import shutil
import subprocess
import sys
import zipfile

from tests.support.paths import ROOT


def test_the_wheel_holds_every_module_and_robot_and_runs_from_elsewhere(tmp_path):
    source = tmp_path / "source"  # a clean copy: no build/ left over from an earlier build
    for part in ("placement", "robots"):
        shutil.copytree(ROOT / part, source / part, ignore=shutil.ignore_patterns("__pycache__"))
    for part in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / part, source / part)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w",
                    str(tmp_path), str(source)], check=True, capture_output=True, timeout=300)
    wheel = next(tmp_path.glob("placement-*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    modules = {p.relative_to(ROOT).as_posix() for p in (ROOT / "placement").rglob("*.py")}
    robots = {"placement/robots/" + p.relative_to(ROOT / "robots").as_posix() for p in (ROOT / "robots").rglob("*")
              if p.is_file() and p.suffix in (".py", ".urdf", ".yaml", ".md") and "__pycache__" not in p.parts}
    assert {"placement/robots/orthoglide/orthoglide.urdf", "placement/robots/orthoglide/orthoglide.yaml"} <= robots
    assert modules - names == set() and robots - names == set()
    unpacked = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(unpacked)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    result = subprocess.run([sys.executable, "-m", "placement", "check", "orthoglide", "--samples", "20"],
                            cwd=elsewhere, env={"PYTHONPATH": str(unpacked), "PATH": "/usr/bin:/bin"},
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr
    assert f"{unpacked}/placement/robots/orthoglide/orthoglide.yaml" in result.stdout
    assert "exact to round-off" in result.stdout
