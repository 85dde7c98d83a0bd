"""``prbdm linearize --compare-truth``: the linearised PRBDM against the truth plant.

The truth is the one the fit was made against, on the same hub and with the same actuators.
"""

from __future__ import annotations

import sys
from typing import Any

from ..errors import BeamInputError

# truths whose modes the truth plant reads (``truth_modal_gains``)
PLANT_TRUTH_MODELS = ("plate", "plate-morley", "beam")


def check_compare_options(args, opts: dict) -> None:
    """Refuse ``--compare-truth`` with options the truth plant has no counterpart of.

    This runs before any work.
    """
    if not args.compare_truth:
        return
    from .fit_checks import check_cache_dir

    if any(opts["load"]) or any(opts["gravity"]):
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
    """Return the truth request a fit recorded.

    Raises BeamInputError naming ``option`` when the model file has none or its truth has no
    modal plant.
    """
    request = getattr(fitted, "truth_request", None)
    if request is None:
        raise BeamInputError(f"{option}: MODEL {model_path!r} carries no truth record "
                             "(give the fit.json written by `prbdm fit`)")
    if request.model not in PLANT_TRUTH_MODELS:
        raise BeamInputError(f"{option}: the fit's truth model {request.model!r} has no "
                             f"modal plant; fit against one of {', '.join(PLANT_TRUTH_MODELS)}")
    return request


def compare_with_truth(lin, model, request, opts: dict, damping_ratio: float, cache_dir: str,
                       quiet: bool = True):
    """Compare ``lin`` (the PRBDM plant of ``model``) with the truth plant.

    The truth plant has the same hub and actuators and is damped alike (every flexible mode of
    the coupled plant).
    """
    from ..plant.comparison import compare_plant
    from ..truth.plant import clamped_model, hybrid_model

    beam = model.beam
    truth = request.compute(beam, cache_dir=cache_dir)
    if not quiet:
        for note in truth.warnings:
            print(f"truth warning: {note}", file=sys.stderr)
    stations = [(a.x_start_m, a.x_end_m) for a in opts["actuators"]]
    hub = opts["hub"]
    if hub is None:
        plant = clamped_model(truth, beam, stations, damping_ratio)
    else:
        plant = hybrid_model(truth, beam, hub.inertia_kg_m2, hub.radius_m, stations,
                             damping_ratio, damping="modal")
    return compare_plant(lin, plant), truth


def comparison_record(cmp, truth, request, source: str, damping_ratio: float) -> dict[str, Any]:
    """``comparison.json``: what was compared with what, and the comparison."""
    from ..plant.comparison_record import comparison_dict

    return {
        "prbdm": {"source": source, "linearised_at": "straight pose (q = 0), unloaded"},
        "truth": {"model": truth.model, "request": request.to_dict(),
                  "mesh_level": int(truth.mesh_level),
                  "selected_omega_rad_s": [float(w) for w in truth.omega_rad_s]},
        "damping": {"ratio": float(damping_ratio),
                    "form": "modal on both sides: every flexible mode of the coupled plant "
                            "(hub-stiffened on a hub), the rigid-body mode undamped"},
        **comparison_dict(cmp),
    }
