"""The tip-load part of a truth.

The model's linear solve, the large-deflection solve and the small-load gap between the 1D beam
and the truth model.
"""

from __future__ import annotations

import dataclasses

from ..member.geometry import Beam
from .result import StaticSolution

__all__ = ["ELASTICA_PLATE_TOL", "tip_response", "elastica_warnings"]

# the linear 2D/3D tip may differ this much from the 1D beam's before the plain elastica is
# flagged as missing plate action
ELASTICA_PLATE_TOL = 0.01


def tip_response(beam: Beam, model: str, level: int | None, large: str
                 ) -> tuple[StaticSolution, StaticSolution | None, float | None]:
    """Solve the tip load: linear, large-deflection, and the 1D beam's small-load gap.

    Returns the linear solve of the truth model, the large-deflection solve (None for
    ``"none"``), and the small-load gap 100 (u_1D / u_model - 1) in % between the 1D beam and
    the truth model's linear tips (None without a vertical load).
    """
    # the solvers load scikit-fem and scipy: imported here, so that a cached truth never does
    from .beam_static import beam_static

    nonlinear = None
    beam_lin = beam_static(beam)
    if model == "beam":
        linear = beam_lin
    elif model == "solid":
        from .solid import solid_static

        linear = solid_static(beam, level=level)
    else:
        from .plate_static import plate_static

        linear = plate_static(beam, level=level)
    u_model = float(linear.tip_displacement_m[2])
    u_1d = float(beam_lin.tip_displacement_m[2])
    # the ratio is load-independent (both linear); undefined without a vertical load
    gap = 100.0 * (u_1d / u_model - 1.0) if u_model != 0.0 and u_1d != 0.0 else None
    if large == "calibrated-elastica":
        from .elastica import elastica_static

        scale = 1.0 if gap is None else 1.0 + gap / 100.0
        nonlinear = dataclasses.replace(elastica_static(beam, ei_scale=scale),
                                        model="calibrated-elastica")
    elif large == "elastica":
        from .elastica import elastica_static

        nonlinear = elastica_static(beam)
    elif large == "solid":
        from .solid import solid_static

        nonlinear = solid_static(beam, nonlinear=True)
    return linear, nonlinear, gap


def elastica_warnings(beam: Beam, model: str, linear: StaticSolution | None,
                      large: str) -> list[str]:
    """Warn when the 1D elastica misses plate action that the linear 2D/3D solve shows.

    The elastica is a 1D model: on wide panels the plate is stiffer (anticlastic curvature is
    restrained), which the linear plate or solid tip deflection reveals against the linear 1D beam
    at no extra cost.
    """
    if large != "elastica" or model == "beam" or linear is None:
        return []
    from .beam_static import beam_static

    u_2d = float(linear.tip_displacement_m[2])
    u_1d = float(beam_static(beam).tip_displacement_m[2])
    if u_1d == 0.0:
        return []
    gap = abs(u_2d / u_1d - 1.0)
    if gap <= ELASTICA_PLATE_TOL:
        return []
    return [
        f"the large-deflection truth is the 1D elastica, but the linear {model} tip deflection "
        f"differs from the 1D beam's by {100 * gap:.1f} %: plate action matters here; use "
        f"large_deflection='solid' (--large-deflection solid) for a 3D nonlinear reference"
    ]
