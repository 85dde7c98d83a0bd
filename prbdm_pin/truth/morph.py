"""A mesh that moves with the planform: the nodes of one beam's mesh mapped onto another's.

Shape sensitivities need the truth as a smooth function of the planform on one mesh topology.
The map takes a beam ``ref`` to a beam ``new`` with the same vertex structure (same vertex count,
width steps at the same vertex indices and in the same direction): along x it is piecewise linear
between the vertex stations, across the width it scales y by the ratio of the half-widths at the
same relative position s in the vertex interval. A node at a width step's station (where two
intervals meet and the half-width is two-valued) scales by the narrow side's ratio below the
narrow half-width and maps linearly along the step's outline piece above it. Vertices map onto
vertices, the outline onto the outline, the axis y = 0 onto itself, the root edge stays at x = 0.
The map is meant for small moves (gradients, optimiser steps): a large one can fold the small
elements at a width step's corner; remesh the new planform then.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam

__all__ = ["check_same_structure", "morph_x", "morph_plane"]


def check_same_structure(ref: Beam, new: Beam) -> None:
    """Check that the two planforms can share one mesh topology.

    Raises
    ------
    BeamInputError
        Unless ``new`` has ``ref``'s vertex count and width steps (same indices, same
        direction).
    """
    if new.x_m.size != ref.x_m.size:
        raise BeamInputError(f"x has {new.x_m.size} vertices: the mesh's planform has "
                             f"{ref.x_m.size}")
    if not np.array_equal(new.step_index, ref.step_index):
        raise BeamInputError(f"width steps at vertices {new.step_index.tolist()}: the mesh's "
                             f"planform has them at {ref.step_index.tolist()}")
    k = ref.step_index
    if np.any(np.sign(np.diff(ref.half_width_m)[k]) != np.sign(np.diff(new.half_width_m)[k])):
        raise BeamInputError("a width step changes direction (its narrow side becomes the wide "
                             "one): the mesh cannot follow")


def _intervals(beam: Beam) -> np.ndarray:
    """Index i of every vertex interval [x_i, x_(i+1)] of positive length."""
    return np.flatnonzero(np.diff(beam.x_m) > 0.0)


def _locate(ref: Beam, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertex index i of the interval holding each station X (m) and the relative position s."""
    iv = _intervals(ref)
    a = ref.x_m[iv]
    j = np.clip(np.searchsorted(a, X, side="right") - 1, 0, iv.size - 1)
    i = iv[j]
    s = (X - ref.x_m[i]) / (ref.x_m[i + 1] - ref.x_m[i])
    return i, np.clip(s, 0.0, 1.0)


def morph_x(ref: Beam, new: Beam, X: np.ndarray) -> np.ndarray:
    """Map stations X (m) along ``ref`` piecewise linearly onto ``new`` (m)."""
    check_same_structure(ref, new)
    X = np.asarray(X, dtype=float)
    i, s = _locate(ref, X)
    return new.x_m[i] + s * (new.x_m[i + 1] - new.x_m[i])


def morph_plane(ref: Beam, new: Beam, p: np.ndarray) -> np.ndarray:
    """Map planform points p (2, n) of ``ref`` onto ``new``: shape (2, n), m.

    See the module docstring for the map.
    """
    check_same_structure(ref, new)
    X, Y = np.asarray(p, dtype=float)
    i, s = _locate(ref, X)
    x = new.x_m[i] + s * (new.x_m[i + 1] - new.x_m[i])
    w0 = ref.half_width_m[i] + s * (ref.half_width_m[i + 1] - ref.half_width_m[i])
    w1 = new.half_width_m[i] + s * (new.half_width_m[i + 1] - new.half_width_m[i])
    y = Y * (w1 / w0)
    tol = 1e-9 * ref.length_m
    for k in ref.step_index:
        at = np.abs(X - ref.x_m[k]) <= tol
        if not at.any():
            continue
        lo0, hi0 = sorted(ref.half_width_m[k:k + 2])
        n0, n1 = new.half_width_m[k:k + 2]
        lo1, hi1 = (n0, n1) if n0 < n1 else (n1, n0)
        a = np.abs(Y[at])
        on_piece = a > lo0
        ya = np.where(on_piece, lo1 + (a - lo0) * (hi1 - lo1) / (hi0 - lo0), a * (lo1 / lo0))
        x[at] = new.x_m[k]
        y[at] = np.sign(Y[at]) * ya
    return np.vstack([x, y])
