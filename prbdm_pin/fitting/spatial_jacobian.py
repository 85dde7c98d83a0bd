"""The analytic Jacobian of the spatial fit's eigen residual over x = [u (n), ln s (n m)].

The residual of :class:`~prbdm_pin.fitting.spatial_design.EigenTerm` is
r = omega_model / omega_truth - 1 for the selected modes, each paired with a mode of its axis
block (in order within the axis). A block's frequencies depend on u through the joint stations
(stick-breaking lengths, their cumulative sums) and through the axis' finite-segment springs
K0_a(x), and on the log factors of that axis only (k_a = s_a K0_a)::

    d omega / du     = (d omega/dx + d omega/dk_a diag(s_a) dK0_a/dx) dx/du,
    d omega / d ln s_a = d omega/dk_a diag(k_a),

with the block derivatives of :mod:`prbdm_pin.chain.spatial_modes_derivatives` and the springs'
of :mod:`prbdm_pin.chain.spatial_stiffness_derivatives`. The modes come from the closed-form
blocks (:mod:`prbdm_pin.chain.spatial_modes`), not from the Pinocchio model the residual uses:
the same matrices to rounding, without building a model per Jacobian.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..chain.sections_derivatives import planar_sections_gradient, roll_yaw_inertia_gradient
from ..chain.spatial_modes_derivatives import axis_frequency_gradients, axis_section_gradient
from ..chain.spatial_stiffness_derivatives import axis_stiffness_gradient
from .joint_jacobian import unit_lengths_jacobian
from .spatial_design import EigenTerm, SpatialDesign

__all__ = ["eigen_jacobian", "spatial_jacobian"]


def eigen_jacobian(design: SpatialDesign, term: EigenTerm, x: np.ndarray) -> np.ndarray:
    """Return d r / d x of the eigen residual ``term`` of ``design`` at x.

    Parameters
    ----------
    design : SpatialDesign
        The fit's design (beam, joints n, axes, bounds).
    term : EigenTerm
        The frequency term (its selection pairs the truth modes with the axis blocks).
    x : ndarray, shape (n + n m,)
        [u (unit box), ln s (node-major, the axes in :attr:`Axes.joint_order`)].

    Returns
    -------
    ndarray, shape (term.size, n + n m)
        Dimensionless: the residual is relative, u and ln s are dimensionless.
    """
    n, m, beam = design.n, design.m, design.beam
    x = np.asarray(x, dtype=float)
    u = x[:n]
    lengths = design.lengths(u)
    s = np.exp(x[n:]).reshape(n, m)
    dx_du = np.add.accumulate(unit_lengths_jacobian(u, beam.length_m, design.o.min_fraction))
    dx_du = dx_du[:-1]  # stations per u: the cumulative lengths of links 0..n-1
    planar = planar_sections_gradient(beam, lengths)
    roll_yaw = roll_yaw_inertia_gradient(beam, lengths, planar) if design.order != ("y",) \
        else None
    sel = term.sel
    out = np.zeros((term.size, x.size))
    for c, a in enumerate(design.order):
        rows = np.flatnonzero(sel.axis == a)
        if not rows.size:
            continue
        K0, dK0 = axis_stiffness_gradient(beam, lengths, a)
        k = s[:, c] * K0
        sec = axis_section_gradient(beam, lengths, a, planar, roll_yaw)
        lam, d_station, d_k = axis_frequency_gradients(beam, lengths, k, a, sec)
        p = rows.size
        scale = 0.5 / (np.sqrt(lam[:p]) * sel.omega_truth_rad_s[rows])  # d omega / d lam / w_t
        d_u = (d_station[:p] + d_k[:p] @ (s[:, c, None] * dK0)) @ dx_du
        out[rows, :n] = scale[:, None] * d_u
        out[rows, n + c::m] = scale[:, None] * d_k[:p] * k
    return out


def spatial_jacobian(design: SpatialDesign) -> Callable[[np.ndarray], np.ndarray] | str:
    """Return the ``jac`` argument of ``least_squares`` for ``design.residual``.

    The analytic Jacobian (:func:`eigen_jacobian`, stacked over the terms in their order) when
    every term is an :class:`EigenTerm` or has a ``jacobian(design, x)`` method and the springs
    are the ``joint`` ones; otherwise ``"2-point"`` (forward differences over the whole
    residual: the ``paper`` springs move with the lengths through the links' sections).
    """
    terms = design.terms
    if getattr(design, "paper", False) or not all(
            isinstance(t, EigenTerm) or hasattr(t, "jacobian") for t in terms):
        return "2-point"

    def jac(x: np.ndarray) -> np.ndarray:
        return np.vstack([eigen_jacobian(design, t, x) if isinstance(t, EigenTerm)
                          else t.jacobian(design, x) for t in terms])

    return jac
