#!/usr/bin/env python3
"""Check every internal link of the built manual (no network).

Usage: python3 scripts/check-links.py [SITE]      (default SITE: target/book)

For every HTML page of the site (the rustdoc tree under rust/ is only a link target: its own
links are rustdoc's), every relative `href`/`src` must name a file inside the site, and a
`#fragment` must be an `id` (or `name`) of the page it points to. Links with a scheme
(https:, mailto:, …) are not followed: the check needs no network. A link that leaves the site
(`../../examples/…` from a page of docs/) is an error too: the site is published without the
rest of the repository, so such a link is dead for its reader; write the path as code
(`examples/couette/in.couette2d`) or link a page of the manual.

Also checked: the relative links of README.md (the front page, outside the site) to files of the
repository, and their anchors into docs/*.md pages (through the built pages' ids).

Exit status 0 when every link resolves, 1 otherwise (each dead link is printed with its page).
"""

from __future__ import annotations

import re
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

ROOT = Path(__file__).resolve().parent.parent


class Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        for k in ("id", "name") if tag == "a" else ("id",):
            if a.get(k):
                self.ids.add(a[k])
        for k in ("href", "src"):
            v = a.get(k)
            if v is not None and not (tag == "link" and a.get("rel") == "preload"):
                self.links.append(v)


def parse(path: Path, cache: dict[Path, Page]) -> Page:
    if path not in cache:
        p = Page()
        p.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = p
    return cache[path]


def is_external(url: str) -> bool:
    s = urlsplit(url)
    return bool(s.scheme) or url.startswith("//")


def check_site(site: Path) -> list[str]:
    errors: list[str] = []
    cache: dict[Path, Page] = {}
    site = site.resolve()
    rust = site / "rust"
    pages = [p for p in site.rglob("*.html") if rust not in p.parents]
    for page in sorted(pages):
        rel = page.relative_to(site)
        # mdBook's 404 page uses site-root-relative links resolved by the server.
        if rel.name == "404.html":
            continue
        doc = parse(page, cache)
        for url in doc.links:
            if is_external(url) or url.startswith("javascript:"):
                continue
            s = urlsplit(url)
            if s.path.startswith("/"):
                errors.append(f"{rel}: absolute link {url} (write it relative to the page)")
                continue
            target = (page.parent / unquote(s.path)).resolve() if s.path else page
            if site not in target.parents and target != site:
                errors.append(
                    f"{rel}: {url} leaves the site (a repository file?): write the path as "
                    "code or link a page of the manual"
                )
                continue
            if target.is_dir():
                target = target / "index.html"
            if not target.is_file():
                errors.append(f"{rel}: dead link {url}")
                continue
            if s.fragment and target.suffix == ".html":
                ids = parse(target, cache).ids
                if unquote(s.fragment) not in ids:
                    errors.append(f"{rel}: dead anchor {url} (no id '{s.fragment}' in "
                                  f"{target.relative_to(site)})")
    return errors


LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")


def check_readme(site: Path) -> list[str]:
    """README.md's relative links: the file must exist; an anchor into docs/X.md must be an
    id of the built page X.html."""
    errors: list[str] = []
    cache: dict[Path, Page] = {}
    text = (ROOT / "README.md").read_text()
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    for url in LINK.findall(text):
        if is_external(url):
            continue
        s = urlsplit(url)
        target = ROOT / unquote(s.path)
        if not target.exists():
            errors.append(f"README.md: dead link {url}")
            continue
        if s.fragment and target.suffix == ".md":
            try:
                html = site / target.relative_to(ROOT / "docs").with_suffix(".html")
            except ValueError:
                continue  # a Markdown file outside the manual: anchors not checked
            if html.is_file() and unquote(s.fragment) not in parse(html, cache).ids:
                errors.append(f"README.md: dead anchor {url}")
    return errors


def main() -> int:
    site = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target/book"
    if not (site / "index.html").is_file():
        print(f"check-links: no site at {site} (build it: bash scripts/build-docs.sh)",
              file=sys.stderr)
        return 1
    errors = check_site(site) + check_readme(site)
    n_pages = sum(1 for p in site.rglob("*.html") if (site / "rust") not in p.parents)
    for e in errors:
        print(f"check-links: {e}", file=sys.stderr)
    if errors:
        print(f"check-links: {len(errors)} dead link(s) in {n_pages} pages", file=sys.stderr)
        return 1
    print(f"check-links: every internal link and anchor of {n_pages} pages and README.md resolves")
    return 0


if __name__ == "__main__":
    sys.exit(main())
