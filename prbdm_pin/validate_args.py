"""Checks of the public functions' object arguments, springs and output paths.

The second half of the door checks (:mod:`prbdm_pin.validate` holds the numbers, units and
types): a model that must be a :class:`~prbdm_pin.PrbdmModel`, the arguments every fit takes,
joint springs against the beam they are built on, and output files and folders checked as the
command line checks ``--out`` (``commands.checks``), before anything is written. Kept apart
because it imports the model and the command line, which the truth (and its cache key) must not.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .errors import BeamInputError
from .validate import SPRING_WINDOW, check_joints, check_path, check_type, check_workers

__all__ = ["check_out_file", "check_out_dir", "check_model", "check_fit_inputs",
           "check_springs"]


def check_out_file(name: str, value: Any) -> Path:
    """Check that ``value`` names a file that can be written, as ``prbdm export --out`` does.

    Refused before anything is written: a wrong type, an existing folder, a path under a file,
    in ``/proc``, ``/sys`` or ``/dev``, or in a folder that cannot be written.
    """
    from .commands.checks import writable_file

    return writable_file(check_path(name, value), name)


def check_out_dir(name: str, value: Any) -> Path:
    """Check that ``value`` is, or can be created as, a folder to write results into.

    As ``--out`` of the commands: refused before anything is made are a wrong type, a path
    that is a file or lies under one, in ``/proc``, ``/sys`` or ``/dev``, or below a folder
    that cannot be written. Nothing is created.
    """
    from .commands.checks import writable_dir

    return writable_dir(check_path(name, value, "output folder"), name)


def check_model(value: Any, name: str = "model") -> Any:
    """``value`` if it is a :class:`~prbdm_pin.PrbdmModel`; else InputTypeError naming it."""
    from .model import PrbdmModel

    return check_type(name, value, PrbdmModel, "a prbdm_pin.PrbdmModel (build_model, "
                      "load_urdf, read_model_json)")


def check_fit_inputs(beam: Any, target: Any, joints: Any, workers: Any = 1) -> int:
    """Check what every fit takes: a Beam, a FitTarget, n joints (capped) and workers.

    Returns n. Wrong types are :class:`InputTypeError`, naming ``beam``, ``target``, ...
    """
    from .geometry import Beam
    from .target import FitTarget

    check_type("beam", beam, Beam)
    check_type("target", target, FitTarget, "a prbdm_pin.FitTarget (target_from_truth)")
    check_workers(workers)
    return check_joints(joints)


def check_springs(beam, stiffness_Nm_per_rad) -> None:
    """Check joint springs (N m/rad, validated) against what the beam can hold.

    A finite-segment spring E / int dx / I(x) over a span l lies between E I_min / L (the
    whole beam, its narrowest section) and E I_max / (1e-5 L) (the shortest link a model may
    have, its widest section); a fitted spring is that times a factor. A spring more than
    ``SPRING_WINDOW`` beyond either end is no joint of this beam (a unit slip, or a value meant
    for another model), and its products with the link inertias would leave double precision.
    """
    from .model_files import LINK_FLOOR_FRACTION

    t3 = beam.thickness_m**3
    E, L = beam.material.E_Pa, beam.length_m
    EI_min = E * 2.0 * float(beam.half_width_m.min()) * t3 / 12.0
    EI_max = E * 2.0 * float(beam.half_width_m.max()) * t3 / 12.0
    lo = EI_min / L / SPRING_WINDOW
    hi = EI_max / (LINK_FLOOR_FRACTION * L) * SPRING_WINDOW
    for i, k in enumerate(stiffness_Nm_per_rad):
        if not lo <= k <= hi:
            raise BeamInputError(
                f"stiffness[{i}] = {float(k):.6g} N m/rad: outside {lo:.3g} ... {hi:.3g} N m/rad,"
                f" {SPRING_WINDOW:g} times beyond the finite-segment springs E I / l of this "
                f"beam (E I = {EI_min:.3g} ... {EI_max:.3g} N m^2, l = {LINK_FLOOR_FRACTION:g} L"
                f" ... L = {L:.6g} m); springs in N mm/rad, or of another model?")
