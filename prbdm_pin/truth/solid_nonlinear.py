"""3D solid truth, the large-deflection solve: total-Lagrangian Saint Venant-Kirchhoff.

Second Piola-Kirchhoff stress S = lambda tr(E) I + 2 mu E of the Green strain E, solved by
Newton's method with load steps under the dead tip load. Each tangent is a batch of BLAS products
summed into a fixed CSR pattern of the free DOFs; Newton corrections come from conjugate
gradients preconditioned by the last LU factorisation while the tangent changes little, and from
a new factorisation otherwise.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolveError
from .solid_fe import SolidDiscretisation, SpdFactor

__all__ = ["CsrPattern", "Kinematics", "TangentSolver", "solve_nonlinear"]


class CsrPattern:
    """Fixed CSR sparsity of the element matrices restricted to a DOF subset.

    ``pos`` sends every kept element-matrix entry to its slot in the CSR data array, so each
    tangent is assembled by one ``bincount`` instead of a COO -> CSR conversion (sort and
    duplicate sum of ~10^7 entries).
    """

    def __init__(self, vdofs: np.ndarray, keep: np.ndarray, n_vec: int):
        index = np.full(n_vec, -1, dtype=np.int64)
        index[keep] = np.arange(keep.size)
        loc = index[vdofs]  # (E, 81) reduced index, -1 where the DOF is not kept
        ne, nd = loc.shape
        rows = np.repeat(loc, nd, axis=1).ravel()
        cols = np.tile(loc, (1, nd)).ravel()
        self.mask = (rows >= 0) & (cols >= 0)
        n = keep.size
        key = rows[self.mask] * n + cols[self.mask]
        unique, self.pos = np.unique(key, return_inverse=True)
        self.indices = (unique % n).astype(np.int32)
        self.indptr = np.searchsorted(unique // n, np.arange(n + 1)).astype(np.int32)
        self.shape = (n, n)
        self.nnz = unique.size

    def matrix(self, element_matrices: np.ndarray) -> sp.csr_matrix:
        """Sum ``element_matrices`` into the pattern; return the CSR matrix."""
        data = np.bincount(self.pos, weights=element_matrices.ravel()[self.mask],
                           minlength=self.nnz)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape)


class Kinematics:
    """Element-level total-Lagrangian SVK kernel: internal forces and tangent stiffness.

    The contractions over Gauss points are batched matrix products (BLAS) rather than
    ``einsum`` loops; the tangent goes into a precomputed sparsity pattern.
    """

    def __init__(self, d: SolidDiscretisation, chunk: int = 64):
        b = d.basis
        self.d = d
        self.dofs = b.element_dofs.T  # (E, 27)
        # G[e, q, a, j] = d phi_a / d X_j at Gauss point q of element e
        self.G = np.stack([b.basis[a][0].grad for a in range(len(b.basis))], axis=0)
        self.G = np.ascontiguousarray(self.G.transpose(2, 3, 0, 1))
        self.w = b.dx  # (E, Q) quadrature weights times |J|
        self.chunk = chunk
        ne, na = self.dofs.shape
        self.vdofs = (3 * self.dofs[:, :, None] + np.arange(3)).reshape(ne, 3 * na)
        self._patterns: dict[str, CsrPattern] = {}

    def pattern(self, which: str = "full") -> CsrPattern:
        """Return the sparsity pattern on ``which`` DOFs (``"full"`` or ``"free"``), built once."""
        if which not in self._patterns:
            keep = np.arange(self.d.n_vec) if which == "full" else self.d.free
            self._patterns[which] = CsrPattern(self.vdofs, keep, self.d.n_vec)
        return self._patterns[which]

    def evaluate(self, u: np.ndarray, tangent: bool = True, which: str = "full"):
        """Return the internal force vector (all DOFs) and, if asked, the tangent stiffness.

        The tangent stiffness (CSR) is on ``which`` DOFs: ``"full"`` or ``"free"``.
        """
        lam, mu = self.d.lam, self.d.mu
        ne, na = self.dofs.shape
        nd = 3 * na
        fint = np.zeros(self.d.n_vec)
        kdata = np.empty((ne, nd, nd)) if tangent else None
        I3 = np.eye(3)
        for s in range(0, ne, self.chunk):
            sl = slice(s, min(s + self.chunk, ne))
            G, w = self.G[sl], self.w[sl]
            n, nq = w.shape
            ue = u[self.vdofs[sl]].reshape(n, 1, na, 3)
            F = I3 + np.swapaxes(ue, 2, 3) @ G  # F_ij = delta_ij + sum_a u_ai g_aj
            Egl = 0.5 * (np.swapaxes(F, 2, 3) @ F - I3)
            tr = Egl[..., 0, 0] + Egl[..., 1, 1] + Egl[..., 2, 2]
            wS = w[..., None, None] * (lam * tr[..., None, None] * I3 + 2 * mu * Egl)
            fe = (G @ np.swapaxes(F @ wS, 2, 3)).sum(axis=1)  # sum_q w P_ij g_aj
            np.add.at(fint, self.vdofs[sl].ravel(), fe.ravel())
            if not tangent:
                continue
            h = (G @ np.swapaxes(F, 2, 3)).reshape(n, nq, nd)  # h_(a i) = F_ij g_aj
            wh = w[..., None] * h
            hh = (np.swapaxes(wh, 1, 2) @ h).reshape(n, na, 3, na, 3)
            # mu (F F^T)_ik (g_a . g_b) and the initial-stress term (g_a . S g_b) delta_ik
            gg = (G @ np.swapaxes(G, 2, 3)).reshape(n, nq, na * na)
            wbF = (mu * w[..., None, None] * (F @ np.swapaxes(F, 2, 3))).reshape(n, nq, 9)
            Kb = (np.swapaxes(wbF, 1, 2) @ gg).reshape(n, 3, 3, na, na)
            gSg = ((G @ wS).transpose(0, 2, 1, 3).reshape(n, na, nq * 3)
                   @ G.transpose(0, 1, 3, 2).reshape(n, nq * 3, na))
            Ke = lam * hh + mu * hh.transpose(0, 1, 4, 3, 2) + Kb.transpose(0, 3, 1, 4, 2)
            Ke[:, :, [0, 1, 2], :, [0, 1, 2]] += gSg
            kdata[sl] = Ke.reshape(n, nd, nd)
        if not tangent:
            return fint, None
        return fint, self.pattern(which).matrix(kdata)


class TangentSolver:
    """Newton corrections K du = r by a factorisation or preconditioned conjugate gradients.

    A fresh factorisation, or conjugate gradients preconditioned by the last factorisation
    while they converge fast.

    Within a load step the tangent changes little between Newton iterations, so the previous
    LU is an excellent preconditioner: a few CG iterations (one triangular solve each) replace a
    new factorisation. The corrections are solved to ``rtol``, so Newton keeps its quadratic
    convergence; if CG needs more than ``max_cg`` iterations the tangent is factored again.
    """

    def __init__(self, rtol: float = 1e-6, max_cg: int = 20, order: np.ndarray | None = None):
        self.lu = None
        self.order = order
        self.rtol = rtol
        self.max_cg = max_cg
        self.factorisations = 0
        self.cg_iterations = 0

    def solve(self, K: sp.csr_matrix, r: np.ndarray, refactor: bool = False) -> np.ndarray:
        """Return du with K du = ``r`` (``refactor``: factor ``K`` afresh)."""
        if self.lu is not None and not refactor:
            M = spla.LinearOperator(K.shape, matvec=self.lu.solve, dtype=float)
            count = [0]

            def tally(_):
                count[0] += 1

            du, info = spla.cg(K, r, x0=self.lu.solve(r), rtol=self.rtol, maxiter=self.max_cg,
                               M=M, callback=tally)
            self.cg_iterations += count[0]
            if info == 0 and np.all(np.isfinite(du)):
                return du
        self.lu = SpdFactor(K, self.order)
        self.factorisations += 1
        return self.lu.solve(r)


def solve_nonlinear(beam, d: SolidDiscretisation, f_ext: np.ndarray, load_steps: int, tol: float,
                    max_iter: int, progress=None, stats=None) -> tuple[np.ndarray, int]:
    """Return the displacements (m, all vector DOFs) under the dead load ``f_ext`` (N).

    Also the number of converged load steps; an increment whose Newton iteration fails is
    halved.
    """
    kin = Kinematics(d)
    solver = TangentSolver(order=d.order)
    free = d.free
    u = np.zeros(d.n_vec)
    u_prev, lam_prev = None, 0.0
    fscale = np.linalg.norm(f_ext[free])
    lam_done, dlam = 0.0, 1.0 / load_steps
    steps = iterations = 0
    while lam_done < 1.0 - 1e-12:
        lam_try = min(1.0, lam_done + dlam)
        u_try = u.copy()
        if u_prev is not None:
            # secant predictor along the converged load path
            u_try += (lam_try - lam_done) / (lam_done - lam_prev) * (u - u_prev)
        converged = False
        du_norm = r_prev = np.inf
        for _ in range(max_iter):
            fint, K = kin.evaluate(u_try, which="free")
            r = (lam_try * f_ext - fint)[free]
            r_norm = np.linalg.norm(r)
            # Rounding in the stiff membrane terms floors the residual (near 1e-9 of the load at
            # P L^2/EI = 1, relatively higher for small loads): accept a residual below tol or
            # one that stopped falling, once the last Newton correction is negligible.
            small_step = du_norm <= 1e-6 * np.linalg.norm(u_try)
            if small_step and (r_norm <= tol * fscale or r_norm > 0.5 * r_prev):
                converged = True
                break
            r_prev = r_norm
            # a large last correction means the tangent moved: factor it afresh
            du = solver.solve(K, r, refactor=du_norm > 3e-2 * np.linalg.norm(u_try))
            du_norm = np.linalg.norm(du)
            u_try[free] += du
            iterations += 1
            if not np.all(np.isfinite(u_try)):
                break
        if converged:
            u_prev, lam_prev = u, lam_done
            u, lam_done = u_try, lam_try
            steps += 1
            if progress is not None:
                progress(lam_done)
        else:
            dlam *= 0.5  # cut the increment and retry from the last converged state
            solver.lu = None
            if dlam < 1e-4:
                raise SolveError(f"solid Newton failed at load factor {lam_try:.4g}")
    if stats is not None:
        stats.update(newton_iterations=iterations, factorisations=solver.factorisations,
                     cg_iterations=solver.cg_iterations)
    return u, steps


