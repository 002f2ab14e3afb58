"""The documentation holds together: every relative link of README.md, docs/*.md and the notebooks'
Markdown cells reaches a file of the repository (and its #anchor a heading of that file, by
GitHub's rules), the README stays a page a reader finishes, and no page refers to anything outside
the repository but the chapter's citation and well-known package sites."""

import json
import re
from pathlib import Path
from urllib.parse import unquote

import pytest

from glamas.paths import REPO

README = REPO / "README.md"
PAGES = [README, *sorted((REPO / "docs").glob("*.md"))]
NOTEBOOKS = sorted((REPO / "notebooks").glob("*.ipynb"))
README_LINES, LINE_CHARS, ROW_CHARS = 210, 300, 340
"""The README's most lines, and its longest line of prose and of a table (a row cannot be wrapped)."""
KNOWN_SITES = ("pypi.org", "numpy.org", "numba.pydata.org", "matplotlib.org", "joblib.readthedocs.io",
               "docs.dask.org", "pettingzoo.farama.org", "jupyter.org", "doi.org", "link.springer.com")
"""Sites a page may link to: package sites, and where the chapter is published."""
OUTSIDE = {
    "a path of some machine": r"(?<![\w.~-])/(?:work|tmp|home|root|Users|mnt|srv|var)/",
    "a home directory": r"(?<![\w/])~/",
    "an issue or session": r"(?i)\b(?:issues?|sessions?)\b",
    "an issue number": r"(?<![\w&/])#\d+\b",
    "a machine's address": r"\blocalhost\b|\b\d{1,3}(?:\.\d{1,3}){3}\b|\b[\w.-]+@[\w-]+\.[\w.-]+",
}
"""What points outside the repository, by what it is."""
LINK = re.compile(r"!?\[([^\]]*)\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
URL = re.compile(r"\b[a-z][a-z0-9+.-]*://([^/\s)>`'\"]+)", re.IGNORECASE)


def _prose(markdown: str) -> str:
    """``markdown`` without its fenced code blocks and code spans, where links are not links."""
    without_fences = re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", markdown, flags=re.MULTILINE | re.DOTALL)
    return re.sub(r"`[^`]*`", "", without_fences)


def _notebook_markdown(path: Path) -> str:
    cells = json.loads(path.read_text())["cells"]
    return "\n\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")


def _text(path: Path) -> str:
    return _notebook_markdown(path) if path.suffix == ".ipynb" else path.read_text()


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: its text as rendered, lower case, without punctuation but
    hyphens and underscores, spaces turned into hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text
    text = re.sub(r"<[^>]+>", "", text).replace("`", "").replace("*", "")
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def anchors(path: Path) -> set:
    """The anchors of ``path``'s headings, a repeated one numbered as GitHub numbers it."""
    seen, found = {}, set()
    for line in _prose(_text(path)).splitlines():
        heading = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if heading:
            base = slug(heading.group(1))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else f"{base}-{count}")
    return found


def links(path: Path) -> list[str]:
    """The targets of the Markdown links and images of ``path`` (notebooks: of their Markdown cells)."""
    return [target for _, target in LINK.findall(_prose(_text(path)))]


def broken(path: Path, target: str) -> str | None:
    """Why the relative link ``target`` of ``path`` does not resolve, or None."""
    if URL.match(target) or target.startswith("mailto:"):
        return None  # checked by test_nothing_refers_outside_the_repository
    file_part, _, anchor = target.partition("#")
    destination = (path.parent / unquote(file_part)).resolve() if file_part else path
    if not destination.is_relative_to(REPO):
        return f"{target}: leaves the repository"
    if not destination.exists():
        return f"{target}: no such file"
    if anchor and (destination.suffix not in (".md", ".ipynb") or anchor not in anchors(destination)):
        return f"{target}: no heading #{anchor} in {destination.relative_to(REPO)}"
    return None


@pytest.mark.parametrize("path", PAGES + NOTEBOOKS, ids=lambda p: str(p.relative_to(REPO)))
def test_every_relative_link_resolves(path):
    assert [why for target in links(path) if (why := broken(path, target))] == []


@pytest.mark.parametrize("path", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_nothing_refers_outside_the_repository(path):
    text = path.read_text()
    found = [f"{what}: {match.group(0)!r}" for what, pattern in OUTSIDE.items()
             for match in re.finditer(pattern, text)]
    found += [f"a site: {match.group(0)!r}" for match in URL.finditer(text)
              if match.group(1).lower() not in KNOWN_SITES and not match.group(0).lower().startswith("tcp://host")]
    assert found == []


def test_the_readme_is_a_page_a_reader_finishes():
    lines = README.read_text().splitlines()
    assert len(lines) <= README_LINES
    assert [n for n, line in enumerate(lines, 1)
            if len(line) > (ROW_CHARS if line.startswith("|") else LINE_CHARS)] == []


def test_the_readme_links_every_page_of_docs():
    linked = {(README.parent / target.partition("#")[0]).resolve() for target in links(README)}
    assert [p.name for p in PAGES[1:] if p.resolve() not in linked] == []


def test_the_link_checker_finds_what_is_broken(tmp_path, monkeypatch):
    assert slug("GLA (Section 4.1, eq. 12-15)") == "gla-section-41-eq-12-15"
    assert slug("The chapter's `make verify` *now*") == "the-chapters-make-verify-now"
    assert anchors(REPO / "docs" / "robustness.md") >= {"output-policy", "exit-codes"}
    assert broken(README, "docs/robustness.md#output-policy") is None
    assert broken(README, "docs/robustness.md#no-such-heading").endswith("no heading #no-such-heading in docs/robustness.md")
    assert broken(README, "docs/missing.md") == "docs/missing.md: no such file"
    assert broken(README, "../elsewhere.md") == "../elsewhere.md: leaves the repository"
    assert links(README) and "docs/ledger.md" in links(README)
    assert re.search(OUTSIDE["a path of some machine"], "see /work/main/README.md")
    assert re.search(OUTSIDE["an issue or session"], "fixed in this Session")
    assert not re.search(OUTSIDE["an issue number"], "[x](#exit-codes)")


def test_every_figure_of_every_experiment_has_its_gallery_row_with_its_notebook():
    """The README's gallery: one row per figure script of every registered experiment, linking the
    script, a notebook that exists and the committed PNG."""
    from glamas.experiments import registry

    rows = [line for line in README.read_text().splitlines() if line.startswith("|")]
    missing = []
    for name in registry.figure_scripts(chapter_only=False):
        row = next((line for line in rows if f"(paper_figures/{name}.py)" in line), None)
        notebooks = [] if row is None else re.findall(r"\((notebooks/[^)]+\.ipynb)\)", row)
        if row is None or f"(paper_figures/output/{name}.png)" not in row or not notebooks \
                or not all((REPO / notebook).exists() for notebook in notebooks):
            missing.append(name)
    assert missing == [], "figure scripts without a full gallery row (script, notebook, image)"
