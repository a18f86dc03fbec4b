"""Every internal link of the built site resolves: its file exists and, with a ``#fragment``, holds that id.

Run after the HTML build: ``python docs/check_links.py docs/_build/html``. External links (with a scheme, such as
``https:``) are not followed: the build machines reach no web site. Exits 1, listing the broken links, if any.
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class Page(HTMLParser):
    """The ids a page defines and the links it makes."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = dict(attrs)
        if values.get("id"):
            self.ids.add(str(values["id"]))
        if tag == "a" and values.get("name"):
            self.ids.add(str(values["name"]))
        for key in ("href", "src"):
            if tag in ("a", "img", "link", "script") and values.get(key):
                self.links.append(str(values[key]))


def parse(file: Path) -> Page:
    page = Page()
    page.feed(file.read_text(encoding="utf-8", errors="replace"))
    return page


def broken_links(site: Path) -> list[str]:
    """The internal links of every page under ``site`` that do not resolve, as "page: link (why)"."""
    pages = {file: parse(file) for file in site.rglob("*.html") if "_sources" not in file.parts}
    broken = []
    for file, page in pages.items():
        for link in page.links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc or link.startswith("mailto:"):
                continue
            target = (file.parent / unquote(parts.path)).resolve() if parts.path else file
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{file.relative_to(site)}: {link} (no such file)")
            elif parts.fragment and target.suffix == ".html":
                ids = (pages.get(target) or parse(target)).ids
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{file.relative_to(site)}: {link} (no such anchor)")
    return broken


def main() -> int:
    site = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/_build/html").resolve()
    broken = broken_links(site)
    for line in broken:
        print(line, file=sys.stderr)
    pages = sum(1 for file in site.rglob("*.html") if "_sources" not in file.parts)
    print(f"{pages} pages: {'every internal link resolves' if not broken else f'{len(broken)} broken internal links'}")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
