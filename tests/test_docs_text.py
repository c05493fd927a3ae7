"""What the pages say: sources cited, not how they were found; the validation page opens with its summary.

The user pages (README.md, docs/, benchmarks/README.md, the validation
scripts) cite papers and public repositories, never the way a source was
looked up or how much time there was, and name what a section is about
rather than an internal issue number.  docs/validation.md is a summary
table with a page per topic (docs/validation/), so that nobody scrolls
through the whole record.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

#: Phrases that tell how the project was researched or run, not what it is.
HOW_FOUND = re.compile(
    r"search[ ]tool|code[ ]index|search[ ]index|find[_]string|stored file id|not reachable|was reachable"
    r"|fetched here|\bsessions?\b|\bagents?\b|\bhelpers'|other helpers|time allowed",
    re.I,
)
#: Internal issue numbers, and "the issue" as a source of a criterion.
ISSUE = re.compile(r"\bissues? \d+|\bthe issue'?s?\b|\(issue\b", re.I)


def user_pages():
    pages = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", ROOT / "benchmarks" / "README.md"]
    pages += [p for p in DOCS.rglob("*.md") if "_build" not in p.parts and p.name != "changelog.md"]
    pages += sorted((ROOT / "validation").glob("*.py"))
    return pages


@pytest.mark.parametrize("page", user_pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_cite_sources_not_how_they_were_found(page):
    text = page.read_text(encoding="utf-8")
    bad = []
    for n, line in enumerate(text.splitlines(), 1):
        for pattern in (HOW_FOUND, ISSUE):
            m = pattern.search(line)
            if m:
                bad.append(f"{page.relative_to(ROOT)}:{n}: {m.group(0)!r} in {line.strip()[:100]!r}")
    assert bad == [], "\n".join(bad)


def test_validation_opens_with_its_summary_table():
    """A one-screen table (quantity, reference, ours, z or relative error, the page) before anything else."""
    text = (DOCS / "validation.md").read_text(encoding="utf-8")
    lines = text.splitlines()
    assert lines[0].startswith("# ")
    first_row = next(i for i, line in enumerate(lines) if line.startswith("|"))
    assert not any(line.startswith("## ") for line in lines[:first_row]), "a section before the summary"
    header = lines[first_row].lower()
    for column in ("quantity", "reference", "ours", "z or relative"):
        assert column in header, column
    rows = [line for line in lines[first_row + 2 :] if line.startswith("|")]
    assert 10 <= len(rows) <= 24, f"{len(rows)} rows: one screen"
    # every row names the page with its detail, and every page is in the toctree
    pages = set()
    for row in rows:
        m = re.search(r"\]\((validation/[a-z-]+)\.md\)", row)
        assert m, f"no link to a detail page: {row[:80]}"
        assert (DOCS / f"{m.group(1)}.md").is_file(), m.group(1)
        pages.add(m.group(1))
    toctree = text[text.index("```{toctree}") :]
    for page in pages:
        assert page in toctree, page
    assert len(text.split()) < 1000, "the summary page holds the summary, the pages the detail"


def test_validation_detail_pages_are_each_short_enough_to_read():
    for page in sorted((DOCS / "validation").glob("*.md")):
        lines = page.read_text(encoding="utf-8").splitlines()
        assert lines[0].startswith("# "), page.name
        assert len(lines) < 600, f"{page.name}: {len(lines)} lines"
