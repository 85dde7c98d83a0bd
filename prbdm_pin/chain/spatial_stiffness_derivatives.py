"""Derivatives of the finite-segment springs of every axis in the joint stations and the design.

The springs are those of :func:`.spatial_stiffness.axis_stiffness`: K_j = C / I_j with
I_j = ∫_(c_j)^(c_(j+1)) dx / S(w(x)) over spring j's span, C the modulus (E for bending, G for
torsion) and S the section's stiffness factor (I_y, I_z or J). Whatever moves, dK = -(K^2 / C) dI
plus the modulus' own term.

Stations (n joints, x_j the j-th joint's station; the lengths' free coordinates as in
:mod:`.sections_derivatives`): the inner span ends c_i = (x_i + x_(i+1)) / 2 move with two
stations each and d/dc of the integral is -+1 / S at the span's start and end, the integrand at
the point (the fundamental theorem, exact for the true integral; the 16-point Gauss rule of the
torsion springs differs from it by the rule's error, below 1e-13 relative). At a width step the
derivative is the mean of the one-sided integrands (the limit of a central difference).

Design variables (:class:`~prbdm_pin.member.design.Design`, lengths fixed): as in
:mod:`.sections_design_derivatives`, dI/dp = -∫ S_w / S^2 dw/dp dx plus, for a moving width
step, the jump of 1 / S it carries across x. dw/dp is linear on every piece (a vertex interval
cut at the span ends), so

- z (in-plane, S = t b^3 / 12, b = 2 w): exact in closed form, with b linear from b_u to b_v,
  ``∫_0^1 (1 - tau) / b^4 = (b_u + 2 b_v) / (6 b_u^3 b_v^2)`` and
  ``∫_0^1 tau / b^4 = (b_v + 2 b_u) / (6 b_u^2 b_v^3)``;
- x (torsion, S = J(b, t)): the same 16-point Gauss rule as the springs themselves, with
  d(1 / J) = -(J_b db + J_t dt) / J^2 and J_b, J_t from the series
  (:func:`prbdm_pin.member.section_derivatives.torsion_constant_gradient`);
- y: :func:`.sections_design_derivatives.finite_segment_design_gradient`.

Thickness and the material in closed form: K_z is proportional to E t, K_x to G = E / (2 (1 + nu)).
"""

from __future__ import annotations

import numpy as np

from ..io.records import readonly_array
from ..member.design import Design
from ..member.geometry import Beam
from ..member.section import torsion_constant_m4
from ..member.section_derivatives import torsion_constant_gradient
from ..member.section_law import section_properties
from ..options.choices import MIN_FRACTION
from .layout import validate_lengths
from .sections_derivatives import finite_segment_stiffness_gradient
from .sections_design_derivatives import (
    _check_design,
    _pieces,
    _steps,
    _width_variations,
    finite_segment_design_gradient,
)
from .spatial_stiffness import _GL_T, _GL_W, axis_stiffness

__all__ = ["axis_stiffness_gradient", "axis_stiffness_design_gradient"]


def _modulus(beam: Beam, axis: str) -> float:
    return beam.material.E_Pa if axis == "z" else beam.material.G_Pa


def _inverse_section(beam: Beam, half_width_m: np.ndarray, axis: str) -> np.ndarray:
    """1 / S of the section of half-width ``half_width_m`` (m): 1 / I_z or 1 / J, 1/m^4."""
    t_u = beam.uniform_thickness_m("the spatial springs' derivatives")
    b, t = 2.0 * np.asarray(half_width_m, dtype=float), t_u
    if axis == "z":
        return 12.0 / (t * b**3)
    return 1.0 / torsion_constant_m4(b, t)


def _check_axis(axis: str) -> None:
    if axis not in ("x", "y", "z"):
        raise ValueError(f"axis = {axis!r}: must be 'x', 'y' or 'z'")


