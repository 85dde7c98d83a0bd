"""Reading JSON files the package did not write itself: every defect is a BeamInputError.

Files on disk (beam, fit.json, model JSON, truth.json, batch.json, results.jsonl) may be
truncated, edited, of another kind or hostile. :func:`read_json` refuses oversized files,
non-UTF-8 text, invalid JSON, NaN/Infinity, integers too long to be numbers and nesting too
deep to be data, naming the file; the ``field_*`` helpers check one value and name its field.
"""

from __future__ import annotations

import json
import math
import os
from typing import Any

from ..errors import BeamInputError
from ..options.limits import limits

__all__ = [
    "read_json", "parse_json", "require_mapping", "field_float", "field_int", "field_str",
    "field_floats", "MAX_DEPTH",
]

# Real data files nest a few levels; a deeper file is not data (and would exhaust the stack).
MAX_DEPTH = 64
_MAX_INT_DIGITS = 30


def _reject_constant(name: str) -> float:
    raise ValueError(f"contains {name}: every value must be finite")


def _parse_int(text: str) -> int:
    if len(text.lstrip("-")) > _MAX_INT_DIGITS:
        raise ValueError(f"contains an integer of {len(text)} digits")
    return int(text)


def _depth(text: str) -> int:
    # Bracket depth outside strings, counted before parsing so deep input never recurses.
    depth = best = 0
    in_str = esc = False
    for ch in text:
        if in_str:
            if esc:
                esc = False
            elif ch == "\\":
                esc = True
            elif ch == '"':
                in_str = False
        elif ch == '"':
            in_str = True
        elif ch in "[{":
            depth += 1
            if depth > best:
                best = depth
                if best > MAX_DEPTH:
                    return best
        elif ch in "]}":
            depth -= 1
    return best


def parse_json(text: str, what: str, *, scan_depth: bool = True) -> Any:
    """Parse JSON ``text`` read from ``what`` (a name for messages) with the checks above.

    ``scan_depth=False`` skips the (pure Python) depth scan for many short texts, where a deep
    one still fails as a RecursionError.
    """
    if scan_depth and _depth(text) > MAX_DEPTH:
        raise BeamInputError(f"{what}: nested deeper than {MAX_DEPTH} levels; not a data file")
    try:
        return json.loads(text, parse_constant=_reject_constant, parse_int=_parse_int)
    except json.JSONDecodeError as exc:
        raise BeamInputError(f"{what}: not valid JSON ({exc})") from None
    except (ValueError, RecursionError) as exc:
        raise BeamInputError(f"{what}: {exc}") from None


def read_json(path: str | os.PathLike, what: str = "file") -> Any:
    """Read and parse the JSON file ``path``; ``what`` ("beam file", "fit.json" ...) names it.

    ``path`` that is not a str or path-like raises :class:`~prbdm_pin.errors.InputTypeError`
    naming it (every public reader of JSON files takes its file as ``path``).
    """
    from ..options.validate import check_path

    p = check_path("path", path, what)
    label = f"{what} {str(p)!r}"
    try:
        size = p.stat().st_size
        if not p.is_file():
            raise BeamInputError(f"{label}: not a regular file")
        cap = limits().max_file_bytes
        if size > cap:
            raise BeamInputError(f"{label}: {size} bytes exceeds the cap max_file_bytes = {cap} "
                                 "(raise it with PRBDM_MAX_FILE_BYTES=N if this is intended)")
        raw = p.read_bytes()
    except FileNotFoundError:
        raise BeamInputError(f"{label}: not found") from None
    except OSError as exc:
        raise BeamInputError(f"{label}: cannot be read ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BeamInputError(
            f"{label}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    return parse_json(text, label)


def require_mapping(obj: Any, what: str) -> dict[str, Any]:
    """``obj`` if it is a JSON object, else a BeamInputError naming ``what``."""
    if not isinstance(obj, dict):
        raise BeamInputError(f"{what}: must be a JSON object, got {type(obj).__name__}")
    return obj


def field_float(field: str, value: Any, *, positive: bool = False,
                nonnegative: bool = False) -> float:
    """``value`` as a finite float (optionally > 0 or >= 0); errors name ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise BeamInputError(f"{field} = {value!r}: must be a number")
    v = float(value)
    if not math.isfinite(v):
        raise BeamInputError(f"{field} = {value!r}: must be finite")
    if positive and not v > 0:
        raise BeamInputError(f"{field} = {value!r}: must be > 0")
    if nonnegative and not v >= 0:
        raise BeamInputError(f"{field} = {value!r}: must be >= 0")
    return v


def field_int(field: str, value: Any, *, minimum: int | None = None,
              maximum: int | None = None) -> int:
    """``value`` as an int within [minimum, maximum]; errors name ``field``."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise BeamInputError(f"{field} = {value!r}: must be an integer")
    if minimum is not None and value < minimum:
        raise BeamInputError(f"{field} = {value!r}: must be >= {minimum}")
    if maximum is not None and value > maximum:
        raise BeamInputError(f"{field} = {value!r}: must be <= {maximum}")
    return int(value)


def field_str(field: str, value: Any, *, printable: bool = True) -> str:
    """Return ``value`` as a string; a BeamInputError names ``field`` otherwise.

    With ``printable`` control characters are refused (they make URDF/MJCF that no XML parser
    reads).
    """
    if not isinstance(value, str):
        raise BeamInputError(f"{field} = {value!r}: must be a string")
    if printable and any(ord(c) < 32 and c not in "\t\n\r" or 0xD800 <= ord(c) <= 0xDFFF
                         for c in value):
        raise BeamInputError(f"{field} = {value!r}: contains control characters")
    return value


def field_floats(field: str, value: Any, *, length: int | None = None, positive: bool = False,
                 nonnegative: bool = False, min_length: int = 0) -> list[float]:
    """``value`` as a list of finite floats (optionally of a given length, > 0 or >= 0)."""
    if not isinstance(value, (list, tuple)):
        raise BeamInputError(f"{field} = {value!r:.80}: must be a list of numbers")
    if length is not None and len(value) != length:
        raise BeamInputError(f"{field}: has {len(value)} values, expected {length}")
    if len(value) < min_length:
        raise BeamInputError(f"{field}: has {len(value)} values, expected at least {min_length}")
    return [field_float(f"{field}[{i}]", v, positive=positive, nonnegative=nonnegative)
            for i, v in enumerate(value)]
