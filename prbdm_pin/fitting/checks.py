"""What every fit takes, checked at its entry (``fit``, ``fit_pareto``, ``codesign_point``)."""

from __future__ import annotations

from typing import Any

from ..options.validate import check_joints, check_type, check_workers

__all__ = ["check_fit_inputs"]


def check_fit_inputs(beam: Any, target: Any, joints: Any, workers: Any = 1) -> int:
    """Check what every fit takes: a Beam, a FitTarget, n joints (capped) and workers.

    Returns n. Wrong types are :class:`InputTypeError`, naming ``beam``, ``target``, ...
    """
    from ..member.geometry import Beam
    from .target import FitTarget

    check_type("beam", beam, Beam)
    check_type("target", target, FitTarget, "a prbdm_pin.FitTarget (target_from_truth)")
    check_workers(workers)
    return check_joints(joints)
