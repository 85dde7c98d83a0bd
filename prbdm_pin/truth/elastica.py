"""Large deflection of the inextensible elastica with varying EI(x), clamped root, dead tip load.

The centreline angle phi(s) (from +x towards +z) minimises::

    1/2 int EI(s) phi'^2 ds - F . r(L),   r(L) = int (cos phi, sin phi) ds,

which gives (EI phi')' = F_x sin phi - F_z cos phi with phi(0) = 0 and EI phi'(L) = 0. The
boundary-value problem is solved with scipy's collocation solver, continuing in the load from the
straight beam so the stable (continuously loaded) branch is followed. Under the member's own
weight (``gravity_m_s2``) the force F becomes the internal force F + g m_out(s), m_out the mass
outboard of s (:mod:`prbdm_pin.truth.self_weight`).

Two optional corrections bring it towards a plate (``compute_truth`` uses the second; the first
was measured against the nonlinear solid and over-stiffens jagged panels, see
scripts/target_consistency.py):

* ``anticlastic=True``: a plate strip of half-width a cannot curl freely across its width once it
  is curved (Ashwell 1950): the anticlastic deflection f(y) of the section stretches the fibres
  (strain kappa f), which the energy per unit length
  ``1/2 int D (kappa^2 + f_yy^2 + 2 nu kappa f_yy) + E t kappa^2 f^2 dy`` resists. Minimising over
  f gives a beam on an elastic foundation across the width, D f_yyyy + E t kappa^2 f = 0 with free
  edges, and the moment ``M = EI kappa r(eta)``,
  ``eta = a (3 (1 - nu^2))^(1/4) sqrt(|kappa| / t)``: r = 1 for a narrow or slightly bent strip
  (the beam) and 1 / (1 - nu^2) for a wide or strongly bent one (the plate's cylindrical
  bending), in closed form in ``anticlastic``. This is geometric nonlinearity of the section that
  a 1D elastica lacks and a linear plate solve cannot see.
* ``ei_scale``: a factor on EI(x), set from the ratio of the 1D and the plate linear tip
  deflections (clamped-root Poisson restraint, 2D load paths of a jagged planform).
"""

from __future__ import annotations

import time
from typing import NamedTuple

import numpy as np
from scipy.integrate import solve_bvp

from ..errors import BeamInputError, SolveError
from ..member.geometry import Beam
from ..member.section_law import section_properties
from .anticlastic import anticlastic_factor, section_curvature
from .result import StaticSolution, Timings
from .self_weight import check_gravity, outboard_mass_kg

__all__ = ["elastica_static", "anticlastic_factor", "ElasticaPrimal", "elastica_primal"]

def _mesh(beam: Beam, n_per_span: int) -> np.ndarray:
    # Nodes at every vertex, where EI(s) has a kink.
    xv = beam.x_m
    counts = np.maximum(4, np.round(n_per_span * np.diff(xv) / beam.length_m).astype(int))
    parts = [np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(xv[:-1], xv[1:], counts, strict=True)]
    return np.concatenate(parts + [xv[-1:]])


# most initial collocation nodes: a planform of thousands of vertices would otherwise start the
# collocation on several nodes per vertex (200k vertices: minutes); it refines where it must
_MAX_INITIAL_NODES = 2001


def _thin(s: np.ndarray, length_m: float) -> np.ndarray:
    """Return at most ``_MAX_INITIAL_NODES`` of the nodes ``s`` (m, ascending, from 0 to L).

    They are unchanged when there are that few, else only those at least L / (that number)
    apart are kept.
    """
    if s.size <= _MAX_INITIAL_NODES:
        return s
    gap = length_m / (_MAX_INITIAL_NODES - 1)
    keep = [float(s[0])]
    for v in map(float, s[1:-1]):
        if v - keep[-1] >= gap and s[-1] - v >= 0.5 * gap:
            keep.append(v)
    keep.append(float(s[-1]))
    return np.array(keep)


def _near_step_hint(beam: Beam) -> str:
    """Return a hint naming the narrowest section or the shortest vertex interval, or "".

    It names them when they are the likely cause of a failed solve: a section of almost no
    stiffness is a hinge, a width change over a tiny interval a step, and the C1 collocation
    follows neither.
    """
    w = beam.half_width_m
    k = int(np.argmin(w))
    if w[k] < 1e-4 * w.max():
        return (f"; half_width[{k}] = {w[k]:.3g} m is a near-hinge (E I {w[k] / w.max():.1g} of "
                "the widest section's) the elastica cannot resolve")
    dx = np.diff(beam.x_m)
    dx = np.where(dx > 0.0, dx, np.inf)
    i = int(np.argmin(dx)) + 1
    if dx[i - 1] >= 1e-4 * beam.length_m:
        return ""
    return (f"; x[{i}] - x[{i - 1}] = {dx[i - 1]:.3g} m is a near-step the elastica cannot "
            f"resolve: make it a width step (x[{i}] = x[{i - 1}]) or lengthen it")


