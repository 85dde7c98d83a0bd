"""How far a truth can be trusted.

Per selected mode, a discretisation error estimate and the gap to 1D beam theory with its cause.

Error estimate: twice the change of each selected frequency to the next mesh level (the
level-(l+1) mesh is the level-l mesh refined once, so the level-l nodes are its first nodes and the
modes are matched by MAC there), floored at ``PRECISION_FLOOR_PCT``. With errors e_l converging
at least like h (the rate at the planform's singular corners), ``|e_l| <= |Delta| / (1 - 1/2)``: an
upper bound for Morley (order 2) as for Argyris. The Argyris/Morley bracket on the same mesh
would be a guaranteed bound and cheap, but it measures the Morley error, far larger than the
Argyris one, so it would refuse every default truth; the next-level change is sharp and costs one
more solve (cached with the truth). scripts/truth_error_estimate.py compares the two.
Nested conforming meshes make Argyris frequencies decrease with the level in exact arithmetic; in
floating point the graded meshes reproduce them only to a few 1e-5, hence the floor.

Beam-theory gap: 100 (omega_1D / omega_truth - 1) against the 1D Euler-Bernoulli beam
(``beam.py``) mode of best MAC. Its cause: for a mode that is not beam-like, the mode has no 1D
counterpart (chordwise, torsion, mixed); for a beam-like mode of a slender strip (full width at
most ``SLENDER_WIDTH`` L everywhere) a plate stiffer than the beam is the clamped Poisson effect
(the root clamp blocks the anticlastic curvature); on a wider panel, or a plate softer than the
beam, it is plate action (2D load paths of a wide or jagged planform).
"""

from __future__ import annotations

import numpy as np

from ..errors import TruthError
from ..member.geometry import Beam
from ..options.limits import limits
from .modal import compute_modal
from .modes import mac_matrix
from .result import ModalSolution
from .settings import ERROR_TOL_PCT

__all__ = [
    "CoarseTruthError",
    "ERROR_TOL_PCT",
    "PRECISION_FLOOR_PCT",
    "SLENDER_WIDTH",
    "next_level_modal",
    "error_estimate_pct",
    "beam_theory_gap",
]


class CoarseTruthError(TruthError):
    """A selected mode's error estimate exceeds the asked tolerance (raise the mesh level)."""

PRECISION_FLOOR_PCT = 0.01
# the strips whose beam-like modes sit above Euler-Bernoulli by the clamp's Poisson restraint only
SLENDER_WIDTH = 0.25
ESTIMATED_MODELS = ("plate", "plate-morley", "beam")
# the 1D truth's mesh "levels": element counts (beam_modal's default is 200)
_BEAM_ELEMENTS = 200


_REFINED_DOF_RATIO = 4


def estimate_skipped(model: str, modal: ModalSolution) -> bool:
    """Whether the next mesh level of a plate truth is too large to be solved for the estimate."""
    # never above the mesh cap either: the estimate is optional, the truth is not
    caps = limits()
    cap = min(caps.max_estimate_dofs, caps.max_mesh_dofs)
    return model in ("plate", "plate-morley") and _REFINED_DOF_RATIO * int(modal.dofs) > cap


def next_level_modal(beam: Beam, model: str, modal: ModalSolution, index: np.ndarray):
    """Return the modal solution one mesh level finer (beam: twice the elements), or None.

    None for a model whose next level is not estimated (the solid: minutes) or too large
    (the cap ``max_estimate_dofs`` of :func:`~prbdm_pin.options.limits.limits`).
    """
    if model not in ESTIMATED_MODELS or estimate_skipped(model, modal):
        return None
    # a few modes beyond the highest selected one: the order shifts by 1e-4 between levels at most
    k = min(int(np.max(index)) + 3, int(modal.omega_rad_s.size))
    if model == "beam" and modal.kinds is not None:
        from .beam_spatial import beam_spatial_modal

        return beam_spatial_modal(beam, n_modes=k, n_elements=2 * _BEAM_ELEMENTS)
    if model == "beam":
        from .beam import beam_modal

        return beam_modal(beam, n_modes=k, n_elements=2 * _BEAM_ELEMENTS)
    return compute_modal(beam, model, modal.mesh_level + 1, k)


def _match(modal: ModalSolution, finer: ModalSolution, index: np.ndarray) -> np.ndarray:
    """Index into ``finer`` of each selected mode of ``modal``: best MAC at the coarse nodes."""
    if modal.model == "beam" and modal.kinds is not None:
        # the families are solved apart: the same family's mode of the same rank
        kinds, finer_kinds = np.array(modal.kinds), np.array(finer.kinds)
        out = []
        for i in np.asarray(index):
            rank = int(np.count_nonzero(kinds[:i] == kinds[i]))
            out.append(int(np.flatnonzero(finer_kinds == kinds[i])[rank]))
        return np.array(out, dtype=int)
    if modal.model == "beam":
        return np.asarray(index)
    n0 = modal.node_uz.shape[1]
    nested = (finer.nodes_m is not None and finer.nodes_m.shape[0] >= n0
              and np.array_equal(finer.nodes_m[:n0], modal.nodes_m))
    if not nested:
        # meshes that are not refinements of each other: the nearest frequency
        w = finer.omega_rad_s
        return np.array([int(np.argmin(np.abs(w / wi - 1.0))) for wi in modal.omega_rad_s[index]])
    mac = mac_matrix(modal.node_uz[index], finer.node_uz[:, :n0])
    return mac.argmax(axis=1)


def error_estimate_pct(modal: ModalSolution, finer: ModalSolution | None,
                       index: np.ndarray) -> np.ndarray | None:
    """Return the estimated relative error of each selected frequency, in %.

    ``2 |omega_l / omega_(l+1) - 1|`` against the next mesh level, at least PRECISION_FLOOR_PCT;
    None without ``finer``.
    """
    if finer is None:
        return None
    j = _match(modal, finer, index)
    change = 100.0 * np.abs(modal.omega_rad_s[index] / finer.omega_rad_s[j] - 1.0)
    return np.maximum(2.0 * change, PRECISION_FLOOR_PCT)


def beam_theory_gap(beam: Beam, modal: ModalSolution, index: np.ndarray,
                    labels: tuple[str, ...]) -> tuple[np.ndarray, tuple[str, ...]]:
    """Return the gap of each selected mode to its best-MAC 1D beam mode, and its cause.

    The gap is 100 (omega_1D / omega_truth - 1) in %; the cause one short phrase each.
    """
    from .beam import beam_modal

    idx = np.asarray(index)
    if modal.model == "beam":
        return np.zeros(idx.size), ("1D beam theory itself",) * idx.size
    j = np.asarray(modal.beam_mode_index)[idx]
    one_d = beam_modal(beam, n_modes=int(max(j.max(), 0)) + 1).omega_rad_s
    gap = 100.0 * (one_d[np.maximum(j, 0)] / modal.omega_rad_s[idx] - 1.0)
    slender = 2.0 * float(np.max(beam.half_width_m)) <= SLENDER_WIDTH * beam.length_m
    causes = []
    for i, g in zip(idx, gap, strict=True):
        label = labels[int(i)]
        if label != "bending":
            causes.append(f"{label} mode: no 1D beam counterpart")
        elif slender and g <= 0.0:
            causes.append("clamped Poisson effect (root clamp blocks the anticlastic curvature)")
        else:
            causes.append("plate action (wide or jagged planform: 2D load paths)")
    return gap, tuple(causes)
