"""Sphinx configuration of the documentation site (``sphinx-build -W --keep-going docs docs/_build/html``).

Everything a page shows that the code can say is produced at build time: the command line's reference from its
argparse parsers (sphinx-argparse), command output (sphinxcontrib-programoutput), the API from the docstrings
(autodoc, napoleon for the Google style), the input files' JSON Schemas and field tables from the pydantic models
(``_ext/schemas.py``), and the gallery's figures by running ``examples/gallery/*.py`` (sphinx-gallery).
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path[:0] = [str(DOCS / "_ext"), str(ROOT)]
os.environ.setdefault("MPLBACKEND", "Agg")
warnings.filterwarnings("ignore", message=".*set_application.* is deprecated")  # sphinx-autodoc-typehints on Sphinx 9

from placement import distribution  # noqa: E402

project = "placement"
author = "the placement authors"
copyright = "the placement authors, BSD-3-Clause"  # noqa: A001
release = distribution.version()
version = release
extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_autodoc_typehints",
    "sphinxarg.ext",
    "sphinxcontrib.programoutput",
    "sphinx_gallery.gen_gallery",
    "schemas",
]
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "**/README.md", "gallery/*.ipynb", "gallery/*.py",
                    "gallery/*.zip", "gallery/*.md5", "gallery/*.json"]
root_doc = "index"
smartquotes = False  # "--tool" in help texts stays two hyphens
suppress_warnings = ["misc.highlighting_failure"]  # docs/paths.md shows JSON with "..." for the rest
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}

# Markdown (MyST): GitHub-style anchors for the existing pages' "(#section)" links; $...$ maths; ::: fences.
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist", "attrs_inline"]
myst_heading_anchors = 4

html_theme = "furo"
html_title = f"placement {release}"
html_static_path: list[str] = []
(DOCS / "_build_generated" / "extra").mkdir(parents=True, exist_ok=True)
html_extra_path = ["_build_generated/extra"]  # schemas/*.schema.json at the site's root, for editors

# The API reference: the public names of placement/__init__.py, Google-style docstrings, type hints from the
# signatures. Nitpicky: every cross-reference must resolve, except to libraries without an inventory here.
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
typehints_use_signature = False
autodoc_typehints_description_target = "documented"  # a pydantic model's fields are in the schema reference
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_attr_annotations = True
nitpicky = True
nitpick_ignore_regex = [
    # Libraries whose inventories are not fetched (the build needs no network) and the standard library's names.
    (r"py:.*", r"(numpy|np|pinocchio|pin|coal|scipy|pydantic|pydantic_core|annotated_types|concurrent|collections|"
               r"typing|types|abc|enum|dataclasses|numba|matplotlib|pathlib|argparse|multiprocessing|dask|distributed|"
               r"meshcat|viser|ruamel|yaml|tqdm|importlib)(\..*)?"),
    (r"py:.*", r"(NDArray|ndarray|ArrayLike|Executor|Future|Path|Callable|Sequence|Iterable|Iterator|Mapping|Any|"
               r"Self|Literal|Annotated|ClassVar|TypeVar|Model|Figure|Axes|Bbox|ModuleType|ABC)"),
    # The modules beneath the public names are not in this reference: a reference into them (placement.robot.
    # sidecar.Drive) is not checked; one to a public name (placement.Robot) is.
    (r"py:.*", r"placement\.[a-z_]+\..*"),
    (r"py:mod", r"placement\..*"),
    # Short names the docstrings of those modules use for their own neighbours, and tuple[float, ...]'s "...".
    (r"py:.*", r"(Drive|Sidecar|Workspace|ToolBody|Plane|ClosedFormFunction|CellFileError|plausibility_warnings|denser|"
               r"default_amplitude|Ellipsis)"),
]


def _autodoc_setup(app) -> None:  # noqa: ANN001
    """Docstrings as the site shows them: an attribute's or property's first line is prose, not "type: text"
    (napoleon would read "Where each number comes from: ..." as a type); a ``|`` is a character, not a
    substitution (``|best − worst|``); a pydantic model's fields are in the schema reference, not here."""
    from pydantic.fields import FieldInfo
    from sphinx.ext.napoleon.docstring import GoogleDocstring

    GoogleDocstring._parse_attribute_docstring = lambda self: self._consume_to_end()

    def escape_bars(app, what, name, obj, options, lines) -> None:  # noqa: ANN001
        lines[:] = [line.replace("|", "\\|") for line in lines]

    def skip_model_fields(app, what, name, obj, skip, options):  # noqa: ANN001, ANN202
        return True if isinstance(obj, FieldInfo) or name.startswith("model_") else None

    app.connect("autodoc-process-docstring", escape_bars, priority=400)
    app.connect("autodoc-skip-member", skip_model_fields)


def setup(app) -> None:  # noqa: ANN001
    _autodoc_setup(app)


# The command output on the pages, run at build time from the repository's root (examples/ paths as printed).
programoutput_use_ansi = False
programoutput_prompt_template = "$ {command}\n{output}"

# The gallery: examples/gallery/plot_*.py, each run at build time (a few seconds each).
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples" / "gallery"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "within_subsection_order": "FileNameSortKey",
    "min_reported_time": 1,
    "show_signature": False,
    "show_memory": False,
}