class ElasticaPrimal(NamedTuple):
    """The converged elastica, kept for its design sensitivities.

    Segment i (cut at the width steps) is s = cuts[i] + (cuts[i + 1] - cuts[i]) tau / L, tau in
    [0, L]; ``sol.sol(tau)`` rows 4 i .. 4 i + 3 are phi (rad), M / m_scale, x (m), z (m);
    ``seg_x``, ``seg_w`` the segment's vertex stations and half-widths (m); EI(s) =
    ``ei_per_width`` w(s) (N m, per m of half-width); ``anticlastic``: whether each section
    carries Ashwell's restraint.
    """

    static: StaticSolution
    sol: object
    cuts: np.ndarray
    seg_x: tuple[np.ndarray, ...]
    seg_w: tuple[np.ndarray, ...]
    ei_per_width: float
    m_scale: float
    anticlastic: bool


def elastica_static(
    beam: Beam,
    tip_force_N: np.ndarray | None = None,
    load_steps: int | None = None,
    tol: float = 1e-9,
    *,
    ei_scale: float = 1.0,
    anticlastic: bool = False,
    gravity_m_s2=None,
) -> StaticSolution:
    """Tip position of the inextensible elastica under a dead tip force in the x-z plane.

    Parameters
    ----------
    beam : Beam
        The planform, thickness and material (its width steps cut the solve into segments).
    tip_force_N : array_like, shape (3,), optional
        Tip force in N (default: ``beam.tip_force_N``); F_y must be 0 (bending is in x-z).
    load_steps : int, optional
        Load increments of the continuation (default: grows with the load index P L^2 / EI_root).
    tol : float
        Collocation residual tolerance of ``solve_bvp`` (relative to the moment scale).
    ei_scale : float
        Factor on EI(x) (> 0; 1 is the plain Euler-Bernoulli section).
    anticlastic : bool
        Stiffen each section by the anticlastic restraint r(eta) of its curvature
        (``anticlastic.anticlastic_factor``).
    gravity_m_s2 : array_like, shape (3,), optional
        The member's own weight as well, m/s^2 (member axes, g_y = 0; default none): a dead
        distributed load rho A(s) g per unit arc length, so the internal force at s is
        F + g m_out(s) (``self_weight.outboard_mass_kg``).

    Returns
    -------
    StaticSolution
        ``nonlinear=True``; tip position and displacement in m; ``dofs`` is the number of
        collocation nodes of the final mesh.
    """
    return elastica_primal(beam, tip_force_N, load_steps, tol, ei_scale=ei_scale,
                           anticlastic=anticlastic, gravity_m_s2=gravity_m_s2).static


