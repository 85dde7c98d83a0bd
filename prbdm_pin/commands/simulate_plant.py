"""``prbdm simulate``'s plant options and ``--compare-truth`` of a plant.

The options (``--hub``, ``--actuator``, ``--input``, ``--outputs``) are checked before any
work; the outputs recorded by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import BeamInputError
from .fit_actuators import check_fit_actuators
from .plant_options import actuators_option, hub_option, names_option


def check_plant_options(args: argparse.Namespace) -> dict:
    """Return the plant options (hub, actuators, input signals, output names).

    Each is refused with a message naming it; ``plant`` says whether any was given.
    """
    from .input_signals import parse_inputs

    names, signal = parse_inputs(args.input)
    outputs = None if args.outputs is None else names_option(args.outputs, "--outputs")
    opts = {"hub": hub_option(args.hub), "actuators": actuators_option(args.actuator),
            "inputs": names, "u": signal, "outputs": outputs}
    opts["plant"] = bool(args.hub or args.actuator or args.input)
    check_fit_actuators(args, len(opts["actuators"]))
    if args.compare_truth and opts["plant"]:
        if args.damping_form != "modal":
            raise BeamInputError(f"--damping-form = {args.damping_form!r}: --compare-truth of "
                                 "a plant damps every flexible mode of both plants alike; use "
                                 "modal")
        if not names:
            raise BeamInputError("--compare-truth: with --hub or --actuator, name the inputs "
                                 "to compare with --input")
    return opts


def plant_outputs(plant: dict, hub: bool) -> tuple[str, ...]:
    """Return the outputs to record: --outputs, or with plant options tip_z (and hub_angle)."""
    if plant["outputs"] is not None:
        return plant["outputs"]
    if plant["plant"]:
        return ("hub_angle", "tip_z") if hub else ("tip_z",)
    return ()


def plant_comparison(model, fitted, plant: dict, outputs, args):
    """Compare the linearised plant with the truth plant (``prbdm linearize --compare-truth``)."""
    from ..plant.linearize import linearize
    from .fit_checks import cache_dir
    from .plant_comparison import compare_with_truth, comparison_record, truth_request_of

    request = truth_request_of(fitted, args.model)
    lin = linearize(model, inputs=plant["inputs"], outputs=outputs or ("tip_z",),
                    damping_ratio=args.damping, damping="modal",
                    actuators=tuple(plant["actuators"]))
    opts = {"hub": model.hub, "actuators": plant["actuators"]}
    cmp, truth = compare_with_truth(lin, model, request, opts, args.damping, cache_dir(args),
                                    quiet=args.quiet)
    return cmp, comparison_record(cmp, truth, request, Path(args.model).name, args.damping)
