"""Every included page fragment sits under the section that includes it: a fragment that opens
with a heading is included with a heading offset (or from below its heading), so that it never
becomes a top-level entry of the site's navigation."""

from __future__ import annotations

import re

from paths import ROOT

DOCS = ROOT / "docs"


def test_included_fragments_with_a_heading_are_offset():
    bad = []
    for page in DOCS.rglob("*.md"):
        if "_build" in page.parts or "gallery" in page.parts:
            continue
        text = page.read_text(encoding="utf-8")
        for m in re.finditer(r"```\{include\} ([^\n]+)\n((?::[^\n]*\n)*)```", text):
            target = (page.parent / m.group(1).strip()).resolve()
            opts = m.group(2)
            first = target.read_text(encoding="utf-8").lstrip().split("\n", 1)[0]
            if first.startswith("#") and ":heading-offset:" not in opts \
                    and ":start-line:" not in opts:
                bad.append(f"{page.relative_to(DOCS)} includes {m.group(1)}")
    assert not bad, bad
