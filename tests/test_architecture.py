"""The package's layout holds: every package in one layer of the import-linter contract (pyproject.toml, checked
by ``lint-imports``), no import cycle, a short top level, files one can hold in one's head, and only
the robot package reads a robot's sidecar (every other module asks the robot: ``Robot.workspace``,
``Robot.plane``, ``Robot.named_drives``, ..., so the sidecar's schema can change behind it).

Imports are read from the source with ``ast``, two ways. As Python runs them when a module is
imported: the statements at a module's top level, less those under ``if TYPE_CHECKING``, each
reaching the module it names and every package above it (whose ``__init__`` runs first), except
the importing module's own packages. And as dependencies of the design: every import, in a
function or for type checking too, reaching the module it names; a package's own modules may
import their package.
"""

import ast
import tomllib
from pathlib import Path

import placement
from tests.support.paths import ROOT

PACKAGE = Path(placement.__file__).parent
MAX_TOP_LEVEL_MODULES = 8
MAX_LINES = 600
ONE_FILE_BY_NECESSITY = {"kinematics/kernels.py"}  # numba's cache does not follow calls into other files


def module_name(file: Path) -> str:
    parts = file.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(file): file for file in PACKAGE.rglob("*.py")}


def _type_checking_nodes(tree: ast.Module) -> set[int]:
    return {id(node) for statement in tree.body if isinstance(statement, ast.If)
            and "TYPE_CHECKING" in ast.unparse(statement.test) for node in ast.walk(statement)}


def imported_at_import_time(name: str) -> set[str]:
    """The package's modules that importing ``name`` runs directly."""
    tree = ast.parse(MODULES[name].read_text(encoding="utf-8"))
    skipped, named = _type_checking_nodes(tree), set()
    for statement in tree.body:
        if id(statement) in skipped:
            continue
        if isinstance(statement, ast.ImportFrom) and statement.module and statement.level == 0:
            named |= {f"{statement.module}.{alias.name}" if f"{statement.module}.{alias.name}" in MODULES
                      else statement.module for alias in statement.names}
        elif isinstance(statement, ast.Import):
            named |= {alias.name for alias in statement.names}
    parents = {".".join(module.split(".")[:i]) for module in named for i in range(1, module.count(".") + 1)}
    own = {".".join(name.split(".")[:i]) for i in range(1, name.count(".") + 2)}
    return {module for module in named | parents if module in MODULES and module not in own}


def named_anywhere(name: str) -> set[str]:
    """The package's modules that ``name`` imports anywhere (top level, functions, type checking)."""
    named = set()
    for node in ast.walk(ast.parse(MODULES[name].read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            named |= {f"{node.module}.{alias.name}" if f"{node.module}.{alias.name}" in MODULES else node.module
                      for alias in node.names}
        elif isinstance(node, ast.Import):
            named |= {alias.name for alias in node.names}
    return {module for module in named if module in MODULES and module != name
            and not (MODULES[module].name == "__init__.py" and name.startswith(module + "."))}


def cycle_through(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of the graph, as the modules along it, or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(node: str, path: list[str]) -> list[str] | None:
        state[node] = 1
        for successor in sorted(graph[node]):
            if state.get(successor) == 1:
                return path[path.index(successor):] + [successor] if successor in path else [node, successor]
            if successor not in state and (found := visit(successor, path + [successor])):
                return found
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state and (found := visit(start, [start])):
            return found
    return None


def test_no_import_cycle():
    graph = {name: imported_at_import_time(name) for name in MODULES}
    assert cycle_through(graph) is None, " -> ".join(cycle_through(graph) or [])


def test_no_import_cycle_even_through_imports_in_functions_or_for_type_checking():
    graph = {name: named_anywhere(name) for name in MODULES}
    assert cycle_through(graph) is None, " -> ".join(cycle_through(graph) or [])


def test_the_cycle_finder_finds_a_cycle():
    assert cycle_through({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert cycle_through({"a": {"b"}, "b": set()}) is None


def test_a_package_import_also_runs_the_packages_above_it():
    assert "placement.robot" in imported_at_import_time("placement.kinematics.base")  # via placement.robot.model
    assert "placement.kinematics" not in imported_at_import_time("placement.kinematics.base")  # its own package


def test_the_top_level_is_short():
    top = sorted(file.name for file in PACKAGE.glob("*.py"))
    assert len(top) <= MAX_TOP_LEVEL_MODULES, top


def test_no_module_is_too_long_to_hold_in_ones_head():
    long = {str(file.relative_to(PACKAGE)): n for file in PACKAGE.rglob("*.py")
            if (n := len(file.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert set(long) <= ONE_FILE_BY_NECESSITY, long


def sidecar_reads(file: Path, root: Path = ROOT) -> list[str]:
    """Where a module reads an attribute called ``sidecar`` (``robot.sidecar``, ``batch.robot.sidecar``, ...)."""
    tree = ast.parse(file.read_text(encoding="utf-8"), filename=str(file))
    return [f"{file.relative_to(root)}:{node.lineno}: {ast.unparse(node)}" for node in ast.walk(tree)
            if isinstance(node, ast.Attribute) and node.attr == "sidecar"]


def test_only_the_robot_package_reads_the_sidecar():
    owner = PACKAGE / "robot"
    files = [file for folder in ("placement", "examples", "benchmarks") for file in sorted((ROOT / folder).rglob("*.py"))
             if owner not in file.parents]
    assert len(files) > 50
    reads = [read for file in files for read in sidecar_reads(file)]
    assert not reads, "read it through a property of placement.robot.model.Robot:\n" + "\n".join(reads)


def test_the_sidecar_check_sees_a_read_and_not_the_sidecar_path(tmp_path):
    module = tmp_path / "module.py"
    module.write_text("def f(batch):\n    return batch.robot.sidecar.workspace, batch.robot.sidecar_path\n")
    assert sidecar_reads(module, tmp_path) == ["module.py:2: batch.robot.sidecar"]


def contract_layers() -> list[list[str]]:
    """The layers of pyproject.toml's import-linter contract, bottom last, each a list of its packages."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    (contract,) = [c for c in config["contracts"] if c["type"] == "layers"]
    assert contract["containers"] == ["placement"]
    return [[name.strip() for name in layer.replace(":", "|").split("|")] for layer in contract["layers"]]


def test_every_package_and_top_level_module_is_in_one_layer():
    listed = [name for layer in contract_layers() for name in layer]
    assert len(listed) == len(set(listed)), listed
    own = {file.stem if file.suffix else file.name for file in PACKAGE.iterdir()
           if (file.suffix == ".py" and file.stem not in ("__init__", "__main__")) or (file / "__init__.py").is_file()}
    assert own == set(listed), f"not in a layer: {sorted(own - set(listed))}; no such package: {sorted(set(listed) - own)}"


def test_the_plug_in_contract_is_below_its_members_and_above_the_physics():
    order = {name: depth for depth, layer in enumerate(contract_layers()) for name in layer}
    assert order["objectives"] < order["contract"] and order["limits"] < order["contract"]  # the list is top first
    assert order["contract"] < order["energy"] < order["kinematics"] < order["robot"] < order["path"]
