"""Structured mapped mesh of a round tube or rod: 27-node hexahedra with curved faces.

A parametric grid (x, a, b) of the member is mapped to space: for a tube, a = rho in [0, 1] from
the inner to the outer wall and b = theta around the axis, r = d(x) / 2 + rho (D(x) - d(x)) / 2;
for a solid rod, an O-grid of the disc: (a, b) = (u, v) in [-1, 1]^2, a core square mapped
linearly and the ring around it blended from the square to the circle of radius D(x) / 2 (a
polar grid would collapse its elements onto the axis). Every node of the quadratic elements,
edge, face and centre nodes too, is the image of its parametric point, so the faces r = d / 2
and r = D / 2 are curved (the element geometry is the quadratic isoparametric one: an error of
O(h^3) in position where linear elements inscribe a polygon, 0.6 % of the area at 32 sides).
Element edges sit on every station of x_m, so D(x) and d(x) are linear in each element.

A mapped mesh and not a mesh generator (gmsh): the tube is a tensor-product domain, the
structured grid is exactly mirror and 90-degree symmetric (the two bending planes are then
degenerate to rounding, which the mode labelling relies on), and it needs no new dependency.
"""

from __future__ import annotations

import numpy as np
from skfem import ElementHex1, ElementHex2, MeshHex, MeshHex2
from skfem.assembly import Dofs

__all__ = ["along_stations", "rod_section_point", "tube_hex_mesh"]


def along_stations(x_m: np.ndarray, n_along: int) -> np.ndarray:
    """Element edges along x (m): every station plus about ``n_along`` elements in all.

    The elements are shared out in proportion to the station intervals' lengths (at least one
    per interval).
    """
    L = float(x_m[-1] - x_m[0])
    out = [x_m[:1]]
    for a, b in zip(x_m[:-1], x_m[1:], strict=True):
        n = max(1, int(round(n_along * (b - a) / L)))
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def rod_section_point(u: np.ndarray, v: np.ndarray, core: float) -> tuple[np.ndarray, np.ndarray]:
    """Map the square (u, v) in [-1, 1]^2 to the unit disc (O-grid), dimensionless.

    Inside max(|u|, |v|) <= ``core`` the square is scaled linearly to a core square of half-side
    ``core``; outside, the point on that square's boundary (same direction) is blended linearly
    in max(|u|, |v|) with the point of the unit circle at the angle that grows linearly along
    each side of the square.
    """
    m = np.maximum(np.abs(u), np.abs(v))
    safe = np.where(m > 0.0, m, 1.0)
    # angle on the circle: linear in the position along the square side the point projects to
    right = np.abs(u) >= np.abs(v)
    phi = np.where(right, np.pi / 4.0 * v / safe, np.pi / 2.0 - np.pi / 4.0 * u / safe)
    phi = np.where(right & (u < 0.0), np.pi - phi, phi)
    phi = np.where(~right & (v < 0.0), -phi, phi)
    rho = np.clip((m - core) / (1.0 - core), 0.0, 1.0)
    inner = np.where(m <= core, 1.0, core / safe)  # onto the core square's boundary
    y = (1.0 - rho) * u * inner + rho * np.cos(phi)
    z = (1.0 - rho) * v * inner + rho * np.sin(phi)
    return y, z


def _grid(n_around: int, n_radial: int, rod: bool):
    """Section grid: parametric (a, b) per vertex, quads (4, q) counter-clockwise, periodic b."""
    if rod:
        n = n_around // 4  # cells per side of the square: n_around cells on its boundary
        g = np.linspace(-1.0, 1.0, n + 1)
        a, b = np.meshgrid(g, g, indexing="ij")
        idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
        q = np.vstack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(),
                       idx[:-1, 1:].ravel()])
        return a.ravel(), b.ravel(), q
    rho = np.linspace(0.0, 1.0, n_radial + 1)
    theta = 2.0 * np.pi * np.arange(n_around) / n_around
    a, b = np.meshgrid(rho, theta, indexing="ij")
    idx = np.arange((n_radial + 1) * n_around).reshape(n_radial + 1, n_around)
    nxt = np.roll(idx, -1, axis=1)
    q = np.vstack([idx[:-1].ravel(), idx[1:].ravel(), nxt[1:].ravel(), nxt[:-1].ravel()])
    return a.ravel(), b.ravel(), q


