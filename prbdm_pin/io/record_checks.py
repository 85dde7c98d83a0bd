"""Validation of the model and result files the package reads: fit.json and model JSON.

A file on disk may be truncated, edited, of another kind or hostile. Each reader here checks
schema, types, finiteness, physical ranges and sizes before anything is built from the file,
and raises :class:`~prbdm_pin.errors.BeamInputError` naming the file, the field and the value.
The link floor comes from the beam (a fixed fraction of its length), never from the file, and
the joint count is capped by ``limits().max_joints``. URDF files are checked in
:mod:`prbdm_pin.model.urdf_checks`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import BeamInputError
from ..io.jsonfile import field_int, field_str, require_mapping
from ..options.choices import (
    EIGEN_NORMS,
    LINK_FLOOR_FRACTION,
    OBJECTIVES,
    STIFFNESS_KINDS,
    StiffnessKind,
)
from ..options.limits import check_cap
from ..options.validate import check_axes

__all__ = [
    "LINK_FLOOR_FRACTION",
    "check_chain",
    "fit_kwargs",
    "file_kind",
]

_SUM_RTOL = 1e-9

_FIT_STR = ("beam_name", "beam_fingerprint", "truth_source", "message", "stiffness_pose")
_FIT_CHOICES = {"objective": OBJECTIVES, "stiffness": STIFFNESS_KINDS, "eigen_norm": EIGEN_NORMS}
_FIT_INT = {"seed": 0, "starts": 1, "starts_run": 0, "nfev": 0}
_FIT_BOOL = ("squared", "success")
# floats written as null when NaN (a loss that was not computed)
_FIT_FLOAT = ("scf_mean", "eigen_loss_pct", "deflection_loss_pct", "displacement_loss_pct",
              "combined_loss_pct", "xi", "eps", "wall_time_s", "worst_mode_error_pct",
              "worst_export_error_pct", "static_theory_gap_pct")
_FIT_REQUIRED = ("beam_name", "beam_fingerprint", "joints", "frequencies", "objective",
                 "stiffness", "lengths_m", "stiffness_Nm_per_rad",
                 "stiffness_per_pose_Nm_per_rad", "factors", "poses_rad", "omega_truth_rad_s",
                 "omega_model_rad_s")


def _array(what: str, field: str, value: Any, shape: tuple, *, finite: bool = True,
           positive: bool = False, optional: bool = False) -> np.ndarray | None:
    """``value`` as a float array of ``shape`` (None in a shape entry: any size >= 1)."""
    if value is None and optional:
        return None
    label = f"{what}: {field}"
    arr = _nested(label, value, len(shape))
    for got, want in zip(arr.shape, shape, strict=True):
        if (want is None and got < 1) or (want is not None and got != want):
            expected = ", ".join("k" if s is None else str(s) for s in shape)
            raise BeamInputError(f"{label} has shape {arr.shape}: expected ({expected})")
    for test, rule in ((finite, np.isfinite), (positive, lambda a: a > 0.0)):
        bad = np.flatnonzero(~rule(arr).ravel()) if test else ()
        if len(bad):
            idx = np.unravel_index(int(bad[0]), arr.shape)
            at = "".join(f"[{int(i)}]" for i in idx)
            raise BeamInputError(f"{label}{at} = {float(arr[idx])!r}: must be "
                                 + ("finite" if rule is np.isfinite else "> 0"))
    return arr


def _nested(label: str, value: Any, ndim: int) -> np.ndarray:
    # a rectangular list of numbers (null = NaN) of depth ndim; anything else names the field
    def walk(v: Any, depth: int, path: str) -> Any:
        if depth == 0:
            if v is None:
                return math.nan
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise BeamInputError(f"{label}{path} = {v!r:.60}: must be a number")
            return float(v)
        if not isinstance(v, (list, tuple)):
            raise BeamInputError(f"{label}{path} = {v!r:.60}: must be a list "
                                 f"({ndim}-D array of numbers)")
        return [walk(x, depth - 1, f"{path}[{i}]") for i, x in enumerate(v)]

    rows = walk(value, ndim, "")
    try:
        arr = np.array(rows, dtype=float)
    except ValueError:
        raise BeamInputError(f"{label}: rows of different lengths (not a {ndim}-D array)") from None
    if arr.ndim != ndim:
        raise BeamInputError(f"{label} has shape {arr.shape}: expected a {ndim}-D array")
    return arr


def check_chain(what: str, lengths_m: Any, stiffness_Nm_per_rad: Any,
                length_m: float | None = None, springs_per_joint: int = 1
                ) -> tuple[np.ndarray, np.ndarray]:
    """Link lengths (m, (n+1,)) and joint springs (N m/rad, (n * springs_per_joint,)) of a file.

    n is between 1 and ``limits().max_joints``; lengths are finite and > 0; with the beam
    length ``length_m`` (m) they sum to it (relative 1e-9) and each is at least
    ``LINK_FLOOR_FRACTION`` of it; springs are finite and > 0, ``springs_per_joint`` per joint
    (the spatial chain's axes per node).
    """
    if not isinstance(lengths_m, (list, tuple)):
        raise BeamInputError(f"{what}: lengths_m = {lengths_m!r:.60}: must be a list of "
                             "link lengths (m)")
    check_cap(f"{what}: joints (len(lengths_m) - 1)", len(lengths_m) - 1, "max_joints")
    if len(lengths_m) < 2:
        raise BeamInputError(f"{what}: lengths_m has {len(lengths_m)} values: needs n + 1 >= 2 "
                             "(n >= 1 joints)")
    lengths = _array(what, "lengths_m", lengths_m, (len(lengths_m),), positive=True)
    n = lengths.size - 1
    k = _array(what, "stiffness_Nm_per_rad", stiffness_Nm_per_rad, (n * springs_per_joint,),
               positive=True)
    if length_m is not None:
        with np.errstate(over="ignore"):
            total = float(np.sum(lengths))
        if not math.isclose(total, length_m, rel_tol=_SUM_RTOL, abs_tol=0.0):
            raise BeamInputError(f"{what}: lengths_m sum to {total!r} m: must equal the beam "
                                 f"length {length_m!r} m")
        floor = LINK_FLOOR_FRACTION * length_m
        bad = np.flatnonzero(lengths < floor)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(f"{what}: lengths_m[{i}] = {float(lengths[i])!r} m: shorter than "
                                 f"{LINK_FLOOR_FRACTION:g} of the beam length ({floor:.3g} m)")
    return lengths, k


def _opt_float(what: str, field: str, value: Any) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise BeamInputError(f"{what}: {field} = {value!r:.60}: must be a number or null")


MODE_KEYS = ("kind", "omega_truth_rad_s", "omega_model_rad_s", "error_pct")


def check_mode_records(what: str, records: Any) -> None:
    """Check fit.json's ``modes``: a list of records with keys :data:`MODE_KEYS`.

    ``kind`` is a string; the frequencies (rad/s) are numbers > 0 and the error (%) a number,
    or null for a truth mode no chain mode represents (its ``kind`` says why).
    """
    if not isinstance(records, list):
        raise BeamInputError(f"{what}: modes = {records!r:.60}: must be a list of records")
    for i, r in enumerate(records):
        r = require_mapping(r, f"{what}: modes[{i}]")
        missing = [k for k in MODE_KEYS if k not in r]
        if missing:
            raise BeamInputError(f"{what}: modes[{i}]: missing key(s) {missing}")
        field_str(f"{what}: modes[{i}].kind", r["kind"])
        for key in MODE_KEYS[1:]:
            v = r[key]
            if v is None and key != "omega_truth_rad_s":
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                    or (key != "error_pct" and v <= 0):
                raise BeamInputError(f"{what}: modes[{i}].{key} = {v!r:.60}: must be a finite "
                                     "number" + (" > 0" if key != "error_pct" else ""))


def fit_kwargs(d: Any, what: str = "fit.json", length_m: float | None = None) -> dict[str, Any]:
    """Check the JSON mapping of a fit.json; return it with the chain fields validated.

    ``length_m`` is the length of the beam the fit belongs to (m; the beam embedded in the
    file or given with it), which the link lengths must sum to.
    """
    d = require_mapping(d, what)
    missing = [k for k in _FIT_REQUIRED if k not in d]
    if missing:
        raise BeamInputError(f"{what}: missing field(s) {missing}")
    n = field_int(f"{what}: joints", d["joints"], minimum=1)
    check_cap(f"{what}: joints", n, "max_joints")
    axes = check_axes(d.get("axes", "y"), f"{what}: axes")
    # a spatial fit's poses, springs and factors run over every spring coordinate
    nk = n * len(axes.joint_order)
    field_int(f"{what}: frequencies", d["frequencies"], minimum=1, maximum=nk)
    for key in _FIT_STR:
        if key in d:
            field_str(f"{what}: {key}", d[key])
    for key, choices in _FIT_CHOICES.items():
        if key in d and d[key] not in choices:
            raise BeamInputError(f"{what}: {key} = {d[key]!r:.60}: must be one of {list(choices)}")
    for key, low in _FIT_INT.items():
        if key in d:
            field_int(f"{what}: {key}", d[key], minimum=low)
    for key in _FIT_BOOL:
        if key in d and not isinstance(d[key], bool):
            raise BeamInputError(f"{what}: {key} = {d[key]!r:.60}: must be true or false")
    for key in _FIT_FLOAT:
        if key in d:
            _opt_float(what, key, d[key])
    if "min_fraction" in d:
        f = d["min_fraction"]
        if isinstance(f, bool) or not isinstance(f, (int, float)) or not 0 < f < 1 / (n + 1):
            raise BeamInputError(f"{what}: min_fraction = {f!r:.60}: must be in (0, 1/(n+1)) = "
                                 f"(0, {1 / (n + 1):.4g}) for n = {n} joints")
    if isinstance(d["lengths_m"], list) and len(d["lengths_m"]) != n + 1:
        raise BeamInputError(f"{what}: lengths_m has {len(d['lengths_m'])} values: "
                             f"joints = {n} needs {n + 1}")
    check_chain(what, d["lengths_m"], d["stiffness_Nm_per_rad"], length_m, nk // n)
    poses = _array(what, "poses_rad", d["poses_rad"], (None, nk))
    m = poses.shape[0]
    _array(what, "stiffness_per_pose_Nm_per_rad", d["stiffness_per_pose_Nm_per_rad"], (m, nk),
           positive=True)
    # one SCF per pose (Eq. 14) or one factor per joint
    # (a spatial paper fit: one factor per axis, at its one pose)
    nf = (m if nk == n else nk // n) if StiffnessKind(d["stiffness"]) is \
        StiffnessKind.PAPER else nk
    _array(what, "factors", d["factors"], (nf,), positive=True)
    w = _array(what, "omega_truth_rad_s", d["omega_truth_rad_s"], (d["frequencies"],),
               positive=True)
    _array(what, "omega_model_rad_s", d["omega_model_rad_s"], (m, w.size), finite=False)
    shapes = {
        "scf_deviation_pct": (m,), "eigen_errors_pct": (m,), "omega_errors_pct": (m, w.size),
        "tip_position_model_m": (None, 3), "tip_position_truth_m": (3,),
        "tip_displacement_truth_m": (3,), "tip_force_N": (3,), "mac": (w.size,),
        "start_losses_pct": (None,), "extra_tip_force_N": (None, 3),
        "extra_tip_position_truth_m": (None, 3), "extra_tip_position_model_m": (None, None, 3),
        "export_pose_rad": (nk,), "omega_export_rad_s": (w.size,),
        "omega_export_errors_pct": (w.size,),
    }
    for key, shape in shapes.items():
        if key in d:
            _array(what, key, d[key], shape, finite=False, optional=True)
    if d.get("gravity_m_s2") is not None:  # a fit made in gravity (m/s^2, world)
        _array(what, "gravity_m_s2", d["gravity_m_s2"], (3,))
    if "modes" in d:
        check_mode_records(what, d["modes"])
    if "warnings" in d:
        ws = d["warnings"]
        if not isinstance(ws, list):
            raise BeamInputError(f"{what}: warnings = {ws!r:.60}: must be a list of strings")
        for i, s in enumerate(ws):
            field_str(f"{what}: warnings[{i}]", s, printable=False)
    if d.get("options") is not None:
        from ..options.objects import options_from_dict

        options_from_dict(d["options"], f"{what}: options")
    if "versions" in d:
        v = require_mapping(d["versions"], f"{what}: versions")
        for key, ver in v.items():
            field_str(f"{what}: versions[{key!r}]", ver)
    return d


# Which file is it ----------------------------------------------------------------------------


def file_kind(d: Any) -> str:
    """Tell what a parsed JSON file is.

    One of ``"model"``, ``"fit"``, ``"beam"``, ``"truth"``, ``"batch"``, ``"pareto"`` or
    ``"unknown"``.
    """
    if not isinstance(d, dict):
        return "unknown"
    if isinstance(d.get("format"), str) and d["format"].startswith("prbdm-model"):
        return "model"
    if "lengths_m" in d and "joints" in d:
        return "fit"
    if {"x", "half_width", "thickness"} <= set(d):
        return "beam"
    if "omega_rad_s" in d and "dofs" in d:
        return "truth"
    if "settings" in d and "shard" in d:
        return "batch"
    if "F_pct" in d and "front_lengths_m" in d:
        return "pareto"
    return "unknown"
