"""Large deflection of the inextensible elastica with varying EI(x), clamped root, dead tip load.

The centreline angle phi(s) (from +x towards +z) minimises
    1/2 int EI(s) phi'^2 ds - F . r(L),   r(L) = int (cos phi, sin phi) ds,
which gives (EI phi')' = F_x sin phi - F_z cos phi with phi(0) = 0 and EI phi'(L) = 0. The
boundary-value problem is solved with scipy's collocation solver, continuing in the load from the
straight beam so the stable (continuously loaded) branch is followed.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_bvp

from ..errors import BeamInputError, SolveError
from ..geometry import Beam
from .result import StaticSolution, Timings

__all__ = ["elastica_static"]


def _mesh(beam: Beam, n_per_span: int) -> np.ndarray:
    # Nodes at every vertex, where EI(s) has a kink.
    xv = beam.x_m
    counts = np.maximum(4, np.round(n_per_span * np.diff(xv) / beam.length_m).astype(int))
    parts = [np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(xv[:-1], xv[1:], counts, strict=True)]
    return np.concatenate(parts + [xv[-1:]])


def elastica_static(
    beam: Beam,
    tip_force_N: np.ndarray | None = None,
    load_steps: int | None = None,
    tol: float = 1e-9,
) -> StaticSolution:
    """Tip position of the inextensible elastica under a dead tip force in the x-z plane.

    Parameters
    ----------
    beam : Beam
    tip_force_N : array_like, shape (3,), optional
        Tip force in N (default: ``beam.tip_force_N``); F_y must be 0 (bending is in x-z).
    load_steps : int, optional
        Load increments of the continuation (default: grows with the load index P L^2 / EI_root).
    tol : float
        Collocation residual tolerance of ``solve_bvp`` (relative to the moment scale).

    Returns
    -------
    StaticSolution
        ``nonlinear=True``; tip position and displacement in m; ``dofs`` is the number of
        collocation nodes of the final mesh.
    """
    F = np.asarray(beam.tip_force_N if tip_force_N is None else tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force_N = {F.tolist()}: must be 3 finite numbers in N")
    P = float(np.hypot(F[0], F[2]))
    if abs(F[1]) > 1e-12 * max(P, 1.0):
        raise BeamInputError(f"tip_force_N[1] = {F[1]} N: bends in x-z only, must be 0")
    L = beam.length_m
    E = beam.material.E_Pa
    alpha = P * L**2 / beam.root_EI_Nm2
    if load_steps is None:
        load_steps = int(np.clip(np.ceil(4 * alpha), 1, 200))
    if not isinstance(load_steps, (int, np.integer)) or load_steps < 1:
        raise BeamInputError(f"load_steps = {load_steps!r}: must be an integer >= 1")

    t0 = time.perf_counter()
    xv, wv, t = beam.x_m, beam.half_width_m, beam.thickness_m
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

    def make(fx: float, fz: float):
        def rhs(tau, y):
            out = np.empty_like(y)
            for i in range(nseg):
                phi, m = y[4 * i], y[4 * i + 1] * m_scale
                sg = a[i] + ell[i] * tau
                EI = EI_factor * np.interp(sg, seg_x[i], seg_w[i])
                out[4 * i] = ell[i] * m / EI
                out[4 * i + 1] = ell[i] * (fx * np.sin(phi) - fz * np.cos(phi)) / m_scale
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
    y = np.zeros((4 * nseg, s.size))
    for i in range(nseg):
        y[4 * i + 2] = a[i] + ell[i] * s
    sol = None
    for k in range(1, load_steps + 1):
        lam = k / load_steps
        rhs, bc = make(lam * F[0], lam * F[2])
        sol = solve_bvp(rhs, bc, s, y, tol=tol, max_nodes=200_000, bc_tol=tol)
        if sol.status != 0:
            raise SolveError(
                f"elastica did not converge at load step {k}/{load_steps} "
                f"(P L^2/EI = {lam * alpha:.3g}): {sol.message}"
            )
        s, y = sol.x, sol.y
    t1 = time.perf_counter()
    tip = np.array([y[4 * nseg - 2, -1], 0.0, y[4 * nseg - 1, -1]])
    return StaticSolution(
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
