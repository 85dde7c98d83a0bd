"""The 3D solid's planform mesh: quadrilaterals split from a triangle mesh graded in 2D.

The plate's mesh (``mesh.planform_tri_mesh``) grades its x stations: a short vertex interval
makes small elements across the whole width. That is affordable for the 2D plate, but the 3D
solid, whose quadrilaterals split every triangle in three, then needs up to 1.4 M DOFs (seed 5 of
``random_beam``: an interval of 0.8 mm at the tip) and SuperLU runs out of memory. Here the size
is small only where the geometry is small: near vertices that are close in the plane, across
narrow necks and in sharp wedges. The local feature size of a boundary point is its distance to
the boundary pieces that are far from it along the boundary (path longer than twice the
distance), the size field grows from it at ``growth`` per unit distance, and interior nodes come
from nested triangular lattices (spacing h / 2^j where the size field is in [h / 2^j, h / 2^(j-1))).
Every triangle is then split into three quadrilaterals, which the solid extrudes to hexahedra.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree
from skfem import MeshQuad, MeshTri

from ..member.geometry import Beam
from .law_mesh import station_lines
from .mesh import (
    CORNER_FLOOR,
    delaunay_with_outline,
    element_size,
    inner_half_width,
    mirrored_mesh,
    reentrant_vertices,
    refine_corners,
    segment_distance,
)

__all__ = ["feature_size_tri_mesh", "half_boundary", "size_field", "tri_to_quads",
           "planform_quad_mesh"]

# size-field growth per unit distance from a feature, and floor as a fraction of the thickness
# (in-plane elements much thinner than the plate gain the 3D solid nothing)
GROWTH = 0.5
FLOOR_THICKNESSES = 0.25

# the boundary path between two points must exceed this multiple of their distance for one to be
# a feature of the other (sharp corners below 60 degrees count, blunter ones do not)
_ARC_RATIO = 2.0


def half_boundary(beam: Beam) -> np.ndarray:
    """Return the vertices (2, m) of the closed upper half of the planform, m.

    Counter-clockwise from (0, 0): the axis, the tip edge, the outline from tip to root and the
    root edge.
    """
    L = beam.length_m
    x, w = beam.x_m, beam.half_width_m
    return np.hstack([[[0.0, L], [0.0, 0.0]], np.vstack([x[::-1], w[::-1]])])


def _samples(poly: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Return points on the closed polygon and their arc length from the first vertex.

    The points are its vertices, points at most ``spacing`` apart and points graded towards
    every vertex.
    """
    nxt = np.roll(poly, -1, axis=1)
    seg = np.linalg.norm(nxt - poly, axis=0)
    start = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    pts, arc = [], []
    for i in range(poly.shape[1]):
        n = max(1, int(np.ceil(seg[i] / spacing)))
        f = np.linspace(0.0, 1.0, n + 1)[:-1]
        # geometric grading towards both ends, so that wedges are detected near their apex
        g = 0.5 ** np.arange(1, 8)
        f = np.unique(np.concatenate([f, g, 1.0 - g]))
        pts.append(poly[:, i : i + 1] + (nxt - poly)[:, i : i + 1] * f)
        arc.append(start[i] + f * seg[i])
    return np.hstack(pts), np.concatenate(arc)


