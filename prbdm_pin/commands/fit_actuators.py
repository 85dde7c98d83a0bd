"""``--fit-actuators``: strain actuator weights fitted to the truth.

Shared by ``prbdm linearize``, ``prbdm simulate`` and ``prbdm export``: the strain actuators'
joint weights fitted to the truth the fit.json was made against (from the cache), instead of
the virtual-work map.
"""

from __future__ import annotations

import argparse

from ..errors import BeamInputError

__all__ = ["add_fit_actuators_option", "check_fit_actuators", "fit_actuators"]

FIT_HELP = ("fit the strain actuators' joint weights to the modal gains of the truth the fit.json "
            "was made against (from the truth cache), instead of the virtual-work map (1 inside "
            "the patch, 1/2 on an end); needs a fit.json and --actuator")


def add_fit_actuators_option(p: argparse.ArgumentParser, cache_dir: bool = False) -> None:
    """Add ``--fit-actuators`` (and ``--cache-dir`` where the command has none)."""
    p.add_argument("--fit-actuators", action="store_true", help=FIT_HELP)
    if cache_dir:
        p.add_argument("--cache-dir", default=None, metavar="DIR",
                       help="truth cache folder of --fit-actuators, shared with `prbdm fit` "
                            "(default $PRBDM_CACHE or ~/.cache/prbdm_pin)")


def check_fit_actuators(args, n_actuators: int) -> None:
    """Refuse ``--fit-actuators`` without actuators or with an unwritable truth cache.

    This runs before any work; a command whose actuators may come from the model file passes
    -1.
    """
    if not args.fit_actuators:
        return
    from .fit_checks import check_cache_dir

    if n_actuators == 0:
        raise BeamInputError("--fit-actuators: no strain actuator to fit; give --actuator XA:XB")
    check_cache_dir(args)


def fit_actuators(args, model, fitted, actuators) -> tuple:
    """Return ``actuators`` with joint weights fitted to the fit.json's truth.

    ``model`` is the PRBDM, clamped or on its hub; ``actuators`` come back unchanged without
    ``--fit-actuators``.
    """
    if not args.fit_actuators:
        return tuple(actuators)
    from ..plant.actuator_fit import fit_strain_actuators
    from .compare_truth import print_truth_warnings, truth_request_of
    from .fit_checks import cache_dir

    if not actuators:
        raise BeamInputError("--fit-actuators: no strain actuator to fit; give --actuator XA:XB")
    request = truth_request_of(fitted, args.model, "--fit-actuators")
    truth = request.compute(model.beam, cache_dir=cache_dir(args))
    print_truth_warnings(truth, args.quiet)
    try:
        return fit_strain_actuators(model, truth, model.beam, actuators)
    except BeamInputError as exc:
        raise BeamInputError(f"--fit-actuators: {exc}") from None