def elastica_primal(
    beam: Beam,
    tip_force_N: np.ndarray | None = None,
    load_steps: int | None = None,
    tol: float = 1e-9,
    *,
    ei_scale: float = 1.0,
    anticlastic: bool = False,
    gravity_m_s2=None,
) -> ElasticaPrimal:
    """``elastica_static`` with the converged solution kept (see ``ElasticaPrimal``)."""
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    P = float(np.hypot(F[0], F[2]))
    if abs(F[1]) > 1e-12 * max(P, 1.0):
        raise BeamInputError(f"tip_force_N[1] = {F[1]} N: bends in x-z only, must be 0")
    if not (isinstance(ei_scale, (int, float, np.floating)) and np.isfinite(ei_scale)
            and ei_scale > 0.0):
        raise BeamInputError(f"ei_scale = {ei_scale!r}: must be a finite number > 0")
    g = np.zeros(3) if gravity_m_s2 is None else check_gravity(gravity_m_s2)
    L = beam.length_m
    E = beam.material.E_Pa * float(ei_scale)
    nu = beam.material.nu
    # the member's weight counts as a tip load for the load steps and the moment scale
    P = P + float(np.hypot(g[0], g[2])) * beam.mass_kg
    alpha = P * L**2 / beam.root_EI_Nm2
    if load_steps is None:
        load_steps = int(np.clip(np.ceil(4 * alpha), 1, 200))
    if not isinstance(load_steps, (int, np.integer)) or load_steps < 1:
        raise BeamInputError(f"load_steps = {load_steps!r}: must be an integer >= 1")

    if anticlastic:
        beam.rectangle_only("the anticlastic elastica")  # its sections are 2 w x t strips
    t0 = time.perf_counter()
    xv, wv, t = beam.x_m, beam.half_width_m, beam.thickness_m
    law = beam.thickness_law_m  # t(s) continuous: interpolated over all stations
    # Scale: moments by P L (or EI_root / L when unloaded), lengths by L.
    m_scale = max(P * L, beam.root_EI_Nm2 / L)

    # A width step makes phi' = M / EI jump, which the collocation's C1 spline cannot follow:
    # the beam is cut there into segments, each solved on its own copy of tau in [0, L] (states
    # stacked, continuity of phi, M, x, z as boundary conditions). Between steps EI(s) is only
    # kinked, and nodes sit at those vertices.
    cuts = np.concatenate([[0.0], xv[beam.step_index], [L]])
    a, ell = cuts[:-1], np.diff(cuts) / L  # s = a_i + ell_i tau on segment i
    nseg = ell.size
    seg_x, seg_w = [], []
    for i in range(nseg):
        lo = 0 if i == 0 else int(beam.step_index[i - 1]) + 1
        hi = xv.size if i == nseg - 1 else int(beam.step_index[i]) + 1
        seg_x.append(xv[lo:hi])
        seg_w.append(wv[lo:hi])
    EI_factor = E * 2.0 * t**3 / 12.0

    def curvature(half_width: np.ndarray, m: np.ndarray, sg) -> np.ndarray:
        if beam.section is not None:  # a round member: E I_y(s) of its section law
            return m / (float(ei_scale) * section_properties(beam, sg).EI_y_Nm2)
        if law is not None:  # E I = E 2 w t(s)^3 / 12, the section's own thickness
            ts = np.interp(sg, xv, law)
            ei = E * 2.0 * ts**3 / 12.0 * half_width
            return m / ei if not anticlastic else section_curvature(m, ei, half_width, ts, nu)
        if not anticlastic:
            return m / (EI_factor * half_width)
        return section_curvature(m, EI_factor * half_width, half_width, t, nu)

    def make(fx: float, fz: float, gx: float = 0.0, gz: float = 0.0):
        weight = bool(gx or gz)

        def rhs(tau, y):
            out = np.empty_like(y)
            for i in range(nseg):
                phi, m = y[4 * i], y[4 * i + 1] * m_scale
                sg = a[i] + ell[i] * tau
                out[4 * i] = ell[i] * curvature(np.interp(sg, seg_x[i], seg_w[i]), m, sg)
                nx, nz = fx, fz  # the internal force at s: the tip force and the outboard weight
                if weight:
                    m_out = outboard_mass_kg(beam, sg)
                    nx, nz = fx + gx * m_out, fz + gz * m_out
                out[4 * i + 1] = ell[i] * (nx * np.sin(phi) - nz * np.cos(phi)) / m_scale
                out[4 * i + 2] = ell[i] * np.cos(phi)
                out[4 * i + 3] = ell[i] * np.sin(phi)
            return out

        def bc(ya, yb):
            joins = [ya[4 * (i + 1): 4 * (i + 2)] - yb[4 * i: 4 * (i + 1)]
                     for i in range(nseg - 1)]
            return np.concatenate([[ya[0], yb[4 * nseg - 3], ya[2], ya[3]], *joins])

        return rhs, bc

    if nseg == 1:
        s = _mesh(beam, 64)
    else:
        # every segment's vertices are nodes of the shared tau mesh
        s = np.unique(np.concatenate(
            [np.linspace(0.0, L, 65)] + [(seg_x[i] - a[i]) / ell[i] for i in range(nseg)]))
    s = _thin(s, L)
    y = np.zeros((4 * nseg, s.size))
    for i in range(nseg):
        y[4 * i + 2] = a[i] + ell[i] * s
    sol = None
    for k in range(1, load_steps + 1):
        lam = k / load_steps
        rhs, bc = make(lam * F[0], lam * F[2], lam * g[0], lam * g[2])
        sol = solve_bvp(rhs, bc, s, y, tol=tol, max_nodes=200_000, bc_tol=tol)
        if sol.status != 0:
            raise SolveError(
                f"elastica did not converge at load step {k}/{load_steps} "
                f"(P L^2/EI = {lam * alpha:.3g}): {sol.message}{_near_step_hint(beam)}"
            )
        s, y = sol.x, sol.y
    t1 = time.perf_counter()
    tip = np.array([y[4 * nseg - 2, -1], 0.0, y[4 * nseg - 1, -1]])
    static = StaticSolution(
        model="elastica",
        nonlinear=True,
        tip_force_N=F.copy(),
        tip_position_m=tip,
        tip_displacement_m=tip - np.array([L, 0.0, 0.0]),
        dofs=int(s.size * nseg),
        mesh_level=0,
        load_steps=load_steps,
        timings=Timings(solve_s=t1 - t0),
    )
    return ElasticaPrimal(static, sol, cuts, tuple(seg_x), tuple(seg_w), EI_factor, m_scale,
                          bool(anticlastic))
