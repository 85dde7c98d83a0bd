"""``elastica_gradient``: the large-deflection (elastica) tip and its design and load gradients.

The elastica ``elastica_static`` solves, in the undeformed arc length s (= x, inextensible),
phi' = kappa(M; s) and M' = F_x sin phi - F_z cos phi with phi(0) = 0, M(L) = 0, and the tip is
r(L) = int (cos phi, sin phi) ds. The section law M = EI kappa r(eta) gives kappa = M / EI(s)
for the plain elastica (r = 1) and, with ``anticlastic=True``, the root of it with Ashwell's
factor r(eta, nu), ``eta = w (3 (1 - nu^2))^(1/4) sqrt(|kappa| / t)`` (``anticlastic``). Its
tangent compliance is C = d kappa / d M = 1 / (EI (r + eta r_eta / 2)) (eta grows as
``sqrt(|kappa|)``), and a design change moves kappa at fixed M by::

    dk = -kappa (dEI / EI r + eta r_eta d ln eta + r_nu d nu) / (r + eta r_eta / 2),

d ln eta = dw / w - dt / (2 t) - nu d nu / (2 (1 - nu^2)). It perturbs the elastica by
psi = d phi, mu = d M: psi' = C mu + dk, mu' = g psi + (dF_x sin phi - dF_z cos phi),
g = F_x cos phi + F_z sin phi, psi(0) = 0, mu(L) = 0, and d r_e = int c_e psi ds with
c_x = -sin phi, c_z = cos phi. With the adjoint (lam, mom) of each tip coordinate::

    lam' = C mom,  mom' = g lam + c_e,  lam(0) = 0,  mom(L) = 0,

(the tangent operator is self-adjoint) integration by parts gives::

    d r_e = -int dk mom ds + int lam (dF_x sin phi - dF_z cos phi) ds,

so two linear solves (x and z, one system) on the converged solution's mesh give the gradient
for every design variable and the tip load. dEI / EI is 3 dt / t, dE / E and dw / w with the
half-width field's derivative at fixed s (a hat function of the vertex for a half-width;
-w'(s) times that hat for a station, the field stretching with its vertex); at a width step a
moved station adds the point term -(kappa_left(M) - kappa_right(M)) mom at the step (the region
left of the step grows). rho does not enter the elastica, nu only through the anticlastic
factor.

``ei_scale`` is a factor on EI: a number is held fixed; ``"plate"`` is the calibrated elastica of
``compute_truth`` (the ratio u_1D / u_plate of the 1D beam's and the plate's linear tips), whose
derivative comes from ``truth_gradient``'s adjoint tips of both and enters through
d r / d scale = (E / scale) d r / d E (EI is proportional to both; eta depends on neither).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..io.records import readonly_array as _ro
from ..member.design import Design, step_partner
from ..member.geometry import Beam
from .elastica import elastica_primal
from .elastica_adjoint import adjoint, section_at

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
        The dead tip force, N (world; F_y = 0).
    ei_scale : float
        The factor on EI.
    anticlastic : bool
        Whether the sections carry Ashwell's anticlastic restraint.
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

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -1.0])
    >>> g = pp.elastica_gradient(beam, ("thickness", "E"))
    >>> isinstance(g, pp.ElasticaGradient), g.ei_scale_source, g.d_tip_position_m.shape
    (True, 'fixed', (3, 2))
    >>> # the tip depends on E and t through E t^3 only: t dw/dt = 3 E dw/dE
    >>> w = g.d_tip_position_m[2]
    >>> round(float(0.01 * w[0]), 7), round(float(3 * 205e9 * w[1]), 7)  # m
    (0.0011707, 0.0011707)
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    tip_force_N: np.ndarray
    ei_scale: float
    anticlastic: bool
    ei_scale_source: str
    d_ei_scale: np.ndarray
    tip_position_m: np.ndarray
    d_tip_position_m: np.ndarray
    d_tip_d_force_m_per_N: np.ndarray
    nodes: int
    solve_s: float
    gradient_s: float


def _plate_scale(d: Design, mesh_level: int | None) -> tuple[float, np.ndarray, float, float]:
    """Return the EI scale of the linear tips, its design gradient and the truths' wall times.

    The scale is u_1D / u_plate of the linear tips under the beam's tip force (1, with zero
    gradient, without a vertical load, as ``compute_truth`` sets it); the wall times (s) are
    those of the two truths' solves and of their gradients.
    """
    from .compute_derivatives import truth_gradient

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
    anticlastic: bool = False,
) -> ElasticaGradient:
    """Return the elastica's large-deflection tip and its derivatives in the design and load.

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
    anticlastic : bool
        Differentiate ``elastica_static(..., anticlastic=True)``: each section stiffened by
        Ashwell's anticlastic restraint of its curvature (then nu enters the tip). With
        ``ei_scale="plate"`` the scale is still the linear tips' ratio.

    Returns
    -------
    ElasticaGradient
        The tip position (m) with its derivatives per SI unit of each design variable (m per
        unit) and per N of the tip load (m/N), the EI scale and the wall times (s).

    Raises
    ------
    BeamInputError
        Bad arguments or design variables (named).
    SolveError
        The elastica or its adjoint did not converge.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -1.0])  # a small load: the elastica is near linear
    >>> g = pp.elastica_gradient(beam, ("thickness",))
    >>> EI = 205e9 * 0.05 * 0.01**3 / 12  # N m^2
    >>> round(float(g.tip_position_m[2]) * 1e3, 4), round(-1.0 / (3 * EI) * 1e3, 4)  # mm, L = 1 m
    (-0.3902, -0.3902)
    >>> round(float(g.d_tip_d_force_m_per_N[2, 1]) * 1e3, 4), round(1e3 / (3 * EI), 4)  # mm/N
    (0.3902, 0.3902)
    >>> round(float(g.d_tip_position_m[2, 0]), 4), round(3 * 1.0 / (3 * EI) / 0.01, 4)  # -3 w / t
    (0.1171, 0.1171)
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    names = design.names if isinstance(design, Design) else design
    if isinstance(names, str):
        names = tuple(n.strip() for n in names.split(","))
    d = Design(beam, tuple(names))
    if (isinstance(tol, bool) or not isinstance(tol, (int, float, np.floating))
            or not np.isfinite(tol) or not 0.0 < tol < 1e-2):
        raise BeamInputError(f"tol = {tol!r}: must be a number in (0, 0.01)")
    if not isinstance(anticlastic, (bool, np.bool_)):
        raise BeamInputError(f"anticlastic = {anticlastic!r}: must be True or False")
    anticlastic = bool(anticlastic)
    source = "fixed"
    d_scale = np.zeros(d.size)
    scale_solve_s = scale_gradient_s = 0.0
    if isinstance(ei_scale, str):
        if ei_scale != "plate":
            raise BeamInputError(f"ei_scale = {ei_scale!r}: must be a number > 0 or 'plate'")
        ei_scale, d_scale, scale_solve_s, scale_gradient_s = _plate_scale(d, mesh_level)
        source = "plate"
    t0 = time.perf_counter()
    pr = elastica_primal(beam, tip_force_N, tol=float(tol), ei_scale=ei_scale,
                         anticlastic=anticlastic)
    F = pr.static.tip_force_N
    t1 = time.perf_counter()
    adj, lam_s, mom_s = adjoint(pr, beam, F, float(tol))

    L = beam.length_m
    cuts = pr.cuts
    a, ell = cuts[:-1], np.diff(cuts) / L
    nseg = ell.size
    first = [0] + [int(k) + 1 for k in beam.step_index]  # global index of each segment's vertex 0
    gx, gw = _GAUSS
    t, nu = beam.uniform_thickness_m("the elastica"), beam.material.nu
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
        kappa, r, eta_dr, dr_dnu = section_at(pr, beam, w, m)
        # d kappa / d p at fixed M is -kd times the relative change of EI kappa r: dEI / EI r
        # + eta r_eta d ln eta / dp (+ r_nu for nu), eta ~ w (1 - nu^2)^(1/4) / sqrt(t)
        kd = kappa / (r + 0.5 * eta_dr)
        lam = np.stack([ad[4 * i] * lam_s, ad[4 * i + 2] * lam_s])  # (x, z)
        mom = np.stack([ad[4 * i + 1] * mom_s, ad[4 * i + 3] * mom_s])
        d_force[[0, 2], 0] += (lam * np.sin(phi)) @ wq
        d_force[[0, 2], 1] -= (lam * np.cos(phi)) @ wq
        d_by_scale[[0, 2]] += (kd * r / ei_scale * mom) @ wq
        # slope of the width field on each quadrature point's vertex interval
        k = np.clip(np.searchsorted(xs, s, side="right") - 1, 0, xs.size - 2)
        slope = np.diff(ws) / np.where(np.diff(xs) > 0.0, np.diff(xs), np.inf)
        slope = slope[k]
        local = range(first[i], first[i] + xs.size)
        for row, (kind, j) in enumerate(d.kinds):
            if kind == "thickness":
                rel = (3.0 * r - 0.5 * eta_dr) / t
            elif kind == "E":
                rel = r / beam.material.E_Pa
            elif kind == "nu":
                if not anticlastic:
                    continue
                rel = dr_dnu - eta_dr * nu / (2.0 * (1.0 - nu * nu))
            elif kind == "rho":
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
                rel = (r + eta_dr) * dw / w
            d_tip[[0, 2], row] += (kd * rel * mom) @ wq
    # a moved width step: the region left of it (curvature kappa_left(M)) grows into the right's
    for row, (kind, j) in enumerate(d.kinds):
        if kind != "x" or step_partner(beam, j) is None:
            continue
        i = int(np.flatnonzero(beam.step_index == min(j, step_partner(beam, j)))[0])
        end = np.array([L])
        m = pr.sol.sol(end)[4 * i + 1] * pr.m_scale
        ad = adj.sol(end)[:, 0]
        mom = np.array([ad[4 * i + 1], ad[4 * i + 3]]) * mom_s
        k_left = section_at(pr, beam, pr.seg_w[i][-1:], m)[0][0]
        k_right = section_at(pr, beam, pr.seg_w[i + 1][:1], m)[0][0]
        d_tip[[0, 2], row] -= (k_left - k_right) * mom
    d_tip += np.outer(d_by_scale, d_scale)
    t2 = time.perf_counter()
    return ElasticaGradient(
        names=d.names, units=d.units, values=_ro(d.values), tip_force_N=_ro(F),
        ei_scale=float(ei_scale), anticlastic=anticlastic, ei_scale_source=source,
        d_ei_scale=_ro(d_scale),
        tip_position_m=_ro(pr.static.tip_position_m),
        d_tip_position_m=_ro(d_tip), d_tip_d_force_m_per_N=_ro(d_force),
        nodes=int(adj.x.size), solve_s=t1 - t0 + scale_solve_s,
        gradient_s=t2 - t1 + scale_gradient_s,
    )
