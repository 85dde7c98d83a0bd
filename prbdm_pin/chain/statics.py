"""Large-deflection statics of the planar chain under a dead tip force.

Damped Newton on the potential of :class:`prbdm_pin.chain.planar.ChainPotential`, one chain at a
time
or a stack at once.

``static_deflection`` is the Pinocchio-model entry point in the style f(model, data, ...); the
planar solvers take link lengths (m) and joint springs (N m/rad) directly, as the fit's inner
loop does. The loads double precision cannot resolve are refused first (:mod:`.statics_guard`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg.lapack import dpotrf as _potrf
from scipy.linalg.lapack import dpotrs as _potrs

from ..errors import BeamInputError, SolveError
from .planar import ChainPotential
from .statics_guard import check_load, load_ok_rows, off_saddle, require_finite

if TYPE_CHECKING:
    import pinocchio as pin

__all__ = ["static_deflection", "static_deflection_planar", "static_deflection_planar_unchecked",
           "static_deflection_planar_batch"]


def _newton(pot: ChainPotential, q: np.ndarray, lam: float, rtol: float, max_iter: int,
            max_step: float) -> tuple[np.ndarray, bool]:
    """Damped Newton descent on V from ``q``; returns (q, converged)."""
    cs = pot.angles(q)  # each point's angles serve its potential and its derivatives
    for _ in range(max_iter):
        g, H, scale = pot.derivatives(q, lam, cs=cs)
        gn = math.sqrt(g @ g)
        require_finite((pot.fx, 0.0, pot.fz), gn, scale)
        C, info = _potrf(H, lower=1)  # LAPACK Cholesky: thin wrapper, cheap for small n
        pd = info == 0
        if gn <= rtol * scale:
            if pd:
                return q, True
            # a stationary point that is not a minimum (e.g. the straight pose under a buckling
            # load): leave it along the direction of negative curvature
            w, V = np.linalg.eigh(H)
            d = V[:, 0] * min(max_step, 1e-2)
        elif pd:
            d = -_potrs(C, g, lower=1)[0]
        else:
            w, V = np.linalg.eigh(H)
            floor = 1e-8 * max(float(np.max(np.abs(w))), 1e-300)
            d = -V @ ((V.T @ g) / np.maximum(np.abs(w), floor))
        step = float(np.maximum.reduce(np.abs(d)))
        if step > max_step:
            d *= max_step / step
        # backtracking (Armijo) on the potential; near the solution V stops resolving the
        # decrease, so a step that shrinks the gradient is accepted as well
        v0, slope = pot.value(q, lam, cs=cs), float(g @ d)
        alpha = 1.0
        for _ in range(40):
            qn = q + d if alpha == 1.0 else q + alpha * d  # 1.0 d is d: one call less
            csn = pot.angles(qn)
            if pot.value(qn, lam, cs=csn) <= v0 + 1e-4 * alpha * min(slope, 0.0):
                break
            gnew = pot.derivatives(qn, lam, hessian=False, cs=csn)[0]
            if math.sqrt(gnew @ gnew) < 0.5 * gn:
                break
            alpha *= 0.5
        else:
            return q, False
        q, cs = qn, csn
    g, H, scale = pot.derivatives(q, lam, cs=cs)
    return q, bool(math.sqrt(g @ g) <= rtol * scale and _potrf(H, lower=1)[1] == 0)


def static_deflection_planar(
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    tip_force_N: np.ndarray,
    q0: np.ndarray | None = None,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
) -> np.ndarray:
    """Equilibrium joint angles (rad) of the planar chain under a dead tip force (N).

    Minimises V(q) = 1/2 q^T K q - F . p_tip(q) by damped Newton steps with the exact Hessian,
    starting from ``q0`` (default straight). If the full load does not converge, the load is
    applied in adaptive steps (continuation), each solved from the previous equilibrium.
    Converged means ||K q - J^T F|| <= rtol * max(||K q||, ||J^T F||) at a minimum of V.

    Raises
    ------
    SolveError
        If no equilibrium is found.
    """
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    n = k.size
    F = np.asarray(tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force = {F.tolist()}: must be 3 finite numbers (N)")
    q = np.zeros(n) if q0 is None else np.array(q0, dtype=float)
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise BeamInputError(f"q0 = {q.tolist()}: must be {n} finite joint angles (rad)")
    return static_deflection_planar_unchecked(np.asarray(lengths_m, dtype=float), k, F, q, rtol,
                                              max_iter, max_step_rad)


def static_deflection_planar_unchecked(
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    tip_force_N: np.ndarray,
    q0: np.ndarray,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
) -> np.ndarray:
    """Compute :func:`static_deflection_planar` for inputs already checked (the fit's inner loop).

    ``lengths_m`` (n+1,), m, ``stiffness_Nm_per_rad`` (n,), N m/rad, ``tip_force_N`` (3,), N,
    finite, and a finite start ``q0`` (n,), rad, all float arrays; ``q0`` is not modified.
    The load is still checked against what double precision resolves (it depends on the
    springs).
    """
    F, q = tip_force_N, q0
    if F[0] == 0.0 and F[2] == 0.0:
        return np.zeros(q.size)  # no in-plane load: V = 1/2 q^T K q has its only minimum at 0
    check_load(lengths_m, stiffness_Nm_per_rad, F, rtol)
    pot = ChainPotential(lengths_m, stiffness_Nm_per_rad, F)
    q1, ok = _newton(pot, q, 1.0, rtol, max_iter, max_step_rad)
    if ok:
        return q1
    # load stepping from the start pose
    lam, dlam = 0.0, 0.25
    while lam < 1.0:
        target = min(1.0, lam + dlam)
        qn, ok = _newton(pot, q, target, rtol, max(1, max_iter // 2), max_step_rad)
        if ok:
            q, lam = qn, target
            dlam *= 1.5
        else:
            dlam *= 0.5
            if dlam < 1e-5:
                # the path stalls at a bifurcation of the straight pose (a column under an
                # axial load), where the full-load descent had only run short of iterations
                qn, ok = _newton(pot, off_saddle(pot, q1), 1.0, rtol, 4 * max_iter,
                                 max_step_rad)
                if ok:
                    return qn
                raise SolveError(
                    f"static deflection: no equilibrium beyond {lam:.4g} of the load "
                    f"tip_force = {F.tolist()} N (load stepping stalled)"
                )
    return q


# Above this many rows the vectorised factorisation beats a LAPACK call per matrix (measured for
# n = 2...8: the two cross near 400 rows)
_ROWS_CHOLESKY_MIN = 400


def _cholesky_solve_batch(H: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve H d = g for a stack of small symmetric matrices.

    Returns d and whether each row is positive definite; rows that are not get d = 0.
    """
    if g.shape[0] >= _ROWS_CHOLESKY_MIN:
        return _cholesky_rows(H, g)
    try:
        # the common case, every row positive definite: LAPACK's loops
        np.linalg.cholesky(H)
        return np.linalg.solve(H, g[..., None])[..., 0], np.ones(g.shape[0], dtype=bool)
    except np.linalg.LinAlgError:
        return _cholesky_rows(H, g)


def _cholesky_rows(H: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Run :func:`_cholesky_solve_batch` row by row in the factorisation.

    So the rows that are not positive definite are found (n^2 vectorised steps for any batch
    size).
    """
    B, n = g.shape
    C = np.zeros_like(H)
    pd = np.ones(B, dtype=bool)
    for j in range(n):
        dj = H[:, j, j] - np.einsum("bk,bk->b", C[:, j, :j], C[:, j, :j])
        pd &= dj > 0.0
        cjj = np.sqrt(np.where(dj > 0.0, dj, 1.0))
        C[:, j, j] = cjj
        if j + 1 < n:
            C[:, j + 1:, j] = (H[:, j + 1:, j]
                               - np.einsum("bik,bk->bi", C[:, j + 1:, :j], C[:, j, :j])) \
                / cjj[:, None]
    y = np.empty_like(g)
    for j in range(n):  # forward: C y = g
        y[:, j] = (g[:, j] - np.einsum("bk,bk->b", C[:, j, :j], y[:, :j])) / C[:, j, j]
    d = np.empty_like(g)
    for j in range(n - 1, -1, -1):  # back: C^T d = y
        d[:, j] = (y[:, j] - np.einsum("bk,bk->b", C[:, j + 1:, j], d[:, j + 1:])) / C[:, j, j]
    d[~pd] = 0.0
    return d, pd


def static_deflection_planar_batch(
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    tip_force_N: np.ndarray,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
) -> tuple[np.ndarray, np.ndarray]:
    """Equilibria of B planar chains under one dead tip force, solved together.

    The method of :func:`static_deflection_planar` (damped Newton with the exact Hessian on
    V = 1/2 q^T K q - F . p_tip, Armijo backtracking, the same convergence test), vectorised over
    the rows, so the fit's inner loop solves a whole population's (or every pose's) statics in
    one pass instead of one Python-level solve per row. Rows that Newton from the straight pose
    cannot finish (a non-convex start, say) are handed to :func:`static_deflection_planar` with
    its load stepping; rows that fail there too are reported, not raised.

    Parameters
    ----------
    lengths_m : ndarray, shape (B, n+1) or (n+1,)
        Link lengths of each chain, m.
    stiffness_Nm_per_rad : ndarray, shape (B, n)
        Joint springs of each chain, N m/rad.
    tip_force_N : ndarray, shape (3,)
        The dead tip force, N (world).

    Returns
    -------
    q : ndarray, shape (B, n)
        Joint angles, rad (NaN where no equilibrium was found).
    ok : ndarray of bool, shape (B,)
        Whether each row converged.
    """
    k = np.atleast_2d(np.asarray(stiffness_Nm_per_rad, dtype=float))
    B, n = k.shape
    L = np.broadcast_to(np.asarray(lengths_m, dtype=float), (B, n + 1))
    F = np.asarray(tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force = {F.tolist()}: must be 3 finite numbers (N)")
    q = np.zeros((B, n))
    ok = np.zeros(B, dtype=bool)
    if F[0] == 0.0 and F[2] == 0.0:
        return q, ~ok  # no in-plane load: the straight pose is the only minimum
    pot = ChainPotential(L, k, F)
    resolvable = load_ok_rows(L, k, F, rtol)
    active = np.flatnonzero(resolvable)
    for it in range(max_iter + 1):
        if active.size == 0:
            break
        qa = q[active]
        g, H, scale = pot.derivatives(qa, rows=active)
        gn = np.linalg.norm(g, axis=1)
        d, pd = _cholesky_solve_batch(H, g)
        fin = np.isfinite(gn) & np.isfinite(scale)
        done = pd & fin & (gn <= rtol * scale)
        ok[active[done]] = True
        # not positive definite, not finite, or out of iterations: the scalar solver takes the
        # row over
        keep = pd & fin & ~done
        active, qa, g, gn, d = active[keep], qa[keep], g[keep], gn[keep], -d[keep]
        if it == max_iter or active.size == 0:
            break
        step = np.max(np.abs(d), axis=1)
        d *= np.minimum(1.0, max_step_rad / np.maximum(step, 1e-300))[:, None]
        v0 = pot.value(qa, rows=active)
        slope = np.minimum(np.einsum("bi,bi->b", g, d), 0.0)
        alpha = np.ones(active.size)
        accepted = np.zeros(active.size, dtype=bool)
        for _ in range(40):
            todo = np.flatnonzero(~accepted)
            if todo.size == 0:
                break
            qn = qa[todo] + alpha[todo, None] * d[todo]
            good = pot.value(qn, rows=active[todo]) <= v0[todo] + 1e-4 * alpha[todo] * slope[todo]
            bad = todo[~good]
            if bad.size:
                gnew = pot.derivatives(qa[bad] + alpha[bad, None] * d[bad],
                                       rows=active[bad], hessian=False)[0]
                good[~good] = np.linalg.norm(gnew, axis=1) < 0.5 * gn[bad]
            accepted[todo[good]] = True
            alpha[todo[~good]] *= 0.5
        q[active[accepted]] = qa[accepted] + alpha[accepted, None] * d[accepted]
        active = active[accepted]  # rows whose line search failed go to the scalar solver
    q[~resolvable] = np.nan
    for r in np.flatnonzero(~ok & resolvable):
        try:
            q[r] = static_deflection_planar(L[r], k[r], F, rtol=rtol, max_iter=max_iter,
                                            max_step_rad=max_step_rad)
            ok[r] = True
        except SolveError:
            q[r] = np.nan
    return q, ok


def static_deflection(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    tip_frame_id: int,
    tip_force_N: np.ndarray,
    q0: np.ndarray | None = None,
    rtol: float = 1e-10,
) -> tuple[np.ndarray, np.ndarray]:
    """Large-deflection equilibrium K q = J(q)^T F under a dead tip force.

    Returns the joint angles q (rad) and the tip position (m, world). See
    :func:`static_deflection_planar` for the method.
    """
    # Pinocchio loads with the model entry point only: the planar solvers (the fits) need none
    from .pin_dynamics import checked_stiffness, planar_lengths, tip_position

    k = checked_stiffness(stiffness_Nm_per_rad, pin_model.nv)
    lengths = planar_lengths(pin_model, tip_frame_id)
    q = static_deflection_planar(lengths, k, tip_force_N, q0=q0, rtol=rtol)
    return q, tip_position(pin_model, data, q, tip_frame_id)
