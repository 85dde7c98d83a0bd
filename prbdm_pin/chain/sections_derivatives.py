"""Derivatives of the link sections and of the finite-segment springs in the joint stations.

A chain of n joints on a beam of length L is cut at the stations x_1 < ... < x_n (joint j sits at
x_j = L_0 + ... + L_(j-1)); x_0 = 0 and x_(n+1) = L are fixed, so the stations are the n free
coordinates of the lengths on their simplex (L_i = x_(i+1) - x_i). Every section quantity is an
integral over [a, b] = [x_i, x_(i+1)] of the planform, so by the fundamental theorem of calculus
its derivative with respect to a cut station is the integrand at the cut:

    d/db ∫_a^b f dx = f(b),
    d/da ∫_a^b f(x) (x - a)^p dx = -[p = 0] f(a) - p ∫_a^b f (x - a)^(p-1).

At a width step the half-width jumps, the integrals have different one-sided derivatives there,
and the derivative returned is their mean (the limit of a central difference). A round or
table member's section law (:mod:`~prbdm_pin.member.section_law`) is continuous: its integrands
(rho A, rho I, E I_y and 1 / E I_y) at the cut are the derivatives.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..member.geometry import Beam
from ..member.section_law import section_properties
from .sections import link_sections_unchecked, planar_sections
from .stiffness import finite_segment_stiffness_unchecked

__all__ = ["SectionGradient", "stations_from_lengths", "planar_sections_gradient",
           "finite_segment_stiffness_gradient", "roll_yaw_inertia_gradient"]


@dataclass(frozen=True, eq=False)
class SectionGradient:
    """The planar sections of n + 1 links and their derivatives in the n joint stations.

    The sections are those of ``sections.planar_sections``.

    Attributes
    ----------
    mass_kg, com_offset_m, inertia_yy_kg_m2, area_moment_m4 : ndarray, shape (n+1,)
        Link mass (kg), centre-of-mass distance from the link's start (m), inertia about the
        centre of mass around y (kg m^2) and mean bending area moment (m^4).
    d_mass_kg_per_m, d_com_offset, d_inertia_yy_kg_m, d_area_moment_m3 : ndarray, shape (n+1, n)
        Entry [i, j]: derivative of link i's quantity with respect to the station of joint
        j + 1 (kg/m, m/m, kg m, m^3).
    """

    mass_kg: np.ndarray
    com_offset_m: np.ndarray
    inertia_yy_kg_m2: np.ndarray
    area_moment_m4: np.ndarray
    d_mass_kg_per_m: np.ndarray
    d_com_offset: np.ndarray
    d_inertia_yy_kg_m: np.ndarray
    d_area_moment_m3: np.ndarray


def stations_from_lengths(lengths_m: np.ndarray) -> np.ndarray:
    """Joint stations x_j = L_0 + ... + L_(j-1), m, shape (n,) for lengths (n+1,)."""
    return np.add.accumulate(np.asarray(lengths_m, dtype=float))[:-1]


def _mean_width(beam: Beam, x: np.ndarray) -> np.ndarray:
    """Return w(x), m; at a width step the mean of the one-sided limits."""
    if not beam.step_index.size:  # called in the fit's inner loop: one interpolation
        return np.interp(x, beam.x_m, beam.half_width_m)
    return 0.5 * (beam.half_width_at(x, "left") + beam.half_width_at(x, "right"))


@lru_cache(maxsize=64)
def _bands(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the entries (link, station) the n stations move and the sign of each span's change.

    Station j + 1 ends link j (first n entries, +1) and starts link j + 1 (last n, -1).
    """
    links = np.r_[np.arange(n), np.arange(1, n + 1)]
    cols = np.r_[np.arange(n), np.arange(n)]
    sign = np.r_[np.ones(n), -np.ones(n)]
    for a in (links, cols, sign):
        a.setflags(write=False)
    return links, cols, sign


