"""Each link's solid as a closed, outward-oriented triangle mesh, in the link's own frame.

A planform link is the slice of the member between its start and end stations: the polygon
|y| <= w(x) (width steps included) extruded to |z| <= t(x) / 2 (uniform thickness or the
thickness law). Between two stations w and t are linear, so every face is planar: the top and
bottom faces lie on z = +-t(x)/2 (a plane over each interval), the sides on y = +-w(x), the
caps and the step faces on x = const. The mesh is therefore the solid itself, not an
approximation: its volume is the integral of 2 w t over the span, and volume times density is
the link's mass of :mod:`prbdm_pin.chain.sections` to rounding (as is its centroid the link's
centre of mass).

A round link (:func:`round_link_mesh`) is the frustum or tube between diameters (D0, d0) at its
start and (D1, d1) at its end: a regular polygon whose circumradius is scaled so its area is the
circle's (pi r^2 at every station, since r is linear in x), so the mesh's volume and centroid
are the circular frustum's exactly, whatever the number of sides.

Vertices are in m, in the link frame: origin at the link's start (its joint), x along the
undeformed beam, y across, z through the thickness.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam
from ..options.checks import check_float, check_int
from ..options.validate import check_type

__all__ = ["LinkMesh", "planform_link_mesh", "round_link_mesh", "ROUND_SEGMENTS"]

# sides of a round section's polygon: a visual choice only (volume and centroid are exact at
# any count)
ROUND_SEGMENTS = 48


@dataclass(frozen=True, eq=False)
class LinkMesh:
    """A closed triangle mesh of one link's solid.

    Attributes
    ----------
    vertices_m : ndarray, shape (v, 3)
        Vertex coordinates in the link frame, m.
    faces : ndarray of int, shape (f, 3)
        Vertex indices of each triangle, counter-clockwise seen from outside.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> mesh = pp.planform_link_mesh(beam, 0.2, 0.7)
    >>> isinstance(mesh, pp.LinkMesh), mesh.vertices_m.shape[1], mesh.faces.shape[1]
    (True, 3, 3)
    >>> edges = np.sort(mesh.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    >>> bool(np.all(np.unique(edges, axis=0, return_counts=True)[1] == 2))  # closed: 2 per edge
    True
    >>> mesh.vertices_m.min(axis=0), mesh.vertices_m.max(axis=0)  # m: the link frame's box
    (array([ 0.   , -0.025, -0.005]), array([0.5  , 0.025, 0.005]))
    """

    vertices_m: np.ndarray
    faces: np.ndarray

    @property
    def volume_m3(self) -> float:
        """Enclosed volume, m^3 (divergence theorem over the triangles)."""
        v = self.vertices_m[self.faces]
        return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)


class _Builder:
    """Collects triangles, sharing a vertex wherever two faces give the same coordinates."""

    def __init__(self) -> None:
        self.index: dict[tuple[float, float, float], int] = {}
        self.faces: list[tuple[int, int, int]] = []

    def vertex(self, p) -> int:
        key = (float(p[0]), float(p[1]), float(p[2]))
        return self.index.setdefault(key, len(self.index))

    def triangle(self, a, b, c, outward) -> None:
        """Triangle a, b, c wound so that its normal points along ``outward``."""
        pa, pb, pc = (np.asarray(p, dtype=float) for p in (a, b, c))
        n = np.cross(pb - pa, pc - pa)
        if not np.any(n):
            return  # a zero-area triangle (two equal points) adds nothing
        if float(np.dot(n, outward)) < 0.0:
            pb, pc = pc, pb
        self.faces.append((self.vertex(pa), self.vertex(pb), self.vertex(pc)))

    def mesh(self) -> LinkMesh:
        v = np.array(list(self.index), dtype=float)
        f = np.array(self.faces, dtype=np.int64)
        v.setflags(write=False)
        f.setflags(write=False)
        return LinkMesh(vertices_m=v, faces=f)


def _zipper(b: _Builder, left: list, right: list, outward) -> None:
    """Triangulate the planar strip between two parallel chains of points sorted along them.

    No triangle has zero area: each has points on both chains.
    """
    i = j = 0
    while i < len(left) - 1 or j < len(right) - 1:
        if j == len(right) - 1 or (i < len(left) - 1 and left[i + 1][1] <= right[j + 1][1]):
            b.triangle(left[i], right[j], left[i + 1], outward)
            i += 1
        else:
            b.triangle(left[i], right[j], right[j + 1], outward)
            j += 1


def planform_link_mesh(beam, start_m: float, end_m: float) -> LinkMesh:
    """Mesh of the member's slice between ``start_m`` and ``end_m``, in that link's frame.

    Parameters
    ----------
    beam : Beam
        The planform w(x) (width steps included) and the thickness, uniform or t(x).
    start_m, end_m : float
        The link's span along the beam, m, 0 <= start < end <= L.

    Returns
    -------
    LinkMesh
        Closed and outward-oriented; vertices relative to (start_m, 0, 0).

    Raises
    ------
    BeamInputError
        A span outside [0, L] or of no length.
    InputTypeError
        ``beam`` not a Beam, a station not a real number.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.05, 0.025], thickness_m=0.01)  # a taper
    >>> mesh = pp.planform_link_mesh(beam, 0.2, 0.7)  # m
    >>> v = mesh.vertices_m[mesh.faces]
    >>> V = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6  # m^3
    >>> b0, b1 = 2 * (0.05 - 0.025 * 0.2), 2 * (0.05 - 0.025 * 0.7)  # m, the widths at the ends
    >>> round(float(V) * 1e6, 4), round((b0 + b1) / 2 * 0.5 * 0.01 * 1e6, 4)  # cm^3: a trapezoid
    (387.5, 387.5)
    """
    check_type("beam", beam, Beam)
    a = check_float("start_m", start_m, unit="m")
    e = check_float("end_m", end_m, unit="m")
    if not (0.0 <= a < e <= beam.length_m):
        raise BeamInputError(f"span = [{start_m!r}, {end_m!r}] m: needs 0 <= start < end <= "
                             f"L = {beam.length_m!r} m")
    x = beam.x_m
    inner = x[(x > a) & (x < e)]
    # the profile along the span: (x, w, t) per station; a width step inside gives two rows
    rows = [(a, float(beam.half_width_at(a, "right")))]
    for xs in np.unique(inner):
        wl, wr = float(beam.half_width_at(xs, "left")), float(beam.half_width_at(xs, "right"))
        rows += [(float(xs), wl)] + ([(float(xs), wr)] if wr != wl else [])
    rows.append((e, float(beam.half_width_at(e, "left"))))
    b = _Builder()

    def h(xv: float) -> float:  # half the thickness at xv
        return 0.5 * float(beam.thickness_at(xv))

    for k in range(len(rows) - 1):
        (x0, w0), (x1, w1) = rows[k], rows[k + 1]
        if x0 == x1:  # a width step: the faces on x = x0 between the two widths, both sides
            out = np.array([1.0 if w0 > w1 else -1.0, 0.0, 0.0])
            hz, lo, hi = h(x0), min(w0, w1), max(w0, w1)
            for s in (1.0, -1.0):
                b.triangle((x0, s * lo, -hz), (x0, s * hi, -hz), (x0, s * hi, hz), out)
                b.triangle((x0, s * lo, -hz), (x0, s * hi, hz), (x0, s * lo, hz), out)
            continue
        h0, h1 = h(x0), h(x1)
        # the top and bottom faces: the chains on x0 and x1 carry the other side's width
        # where a step meets them, so their edges match the step faces' (no T-junctions)
        ys0 = _edge_ys(rows, k, w0, before=True)
        ys1 = _edge_ys(rows, k + 1, w1, before=False)
        for s in (1.0, -1.0):
            left = [(x0, y, s * h0) for y in ys0]
            right = [(x1, y, s * h1) for y in ys1]
            _zipper(b, [(p[0], p[1], p[2]) for p in left], [(p[0], p[1], p[2]) for p in right],
                    np.array([0.0, 0.0, s]))
        for s in (1.0, -1.0):  # the sides y = +-w(x)
            out = np.array([0.0, s, 0.0])
            b.triangle((x0, s * w0, -h0), (x1, s * w1, -h1), (x1, s * w1, h1), out)
            b.triangle((x0, s * w0, -h0), (x1, s * w1, h1), (x0, s * w0, h0), out)
    for (xc, wc), sx in ((rows[0], -1.0), (rows[-1], 1.0)):  # the end caps
        hz, out = h(xc), np.array([sx, 0.0, 0.0])
        b.triangle((xc, -wc, -hz), (xc, wc, -hz), (xc, wc, hz), out)
        b.triangle((xc, -wc, -hz), (xc, wc, hz), (xc, -wc, hz), out)
    m = b.mesh()
    v = np.array(m.vertices_m)
    v[:, 0] -= a
    v.setflags(write=False)
    return LinkMesh(vertices_m=v, faces=m.faces)


def _edge_ys(rows: list, k: int, w: float, before: bool) -> list[float]:
    """Return the sorted y values along the top face's edge at row k.

    They are +-w, and +-the other width of a step there (the one on the far side of the step).
    """
    ys = {-w, w}
    other = k - 1 if before else k + 1
    if 0 <= other < len(rows) and rows[other][0] == rows[k][0]:
        wo = rows[other][1]
        if wo < w:  # a narrower step face meets this edge inside it
            ys |= {-wo, wo}
    return sorted(ys)


def round_link_mesh(length_m: float, D0_m: float, D1_m: float, d0_m: float = 0.0,
                    d1_m: float = 0.0, segments: int = ROUND_SEGMENTS) -> LinkMesh:
    """Mesh of a round link: a frustum (solid) or tube along x from 0 to ``length_m``.

    Parameters
    ----------
    length_m : float
        The link's length, m (> 0).
    D0_m, D1_m : float
        Outer diameters at the link's start and end, m (> 0).
    d0_m, d1_m : float
        Inner diameters there, m (0: solid at that end; 0 <= d < D).
    segments : int
        Sides of the polygon (>= 3); its circumradius is r sqrt(2 pi / (N sin(2 pi / N))), so
        its area is pi r^2 and the mesh's volume and centroid are the circular solid's exactly.

    Returns
    -------
    LinkMesh
        Closed and outward-oriented, in the link frame (start at the origin).

    Raises
    ------
    BeamInputError
        A length or diameter that is not finite, D <= 0, d < 0 or d >= D, segments < 3.
    InputTypeError
        A size that is not a real number, ``segments`` not an integer.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> def volume(mesh):  # m^3: the divergence theorem over the triangles
    ...     v = mesh.vertices_m[mesh.faces]
    ...     return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6)
    >>> cone = pp.round_link_mesh(0.5, 0.03, 0.02)  # m: a solid frustum
    >>> L, D0, D1 = 0.5, 0.03, 0.02  # m
    >>> V_frustum = np.pi * L / 12 * (D0**2 + D0 * D1 + D1**2)  # m^3
    >>> round(volume(cone) * 1e6, 4), round(V_frustum * 1e6, 4)  # cm^3
    (248.7094, 248.7094)
    >>> tube = pp.round_link_mesh(0.5, 0.02, 0.02, 0.016, 0.016, segments=12)
    >>> round(volume(tube) * 1e6, 4), round(np.pi / 4 * (0.02**2 - 0.016**2) * 0.5 * 1e6, 4)  # cm^3
    (56.5487, 56.5487)
    """
    length_m = check_float("length_m", length_m, low=0.0, low_open=True, unit="m")
    D0_m = check_float("D0_m", D0_m, low=0.0, low_open=True, unit="m")
    D1_m = check_float("D1_m", D1_m, low=0.0, low_open=True, unit="m")
    # an inner diameter equal to the outer one would leave a wall of no thickness
    d0_m = check_float("d0_m", d0_m, low=0.0, high=D0_m, high_open=True, unit="m")
    d1_m = check_float("d1_m", d1_m, low=0.0, high=D1_m, high_open=True, unit="m")
    segments = check_int("segments", segments, 3)
    return round_profile_mesh(np.array([0.0, length_m]), np.array([D0_m, D1_m]),
                              np.array([d0_m, d1_m]), segments)


def round_profile_mesh(x_m: np.ndarray, D_m: np.ndarray, d_m: np.ndarray,
                       segments: int = ROUND_SEGMENTS) -> LinkMesh:
    """Mesh of a round solid whose diameters are linear between stations ``x_m`` (checked).

    One closed surface through rings at every station (outer along x, then inner back), so a
    link spanning a station of its member's diameter laws is one watertight solid; volume and
    centroid are the circular solid's exactly (see :func:`round_link_mesh`).
    """
    scale = math.sqrt(2.0 * math.pi / (segments * math.sin(2.0 * math.pi / segments)))
    phi = 2.0 * math.pi * np.arange(segments) / segments
    cs = np.column_stack([np.cos(phi), np.sin(phi)])

    def ring(xv: float, d: float) -> list:
        r = 0.5 * d * scale
        if r == 0.0:
            return [(xv, 0.0, 0.0)] * segments  # a point: its triangles collapse and drop out
        return [(xv, float(r * c), float(r * s)) for c, s in cs]

    b = _Builder()
    xs = [float(v) for v in x_m]
    # the closed loop of rings: outer start -> ... -> outer end -> inner end -> ... -> back
    loop = ([ring(xv, float(D)) for xv, D in zip(xs, D_m, strict=True)]
            + [ring(xv, float(d)) for xv, d in zip(xs[::-1], d_m[::-1], strict=True)])
    tris = []
    for A, B in zip(loop, loop[1:] + loop[:1], strict=True):
        for i in range(segments):
            i1 = (i + 1) % segments
            tris += [(A[i], B[i], B[i1]), (A[i], B[i1], A[i1])]
    # wound consistently around the loop; the sign of the volume says whether outward
    for t in tris:
        b.triangle(*t, outward=np.cross(np.subtract(t[1], t[0]), np.subtract(t[2], t[0])))
    m = b.mesh()
    if m.volume_m3 < 0.0:
        m = LinkMesh(vertices_m=m.vertices_m, faces=np.ascontiguousarray(m.faces[:, ::-1]))
    return m
