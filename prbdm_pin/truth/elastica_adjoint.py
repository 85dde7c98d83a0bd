"""The adjoint of the elastica's tangent equation (see ``elastica_gradient``) and its section law.

The section law it linearises is the curvature kappa(M) of each section, whose slope
d kappa / d M is the tangent compliance 1 / (EI (r + eta r_eta / 2)) (1 / EI without the
anticlastic restraint).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_bvp

from ..errors import SolveError
from ..member.geometry import Beam
from .anticlastic import section_state
from .elastica import ElasticaPrimal

__all__ = ["adjoint", "section_at"]


def section_at(pr: ElasticaPrimal, beam: Beam, w: np.ndarray,
               m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return ``anticlastic.section_state`` (kappa in 1/m, r, eta r_eta, r_nu) of sections.

    The sections are the primal's, of half-widths ``w`` (m) under moments ``m`` (N m).
    """
    t_u = beam.uniform_thickness_m("the elastica")
    return section_state(m, pr.ei_per_width * w, w, t_u, beam.material.nu,
                         pr.anticlastic)


def _compliance(pr: ElasticaPrimal, beam: Beam, i: int, s: np.ndarray,
                m: np.ndarray) -> np.ndarray:
    """Return the tangent compliance d kappa / d M (1/(N m^2)) of segment i at stations s (m).

    The sections are under moments m (N m).
    """
    w = np.interp(s, pr.seg_x[i], pr.seg_w[i])
    _, r, eta_dr, _ = section_at(pr, beam, w, m)
    return 1.0 / (pr.ei_per_width * w * (r + 0.5 * eta_dr))


def adjoint(pr: ElasticaPrimal, beam: Beam, F: np.ndarray,
            tol: float) -> tuple[object, float, float]:
    """Solve the adjoints (lam, mom) of the tip's x and z on the primal's mesh.

    Parameters
    ----------
    pr : ElasticaPrimal
        The converged elastica.
    beam : Beam
        The beam the elastica was solved for.
    F : ndarray, shape (3,)
        Its tip force, N.
    tol : float
        Collocation tolerance of ``solve_bvp``.

    Returns
    -------
    sol, lam_scale, mom_scale
        A solve_bvp solution whose rows 4 i .. 4 i + 3 are lam_x, mom_x, lam_z, mom_z on
        segment i, scaled by ``lam_scale`` = L^2 / EI_root (lam, 1/N) and ``mom_scale`` = L
        (mom, m).
    """
    beam.uniform_thickness_m("the elastica's sensitivities")  # pr.ei_per_width: one t
    L = beam.length_m
    cuts = pr.cuts
    a, ell = cuts[:-1], np.diff(cuts) / L
    nseg = ell.size
    ei_root = beam.root_EI_Nm2
    lam_s, mom_s = L**2 / ei_root, L

    def rhs(tau, y):
        out = np.empty_like(y)
        prim = pr.sol.sol(tau)
        for i in range(nseg):
            phi = prim[4 * i]
            c = _compliance(pr, beam, i, a[i] + ell[i] * tau, prim[4 * i + 1] * pr.m_scale)
            g = F[0] * np.cos(phi) + F[2] * np.sin(phi)
            for j, ce in ((0, -np.sin(phi)), (2, np.cos(phi))):
                lam, mom = y[4 * i + j] * lam_s, y[4 * i + j + 1] * mom_s
                out[4 * i + j] = ell[i] * c * mom / lam_s
                out[4 * i + j + 1] = ell[i] * (g * lam + ce) / mom_s
        return out

    def bc(ya, yb):
        joins = [ya[4 * (i + 1): 4 * (i + 2)] - yb[4 * i: 4 * (i + 1)] for i in range(nseg - 1)]
        last = 4 * (nseg - 1)
        return np.concatenate([[ya[0], ya[2], yb[last + 1], yb[last + 3]], *joins])

    tau = pr.sol.x
    sol = solve_bvp(rhs, bc, tau, np.zeros((4 * nseg, tau.size)), tol=tol, max_nodes=200_000,
                    bc_tol=tol)
    if sol.status != 0:
        raise SolveError(f"elastica adjoint did not converge on {beam.name!r}: {sol.message}")
    return sol, lam_s, mom_s
