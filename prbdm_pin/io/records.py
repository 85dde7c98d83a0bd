"""The JSON form of the result dataclasses: arrays as lists, NaN and inf as null, read back."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable
from dataclasses import fields
from typing import Any

import numpy as np

from .atomic import atomic_write_text

__all__ = ["JsonRecord", "from_json", "jsonable", "readonly_array"]


def readonly_array(v: Any) -> np.ndarray | None:
    """``v`` as a read-only float array (None stays None)."""
    if v is None:
        return None
    a = np.array(v, dtype=float)
    a.setflags(write=False)
    return a


def jsonable(v: Any) -> Any:
    """``v`` with arrays as lists and NaN / inf as None, ready for ``json.dumps``."""
    if isinstance(v, np.ndarray):
        return jsonable(v.tolist())
    if isinstance(v, (list, tuple)):
        return [jsonable(x) for x in v]
    if isinstance(v, (np.floating, float)):
        f = float(v)
        return f if math.isfinite(f) else None
    if isinstance(v, np.integer):
        return int(v)
    return v


def from_json(v: Any) -> Any:
    """Invert :func:`jsonable` on lists: None back to NaN."""
    if isinstance(v, list):
        return [from_json(x) for x in v]
    return math.nan if v is None else v


class JsonRecord:
    """Base of the frozen result dataclasses: their JSON form, field by field.

    ``array_fields`` names the fields read back as float arrays; :meth:`nested_readers` the
    fields that hold an object with its own ``to_dict`` (written as its mapping, read back by the
    reader), so that this base knows no result type of the layers above it.
    """

    array_fields: frozenset[str] = frozenset()

    @classmethod
    def nested_readers(cls) -> dict[str, Callable[[Any], Any]]:
        """Return the readers of the fields that hold an object with a ``to_dict`` (none here)."""
        return {}

    def to_dict(self) -> dict[str, Any]:
        """Return a JSON-ready mapping (NaN and inf written as null)."""
        d = {}
        nested = self.nested_readers()
        for f in fields(self):  # type: ignore[arg-type]
            v = getattr(self, f.name)
            if f.name == "versions":
                v = {k: ver for k, ver in v}
            elif v is not None and f.name in nested:
                v = v.to_dict()
            d[f.name] = jsonable(v)
        return d

    def to_json(self) -> str:
        """Return the JSON text of :meth:`to_dict`, indented, with a final newline."""
        return json.dumps(self.to_dict(), indent=2) + "\n"

    def save(self, path: str | os.PathLike):
        """Write the JSON form atomically."""
        return atomic_write_text(path, self.to_json())

    @classmethod
    def from_dict(cls, d: dict[str, Any]):
        """Rebuild from :meth:`to_dict`'s form; names that are not fields are ignored."""
        names = {f.name for f in fields(cls)}  # type: ignore[arg-type]
        kw = {}
        nested = cls.nested_readers()
        for k, v in d.items():
            if k not in names:
                continue
            if k == "versions":
                v = tuple((a, b) for a, b in v.items())
            elif k in nested:
                v = None if v is None else nested[k](v)
            elif k in cls.array_fields:
                v = None if v is None else np.array(from_json(v), dtype=float)
            elif isinstance(v, list):
                v = tuple(v)
            elif v is None and k not in ("message",):
                v = math.nan
            kw[k] = v
        return cls(**kw)
