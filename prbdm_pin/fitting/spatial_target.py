"""Which truth modes a spatial fit matches, by kind, and how its result names them.

Axis y takes the bending-type modes (labelled ``bending`` or ``mixed``: uniform across the
width), x the ``torsion`` modes and z the ``in-plane`` modes; a ``chordwise`` mode (bending
across the width) has no chain counterpart on any axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..options.choices import Axes
from .mode_records import mode_record

__all__ = ["AXIS_KINDS", "SpatialSelection", "select_spatial", "spatial_records"]

# the truth labels each joint axis represents
AXIS_KINDS = {"y": ("bending", "mixed"), "x": ("torsion",), "z": ("in-plane",)}
_AXIS_NAME = {"y": "bending", "x": "torsion", "z": "in-plane"}
_HINT = {"y": "a wide panel's band holds torsion and chordwise modes between its bending ones",
         "x": "the plate and the solid have torsion modes, the 1D beam with spatial=True too",
         "z": "the solid has in-plane modes, the 1D beam with spatial=True too (not the plate)"}


@dataclass(frozen=True)
class SpatialSelection:
    """The truth modes a spatial fit matches, ascending in frequency.

    Attributes
    ----------
    index : ndarray of int, shape (N,)
        Their indices among the truth's computed modes.
    omega_truth_rad_s : ndarray, shape (N,)
        Their frequencies, rad/s.
    kind : tuple of str
        Their truth labels.
    axis : ndarray of str, shape (N,)
        The joint axis each is matched to (``"y"``, ``"z"``, ``"x"``).
    """

    index: np.ndarray
    omega_truth_rad_s: np.ndarray
    kind: tuple[str, ...]
    axis: np.ndarray


def select_spatial(target, axes: Axes, joints: int, per_kind: int | None) -> SpatialSelection:
    """Select the first ``per_kind`` (default n) truth modes of each kind the axes represent.

    Parameters
    ----------
    target : FitTarget
        With every truth mode and its label (``all_omega_rad_s``, ``all_labels``).
    axes : Axes
    joints : int
        n; a kind's modes number at most n (the chain's coordinates about that axis).
    per_kind : int or None
        Modes of each kind to match (the ``frequencies`` option), 1..n; None for n.

    Raises
    ------
    BeamInputError
        Naming the field: no labelled truth modes, ``frequencies`` beyond n, or fewer truth
        modes of a kind than asked (e.g. torsion on the 1D bending-only beam).
    """
    if target.all_omega_rad_s is None:
        raise BeamInputError(f"axes = {axes.value!r}: a spatial fit needs every truth mode "
                             "with its label (a target from target_from_truth or a truth file "
                             "with labels); this target holds bending frequencies only")
    n_kind = joints if per_kind is None else int(per_kind)
    if not 1 <= n_kind <= joints:
        raise BeamInputError(f"frequencies = {per_kind}: must be in 1..{joints} (modes of each "
                             f"kind an {joints}-joint chain has about each axis)")
    w_all, labels = target.all_omega_rad_s, target.all_labels
    idx, axis = [], []
    for a in axes.joint_order:
        found = [i for i, lab in enumerate(labels) if lab in AXIS_KINDS[a]]
        if len(found) < n_kind:
            raise BeamInputError(
                f"axes = {axes.value!r}: the truth ({target.source or 'target'}) has "
                f"{len(found)} {_AXIS_NAME[a]} mode(s) among its {len(labels)} computed, "
                f"{n_kind} asked (frequencies, default n = {joints}): {_HINT[a]}, compute "
                "more modes (n_computed), or ask for fewer frequencies")
        idx += found[:n_kind]
        axis += [a] * n_kind
    order = np.argsort(w_all[idx], kind="stable")
    index = np.asarray(idx)[order]
    return SpatialSelection(index=index, omega_truth_rad_s=w_all[index].copy(),
                            kind=tuple(labels[i] for i in index),
                            axis=np.asarray(axis)[order])


def spatial_records(sel: SpatialSelection, omega_model_rad_s: np.ndarray, target,
                    mac: np.ndarray | None = None) -> tuple[dict, ...]:
    """fit.json's ``modes`` of a spatial fit, ascending in truth frequency.

    The matched modes with their paired model frequencies (rad/s) and MAC (NaN: paired by
    order), and every other truth mode below the highest matched one with none (it is in the
    band, and no axis represents it).
    """
    mac = np.full(sel.index.size, np.nan) if mac is None else mac
    matched = {int(i): (float(w), float(c))
               for i, w, c in zip(sel.index, omega_model_rad_s, mac, strict=True)}
    top = float(sel.omega_truth_rad_s.max())
    out = []
    for i, (w, lab) in enumerate(zip(target.all_omega_rad_s, target.all_labels, strict=True)):
        if i in matched:
            out.append(mode_record(lab, w, *matched[i]))
        elif w <= top:
            out.append(mode_record(lab, w, None))
    return tuple(out)
