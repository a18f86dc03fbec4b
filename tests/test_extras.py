"""The lean core: ``import placement`` and the main command need none of the extras' packages, a feature whose
extra is missing says which extra to install, and the extras of pyproject.toml bring what each feature imports.

A missing package is simulated as Python's import system allows: ``sys.modules[name] = None`` makes every import
of ``name`` fail with an ImportError, as if it were not installed.
"""

import json
import pickle
import re
import subprocess
import sys
import tomllib
from importlib import metadata

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from placement import distribution
from placement.__main__ import main
from placement.distribution import CLUSTER, FEATURES, FRONTS, PLOTS, SCENE, WORKBENCH, Feature
from placement.exceptions import MissingExtraError, PlacementError
from tests.support.paths import EXAMPLE, ROOT

OPTIONAL = sorted({module for feature in FEATURES for module in feature.modules} | {"dask", "umsgpack"})
PRELUDE = f"import json, sys\nOPTIONAL = {OPTIONAL!r}\n"
BLOCK_OPTIONAL = PRELUDE + "for name in OPTIONAL:\n    sys.modules[name] = None\n"
LOADED = "print(json.dumps(sorted({name.split('.')[0] for name in sys.modules} & set(OPTIONAL))))\n"


def python(code: str, *arguments: str) -> subprocess.CompletedProcess:
    """``code`` run by this Python in a fresh process, from the repository's root, with ``arguments``."""
    return subprocess.run([sys.executable, "-c", code, *arguments], cwd=ROOT, capture_output=True, text=True,
                          timeout=300, check=False)


def loaded_after(code: str) -> list[str]:
    """The optional packages a fresh process has imported after running ``code``."""
    result = python(PRELUDE + code + "\n" + LOADED)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.splitlines()[-1])


def test_import_placement_loads_no_optional_package():
    assert loaded_after("import placement") == []


def test_the_main_command_loads_no_optional_package():
    assert loaded_after("from placement.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass") == []


def test_the_main_command_runs_with_every_optional_package_missing():
    result = python(BLOCK_OPTIONAL + "from placement.cli import main\n"
                    "sys.exit(main(['--robot', 'orthoglide', '--path', sys.argv[1], '--generations', '6', "
                    "'--population', '16', '--quiet']))", str(EXAMPLE))
    assert result.returncode == 0, result.stderr
    assert "best placement (least energy)" in result.stdout and "gain:" in result.stdout


def test_the_library_names_the_missing_extra():
    """Each optional part of the library, its packages missing: an ImportError that is a MissingExtraError, before
    any work (the front before its searches, the cluster before connecting)."""
    code = BLOCK_OPTIONAL + """
from placement import load_path, load_robot, pareto_front
from placement.evaluation.parallel import cluster
from placement.exceptions import MissingExtraError

def attempt(action):
    try:
        action()
    except MissingExtraError as error:
        return [error.extra, isinstance(error, ImportError), str(error)]
    return None

def enter_cluster():
    with cluster("tcp://127.0.0.1:1"):
        pass

robot, path = load_robot("orthoglide"), load_path(sys.argv[1])
print(json.dumps({
    "scene": attempt(lambda: __import__("placement.output.scene")),
    "plots": attempt(lambda: __import__("placement.output.plots")),
    "workbench": attempt(lambda: __import__("placement.app.page")),
    "front": attempt(lambda: pareto_front(robot, path, ("energy", "dexterity"))),
    "cluster": attempt(enter_cluster),
}))
"""
    result = python(code, str(EXAMPLE))
    assert result.returncode == 0, result.stderr
    answers = json.loads(result.stdout.splitlines()[-1])
    expected = {"scene": SCENE, "plots": PLOTS, "workbench": WORKBENCH, "front": FRONTS, "cluster": CLUSTER}
    for part, feature in expected.items():
        extra, is_import_error, message = answers[part]
        assert extra == feature.extra and is_import_error, part
        assert message.startswith(f"{feature.words} needs the '{feature.extra}' extra: "
                                  f"pip install '{distribution.NAME}[{feature.extra}]'"), message


