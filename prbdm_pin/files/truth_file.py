"""Reading a ``truth.json`` (written by ``prbdm truth`` or by hand) for ``prbdm fit --truth``.

The file is outside the package's control: every field is checked (type, finiteness, range and
length consistent with ``omega_rad_s``) and every defect is a BeamInputError naming the field.
Only ``omega_rad_s`` is required; a hand-made file may leave out everything else.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import BeamInputError
from ..io.jsonfile import (
    field_float,
    field_floats,
    field_int,
    field_str,
    read_json,
    require_mapping,
)

__all__ = ["TruthFile", "read_truth_file", "truth_file_from_dict"]

# a MAC or a mass fraction computed in floating point may exceed 1 by rounding
_UNIT_TOL = 1e-9
_FLOAT_LISTS_N = ("mpf_z", "error_estimate_pct", "beam_gap_pct")
_STR_LISTS = ("beam_gap_cause", "all_labels", "warnings")
_STRINGS = ("beam", "model", "selection", "version", "large_deflection")
_VECTORS_3 = ("tip_position_m", "tip_displacement_m", "linear_tip_displacement_m")
_KNOWN = {"omega_rad_s", "beam_fingerprint", "mode_index", "mpf_z_fraction", "mac", "labels",
          "all_omega_rad_s", "static_theory_gap_pct", "mesh_level", "error_estimate_level",
          "dofs", "wall_time_s", "versions", "seed", *_FLOAT_LISTS_N, *_STR_LISTS, *_STRINGS,
          *_VECTORS_3}


@dataclass(frozen=True)
class TruthFile:
    """The fields of a truth.json that a fit uses (validated).

    Attributes
    ----------
    omega_rad_s : ndarray, shape (N,)
        Bending frequencies, ascending, > 0, rad/s.
    beam_fingerprint : str or None
        ``Beam.fingerprint()`` of the beam it was computed for (None in a hand-made file).
    tip_position_m, tip_displacement_m : ndarray, shape (3,), or None
        Large-deflection tip position and displacement under the beam's tip force, m.
    mac : ndarray, shape (N,), or None
        MAC of each mode with a beam bending mode, in [0, 1].
    static_theory_gap_pct : float or None
        100 (u_1D / u_truth - 1), %.
    """

    omega_rad_s: np.ndarray
    beam_fingerprint: str | None = None
    tip_position_m: np.ndarray | None = None
    tip_displacement_m: np.ndarray | None = None
    mac: np.ndarray | None = None
    static_theory_gap_pct: float | None = None


def _opt(d: dict, key: str) -> Any:
    return d.get(key)


def _unit_interval(field: str, value: Any, n: int) -> np.ndarray:
    v = np.array(field_floats(field, value, length=n))
    bad = np.flatnonzero((v < 0.0) | (v > 1.0 + _UNIT_TOL))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"{field}[{i}] = {v[i]!r}: must be in [0, 1]")
    return v


def truth_file_from_dict(d: Any, what: str = "truth.json") -> TruthFile:
    """Validate the parsed mapping ``d`` of a truth file named ``what`` (for messages)."""
    d = require_mapping(d, what)
    unknown = sorted(set(d) - _KNOWN)
    if unknown:
        raise BeamInputError(f"{what}: {unknown[0]} = {d[unknown[0]]!r:.60}: not a truth.json "
                             f"field (known: {', '.join(sorted(_KNOWN))})")
    # what made the file (every JSON the package writes says): checked, not used
    if _opt(d, "versions") is not None:
        for k, v in require_mapping(d["versions"], f"{what}: versions").items():
            field_str(f"versions.{k}", v)
    seed = _opt(d, "seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int)):
        raise BeamInputError(f"seed = {seed!r:.40}: must be an integer or null")
    if "omega_rad_s" not in d:
        raise BeamInputError(f"{what}: omega_rad_s: missing (the bending frequencies, rad/s)")
    w = np.array(field_floats("omega_rad_s", d["omega_rad_s"], positive=True, min_length=1))
    bad = np.flatnonzero(np.diff(w) < 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise BeamInputError(f"omega_rad_s[{i}] = {w[i]!r}: must not be below omega_rad_s[{i - 1}]"
                             f" = {w[i - 1]!r} (ascending)")
    n = w.size
    fp = _opt(d, "beam_fingerprint")
    if fp is not None and not (isinstance(fp, str) and re.fullmatch(r"[0-9a-f]{64}", fp)):
        raise BeamInputError(f"beam_fingerprint = {fp!r:.80}: must be 64 hex digits or null")
    vec = {k: None if _opt(d, k) is None else np.array(field_floats(k, d[k], length=3))
           for k in _VECTORS_3}
    mac = None if _opt(d, "mac") is None else _unit_interval("mac", d["mac"], n)
    if _opt(d, "mpf_z_fraction") is not None:
        _unit_interval("mpf_z_fraction", d["mpf_z_fraction"], n)
    for k in _FLOAT_LISTS_N:
        if _opt(d, k) is not None:
            field_floats(k, d[k], length=n, nonnegative=k == "mpf_z")
    gap = _opt(d, "static_theory_gap_pct")
    gap = None if gap is None else field_float("static_theory_gap_pct", gap)
    for k in _STRINGS:
        if _opt(d, k) is not None:
            field_str(k, d[k])
    for k in _STR_LISTS + ("labels",):
        v = _opt(d, k)
        if v is not None:
            if not isinstance(v, list):
                raise BeamInputError(f"{k} = {v!r:.80}: must be a list of strings")
            for i, s in enumerate(v):
                field_str(f"{k}[{i}]", s)
    if _opt(d, "labels") is not None and len(d["labels"]) != n:
        raise BeamInputError(f"labels: has {len(d['labels'])} values, expected {n}")
    for k, lo in (("mesh_level", 0), ("error_estimate_level", 0), ("dofs", 1)):
        if _opt(d, k) is not None:
            field_int(k, d[k], minimum=lo)
    if _opt(d, "wall_time_s") is not None:
        field_float("wall_time_s", d["wall_time_s"], nonnegative=True)
    _check_indices(d, w)
    return TruthFile(w, fp, vec["tip_position_m"], vec["tip_displacement_m"], mac, gap)


def _check_indices(d: dict, w: np.ndarray) -> None:
    """``all_omega_rad_s``, ``all_labels`` and ``mode_index`` consistent with ``omega_rad_s``."""
    every = _opt(d, "all_omega_rad_s")
    if every is not None:
        every = np.array(field_floats("all_omega_rad_s", every, positive=True, min_length=1))
        labels = _opt(d, "all_labels")
        if labels is not None and len(labels) != every.size:
            raise BeamInputError(f"all_labels: has {len(labels)} values, expected "
                                 f"{every.size} (one per all_omega_rad_s)")
    idx = _opt(d, "mode_index")
    if idx is None:
        return
    if not isinstance(idx, list) or len(idx) != w.size:
        raise BeamInputError(f"mode_index = {idx!r:.80}: must be a list of {w.size} integers")
    top = None if every is None else every.size - 1
    for i, v in enumerate(idx):
        field_int(f"mode_index[{i}]", v, minimum=0, maximum=top)
    if every is not None:
        for i, v in enumerate(idx):
            if not math.isclose(every[v], w[i], rel_tol=1e-12):
                raise BeamInputError(
                    f"omega_rad_s[{i}] = {w[i]!r}: differs from all_omega_rad_s[mode_index[{i}]"
                    f" = {v}] = {every[v]!r}")


def read_truth_file(path: str | os.PathLike) -> TruthFile:
    """Read and validate the truth file ``path`` (BeamInputError naming the file and field)."""
    what = f"truth file {str(path)!r}"
    d = read_json(path, "truth file")
    try:
        return truth_file_from_dict(d, what)
    except BeamInputError as exc:
        msg = str(exc)
        raise BeamInputError(msg if msg.startswith(what) else f"{what}: {msg}") from None
