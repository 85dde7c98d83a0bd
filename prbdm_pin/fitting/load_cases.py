"""Extra load cases of a fit: further tip loads whose large-deflection truth tips the fit matches.

``fit(beam, target, n, ..., extra_loads=(2, 5))`` (the command line's ``--extra-loads 2,5``)
adds load cases at 2 and 5 times the beam's tip force; each truth tip comes from the
large-deflection model of the target's truth (``target.truth_request.large_deflection``, the
calibrated elastica by default: the 1D elastica with E I(x) scaled by the truth model's
``static_theory_gap_pct``, so that at small load it is the model the frequencies come from).
A :class:`~prbdm_pin.target.LoadCase` given instead is taken as it is (a tip computed
elsewhere, a measurement).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..options.checks import check_float, shown
from .target import FitTarget, LoadCase

__all__ = ["LARGE_DEFLECTION_TIPS", "extra_load_cases", "with_extra_loads"]

# the large-deflection models that give an extra load case its truth tip
LARGE_DEFLECTION_TIPS = ("calibrated-elastica", "elastica", "solid")


def extra_load_cases(beam, factors: Sequence[float], large_deflection: str = "calibrated-elastica",
                     static_theory_gap_pct: float | None = None) -> tuple[LoadCase, ...]:
    """Load cases at multiples of the beam's tip force, with their large-deflection truth tips.

    Parameters
    ----------
    beam : Beam
        Its ``tip_force_N`` (N) is the load each factor multiplies.
    factors : sequence of float
        Finite, non-zero multiples of the tip force.
    large_deflection : {"calibrated-elastica", "elastica", "solid"}
        The truth tip's model: the elastica (milliseconds; ``calibrated-elastica`` scales
        E I(x) by 1 + ``static_theory_gap_pct`` / 100) or the nonlinear 3D solid (minutes).
    static_theory_gap_pct : float or None
        The primary truth's gap to 1D theory, % (the linear ratio does not depend on the load).

    Returns
    -------
    tuple of LoadCase
        One per factor: the force (N), the truth tip position and displacement (m).
    """
    if large_deflection not in LARGE_DEFLECTION_TIPS:
        raise BeamInputError(f"large_deflection = {large_deflection!r}: must be one of "
                             f"{', '.join(LARGE_DEFLECTION_TIPS)}")
    cases = []
    for i, f in enumerate(factors):
        f = check_float(f"extra_loads[{i}]", f)
        if f == 0.0:
            raise BeamInputError(f"extra_loads[{i}] = 0: a multiple of the tip force must be "
                                 "non-zero")
        b = beam.with_tip_force(f * beam.tip_force_N)
        if large_deflection == "solid":
            from ..truth.solid import solid_static

            st = solid_static(b, nonlinear=True)
        else:
            from ..truth.elastica import elastica_static

            gap = static_theory_gap_pct if large_deflection == "calibrated-elastica" else None
            st = elastica_static(b, ei_scale=1.0 if gap is None else 1.0 + gap / 100.0)
        cases.append(LoadCase(b.tip_force_N, st.tip_position_m, st.tip_displacement_m))
    return tuple(cases)


def with_extra_loads(target: FitTarget, beam, extra_loads: Any) -> FitTarget:
    """Return ``target`` with ``extra_loads`` added to its load cases.

    Each entry of ``extra_loads`` is a :class:`LoadCase` (taken as it is) or a number, a
    multiple of the beam's tip force whose truth tip :func:`extra_load_cases` computes with
    the target's large-deflection model (its ``truth_request``; the calibrated elastica
    without one). Refused, naming ``extra_loads``: not a sequence, an entry of another kind, a
    zero or non-finite multiple, no tip load on the beam, a target without a truth tip.
    """
    if isinstance(extra_loads, (str, bytes, dict, LoadCase)) or not isinstance(
            extra_loads, (Sequence, np.ndarray)):
        raise InputTypeError(f"extra_loads = {shown(extra_loads)}: must be a sequence of "
                             "multiples of the beam's tip force or of prbdm_pin.LoadCase")
    items = list(extra_loads)
    if not items:
        return target
    if not np.any(beam.tip_force_N) and not all(isinstance(c, LoadCase) for c in items):
        raise BeamInputError("extra_loads: multiples of the tip force need a tip load, and "
                             "the beam's tip_force is [0, 0, 0] N")
    request = target.truth_request
    model = getattr(request, "large_deflection", "calibrated-elastica")
    if model not in LARGE_DEFLECTION_TIPS:  # "none": the truth solved no large deflection
        model = "calibrated-elastica"
    cases: list[LoadCase] = []
    for i, c in enumerate(items):
        if isinstance(c, LoadCase):
            cases.append(c)
            continue
        if isinstance(c, bool) or not isinstance(c, (int, float, np.integer, np.floating)):
            raise InputTypeError(f"extra_loads[{i}] = {shown(c)}: must be a multiple of the "
                                 "beam's tip force (a number) or a prbdm_pin.LoadCase")
        case, = extra_load_cases(beam, [c], model, target.static_theory_gap_pct)
        cases.append(case)
    factors = [c for c in items if not isinstance(c, LoadCase)]
    note = f"; extra loads x{','.join(f'{f:g}' for f in factors)} ({model})" if factors else \
        f"; {len(items)} extra load case(s)"
    return dataclasses.replace(target, extra_loads=target.extra_loads + tuple(cases),
                               source=target.source + note)