def _feature_sizes(poly: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Boundary points (2, s) and their local feature size (m)."""
    q, s = _samples(poly, spacing)
    perimeter = float(np.sum(np.linalg.norm(np.roll(poly, -1, axis=1) - poly, axis=0)))
    d = np.sqrt(((q[:, :, None] - q[:, None, :]) ** 2).sum(axis=0))
    path = np.abs(s[:, None] - s[None, :])
    path = np.minimum(path, perimeter - path)
    far = path > _ARC_RATIO * d
    lfs = np.where(far, d, np.inf).min(axis=1)
    # a boundary point needs an element no longer than the boundary piece it lies on
    nxt = np.roll(poly, -1, axis=1)
    seg = np.linalg.norm(nxt - poly, axis=0)
    at_vertex = np.concatenate([[seg[-1]], seg[:-1]])  # the shorter of the two incident pieces
    at_vertex = np.minimum(at_vertex, seg)
    dv = np.sqrt(((q[:, :, None] - poly[:, None, :]) ** 2).sum(axis=0))
    lfs = np.minimum(lfs, (at_vertex[None, :] + dv).min(axis=1))
    return q, lfs


def size_field(beam: Beam, h_m: float, growth: float = 0.5, floor_m: float = 0.0):
    """Return the element-size function s(points (2, n)) -> (n,) m of the feature mesh.

    ``s = min(h_m, min_q lfs(q) + growth |p - q|)`` over boundary points q, at least ``floor_m``
    (used by ``feature_size_tri_mesh``).
    """
    poly = half_boundary(beam)
    q, lfs = _feature_sizes(poly, h_m / 4.0)
    keep = lfs < h_m
    q, lfs = q[:, keep], lfs[keep]

    def s(p: np.ndarray) -> np.ndarray:
        p = np.atleast_2d(p)
        out = np.full(p.shape[1], float(h_m))
        for i in range(0, p.shape[1], 4096):
            c = p[:, i : i + 4096]
            d = np.sqrt(((c[:, :, None] - q[:, None, :]) ** 2).sum(axis=0))
            if d.size:
                out[i : i + 4096] = np.minimum(out[i : i + 4096],
                                               (lfs[None, :] + growth * d).min(axis=1))
        return np.maximum(out, floor_m)

    s.features = (q, lfs)
    s.growth = growth
    return s


def _boundary_points(poly: np.ndarray, size) -> np.ndarray:
    """Points on the closed polygon spaced by the size field, every vertex included."""
    out = []
    nxt = np.roll(poly, -1, axis=1)
    for i in range(poly.shape[1]):
        a, b = poly[:, i], nxt[:, i]
        length = float(np.linalg.norm(b - a))
        tt = np.linspace(0.0, 1.0, 201)
        inv = 1.0 / size(a[:, None] + (b - a)[:, None] * tt)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(tt))]) * length
        n = max(1, int(np.ceil(cum[-1] - 1e-9)))
        f = np.interp(np.linspace(0.0, cum[-1], n + 1)[:-1], cum, tt)
        out.append(a[:, None] + (b - a)[:, None] * f)
    return np.hstack(out)


def _lattice(h: float, boxes: np.ndarray) -> np.ndarray:
    """Return the points (2, n) of the triangular lattice of spacing h inside any box.

    Rows are parallel to the axis, the axis a row; the boxes (4, b) are x0, x1, y0, y1.
    """
    dy = h * np.sqrt(3.0) / 2.0
    pts = []
    for x0, x1, y0, y1 in boxes.T:
        rows = np.arange(max(1, int(np.floor(y0 / dy))), int(np.ceil(y1 / dy)) + 1)
        for j in rows:
            off = 0.5 * h * (j % 2)
            x = off + h * np.arange(int(np.floor((x0 - off) / h)), int(np.ceil((x1 - off) / h)) + 1)
            pts.append(np.vstack([x, np.full(x.size, j * dy)]))
    if not pts:
        return np.zeros((2, 0))
    p = np.hstack(pts)
    _, idx = np.unique(np.round(p.T / (1e-6 * h)).astype(np.int64), axis=0, return_index=True)
    return p[:, np.sort(idx)]


def _interior_points(beam: Beam, size, h: float, poly: np.ndarray) -> np.ndarray:
    L = beam.length_m
    ymax = float(np.max(beam.half_width_m))
    q, lfs = size.features
    kept: list[np.ndarray] = []
    levels: list[np.ndarray] = []
    for j in range(16):
        hj = h / 2**j
        if j == 0:
            boxes = np.array([[0.0], [L], [0.0], [ymax]])
        else:
            # the size field is below 2 h_j only within (2 h_j - lfs) / growth of a feature
            need = lfs < 2.0 * hj
            if not need.any():
                break
            r = (2.0 * hj - lfs[need]) / size.growth + hj
            boxes = np.vstack([q[0, need] - r, q[0, need] + r, q[1, need] - r, q[1, need] + r])
        c = _lattice(hj, boxes)
        c = c[:, (c[0] > 0.0) & (c[0] < L)]
        c = c[:, c[1] < inner_half_width(beam, c[0])]
        if not c.size:
            continue
        s = size(c)
        # the lattice of level j serves where the size field is in [h_j, 2 h_j)
        sel = (s >= hj * (1 - 1e-9)) & ((s < 2.0 * hj) | (j == 0))
        c, s = c[:, sel], s[sel]
        d = segment_distance(c, poly, np.roll(poly, -1, axis=1))
        c = c[:, d > 0.55 * s]
        kept.append(c)
        levels.append(np.full(c.shape[1], j))
    pts = np.hstack(kept) if kept else np.zeros((2, 0))
    lev = np.concatenate(levels) if levels else np.zeros(0, dtype=int)
    if not lev.size:
        return pts
    # drop a coarse point that has a finer-level point within 0.6 of its own spacing
    keep = np.ones(pts.shape[1], dtype=bool)
    tree = cKDTree(pts.T)
    for i in np.flatnonzero(lev < lev.max()):
        near = tree.query_ball_point(pts[:, i], r=0.6 * h / 2 ** lev[i])
        if any(lev[k] > lev[i] for k in near):
            keep[i] = False
    return pts[:, keep]


def feature_size_tri_mesh(beam: Beam, h_m: float, growth: float = 0.5,
                          floor_m: float = 0.0) -> MeshTri:
    """Build a triangle mesh of the planform with element size ``size_field``.

    The size is h_m where the geometry is wide; the mesh is mirror-symmetric about y = 0, every
    planform vertex a node (nodes in m).
    """
    size = size_field(beam, h_m, growth, floor_m)
    poly = half_boundary(beam)
    boundary = _boundary_points(poly, size)
    interior = _interior_points(beam, size, h_m, poly)
    # the upper outline (root to tip) must be made of mesh edges
    outline = _outline_polyline(beam, boundary)
    # a thickness law's stations: lines of mesh edges across the width (interior points and
    # axis points within half a size of one are dropped, or they would make slivers against it)
    lines = station_lines(beam, size, outline)
    for line in lines:
        xk = line[0, 0]
        near = np.abs(interior[0] - xk) < 0.5 * size(interior)
        interior = interior[:, ~near]
        axis = (boundary[1] == 0.0) & (boundary[0] != xk) & (boundary[0] > 0.0) & (
            boundary[0] < beam.length_m)
        boundary = boundary[:, ~(axis & (np.abs(boundary[0] - xk) < 0.5 * size(boundary)))]
    p_up, t_up = delaunay_with_outline(np.hstack([boundary, interior]), outline,
                                       np.empty((2, 0)), beam.length_m, lines)
    return _mirror_half(beam, p_up, t_up)


def _outline_polyline(beam: Beam, boundary: np.ndarray) -> np.ndarray:
    """Return the boundary points on the upper outline y = w(x), ordered from root to tip."""
    # distance to the outline's pieces, not |y - w(x)|: a width step's vertical piece is outline
    xy = np.vstack([beam.x_m, beam.half_width_m])
    on = segment_distance(boundary, xy[:, :-1], xy[:, 1:]) < 1e-9 * beam.length_m
    on &= boundary[1] > 0.0
    pts = boundary[:, on]
    # ordered along the outline: the boundary points come counter-clockwise (tip to root)
    return pts[:, ::-1]


def _mirror_half(beam: Beam, p_up: np.ndarray, t_up: np.ndarray) -> MeshTri:
    c = p_up[:, t_up].mean(axis=1)
    t_up = t_up[:, np.abs(c[1]) < inner_half_width(beam, c[0])]
    v = p_up[:, t_up]
    area = 0.5 * np.abs((v[0, 1] - v[0, 0]) * (v[1, 2] - v[1, 0])
                        - (v[0, 2] - v[0, 0]) * (v[1, 1] - v[1, 0]))
    # Qhull leaves zero-area triangles on straight runs of collinear hull points
    scale = float(np.sqrt(np.median(area)))
    flat = area < 1e-12 * scale**2
    t_up, area = t_up[:, ~flat], area[~flat]
    used = np.unique(t_up)
    remap = np.full(p_up.shape[1], -1)
    remap[used] = np.arange(used.size)
    return mirrored_mesh(beam, p_up[:, used], remap[t_up], area)


def tri_to_quads(mesh: MeshTri) -> MeshQuad:
    """Split every triangle into three quadrilaterals, counter-clockwise.

    Each is (vertex, edge midpoint, centroid, edge midpoint); shared edges get one midpoint, so
    the mesh is conforming.
    """
    p, t = mesh.p, mesh.t.copy()
    v = p[:, t]
    cw = ((v[0, 1] - v[0, 0]) * (v[1, 2] - v[1, 0])
          - (v[0, 2] - v[0, 0]) * (v[1, 1] - v[1, 0])) < 0.0
    t[1, cw], t[2, cw] = t[2, cw], t[1, cw].copy()
    tri = MeshTri(p, t)
    n, nf = p.shape[1], tri.facets.shape[1]
    points = np.hstack([p, p[:, tri.facets].mean(axis=1), p[:, tri.t].mean(axis=1)])
    e01, e12, e02 = tri.t2f + n  # scikit-fem's facet order for triangles: 01, 12, 02
    c = n + nf + np.arange(t.shape[1])
    t0, t1, t2 = tri.t
    quads = np.hstack([np.vstack([t0, e01, c, e02]), np.vstack([t1, e12, c, e01]),
                       np.vstack([t2, e02, c, e12])])
    return MeshQuad(np.ascontiguousarray(points), np.ascontiguousarray(quads))


def planform_quad_mesh(beam: Beam, level: int = 2, corner_passes: int = 2,
                       root_size_m: float | None = None) -> MeshQuad:
    """Quadrilateral mesh of the planform for the solid, mirror-symmetric about y = 0 (nodes in m).

    The triangles of ``feature_size_tri_mesh`` (size 2 L / (10 2^level) where the planform is
    wide, floored at a quarter of the thickness) are refined at the re-entrant and clamped-free
    root corners to 2^-corner_passes of the local size and, with ``root_size_m``, along the
    clamp x = 0 until no deeper than that (the clamp blocks the root's Poisson contraction, an
    edge singularity of 3D elasticity); each is then split into three quadrilaterals of about
    L / (10 2^level). The quadrilaterals inherit the triangles' shape: a mapped mesh
    y = eta w(x) sheared its elements along steep outline pieces (3.5 degree corners, aspect
    ratio 72 on ``reference-random.json``), which stiffened the solid by up to 5 %.
    """
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or level < 0:
        raise ValueError(f"level = {level!r}: must be an integer >= 0")
    h = 2.0 * element_size(beam, level)
    # the thinnest section sets the floor (a thickness law's; the thickness when uniform)
    t_min = float(np.min(beam.thickness_at(beam.x_m)))
    size = size_field(beam, h, GROWTH, FLOOR_THICKNESSES * t_min)
    tri = feature_size_tri_mesh(beam, h, GROWTH, FLOOR_THICKNESSES * t_min)
    w0 = beam.half_width_m[0]
    corners = np.hstack([reentrant_vertices(beam), [[0.0, 0.0], [w0, -w0]]])
    local = size(np.vstack([corners[0], np.abs(corners[1])]))  # the field is of the upper half
    target = 1.01 * np.maximum(local, CORNER_FLOOR * h) * 0.5**corner_passes
    tri = refine_corners(tri, corners, target)
    for _ in range(0 if root_size_m is None else 20):
        v = tri.p[:, tri.t]
        on_root = np.isclose(v[0], 0.0, atol=1e-12 * beam.length_m).sum(axis=0) >= 2
        marked = np.flatnonzero(on_root & (np.ptp(v[0], axis=0) > root_size_m))
        if not marked.size:
            break
        tri = tri.refined(marked)
    return tri_to_quads(tri)
