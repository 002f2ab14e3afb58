"""The book (`make book`): the README, the notebooks with their committed outputs (nothing is
executed) and docs/ as one site, built by Sphinx from the repository's root with this directory
as its configuration (`sphinx-build -c book . out/book/html`)."""

project = "glamas"
author = "The glamas authors"
copyright = "The glamas authors; code MIT, text and figures CC BY 4.0"

extensions = ["myst_nb", "sphinx_external_toc"]
external_toc_path = "book/_toc.yml"
include_patterns = ["README.md", "notebooks/*.ipynb", "docs/*.md"]

nb_execution_mode = "off"  # the committed outputs, from the paper-scale runs
nb_render_markdown_format = "gfm"  # Markdown outputs hold tables (verdicts, measurements)
myst_heading_anchors = 6  # the pages link to headings by GitHub's anchors (#the-tests-time)

html_theme = "sphinx_book_theme"
html_title = "glamas"
html_theme_options = {"show_toc_level": 2}
html_show_sphinx = False
html_extra_path = ["extra"]  # index.html, which opens the front page (README.html)
html_static_path = ["static"]
html_css_files = ["tables.css"]