def planar_sections_gradient(beam: Beam, lengths_m: np.ndarray,
                             sections: tuple | None = None) -> SectionGradient:
    """Return the planar sections of ``lengths_m`` and their exact derivatives in the stations.

    The sections are :func:`sections.planar_sections` of ``lengths_m`` (m, (n+1,), valid); the
    derivatives are with respect to the joint stations (see the module docstring).
    ``sections``: ``planar_sections(beam, lengths_m)`` when already computed.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    if sections is None:
        sections = planar_sections(beam, lengths)
    mass, offset, Iyy, area_moment = sections
    nl = lengths.size
    n = nl - 1
    sec = beam.section is not None
    law = beam.thickness_law_m is not None or sec
    # under a thickness law rho_t is rho and A, w2 carry t(x) (A = ∫ 2 w t); a section law's
    # rows carry rho already (A = ∫ rho A is the mass, w2 the mass per length)
    t = 1.0 if law else beam.thickness_m
    rho_t = 1.0 if sec else beam.material.rho_kg_m3 * t
    # moments about each link's start: A = ∫ 2w, P1 = ∫ 2w (x - a) (P2 = ∫ 2w (x - a)^2 enters
    # only through its derivative)
    A = mass / rho_t
    P1 = A * offset
    x = stations_from_lengths(lengths)
    h = np.empty(nl)  # the spans the sections integrated over
    h[0] = x[0]
    np.subtract(x[1:], x[:-1], out=h[1:-1])
    h[-1] = beam.length_m - x[-1]
    if sec:
        sp = section_properties(beam, x)
        w2 = sp.rhoA_kg_m
    else:
        w2 = 2.0 * _mean_width(beam, x)
    if law and not sec:
        w2 = w2 * beam.thickness_at(x)
    # each link moves with two stations only: its end (station j + 1 ends link j, the first n
    # entries) and its start (station j + 1 starts link j + 1, the last n), both bands at once
    links, cols, dh = _bands(n)
    # ends: d/db of A, P1, P2 is the integrand at b; starts: (x - a)^p vanishes at a for p > 0
    he = h[:n]
    d = np.empty((3, 2 * n))  # dA, dP1, dP2
    d[0, :n] = w2
    np.negative(w2, out=d[0, n:])
    np.multiply(w2, he, out=d[1, :n])
    np.negative(A[1:], out=d[1, n:])
    np.multiply(d[1, :n], he, out=d[2, :n])
    np.multiply(-2.0, P1[1:], out=d[2, n:])
    dA, dP1, dP2 = d[0], d[1], d[2]
    Al, hl = A[links], h[links]
    off, r = offset[links], P1[links] / Al
    # rows: mass, offset, Iyy = rho t (P2 - P1^2 / A) + rho t A t^2 / 12 (row 0 holds
    # rho t dA), mean area moment
    v = np.empty((4, 2 * n))
    np.multiply(rho_t, dA, out=v[0])
    np.divide(dP1 - off * dA, Al, out=v[1])
    if law:  # the z^2 term and the mean area moment: T = ∫ 2 w t^3 / 12 moves by its integrand
        if sec:  # ∫ rho I_y and ∫ E I_y / E move by theirs
            gm, g = sp.rhoI_y_kg_m, sp.EI_y_Nm2 / beam.material.E_Pa
        else:
            g = w2 * beam.thickness_at(x) ** 2 / 12.0
            gm = rho_t * g
        dT = np.r_[g, -g]
        T = area_moment[links] * hl
        np.add(rho_t * (dP2 - 2.0 * r * dP1 + r * r * dA), np.r_[gm, -gm], out=v[2])
        np.subtract(dT / hl, T / hl**2 * dh, out=v[3])
    else:
        np.add(rho_t * (dP2 - 2.0 * r * dP1 + r * r * dA), v[0] * t * t / 12.0, out=v[2])
        np.multiply(t**3 / 12.0, dA / hl - Al / hl**2 * dh, out=v[3])
    out = np.zeros((4, nl, n))
    out[:, links, cols] = v
    return SectionGradient(mass, offset, Iyy, area_moment, *out)


def roll_yaw_inertia_gradient(beam: Beam, lengths_m: np.ndarray,
                              sections: SectionGradient | None = None
                              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return the links' inertias about x and z and their derivatives in the joint stations.

    The inertias are about each link's centre of mass, as :func:`sections.link_sections`
    computes them: I_xx = rho t S_yy + m t^2 / 12 and I_zz = rho t (S_xx + S_yy), with
    S_yy = ∫ 2 w^3 / 3 dx and S_xx the second moment of the area in x about the centre of mass
    (rho t S_xx = I_yy - m t^2 / 12). S_yy's derivative at a moving span end is its integrand
    there (at a width step the mean of the one-sided values, as the module docstring says).

    Parameters
    ----------
    beam : Beam
    lengths_m : ndarray, shape (n+1,)
        Valid link lengths, m.
    sections : SectionGradient, optional
        ``planar_sections_gradient(beam, lengths_m)`` when already computed (its mass and I_yy
        derivatives give those of S_xx).

    Returns
    -------
    inertia_xx, inertia_zz : ndarray, shape (n+1,)
        kg m^2.
    d_inertia_xx, d_inertia_zz : ndarray, shape (n+1, n)
        Entry [i, j]: derivative of link i's inertia in the station of joint j + 1, kg m.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    if sections is None:
        sections = planar_sections_gradient(beam, lengths)
    sec = link_sections_unchecked(beam, lengths)
    Ixx, Izz = sec.inertia_com_kg_m2[:, 0, 0], sec.inertia_com_kg_m2[:, 2, 2]
    n = lengths.size - 1
    if beam.section is not None:  # ∫ rho I_x, ∫ rho I_z and ∫ rho I_y move by their integrands
        return (Ixx, Izz, *_section_roll_yaw(beam, lengths, sections.d_inertia_yy_kg_m))
    law = beam.thickness_law_m is not None
    t = 1.0 if law else beam.thickness_m  # a law's t(x) goes into the integrands below
    rho_t = beam.material.rho_kg_m3 * t
    x = stations_from_lengths(lengths)
    left, right = beam.half_width_at(x, "left"), beam.half_width_at(x, "right")
    g = (left**3 + right**3) / 3.0  # the mean one-sided 2 w^3 / 3 at each station
    links, cols, sign = _bands(n)
    if law:
        tx = beam.thickness_at(x)
        g = g * tx
    dSyy = np.zeros((n + 1, n))
    dSyy[links, cols] = sign * np.r_[g, g]  # a station ends link j (+), starts link j + 1 (-)
    if law:  # rho ∫ 2 w t^3 / 12 moves by its integrand (the mean one-sided w at a step)
        gt = rho_t * (left + right) * tx**3 / 12.0
        thick = np.zeros((n + 1, n))
        thick[links, cols] = sign * np.r_[gt, gt]
    else:
        thick = sections.d_mass_kg_per_m * (t * t / 12.0)
    d_xx = rho_t * dSyy + thick
    d_zz = (sections.d_inertia_yy_kg_m - thick) + rho_t * dSyy
    return Ixx, Izz, d_xx, d_zz


def _section_roll_yaw(beam: Beam, lengths: np.ndarray, d_inertia_yy: np.ndarray):
    """Return d I_xx (∫ rho I_x) and d I_zz (I_yy - ∫ rho I_y + ∫ rho I_z), kg m."""
    n = lengths.size - 1
    sp = section_properties(beam, stations_from_lengths(lengths))
    links, cols, sign = _bands(n)

    def band(g):
        out = np.zeros((n + 1, n))
        out[links, cols] = sign * np.r_[g, g]  # a station ends link j (+), starts j + 1 (-)
        return out

    return band(sp.rhoI_x_kg_m), d_inertia_yy + band(sp.rhoI_z_kg_m - sp.rhoI_y_kg_m)


def finite_segment_stiffness_gradient(beam: Beam, lengths_m: np.ndarray,
                                      K: np.ndarray | None = None
                                      ) -> tuple[np.ndarray, np.ndarray]:
    """Return the finite-segment springs and their derivatives in the joint stations.

    The springs are K_j = E (2 t^3 / 12) / ∫_(c_j)^(c_(j+1)) dx / w (N m/rad, (n,),
    ``stiffness.finite_segment_stiffness``); their derivatives with respect to the joint
    stations are in N m/rad per m, shape (n, n) (entry [j, l]: spring j, station l + 1).

    The span ends c_j are the links' mid-spans (x_j + x_(j+1)) / 2, except c_0 = 0 and c_n = L,
    which do not move; d/dc of the integral is -+1 / w(c) at its ends. ``K``: the springs of
    ``lengths_m`` when already computed.
    """
    lengths = np.asarray(lengths_m, dtype=float)
    if K is None:
        K = finite_segment_stiffness_unchecked(beam, lengths)
    n = K.size
    law = beam.thickness_law_m is not None
    # under a law the integral is of 1 / (w t^3): t^3 leaves C for the integrand; a section
    # law's is of 1 / E I_y (C = 1)
    C = beam.material.E_Pa * 2.0 * (1.0 if law else beam.thickness_m**3) / 12.0
    if beam.section is not None:
        C = 1.0
    ends = np.add.accumulate(lengths)
    centres = ends - 0.5 * lengths
    if n == 1:
        return K, np.zeros((1, 1))
    inner = centres[1:n]  # c_1 .. c_(n-1), each the mean of stations j and j + 1
    dI_dc = 0.5 / _mean_width(beam, inner)  # (n-1,): 1 / w(c) times dc/dx = 1/2
    if beam.section is not None:
        dI_dc = 0.5 / section_properties(beam, inner).EI_y_Nm2
    elif law:
        dI_dc = dI_dc / beam.thickness_at(inner) ** 3
    # spring j's integral ends at c_(j+1) (+) and spring j + 1's starts there (-): dI is
    # tridiagonal, written through views of its diagonals
    dI = np.zeros((n, n))
    flat = dI.reshape(-1)
    diag = flat[:: n + 1]
    diag[:-1] = dI_dc
    diag[1:] -= dI_dc
    flat[1:: n + 1] = dI_dc
    np.negative(dI_dc, out=flat[n:: n + 1])
    dK = -(K * K / C)[:, None] * dI
    return K, dK
