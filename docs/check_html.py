"""Checks on the built site that Sphinx's warnings do not catch.

Run after the build (``.ci/run`` does)::

    python3 docs/check_html.py docs/_build/html

It prints one line per fault and exits 1 if there is any:

* a "Type:" field in the API reference.  The package's types live in its
  annotations, so such a field is a property's first line that Napoleon read
  as ``type: description`` (a summary with a colon in it);
* numpy's ``ArrayLike`` printed as its expansion (``_SupportsArray``, ...)
  instead of its name;
* a page that loads a script or a style from the network (MathJax from a
  CDN, say): the site is opened from the disk, offline;
* a page with math but without the local MathJax (``_static/mathjax``);
* a notebook's output that links a Dask dashboard (gone once the page is
  built).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

TYPE_FIELD = re.compile(
    r'<dt class="field-(?:odd|even)">Type<span class="colon">:</span></dt>\s*<dd[^>]*>(.*?)</dd>', re.S
)
EXPANDED = ("_SupportsArray", "_NestedSequence", "_Buffer")
REMOTE = re.compile(r'<(?:script|link)\b[^>]*\b(?:src|href)="(?:https?:)?//[^"]+"', re.I)
MATH = re.compile(r'class="math[" ]')
MATHJAX_LOCAL = re.compile(r'<script[^>]*src="(?:\.\./)*_static/mathjax/[a-z-]+\.js(?:\?v=[0-9a-f]+)?"')


def _text(fragment: str) -> str:
    return " ".join(re.sub(r"<[^>]+>", " ", fragment).split())


def faults(site: Path) -> list[str]:
    """Every fault of the built site in ``site`` (the HTML folder), one line each."""
    out = []
    for page in sorted(site.rglob("*.html")):
        rel = page.relative_to(site).as_posix()
        if rel.startswith("_modules/"):  # the highlighted sources (viewcode) print code as it is
            continue
        html = page.read_text(encoding="utf-8")
        if rel.startswith("api/"):
            for m in TYPE_FIELD.finditer(html):
                out.append(f"{rel}: a property's summary read as its type: {_text(m.group(1))!r}")
            for word in EXPANDED:
                if word in html:
                    out.append(f"{rel}: numpy's ArrayLike printed in full ({word})")
                    break
        for m in REMOTE.finditer(html):
            out.append(f"{rel}: loads from the network: {m.group(0)[:120]}")
        if MATH.search(html) and not MATHJAX_LOCAL.search(html):
            out.append(f"{rel}: has math but not the local MathJax (_static/mathjax)")
        if "dashboard: http" in html:
            out.append(f"{rel}: a cell prints a Dask dashboard's address")
    if not (site / "_static" / "mathjax" / "tex-chtml.js").is_file():
        out.append("_static/mathjax/tex-chtml.js is missing (sphinx-mathjax-offline, docs/conf.py)")
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(
            "usage: python3 docs/check_html.py HTML_FOLDER (the built site, e.g. docs/_build/html)",
            file=sys.stderr,
        )
        return 1
    site = Path(argv[0])
    if not (site / "index.html").is_file():
        print(f"{site}: no index.html; build the site first", file=sys.stderr)
        return 1
    found = faults(site)
    for line in found:
        print(line)
    print(f"{site}: {len(found)} faults" if found else f"{site}: no faults")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
