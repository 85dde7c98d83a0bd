"""``--compare-truth``: which truth a command compares with.

``prbdm simulate --compare-truth`` compares the tip response (``plant.truth_comparison``). The
comparison itself is a library function; this module only reads the options and the fit's
record.
"""

from __future__ import annotations

import sys


def comparison_request(model, fitted, truth_model: str | None = None, quiet: bool = True):
    """Return the truth request ``prbdm simulate --compare-truth`` asks for.

    With no ``--truth-model`` (or the fit's own model), the request recorded in the fit
    (``fitted.truth_request``: model, selection, mesh level, ...) when it is a plate or beam truth,
    so the comparison finds the fit's truth in the cache; otherwise ``--truth-model`` (default
    plate) at ``prbdm fit``'s defaults with n = joints modes.
    """
    from ..plant.truth_comparison import TRUTH_MODELS
    from ..truth.request import TruthRequest

    recorded = getattr(fitted, "truth_request", None)
    if recorded is not None and truth_model in (None, recorded.model):
        if recorded.model in TRUTH_MODELS:
            return recorded
        if not quiet:
            print(f"note: the fit's {recorded.model} truth has no modal superposition here; "
                  "comparing with the plate truth", file=sys.stderr)
    return TruthRequest(model=truth_model or "plate", modes=int(model.n_joints))


def print_truth_warnings(truth, quiet: bool) -> None:
    """Print the truth's warnings to stderr (unless ``quiet``)."""
    if not quiet:
        for note in truth.warnings:
            print(f"truth warning: {note}", file=sys.stderr)
