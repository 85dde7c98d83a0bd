"""A TruthResult as plain data: a JSON tree of scalars and a flat mapping of numeric arrays.

The cache stores truths in this form (``truth.cache``): nothing in it can run code when read,
and :func:`decode` rebuilds the frozen dataclasses field by field from their annotations,
refusing (``EntryError``) any value of the wrong kind, so a damaged or forged entry is rejected
rather than returned with, e.g., a string where a frequency array belongs.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .result import ModalSolution, StaticSolution, Timings, TruthResult

__all__ = ["EntryError", "encode", "decode", "check_truth"]

_CLASSES = {"Timings": Timings, "ModalSolution": ModalSolution,
            "StaticSolution": StaticSolution, "TruthResult": TruthResult}
# numeric array kinds only: bool, int, uint, float (no object, string or void arrays)
_ARRAY_KINDS = "biuf"


class EntryError(ValueError):
    """Stored data that is not a valid TruthResult (the message says which field)."""


def _kind(annotation: str) -> tuple[str, bool]:
    """Return the base type name of a field annotation and whether None is allowed."""
    parts = [p.strip() for p in annotation.split("|")]
    optional = "None" in parts
    parts = [p for p in parts if p != "None"]
    if len(parts) != 1:
        raise TypeError(f"unsupported annotation {annotation!r}")
    return parts[0], optional


def encode(obj: Any, arrays: dict[str, np.ndarray], path: str = "") -> dict[str, Any]:
    """Return the JSON tree of the dataclass ``obj``; arrays go into ``arrays`` by dotted path.

    An array field is recorded in the tree as ``"array"`` (or null), its data as
    ``arrays[path]``.
    """
    out: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        base, _ = _kind(f.type)
        v = getattr(obj, f.name)
        where = f"{path}{f.name}"
        if v is None:
            out[f.name] = None
        elif base == "np.ndarray":
            a = np.ascontiguousarray(v)
            if a.dtype.kind not in _ARRAY_KINDS:
                raise TypeError(f"{where}: array of dtype {a.dtype} cannot be stored")
            arrays[where] = a
            out[f.name] = "array"
        elif base in _CLASSES:
            out[f.name] = encode(v, arrays, f"{where}.")
        elif base == "tuple[str, ...]":
            out[f.name] = [str(s) for s in v]
        elif base == "bool":
            out[f.name] = bool(v)
        elif base == "int":
            out[f.name] = int(v)
        elif base == "float":
            out[f.name] = float(v)
        elif base == "str":
            out[f.name] = str(v)
        else:
            raise TypeError(f"{where}: unsupported field type {f.type!r}")
    return out


def _scalar(where: str, base: str, v: Any) -> Any:
    if base == "tuple[str, ...]":
        if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
            raise EntryError(f"{where}: expected a list of strings")
        return tuple(v)
    if base == "bool":
        if not isinstance(v, bool):
            raise EntryError(f"{where}: expected true or false")
        return v
    if base == "int":
        if isinstance(v, bool) or not isinstance(v, int):
            raise EntryError(f"{where}: expected an integer")
        return v
    if base == "float":
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise EntryError(f"{where}: expected a number")
        return float(v)
    if base == "str":
        if not isinstance(v, str):
            raise EntryError(f"{where}: expected a string")
        return v
    raise EntryError(f"{where}: unsupported field type {base!r}")


def decode(cls_name: str, tree: Any, arrays: dict[str, np.ndarray], path: str = "") -> Any:
    """Rebuild the dataclass ``cls_name`` from :func:`encode`'s tree and arrays (read-only).

    Raises
    ------
    EntryError
        A missing, extra or mistyped field or array.
    """
    cls = _CLASSES[cls_name]
    if not isinstance(tree, dict):
        raise EntryError(f"{path or cls_name}: expected an object")
    fields = dataclasses.fields(cls)
    extra = set(tree) - {f.name for f in fields}
    if extra:
        raise EntryError(f"{path}{sorted(extra)[0]}: not a field of {cls_name}")
    kwargs = {}
    for f in fields:
        where = f"{path}{f.name}"
        if f.name not in tree:
            raise EntryError(f"{where}: missing")
        base, optional = _kind(f.type)
        v = tree[f.name]
        if v is None:
            if not optional:
                raise EntryError(f"{where}: must not be null")
            kwargs[f.name] = None
        elif base == "np.ndarray":
            if v != "array" or where not in arrays:
                raise EntryError(f"{where}: array missing")
            a = np.array(arrays[where])
            if a.dtype.kind not in _ARRAY_KINDS:
                raise EntryError(f"{where}: array of dtype {a.dtype}")
            a.setflags(write=False)
            kwargs[f.name] = a
        elif base in _CLASSES:
            kwargs[f.name] = decode(base, v, arrays, f"{where}.")
        else:
            kwargs[f.name] = _scalar(where, base, v)
    return cls(**kwargs)


def check_truth(result: TruthResult) -> None:
    """Check the shapes and values a TruthResult must have (EntryError otherwise).

    Finite positive frequencies, selected arrays of one length N, indices into the computed
    modes.
    """
    w = result.omega_rad_s
    n = w.shape[0] if w.ndim == 1 else -1
    if n < 1 or not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise EntryError("omega_rad_s: must be a non-empty vector of finite values > 0")
    for name in ("mode_index", "mpf_z_fraction", "mac_beam", "error_estimate_pct",
                 "beam_gap_pct"):
        a = getattr(result, name)
        if a is not None and a.shape != (n,):
            raise EntryError(f"{name}: shape {a.shape}, expected ({n},)")
    k = result.modal.omega_rad_s.shape
    if len(k) != 1 or result.mode_index.dtype.kind not in "iu" or np.any(
            (result.mode_index < 0) | (result.mode_index >= k[0])):
        raise EntryError("mode_index: must index modal.omega_rad_s")
    if not np.array_equal(result.modal.omega_rad_s[result.mode_index], w):
        raise EntryError("omega_rad_s: differs from modal.omega_rad_s[mode_index]")
    if len(result.labels) != k[0]:
        raise EntryError(f"labels: {len(result.labels)} labels for {k[0]} modes")
    gap = result.static_theory_gap_pct
    if gap is not None and not math.isfinite(gap):
        raise EntryError("static_theory_gap_pct: must be finite")
