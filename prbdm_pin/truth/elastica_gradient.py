"""``elastica_gradient``: the large-deflection (elastica) tip and its design and load gradients.

The elastica ``elastica_static`` solves, in the undeformed arc length s (= x, inextensible),
phi' = C M and M' = F_x sin phi - F_z cos phi with phi(0) = 0, M(L) = 0, C = 1 / EI(s), and the
tip is r(L) = int (cos phi, sin phi) ds. A design change dC(s) perturbs it by psi = d phi,
mu = d M: psi' = C mu + dC M, mu' = g psi + (dF_x sin phi - dF_z cos phi), g = F_x cos phi +
F_z sin phi, psi(0) = 0, mu(L) = 0, and d r_e = int c_e psi ds with c_x = -sin phi,
c_z = cos phi. With the adjoint (lam, mom) of each tip coordinate,

    lam' = C mom,  mom' = g lam + c_e,  lam(0) = 0,  mom(L) = 0,

(the tangent operator is self-adjoint) integration by parts gives

    d r_e = -int dC M mom ds + int lam (dF_x sin phi - dF_z cos phi) ds,

so two linear solves (x and z, one system) on the converged solution's mesh give the gradient
for every design variable and the tip load. dC = -dEI / EI^2: thickness 3 / t and E 1 / E
scalings, the half-width field's derivative at fixed s (a hat function of the vertex for a
half-width; -w'(s) times that hat for a station, the field stretching with its vertex), and at
a width step a moved station adds the point term -(C_left - C_right) M mom at the step (the
region left of the step grows). rho and nu do not enter the elastica itself.

``ei_scale`` is a factor on EI: a number is held fixed; ``"plate"`` is the calibrated elastica of
``compute_truth`` (the ratio u_1D / u_plate of the 1D beam's and the plate's linear tips), whose
derivative comes from ``truth_gradient``'s adjoint tips of both and enters through
d r / d scale = (E / scale) d r / d E (EI is proportional to both).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_bvp

from ..design import Design, step_partner
from ..errors import BeamInputError, SolveError
from ..geometry import Beam
from ..json_record import readonly_array as _ro
from .elastica import ElasticaPrimal, elastica_primal

__all__ = ["ElasticaGradient", "elastica_gradient"]

# Gauss-Legendre points per interval of the quadrature of the gradient integrals (every integrand
# is smooth between mesh nodes and vertices; the interpolants are cubic)
_GAUSS = np.polynomial.legendre.leggauss(4)


@dataclass(frozen=True, eq=False)
class ElasticaGradient:
    """The elastica's tip under a dead tip load and its derivatives.

    Attributes
    ----------
    names, units : tuple of str
        The design variables and their SI units.
    values : ndarray, shape (n,)
        The design variables' values (SI units).
    tip_force_N : ndarray, shape (3,)
    ei_scale : float
        The factor on EI.
    ei_scale_source : str
        ``"fixed"`` (a number, not differentiated) or ``"plate"`` (u_1D / u_plate of the linear
        tips, differentiated).
    d_ei_scale : ndarray, shape (n,)
        d ei_scale / d p_j (zero when fixed), per unit of variable j.
    tip_position_m : ndarray, shape (3,)
        Tip position (x, 0, z), m.
    d_tip_position_m : ndarray, shape (3, n)
        d tip_position / d p_j, m per unit of variable j (row y is zero).
    d_tip_d_force_m_per_N : ndarray, shape (3, 2)
        d tip_position / d (F_x, F_z), m/N.
    nodes : int
        Collocation nodes of the adjoint solve.
    solve_s, gradient_s : float
        Wall time of the elastica's solve and of all gradients after it (with
        ``ei_scale="plate"`` each includes the part of the two linear truths': ``truth_gradient``
        solves their modes too).
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    tip_force_N: np.ndarray
    ei_scale: float
    ei_scale_source: str
    d_ei_scale: np.ndarray
    tip_position_m: np.ndarray
    d_tip_position_m: np.ndarray
    d_tip_d_force_m_per_N: np.ndarray
    nodes: int
    solve_s: float
    gradient_s: float


