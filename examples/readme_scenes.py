"""Regenerate the documentation's 3-D scene figures from the documentation's own commands.

Each figure is the ``--html`` page of a command the documentation prints (checked: the command must appear in
README.md or a page of docs/ word for word), rendered by headless Chromium (software WebGL) into docs/figures/.
A search takes a few minutes on a two-core machine; the three together about ten.

    python examples/readme_scenes.py            # every figure
    python examples/readme_scenes.py rectangles # those whose name contains the word
"""

from __future__ import annotations

import glob
import os
import shlex
import sys
import tempfile
import time
from pathlib import Path

from placement.__main__ import main as placement_main
from placement.output.scene import find_browser, screenshot

ROOT = Path(__file__).resolve().parent.parent
FIGURES = ROOT / "docs" / "figures"
SIZE = (1000, 700)  # px
SCENES = {  # figure -> the documentation's command, its --html file replaced by the figure's page
    "scene_rectangles.png":
        "python -m placement --robot orthoglide --path examples/paper_rectangles/*.yaml --html rectangles.html",
    "scene_pocket_cell.png":
        "python -m placement --robot orthoglide --path examples/pocket.yaml --cell examples/cell_orthoglide.yaml "
        "--html pocket.html",
    "scene_ur5_contour_cell.png":
        "python -m placement --robot ur5 --path examples/contour.yaml --cell examples/cell_ur5_table_wall.yaml "
        "--minimize --html contour.html",
}


def arguments(command: str, page: Path) -> list[str]:
    """The command's arguments after ``python -m placement`` (run from the repository's root), globs expanded as a
    shell does, its --html file replaced by ``page``."""
    words: list[str] = []
    for word in shlex.split(command)[3:]:
        words += sorted(glob.glob(word, root_dir=ROOT)) if "*" in word else [word]
    words[words.index("--html") + 1] = str(page)
    return words


def render(figure: str, command: str) -> None:
    """Run the command, render its page into docs/figures/``figure``."""
    pages = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").rglob("*.md") if "_build" not in p.parts)]
    text = " ".join(" ".join(page.read_text().replace("\\\n", " ").split()) for page in pages)
    if command not in text:
        raise SystemExit(f"{figure}: the command is no longer in README.md or a page of docs/: {command}")
    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "scene.html"
        start = time.perf_counter()
        if placement_main([*arguments(command, page), "--quiet"]) != 0:
            raise SystemExit(f"{figure}: the command failed: {command}")
        if not screenshot(page, FIGURES / figure, size=SIZE):
            raise SystemExit(f"{figure}: Chromium wrote no image")
    print(f"{figure}: {time.perf_counter() - start:.0f} s")


def main() -> None:
    if find_browser() is None:
        raise SystemExit("no Chromium-family browser: install Debian's chromium package")
    os.chdir(ROOT)  # the README's commands name files from the repository's root
    wanted = sys.argv[1:]
    for figure, command in SCENES.items():
        if not wanted or any(word in figure for word in wanted):
            render(figure, command)


if __name__ == "__main__":
    main()
