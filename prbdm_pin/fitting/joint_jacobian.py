"""The analytic Jacobian of the ``joint`` residuals over x = [u (n), ln s (n)].

The residuals depend on u through the joint stations (stick-breaking lengths, their cumulative
sums) and through the finite-segment springs K0(x), and on ln s through the springs k = s K0::

    dr/du = (dr/dx + dr/dk diag(s) dK0/dx) dx/du,   dr/d ln s = dr/dk diag(k),

with dr/dx and dr/dk from :mod:`prbdm_pin.chain.chain_derivatives` (eigen residuals: mode
derivatives at
each pose; tip residuals: implicit differentiation of each load case's equilibrium) and, with
``gain_points``, :mod:`prbdm_pin.chain.amplitude_derivatives` (each mode's tip amplitude: the
modal expansion of its shape's derivative).
"""

from __future__ import annotations

import numpy as np

from ..chain.amplitude_derivatives import tip_amplitude_gradients
from ..chain.chain_derivatives import frequency_gradients, static_tip_gradient
from ..chain.sections_derivatives import finite_segment_stiffness_gradient, planar_sections_gradient

__all__ = ["unit_lengths_jacobian", "joint_residual_jacobian"]


def unit_lengths_jacobian(u: np.ndarray, length_m: float, min_fraction: float) -> np.ndarray:
    """Return d lengths / d u of ``problem.lengths_from_unit``, m, shape (n+1, n).

    Link j takes ``e_j = u_j r_j`` of the excess r_j still unassigned (r_(j+1) = r_j - e_j), the
    last link the rest; u is clipped to [0, 1] there, so the derivative is the one inside.
    """
    u = np.asarray(u, dtype=float).tolist()
    n = len(u)
    rest = length_m - (n + 1) * min_fraction * length_m
    # Python floats (the same IEEE arithmetic): numpy's call overhead would dominate n^2 products
    d_rest = [0.0] * n
    rows = []
    for j, uj in enumerate(u):
        uj = min(max(uj, 0.0), 1.0)
        de = [uj * d for d in d_rest]
        de[j] += rest
        rows.append(de)
        rest -= uj * rest
        d_rest = [a - b for a, b in zip(d_rest, de, strict=True)]
    rows.append(d_rest)
    return np.array(rows).reshape(n + 1, n)


def joint_residual_jacobian(res, x: np.ndarray, chain: tuple, static_poses: list
                            ) -> np.ndarray:
    """Return the Jacobian (size, 2n) of ``res.residuals`` (a :class:`JointResiduals`) at x.

    It reuses what the residuals computed there: ``chain`` = (link lengths (m) and spring
    factors of x, ``planar_sections``, unit springs K0 (N m/rad), mass matrices at the poses
    (kg m^2), ``chain_points`` at the poses) and the equilibrium of each load case (rad,
    ``static_poses``).

    Raises SolveError or LinAlgError where the model cannot be solved (the caller decides).
    """
    p, spec = res.p, res.spec
    n = p.n_joints
    lengths, s, sections, K0, M, points = chain
    sec = planar_sections_gradient(p.beam, lengths, sections)
    K0, dK0 = finite_segment_stiffness_gradient(p.beam, lengths, K0)
    k = s * K0
    dx_du = np.add.accumulate(unit_lengths_jacobian(x[:n], p.length_m, p.min_fraction))[:-1]
    dk_dx = s[:, None] * dK0  # springs per station, at fixed s
    out = np.empty((res.size(), 2 * n))

    def chain_rule(rows: slice, scale, d_x: np.ndarray, d_k: np.ndarray) -> None:
        """Write scale [dr/du, dr/d ln s] from the derivatives at fixed springs and stations."""
        np.multiply(scale, (d_x + d_k @ dk_dx) @ dx_du, out=out[rows, :n])
        np.multiply(scale, d_k * k, out=out[rows, n:])

    row = 0
    if spec.objective.has_eigen_term:
        lam, d_x, d_k = frequency_gradients(lengths, sec, k, p.poses_rad, M, points)
        N = p.n_freq
        lam, d_x, d_k = lam[:, :N], d_x[:, :N], d_k[:, :N]
        if not p.squared:  # d omega = d lam / (2 omega)
            f = 0.5 / np.sqrt(lam)[..., None]
            d_x, d_k = d_x * f, d_k * f
        row = p.n_poses * N
        chain_rule(slice(0, row), res.eigen_row_scale, d_x.reshape(-1, n), d_k.reshape(-1, n))
    for case, q, scale in zip(res.cases, static_poses, res.tip_scale, strict=True):
        _, _, dtip = static_tip_gradient(lengths, k, case.tip_force_N, q)
        chain_rule(slice(row, row + 3), scale, dtip[:, :n], dtip[:, n:])
        row += 3
    term = res.gains
    if term is not None:  # one point (tip), at the straight pose (the only pose)
        a, d_x, d_k = tip_amplitude_gradients(lengths, sec, k, M[0], points)
        rows = term.rows
        # r = w (s a - a_truth) / norm: the sign s as the residual aligned it
        scale = (term.weight * term.signs(a[rows, None]) / term.norm)[:, None]
        chain_rule(slice(row, row + rows.size), scale, d_x[rows], d_k[rows])
    return out
