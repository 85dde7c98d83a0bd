"""Where a thickness law needs mesh edges: lines across the width at its kinks.

The plate's and the solid's planform meshes (``mesh``, ``feature_mesh``) make every line
x = x_k returned here a chain of mesh edges, so that t(x) is linear inside every element.
"""

from __future__ import annotations

import numpy as np

from ..member.geometry import Beam

__all__ = ["MIN_LINE_ANGLE_DEG", "law_stations", "station_lines"]

# a station line meeting the outline at less than this angle would make slivers between the two
# (on random panels, a vertex interval of 0.8 mm next to a 0.14 m drop of the half-width: 0.3
# degrees, and Argyris eigenpairs with residuals of 1e-2): no line there
MIN_LINE_ANGLE_DEG = 20.0


def law_stations(beam: Beam) -> np.ndarray:
    """Return the inner stations x_k (m) where the thickness law's slope changes.

    Empty for a uniform thickness. The plate and solid meshes make the line x = x_k across the
    width a chain of mesh edges, so t(x) is linear inside every element and quadrature of E t^3
    and rho t is exact. A station whose line would meet the outline at less than
    ``MIN_LINE_ANGLE_DEG`` is left out: elements straddle it and the quadrature of t (evaluated
    at the quadrature points) is then not exact there, an error that vanishes with the mesh.
    """
    law = beam.thickness_law_m
    if law is None:
        return np.zeros(0)
    x, w = beam.x_m, beam.half_width_m
    out = []
    for k in range(1, x.size - 1):
        if x[k] == x[k - 1]:
            continue  # the second vertex of a width step: its station is the first's
        j = k + 1 if x[k + 1] == x[k] else k  # the step's tip-side vertex (k if no step)
        if j + 1 >= x.size:
            continue
        s0 = (law[k] - law[k - 1]) / (x[k] - x[k - 1])
        s1 = (law[j + 1] - law[j]) / (x[j + 1] - x[j])
        if abs(s1 - s0) <= 1e-12 * max(abs(s0), abs(s1)):
            continue  # t is linear across the station
        if _line_angle_deg(x, w, k, j) >= MIN_LINE_ANGLE_DEG:
            out.append(float(x[k]))
    return np.array(out)


def _line_angle_deg(x: np.ndarray, w: np.ndarray, k: int, j: int) -> float:
    """Smallest angle (degrees) between the station line x = x_k and the outline at its top.

    ``k`` and ``j`` are the station's vertices (equal unless a width step); the line ends at
    the narrower side, whose outline pieces toward the root (``k - 1``) or the tip (``j + 1``)
    it meets; a step's own vertical piece continues the line and makes no angle.
    """
    top = (x[k], min(w[k], w[j]))
    ends = []
    if j == k or w[k] <= w[j]:
        ends.append((x[k - 1], w[k - 1]))
    if j == k or w[j] <= w[k]:
        ends.append((x[j + 1], w[j + 1]))
    # the angle between the downward line (0, -1) and each piece from the top
    angles = [np.degrees(np.arccos(np.clip(-(ey - top[1]) / np.hypot(ex - top[0], ey - top[1]),
                                           -1.0, 1.0))) for ex, ey in ends]
    return float(min(angles))


def station_lines(beam: Beam, size_m, outline: np.ndarray | None = None
                  ) -> tuple[np.ndarray, ...]:
    """Polylines (2, k) across the upper half-width at every ``law_stations`` x_k, m.

    From (x_k, 0) to (x_k, w(x_k)) (the narrower side at a width step), points spaced by the
    mesh's size field ``s = size_m(points (2, n))`` (m; equal steps in the integral of 1 / s
    along the line, so a uniform s gives about w / s equal steps). With ``outline`` (2, b), the
    polyline of the upper outline, inner points closer than 0.55 s to it are left out, as the
    meshes leave out interior points there (they would make slivers against the outline).
    """
    from .mesh import inner_half_width, segment_distance  # mesh imports this module

    out = []
    for xk in law_stations(beam):
        w = float(inner_half_width(beam, np.array([xk]))[0])
        ys = np.linspace(0.0, w, 201)
        inv = 1.0 / size_m(np.vstack([np.full(ys.size, xk), ys]))
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(ys))])
        n = max(1, int(np.ceil(cum[-1] - 0.25)))
        y = np.interp(np.linspace(0.0, cum[-1], n + 1), cum, ys)
        y[0], y[-1] = 0.0, w
        pts = np.vstack([np.full(y.size, xk), y])
        if outline is not None and n > 1:
            inner = pts[:, 1:-1]
            far = segment_distance(inner, outline[:, :-1], outline[:, 1:]) > 0.55 * size_m(inner)
            pts = np.hstack([pts[:, :1], inner[:, far], pts[:, -1:]])
        out.append(pts)
    return tuple(out)
