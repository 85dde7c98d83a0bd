"""Checks of option values, free of numpy.

Each returns the value in its checked type or raises a BeamInputError that names the option and
the value.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

from ..errors import BeamInputError
from .choices import Choice

__all__ = ["check_int", "check_float", "check_bool", "check_choice"]


def check_int(name: str, v: Any, low: int, *, optional: bool = False) -> int | None:
    """``v`` as an int >= ``low`` (not a bool; None too when ``optional``)."""
    if v is None and optional:
        return None
    if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < low:
        raise BeamInputError(f"{name} = {v!r}: must be an integer >= {low}"
                             + (" or None" if optional else ""))
    return int(v)


def check_float(name: str, v: Any, *, low: float | None = None, low_open: bool = False,
           optional: bool = False, unit: str = "") -> float | None:
    """Return ``v`` as a finite float, > ``low`` (``low_open``) or >= ``low``.

    None is accepted too when ``optional``; ``unit`` is named in the error.
    """
    if v is None and optional:
        return None
    ok = not isinstance(v, bool) and isinstance(v, numbers.Real) and math.isfinite(float(v))
    if ok and low is not None:
        ok = float(v) > low if low_open else float(v) >= low
    if not ok:
        bound = "" if low is None else f" {'>' if low_open else '>='} {low:g}"
        raise BeamInputError(f"{name} = {v!r}: must be a finite number{bound}"
                             + (f" ({unit})" if unit else ""))
    return float(v)


def check_bool(name: str, v: Any) -> bool:
    """``v`` if it is True or False."""
    if not isinstance(v, bool):
        raise BeamInputError(f"{name} = {v!r}: must be true or false")
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
