"""Derivatives of the link sections and finite-segment springs in a design's variables.

The variables are those of a :class:`~prbdm_pin.member.design.Design` (thickness, half_width[i],
x[i], E,
rho, nu); the link lengths are held fixed.

Thickness and the material enter in closed form: the masses and inertias are rho t times
planform integrals plus the thickness term m t^2 / 12, the mean area moment is A t^3 / (12 h) and
a spring E (2 t^3 / 12) / ∫ dx / w; nu enters none of them. A half-width or a station moves the
outline: every quantity is ∫_a^b g(w(x), x) dx over a fixed span [a, b], so its derivative is

    ∫_a^b g_w(w, x) dw/dp dx  +  sum over moving width steps X in [a, b] of (g(w_L) - g(w_R)),

where dw/dp is the hat function of the vertex (half_width[i]: the vertex's own side of a step)
or, for a station moving its vertices V, ``-w'(x) sum_(v in V) N_v(x)``. Both are linear on each
vertex interval, so the first term is exact by two-point Gauss quadrature for the polynomial
integrands of the sections (degree <= 3, as in :mod:`.sections`) and in closed form for the
spring's 1 / w. The second term is the jump of the integrand that a moving width step carries
across x; where the step sits exactly on a span end the two one-sided derivatives differ and the
derivative returned is their mean (half the jump to each span), as in :mod:`.section_gradients`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..io.records import readonly_array
from ..member.design import Design, step_partner
from ..member.geometry import Beam
from ..options.choices import MIN_FRACTION
from .layout import validate_lengths
from .sections import link_sections_unchecked
from .stiffness import finite_segment_stiffness_unchecked

__all__ = ["SectionDesignGradient", "section_design_gradient", "finite_segment_design_gradient"]

_GAUSS_T = np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)])  # on [0, 1]
_SERIES = 1e-3  # |r| below which psi(r) = (r - ln(1 + r)) / r^2 takes its series


@dataclass(frozen=True, eq=False)
class SectionDesignGradient:
    """The sections of n + 1 links and their derivatives with respect to a design's variables.

    Attributes
    ----------
    names, units : tuple of str
        The design variables and their SI units (``Design.names``, ``Design.units``).
    mass_kg, com_offset_m : ndarray, shape (n+1,)
        Link mass (kg) and centre-of-mass distance from the link's start (m), as
        :func:`sections.link_sections` computes them.
    inertia_xx_kg_m2, inertia_yy_kg_m2, inertia_zz_kg_m2 : ndarray, shape (n+1,)
        Inertia about the centre of mass around x, y and z (kg m^2).
    area_moment_m4 : ndarray, shape (n+1,)
        Mean bending area moment (m^4).
    d_mass_kg, d_com_offset_m, d_area_moment_m4 : ndarray, shape (n+1, nv)
        Entry [i, j]: derivative of link i's quantity per unit of variable j (its unit per the
        variable's unit).
    d_inertia_xx_kg_m2, d_inertia_yy_kg_m2, d_inertia_zz_kg_m2 : ndarray, shape (n+1, nv)
        The same for the inertias (kg m^2 per the variable's unit).
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    mass_kg: np.ndarray
    com_offset_m: np.ndarray
    inertia_xx_kg_m2: np.ndarray
    inertia_yy_kg_m2: np.ndarray
    inertia_zz_kg_m2: np.ndarray
    area_moment_m4: np.ndarray
    d_mass_kg: np.ndarray
    d_com_offset_m: np.ndarray
    d_inertia_xx_kg_m2: np.ndarray
    d_inertia_yy_kg_m2: np.ndarray
    d_inertia_zz_kg_m2: np.ndarray
    d_area_moment_m4: np.ndarray


def _check_design(beam: Beam, design: Design) -> None:
    if not isinstance(design, Design):
        raise InputTypeError(f"design = {design!r}: must be a prbdm_pin.Design")
    if beam.x_m.size != design.beam.x_m.size or not np.array_equal(
            np.diff(beam.x_m) == 0.0, np.diff(design.beam.x_m) == 0.0):
        raise BeamInputError(f"beam {beam.name!r}: must have the vertex structure of the "
                             "design's beam (design.beam_at(p))")


def _pieces(beam: Beam, bounds: np.ndarray):
    """Cut [0, L] at the span bounds (n_spans + 1,) and the planform vertices.

    Returns the non-empty pieces: their ends u, v (m), the span and the vertex interval k holding
    each.
    """
    x = beam.x_m
    cuts = np.sort(np.r_[x, bounds])
    u, v = cuts[:-1], cuts[1:]
    keep = v > u
    u, v = u[keep], v[keep]
    mid = 0.5 * (u + v)
    span = np.clip(np.searchsorted(bounds, mid, "right") - 1, 0, bounds.size - 2)
    k = np.clip(np.searchsorted(x, mid, "right") - 1, 0, x.size - 2)
    return u, v, span, k


def _width_variations(beam: Beam, design: Design, k: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """Return dw/dp_j (m per unit of p_j) at the points ``xs`` (P, G) for every variable j.

    The points lie in the vertex intervals ``k`` (P,). Shape (nv, P, G), zero for thickness and
    the material.
    """
    x, w = beam.x_m, beam.half_width_m
    x0, H = x[k][:, None], (x[k + 1] - x[k])[:, None]
    s = (xs - x0) / H
    slope = ((w[k + 1] - w[k]) / (x[k + 1] - x[k]))[:, None]

    def hat(i: int) -> np.ndarray:  # N_i on the interval k: 1 - s at its start, s at its end
        return np.where(k[:, None] == i, 1.0 - s, 0.0) + np.where(k[:, None] + 1 == i, s, 0.0)

    out = np.zeros((design.size,) + xs.shape)
    for row, (kind, i) in enumerate(design.kinds):
        if kind == "half_width":
            out[row] = hat(i)
        elif kind == "x":
            j = step_partner(beam, i)
            out[row] = -slope * (hat(i) + (hat(j) if j is not None else 0.0))
    return out


def _steps(beam: Beam, design: Design, bounds: np.ndarray):
    """List the moving width steps as (variable row, station X (m), w_L, w_R (m), spans).

    ``spans`` is a list of (span, weight) with weight 1 inside a span and 1/2 to each side of a
    span end.
    """
    out = []
    for row, (kind, i) in enumerate(design.kinds):
        j = step_partner(beam, i) if kind == "x" else None
        if j is None:
            continue
        lo, hi = min(i, j), max(i, j)
        X = float(beam.x_m[i])
        at = np.flatnonzero(bounds == X)
        if at.size:
            spans = [(s, 0.5) for s in (at[0] - 1, at[0]) if 0 <= s < bounds.size - 1]
        else:
            spans = [(int(np.searchsorted(bounds, X, "right") - 1), 1.0)]
        out.append((row, X, beam.half_width_m[lo], beam.half_width_m[hi], spans))
    return out


def _outline_integrals(beam: Beam, design: Design, bounds: np.ndarray) -> np.ndarray:
    """Differentiate the span integrals of the outline with respect to the outline variables.

    The integrals are those of 2 w, 2 w (x - m), 2 w (x - m)^2 and 2 w^3 / 3 (m the span's
    mid-point); shape (4, spans, nv).
    """
    u, v, span, k = _pieces(beam, bounds)
    mids = 0.5 * (bounds[:-1] + bounds[1:])
    h = v - u
    xg = u[:, None] + h[:, None] * _GAUSS_T
    wg = np.interp(xg, beam.x_m, beam.half_width_m)  # pieces never straddle a step
    xl = xg - mids[span][:, None]
    dw = _width_variations(beam, design, k, xg)  # (nv, P, 2)
    g_w = np.stack([np.full_like(xg, 2.0), 2.0 * xl, 2.0 * xl * xl, 2.0 * wg * wg])
    per_piece = np.einsum("rpg,vpg->rpv", g_w, dw) * (0.5 * h)[None, :, None]
    out = np.zeros((4, bounds.size - 1, design.size))
    np.add.at(out, (slice(None), span), per_piece)
    for row, X, wl, wr, spans in _steps(beam, design, bounds):
        for s, weight in spans:
            d = X - mids[s]
            g = np.array([2.0 * wl, 2.0 * wl * d, 2.0 * wl * d * d, 2.0 * wl**3 / 3.0])
            g -= np.array([2.0 * wr, 2.0 * wr * d, 2.0 * wr * d * d, 2.0 * wr**3 / 3.0])
            out[:, s, row] += weight * g
    return out


def section_design_gradient(beam: Beam, design: Design, lengths_m: np.ndarray,
                            min_fraction: float = MIN_FRACTION) -> SectionDesignGradient:
    """Return the exact sections of ``beam`` cut at ``lengths_m`` and their design derivatives.

    The derivatives are with respect to the variables of ``design`` at fixed lengths (see the
    module docstring).

    Parameters
    ----------
    beam : Beam
        ``design.beam_at(p)``: the design at which the derivatives are taken.
    design : Design
        The design variables.
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m.
    min_fraction : float
        Eq. 15's bound the lengths are checked against.

    Returns
    -------
    SectionDesignGradient
        The sections (kg, m, kg m^2, m^4) and their derivatives per SI unit of each variable.
    """
    _check_design(beam, design)
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    sec = link_sections_unchecked(beam, lengths)
    t, rho = beam.uniform_thickness_m("the design derivatives"), beam.material.rho_kg_m3
    rho_t = rho * t
    mass, h = sec.mass_kg, sec.length_m
    Ixx, Iyy, Izz = (sec.inertia_com_kg_m2[:, a, a] for a in range(3))
    offset = sec.com_m[:, 0] - sec.start_m
    # the planform integrals behind them: A = ∫ 2w, c the centre of mass from the mid-span
    A = mass / rho_t
    c = offset - 0.5 * h
    thick = mass * (t * t / 12.0)
    bounds = np.r_[0.0, sec.end_m]
    bounds[-1] = beam.length_m
    dA, dS1, dS2, dSyy = _outline_integrals(beam, design, bounds)
    dm = rho_t * dA
    dc = (dS1 - c[:, None] * dA) / A[:, None]
    dSc = dS2 - 2.0 * c[:, None] * dS1 + (c * c)[:, None] * dA  # about the centre of mass
    d_thick = dm * (t * t / 12.0)
    d = {"m": dm, "c": dc, "xx": rho_t * dSyy + d_thick, "yy": rho_t * dSc + d_thick,
         "zz": rho_t * (dSc + dSyy), "I": dA * (t**3 / 12.0) / h[:, None]}
    area = sec.area_moment_m4
    for row, (kind, _) in enumerate(design.kinds):
        if kind == "thickness":  # rho t scales everything but the t^3 terms
            d["m"][:, row] = mass / t
            d["xx"][:, row] = (Ixx + 2.0 * thick) / t
            d["yy"][:, row] = (Iyy + 2.0 * thick) / t
            d["zz"][:, row] = Izz / t
            d["I"][:, row] = 3.0 * area / t
        elif kind == "rho":
            for key, q in (("m", mass), ("xx", Ixx), ("yy", Iyy), ("zz", Izz)):
                d[key][:, row] = q / rho
    values = (mass, offset, Ixx, Iyy, Izz, area)
    derivatives = (d[key] for key in ("m", "c", "xx", "yy", "zz", "I"))
    return SectionDesignGradient(design.names, design.units,
                                 *(readonly_array(v) for v in (*values, *derivatives)))


def _psi(r: np.ndarray) -> np.ndarray:
    """(r - ln(1 + r)) / r^2, r > -1, with its series where the difference cancels."""
    r = np.asarray(r, dtype=float)
    small = np.abs(r) < _SERIES
    rs = np.where(small, 0.0, r)
    exact = (rs - np.log1p(rs)) / np.where(small, 1.0, rs * rs)
    series = 0.5 - r / 3.0 + r * r / 4.0 - r**3 / 5.0 + r**4 / 6.0
    return np.where(small, series, exact)


def finite_segment_design_gradient(beam: Beam, design: Design, lengths_m: np.ndarray,
                                   min_fraction: float = MIN_FRACTION
                                   ) -> tuple[np.ndarray, np.ndarray]:
    """Return the finite-segment springs and their derivatives in the design variables.

    The springs are K_j = E (2 t^3 / 12) / ∫_(c_j)^(c_(j+1)) dx / w (N m/rad, (n,),
    ``stiffness.finite_segment_stiffness``); their derivatives with respect to the variables of
    ``design`` are taken at fixed lengths, shape (n, nv), N m/rad per unit of each variable.

    On a piece [u, v] where w is linear, ∫ (dw/dp) / w^2 is exact from dw/dp at its ends:
    ``(v - u) (dw_u psi(r) / w_u^2 + dw_v psi(-r / (1 + r)) / w_v^2)``, r = w_v / w_u - 1,
    psi(r) = (r - ln(1 + r)) / r^2.

    Parameters
    ----------
    beam : Beam
        ``design.beam_at(p)``.
    design : Design
        The design variables.
    lengths_m : array_like, shape (n+1,)
        Valid link lengths, m.
    min_fraction : float
        Eq. 15's bound the lengths are checked against.

    Returns
    -------
    K : ndarray, shape (n,)
        The springs, N m/rad.
    dK : ndarray, shape (n, nv)
        Their derivatives, N m/rad per SI unit of each variable.
    """
    _check_design(beam, design)
    lengths = validate_lengths(beam, lengths_m, min_fraction)
    K = finite_segment_stiffness_unchecked(beam, lengths)
    bounds = lengths.cumsum() - 0.5 * lengths  # the springs' spans end at the links' mid-spans
    bounds[0] = 0.0
    bounds[-1] = beam.length_m
    u, v, span, k = _pieces(beam, bounds)
    # a piece's ends take its own interval's values (one-sided at a step)
    x, w = beam.x_m, beam.half_width_m
    slope = (w[k + 1] - w[k]) / (x[k + 1] - x[k])
    wu, wv = w[k] + slope * (u - x[k]), w[k] + slope * (v - x[k])
    dw = _width_variations(beam, design, k, np.stack([u, v], axis=1))  # (nv, P, 2)
    r = wv / wu - 1.0
    weight_u = _psi(r) / (wu * wu)  # ∫_0^1 (1 - tau) / w^2 dtau
    weight_v = _psi(wu / wv - 1.0) / (wv * wv)  # ∫_0^1 tau / w^2 dtau
    per_piece = -(v - u)[None] * (dw[..., 0] * weight_u + dw[..., 1] * weight_v)  # (nv, P)
    dI = np.zeros((K.size, design.size))
    np.add.at(dI, span, per_piece.T)
    for row, _, wl, wr, spans in _steps(beam, design, bounds):
        for s, weight in spans:
            dI[s, row] += weight * (1.0 / wl - 1.0 / wr)
    t_u = beam.uniform_thickness_m("the design derivatives")
    integral = beam.material.E_Pa * (2.0 * t_u**3 / 12.0) / K
    dK = -(K / integral)[:, None] * dI
    for row, (kind, _) in enumerate(design.kinds):
        if kind == "thickness":
            dK[:, row] = 3.0 * K / beam.uniform_thickness_m("the design derivatives")
        elif kind == "E":
            dK[:, row] = K / beam.material.E_Pa
    return K, readonly_array(dK)
