"""Finite-segment springs of every joint axis: bending about y and z, torsion about x.

Each joint's spring stands for the member between the centres of the links it joins (the end
links counted to the clamp and to the tip, so the spans tile the member), as for the planar
chain's :func:`~prbdm_pin.chain.stiffness.finite_segment_stiffness`: K = C / ∫ dx / S(x) with
the section stiffness C S(x) of the axis:

- ``y`` (out-of-plane bending): E I_y, I_y = 2 w t^3 / 12 (the planar chain's springs, the same
  numbers bit for bit);
- ``z`` (in-plane bending): E I_z, I_z = t (2 w)^3 / 12, integrated in closed form on each
  vertex interval where w is linear;
- ``x`` (torsion): G J with the Saint-Venant constant J(2 w, t) of the rectangle
  (:func:`prbdm_pin.member.section.torsion_constant_m4`), integrated by 16-point
  Gauss-Legendre on each vertex interval (1 / J is smooth there; the rule's error is below
  1e-13 relative for every interval whose end widths differ by less than a factor 10).

A round member's E I_z and G J (:mod:`~prbdm_pin.member.section_law`) are integrated as its
E I_y is (:func:`~prbdm_pin.chain.stiffness_law.inverse_section_integral`).
"""

from __future__ import annotations

import numpy as np

from ..member.geometry import Beam
from ..member.section import torsion_constant_m4
from ..member.section_law import section_properties
from ..options.choices import MIN_FRACTION, Axes
from ..options.validate import check_axes, check_type
from .layout import validate_lengths
from .stiffness import finite_segment_stiffness_unchecked
from .stiffness_law import inverse_section_integral

__all__ = ["axis_stiffness", "spatial_stiffness", "spring_axes", "link_mean_section_m4",
           "paper_axis_unit_stiffness"]

_GL_T, _GL_W = np.polynomial.legendre.leggauss(16)


def _spans(lengths: np.ndarray) -> np.ndarray:
    """Return the springs' span ends: 0, the inner links' centres, L; m, shape (n + 1,)."""
    ends = np.add.accumulate(lengths)
    centres = ends - 0.5 * lengths
    centres[0] = 0.0
    centres[-1] = ends[-1]
    return centres


def _span_integrals(beam: Beam, lengths: np.ndarray, axis: str) -> np.ndarray:
    """∫ dx / S(x) over each spring's span (S = I_z or J, m^4), 1/m^3, shape (n,)."""
    c = _spans(lengths)
    n = c.size - 1
    cuts = np.union1d(c, beam.x_m)
    u, v = cuts[:-1], cuts[1:]
    keep = v > u
    u, v = u[keep], v[keep]
    # one-sided widths at the sub-interval ends (a width step jumps between them)
    wu = 2.0 * np.asarray(beam.half_width_at(u, "right"), dtype=float)
    wv = 2.0 * np.asarray(beam.half_width_at(v, "left"), dtype=float)
    t = beam.uniform_thickness_m("the spatial chain")
    if axis == "z":
        # ∫ dx / (t b^3 / 12) with b linear from wu to wv: 12 (v - u) (wu + wv) / (2 t wu^2 wv^2)
        part = 6.0 * (v - u) * (wu + wv) / (t * wu * wu * wv * wv)
    else:
        s = 0.5 * (_GL_T + 1.0)
        b = wu[:, None] + (wv - wu)[:, None] * s
        part = (v - u) * (0.5 * _GL_W / torsion_constant_m4(b, t)).sum(axis=1)
    span = np.searchsorted(c, 0.5 * (u + v)) - 1
    return np.bincount(np.clip(span, 0, n - 1), part, n)


def axis_stiffness(beam: Beam, lengths: np.ndarray, axis: str) -> np.ndarray:
    """Finite-segment springs of one axis (``"y"``, ``"z"`` or ``"x"``), N m/rad, shape (n,).

    ``lengths`` (m, shape (n+1,)) already validated.
    """
    if axis == "y":
        return finite_segment_stiffness_unchecked(beam, lengths)
    if axis not in ("z", "x"):
        raise ValueError(f"axis = {axis!r}: must be 'x', 'y' or 'z'")
    if beam.section is not None:  # ∫ dx / (E I_z or G J) of the section law, 1/(N m)
        c = _spans(lengths)
        u, v, part = inverse_section_integral(beam, np.union1d(c, beam.x_m)[None],
                                              "EI_z_Nm2" if axis == "z" else "GJ_Nm2")
        span = np.clip(np.searchsorted(c, 0.5 * (u[0] + v[0])) - 1, 0, c.size - 2)
        return 1.0 / np.bincount(span, part[0], c.size - 1)
    modulus = beam.material.E_Pa if axis == "z" else beam.material.G_Pa
    return modulus / _span_integrals(beam, lengths, axis)


def spring_axes(axes: Axes | str, n_joints: int) -> tuple[str, ...]:
    """Return the axis of every spring coordinate, node-major: joint 1's axes, then joint 2's, ...

    Within a node the order is :attr:`Axes.joint_order` (y, z, x).
    """
    order = Axes(axes).joint_order
    return order * int(n_joints)


