"""``--compare-truth``: which truth a command compares with, and the options it refuses.

``prbdm simulate --compare-truth`` compares the tip response (``plant.truth_comparison``),
``prbdm linearize --compare-truth`` and ``prbdm simulate --compare-truth`` of a plant the plant
(``plant.comparison_truth``); ``--fit-actuators`` fits to the same truth. The comparisons
themselves are library functions; this module only reads the options and the fit's record.
"""

from __future__ import annotations

import sys

from ..errors import BeamInputError


def check_compare_options(args, opts: dict) -> None:
    """Refuse ``--compare-truth`` with options the truth plant has no counterpart of.

    This runs before any work.
    """
    if not args.compare_truth:
        return
    from .fit_checks import check_cache_dir

    if any(opts["load"]) or any(opts["gravity"] or ()):  # None: --gravity not given
        raise BeamInputError("--compare-truth: the truth plant is the unloaded straight beam; "
                             "drop --load and --gravity")
    if args.damping_form != "modal":
        raise BeamInputError(f"--damping-form = {args.damping_form!r}: --compare-truth damps "
                             "every flexible mode of both plants alike; use modal")
    if not args.damping_ratio > 0.0:
        raise BeamInputError(f"--damping-ratio = {args.damping_ratio!r}: --compare-truth needs "
                             "damped modes (> 0) for finite resonance peaks")
    check_cache_dir(args)


def truth_request_of(fitted, model_path: str, option: str = "--compare-truth"):
    """Return the truth request a fit recorded, for the truth plant.

    Raises BeamInputError naming ``option`` when the model file has none or its truth has no
    modal plant.
    """
    from ..plant.comparison_truth import PLANT_TRUTH_MODELS

    request = getattr(fitted, "truth_request", None)
    if request is None:
        raise BeamInputError(f"{option}: MODEL {model_path!r} carries no truth record "
                             "(give the fit.json written by `prbdm fit`)")
    if request.model not in PLANT_TRUTH_MODELS:
        raise BeamInputError(f"{option}: the fit's truth model {request.model!r} has no "
                             f"modal plant; fit against one of {', '.join(PLANT_TRUTH_MODELS)}")
    return request


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
