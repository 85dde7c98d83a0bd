"""The kind of every computed mode, and the first modes of one kind.

A spatial chain fits bending modes to its y joints, torsion modes to its x joints and in-plane
bending modes to its z joints: it asks for each kind apart. The kinds follow the labels of
:func:`~prbdm_pin.truth.modes.label_modes`, with ``mixed`` (symmetric, uniform across the width,
not beam-like along the axis: jagged panels) counted as bending, as the chain bends for it;
``chordwise`` stays apart (no chain of rigid links represents it).
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from .modes import label_modes
from .result import ModalSolution, TruthResult

__all__ = ["KINDS", "SELECTABLE_KINDS", "kind_of_label", "mode_kinds", "kind_counts",
           "select_by_kind"]

# every kind a mode can have; "axial" is the 3D solid's extension modes
KINDS = ("bending", "torsion", "in-plane", "chordwise", "axial")
# the kinds a spatial chain's joints stand for
SELECTABLE_KINDS = ("bending", "torsion", "in-plane")
_OF_LABEL = {"bending": "bending", "mixed": "bending", "torsion": "torsion",
             "in-plane": "in-plane", "chordwise": "chordwise", "axial": "axial"}


def kind_of_label(label: str) -> str:
    """Return the kind of a mode label (``"mixed"`` is ``"bending"``, the others their own)."""
    try:
        return _OF_LABEL[label]
    except KeyError:
        raise ValueError(f"label = {label!r}: not a mode label ({sorted(_OF_LABEL)})") from None


def _modal_and_labels(truth_or_modal) -> tuple[ModalSolution, tuple[str, ...]]:
    if isinstance(truth_or_modal, TruthResult):
        return truth_or_modal.modal, tuple(truth_or_modal.labels)
    if isinstance(truth_or_modal, ModalSolution):
        return truth_or_modal, label_modes(truth_or_modal)
    raise BeamInputError(f"truth = {truth_or_modal!r:.80}: must be a TruthResult or a "
                         "ModalSolution")


def mode_kinds(truth_or_modal: TruthResult | ModalSolution) -> tuple[str, ...]:
    """Return the kind of every computed mode, ascending in frequency.

    Parameters
    ----------
    truth_or_modal : TruthResult or ModalSolution
        A truth (its ``labels``) or a modal solution (labelled by ``label_modes``).

    Returns
    -------
    tuple of str
        One of :data:`KINDS` per mode of ``modal.omega_rad_s``.
    """
    _, labels = _modal_and_labels(truth_or_modal)
    return tuple(kind_of_label(lab) for lab in labels)


def kind_counts(truth_or_modal: TruthResult | ModalSolution) -> dict[str, int]:
    """Return how many computed modes there are of each of :data:`KINDS` (zeros included)."""
    kinds = mode_kinds(truth_or_modal)
    return {k: kinds.count(k) for k in KINDS}


def _hint(modal: ModalSolution, kind: str) -> str:
    if modal.model == "beam" and modal.kinds is None and kind != "bending":
        return ("the 1D beam truth solves its torsion and in-plane modes only on request "
                "(spatial=True)")
    if modal.model.startswith("plate") and kind == "in-plane":
        return "a plate has no in-plane modes (use the solid or the 1D beam with spatial=True)"
    return "compute more modes (n_computed)"


def select_by_kind(truth_or_modal: TruthResult | ModalSolution, kind: str, n: int, *,
                   field: str | None = None) -> np.ndarray:
    """Return the indices of the ``n`` lowest computed modes of one kind.

    Parameters
    ----------
    truth_or_modal : TruthResult or ModalSolution
    kind : {"bending", "torsion", "in-plane"}
        ``bending`` counts the modes labelled ``bending`` and ``mixed`` (never ``chordwise``).
    n : int
        How many, >= 1.
    field : str, optional
        What the caller's user asked for, to name in the error (e.g. ``"axes = 'xy'"``);
        default ``"kind = '<kind>', n = <n>"``.

    Returns
    -------
    ndarray of int, shape (n,)
        Indices into ``modal.omega_rad_s`` (ascending frequency).

    Raises
    ------
    BeamInputError
        An unknown kind, a bad count, or fewer than ``n`` computed modes of the kind (the
        message names ``field``, the counts and what would give more).
    """
    if kind not in SELECTABLE_KINDS:
        raise BeamInputError(f"kind = {kind!r}: must be one of {SELECTABLE_KINDS}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise BeamInputError(f"n = {n!r}: must be an integer >= 1")
    modal, _ = _modal_and_labels(truth_or_modal)
    kinds = np.array(mode_kinds(truth_or_modal), dtype=object)
    found = np.flatnonzero(kinds == kind)
    if found.size < n:
        name = field if field is not None else f"kind = {kind!r}, n = {int(n)}"
        raise BeamInputError(
            f"{name}: the {modal.model} truth has {found.size} {kind} modes among its "
            f"{kinds.size} computed; {int(n)} needed: {_hint(modal, kind)}")
    return found[:n]
