"""The API reference lists every public name: a name added to ``prbdm_pin.__all__`` without an
entry in docs/api/ fails here, not silently in the published docs."""

from __future__ import annotations

import re

from paths import ROOT

import prbdm_pin

API_DIR = ROOT / "docs" / "api"


def _api_text() -> str:
    pages = sorted(API_DIR.glob("*.rst")) + sorted(API_DIR.glob("*.md"))
    assert pages, f"no API pages in {API_DIR}"
    return "\n".join(p.read_text(encoding="utf-8") for p in pages)


def _autosummary_entries(text: str) -> list[str]:
    """Names listed under every ``.. autosummary::`` directive (indented, after its options)."""
    entries = []
    for block in re.findall(r"^\.\. autosummary::\n((?:[ \t]+.*\n|\n)+)", text, re.M):
        for line in block.splitlines():
            item = line.strip()
            if item and not item.startswith(":"):
                entries.append(item)
    return entries


def test_every_public_name_has_an_api_entry():
    entries = _autosummary_entries(_api_text())
    missing = [n for n in prbdm_pin.__all__ if n != "__version__" and n not in entries]
    assert not missing, f"public names without an API entry in docs/api/: {missing}"


def test_api_entries_are_public_and_listed_once():
    entries = _autosummary_entries(_api_text())
    unknown = sorted(set(entries) - set(prbdm_pin.__all__))
    twice = sorted({n for n in entries if entries.count(n) > 1})
    assert not unknown, f"API entries that are not in prbdm_pin.__all__: {unknown}"
    assert not twice, f"API entries listed more than once: {twice}"


def test_version_is_named():
    assert "prbdm_pin.__version__" in _api_text()


def test_entry_parser_sees_a_missing_name():
    # the check above is only as good as its parser: drop one listed name and it must notice
    text = _api_text()
    entries = _autosummary_entries(text)
    assert len(entries) == len(prbdm_pin.__all__) - 1
    dropped = text.replace(f"   {entries[0]}\n", "", 1)
    assert entries[0] not in _autosummary_entries(dropped)
