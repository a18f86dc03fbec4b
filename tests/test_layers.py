"""The layers keep to their interfaces: only the robot package reads a robot's sidecar.

Every other module asks the robot (``Robot.workspace``, ``Robot.plane``, ``Robot.named_drives``, ...),
so the sidecar's schema can change behind ``placement.robot`` without touching the layers that use it.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OWNER = ROOT / "placement" / "robot"


def sidecar_reads(file: Path, root: Path = ROOT) -> list[str]:
    """Where a module reads an attribute called ``sidecar`` (``robot.sidecar``, ``batch.robot.sidecar``, ...)."""
    tree = ast.parse(file.read_text(encoding="utf-8"), filename=str(file))
    return [f"{file.relative_to(root)}:{node.lineno}: {ast.unparse(node)}" for node in ast.walk(tree)
            if isinstance(node, ast.Attribute) and node.attr == "sidecar"]


def test_only_the_robot_package_reads_the_sidecar():
    files = [file for folder in ("placement", "examples", "benchmarks") for file in sorted((ROOT / folder).rglob("*.py"))
             if OWNER not in file.parents]
    assert len(files) > 50
    reads = [read for file in files for read in sidecar_reads(file)]
    assert not reads, "read it through a property of placement.robot.model.Robot:\n" + "\n".join(reads)


def test_the_check_sees_a_read_and_not_the_sidecar_path(tmp_path):
    module = tmp_path / "module.py"
    module.write_text("def f(batch):\n    return batch.robot.sidecar.workspace, batch.robot.sidecar_path\n")
    assert sidecar_reads(module, tmp_path) == ["module.py:2: batch.robot.sidecar"]
