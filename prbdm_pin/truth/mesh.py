"""The plate's triangle mesh of a planform, which follows its vertices exactly.

Nodes sit on columns at x stations that include every planform vertex, so the piecewise-linear
outline is represented exactly. Random planforms can have vertices a few millimetres apart; a plain
mapped mesh would then put a sliver next to a large element, so the x stations are graded: the
local element size grows from a short vertex interval at most by the factor ``growth`` per element
length. (The 3D solid uses a mesh graded in two dimensions instead: ``feature_mesh``.)
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay
from skfem import MeshTri

from ..member.geometry import Beam
from .law_mesh import station_lines

# elements touching a re-entrant corner are refined to h / 2**CORNER_PASSES (h the level's base
# element size); measured with scripts/bench_truth.py
CORNER_PASSES = 4
# element size at most NARROW_ELEMENTS x the half-width at a narrow vertex
NARROW_ELEMENTS = 0.5
CORNER_FLOOR = 0.25

__all__ = [
    "CORNER_PASSES",
    "refine_corners",
    "segment_distance",
    "reentrant_vertices",
    "element_size",
    "x_stations",
    "station_count",
    "planform_tri_mesh",
    "inner_half_width",
    "mirrored_mesh",
    "mirror_nodes",
]


def element_size(beam: Beam, level: int, base_elements: int = 10) -> float:
    """Target in-plane element size in m at refinement ``level`` (halves with each level)."""
    if level < 0:
        raise ValueError(f"level = {level}: must be >= 0")
    return beam.length_m / (base_elements * 2**level)


def x_stations(
    beam: Beam, h_m: float, growth: float = 0.3, narrow: bool = False
) -> np.ndarray:
    """Graded x stations (m) that contain every planform vertex.

    The size field is s(x) = min(h, min_k(l_k + growth * dist(x, interval_k))) over vertex
    intervals of length l_k < h, so elements next to a short interval are small and grow gently.
    With ``narrow`` it is also at most ``c w_k + growth * |x - x_k|`` at every vertex of half-width
    w_k < h / c (c = ``NARROW_ELEMENTS``), so a narrow neck gets two elements across its
    half-width instead of slivers.
    """
    out = [beam.x_m[:1]]
    for xs, cum, n in _interval_counts(beam, h_m, growth, narrow):
        targets = np.linspace(0.0, cum[-1], n + 1)
        out.append(np.interp(targets, cum, xs)[1:])
    x = np.concatenate(out)
    x[-1] = beam.x_m[-1]
    return x


def _interval_counts(beam: Beam, h_m: float, growth: float, narrow: bool):
    """Return, for every vertex interval, sample points and element counts.

    Sample points (m), the cumulative element count along them (the integral of 1 / size) and
    the number of elements ``x_stations`` puts there.
    """
    starts, ends = beam.intervals_m  # a width step is one station
    for a, b in zip(starts, ends, strict=True):
        xs = np.linspace(a, b, 201)
        inv = 1.0 / local_size(beam, h_m, growth, xs, narrow)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(xs))])
        yield xs, cum, max(1, int(np.ceil(cum[-1] - 1e-9)))


def station_count(beam: Beam, h_m: float, growth: float = 0.3, narrow: bool = False) -> int:
    """Return the number of ``x_stations`` (computed without building them)."""
    return 1 + sum(n for _, _, n in _interval_counts(beam, h_m, growth, narrow))


def local_size(
    beam: Beam, h_m: float, growth: float, x: np.ndarray, narrow: bool = False
) -> np.ndarray:
    """Return the size field of ``x_stations`` evaluated at ``x`` (m)."""
    xv = beam.x_m
    lengths = np.diff(xv)
    x = np.asarray(x, dtype=float)
    s = np.full_like(x, h_m)
    for k in np.flatnonzero((lengths < h_m) & (lengths > 0.0)):
        d = np.maximum(0.0, np.maximum(xv[k] - x, x - xv[k + 1]))
        s = np.minimum(s, lengths[k] + growth * d)
    # a width step is an outline piece across the span, of length |w_(k+1) - w_k|: as short
    # as a vertex interval of that length
    for k in beam.step_index:
        jump = abs(float(beam.half_width_m[k + 1] - beam.half_width_m[k]))
        if jump < h_m:
            s = np.minimum(s, jump + growth * np.abs(x - xv[k]))
    if narrow:
        wv = beam.half_width_m
        for k in np.flatnonzero(NARROW_ELEMENTS * wv < h_m):
            s = np.minimum(s, NARROW_ELEMENTS * wv[k] + growth * np.abs(x - xv[k]))
    return s


def _upper_outline(beam: Beam, xs: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Return the points (2, b) on the upper outline y = w(x).

    A column's top at every station plus extra points on steep pieces so that boundary spacing
    follows the local size. A width step
    is a vertical piece at its station, from the root-side to the tip-side half-width.
    """
    wl = beam.half_width_at(xs, "left")
    wr = beam.half_width_at(xs, "right")
    # the outline's corners: two at a step's station, one elsewhere
    px, py, ps = [], [], []
    for x, a, b, s in zip(xs, wl, wr, sizes, strict=True):
        for y in ((a, b) if a != b else (b,)):
            px.append(x)
            py.append(y)
            ps.append(s)
    out = []
    for i in range(len(px) - 1):
        a = np.array([px[i], py[i]])
        b = np.array([px[i + 1], py[i + 1]])
        s = min(ps[i], ps[i + 1])
        n = max(1, int(round(np.linalg.norm(b - a) / s)))
        tt = np.linspace(0.0, 1.0, n + 1)[:-1]
        out.append(a[:, None] + (b - a)[:, None] * tt)
    out.append(np.array([[px[-1]], [py[-1]]]))
    return np.hstack(out)


def segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (m) from points p (2, n) to the polyline through a -> b pieces (2, m) each."""
    d = b - a
    ap = p[:, :, None] - a[:, None, :]
    tt = np.clip(np.einsum("inm,im->nm", ap, d) / np.maximum(np.einsum("im,im->m", d, d), 1e-300),
                 0.0, 1.0)
    q = a[:, None, :] + d[:, None, :] * tt[None]
    return np.sqrt(((p[:, :, None] - q) ** 2).sum(axis=0)).min(axis=1)


def _missing_edges(p: np.ndarray, t: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """Return the indices i of outline pieces (outline[:, i], [:, i + 1]) not mesh edges."""
    scale = 1e-9 * max(float(np.ptp(p[0])), float(np.ptp(p[1])))
    key = {tuple(k): i for i, k in enumerate(np.round(p.T / scale).astype(np.int64))}
    ids = np.array([key[tuple(k)] for k in np.round(outline.T / scale).astype(np.int64)])
    edges = np.sort(np.hstack([t[[0, 1]], t[[1, 2]], t[[0, 2]]]), axis=0)
    have = set(map(tuple, edges.T))
    pieces = np.sort(np.vstack([ids[:-1], ids[1:]]), axis=0)
    return np.array([i for i, e in enumerate(map(tuple, pieces.T)) if e not in have], dtype=int)


def delaunay_with_outline(
    before: np.ndarray, outline: np.ndarray, after: np.ndarray, length_m: float,
    lines: tuple[np.ndarray, ...] = (),
) -> tuple[np.ndarray, np.ndarray]:
    """Triangulate the points so that every piece of the polyline ``outline`` is a mesh edge.

    A Delaunay triangulation of the points ``before``, ``outline``, ``after`` (each (2, k), m;
    duplicates within 1e-9 ``length_m`` merged, first kept). Returns nodes (2, N) and triangles
    (3, M). Every piece of each polyline of ``lines`` (each (2, k), m) is made a mesh edge too
    (the thickness law's station lines: no element straddles one).

    The outline of a concave planform is not always made of Delaunay edges: the missing pieces
    are split and the points triangulated again (boundary recovery by refinement).
    """
    polylines = [outline, *lines]
    for _ in range(20):
        p = np.hstack([before, *polylines, after])
        _, idx = np.unique(np.round(p.T / (1e-9 * length_m)), axis=0, return_index=True)
        p = p[:, np.sort(idx)]
        t = Delaunay(p.T).simplices.T
        done = True
        for i, line in enumerate(polylines):
            missing = _missing_edges(p, t, line)
            if missing.size:
                done = False
                mid = 0.5 * (line[:, missing] + line[:, missing + 1])
                polylines[i] = np.insert(line, missing + 1, mid, axis=1)
        if done:
            break
    return p, t


def inner_half_width(beam: Beam, x_m: np.ndarray) -> np.ndarray:
    """Return the smaller of the two one-sided half-widths at ``x_m`` (m).

    A point (x, y) with ``|y|`` below it is inside the planform; at a step's station the points
    between the two are on its outline.
    """
    return np.minimum(beam.half_width_at(x_m, "left"), beam.half_width_at(x_m, "right"))


def reentrant_vertices(beam: Beam, min_turn_rad: float = np.radians(5.0)) -> np.ndarray:
    """Return the re-entrant corners: planform vertices (2, r), m.

    Vertices of the upper outline (and their mirror images) where the interior angle exceeds
    pi + ``min_turn_rad``: plate bending moments are singular there and uniform refinement
    converges slowly.
    """
    x, w = beam.x_m, beam.half_width_m
    direction = np.arctan2(np.diff(w), np.diff(x))
    # walking the upper outline root -> tip the plate lies on the right: a left turn is re-entrant
    k = 1 + np.flatnonzero(np.diff(direction) > min_turn_rad)
    return np.hstack([np.vstack([x[k], w[k]]), np.vstack([x[k], -w[k]])])


def refine_corners(mesh: MeshTri, corners: np.ndarray, target_m: np.ndarray) -> MeshTri:
    """Refine the elements touching a corner until they are no longer than its ``target_m``.

    Red-green-blue, conforming: a geometric grading towards each corner (sizes double
    outwards).
    """
    if not corners.size:
        return mesh
    tol = 1e-9 * float(np.ptp(mesh.p[0]))
    for _ in range(40):
        dist = np.sqrt(((mesh.p[:, :, None] - corners[:, None, :]) ** 2).sum(axis=0))
        # the size target of the corner a node sits on (inf for nodes on no corner)
        node_target = np.where(dist < tol, target_m[None, :], np.inf).min(axis=1)
        v = mesh.p[:, mesh.t]
        diam = np.max([np.linalg.norm(v[:, a] - v[:, b], axis=0)
                       for a, b in ((0, 1), (1, 2), (0, 2))], axis=0)
        marked = np.flatnonzero(diam > node_target[mesh.t].min(axis=0))
        if not marked.size:
            break
        mesh = mesh.refined(marked)
    return mesh


def planform_tri_mesh(
    beam: Beam, level: int = 1, growth: float = 0.3, corner_passes: int = CORNER_PASSES
) -> MeshTri:
    """Graded triangle mesh of the planform, mirror-symmetric about y = 0 (nodes in m).

    Nodes sit on columns at the graded ``x_stations`` (every planform vertex is a column, so the
    outline is exact), spaced across the half-width at about the local element size, plus extra
    nodes along steep outline pieces; interior nodes too close to the outline are dropped and the
    upper half is Delaunay-triangulated (scipy) and mirrored. A short vertex interval, a narrow
    section or a steep step of the outline then gets small, well-shaped triangles instead of the
    slivers of a mapped mesh. The axis y = 0 is a mesh line and symmetric modes stay symmetric.
    A narrow neck gets two elements across its half-width, and the elements touching a
    re-entrant corner of the outline are refined until no longer than s / 2**corner_passes
    (s the local element size of the x stations)
    (geometric grading towards the bending-moment singularity there, which otherwise dominates
    the error and slows uniform convergence to about O(h) in the frequencies).
    Level ``k > 0`` is the level-0 mesh uniformly refined ``k`` times (nested meshes).
    """
    if level < 0:
        raise ValueError(f"level = {level}: must be >= 0")
    h = element_size(beam, 0)
    # the clamped-free root corners are singular too (strongly so when the outline flares out
    # from a narrow root)
    w0 = beam.half_width_m[0]
    corners = np.hstack([reentrant_vertices(beam), [[0.0, 0.0], [w0, -w0]]])
    # relative to the local size: a corner at a narrow neck is refined further than a wide one
    # (floored at h / 2**(corner_passes + 2): tinier elements buy little accuracy and cost
    # eigensolver precision, which degrades like the inverse fourth power of the smallest size)
    target = 1.01 * np.maximum(local_size(beam, h, growth, corners[0], narrow=True),
                               CORNER_FLOOR * h) * 0.5**corner_passes
    mesh = refine_corners(_base_tri_mesh(beam, h, growth), corners, target)
    # uniform refinement of the base mesh: nested meshes, so the conforming Argyris frequencies
    # decrease monotonically with the level
    return mesh.refined(level) if level > 0 else mesh


def _base_tri_mesh(beam: Beam, h: float, growth: float) -> MeshTri:
    xs = x_stations(beam, h, growth, narrow=True)
    sizes = local_size(beam, h, growth, xs, narrow=True)
    gaps = np.diff(xs)
    near = np.minimum(np.concatenate([gaps, gaps[-1:]]), np.concatenate([gaps[:1], gaps]))
    sizes = np.minimum(sizes, np.maximum(near, 0.5 * sizes))
    # at a step's station the column stops at the narrower side (the rest is outline)
    w = np.minimum(beam.half_width_at(xs, "left"), beam.half_width_at(xs, "right"))
    outline = _upper_outline(beam, xs, sizes)
    col_pts = []
    for x, wi, s in zip(xs, w, sizes, strict=True):
        n = max(1, int(np.ceil(wi / s - 0.25)))
        y = np.linspace(0.0, wi, n + 1)[:-1]
        col_pts.append(np.vstack([np.full(y.size, x), y]))
    cp = np.hstack(col_pts)
    # the clamp edge x = 0, the tip edge x = L and the axis y = 0 lie on the convex hull
    edge_col = (cp[0] == xs[0]) | (cp[0] == xs[-1]) | (cp[1] == 0.0)
    s_at = np.interp(cp[0], xs, sizes)
    keep = edge_col | (segment_distance(cp, outline[:, :-1], outline[:, 1:]) > 0.55 * s_at)
    interior = cp[:, keep]
    lines = station_lines(beam, lambda p: np.interp(p[0], xs, sizes), outline)
    p_up, t_up = delaunay_with_outline(np.empty((2, 0)), outline, interior, beam.length_m, lines)
    c = p_up[:, t_up].mean(axis=1)
    t_up = t_up[:, np.abs(c[1]) < inner_half_width(beam, c[0])]
    area = 0.5 * np.abs(
        (p_up[0, t_up[1]] - p_up[0, t_up[0]]) * (p_up[1, t_up[2]] - p_up[1, t_up[0]])
        - (p_up[0, t_up[2]] - p_up[0, t_up[0]]) * (p_up[1, t_up[1]] - p_up[1, t_up[0]])
    )
    # Qhull leaves zero-area triangles on straight runs of collinear hull points
    flat = area < 1e-9 * float(np.min(sizes)) ** 2
    t_up, area = t_up[:, ~flat], area[~flat]
    return mirrored_mesh(beam, p_up, t_up, area)


def mirrored_mesh(beam: Beam, p_up: np.ndarray, t_up: np.ndarray, area: np.ndarray) -> MeshTri:
    """Mirror the upper-half mesh about the axis y = 0 into the full planform mesh.

    The half mesh has triangles ``t_up`` (3, k), nodes ``p_up`` ((2, N), m) and triangle areas
    ``area`` (m^2); the axis must carry nodes of both halves.

    Raises RuntimeError when the half mesh does not tile the half planform (1e-9 relative).
    """
    if abs(2.0 * area.sum() - beam.planform_area_m2) > 1e-9 * beam.planform_area_m2:
        raise RuntimeError(
            f"planform mesh of {beam.name!r} does not cover the planform "
            f"({2.0 * area.sum():.9g} vs {beam.planform_area_m2:.9g} m^2)"
        )
    px, py = p_up
    n_up = px.size
    on_axis = py == 0.0
    mirror = np.empty(n_up, dtype=np.int64)
    off = np.flatnonzero(~on_axis)
    mirror[off] = n_up + np.arange(off.size)
    mirror[on_axis] = np.flatnonzero(on_axis)
    p = np.vstack([np.concatenate([px, px[off]]), np.concatenate([py, -py[off]])])
    t = np.hstack([t_up, mirror[t_up]])
    return MeshTri(np.ascontiguousarray(p), np.ascontiguousarray(t))


def mirror_nodes(mesh: MeshTri, tol_m: float = 1e-9) -> np.ndarray:
    """For every node the index of its mirror image about y = 0 (raises if there is none)."""
    p = mesh.p
    key = np.round(p.T / tol_m).astype(np.int64)
    lookup = {tuple(k): i for i, k in enumerate(key)}
    out = np.empty(p.shape[1], dtype=np.int64)
    for i, (kx, ky) in enumerate(key):
        j = lookup.get((kx, -ky))
        if j is None:
            raise ValueError(f"node {i} at {p[:, i]} has no mirror image")
        out[i] = j
    return out
