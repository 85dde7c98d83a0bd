"""Structured mapped meshes of a planform that follow its vertices exactly.

The planform is mapped from (x, eta) in [0, L] x [-1, 1] by y = eta * w(x). Element edges sit on
every planform vertex, so the piecewise-linear outline is represented exactly. Random planforms
can have vertices a few millimetres apart; a plain mapped mesh would then put a sliver next to a
large element, so the x stations are graded: the local element size grows from a short vertex
interval at most by the factor ``growth`` per element length.
"""

from __future__ import annotations

import numpy as np
from skfem import MeshQuad, MeshTri

from ..geometry import Beam

__all__ = ["element_size", "x_stations", "eta_stations", "planform_quad_mesh", "planform_tri_mesh"]


def element_size(beam: Beam, level: int, base_elements: int = 10) -> float:
    """Target in-plane element size in m at refinement ``level`` (halves with each level)."""
    if level < 0:
        raise ValueError(f"level = {level}: must be >= 0")
    return beam.length_m / (base_elements * 2**level)


def x_stations(beam: Beam, h_m: float, growth: float = 0.3) -> np.ndarray:
    """Graded x stations (m) that contain every planform vertex.

    The size field is s(x) = min(h, min_k(l_k + growth * dist(x, interval_k))) over vertex
    intervals of length l_k < h, so elements next to a short interval are small and grow gently.
    """
    xv = beam.x_m
    lengths = np.diff(xv)
    short = np.flatnonzero(lengths < h_m)

    def size(x: np.ndarray) -> np.ndarray:
        s = np.full_like(x, h_m)
        for k in short:
            d = np.maximum(0.0, np.maximum(xv[k] - x, x - xv[k + 1]))
            s = np.minimum(s, lengths[k] + growth * d)
        return s

    out = [xv[:1]]
    for a, b in zip(xv[:-1], xv[1:], strict=True):
        xs = np.linspace(a, b, 201)
        inv = 1.0 / size(xs)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(xs))])
        n = max(1, int(np.ceil(cum[-1] - 1e-9)))
        targets = np.linspace(0.0, cum[-1], n + 1)
        out.append(np.interp(targets, cum, xs)[1:])
    x = np.concatenate(out)
    x[-1] = xv[-1]
    return x


def eta_stations(beam: Beam, h_m: float) -> np.ndarray:
    """Stations in eta in [-1, 1]; an even count of elements so the axis y = 0 is a mesh line."""
    w_max = float(np.max(beam.half_width_m))
    n_half = max(1, int(np.ceil(w_max / h_m)))
    return np.linspace(-1.0, 1.0, 2 * n_half + 1)


def _grid(beam: Beam, level: int) -> tuple[np.ndarray, int, int]:
    h = element_size(beam, level)
    xs = x_stations(beam, h)
    etas = eta_stations(beam, h)
    X, E = np.meshgrid(xs, etas, indexing="ij")
    Y = E * beam.half_width_at(X)
    p = np.vstack([X.ravel(), Y.ravel()])
    return p, xs.size, etas.size


def planform_quad_mesh(beam: Beam, level: int = 1) -> MeshQuad:
    """Mapped quadrilateral mesh of the planform (nodes in m)."""
    p, nx, ne = _grid(beam, level)
    idx = np.arange(nx * ne).reshape(nx, ne)
    a = idx[:-1, :-1].ravel()
    b = idx[1:, :-1].ravel()
    c = idx[1:, 1:].ravel()
    d = idx[:-1, 1:].ravel()
    return MeshQuad(p, np.vstack([a, b, c, d]))


def planform_tri_mesh(beam: Beam, level: int = 1) -> MeshTri:
    """Mapped triangle mesh of the planform, mirror-symmetric about y = 0 (nodes in m).

    Each quad is split along the diagonal that points away from the axis, so the mesh is the
    mirror image of itself and symmetric modes stay exactly symmetric.
    """
    p, nx, ne = _grid(beam, level)
    idx = np.arange(nx * ne).reshape(nx, ne)
    a = idx[:-1, :-1]
    b = idx[1:, :-1]
    c = idx[1:, 1:]
    d = idx[:-1, 1:]
    upper = np.zeros_like(a, dtype=bool)
    upper[:, (ne - 1) // 2:] = True
    t1 = np.where(upper, np.stack([a, b, d]), np.stack([a, b, c]))
    t2 = np.where(upper, np.stack([b, c, d]), np.stack([a, c, d]))
    t = np.hstack([t1.reshape(3, -1), t2.reshape(3, -1)])
    return MeshTri(p, t)
