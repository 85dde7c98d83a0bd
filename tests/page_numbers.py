"""Numbers written on the documentation's pages, read back for a test to compare with a rerun of
the script the page names (so a page cannot keep a number its script no longer gives).

Imported as ``from page_numbers import ...`` (pytest puts this folder on ``sys.path``); not a
test module.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["assert_printed", "page_numbers"]


def page_numbers(page: Path, pattern: str) -> tuple[str, ...]:
    """The groups of ``pattern`` on ``page``, found exactly once (lines joined, as rendered)."""
    text = " ".join(page.read_text(encoding="utf-8").split())
    found = re.findall(pattern, text)
    assert len(found) == 1, f"{page.name}: {pattern!r} found {len(found)} times, not once"
    return found[0] if isinstance(found[0], tuple) else (found[0],)


def assert_printed(printed: str, value: float, what: str) -> None:
    """``value`` rounds to the number the page prints, to the digits it prints."""
    mantissa, _, exponent = printed.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    # half a unit of the last printed digit; 1e-9 of it for the decimal's binary rounding
    half_unit = 0.5 * 10.0 ** (int(exponent or 0) - decimals) * (1.0 + 1e-9)
    assert abs(value - float(printed)) <= half_unit, \
        f"{what}: the page says {printed}, the rerun gives {value!r}"
