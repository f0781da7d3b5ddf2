"""Every relative link and anchor in README.md and docs/*.md resolves.

A link's file must exist (a folder is fine), and its anchor (`page.md#anchor`, or
`#anchor` within the page) must be the GitHub slug of a heading in that page. Links to
http(s) and mailto are not checked; neither is text inside code blocks or code spans.
Only the standard library is used: this needs neither the compiled module nor numpy.
"""

from __future__ import annotations

import re
import unicodedata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
# [text](target) and ![alt](target), with an optional "title" after the target.
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^ {0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
EXTERNAL = ("http://", "https://", "mailto:")


def pages() -> list[Path]:
    """README.md and every Markdown page under docs/ (docs/bench/ included)."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def prose_lines(text: str) -> list[tuple[int, str]]:
    """(line number, line) outside fenced code blocks."""
    out, fence = [], None
    for number, line in enumerate(text.split("\n"), start=1):
        m = FENCE.match(line)
        if m:
            if fence is None:
                fence = m.group(1)
            elif m.group(1) == fence:
                fence = None
            continue
        if fence is None:
            out.append((number, line))
    return out


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: the rendered text in lower case, every character
    but letters, marks, digits, `_`, `-` and spaces dropped, spaces turned into `-`."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link reads as its text
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML tags
    kept = [
        ch
        for ch in text.lower()
        if ch in " -_" or unicodedata.category(ch)[0] in "LMN" or unicodedata.category(ch) == "Pc"
    ]
    return "".join(kept).replace(" ", "-")


def anchors(page: Path) -> set[str]:
    """The anchors of a page's headings, duplicates numbered `-1`, `-2`, ... as GitHub does."""
    seen: dict[str, int] = {}
    out = set()
    for _, line in prose_lines(page.read_text(encoding="utf-8")):
        m = HEADING.match(line)
        if not m:
            continue
        base = slug(m.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        out.add(base if count == 0 else f"{base}-{count}")
    return out


def links(page: Path) -> list[tuple[int, str]]:
    """(line number, target) of every link and image in a page's prose."""
    out = []
    for number, line in prose_lines(page.read_text(encoding="utf-8")):
        line = CODE_SPAN.sub("", line)
        out += [(number, m.group(1)) for m in LINK.finditer(line)]
        m = REFERENCE.match(line)
        if m:
            out.append((number, m.group(1)))
    return out


def broken_links(page_list: list[Path]) -> list[str]:
    """What does not resolve, one line each: `file:line: target: why`."""
    cache: dict[Path, set[str]] = {}
    problems = []
    for page in page_list:
        for number, target in links(page):
            if target.startswith(EXTERNAL):
                continue
            path_part, _, anchor = target.partition("#")
            dest = (page.parent / path_part).resolve() if path_part else page
            where = f"{page.relative_to(ROOT)}:{number}: {target}"
            if not dest.exists():
                problems.append(f"{where}: no file {dest}")
                continue
            if not anchor:
                continue
            if dest.suffix != ".md" or dest.is_dir():
                problems.append(f"{where}: an anchor into a file that is not Markdown")
                continue
            if dest not in cache:
                cache[dest] = anchors(dest)
            if anchor not in cache[dest]:
                problems.append(f"{where}: no heading with anchor #{anchor} in {dest.name}")
    return problems


def test_every_relative_link_and_anchor_resolves():
    problems = broken_links(pages())
    assert not problems, "broken links:\n" + "\n".join(problems)


def test_the_check_finds_links_and_headings():
    # The README links to the guide, and the guide's pages have headings: guards against a
    # pattern that silently matches nothing.
    targets = [t for _, t in links(ROOT / "README.md")]
    assert "docs/README.md" in targets
    assert "docs/slider.svg" in targets
    assert len(pages()) > 10


def test_slugs_follow_github():
    assert slug("Design studies (`mbfx.study` and `mbfx study`)") == "design-studies-mbfxstudy-and-mbfx-study"
    assert slug("Command files (`mbfx run ANALYSIS.acf`)") == "command-files-mbfx-run-analysisacf"
    assert slug("What ERROR means: per step (Adams) or per run") == "what-error-means-per-step-adams-or-per-run"
    assert slug("The multibody core (`src/mbd/`)") == "the-multibody-core-srcmbd"
    assert slug("Figures (issue 22)") == "figures-issue-22"
    assert slug("1. One expression") == "1-one-expression"


def test_a_broken_link_or_anchor_is_found(tmp_path):
    page = tmp_path / "page.md"
    (tmp_path / "other.md").write_text("# Other\n\n## Same\n\n## Same\n", encoding="utf-8")
    page.write_text(
        "# Page\n\n[ok](other.md#same-1) [ok](#page) [bad](missing.md) [bad](other.md#nope)\n"
        "[bad](#nothing) `[code](missing.md)`\n\n```text\n[fenced](missing.md)\n```\n",
        encoding="utf-8",
    )
    global ROOT
    saved, ROOT = ROOT, tmp_path
    try:
        problems = broken_links([page])
    finally:
        ROOT = saved
    assert len(problems) == 3, problems
    assert any("missing.md" in p for p in problems)
    assert any("#nope" in p for p in problems)
    assert any("#nothing" in p for p in problems)
