"""Small vibrations of the elastica about its sag under its own weight (and a dead tip force).

The inextensible member's centreline angle is phi(s) = phi_0(s) + theta(s, t), phi_0 the
equilibrium (:func:`prbdm_pin.truth.elastica.elastica_primal` with ``gravity_m_s2``), theta a
small motion with theta(0) = 0. Its energy to second order in theta (the first order vanishes at
the equilibrium):

    V_2 = 1/2 int EI theta'^2 ds + 1/2 int N(s) theta^2 ds,
    N(s) = (F + g m_out(s)) . (cos phi_0, sin phi_0),

N the axial tension (the internal force along the tangent; m_out the mass outboard of s), and
the kinetic energy T = 1/2 int rho A |r_t|^2 ds with r_t(s) = int_0^s (-sin phi_0, cos phi_0)
theta_t ds'. theta on quadratic Lagrange elements (edges on the 1D beam's stations) gives
K = int EI psi_i' psi_j' + N psi_i psi_j and the dense M = int rho A R_i . R_j,
R_i(s) = int_0^s n(s') psi_i(s') ds'; the frequencies are those of (K, M).

About the straight member (g along it, no sag) this is the prestressed beam of
:mod:`prbdm_pin.truth.beam_gravity` in the angle theta = w'; about a sag it is the member's own
linearisation there, what a chain's frequencies about its sag are compared with.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from .beam import _check_count, beam_stations
from .elastica import elastica_primal
from .result import StaticSolution
from .self_weight import check_gravity, outboard_mass_kg

__all__ = ["elastica_gravity_modes"]

# Gauss points per element: psi psi' EI is of degree 5 on a tapered element, and N(s), phi_0(s)
# are smooth: 6 points leave the quadrature error far below the elements' h^4
_NQ = 6


def _phi0(pr, s: np.ndarray) -> np.ndarray:
    """Return the equilibrium angle phi_0 (rad) at arc lengths ``s`` (m), from the collocation."""
    L = pr.cuts[-1]
    i = np.clip(np.searchsorted(pr.cuts, s, side="right") - 1, 0, pr.cuts.size - 2)
    out = np.empty_like(s)
    for k in np.unique(i):
        on = i == k
        tau = (s[on] - pr.cuts[k]) * L / (pr.cuts[k + 1] - pr.cuts[k])
        out[on] = pr.sol.sol(tau)[4 * k]
    return out


def _shape(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quadratic Lagrange shape functions (3, q) at xi in [0, 1] and their d/dxi."""
    N = np.array([2 * (xi - 0.5) * (xi - 1), -4 * xi * (xi - 1), 2 * xi * (xi - 0.5)])
    dN = np.array([4 * xi - 3, -8 * xi + 4, 4 * xi - 1])
    return N, dN


