"""The truth's choices and defaults: its models, large-deflection solves and mesh levels.

Light on purpose (numpy only): the command line and the cached-truth path read these without
loading the finite-element code.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..options.choices import TRUTH_MODELS

__all__ = [
    "lanczos_start",
    "MODELS",
    "SELECTIONS",
    "LARGE_DEFLECTION",
    "DEFAULT_LARGE_DEFLECTION",
    "DEFAULT_PLATE_LEVEL",
    "DEFAULT_COMPUTED_MODES",
    "ERROR_TOL_PCT",
    "check_mesh_level",
    "check_level",
]

MODELS = TRUTH_MODELS
# "paper": the N modes of largest z mass participation; "shape": the lowest N beam-like modes
SELECTIONS = ("paper", "shape")
# "calibrated-elastica" (default): the elastica with EI(x) scaled so that its small-load tip is the
# truth model's own linear tip (the frequencies' model); "elastica": the plain 1D elastica;
# "solid": the nonlinear 3D solid (reference, about a minute on a wide panel)
LARGE_DEFLECTION = ("calibrated-elastica", "elastica", "solid", "none")
DEFAULT_LARGE_DEFLECTION = "calibrated-elastica"
# Cheapest level meeting 0.1 % on the five bending modes of the shipped beams
# (scripts/bench_truth.py): the level-0 mesh is graded towards re-entrant corners, which is where
# the error of a uniform mesh concentrates.
DEFAULT_PLATE_LEVEL = 0
# Enough modes that the z mass participation of the unseen modes cannot reorder a 5-mode selection.
DEFAULT_COMPUTED_MODES = 25
# Largest accepted error estimate of a selected frequency, % (``truth.estimate``): a truth above
# it is refused unless the caller accepts it (error_tol_pct=None, --accept-coarse).
ERROR_TOL_PCT = 0.5


def check_mesh_level(level: object) -> int:
    """``mesh_level`` of ``compute_truth`` as an int; BeamInputError outside [0, 6]."""
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or not 0 <= level <= 6:
        raise BeamInputError(f"mesh_level = {level!r}: must be an integer in [0, 6]")
    return int(level)


def check_level(level: object) -> int:
    """``level`` of a single solver as an int; BeamInputError below 0."""
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or level < 0:
        raise BeamInputError(f"level = {level!r}: must be an integer >= 0")
    return int(level)


def lanczos_start(size: int) -> np.ndarray:
    """Return the start vector of every shift-invert Lanczos solve of the truth, shape (size,).

    ARPACK starts from a random vector unless given one, so the same truth came out different
    in its last digits (1e-10 relative) from run to run, and a fit with several exact solutions
    (n frequencies for 2n unknowns) picked a different one. A fixed pseudo-random vector keeps
    every eigensolve reproducible and still has a component along every mode (a constant vector
    would have none along the antisymmetric ones).
    """
    return np.random.default_rng(0).standard_normal(int(size))

