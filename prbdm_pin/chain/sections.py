"""Exact per-link mass, centre of mass, inertia about the centre of mass and bending area moment.

The planform half-width w(x) is piecewise linear, so over any span every integrand needed here
(the area 2 w, its first and second moments in x, and the y^2 moment 2 w^3 / 3) is a polynomial of
degree <= 3 on each vertex interval. Two-point Gauss-Legendre quadrature is exact for cubics, so
splitting the link spans at the planform vertices and summing gives the exact integrals (to
rounding) without sampling or polygon clipping. A width step (two vertices at one station) splits
the axis there too, so a link that straddles or ends on a step integrates each side exactly.

A thickness law t(x), linear between the same stations, raises the degrees: the mass density
2 w t is quadratic, its second moment in x and the y^2 and z^2 moments (2 w^3 t / 3, 2 w t^3 / 12)
are quartic, so three-point Gauss-Legendre (exact to degree 5) integrates them exactly.

A round member (outer and inner diameters linear between stations: conical frusta) reads its
section law from :func:`~prbdm_pin.member.section_law.section_properties`: rho A is quadratic,
rho A (x - c)^2, the rotary inertias rho I and E I_y quartic, so the same three-point rule is
exact; a section table's laws are linear, so exact too. The roll inertia is then ∫ rho I_x
(the polar moment), pitch ∫ rho A (x - x_c)^2 + ∫ rho I_y and yaw ∫ rho A (x - x_c)^2 +
∫ rho I_z.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..member.geometry import Beam
from ..member.section_law import section_properties
from ..options.choices import MIN_FRACTION
from .layout import validate_lengths

__all__ = ["LinkSections", "link_sections", "link_sections_unchecked", "planar_sections"]

# two-point Gauss-Legendre on [0, 1]: exact for polynomials up to degree 3
_GAUSS_T = np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)])
_ROWS = np.arange(4)
# three-point Gauss-Legendre on [0, 1]: exact for polynomials up to degree 5 (the thickness law)
_GAUSS3_T = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_GAUSS3_W = np.array([5.0, 8.0, 5.0]) / 18.0


@dataclass(frozen=True, eq=False)
class LinkSections:
    """Rigid-body properties of the n + 1 links of a beam cut at given lengths.

    Attributes
    ----------
    start_m, end_m : ndarray, shape (n+1,)
        Span [start, end] of each link along the beam axis, m.
    mass_kg : ndarray, shape (n+1,)
        Link masses, kg.
    com_m : ndarray, shape (n+1, 3)
        Centres of mass in the beam frame (root at the origin, axis along x), m.
    inertia_com_kg_m2 : ndarray, shape (n+1, 3, 3)
        Inertia tensors about the centres of mass, beam axes, kg m^2 (thickness term included).
    area_moment_m4 : ndarray, shape (n+1,)
        Mean bending area moment I_yy = 2 w t^3 / 12 over each link's span, m^4.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> sec = pp.link_sections(beam, [0.2, 0.5, 0.3])  # m
    >>> isinstance(sec, pp.LinkSections), sec.inertia_com_kg_m2.shape
    (True, (3, 3, 3))
    >>> sec.start_m, sec.end_m  # m
    (array([0. , 0.2, 0.7]), array([0.2, 0.7, 1. ]))
    >>> sec.com_m[:, 0].round(3)  # m: the links' mid-points on a uniform strip
    array([0.1 , 0.45, 0.85])
    """

    start_m: np.ndarray
    end_m: np.ndarray
    mass_kg: np.ndarray
    com_m: np.ndarray
    inertia_com_kg_m2: np.ndarray
    area_moment_m4: np.ndarray

    @property
    def n_links(self) -> int:
        """Number of links n + 1."""
        return int(self.mass_kg.size)

    @property
    def length_m(self) -> np.ndarray:
        """Link lengths, m."""
        return self.end_m - self.start_m


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=float)
    a.setflags(write=False)
    return a


def link_sections(beam: Beam, lengths_m: np.ndarray,
                  min_fraction: float = MIN_FRACTION) -> LinkSections:
    """Exact sections of the links of ``beam`` cut at ``lengths_m``.

    Parameters
    ----------
    beam : Beam
    lengths_m : array_like, shape (n+1,)
        Link lengths in m; they must sum to the beam length and each lie in
        [min_fraction L, (1 - min_fraction) L].
    min_fraction : float
        Eq. 15's bound, 0.02 by default.

    Returns
    -------
    LinkSections
        Masses (kg), centres of mass (m, beam frame), inertia about the COM (kg m^2) and mean
        bending area moment (m^4) of each link.

    Notes
    -----
    For a plate of density rho and thickness t spanning z in [-t/2, t/2]:
    Ixx = rho t ∫∫ y^2 dA + m t^2/12, Iyy = rho t ∫∫ (x - xc)^2 dA + m t^2/12,
    Izz = rho t ∫∫ ((x - xc)^2 + y^2) dA; products of inertia vanish by symmetry.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> l = np.array([0.2, 0.5, 0.3])  # m
    >>> sec = pp.link_sections(beam, l)
    >>> sec.mass_kg.round(4), (7850.0 * 0.05 * 0.01 * l).round(4)  # kg, rho b t l
    (array([0.785 , 1.9625, 1.1775]), array([0.785 , 1.9625, 1.1775]))
    >>> m = sec.mass_kg  # kg; below I_yy about the COM, kg m^2, and m (l^2 + t^2) / 12
    >>> sec.inertia_com_kg_m2[:, 1, 1].round(6), (m * (l**2 + 0.01**2) / 12).round(6)
    (array([0.002623, 0.040902, 0.008841]), array([0.002623, 0.040902, 0.008841]))
    >>> # the mean area moments in 1e-9 m^4, and a uniform strip's b t^3 / 12
    >>> (sec.area_moment_m4 * 1e9).round(4), round(0.05 * 0.01**3 / 12 * 1e9, 4)
    (array([4.1667, 4.1667, 4.1667]), 4.1667)
    """
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    return link_sections_unchecked(beam, lengths)


def _integrals(beam: Beam, lengths: np.ndarray):
    """Link spans, mid-spans and the exact planform integrals of every link, all at once.

    The integrals are the area, the first and second moment in x about the mid-span, and the
    y^2 moment.

    ``lengths`` is (n+1,) or a stack (B, n+1) of designs (the fit's finite differences); every
    output then has the same leading shape. Each design's numbers do not depend on the stack.
    """
    # called inside optimisation loops on a single design: ndarray methods and preallocated
    # arrays rather than numpy's wrapper functions, each of which costs as much as the
    # arithmetic of a short chain
    shape = lengths.shape
    nl = shape[-1]
    L = lengths.reshape(-1, nl)
    B = L.shape[0]
    xv = beam.x_m
    nv = xv.size
    se = np.zeros((B, nl + 1))  # link boundaries: link i spans [se[i], se[i + 1]]
    np.add.accumulate(L, axis=1, out=se[:, 1:])
    se[:, -1] = beam.length_m  # the tip is the beam's end, not a rounded sum
    starts, ends = se[:, :-1], se[:, 1:]
    mids = 0.5 * (starts + ends)
    # sub-intervals between all planform vertices and link boundaries (an empty one where a
    # boundary meets a vertex adds exact zeros)
    cuts = np.empty((B, nv + nl))
    cuts[:, :nv] = xv
    cuts[:, nv:] = ends
    cuts.sort(axis=1)
    u, v = cuts[:, :-1], cuts[:, 1:]
    # the link of each sub-interval: how many link ends lie below its middle (at most nl - 1,
    # as no middle lies beyond the tip)
    centre = 0.5 * (u + v)
    if B == 1:
        link = ends[0].searchsorted(centre)
    else:
        link = (centre[:, :, None] > ends[:, None, :]).sum(axis=2)
        link += nl * np.arange(B)[:, None]  # the flat index of (design, link)
    h = v - u
    if beam.section is not None:
        return _section_integrals(beam, shape, starts, ends, mids, link, u, h, B * nl)
    if beam.thickness_law_m is not None:
        return _law_integrals(beam, shape, starts, ends, mids, link, u, h, B * nl)
    xg = u[..., None] + h[..., None] * _GAUSS_T  # (B, s, 2) Gauss points
    wg = np.interp(xg, xv, beam.half_width_m)
    xl = xg - mids.ravel()[link][..., None]  # about the mid-span
    w2 = 2.0 * wg
    # rows: area, first and second moment in x, y^2 moment (2 w^3 / 3); Gauss weights h / 2
    f = np.empty((4,) + xg.shape)
    f[0] = w2
    np.multiply(w2, xl, out=f[1])
    np.multiply(f[1], xl, out=f[2])
    f[3] = w2 * wg * wg / 3.0
    f = np.add.reduce(f, axis=3) * (0.5 * h)
    # all four rows in one bincount: row r's bins are offset by r B nl
    bins = (link.ravel() + (B * nl) * _ROWS[:, None]).ravel()
    out = np.bincount(bins, f.ravel(), 4 * B * nl).reshape((4,) + shape)
    return (starts.reshape(shape), ends.reshape(shape), mids.reshape(shape), *out)


def _law_integrals(beam: Beam, shape, starts, ends, mids, link, u, h, nbins):
    """:func:`_integrals` under a thickness law: every row weighted by t(x), plus ∫ 2 w t^3.

    Rows: ∫ 2 w t, its first and second moment in x about the mid-span, ∫ 2 w^3 t / 3 and
    ∫ 2 w t^3 / 12 (m^2 ... m^6), each quartic at most on a sub-interval: 3-point Gauss is exact.
    """
    xg = u[..., None] + h[..., None] * _GAUSS3_T
    wg = np.interp(xg, beam.x_m, beam.half_width_m)
    tg = np.interp(xg, beam.x_m, beam.thickness_law_m)
    xl = xg - mids.ravel()[link][..., None]
    a = 2.0 * wg * tg
    rows = np.stack([a, a * xl, a * xl * xl, a * wg * wg / 3.0, a * tg * tg / 12.0])
    f = np.sum(rows * _GAUSS3_W, axis=-1) * h
    out = np.stack([np.bincount(link.ravel(), r.ravel(), nbins) for r in f])
    return (starts.reshape(shape), ends.reshape(shape), mids.reshape(shape),
            *out.reshape((5,) + shape))


def _section_integrals(beam: Beam, shape, starts, ends, mids, link, u, h, nbins):
    """:func:`_integrals` of a section law (round): mass, inertia and stiffness per length.

    Rows: ∫ rho A, its first and second moment in x about the mid-span (kg, kg m, kg m^2),
    ∫ rho I_x, ∫ rho I_y, ∫ rho I_z (kg m^2) and ∫ E I_y (N m^3). With D, d linear between
    stations rho A is quadratic and the rest quartic at most: 3-point Gauss is exact.
    """
    xg = u[..., None] + h[..., None] * _GAUSS3_T
    sp = section_properties(beam, xg)
    xl = xg - mids.ravel()[link][..., None]
    a = sp.rhoA_kg_m
    rows = np.stack([a, a * xl, a * xl * xl, sp.rhoI_x_kg_m, sp.rhoI_y_kg_m, sp.rhoI_z_kg_m,
                     sp.EI_y_Nm2])
    f = np.sum(rows * _GAUSS3_W, axis=-1) * h
    out = np.stack([np.bincount(link.ravel(), r.ravel(), nbins) for r in f])
    return (starts.reshape(shape), ends.reshape(shape), mids.reshape(shape),
            *out.reshape((7,) + shape))


def _properties(beam: Beam, lengths: np.ndarray):
    """Return the links' properties from the exact integrals, with or without a thickness law.

    Mass (kg), COM offset from mid-span (m), second moments about the COM in x and y times
    rho (kg m^2), the z^2 (thickness) term (kg m^2), the mean area moment (m^4) and Izz about the
    COM (kg m^2) of each link.
    """
    rho = beam.material.rho_kg_m3
    if beam.section is not None:  # rows carry rho and E already; the roll inertia is ∫ rho I_x
        starts, ends, mids, m, S1, S2, Rx, Ry, Rz, EIy = _integrals(beam, lengths)
        dx = S1 / m
        Sxx_c = S2 - m * dx * dx
        return (starts, ends, mids, m, dx, Sxx_c, Rx - Ry, Ry,
                EIy / beam.material.E_Pa / (ends - starts), Sxx_c + Rz)
    if beam.thickness_law_m is not None:
        starts, ends, mids, A, S1, S2, Syy, T3 = _integrals(beam, lengths)
        dx = S1 / A
        Sxx_c = S2 - A * dx * dx
        return (starts, ends, mids, rho * A, dx, rho * Sxx_c, rho * Syy, rho * T3,
                T3 / (ends - starts), rho * (Sxx_c + Syy))
    starts, ends, mids, A, S1, S2, Syy = _integrals(beam, lengths)
    t = beam.thickness_m
    rho_t = rho * t
    mass = rho_t * A
    dx = S1 / A  # COM offset from mid-span
    Sxx_c = S2 - A * dx * dx  # second moment about the COM
    area_moment = A * (t**3 / 12.0) / (ends - starts)  # mean of 2 w t^3 / 12 over the span
    return (starts, ends, mids, mass, dx, rho_t * Sxx_c, rho_t * Syy, mass * (t * t / 12.0),
            area_moment, rho_t * (Sxx_c + Syy))


def link_sections_unchecked(beam: Beam, lengths: np.ndarray) -> LinkSections:
    """:func:`link_sections` for lengths (m, shape (n+1,)) already validated."""
    starts, ends, mids, mass, dx, Ixx_c, Iyy, thick, area_moment, Izz = _properties(beam, lengths)
    nl = lengths.size
    com = np.zeros((nl, 3))
    com[:, 0] = mids + dx
    inertia = np.zeros((nl, 3, 3))
    inertia[:, 0, 0] = Iyy + thick
    inertia[:, 1, 1] = Ixx_c + thick
    inertia[:, 2, 2] = Izz
    return LinkSections(
        start_m=_ro(starts), end_m=_ro(ends), mass_kg=_ro(mass), com_m=_ro(com),
        inertia_com_kg_m2=_ro(inertia), area_moment_m4=_ro(area_moment),
    )


def planar_sections(
    beam: Beam, lengths: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Compute what the planar bending dynamics needs, as :func:`link_sections_unchecked` does.

    With the same arithmetic: mass (kg), centre-of-mass distance from the link's start (m),
    inertia about the centre of mass around y (kg m^2) and mean area moment (m^4), each (n+1,).
    """
    starts, ends, mids, mass, dx, Ixx_c, _, thick, area_moment, _ = _properties(beam, lengths)
    return mass, mids + dx - starts, Ixx_c + thick, area_moment
