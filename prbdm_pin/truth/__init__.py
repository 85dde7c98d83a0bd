"""The finite-element truth a PRBDM is fitted against (scikit-fem).

``compute_truth`` (``truth.compute``) computes the truth a ``TruthRequest`` (``truth.request``)
asks for: it runs a modal analysis (``truth.modal``: Kirchhoff plate by default, 3D solid or 1D
beam on request), labels and selects the bending modes (``truth.modes``; the modes of one kind,
bending, torsion or in-plane: ``truth.mode_kinds``), solves the tip-load
case (``truth.tip_response``) and refuses results it cannot trust (negative or complex
eigenvalues, a failed convergence check, a coarse error estimate). This module only
re-exports the public names; the finite-element code loads when a truth is solved.
"""

from .compute import compute_truth
from .estimate import CoarseTruthError
from .modal import compute_modal
from .mode_kinds import mode_kinds, select_by_kind
from .request import TruthRequest
from .result import ModalSolution, StaticSolution, Timings, TruthResult
from .settings import (
    DEFAULT_COMPUTED_MODES,
    DEFAULT_LARGE_DEFLECTION,
    DEFAULT_PLATE_LEVEL,
    ERROR_TOL_PCT,
    LARGE_DEFLECTION,
    MODELS,
)

__all__ = [
    "MODELS",
    "LARGE_DEFLECTION",
    "DEFAULT_PLATE_LEVEL",
    "DEFAULT_LARGE_DEFLECTION",
    "DEFAULT_COMPUTED_MODES",
    "TruthRequest",
    "TruthResult",
    "ModalSolution",
    "StaticSolution",
    "Timings",
    "compute_truth",
    "compute_modal",
    "mode_kinds",
    "select_by_kind",
    "CoarseTruthError",
    "ERROR_TOL_PCT",
]