def _place(x, a, b, stations, outer, inner, rod: bool, core: float) -> np.ndarray:
    """Physical points (3, n) of parametric points (x, a, b), m."""
    D = np.interp(x, stations, outer)
    if rod:
        y, z = rod_section_point(a, b, core)
        return np.vstack([x, 0.5 * D * y, 0.5 * D * z])
    r = 0.5 * np.interp(x, stations, inner) + a * 0.5 * (D - np.interp(x, stations, inner))
    return np.vstack([x, r * np.cos(b), r * np.sin(b)])


def tube_hex_mesh(x_m: np.ndarray, outer_diameter_m: np.ndarray, inner_diameter_m: np.ndarray,
                  n_around: int = 16, n_radial: int = 2, n_along: int = 20) -> MeshHex2:
    """Quadratic hexahedral mesh of a tube (inner diameter > 0) or rod (inner diameter 0).

    Parameters
    ----------
    x_m, outer_diameter_m, inner_diameter_m : ndarray, shape (k,)
        Stations (m, increasing) and the diameters there (m), linear between stations; the inner
        diameters all zero (a rod) or all positive (a tube). Checked by the caller.
    n_around : int
        Elements around the circumference (a multiple of 4).
    n_radial : int
        Elements through the wall (tube) ; the rod's O-grid ignores it (its ring has about a
        quarter of the side's n_around / 4 elements across).
    n_along : int
        About this many elements along x (every station an element edge).

    Returns
    -------
    MeshHex2
        Nodes in m, the axis along x, the clamp section at x = x_m[0].
    """
    rod = not np.any(inner_diameter_m > 0.0)
    xs = along_stations(x_m, n_along)
    a2, b2, q = _grid(n_around, n_radial, rod)
    ns, nx = a2.size, xs.size
    # O-grid core: the grid line nearest half the section (at least one ring layer)
    n_side = n_around // 4
    core = 1.0 - 2.0 * max(1, int(round(n_side / 4.0))) / n_side if rod else 0.0
    X = np.repeat(xs, ns)
    A = np.tile(a2, nx)
    B = np.tile(b2, nx)
    lo = np.arange(nx - 1)[:, None] * ns
    c0, c1, c2, c3 = (lo + q[k][None, :] for k in range(4))
    c0, c1, c2, c3 = (c.ravel() for c in (c0, c1, c2, c3))
    # skfem's hexahedron vertex order, reference (xi, eta, zeta) = (x, a, b)-ish:
    # (0,0,0), (0,0,1), (0,1,0), (1,0,0), (0,1,1), (1,0,1), (1,1,0), (1,1,1) with xi along x,
    # eta along c0 -> c1 and zeta along c0 -> c3: right-handed as (x, a, b) is
    t = np.vstack([c0, c3, c1, c0 + ns, c2, c3 + ns, c1 + ns, c2 + ns])
    lin = MeshHex(_place(X, A, B, x_m, outer_diameter_m, inner_diameter_m, rod, core), t)
    # every quadratic node: the trilinear image of its reference point in parametric space
    dofs = Dofs(lin, ElementHex2())
    ref = ElementHex2.doflocs  # (27, 3)
    e1 = ElementHex1()
    shape = np.array([e1.lbasis(ref.T, i)[0] for i in range(8)])  # (8 vertices, 27 nodes)
    par = np.stack([X[t], A[t], B[t]])  # (3, 8, E)
    if not rod:
        # unwrap the angle within each element (the seam theta = 2 pi -> 0)
        th = par[2]
        par[2] = th[0] + (th - th[0] + np.pi) % (2.0 * np.pi) - np.pi
    node_par = np.einsum("vj,cve->cje", shape, par)  # (3, 27, E)
    pts = _place(*(node_par[c].ravel() for c in range(3)), x_m, outer_diameter_m,
                 inner_diameter_m, rod, core).reshape(3, 27, -1)
    doflocs = np.zeros((3, dofs.N))
    doflocs[:, dofs.element_dofs] = pts
    return MeshHex2(doflocs=doflocs, t=lin.t)
