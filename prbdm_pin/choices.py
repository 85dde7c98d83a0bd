"""Enumerated choices of the fit, the truth and the exports, and the fit's default eigen norm.

Each set is written here once, free of numpy and the numerics, so that the command line lists
them in ``prbdm COMMAND --help`` without loading either; the modules that act on a choice
import it from here.
"""

from __future__ import annotations

__all__ = [
    "OBJECTIVES",
    "STIFFNESS_KINDS",
    "EIGEN_NORMS",
    "DEFAULT_EIGEN_NORM",
    "TRUTH_MODELS",
    "FORMATS",
    "EXPORT_DAMPING_FORMS",
]

# what a fit minimises: Eq. 17, Eq. 19 or Eq. 27
OBJECTIVES = ("eigen", "deflection", "combined")
# one SCF per pose (Eq. 14), or one factor per joint
STIFFNESS_KINDS = ("paper", "joint")
# eigen error per pose: Eq. 16's l2 norm, or the rms of the per-mode relative errors
EIGEN_NORMS = ("paper", "relative")
# the eigen norm of fit and fit_pareto: the relative norm keeps every mode in view and gives
# the better model for dynamics (scripts/dynamic_accuracy.py compares the two; README)
DEFAULT_EIGEN_NORM = "relative"
# finite-element truth models (``truth.compute_truth``)
TRUTH_MODELS = ("plate", "plate-morley", "solid", "beam")
# files ``export_model`` writes
FORMATS = ("urdf", "mjcf", "json")
# joint damping an export carries: C = beta K, or every mode the same ratio (JSON only)
EXPORT_DAMPING_FORMS = ("stiffness", "modal")