def _adjoint(pr: ElasticaPrimal, beam: Beam, F: np.ndarray, tol: float):
    """Solve the adjoints (lam, mom) of the tip's x and z on the primal's mesh.

    Returns a solve_bvp solution whose rows 4 i .. 4 i + 3 are lam_x, mom_x, lam_z, mom_z on
    segment i, scaled by L^2 / EI_root (lam, 1/N) and L (mom, m).
    """
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
            s = a[i] + ell[i] * tau
            c = 1.0 / (pr.ei_per_width * np.interp(s, pr.seg_x[i], pr.seg_w[i]))
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


def _plate_scale(d: Design, mesh_level: int | None) -> tuple[float, np.ndarray, float, float]:
    """Return u_1D / u_plate of the linear tips under the beam's tip force, and its gradient.

    1 and zeros without a vertical load, as ``compute_truth`` sets it; also the wall times of
    the two truths' solves and of their gradients (s).
    """
    from .gradient import truth_gradient

    if d.beam.tip_force_N[2] == 0.0:
        return 1.0, np.zeros(d.size), 0.0, 0.0
    # modes=1: the fewest frequencies truth_gradient computes alongside its tips
    gb = truth_gradient(d.beam, d, model="beam", modes=1)
    gp = truth_gradient(d.beam, d, model="plate", modes=1, mesh_level=mesh_level)
    scale = gb.tip_z_m / gp.tip_z_m
    return (scale, (gb.d_tip_z_m - scale * gp.d_tip_z_m) / gp.tip_z_m,
            gb.solve_s + gp.solve_s, gb.gradient_s + gp.gradient_s)


