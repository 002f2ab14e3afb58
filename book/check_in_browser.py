"""Open pages of the built book in headless chromium and report every image on them:
``python book/check_in_browser.py PAGE.html ... [--screenshot DIR]`` prints one JSON object, each
page's path -> a list of [src, naturalWidth] (0: the image did not load). Run by tests/test_book.py
in the book's environment (.venv-book, which has Playwright); Playwright drives the system's
chromium (CHROMIUM, default /usr/bin/chromium) and downloads no browser of its own."""

import argparse
import json
import os
from pathlib import Path

from playwright.sync_api import sync_playwright

CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
IMAGES = """async () => {
    const images = Array.from(document.images);
    images.forEach(image => { image.loading = "eager"; });
    await Promise.all(images.map(image => image.decode().catch(() => null)));
    return images.map(image => [image.getAttribute("src"), image.naturalWidth]);
}"""
"""Every image of the page once each has loaded or failed (a lazy one made eager first)."""


def images(pages: list[Path], screenshots: Path | None) -> dict:
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 1000})
        found = {}
        for path in pages:
            page.goto(path.resolve().as_uri(), wait_until="load")
            found[str(path)] = page.evaluate(IMAGES)
            if screenshots:
                page.screenshot(path=str(screenshots / f"{path.stem}.png"))
        browser.close()
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("pages", nargs="+", type=Path)
    parser.add_argument("--screenshot", type=Path, help="a directory: a screenshot of each page's top")
    options = parser.parse_args()
    print(json.dumps(images(options.pages, options.screenshot)))


if __name__ == "__main__":
    main()