def spatial_stiffness(beam: Beam, lengths_m: np.ndarray, axes: Axes | str = Axes.Y,
                      min_fraction: float = MIN_FRACTION) -> np.ndarray:
    """Finite-segment springs of every joint axis, N m/rad, node-major (:func:`spring_axes`).

    Parameters
    ----------
    beam : Beam
        Planform, thickness (m), E and nu (G = E / (2 (1 + nu))).
    lengths_m : array_like, shape (n+1,)
        Link lengths, m (validated as for :func:`~prbdm_pin.build_model`).
    axes : Axes or {"y", "xy", "yz", "xyz"}
        The joint axes at each node.
    min_fraction : float
        Lower bound on each link as a fraction of L.

    Returns
    -------
    ndarray
        Springs, N m/rad, n times the number of axes: for ``"y"`` the planar chain's
        finite-segment springs.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> k = pp.spatial_stiffness(beam, [0.5, 0.5], axes="xyz")  # one joint, axes y, z, x
    >>> k.shape
    (3,)
    >>> b, t, E, G, span = 0.05, 0.01, 205e9, 205e9 / (2 * 1.28), 1.0  # m, m, Pa, Pa, m
    >>> k[:2].round(1), round(E * b * t**3 / 12 / span, 1), round(E * t * b**3 / 12 / span, 1)
    (array([  854.2, 21354.2]), 854.2, 21354.2)
    >>> J = b * t**3 / 3 * (1 - 0.630 * t / b)  # m^4: a strip's J (Timoshenko & Goodier)
    >>> round(float(k[2])), round(G * J / span)  # N m/rad
    (1166, 1166)
    """
    check_type("beam", beam, Beam)
    order = check_axes(axes).joint_order
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    per_axis = np.stack([axis_stiffness(beam, lengths, a) for a in order], axis=1)
    return per_axis.reshape(-1)


def link_mean_section_m4(beam: Beam, lengths: np.ndarray, axis: str) -> np.ndarray:
    """Each link's mean section constant of one axis over its span, m^4, shape (n+1,).

    ``y``: I_y = 2 w t^3 / 12; ``z``: I_z = t (2 w)^3 / 12; ``x``: Roark's closed-form J of the
    rectangle (:func:`~prbdm_pin.member.section.torsion_constant_thin_m4`, the paper-style
    closed form). 16-point Gauss-Legendre on each vertex interval: exact for I_y and I_z (cubic
    in x), and for Roark's J to rounding where the end widths differ by less than a factor 10.
    ``lengths`` (m, shape (n+1,)) already validated.
    """
    from ..member.section import torsion_constant_thin_m4

    ends = np.add.accumulate(lengths)
    ends[-1] = beam.length_m
    starts = ends - lengths
    cuts = np.union1d(np.r_[0.0, ends], beam.x_m)
    u, v = cuts[:-1], cuts[1:]
    keep = v > u
    u, v = u[keep], v[keep]
    s = 0.5 * (_GL_T + 1.0)
    x = u[:, None] + (v - u)[:, None] * s
    if beam.section is not None:  # the section law's constants: quartic at most, exact
        sp = section_properties(beam, x)
        mat = beam.material
        S = {"y": sp.EI_y_Nm2 / mat.E_Pa, "z": sp.EI_z_Nm2 / mat.E_Pa,
             "x": sp.GJ_Nm2 / mat.G_Pa}[axis]
        part = (v - u) * (0.5 * _GL_W * S).sum(axis=1)
    else:
        b = 2.0 * np.asarray(beam.half_width_at(x.ravel()), dtype=float).reshape(x.shape)
        t = beam.uniform_thickness_m("the spatial chain")
        section = {"y": lambda w: w * t**3 / 12.0, "z": lambda w: t * w**3 / 12.0,
                   "x": lambda w: torsion_constant_thin_m4(w, t)}[axis]
        part = (v - u) * (0.5 * _GL_W * section(b)).sum(axis=1)
    link = np.clip(np.searchsorted(ends, 0.5 * (u + v)), 0, lengths.size - 1)
    return np.bincount(link, part, lengths.size) / (ends - starts)


def paper_axis_unit_stiffness(beam: Beam, lengths: np.ndarray, mass_kg: np.ndarray,
                              axis: str) -> np.ndarray:
    """Return the paper's equation 14 on any axis at unit factor, N m/rad, shape (n,).

    Joint j drives link j + 1: K_j = sqrt(C S_(j+1) / m_(j+1)) with S the link's mean section
    constant of the axis (:func:`link_mean_section_m4`), C = E for bending (y, z) and G for
    torsion (x), and m the link mass (kg, shape (n+1,)). For ``y`` this is
    :func:`~prbdm_pin.chain.stiffness.paper_unit_stiffness` with the exact mean I_y.
    """
    modulus = beam.material.G_Pa if axis == "x" else beam.material.E_Pa
    S = link_mean_section_m4(beam, lengths, axis)
    return np.sqrt(modulus * S[1:] / np.asarray(mass_kg, dtype=float)[1:])
