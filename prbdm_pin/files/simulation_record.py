"""``simulation.json``: what ``prbdm simulate`` integrated with, beside ``trajectory.csv``."""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any

__all__ = ["simulation_record"]


def simulation_record(tr, asked: str) -> dict[str, Any]:
    """Return the JSON form of the integrator a trajectory was computed with, and its counts.

    Parameters
    ----------
    tr : Trajectory
        The simulated trajectory; ``tr.integrator`` is the integrator actually used (the
        rule's pick when ``asked`` is ``"auto"``).
    asked : str
        The method asked for (``--method``).

    Returns
    -------
    dict
        ``kind``, ``method_asked``, ``method`` (used), ``integrator`` (its class and every
        field; an infinite one as the string ``"inf"``), ``steps``, ``rhs_evaluations``,
        ``jacobian_updates``, ``cpu_time_s``.
    """
    integ = tr.integrator
    settings: dict[str, Any] = {"type": type(integ).__name__}
    for f in fields(integ):
        v = getattr(integ, f.name)
        settings[f.name] = "inf" if isinstance(v, float) and math.isinf(v) else v
    return {"kind": "simulation", "method_asked": asked, "method": tr.method,
            "integrator": settings, "steps": int(tr.steps),
            "rhs_evaluations": int(tr.rhs_evaluations),
            "jacobian_updates": int(tr.jacobian_updates), "cpu_time_s": float(tr.cpu_time_s)}