def axis_stiffness_gradient(beam: Beam, lengths_m: np.ndarray, axis: str,
                            K: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Return one axis' finite-segment springs and their derivatives in the joint stations.

    Parameters
    ----------
    beam : Beam
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m.
    axis : {"y", "z", "x"}
        Out-of-plane bending, in-plane bending or torsion.
    K : ndarray, shape (n,), optional
        ``axis_stiffness(beam, lengths_m, axis)`` when already computed, N m/rad.

    Returns
    -------
    K : ndarray, shape (n,)
        The springs, N m/rad.
    dK : ndarray, shape (n, n)
        Entry [j, l]: d K_j / d x_(l+1), N m/rad per m.
    """
    _check_axis(axis)
    lengths = np.asarray(lengths_m, dtype=float)
    if axis == "y":
        return finite_segment_stiffness_gradient(beam, lengths, K)
    if K is None:
        K = axis_stiffness(beam, lengths, axis)
    n = K.size
    if n == 1:  # the one span is [0, L]: nothing moves
        return K, np.zeros((1, 1))
    ends = np.add.accumulate(lengths)
    inner = (ends - 0.5 * lengths)[1:n]  # c_1 .. c_(n-1)
    C = _modulus(beam, axis)
    if beam.section is not None:  # the integrand 1 / (E I_z or G J) of the section law: C = 1
        sp = section_properties(beam, inner)
        g, C = 1.0 / (sp.EI_z_Nm2 if axis == "z" else sp.GJ_Nm2), 1.0
    elif beam.step_index.size:  # the mean of the one-sided integrands at a step
        g = 0.5 * (_inverse_section(beam, beam.half_width_at(inner, "left"), axis)
                   + _inverse_section(beam, beam.half_width_at(inner, "right"), axis))
    else:  # the fit's inner loop: one interpolation
        g = _inverse_section(beam, np.interp(inner, beam.x_m, beam.half_width_m), axis)
    dI_dc = 0.5 * g  # dc_i / dx = 1/2 for both stations of c_i
    # spring j's span ends at c_(j+1) (+), spring j + 1's starts there (-): each c_i moves
    # stations i and i + 1 (columns i - 1 and i)
    dI = np.zeros((n, n))
    j = np.arange(n - 1)
    for col in (j, j + 1):
        dI[j, col] += dI_dc
        dI[j + 1, col] -= dI_dc
    return K, -(K * K / C)[:, None] * dI


def axis_stiffness_design_gradient(beam: Beam, design: Design, lengths_m: np.ndarray,
                                   axis: str, min_fraction: float = MIN_FRACTION
                                   ) -> tuple[np.ndarray, np.ndarray]:
    """Return one axis' finite-segment springs and their derivatives in the design variables.

    The lengths are held fixed (see the module docstring for how each axis is differentiated).

    Parameters
    ----------
    beam : Beam
        ``design.beam_at(p)``: the design at which the derivatives are taken.
    design : Design
        The design variables (thickness, half_width[i], x[i], E, rho, nu).
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m.
    axis : {"y", "z", "x"}
        Out-of-plane bending, in-plane bending or torsion.
    min_fraction : float
        Eq. 15's bound the lengths are checked against.

    Returns
    -------
    K : ndarray, shape (n,)
        The springs, N m/rad.
    dK : ndarray, shape (n, nv)
        Their derivatives, N m/rad per SI unit of each variable.
    """
    _check_axis(axis)
    if axis == "y":
        return finite_segment_design_gradient(beam, design, lengths_m, min_fraction)
    _check_design(beam, design)
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    K = axis_stiffness(beam, lengths, axis)
    bounds = lengths.cumsum() - 0.5 * lengths
    bounds[0] = 0.0
    bounds[-1] = beam.length_m
    u, v, span, k = _pieces(beam, bounds)
    x, w = beam.x_m, beam.half_width_m
    slope = (w[k + 1] - w[k]) / (x[k + 1] - x[k])  # a piece lies in one vertex interval
    t = beam.uniform_thickness_m("the spatial springs' derivatives")
    d_thick = np.zeros(K.size)  # dI/dt at fixed widths
    if axis == "z":
        bu, bv = 2.0 * (w[k] + slope * (u - x[k])), 2.0 * (w[k] + slope * (v - x[k]))
        db = 2.0 * _width_variations(beam, design, k, np.stack([u, v], axis=1))  # (nv, P, 2)
        weight_u = (bu + 2.0 * bv) / (6.0 * bu**3 * bv**2)
        weight_v = (bv + 2.0 * bu) / (6.0 * bu**2 * bv**3)
        per_piece = -(36.0 / t) * (v - u) * (db[..., 0] * weight_u + db[..., 1] * weight_v)
    else:
        xg = u[:, None] + (v - u)[:, None] * (0.5 * (_GL_T + 1.0))
        b = 2.0 * (w[k][:, None] + slope[:, None] * (xg - x[k][:, None]))
        J, J_b, J_t = torsion_constant_gradient(b, t)
        gw = (0.5 * _GL_W) * (v - u)[:, None] / (J * J)  # Gauss weights times 1 / J^2
        db = 2.0 * _width_variations(beam, design, k, xg)  # (nv, P, 16)
        per_piece = -np.einsum("pg,vpg->vp", gw * J_b, db)
        d_thick = np.bincount(span, -(gw * J_t).sum(axis=1), K.size)
    dI = np.zeros((K.size, design.size))
    np.add.at(dI, span, per_piece.T)
    for row, _, wl, wr, spans in _steps(beam, design, bounds):
        jump = float(_inverse_section(beam, wl, axis) - _inverse_section(beam, wr, axis))
        for s, weight in spans:
            dI[s, row] += weight * jump
    C = _modulus(beam, axis)
    integral = C / K
    dK = -(K / integral)[:, None] * dI
    nu = beam.material.nu
    for row, (kind, _) in enumerate(design.kinds):
        if kind == "thickness":
            # I_z is proportional to t; J's thickness derivative came through the rule
            dK[:, row] = K / t if axis == "z" else -(K / integral) * d_thick
        elif kind == "E":
            dK[:, row] = K / beam.material.E_Pa
        elif kind == "nu":
            dK[:, row] = 0.0 if axis == "z" else -K / (1.0 + nu)
    return K, readonly_array(dK)