@pytest.mark.parametrize(("missing", "arguments", "feature"), [
    ("meshcat", ["--html", "scene.html"], SCENE),
    ("trimesh", ["--show"], SCENE),
    ("matplotlib", ["--objectives", "energy,dexterity", "--png", "front.png"], PLOTS),
    ("pymoo", ["--objectives", "energy,dexterity"], FRONTS),
    ("distributed", ["--scheduler", "tcp://127.0.0.1:1"], CLUSTER),
    ("matplotlib", ["map", "--grid", "x=-10:10:3,y=-10:10:3", "--png", "map.png"], PLOTS),
    ("meshcat", ["map", "--grid", "x=-10:10:3", "--html", "map.html"], SCENE),
    ("matplotlib", ["feed", "--at", "x=0", "--feeds", "0.2:0.6:3", "--png", "feed.png"], PLOTS),
    ("viser", ["app"], WORKBENCH),
    ("pymoo", ["app"], WORKBENCH),
])
def test_the_command_line_names_the_missing_extra_before_any_work(missing, arguments, feature, monkeypatch, tmp_path,
                                                                     capsys):
    monkeypatch.setitem(sys.modules, missing, None)
    monkeypatch.chdir(tmp_path)
    command = [arguments[0]] if arguments[0] in ("map", "feed", "app") else []
    options = arguments[len(command):]
    assert main([*command, "--robot", "orthoglide", "--path", str(EXAMPLE), *options]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(f"error: {feature.words} needs the '{feature.extra}' extra: "
                                   f"pip install '{distribution.NAME}[{feature.extra}]' ("), captured.err
    assert "best placement" not in captured.out and list(tmp_path.iterdir()) == []  # nothing searched or written


def test_a_missing_extra_error_travels_whole():
    error = MissingExtraError("plotting (--png)", "viz", "matplotlib", "placement", "No module named 'matplotlib'")
    assert isinstance(error, PlacementError) and isinstance(error, ImportError)
    copy = pickle.loads(pickle.dumps(error))
    assert type(copy) is MissingExtraError and str(copy) == str(error) and copy.extra == "viz"
    assert str(error) == ("plotting (--png) needs the 'viz' extra: pip install 'placement[viz]' "
                          "(No module named 'matplotlib')")


def test_require_imports_what_is_there_and_names_what_is_not(monkeypatch):
    distribution.require(Feature("nothing", "none", ("json", "csv")))
    monkeypatch.setitem(sys.modules, "csv", None)
    with pytest.raises(MissingExtraError, match=r"^nothing needs the 'none' extra: pip install 'path-placement\[none\]' "
                                                r"\(import of csv halted"):
        distribution.require(Feature("nothing", "none", ("json", "csv")))


def project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def closure(requirements: list[str]) -> set[str]:
    """The distributions the requirements install, with theirs, as this environment has them (normalised names);
    placement's own extras (``path-placement[viz]``) as pyproject.toml gives them, not as it was last installed."""
    seen: set[tuple[str, frozenset[str]]] = set()
    todo = [Requirement(text) for text in requirements]
    while todo:
        requirement = todo.pop()
        key = (canonicalize_name(requirement.name), frozenset(requirement.extras))
        if key in seen:
            continue
        seen.add(key)
        if key[0] == canonicalize_name(distribution.NAME):
            todo += [Requirement(text) for extra in requirement.extras for text in project()["optional-dependencies"][extra]]
            continue
        for text in metadata.requires(requirement.name) or []:
            needed = Requirement(text)
            if needed.marker is None or any(needed.marker.evaluate({"extra": extra})
                                            for extra in (*requirement.extras, "")):
                todo.append(needed)
    return {name for name, _ in seen}


def providers(module: str) -> set[str]:
    """The distributions that install the top-level module ``module`` (normalised names)."""
    return {canonicalize_name(name) for name in metadata.packages_distributions()[module]}


def test_each_feature_extra_brings_the_modules_it_imports_and_the_core_none_of_them():
    extras = project()["optional-dependencies"]
    core = closure(project()["dependencies"])
    for feature in FEATURES:
        assert feature.extra in extras, feature
        brought = closure(extras[feature.extra])
        for module in feature.modules:
            assert providers(module) & brought, f"{module}: not in the '{feature.extra}' extra"
            assert not providers(module) & core, f"{module}: the core installs it"
    assert not providers("dask") & core
    everything = closure(extras["all"])
    assert all(closure(extras[feature.extra]) <= everything for feature in FEATURES)
    assert everything <= closure(extras["test"])  # the suite tests every feature


def test_the_version_is_the_distributions_and_the_source_trees_without_it(monkeypatch, capsys):
    import placement

    assert placement.__version__ == metadata.version(distribution.NAME) == project()["version"]
    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"placement {placement.__version__}\n"

    def not_installed(name: str) -> str:
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(distribution.metadata, "version", not_installed)
    assert distribution.version() == project()["version"]  # read from the source tree's pyproject.toml
    assert re.fullmatch(r"\d+(\.\d+)*", distribution.version())