def elastica_gravity_modes(beam: Beam, gravity_m_s2, tip_force_N=None, n_modes: int = 3,
                           n_elements: int = 100) -> tuple[np.ndarray, StaticSolution]:
    """Return the bending frequencies about the sag (rad/s) and the sag itself.

    Parameters
    ----------
    beam : Beam
    gravity_m_s2 : array_like (3,)
        Gravity, m/s^2, member axes (g_y = 0).
    tip_force_N : array_like (3,), optional
        A dead tip force, N (default none).
    n_modes : int
        Number of frequencies, lowest first.
    n_elements : int
        About this many elements along the span (the 1D beam's stations). The quadratic
        elements converge as h^4 (tests/truth/test_truth_sag_modes.py); the dense mass matrix
        costs n^2 memory and n^3 time.

    Returns
    -------
    omega_rad_s : ndarray (n_modes,)
        Ascending, rad/s.
    static : StaticSolution
        The elastica's tip under the weight and the tip force (m).

    Raises
    ------
    BeamInputError
        A bad argument (naming it), or an equilibrium that is not stable (it buckles).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> omega, sag = pp.elastica_gravity_modes(beam, [0.0, 0.0, -9.81], n_modes=2, n_elements=40)
    >>> EI, rho_A = 205e9 * 0.05 * 0.01**3 / 12, 7850.0 * 0.05 * 0.01  # N m^2, kg/m
    >>> eb = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, Euler-Bernoulli
    >>> omega.round(1), eb.round(1)  # rad/s: a sag this small barely moves them
    (array([ 51.9, 325.1]), array([ 51.9, 325.1]))
    >>> q = rho_A * 9.81  # N/m: a 5.6 mm sag, small against L, so the linear q L^4 / (8 EI)
    >>> round(float(sag.tip_displacement_m[2]) * 1e3, 3), round(-q / (8 * EI) * 1e3, 3)  # mm
    (-5.635, -5.635)
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r:.60}: must be a prbdm_pin.Beam")
    g = check_gravity(gravity_m_s2)
    F = np.zeros(3) if tip_force_N is None else np.asarray(tip_force_N, dtype=float)
    n_modes = _check_count("n_modes", n_modes)
    pr = elastica_primal(beam, F, gravity_m_s2=g)
    xs = beam_stations(beam, n_elements)
    ne = xs.size - 1
    h = np.diff(xs)
    gx, gw = np.polynomial.legendre.leggauss(_NQ)
    xi, wq = 0.5 * (gx + 1.0), 0.5 * gw
    N, dN = _shape(xi)
    # quadrature points and weights of every element (ne, q)
    s = xs[:-1, None] + h[:, None] * xi[None]
    w = h[:, None] * wq[None]
    phi = _phi0(pr, s.ravel()).reshape(s.shape)
    half = beam.half_width_at(s)
    t_u = beam.uniform_thickness_m("the elastica modes")
    t, E, rho = t_u, beam.material.E_Pa, beam.material.rho_kg_m3
    EI, rhoA = E * 2 * half * t**3 / 12.0, rho * 2 * half * t
    m_out = outboard_mass_kg(beam, s)
    tension = (F[0] + g[0] * m_out) * np.cos(phi) + (F[2] + g[2] * m_out) * np.sin(phi)
    ndof = 2 * ne + 1
    dofs = 2 * np.arange(ne)[:, None] + np.arange(3)[None]  # (ne, 3)
    K = np.zeros((ndof, ndof))
    for e in range(ne):
        B = dN / h[e]
        ke = (B * (EI[e] * w[e])) @ B.T + (N * (tension[e] * w[e])) @ N.T
        K[np.ix_(dofs[e], dofs[e])] += ke
    # R(s) = int_0^s n psi: the whole elements before, and each point's part of its own
    # element by a Gauss rule on [element start, point]
    nvec = np.stack([-np.sin(phi), np.cos(phi)])  # (2, ne, q)
    full = np.zeros((ne + 1, ndof, 2))
    R = np.zeros((ne, _NQ, ndof, 2))
    for e in range(ne):
        ss = xs[e] + np.outer(xi, xi) * h[e]  # (point, sub-point) along [start, point]
        ph = _phi0(pr, ss.ravel()).reshape(ss.shape)
        Nsub = _shape(np.outer(xi, xi).ravel())[0].reshape(3, _NQ, _NQ)
        ws = (xi * h[e])[:, None] * wq[None]  # sub-weights of each point's interval
        part = np.einsum("jpr,pr,cpr->pjc", Nsub, ws, np.stack([-np.sin(ph), np.cos(ph)]))
        R[e] = full[e][None]
        R[e][:, dofs[e]] += part
        whole = np.einsum("jq,q,cq->jc", N, w[e], nvec[:, e])
        full[e + 1] = full[e]
        full[e + 1][dofs[e]] += whole
    M = np.einsum("eq,eqic,eqjc->ij", rhoA * w, R, R)
    free = np.arange(1, ndof)  # theta(0) = 0: the clamp
    n = free.size
    k = min(n_modes, n)
    try:
        # the largest mu = 1 / omega^2 of M phi = mu K phi: the lowest modes of K phi =
        # omega^2 M phi would lose EPS omega_max^2 / omega_1^2 (3e-7 at 100 elements) to
        # rounding (as in truth.beam)
        mu = scipy.linalg.eigh(M[np.ix_(free, free)], K[np.ix_(free, free)],
                               eigvals_only=True, subset_by_index=[n - k, n - 1])
        lam = 1.0 / mu[::-1]
    except np.linalg.LinAlgError:  # K not positive definite: buckled
        lam = np.array([-1.0])
    if not lam[0] > 0.0:
        raise BeamInputError(f"gravity_m_s2 = {g.tolist()}, tip_force_N = {F.tolist()}: the "
                             "sagged member is not stable (it buckles): no vibration about it")
    return np.sqrt(lam), pr.static
