"""``prbdm simulate``'s plant options and ``--compare-truth`` of a plant.

The options (``--hub``, ``--hub-axis``, ``--spin``, ``--actuator``, ``--input``, ``--outputs``)
are checked before any work; the outputs recorded by default.
"""

from __future__ import annotations

import argparse

from ..errors import BeamInputError
from .fit_actuators import check_fit_actuators
from .plant_options import actuators_option, hub_option, names_option, spans_option


def check_plant_options(args: argparse.Namespace) -> dict:
    """Return the plant options (hub, actuators, input signals, output names).

    Each is refused with a message naming it; ``plant`` says whether any was given.
    """
    from .input_signals import parse_inputs

    names, signal = parse_inputs(args.input)
    outputs = None if args.outputs is None else names_option(args.outputs, "--outputs")
    opts = {"hub": hub_option(args.hub, args.hub_axis),
            "actuators": actuators_option(args.actuator),
            "inputs": names, "u": signal, "outputs": outputs,
            "loads": spans_option(args.distributed_span)}
    opts["plant"] = bool(args.hub or args.actuator or args.input)
    if args.spin is not None:
        from .checks import in_range

        in_range("--spin", args.spin, unit="rad/s")
        if args.hub is None:
            raise BeamInputError(f"--spin = {args.spin!r}: needs --hub INERTIA:RADIUS (the hub "
                                 "spins)")
        if args.compare_truth:
            raise BeamInputError(f"--spin = {args.spin!r}: --compare-truth compares the plant "
                                 "at rest; drop one")
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
    """Compare the linearised plant with the truth plant (``prbdm linearize --compare-truth``).

    Returns the :class:`~prbdm_pin.plant.comparison_truth.TruthPlantComparison`.
    """
    from ..plant.comparison_truth import compare_truth_plant
    from ..plant.linearize import linearize
    from .compare_truth import print_truth_warnings, truth_request_of
    from .fit_checks import cache_dir

    request = truth_request_of(fitted, args.model)
    lin = linearize(model, inputs=plant["inputs"], outputs=outputs or ("tip_z",),
                    damping_ratio=args.damping, damping="modal",
                    actuators=tuple(plant["actuators"]), loads=plant["loads"])
    cmp = compare_truth_plant(lin, model, request, plant["actuators"], args.damping,
                              cache_dir(args))
    print_truth_warnings(cmp.truth, args.quiet)
    return cmp
