"""`make book` builds the reproduction as one site, and the site holds together: every page of
book/_toc.yml is built, every relative link, image, script and style sheet of every page reaches a
file of the site (and its #anchor an element of that page), every notebook page shows each image
its notebook's outputs hold, and in a real browser (headless chromium, where installed) every image
of the front page and of a notebook's page loads. Every Markdown table of a notebook, in its cells
and its outputs, is rendered as a table.

`make book-check` runs this file (`make test` leaves it out: the book is built in an environment
of its own, .venv-book, made on first use)."""

import json
import os
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

from glamas.paths import REPO

TOC = REPO / "book" / "_toc.yml"
BOOK_PYTHON = REPO / ".venv-book" / "bin" / "python"
CHROMIUM = Path(os.environ.get("CHROMIUM", "/usr/bin/chromium"))
BROWSED = ("README", "notebooks/04_gridworld_2observe")
"""The pages opened in the browser: the front page and a notebook with many figures."""


class _Page(HTMLParser):
    """The targets a page refers to (links, images, scripts, style sheets) and the ids it holds."""

    def __init__(self):
        super().__init__()
        self.targets, self.ids, self.images, self.tables = [], set(), [], 0

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.ids.update(value for key, value in attrs.items() if key in ("id", "name") and value)
        for key in ("href", "src"):
            if attrs.get(key):
                self.targets.append(attrs[key])
        if tag == "img" and attrs.get("src"):
            self.images.append(attrs["src"])
        self.tables += tag == "table"


def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def broken(site: Path) -> list[str]:
    """Every relative reference of the HTML pages under ``site`` (the theme's templates in _static
    aside) that reaches no file of the site, or no element of its page with the #anchor it names,
    as "page: target (why)"."""
    site = site.resolve()
    pages = {path: _parse(path) for path in sorted(site.rglob("*.html")) if "_static" not in path.parts}
    found = []
    for path, page in pages.items():
        for target in page.targets:
            parts = urlsplit(target)
            if parts.scheme or target.startswith("//"):
                continue  # another site, or data: and mailto:
            destination = (path.parent / unquote(parts.path)).resolve() if parts.path else path
            where = f"{path.relative_to(site)}: {target}"
            if not destination.is_relative_to(site):
                found.append(f"{where} (leaves the site)")
            elif not destination.exists():
                found.append(f"{where} (no such file)")
            elif parts.fragment and destination.suffix == ".html" and \
                    unquote(parts.fragment) not in pages.get(destination, _parse(destination)).ids:
                found.append(f"{where} (no element #{parts.fragment})")
    return found


def toc_pages() -> list[str]:
    """The pages book/_toc.yml lists (its root first), as paths without their suffix."""
    text = TOC.read_text()
    return re.findall(r"^root:\s*(\S+)", text, re.MULTILINE) + re.findall(r"-\s*file:\s*(\S+)", text)


def output_images(notebook: Path) -> int:
    """How many images the committed outputs of ``notebook`` hold."""
    cells = json.loads(notebook.read_text())["cells"]
    return sum(any(kind.startswith("image/") for kind in output.get("data", {}))
               for cell in cells for output in cell.get("outputs", []))


RULE = re.compile(r"^\|(?:\s*:?-+:?\s*\|)+\s*$", re.MULTILINE)
"""The rule under a Markdown table's header."""


def markdown_tables(notebook: Path) -> int:
    """How many Markdown tables ``notebook`` holds: in its Markdown cells and its Markdown outputs
    (the verdict tables and glamas.tables)."""
    cells = json.loads(notebook.read_text())["cells"]
    texts = ["".join(cell["source"]) for cell in cells if cell["cell_type"] == "markdown"]
    texts += ["".join(output["data"]["text/markdown"]) for cell in cells for output in cell.get("outputs", [])
              if "text/markdown" in output.get("data", {})]
    return sum(len(RULE.findall(text)) for text in texts)


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The book as `make book` builds it (any Sphinx warning fails the build)."""
    out = tmp_path_factory.mktemp("book")
    done = subprocess.run(["make", "--no-print-directory", "book", f"BOOK_OUT={out}"], cwd=REPO,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, f"make book failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return out / "html"


def test_every_page_of_the_table_of_contents_is_built(site):
    assert [page for page in toc_pages() if not (site / f"{page}.html").is_file()] == []
    assert (site / "index.html").is_file()


def test_the_book_holds_the_readme_every_notebook_and_every_doc():
    listed = set(toc_pages())
    pages = ["README", *(f"notebooks/{p.stem}" for p in (REPO / "notebooks").glob("*.ipynb")),
             *(f"docs/{p.stem}" for p in (REPO / "docs").glob("*.md"))]
    assert [page for page in pages if page not in listed] == []


def test_every_link_image_and_anchor_of_the_book_resolves(site):
    assert broken(site) == []


def test_every_notebook_page_shows_its_images(site):
    shown = {page: len(_parse(site / f"{page}.html").images) for page in toc_pages()}
    missing = [f"{p.stem}: {shown[f'notebooks/{p.stem}']} of {output_images(p)}"
               for p in sorted((REPO / "notebooks").glob("*.ipynb"))
               if shown[f"notebooks/{p.stem}"] < output_images(p)]
    assert missing == []


def test_every_markdown_table_of_a_notebook_is_rendered_as_a_table(site):
    shown = {p.stem: _parse(site / "notebooks" / f"{p.stem}.html").tables for p in (REPO / "notebooks").glob("*.ipynb")}
    assert [f"{p.stem}: {shown[p.stem]} of {markdown_tables(p)}" for p in sorted((REPO / "notebooks").glob("*.ipynb"))
            if shown[p.stem] < markdown_tables(p)] == []


def test_the_link_checker_finds_what_is_broken(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "fig.png").write_bytes(b"")
    (tmp_path / "docs" / "a.html").write_text('<h1 id="top">A</h1><img src="../fig.png"><a href="#top">x</a>'
                                             '<a href="https://doi.org/x">y</a>')
    (tmp_path / "index.html").write_text('<a href="docs/a.html#top">a</a><a href="docs/a.html#gone">b</a>'
                                         '<img src="missing.png"><a href="../outside.html">c</a>')
    assert broken(tmp_path) == ["index.html: docs/a.html#gone (no element #gone)",
                                "index.html: missing.png (no such file)",
                                "index.html: ../outside.html (leaves the site)"]


def test_every_image_of_the_front_page_and_a_notebook_loads_in_a_browser(site):
    if not CHROMIUM.exists() or shutil.which("make") is None or subprocess.run(
            [BOOK_PYTHON, "-c", "import playwright"], capture_output=True).returncode != 0:
        pytest.skip(f"no browser check: needs chromium at {CHROMIUM} and Playwright in .venv-book")
    pages = [site / f"{page}.html" for page in BROWSED]
    done = subprocess.run([BOOK_PYTHON, REPO / "book" / "check_in_browser.py", *pages],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    found = json.loads(done.stdout)
    assert all(found[str(page)] for page in pages)  # each page shows images
    assert {page: [src for src, width in images if width == 0] for page, images in found.items()} == \
        {str(page): [] for page in pages}
