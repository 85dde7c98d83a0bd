"""Checks of option values, free of numpy.

Each returns the value in its checked type or raises a BeamInputError that names the option and
the value.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

from ..errors import BeamInputError, InputTypeError
from .choices import Choice

__all__ = ["check_int", "check_float", "check_bool", "check_choice", "shown"]


def shown(v: Any, width: int = 80) -> str:
    """``repr(v)`` cut to ``width`` characters, for a message (an int of any size too)."""
    if isinstance(v, numbers.Integral) and not isinstance(v, bool) and abs(v) >= 10**30:
        return f"{'-' if v < 0 else ''}an integer of {len(format(abs(v), 'x')) * 4} bits"
    try:
        text = repr(v)
    except Exception:  # noqa: BLE001 - a hostile __repr__ must not hide the real error
        text = f"<{type(v).__name__}>"
    return text if len(text) <= width else text[: width - 3] + "..."


def check_int(name: str, v: Any, low: int, *, optional: bool = False,
              high: int | None = None) -> int | None:
    """``v`` as an int in ``low..high`` (not a bool; None too when ``optional``).

    A value that is not an integer raises :class:`InputTypeError`, one out of range
    :class:`BeamInputError`; both name ``name``.
    """
    if v is None and optional:
        return None
    want = f"an integer >= {low}" if high is None else f"an integer in {low}..{high}"
    want += " or None" if optional else ""
    if isinstance(v, bool) or not isinstance(v, numbers.Integral):
        raise InputTypeError(f"{name} = {shown(v)}: must be {want}")
    if v < low or (high is not None and v > high):
        raise BeamInputError(f"{name} = {shown(v)}: must be {want}")
    return int(v)


def check_float(name: str, v: Any, *, low: float | None = None, low_open: bool = False,
                optional: bool = False, unit: str = "", high: float | None = None,
                high_open: bool = False) -> float | None:
    """Return ``v`` as a finite float in the range ``low``..``high`` (each end open if asked).

    None is accepted too when ``optional``; ``unit`` is named in the error. A value that is not
    a real number (a string, a bool, a complex number, None) raises :class:`InputTypeError`;
    one that is not finite, too large for a float, or out of range :class:`BeamInputError`.
    """
    if v is None and optional:
        return None
    bound = "" if low is None else f" {'>' if low_open else '>='} {low:g}"
    if high is not None:
        bound += f"{' and' if bound else ''} {'<' if high_open else '<='} {high:g}"
    text = f"must be a finite number{bound}" + (f" ({unit})" if unit else "")
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise InputTypeError(f"{name} = {shown(v)}: {text}")
    try:
        f = float(v)
    except OverflowError:  # an int beyond 1.8e308
        f = math.inf
    ok = math.isfinite(f)
    if ok and low is not None:
        ok = f > low if low_open else f >= low
    if ok and high is not None:
        ok = f < high if high_open else f <= high
    if not ok:
        raise BeamInputError(f"{name} = {shown(v)}: {text}")
    return f


def check_bool(name: str, v: Any) -> bool:
    """``v`` if it is True or False."""
    if not isinstance(v, bool):
        raise InputTypeError(f"{name} = {shown(v)}: must be true or false")
    return v


def check_choice(name: str, v: Any, kind: type[Choice] | Sequence[str]) -> Any:
    """Return ``v`` as a member of the enumeration ``kind``, or as one of the strings ``kind``.

    Otherwise a BeamInputError names ``name`` and the allowed values.
    """
    if isinstance(kind, type) and issubclass(kind, Choice):
        try:
            return kind(v)
        except ValueError:
            allowed = kind.values()
    else:
        allowed = tuple(kind)
        if isinstance(v, str) and v in allowed:
            return v
    raise BeamInputError(f"{name} = {v!r}: must be one of {', '.join(allowed)}")