def elastica_gradient(
    beam: Beam,
    design: Design | tuple[str, ...] | list[str],
    tip_force_N: np.ndarray | None = None,
    ei_scale: float | str = 1.0,
    tol: float = 1e-9,
    mesh_level: int | None = None,
) -> ElasticaGradient:
    """Compute the elastica's large-deflection tip and its design derivatives.

    The derivatives with respect to the design variables (and the tip load) come from the
    adjoint of the tangent equation.

    Parameters
    ----------
    beam : Beam
        The design point.
    design : Design or sequence of str
        The design variables (a ``Design`` of any beam of the same vertex structure, or its
        variable names); the gradient is taken at ``beam``.
    tip_force_N : array_like, shape (3,), optional
        Dead tip force in N (default ``beam.tip_force_N``); F_y must be 0.
    ei_scale : float or "plate"
        Factor on EI(x): a number (> 0, as ``elastica_static`` takes it) is held fixed;
        ``"plate"`` is u_1D / u_plate of the linear tips under ``beam.tip_force_N`` (the
        calibrated elastica of ``compute_truth``; 1 without a vertical load), differentiated.
    tol : float
        Collocation tolerance of the elastica and of its adjoint (``solve_bvp``).
    mesh_level : int, optional
        Plate mesh level of ``ei_scale="plate"`` (default: ``truth_gradient``'s); ignored
        otherwise.

    Returns
    -------
    ElasticaGradient

    Raises
    ------
    BeamInputError
        Bad arguments or design variables (named).
    SolveError
        The elastica or its adjoint did not converge.
    """
    if not isinstance(beam, Beam):
        raise BeamInputError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    names = design.names if isinstance(design, Design) else design
    if isinstance(names, str):
        names = tuple(n.strip() for n in names.split(","))
    d = Design(beam, tuple(names))
    if (isinstance(tol, bool) or not isinstance(tol, (int, float, np.floating))
            or not np.isfinite(tol) or not 0.0 < tol < 1e-2):
        raise BeamInputError(f"tol = {tol!r}: must be a number in (0, 0.01)")
    source = "fixed"
    d_scale = np.zeros(d.size)
    scale_solve_s = scale_gradient_s = 0.0
    if isinstance(ei_scale, str):
        if ei_scale != "plate":
            raise BeamInputError(f"ei_scale = {ei_scale!r}: must be a number > 0 or 'plate'")
        ei_scale, d_scale, scale_solve_s, scale_gradient_s = _plate_scale(d, mesh_level)
        source = "plate"
    t0 = time.perf_counter()
    pr = elastica_primal(beam, tip_force_N, tol=float(tol), ei_scale=ei_scale)
    F = pr.static.tip_force_N
    t1 = time.perf_counter()
    adj, lam_s, mom_s = _adjoint(pr, beam, F, float(tol))

    L = beam.length_m
    cuts = pr.cuts
    a, ell = cuts[:-1], np.diff(cuts) / L
    nseg = ell.size
    first = [0] + [int(k) + 1 for k in beam.step_index]  # global index of each segment's vertex 0
    gx, gw = _GAUSS
    n = d.size
    d_tip = np.zeros((3, n))
    d_force = np.zeros((3, 2))
    d_by_scale = np.zeros(3)  # d r / d ei_scale
    for i in range(nseg):
        xs, ws = pr.seg_x[i], pr.seg_w[i]
        # quadrature intervals: both meshes and the segment's vertices (EI kinks), in tau
        nodes = np.unique(np.concatenate([pr.sol.x, adj.x, (xs - a[i]) / ell[i]]))
        nodes = nodes[(nodes >= 0.0) & (nodes <= L)]
        mid, half = 0.5 * (nodes[1:] + nodes[:-1]), 0.5 * np.diff(nodes)
        tau = (mid[:, None] + half[:, None] * gx[None, :]).ravel()
        wq = (half[:, None] * gw[None, :]).ravel() * ell[i]  # ds weights
        s = a[i] + ell[i] * tau
        prim, ad = pr.sol.sol(tau), adj.sol(tau)
        phi, m = prim[4 * i], prim[4 * i + 1] * pr.m_scale
        w = np.interp(s, xs, ws)
        c = 1.0 / (pr.ei_per_width * w)
        lam = np.stack([ad[4 * i] * lam_s, ad[4 * i + 2] * lam_s])  # (x, z)
        mom = np.stack([ad[4 * i + 1] * mom_s, ad[4 * i + 3] * mom_s])
        d_force[[0, 2], 0] += (lam * np.sin(phi)) @ wq
        d_force[[0, 2], 1] -= (lam * np.cos(phi)) @ wq
        d_by_scale[[0, 2]] += (c / ei_scale * m * mom) @ wq
        # slope of the width field on each quadrature point's vertex interval
        k = np.clip(np.searchsorted(xs, s, side="right") - 1, 0, xs.size - 2)
        slope = np.diff(ws) / np.where(np.diff(xs) > 0.0, np.diff(xs), np.inf)
        slope = slope[k]
        local = range(first[i], first[i] + xs.size)
        for row, (kind, j) in enumerate(d.kinds):
            if kind == "thickness":
                dc = -3.0 * c / beam.thickness_m
            elif kind == "E":
                dc = -c / beam.material.E_Pa
            elif kind in ("rho", "nu"):
                continue
            else:
                moved = [j] if kind == "half_width" else [j, step_partner(beam, j)]
                moved = [v - first[i] for v in moved if v is not None and v in local]
                if not moved:
                    continue
                dw = np.zeros_like(s)
                for v in moved:
                    e = np.zeros(xs.size)
                    e[v] = 1.0
                    hat = np.interp(s, xs, e)
                    dw += hat if kind == "half_width" else -slope * hat
                dc = -c * dw / w
            d_tip[[0, 2], row] -= (dc * m * mom) @ wq
    # a moved width step: the region left of it (compliance C_left) grows into C_right's
    for row, (kind, j) in enumerate(d.kinds):
        if kind != "x" or step_partner(beam, j) is None:
            continue
        i = int(np.flatnonzero(beam.step_index == min(j, step_partner(beam, j)))[0])
        end = np.array([L])
        m = float(pr.sol.sol(end)[4 * i + 1, 0]) * pr.m_scale
        ad = adj.sol(end)[:, 0]
        mom = np.array([ad[4 * i + 1], ad[4 * i + 3]]) * mom_s
        c_left = 1.0 / (pr.ei_per_width * pr.seg_w[i][-1])
        c_right = 1.0 / (pr.ei_per_width * pr.seg_w[i + 1][0])
        d_tip[[0, 2], row] -= (c_left - c_right) * m * mom
    d_tip += np.outer(d_by_scale, d_scale)
    t2 = time.perf_counter()
    return ElasticaGradient(
        names=d.names, units=d.units, values=_ro(d.values), tip_force_N=_ro(F),
        ei_scale=float(ei_scale), ei_scale_source=source, d_ei_scale=_ro(d_scale),
        tip_position_m=_ro(pr.static.tip_position_m),
        d_tip_position_m=_ro(d_tip), d_tip_d_force_m_per_N=_ro(d_force),
        nodes=int(adj.x.size), solve_s=t1 - t0 + scale_solve_s,
        gradient_s=t2 - t1 + scale_gradient_s,
    )
